//! Input: OFF bytes (`OFF`, `COFF`, `NOFF`, `CNOFF`, `STOFF`, ... in 3D,
//! ASCII; binary OFF, `OFF BINARY`, is read by `off_binary.rs`). Output: a
//! [`Mesh`], polygons split into fans (or, flat ones whose fan would fold,
//! by ear clipping: `polygon.rs`); and the OFF writer.
//!
//! Hand-written: no maintained crate reads OFF; the format is a header line,
//! counts, one vertex per line, one face per line.
//!
//! Vertex lines: the first three numbers (colors, normals, texture
//! coordinates after them are ignored). Face lines: `k i1 .. ik`, then
//! ignored color values; a face whose indices do not fit its line runs on
//! over the next ones (as CGAL and libigl read it), and the rest of the
//! line holding its last index is color. A face line that really lists
//! too few indices then takes the next face's line, and the file runs out
//! of face lines: refused as truncated. Indices are 0-based; indices past
//! the vertex count load as they are (validation reports them). The counts
//! are checked against the bytes that follow before any allocation.

use std::io::Write;

use super::text::{self, parse_f64, parse_index_u32, show, tokens, FaceSink, Lines};
use super::{write_err, LoadError, LoadNote, LoadReport, MeshFormat, SaveError, MAX_ELEMENTS};
use crate::mesh::Mesh;

const FORMAT: MeshFormat = MeshFormat::Off;

/// Fewest bytes a vertex line can take (`0 0 0\n`).
const MIN_VERTEX_BYTES: u64 = 6;
/// Fewest bytes a face line can take (`3 0 1 2\n`).
const MIN_FACE_BYTES: u64 = 8;

/// Whether a token is an OFF header keyword: `OFF` with optional prefixes
/// `ST`, `C`, `N`, `4`, `n`.
fn is_off_keyword(t: &[u8]) -> bool {
    match t.strip_suffix(b"OFF") {
        Some(prefix) => prefix
            .iter()
            .all(|b| matches!(b, b'S' | b'T' | b'C' | b'N' | b'4' | b'n')),
        None => false,
    }
}

/// Splits a header token into its OFF keyword and a vertex count glued to
/// it: ModelNet's files start `OFF490 518 0`. `None` when the token is no
/// OFF keyword, or something other than digits follows it.
pub(super) fn split_off_keyword(t: &[u8]) -> Option<(&[u8], Option<&[u8]>)> {
    let end = t.windows(3).position(|w| w == b"OFF")? + 3;
    let (keyword, rest) = t.split_at(end);
    if !is_off_keyword(keyword) || !rest.iter().all(u8::is_ascii_digit) {
        return None;
    }
    Some((keyword, (!rest.is_empty()).then_some(rest)))
}

fn parse_err(line: usize, message: String) -> LoadError {
    LoadError::Parse {
        format: FORMAT,
        line: Some(line),
        message,
    }
}

/// Lines that carry data: comments (`#` to end of line) cut, blank lines
/// skipped.
fn data_lines(bytes: &[u8]) -> impl Iterator<Item = (usize, &[u8])> {
    Lines::new(bytes)
        .map(|(n, l)| {
            let cut = l.iter().position(|&b| b == b'#').unwrap_or(l.len());
            (n, &l[..cut])
        })
        .filter(|(_, l)| tokens(l).next().is_some())
}

fn parse_count(token: &[u8], line: usize, what: &str) -> Result<u64, LoadError> {
    std::str::from_utf8(token)
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .ok_or_else(|| {
            parse_err(
                line,
                format!("expected the {what} count, found `{}`", show(token)),
            )
        })
}

/// Reads OFF.
pub(super) fn read(bytes: &[u8]) -> Result<(Mesh, LoadReport), LoadError> {
    let mut lines = data_lines(bytes);
    let (header_line, header) = lines
        .next()
        .ok_or_else(|| parse_err(1, "empty file: expected `OFF`".to_owned()))?;
    let mut head = tokens(header);
    let first = head.next().unwrap_or_default();
    let Some((keyword, glued)) = split_off_keyword(first) else {
        return Err(parse_err(
            header_line,
            format!("expected `OFF`, found `{}`", show(first)),
        ));
    };
    if keyword.contains(&b'4') || keyword.contains(&b'n') {
        return Err(LoadError::Unsupported {
            format: FORMAT,
            feature: format!("`{}`: OFF in other than three dimensions", show(keyword)),
        });
    }
    let mut counts: Vec<(&[u8], usize)> = glued
        .into_iter()
        .chain(head)
        .map(|t| (t, header_line))
        .collect();
    if counts
        .first()
        .is_some_and(|(t, _)| t.eq_ignore_ascii_case(b"BINARY"))
    {
        let data = &bytes[line_end_offset(bytes, header_line).min(bytes.len())..];
        return super::off_binary::read(data, keyword);
    }
    if counts.is_empty() {
        let (n, l) = lines.next().ok_or_else(|| {
            parse_err(
                header_line,
                "unexpected end of file: expected the vertex and face counts".to_owned(),
            )
        })?;
        counts = tokens(l).map(|t| (t, n)).collect();
    }
    let counts_line = counts.first().map_or(header_line, |c| c.1);
    if counts.len() > 3 {
        return Err(parse_err(
            counts_line,
            format!(
                "{} numbers where the vertex, face and edge counts belong: this reader takes \
                 the vertices and faces one per line after that line",
                counts.len()
            ),
        ));
    }
    let (nv_tok, nf_tok) = match counts.as_slice() {
        [v, f, ..] => (v.0, f.0),
        _ => {
            return Err(parse_err(
                counts_line,
                "expected the vertex, face and edge counts".to_owned(),
            ))
        }
    };
    let nv = parse_count(nv_tok, counts_line, "vertex")?;
    let nf = parse_count(nf_tok, counts_line, "face")?;

    // Bytes after the counts line bound what the counts may claim.
    let counts_end = line_end_offset(bytes, counts_line);
    let available = (bytes.len() - counts_end.min(bytes.len())) as u64;
    let vertex_bytes = u128::from(nv) * u128::from(MIN_VERTEX_BYTES);
    let face_bytes = u128::from(nf) * u128::from(MIN_FACE_BYTES);
    let room = u128::from(available) + 1; // the last line may lack its newline
    if vertex_bytes > room {
        return Err(LoadError::ClaimedCountTooLarge {
            format: FORMAT,
            element: "vertex".to_owned(),
            claimed: nv,
            available_bytes: available,
        });
    }
    if vertex_bytes + face_bytes > room {
        return Err(LoadError::ClaimedCountTooLarge {
            format: FORMAT,
            element: "face".to_owned(),
            claimed: nf,
            available_bytes: available,
        });
    }
    for (n, what) in [(nv, "vertices"), (nf, "faces")] {
        if n > MAX_ELEMENTS as u64 {
            return Err(LoadError::TooManyElements {
                format: FORMAT,
                what,
                limit: MAX_ELEMENTS as u64,
            });
        }
    }
    // Both counts are now at most the input size and `MAX_ELEMENTS`.
    let (nv, nf) = (nv as usize, nf as usize);

    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(nv);
    for got in 0..nv {
        let (n, l) = lines.next().ok_or(LoadError::Truncated {
            format: FORMAT,
            what: "vertices",
            expected: nv as u64,
            got: got as u64,
        })?;
        let mut toks = tokens(l);
        let mut p = [0.0; 3];
        for c in &mut p {
            let t = toks
                .next()
                .ok_or_else(|| parse_err(n, "a vertex needs three coordinates".to_owned()))?;
            *c = parse_f64(t)
                .ok_or_else(|| parse_err(n, format!("expected a number, found `{}`", show(t))))?;
        }
        positions.push(p);
    }

    let mut sink = FaceSink::new(FORMAT, nf);
    let mut ids: Vec<u32> = Vec::new();
    for got in 0..nf {
        let (n, l) = lines.next().ok_or(LoadError::Truncated {
            format: FORMAT,
            what: "faces",
            expected: nf as u64,
            got: got as u64,
        })?;
        let mut toks = tokens(l);
        let k_tok = toks.next().unwrap_or_default();
        let k = std::str::from_utf8(k_tok)
            .ok()
            .and_then(|s| s.parse::<usize>().ok())
            .ok_or_else(|| {
                parse_err(
                    n,
                    format!("expected the face's vertex count, found `{}`", show(k_tok)),
                )
            })?;
        ids.clear();
        // The indices may run on over the next lines (as CGAL and libigl
        // read them); the rest of the line holding the last one is color.
        let mut at = n;
        for _ in 0..k {
            let t = loop {
                if let Some(t) = toks.next() {
                    break t;
                }
                let (next, l) = lines.next().ok_or_else(|| {
                    parse_err(
                        at,
                        format!("the face announces {k} vertices but lists fewer"),
                    )
                })?;
                (at, toks) = (next, tokens(l));
            };
            ids.push(parse_index_u32(FORMAT, Some(at), t)?);
        }
        sink.push(&ids)?;
    }

    let mut notes: Vec<LoadNote> = Vec::new();
    let (faces, triangulated) = sink.finish(&positions);
    notes.extend(triangulated);
    let mesh = Mesh { positions, faces };
    Ok((
        mesh,
        LoadReport {
            format: FORMAT,
            notes,
        },
    ))
}

/// The byte offset just past the end of 1-based line `line` (its line end
/// as [`Lines`] reads it).
fn line_end_offset(bytes: &[u8], line: usize) -> usize {
    let mut lines = Lines::new(bytes);
    for _ in 0..line {
        if lines.next().is_none() {
            return bytes.len();
        }
    }
    bytes.len() - lines.rest_len()
}

/// Writes OFF with shortest round-trip coordinates.
pub(super) fn write<W: Write>(mesh: &Mesh, out: &mut W) -> Result<(), SaveError> {
    let mut body = || -> std::io::Result<()> {
        writeln!(out, "OFF\n{} {} 0", mesh.positions.len(), mesh.faces.len())?;
        for p in &mesh.positions {
            text::write_f64(out, p[0])?;
            out.write_all(b" ")?;
            text::write_f64(out, p[1])?;
            out.write_all(b" ")?;
            text::write_f64(out, p[2])?;
            out.write_all(b"\n")?;
        }
        for [a, b, c] in &mesh.faces {
            writeln!(out, "3 {} {} {}", a.0, b.0, c.0)?;
        }
        Ok(())
    };
    body().map_err(write_err)
}
