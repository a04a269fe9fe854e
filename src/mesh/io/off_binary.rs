//! Input: the bytes of a binary OFF file after its `OFF BINARY` header line,
//! and the header's keyword. Output: a [`Mesh`] (polygons split into fans,
//! or by ear clipping as in `polygon.rs`) and the layout it was read in.
//!
//! Binary OFF holds 32-bit values: the vertex, face and edge counts; per
//! vertex `x y z` as `f32`, then a normal (3 `f32`, prefix `N`), a color
//! (4 `f32`, prefix `C`) and texture coordinates (2 `f32`, prefix `ST`);
//! per face a vertex count `k`, `k` vertex indices and, in Geomview's
//! layout, a color count `c` and `c` `f32` color values. Geomview writes
//! them big-endian; `pmp-library` writes no color counts, big-endian now
//! and little-endian in earlier versions (its sample meshes are). The file
//! does not say which, so every layout is tried ([`BinaryOffLayout::ALL`]), each
//! only as a walk over the bytes: the counts must fit the bytes that
//! follow, every face must have at least three vertices and at most four
//! color values, and the walk must end exactly at the end of the file. A
//! file is read when exactly one layout passes, refused by name when none
//! or several do: never guessed. Hand-written, like the ASCII reader: no
//! maintained crate reads binary OFF.

use super::text::FaceSink;
use super::{InvalidIndexReason, LoadError, LoadNote, LoadReport, MeshFormat, MAX_ELEMENTS};
use crate::mesh::Mesh;
use std::fmt;

const FORMAT: MeshFormat = MeshFormat::Off;

/// The order of a 32-bit value's bytes in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ByteOrder {
    /// Most significant byte first (Geomview's binary OFF).
    Big,
    /// Least significant byte first.
    Little,
}

/// Whether each face of a binary OFF file ends with a color count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FaceColors {
    /// A color count `c` and `c` color values follow the indices
    /// (Geomview).
    Counted,
    /// The indices end the face (`pmp-library`).
    Absent,
}

/// How a binary OFF file lays out its values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BinaryOffLayout {
    /// The byte order of every value.
    pub byte_order: ByteOrder,
    /// Whether faces carry color counts.
    pub face_colors: FaceColors,
}

impl BinaryOffLayout {
    /// Every layout a binary OFF file may have.
    pub const ALL: [BinaryOffLayout; 4] = [
        BinaryOffLayout {
            byte_order: ByteOrder::Big,
            face_colors: FaceColors::Counted,
        },
        BinaryOffLayout {
            byte_order: ByteOrder::Big,
            face_colors: FaceColors::Absent,
        },
        BinaryOffLayout {
            byte_order: ByteOrder::Little,
            face_colors: FaceColors::Counted,
        },
        BinaryOffLayout {
            byte_order: ByteOrder::Little,
            face_colors: FaceColors::Absent,
        },
    ];
}

impl fmt::Display for BinaryOffLayout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let order = match self.byte_order {
            ByteOrder::Big => "big-endian",
            ByteOrder::Little => "little-endian",
        };
        let colors = match self.face_colors {
            FaceColors::Counted => "with per-face color counts",
            FaceColors::Absent => "without per-face color counts",
        };
        write!(f, "{order}, {colors}")
    }
}

/// The most color values a face may carry (an RGBA color).
const MAX_FACE_COLORS: u32 = 4;

/// 32-bit values read in one byte order; `None` past the end.
struct Values<'a> {
    bytes: &'a [u8],
    at: usize,
    order: ByteOrder,
}

impl Values<'_> {
    fn u32(&mut self) -> Option<u32> {
        let word: [u8; 4] = self.bytes.get(self.at..self.at + 4)?.try_into().ok()?;
        self.at += 4;
        Some(match self.order {
            ByteOrder::Big => u32::from_be_bytes(word),
            ByteOrder::Little => u32::from_le_bytes(word),
        })
    }

    fn f32(&mut self) -> Option<f32> {
        self.u32().map(f32::from_bits)
    }

    /// Skips `n` values; `None` when fewer are left.
    fn skip(&mut self, n: u64) -> Option<()> {
        let end = u64::try_from(self.at)
            .ok()?
            .checked_add(n.checked_mul(4)?)?;
        if end > self.bytes.len() as u64 {
            return None;
        }
        self.at = end as usize;
        Some(())
    }

    fn left(&self) -> u64 {
        (self.bytes.len() - self.at) as u64
    }
}

/// The values per vertex that the keyword's prefixes add to `x y z`.
fn extra_vertex_values(keyword: &[u8]) -> u64 {
    let prefix = keyword.strip_suffix(b"OFF").unwrap_or_default();
    let has = |s: &[u8]| prefix.windows(s.len()).any(|w| w == s);
    3 * u64::from(has(b"N")) + 4 * u64::from(has(b"C")) + 2 * u64::from(has(b"ST"))
}

/// The mesh being built by a walk.
struct Building {
    positions: Vec<[f64; 3]>,
    sink: FaceSink,
    ids: Vec<u32>,
}

/// Walks `data` in `layout`: `Ok(Some(counts))` when the layout reads it
/// to its end exactly (see the module documentation), `Ok(None)` when it
/// does not. A trial (`build: None`) allocates nothing and fails on
/// nothing else; a build collects the mesh and refuses a negative index
/// or too many faces.
fn walk(
    data: &[u8],
    layout: BinaryOffLayout,
    per_vertex: u64,
    mut build: Option<&mut Building>,
) -> Result<Option<(u32, u32)>, LoadError> {
    let mut v = Values {
        bytes: data,
        at: 0,
        order: layout.byte_order,
    };
    let Some((nv, nf, _edges)) = (|| Some((v.u32()?, v.u32()?, v.u32()?)))() else {
        return Ok(None);
    };
    // Each face takes at least four values: the bound holds before any
    // face is read, and bounds what a build reserves.
    let least = u128::from(nv) * u128::from(per_vertex) * 4 + u128::from(nf) * 16;
    if least > u128::from(v.left()) {
        return Ok(None);
    }
    match build.as_deref_mut() {
        None => {
            if v.skip(u64::from(nv) * per_vertex).is_none() {
                return Ok(None);
            }
        }
        Some(b) => {
            b.positions.reserve(nv as usize);
            for _ in 0..nv {
                let p = [v.f32(), v.f32(), v.f32()];
                let (Some(x), Some(y), Some(z)) = (p[0], p[1], p[2]) else {
                    return Ok(None);
                };
                b.positions.push([x, y, z].map(f64::from));
                if v.skip(per_vertex - 3).is_none() {
                    return Ok(None);
                }
            }
        }
    }
    for face in 0..nf {
        let Some(k) = v.u32().filter(|&k| k >= 3) else {
            return Ok(None);
        };
        match build.as_deref_mut() {
            None => {
                if v.skip(u64::from(k)).is_none() {
                    return Ok(None);
                }
            }
            Some(b) => {
                b.ids.clear();
                for _ in 0..k {
                    let Some(id) = v.u32() else {
                        return Ok(None);
                    };
                    if id > i32::MAX as u32 {
                        return Err(LoadError::InvalidIndex {
                            format: FORMAT,
                            line: None,
                            text: format!("{} (face {face})", id as i32),
                            reason: InvalidIndexReason::Negative,
                        });
                    }
                    b.ids.push(id);
                }
                b.sink.push(&b.ids)?;
            }
        }
        if layout.face_colors == FaceColors::Counted {
            let colors = v.u32().filter(|&c| c <= MAX_FACE_COLORS);
            if colors.and_then(|c| v.skip(u64::from(c))).is_none() {
                return Ok(None);
            }
        }
    }
    Ok((v.left() == 0).then_some((nv, nf)))
}

/// Reads binary OFF: `data` is the file after its header line, `keyword`
/// the header's keyword (`OFF`, `NOFF`, `COFF`, ...; not `4OFF`, `nOFF`).
pub(super) fn read(data: &[u8], keyword: &[u8]) -> Result<(Mesh, LoadReport), LoadError> {
    let per_vertex = 3 + extra_vertex_values(keyword);
    let mut fits = Vec::new();
    for layout in BinaryOffLayout::ALL {
        if let Some(counts) = walk(data, layout, per_vertex, None)? {
            fits.push((layout, counts));
        }
    }
    if !fits.is_empty() && fits.iter().all(|&(_, (_, nf))| nf == 0) {
        // A file with no faces reads alike with and without color counts
        // (and in both byte orders when its counts read the same both
        // ways, as zero does): refused for what it lacks, not as ambiguous.
        return Err(parse_err(
            "binary OFF: the file declares no faces".to_owned(),
        ));
    }
    let (layout, (nv, nf)) = match fits.as_slice() {
        [one] => *one,
        [] => return Err(no_layout()),
        // Not met by any file of a realistic size: with faces, the layouts
        // with and without color counts cannot both read a file to its end
        // (a face's color count of 3 or 4 would have to be the next face's
        // vertex count, so the one reads two faces where the other reads
        // one), and both byte orders would need face and vertex counts
        // whose bytes read the same both ways (at least 0x01000001).
        several => {
            let names: Vec<String> = several.iter().map(|(l, _)| format!("({l})")).collect();
            return Err(parse_err(format!(
                "binary OFF: the file reads to its end in more than one layout, {}: refused rather than guessed",
                names.join(" and ")
            )));
        }
    };
    for (n, what) in [(nv, "vertices"), (nf, "faces")] {
        if n as usize > MAX_ELEMENTS {
            return Err(LoadError::TooManyElements {
                format: FORMAT,
                what,
                limit: MAX_ELEMENTS as u64,
            });
        }
    }
    let mut b = Building {
        positions: Vec::new(),
        sink: FaceSink::new(FORMAT, nf as usize),
        ids: Vec::new(),
    };
    // The same walk as the trial that passed: it passes again.
    walk(data, layout, per_vertex, Some(&mut b))?.ok_or_else(no_layout)?;
    let mut notes = vec![LoadNote::BinaryOffLayout(layout)];
    let (faces, triangulated) = b.sink.finish(&b.positions);
    notes.extend(triangulated);
    Ok((
        Mesh {
            positions: b.positions,
            faces,
        },
        LoadReport {
            format: FORMAT,
            notes,
        },
    ))
}

fn no_layout() -> LoadError {
    parse_err(
        "binary OFF: no layout (32-bit values big- or little-endian, faces with or without \
         color counts) reads the file to its end: truncated, or not binary OFF"
            .to_owned(),
    )
}

fn parse_err(message: String) -> LoadError {
    LoadError::Parse {
        format: FORMAT,
        line: None,
        message,
    }
}
