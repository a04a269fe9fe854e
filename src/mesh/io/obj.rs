//! Input: Wavefront OBJ bytes. Output: a [`Mesh`] of all `v` and `f`
//! statements of all objects and groups (merged), polygons split into fans
//! (or, flat ones whose fan would fold, by ear clipping: `polygon.rs`);
//! and the OBJ writer.
//!
//! Hand-written reader: tobj drops unused vertices and renumbers the rest
//! per model, rejects out-of-range indices (which must load so validation
//! can name them) and parses `f32` unless a crate-wide feature is set.
//!
//! Indices: `k >= 1` is vertex `k - 1`, `k < 0` counts back from the
//! vertices read so far; `0`, a relative index before the first vertex, and
//! an index beyond `u32` are errors. Indices past the vertex count load as
//! they are. Texture and normal indices (`v/vt/vn`) are ignored, as are
//! `vt`, `vn`, materials, groups, smoothing; `l` and `p` elements are counted
//! in a note. A `#` starts a comment, on its own line or after a face's
//! ids.

use std::io::Write;

use super::text::{self, check_vertex_room, parse_f64, show, tokens, FaceSink, Lines};
use super::{
    write_err, InvalidIndexReason, LoadError, LoadNote, LoadReport, MeshFormat, SaveError,
};
use crate::mesh::Mesh;

const FORMAT: MeshFormat = MeshFormat::Obj;

/// Reads OBJ.
pub(super) fn read(bytes: &[u8]) -> Result<(Mesh, LoadReport), LoadError> {
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut sink = FaceSink::new(FORMAT, 0);
    let mut ids: Vec<u32> = Vec::new();
    let mut lines_and_points = 0usize;
    let mut unknown = 0usize;
    // The first unrecognized statement's keyword and line, for the note (a
    // file of another format named `.obj` is all unrecognized).
    let mut first_unknown: Option<(String, usize)> = None;
    let mut joined: Vec<u8> = Vec::new();
    let mut lines = Lines::new(bytes);

    while let Some((number, first)) = lines.next() {
        // A trailing backslash continues the statement on the next line.
        let line: &[u8] = if first.ends_with(b"\\") {
            joined.clear();
            let mut part = first;
            while let Some(head) = part.strip_suffix(b"\\") {
                joined.extend_from_slice(head);
                joined.push(b' ');
                match lines.next() {
                    Some((_, next)) => part = next,
                    None => {
                        part = &[];
                        break;
                    }
                }
            }
            joined.extend_from_slice(part);
            &joined
        } else {
            first
        };
        let line_no = Some(number);
        let mut toks = tokens(line);
        let Some(keyword) = toks.next() else { continue };
        match keyword {
            b"v" => {
                let mut p = [0.0; 3];
                for c in &mut p {
                    let t = toks.next().ok_or_else(|| LoadError::Parse {
                        format: FORMAT,
                        line: line_no,
                        message: "a vertex needs three coordinates".to_owned(),
                    })?;
                    *c = parse_f64(t).ok_or_else(|| LoadError::Parse {
                        format: FORMAT,
                        line: line_no,
                        message: format!("expected a number, found `{}`", show(t)),
                    })?;
                }
                check_vertex_room(FORMAT, positions.len())?;
                positions.push(p);
            }
            b"f" | b"fo" => {
                ids.clear();
                // A `#` starts a comment, after the ids as on its own line.
                for t in toks.take_while(|t| !t.starts_with(b"#")) {
                    let v = t.split(|&b| b == b'/').next().unwrap_or(t);
                    ids.push(parse_index(v, positions.len(), line_no)?);
                }
                sink.push(&ids)?;
            }
            b"l" | b"p" => lines_and_points += 1,
            b"vt" | b"vn" | b"vp" | b"o" | b"g" | b"s" | b"mg" | b"usemtl" | b"mtllib"
            | b"usemap" | b"maplib" => {}
            k if k.starts_with(b"#") => {}
            k => {
                unknown += 1;
                first_unknown.get_or_insert_with(|| (show(k), number));
            }
        }
    }

    let mut notes = Vec::new();
    let (faces, triangulated) = sink.finish(&positions);
    notes.extend(triangulated);
    if lines_and_points > 0 {
        notes.push(LoadNote::Ignored {
            kind: "line and point elements".to_owned(),
            count: lines_and_points,
        });
    }
    if let Some((keyword, line)) = first_unknown {
        notes.push(LoadNote::Ignored {
            kind: format!("unrecognized statements (the first, on line {line}: `{keyword}`)"),
            count: unknown,
        });
    }
    let mesh = Mesh { positions, faces };
    Ok((
        mesh,
        LoadReport {
            format: FORMAT,
            notes,
        },
    ))
}

/// Resolves one OBJ vertex reference (1-based or negative relative).
fn parse_index(token: &[u8], seen: usize, line: Option<usize>) -> Result<u32, LoadError> {
    let bad = |reason| LoadError::InvalidIndex {
        format: FORMAT,
        line,
        text: show(token),
        reason,
    };
    let (negative, digits) = match token.split_first() {
        Some((b'-', d)) => (true, d),
        Some((b'+', d)) => (false, d),
        _ => (false, token),
    };
    if !text::is_digits(digits) {
        return Err(bad(InvalidIndexReason::NotAnInteger));
    }
    let k: u64 = std::str::from_utf8(digits)
        .ok()
        .and_then(|s| s.parse().ok())
        .ok_or(bad(InvalidIndexReason::TooLarge))?;
    if k == 0 {
        return Err(bad(InvalidIndexReason::Zero));
    }
    let index = if negative {
        (seen as u64)
            .checked_sub(k)
            .ok_or(bad(InvalidIndexReason::BeforeFirstVertex))?
    } else {
        k - 1
    };
    u32::try_from(index).map_err(|_| bad(InvalidIndexReason::TooLarge))
}

/// Writes OBJ: `v x y z` with shortest round-trip numbers, `f a b c`
/// 1-based.
pub(super) fn write<W: Write>(mesh: &Mesh, out: &mut W) -> Result<(), SaveError> {
    let mut body = || -> std::io::Result<()> {
        out.write_all(b"# written by wmslice\n")?;
        for p in &mesh.positions {
            out.write_all(b"v ")?;
            text::write_f64(out, p[0])?;
            out.write_all(b" ")?;
            text::write_f64(out, p[1])?;
            out.write_all(b" ")?;
            text::write_f64(out, p[2])?;
            out.write_all(b"\n")?;
        }
        for [a, b, c] in &mesh.faces {
            let one = |v: crate::ids::VertexId| u64::from(v.0) + 1;
            writeln!(out, "f {} {} {}", one(*a), one(*b), one(*c))?;
        }
        Ok(())
    };
    body().map_err(write_err)
}
