//! Input: the bytes of a text mesh format (OBJ, OFF, ASCII STL). Output:
//! numbered lines, whitespace-separated tokens, exactly rounded numbers, and
//! a face sink that fan-triangulates polygons under the element limit.
//!
//! Works on bytes, not `str`: a stray non-UTF-8 byte in a comment or a name
//! does not fail the file; only a number that is not valid text does.

use super::{LoadError, LoadNote, MeshFormat, MAX_ELEMENTS};
use crate::ids::VertexId;

/// Iterator over `(1-based line number, line without its end of line)`.
/// A line ends at `\n`, `\r\n`, or a lone `\r` (classic Mac OS files,
/// as the ASCII STL reader also takes them).
pub(super) struct Lines<'a> {
    rest: &'a [u8],
    line: usize,
    done: bool,
}

impl<'a> Lines<'a> {
    pub(super) fn new(bytes: &'a [u8]) -> Self {
        Lines {
            rest: bytes,
            line: 0,
            done: false,
        }
    }

    /// How many bytes follow the lines read so far.
    pub(super) fn rest_len(&self) -> usize {
        self.rest.len()
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        self.line = self.line.saturating_add(1);
        let (line, rest) = match memchr::memchr2(b'\n', b'\r', self.rest) {
            Some(i) => {
                let crlf = self.rest[i] == b'\r' && self.rest.get(i + 1) == Some(&b'\n');
                (&self.rest[..i], &self.rest[i + 1 + usize::from(crlf)..])
            }
            None => {
                self.done = true;
                (self.rest, &self.rest[self.rest.len()..])
            }
        };
        self.rest = rest;
        Some((self.line, line))
    }
}

/// Whether `bytes[i]` is a `\r` that ends a line by itself (classic Mac
/// OS line ends), not the first half of `\r\n`.
pub(super) fn is_lone_cr(bytes: &[u8], i: usize) -> bool {
    bytes.get(i) == Some(&b'\r') && bytes.get(i + 1) != Some(&b'\n')
}

/// Whether a byte separates tokens (ASCII whitespace, and NUL, which some
/// exporters pad text files with).
#[inline]
pub(super) fn is_space(b: u8) -> bool {
    b.is_ascii_whitespace() || b == 0 || b == 0x0b
}

/// The whitespace-separated tokens of a line.
pub(super) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|&b| is_space(b)).filter(|t| !t.is_empty())
}

/// Parses a number with Rust's correctly rounded parser (nearest `f64`;
/// accepts `inf` and `nan`, which validation reports).
pub(super) fn parse_f64(token: &[u8]) -> Option<f64> {
    std::str::from_utf8(token).ok()?.parse::<f64>().ok()
}

/// A token shown in an error message (lossy, at most 40 characters).
pub(super) fn show(token: &[u8]) -> String {
    let s = String::from_utf8_lossy(token);
    if s.chars().count() > 40 {
        let mut t: String = s.chars().take(40).collect();
        t.push_str("...");
        t
    } else {
        s.into_owned()
    }
}

/// Parses a non-negative integer index that must fit in `u32`.
pub(super) fn parse_index_u32(
    format: MeshFormat,
    line: Option<usize>,
    token: &[u8],
) -> Result<u32, LoadError> {
    let bad = |reason| LoadError::InvalidIndex {
        format,
        line,
        text: show(token),
        reason,
    };
    let digits = token.strip_prefix(b"+").unwrap_or(token);
    if let Some(d) = digits.strip_prefix(b"-") {
        return Err(if is_digits(d) {
            bad(super::InvalidIndexReason::Negative)
        } else {
            bad(super::InvalidIndexReason::NotAnInteger)
        });
    }
    if !is_digits(digits) {
        return Err(bad(super::InvalidIndexReason::NotAnInteger));
    }
    std::str::from_utf8(digits)
        .ok()
        .and_then(|s| s.parse::<u32>().ok())
        .ok_or(bad(super::InvalidIndexReason::TooLarge))
}

/// Whether a token is one or more ASCII digits.
pub(super) fn is_digits(t: &[u8]) -> bool {
    !t.is_empty() && t.iter().all(u8::is_ascii_digit)
}

/// Collects faces, splitting polygons into fans (and, once the vertices
/// are read, ear clipping flat ones whose fans would fold), counting what
/// it did.
pub(super) struct FaceSink {
    format: MeshFormat,
    pub(super) faces: Vec<[VertexId; 3]>,
    /// Each polygon's first triangle in `faces` and its number of
    /// triangles (both within [`MAX_ELEMENTS`], so `u32`: 8 bytes a
    /// polygon).
    polygon_at: Vec<(u32, u32)>,
    /// Faces read from the file (before triangulation), for error messages.
    pub(super) read: usize,
}

impl FaceSink {
    pub(super) fn new(format: MeshFormat, capacity: usize) -> Self {
        FaceSink {
            format,
            faces: Vec::with_capacity(capacity),
            polygon_at: Vec::new(),
            read: 0,
        }
    }

    /// Adds one face given as raw vertex ids (any values: out-of-range ids
    /// are kept for validation). Polygons become fans `(0, i, i + 1)`.
    pub(super) fn push(&mut self, ids: &[u32]) -> Result<(), LoadError> {
        let face = self.read;
        self.read = self.read.saturating_add(1);
        let (&first, rest) = match ids.split_first() {
            Some(x) if ids.len() >= 3 => x,
            _ => {
                return Err(LoadError::NonTriangleFace {
                    format: self.format,
                    face,
                    arity: ids.len(),
                })
            }
        };
        let new = ids.len() - 2;
        if self.faces.len().saturating_add(new) > MAX_ELEMENTS {
            return Err(LoadError::TooManyElements {
                format: self.format,
                what: "faces",
                limit: MAX_ELEMENTS as u64,
            });
        }
        if new > 1 {
            // Within the element limit checked above.
            self.polygon_at.push((self.faces.len() as u32, new as u32));
        }
        for pair in rest.windows(2) {
            self.faces
                .push([VertexId(first), VertexId(pair[0]), VertexId(pair[1])]);
        }
        Ok(())
    }

    /// The faces, once every vertex is read: a flat polygon whose fan
    /// would fold is split by ear clipping instead ([`super::polygon`]);
    /// and the triangulation note, if any polygon was split.
    pub(super) fn finish(
        mut self,
        positions: &[[f64; 3]],
    ) -> (Vec<[VertexId; 3]>, Option<LoadNote>) {
        let mut ear_clipped = 0;
        let mut budget = super::polygon::EAR_CLIPPING_BUDGET;
        let mut ids = Vec::new();
        for &(at, triangles) in &self.polygon_at {
            let range = at as usize..at as usize + triangles as usize;
            let fan = &self.faces[range.clone()];
            ids.clear();
            ids.extend(
                [fan[0][0], fan[0][1]]
                    .iter()
                    .chain(fan.iter().map(|t| &t[2]))
                    .map(|v| v.0),
            );
            if let Some(tris) = super::polygon::untangled(&ids, positions, &mut budget) {
                for (face, t) in self.faces[range].iter_mut().zip(tris) {
                    *face = t.map(VertexId);
                }
                ear_clipped += 1;
            }
        }
        let note = (!self.polygon_at.is_empty()).then_some(LoadNote::Triangulated {
            polygons: self.polygon_at.len(),
            triangles: self.polygon_at.iter().map(|&(_, n)| n as usize).sum(),
            ear_clipped,
        });
        (self.faces, note)
    }
}

/// Fails when one more vertex would exceed the element limit.
pub(super) fn check_vertex_room(format: MeshFormat, len: usize) -> Result<(), LoadError> {
    if len >= MAX_ELEMENTS {
        Err(LoadError::TooManyElements {
            format,
            what: "vertices",
            limit: MAX_ELEMENTS as u64,
        })
    } else {
        Ok(())
    }
}

/// Writes an `f64` with the shortest representation that parses back to the
/// same value (Rust's `{:?}`: `0.1`, `1.0`, `-0.0`, `1e-7`, `inf`, `NaN`).
pub(super) fn write_f64<W: std::io::Write>(out: &mut W, x: f64) -> std::io::Result<()> {
    write!(out, "{x:?}")
}
