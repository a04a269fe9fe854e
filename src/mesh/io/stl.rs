//! Input: STL bytes (binary or ASCII). Output: a welded [`Mesh`]; and the
//! binary (through `stl_io::write_stl`) and ASCII STL writers.
//!
//! Hand-written readers: stl_io picks ASCII whenever the header starts with
//! `solid ` (many binary files do), its binary reader is private, and its
//! ASCII reader parses `f32` (rounding the `f64` text we write).
//!
//! Binary or ASCII is decided by content: a file of exactly 84 + 50 n bytes
//! (n read at offset 80) is binary even if it starts with `solid`; a file
//! starting with `solid`, or whose first kilobyte is text, is read as
//! ASCII, falling back to binary only when the ASCII parse fails and the
//! bytes are not text.

use std::io::Write;

use super::text::{self, is_space, parse_f64, show};
use super::{corners, write_err, LoadError, LoadNote, LoadReport, MeshFormat, SaveError};
use crate::mesh::weld::{try_weld_exact, weld_corners, WeldError, Welded};
use crate::mesh::Mesh;

const HEADER: usize = 80;
const RECORD: u64 = 50;

/// The triangle count a binary header claims, if there is a header.
fn claimed_count(bytes: &[u8]) -> Option<u32> {
    let b = bytes.get(HEADER..HEADER + 4)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// Whether the size is exactly 84 + 50 n for the n in the header.
pub(super) fn binary_size_matches(bytes: &[u8]) -> bool {
    claimed_count(bytes).is_some_and(|n| 84 + RECORD * u64::from(n) == bytes.len() as u64)
}

/// Whether the header claims no triangle and a positive whole number of
/// records follows (a count never filled in, read by size).
pub(super) fn binary_count_unfilled(bytes: &[u8]) -> bool {
    let available = (bytes.len() as u64).saturating_sub(84);
    claimed_count(bytes) == Some(0) && available > 0 && available % RECORD == 0
}

/// Whether the file starts (after blanks) with the keyword `solid`.
fn starts_with_solid(bytes: &[u8]) -> bool {
    let start = bytes
        .iter()
        .position(|&b| !is_space(b))
        .unwrap_or(bytes.len());
    let rest = &bytes[start..];
    rest.len() >= 5
        && rest[..5].eq_ignore_ascii_case(b"solid")
        && !matches!(rest.get(5), Some(&b) if !is_space(b))
}

/// Whether the file's first kilobyte looks like text.
fn looks_like_text(bytes: &[u8]) -> bool {
    bytes
        .iter()
        .take(1024)
        .all(|&b| b == b'\t' || b == b'\n' || b == b'\r' || (0x20..0x7f).contains(&b))
}

/// Reads STL, binary or ASCII as the content says.
pub(super) fn read(bytes: &[u8]) -> Result<(Mesh, LoadReport), LoadError> {
    if binary_size_matches(bytes) {
        return read_binary(bytes);
    }
    // Text that is no binary STL of its size and does not start with
    // `solid` (comments before it, a typo): the ASCII reader names the
    // first word, which says more than a binary triangle count read from
    // characters. (An empty file stays a truncated binary one.)
    if starts_with_solid(bytes) || (!bytes.is_empty() && looks_like_text(bytes)) {
        return match read_ascii(bytes) {
            Ok(r) => Ok(r),
            Err(e) => {
                // Content that is not text is binary whatever its header
                // says: the binary reader's verdict names what is wrong.
                if looks_like_text(bytes) {
                    Err(e)
                } else {
                    read_binary(bytes)
                }
            }
        };
    }
    read_binary(bytes)
}

fn weld_error(e: WeldError, format: MeshFormat) -> LoadError {
    match e {
        WeldError::TooManyElements { what, limit } => LoadError::TooManyElements {
            format,
            what,
            limit: limit as u64,
        },
    }
}

fn read_binary(bytes: &[u8]) -> Result<(Mesh, LoadReport), LoadError> {
    let format = MeshFormat::StlBinary;
    let len = bytes.len() as u64;
    let n = claimed_count(bytes).ok_or(LoadError::Truncated {
        format,
        what: "bytes",
        expected: 84,
        got: len,
    })?;
    let available = len - 84;
    let mut notes = Vec::new();
    let n = if binary_count_unfilled(bytes) {
        notes.push(LoadNote::StlCountZero {
            triangles: available / RECORD,
        });
        u32::try_from(available / RECORD).unwrap_or(u32::MAX)
    } else {
        n
    };
    let need = 84 + RECORD * u64::from(n);
    if need > len {
        // Less than half of the claimed data: the count is not to be trusted.
        return Err(if available < RECORD * u64::from(n) / 2 {
            LoadError::ClaimedCountTooLarge {
                format,
                element: "triangle".to_owned(),
                claimed: u64::from(n),
                available_bytes: available,
            }
        } else {
            LoadError::Truncated {
                format,
                what: "bytes",
                expected: need,
                got: len,
            }
        });
    }
    if n as usize > super::MAX_ELEMENTS {
        return Err(LoadError::TooManyElements {
            format,
            what: "faces",
            limit: super::MAX_ELEMENTS as u64,
        });
    }
    if bytes.len() >= 5 && bytes[..5].eq_ignore_ascii_case(b"solid") {
        notes.push(LoadNote::BinaryStlHeaderSaysSolid);
    }
    // `need <= len`, checked above: the records are there, and welding reads
    // them in place (no soup of n triangles is allocated).
    let records = &bytes[84..need as usize];
    let f =
        |r: &[u8], o: usize| f64::from(f32::from_le_bytes([r[o], r[o + 1], r[o + 2], r[o + 3]]));
    // Bytes 0..12 of a record are the normal (ignored), 48..50 the
    // attribute count.
    let welded = weld_corners(n as usize, |i| {
        let o = (i / 3) * RECORD as usize + 12 + 12 * (i % 3);
        [f(records, o), f(records, o + 4), f(records, o + 8)]
    })
    .map_err(|e| weld_error(e, format))?;
    let rest = len - need;
    if rest > 0 && rest % RECORD == 0 {
        notes.push(LoadNote::StlUnclaimedTriangles {
            claimed: n,
            more: rest / RECORD,
        });
    } else if rest > 0 {
        notes.push(LoadNote::TrailingBytes { bytes: rest });
    }
    Ok(report(welded, format, notes))
}

fn finish(
    soup: Vec<[[f64; 3]; 3]>,
    format: MeshFormat,
    notes: Vec<LoadNote>,
) -> Result<(Mesh, LoadReport), LoadError> {
    let welded = try_weld_exact(&soup).map_err(|e| weld_error(e, format))?;
    Ok(report(welded, format, notes))
}

fn report(welded: Welded, format: MeshFormat, mut notes: Vec<LoadNote>) -> (Mesh, LoadReport) {
    notes.push(LoadNote::Welded {
        corners: welded.corners,
        vertices: welded.vertices,
    });
    (welded.mesh, LoadReport { format, notes })
}

/// Tokens of an ASCII file with their 1-based line numbers.
#[derive(Clone)]
struct Tokens<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Tokens<'a> {
    /// Whether the byte at `pos` ends a line: `\n`, or a `\r` not followed
    /// by `\n` (classic Mac OS line ends; `\r\n` ends at its `\n`).
    fn ends_line(&self, pos: usize) -> bool {
        self.bytes.get(pos) == Some(&b'\n') || text::is_lone_cr(self.bytes, pos)
    }

    fn next(&mut self) -> Option<(&'a [u8], usize)> {
        while let Some(&b) = self.bytes.get(self.pos) {
            if !is_space(b) {
                break;
            }
            if self.ends_line(self.pos) {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while self.bytes.get(self.pos).is_some_and(|&b| !is_space(b)) {
            self.pos += 1;
        }
        (self.pos > start).then(|| (&self.bytes[start..self.pos], self.line))
    }

    /// Skips the rest of the current line (a solid's name).
    fn skip_line(&mut self) {
        while self.pos < self.bytes.len() && !self.ends_line(self.pos) {
            self.pos += 1;
        }
    }
}

fn parse_err(line: usize, message: String) -> LoadError {
    LoadError::Parse {
        format: MeshFormat::StlAscii,
        line: Some(line),
        message,
    }
}

fn expect(tokens: &mut Tokens<'_>, keyword: &str, eof_line: usize) -> Result<usize, LoadError> {
    match tokens.next() {
        Some((t, line)) if t.eq_ignore_ascii_case(keyword.as_bytes()) => Ok(line),
        Some((t, line)) => Err(parse_err(
            line,
            format!("expected `{keyword}`, found `{}`", show(t)),
        )),
        None => Err(parse_err(
            eof_line,
            format!("unexpected end of file: expected `{keyword}`"),
        )),
    }
}

fn number(tokens: &mut Tokens<'_>, eof_line: usize) -> Result<f64, LoadError> {
    match tokens.next() {
        Some((t, line)) => parse_f64(t)
            .ok_or_else(|| parse_err(line, format!("expected a number, found `{}`", show(t)))),
        None => Err(parse_err(
            eof_line,
            "unexpected end of file: expected a number".to_owned(),
        )),
    }
}

fn read_ascii(bytes: &[u8]) -> Result<(Mesh, LoadReport), LoadError> {
    let format = MeshFormat::StlAscii;
    let mut tokens = Tokens {
        bytes,
        pos: 0,
        line: 1,
    };
    let mut soup: Vec<[[f64; 3]; 3]> = Vec::new();
    let mut polygons = 0usize;
    let mut fan_triangles = 0usize;
    let mut facets = 0usize;
    let mut loop_vertices: Vec<[f64; 3]> = Vec::with_capacity(3);
    let mut solids = 0usize;
    let mut unreadable_normals = 0usize;
    let mut missing_normals = 0usize;
    let mut stray_words = 0usize;
    let mut endfacet_line = None;
    let mut endsolid_line = None;

    'solids: loop {
        let eof_line = tokens.line;
        match tokens.next() {
            None if solids > 0 => break 'solids,
            None => {
                return Err(parse_err(
                    eof_line,
                    "empty file: expected `solid`".to_owned(),
                ))
            }
            Some((t, _)) if t.eq_ignore_ascii_case(b"solid") => {
                solids += 1;
                tokens.skip_line();
            }
            Some((t, line)) => {
                // After a solid: say where it ended, and what the word is
                // (a facet outside any solid, or text that is not STL, as
                // a gmsh script appended to the file).
                let after = match endsolid_line {
                    Some(e) if t.eq_ignore_ascii_case(b"facet") => format!(
                        " after `endsolid` on line {e}: a facet outside any solid (an `endsolid` too early?)"
                    ),
                    Some(e) => format!(" after `endsolid` on line {e}: what follows the last solid is not STL"),
                    None => String::new(),
                };
                return Err(parse_err(
                    line,
                    format!("expected `solid`, found `{}`{after}", show(t)),
                ));
            }
        }
        loop {
            let eof_line = tokens.line;
            let (t, line) = tokens.next().ok_or_else(|| {
                // After a whole facet, the file may be cut off between two
                // facets (whole bodies lost, nothing open to show it) or
                // written without its last line: the file cannot tell, so
                // it is refused, saying how to read it if it is whole.
                let why = if facets > 0 {
                    format!(
                        " (the file ends after {facets} whole facets without `endsolid`: \
                         cut off, or written without it; if it is whole, add `endsolid`)"
                    )
                } else {
                    String::new()
                };
                parse_err(
                    eof_line,
                    format!("unexpected end of file: expected `facet` or `endsolid`{why}"),
                )
            })?;
            if t.eq_ignore_ascii_case(b"endsolid") {
                endsolid_line = Some(line);
                tokens.skip_line();
                continue 'solids;
            }
            if !t.eq_ignore_ascii_case(b"facet") && endfacet_line == Some(line) {
                // A word after `endfacet` on its line (`endfacet bar`).
                stray_words += 1;
                continue;
            }
            if !t.eq_ignore_ascii_case(b"facet") {
                return Err(parse_err(
                    line,
                    format!("expected `facet` or `endsolid`, found `{}`", show(t)),
                ));
            }
            // `facet normal nx ny nz`: the normal is informative only (the
            // orientation is the vertex order's), so a component that is
            // not a number (`weirdvalue`, as exporters have written) is
            // counted, not refused, and so is a `facet` with no normal at
            // all (`facet` then `outer loop`). Exactly three tokens are
            // taken after `normal`: a normal missing one would take
            // `outer`, which is refused.
            let mut ahead = tokens.clone();
            if ahead
                .next()
                .is_some_and(|(t, _)| t.eq_ignore_ascii_case(b"outer"))
            {
                tokens = ahead;
                missing_normals += 1;
            } else {
                let after_facet = tokens.line;
                expect(&mut tokens, "normal", after_facet)?;
                let mut readable = true;
                for _ in 0..3 {
                    let l = tokens.line;
                    let (t, line) = tokens.next().ok_or_else(|| {
                        parse_err(l, "unexpected end of file: expected a number".to_owned())
                    })?;
                    if t.eq_ignore_ascii_case(b"outer") {
                        return Err(parse_err(
                            line,
                            "expected a number, found `outer`".to_owned(),
                        ));
                    }
                    readable &= parse_f64(t).is_some();
                }
                unreadable_normals += usize::from(!readable);
                let l = tokens.line;
                expect(&mut tokens, "outer", l)?;
            }
            let l = tokens.line;
            expect(&mut tokens, "loop", l)?;
            loop_vertices.clear();
            loop {
                let eof_line = tokens.line;
                let (t, line) = tokens.next().ok_or_else(|| {
                    parse_err(
                        eof_line,
                        "unexpected end of file: expected `vertex` or `endloop`".to_owned(),
                    )
                })?;
                if t.eq_ignore_ascii_case(b"endloop") {
                    break;
                }
                if !t.eq_ignore_ascii_case(b"vertex") {
                    return Err(parse_err(
                        line,
                        format!("expected `vertex` or `endloop`, found `{}`", show(t)),
                    ));
                }
                let mut p = [0.0; 3];
                for c in &mut p {
                    let l = tokens.line;
                    *c = number(&mut tokens, l)?;
                }
                loop_vertices.push(p);
            }
            // Words after `endloop` on its line (`endloop foo`) are
            // skipped and counted; `endfacet` must follow.
            let endloop_line = tokens.line;
            loop {
                let (t, line) = tokens.next().ok_or_else(|| {
                    parse_err(
                        tokens.line,
                        "unexpected end of file: expected `endfacet`".to_owned(),
                    )
                })?;
                if t.eq_ignore_ascii_case(b"endfacet") {
                    endfacet_line = Some(line);
                    break;
                }
                if line != endloop_line {
                    return Err(parse_err(
                        line,
                        format!("expected `endfacet`, found `{}`", show(t)),
                    ));
                }
                stray_words += 1;
            }
            let (&first, rest) = match loop_vertices.split_first() {
                Some(x) if loop_vertices.len() >= 3 => x,
                _ => {
                    return Err(LoadError::NonTriangleFace {
                        format,
                        face: facets,
                        arity: loop_vertices.len(),
                    })
                }
            };
            if soup.len().saturating_add(rest.len() - 1) > super::MAX_ELEMENTS {
                return Err(LoadError::TooManyElements {
                    format,
                    what: "faces",
                    limit: super::MAX_ELEMENTS as u64,
                });
            }
            for pair in rest.windows(2) {
                soup.push([first, pair[0], pair[1]]);
            }
            if rest.len() > 2 {
                polygons += 1;
                fan_triangles += rest.len() - 1;
            }
            facets += 1;
        }
    }
    let mut notes = Vec::new();
    if polygons > 0 {
        notes.push(LoadNote::Triangulated {
            polygons,
            triangles: fan_triangles,
            ear_clipped: 0,
        });
    }
    if unreadable_normals > 0 {
        notes.push(LoadNote::Ignored {
            kind: "facet normals that are not numbers (normals are not used)".to_owned(),
            count: unreadable_normals,
        });
    }
    if missing_normals > 0 {
        notes.push(LoadNote::Ignored {
            kind: "facets without a normal (normals are not used)".to_owned(),
            count: missing_normals,
        });
    }
    if stray_words > 0 {
        notes.push(LoadNote::Ignored {
            kind: "words after `endloop` or `endfacet` on their lines".to_owned(),
            count: stray_words,
        });
    }
    finish(soup, format, notes)
}

/// The unit normal of a triangle as `f32` (informative: readers ignore it).
fn normal(c: &[[f64; 3]; 3]) -> [f64; 3] {
    let u = [c[1][0] - c[0][0], c[1][1] - c[0][1], c[1][2] - c[0][2]];
    let v = [c[2][0] - c[0][0], c[2][1] - c[0][1], c[2][2] - c[0][2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len.is_finite() && len > 0.0 {
        [n[0] / len, n[1] / len, n[2] / len]
    } else {
        [0.0; 3]
    }
}

/// Writes binary STL. Coordinates must be exact `f32` unless `lossy`.
pub(super) fn write_binary<W: Write>(
    mesh: &Mesh,
    lossy: bool,
    out: &mut W,
) -> Result<(), SaveError> {
    if !lossy {
        for (v, p) in mesh.positions.iter().enumerate() {
            for &x in p {
                // NaN stays NaN in f32; every other value must survive.
                if !x.is_nan() && f64::from(x as f32) != x {
                    return Err(SaveError::NotF32Exact {
                        vertex: crate::ids::VertexId::from_idx(v),
                        value: x,
                    });
                }
            }
        }
    }
    if u32::try_from(mesh.faces.len()).is_err() {
        return Err(SaveError::TooManyFaces {
            format: MeshFormat::StlBinary,
            limit: u64::from(u32::MAX),
        });
    }
    let to32 = |p: [f64; 3]| stl_io::Vector::new([p[0] as f32, p[1] as f32, p[2] as f32]);
    let triangles = mesh.faces.iter().map(|tri| {
        let c = corners(mesh, tri);
        stl_io::Triangle {
            normal: to32(normal(&c)),
            vertices: [to32(c[0]), to32(c[1]), to32(c[2])],
        }
    });
    stl_io::write_stl(out, triangles).map_err(write_err)
}

/// Writes ASCII STL with shortest round-trip coordinates.
pub(super) fn write_ascii<W: Write>(mesh: &Mesh, out: &mut W) -> Result<(), SaveError> {
    let mut body = || -> std::io::Result<()> {
        out.write_all(b"solid wmslice\n")?;
        for tri in &mesh.faces {
            let c = corners(mesh, tri);
            let n = normal(&c);
            out.write_all(b"  facet normal ")?;
            write_triple(out, n)?;
            out.write_all(b"\n    outer loop\n")?;
            for p in c {
                out.write_all(b"      vertex ")?;
                write_triple(out, p)?;
                out.write_all(b"\n")?;
            }
            out.write_all(b"    endloop\n  endfacet\n")?;
        }
        out.write_all(b"endsolid wmslice\n")
    };
    body().map_err(write_err)
}

fn write_triple<W: Write>(out: &mut W, p: [f64; 3]) -> std::io::Result<()> {
    text::write_f64(out, p[0])?;
    out.write_all(b" ")?;
    text::write_f64(out, p[1])?;
    out.write_all(b" ")?;
    text::write_f64(out, p[2])
}
