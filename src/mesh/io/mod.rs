//! Input: mesh files (or their bytes) in STL (binary and ASCII), Wavefront
//! OBJ, OFF, PLY (ASCII, binary little and big endian) and 3MF. Output: a
//! [`Mesh`] with coordinates exactly as the file holds them, plus a
//! [`LoadReport`] saying what the loader did (welding, triangulation,
//! transforms); and the writers for the same formats.
//!
//! Exactness: binary formats keep their `f32`/`f64` values bit for bit; text
//! formats are parsed with Rust's correctly rounded `f64` parser and written
//! with the shortest round-trip formatting, so every writer/reader pair gives
//! back the same coordinates. Binary STL (`f32`) refuses, with
//! [`SaveError::NotF32Exact`], a coordinate it would round unless
//! [`SaveOptions::lossy_f32`] asks for it.
//!
//! Safety: no input panics; memory is bounded by the input size (counts in
//! headers are checked against the bytes that follow before anything is
//! allocated for them; 3MF parts are inflated under size and ratio limits).
//! Vertex and face counts are limited to [`MAX_ELEMENTS`] (`u32::MAX - 1`).
//!
//! Out-of-range face indices in OBJ, OFF and PLY still load (as ids `>=` the
//! vertex count) so that validation can report them with element ids.
//!
//! Outputs are written atomically: into a temporary file in the target
//! directory, then renamed over the target; an error leaves no partial file.

mod error;
mod exact_positions;
mod exact_transform;
mod obj;
mod off;
mod off_binary;
mod ply;
mod polygon;
mod stl;
mod text;
mod threemf;

use rayon::prelude::*;
use std::fmt;
use std::io::{self, BufWriter, Write};
use std::path::Path;

pub use error::{InvalidIndexReason, LoadError, SaveError};
pub use exact_positions::ExactPositions;
pub use off_binary::{BinaryOffLayout, ByteOrder, FaceColors};

use super::Mesh;
use crate::ids::{FaceId, VertexId};
pub use crate::mesh::weld::MAX_ELEMENTS;
pub use threemf::{
    INSTANCE_ALLOWANCE, MAX_COMPONENT_DEPTH, MAX_INSTANCE_FACTOR, MAX_PART_BYTES, MAX_RATIO,
    MAX_XML_DEPTH, RATIO_FREE_BYTES,
};

/// A mesh file format (with its encoding).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MeshFormat {
    /// Binary STL: `f32` triangle soup.
    StlBinary,
    /// ASCII STL: text triangle soup.
    StlAscii,
    /// Wavefront OBJ.
    Obj,
    /// Object File Format.
    Off,
    /// PLY, ASCII encoding.
    PlyAscii,
    /// PLY, binary little endian.
    PlyBinaryLittleEndian,
    /// PLY, binary big endian.
    PlyBinaryBigEndian,
    /// 3D Manufacturing Format (zip package of XML).
    ThreeMf,
}

impl MeshFormat {
    /// Every format, for tests and help texts.
    pub const ALL: [MeshFormat; 8] = [
        MeshFormat::StlBinary,
        MeshFormat::StlAscii,
        MeshFormat::Obj,
        MeshFormat::Off,
        MeshFormat::PlyAscii,
        MeshFormat::PlyBinaryLittleEndian,
        MeshFormat::PlyBinaryBigEndian,
        MeshFormat::ThreeMf,
    ];

    /// The format a file extension names (case-insensitive, without the
    /// dot): the default encoding of its family (`stl` is binary STL, `ply`
    /// binary little-endian PLY). Readers decide the encoding by content.
    pub fn from_extension(ext: &str) -> Option<MeshFormat> {
        let ext = ext.to_ascii_lowercase();
        Some(match ext.as_str() {
            "stl" => MeshFormat::StlBinary,
            "obj" => MeshFormat::Obj,
            "off" => MeshFormat::Off,
            "ply" => MeshFormat::PlyBinaryLittleEndian,
            "3mf" => MeshFormat::ThreeMf,
            _ => return None,
        })
    }

    /// The usual file extension (without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            MeshFormat::StlBinary | MeshFormat::StlAscii => "stl",
            MeshFormat::Obj => "obj",
            MeshFormat::Off => "off",
            MeshFormat::PlyAscii
            | MeshFormat::PlyBinaryLittleEndian
            | MeshFormat::PlyBinaryBigEndian => "ply",
            MeshFormat::ThreeMf => "3mf",
        }
    }

    /// Whether two formats are encodings of one family (both STL, both PLY,
    /// or equal).
    pub fn same_family(self, other: MeshFormat) -> bool {
        self.extension() == other.extension()
    }
}

impl fmt::Display for MeshFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MeshFormat::StlBinary => "binary STL",
            MeshFormat::StlAscii => "ASCII STL",
            MeshFormat::Obj => "OBJ",
            MeshFormat::Off => "OFF",
            MeshFormat::PlyAscii => "ASCII PLY",
            MeshFormat::PlyBinaryLittleEndian => "binary little-endian PLY",
            MeshFormat::PlyBinaryBigEndian => "binary big-endian PLY",
            MeshFormat::ThreeMf => "3MF",
        })
    }
}

/// What the loader did besides reading: one typed note per step.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LoadNote {
    /// Polygons with more than three vertices were split into fans, or,
    /// flat ones whose fan would fold, by ear clipping.
    Triangulated {
        /// Polygons split.
        polygons: usize,
        /// Triangles they became.
        triangles: usize,
        /// Of those polygons, the ones split by ear clipping.
        ear_clipped: usize,
    },
    /// PLY triangle strips were split into triangles.
    Strips {
        /// Strips read.
        strips: usize,
        /// Triangles they became.
        triangles: usize,
        /// Triangles with a repeated vertex id (the strips' joints), dropped.
        joints: usize,
    },
    /// A triangle soup (STL) was welded by exact coordinate equality.
    Welded {
        /// Corners read (three per triangle).
        corners: usize,
        /// Distinct vertices kept.
        vertices: usize,
    },
    /// A 3MF build item carried a non-identity transform (its own or its
    /// components'), applied exactly.
    TransformApplied {
        /// The build item (0-based).
        item: usize,
        /// The object it places.
        object: u64,
    },
    /// A binary STL whose 80-byte header starts with `solid` (read as
    /// binary because its size is exactly 84 + 50 n, or because its
    /// content is not text).
    BinaryStlHeaderSaysSolid,
    /// A binary STL whose header claims no triangle, followed by a whole
    /// number of triangle records (a writer that never filled the count
    /// in): the records are read.
    StlCountZero {
        /// Triangle records read.
        triangles: u64,
    },
    /// A binary STL followed by more whole triangle records than its
    /// header claims: the claimed ones are read, the rest ignored (the
    /// file does not say which is right).
    StlUnclaimedTriangles {
        /// Triangles the header claims.
        claimed: u32,
        /// Whole records after them.
        more: u64,
    },
    /// Bytes after the data the file declares, ignored.
    TrailingBytes {
        /// How many.
        bytes: u64,
    },
    /// Elements the mesh does not use (OBJ lines and points, PLY elements
    /// other than vertices and faces, ...), skipped.
    Ignored {
        /// What was skipped.
        kind: String,
        /// How many.
        count: usize,
    },
    /// A 3MF model in a unit other than millimetres: coordinates are kept
    /// as written, not scaled.
    Unit {
        /// The unit the file names.
        unit: String,
    },
    /// A binary OFF file, read in the one layout that reads it to its end.
    BinaryOffLayout(BinaryOffLayout),
}

impl fmt::Display for LoadNote {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadNote::Triangulated {
                polygons,
                triangles,
                ear_clipped: 0,
            } => write!(
                f,
                "triangulated {polygons} polygons into {triangles} triangles (fans)"
            ),
            LoadNote::Triangulated {
                polygons,
                triangles,
                ear_clipped,
            } => write!(
                f,
                "triangulated {polygons} polygons into {triangles} triangles (fans; \
                 {ear_clipped} flat ones that are not convex by ear clipping, as \
                 their fans would fold)"
            ),
            LoadNote::Strips {
                strips,
                triangles,
                joints,
            } => write!(
                f,
                "read {strips} triangle strips as {triangles} triangles \
                 ({joints} joining triangles with a repeated vertex dropped)"
            ),
            LoadNote::Welded { corners, vertices } => write!(
                f,
                "welded {corners} corners into {vertices} vertices (exact coordinate equality)"
            ),
            LoadNote::TransformApplied { item, object } => write!(
                f,
                "build item {item} (object {object}): transform applied exactly"
            ),
            LoadNote::BinaryStlHeaderSaysSolid => {
                f.write_str("binary STL whose header starts with `solid`")
            }
            LoadNote::StlCountZero { triangles } => write!(
                f,
                "the header claims 0 triangles, but {triangles} whole triangle records follow: read"
            ),
            LoadNote::StlUnclaimedTriangles { claimed, more } => write!(
                f,
                "the header claims {claimed} triangles, but {more} more whole triangle record(s) \
                 follow: ignored (if they belong to the mesh, the header's count is wrong)"
            ),
            LoadNote::TrailingBytes { bytes } => {
                write!(f, "{bytes} trailing bytes after the data ignored")
            }
            LoadNote::Ignored { kind, count } => write!(f, "ignored {count} {kind}"),
            LoadNote::Unit { unit } => write!(
                f,
                "the model unit is `{unit}`: coordinates kept as written, not converted to mm"
            ),
            LoadNote::BinaryOffLayout(layout) => write!(
                f,
                "binary OFF read as {layout} (the one layout that reads the file to its end)"
            ),
        }
    }
}

/// What was read and how.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LoadReport {
    /// The format and encoding actually read.
    pub format: MeshFormat,
    /// Steps the loader took, in order.
    pub notes: Vec<LoadNote>,
}

impl fmt::Display for LoadReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "read as {}", self.format)?;
        for n in &self.notes {
            write!(f, "; {n}")?;
        }
        Ok(())
    }
}

/// Options for the writers.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SaveOptions {
    /// Binary STL only: round coordinates to the nearest `f32` instead of
    /// refusing a mesh that `f32` cannot hold exactly.
    pub lossy_f32: bool,
}

/// Reads a mesh file. The extension picks the family (STL, OBJ, OFF, PLY,
/// 3MF); the content decides the encoding (binary or ASCII STL, PLY's
/// `format` line). Files without a known extension are recognized by
/// content. As [`load_bytes`], a 3MF vertex whose transformed position is
/// not a double is refused ([`load_exact`] keeps it, for snapping).
pub fn load(path: &Path) -> Result<(Mesh, LoadReport), LoadError> {
    doubles_only(load_exact(path)?)
}

/// As [`load`], with the vertices whose exact position is not a double
/// given exactly beside the mesh, as [`load_bytes_exact`] does.
pub fn load_exact(path: &Path) -> Result<(Mesh, LoadReport, ExactPositions), LoadError> {
    let ext = path.extension().and_then(|e| e.to_str());
    let hint = ext.and_then(MeshFormat::from_extension);
    let bytes = read_file(path).map_err(|source| LoadError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    // The content decides when the extension does not; a format it cannot
    // tell is named with the extension the file had.
    load_bytes_exact(&bytes, hint).map_err(|e| match e {
        LoadError::UnknownFormat { extension: None } => LoadError::UnknownFormat {
            extension: ext.map(str::to_owned),
        },
        e => e,
    })
}

/// A mesh read, refused when some vertex's exact position is not a double.
fn doubles_only(
    (mesh, report, exact): (Mesh, LoadReport, ExactPositions),
) -> Result<(Mesh, LoadReport), LoadError> {
    match exact.refusal() {
        Some(e) => Err(e),
        None => Ok((mesh, report)),
    }
}

/// The bytes of a file, as `std::fs::read` gives them. A large file is read
/// in pieces in parallel on the current rayon pool: reading a file the
/// system has cached is mostly copying, and two cores copy faster than
/// one. Its length is only a guess for where the pieces go: a file that
/// grows is read to its end, and one that shrinks is read again whole.
pub fn read_file(path: &Path) -> std::io::Result<Vec<u8>> {
    #[cfg(unix)]
    {
        use std::io::{Read, Seek, SeekFrom};
        use std::os::unix::fs::FileExt;
        const PIECE: usize = 4 << 20;
        let mut file = std::fs::File::open(path)?;
        let len = usize::try_from(file.metadata()?.len()).unwrap_or(0);
        if len >= 2 * PIECE && rayon::current_num_threads() > 1 {
            let mut bytes = vec![0u8; len];
            let read = bytes
                .par_chunks_mut(PIECE)
                .enumerate()
                .try_for_each(|(k, piece)| file.read_exact_at(piece, (k * PIECE) as u64));
            if read.is_ok() {
                file.seek(SeekFrom::Start(len as u64))?;
                file.read_to_end(&mut bytes)?;
                return Ok(bytes);
            }
        }
    }
    std::fs::read(path)
}

/// Reads a mesh from bytes. `hint` picks the family (the encoding within it,
/// binary or ASCII STL, PLY's encoding, is always decided by content); with
/// `None` the format is recognized by content ([`detect_format`]).
///
/// Every coordinate of the mesh is exactly the file's: a 3MF vertex whose
/// transformed position is not a double is refused
/// ([`LoadError::InexactTransform`]; [`load_bytes_exact`] keeps it, for
/// snapping).
pub fn load_bytes(bytes: &[u8], hint: Option<MeshFormat>) -> Result<(Mesh, LoadReport), LoadError> {
    doubles_only(load_bytes_exact(bytes, hint)?)
}

/// As [`load_bytes`], but the vertices whose exact position is not a double
/// (3MF transforms that round) are given exactly beside the mesh, which
/// holds their nearest doubles: snapping
/// ([`crate::mesh::prepare::prepare_exact`]) places them exactly.
pub fn load_bytes_exact(
    bytes: &[u8],
    hint: Option<MeshFormat>,
) -> Result<(Mesh, LoadReport, ExactPositions), LoadError> {
    let bytes = without_utf8_bom(bytes);
    if bytes.is_empty() {
        return Err(LoadError::Empty);
    }
    if let Some(e) = git_lfs_pointer(bytes) {
        return Err(e);
    }
    let format = match hint {
        Some(f) => f,
        None => detect_format(bytes).ok_or(LoadError::UnknownFormat { extension: None })?,
    };
    if let Some(e) = utf16_text(format, bytes) {
        return Err(e);
    }
    let doubles = match format {
        MeshFormat::StlBinary | MeshFormat::StlAscii => stl::read(bytes),
        MeshFormat::Obj => obj::read(bytes),
        MeshFormat::Off => off::read(bytes),
        MeshFormat::PlyAscii
        | MeshFormat::PlyBinaryLittleEndian
        | MeshFormat::PlyBinaryBigEndian => ply::read(bytes),
        MeshFormat::ThreeMf => return threemf::read(bytes),
    };
    doubles.map(|(mesh, report)| (mesh, report, ExactPositions::default()))
}

/// The bytes after a UTF-8 byte-order mark (as Windows tools save text
/// "UTF-8 with BOM"), which would otherwise glue itself to the first
/// keyword (an OBJ's first `v` went unread, shifting every index). A file
/// of a binary STL's exact size keeps its bytes: its 80-byte header may
/// start with any.
fn without_utf8_bom(bytes: &[u8]) -> &[u8] {
    match bytes.strip_prefix(b"\xEF\xBB\xBF") {
        Some(rest) if !stl::binary_size_matches(bytes) => rest,
        _ => bytes,
    }
}

/// A text format's file that starts with a UTF-16 byte-order mark (as
/// some Windows tools save text): named as such, where the readers of
/// bytes would report some later token as malformed. An STL only when its
/// size is not a binary STL's and its UTF-16 text starts with `solid`: a
/// binary STL's 80-byte header may start with any bytes.
fn utf16_text(format: MeshFormat, bytes: &[u8]) -> Option<LoadError> {
    let big = match bytes {
        [0xFE, 0xFF, ..] => true,
        [0xFF, 0xFE, ..] => false,
        _ => return None,
    };
    let text = match format {
        MeshFormat::ThreeMf => false,
        MeshFormat::StlBinary | MeshFormat::StlAscii if stl::binary_size_matches(bytes) => false,
        MeshFormat::StlBinary | MeshFormat::StlAscii => {
            let units = bytes[2..].chunks_exact(2).take(5).map(|u| {
                let u = [u[0], u[1]];
                if big {
                    u16::from_be_bytes(u)
                } else {
                    u16::from_le_bytes(u)
                }
            });
            units
                .map(|u| u8::try_from(u).unwrap_or(0).to_ascii_lowercase())
                .eq(*b"solid")
        }
        _ => true,
    };
    text.then(|| LoadError::Parse {
        format,
        line: Some(1),
        message: "the file is UTF-16 text (it starts with a UTF-16 byte-order mark): \
                  save it as UTF-8 or ASCII"
            .to_owned(),
    })
}

/// A Git LFS pointer file in place of the mesh (a repository cloned
/// without `git lfs`): named as such, where the readers would report its
/// first word as malformed or read it as an OBJ without faces. Only a
/// file that starts with the pointer's first line and is short (a pointer
/// is about 130 bytes), and never one of a binary STL's exact size.
fn git_lfs_pointer(bytes: &[u8]) -> Option<LoadError> {
    const FIRST_LINE: &[u8] = b"version https://git-lfs.github.com/spec/v1";
    let pointer =
        bytes.starts_with(FIRST_LINE) && bytes.len() <= 1024 && !stl::binary_size_matches(bytes);
    pointer.then(|| LoadError::GitLfsPointer {
        size: text::Lines::new(bytes)
            .find_map(|(_, line)| line.strip_prefix(b"size "))
            .and_then(|n| std::str::from_utf8(n).ok()?.trim().parse().ok()),
    })
}

/// Recognizes a format by content alone: the zip signature (3MF), `ply`,
/// an `OFF` header, binary STL by its exact size 84 + 50 n, `solid` (ASCII
/// STL), OBJ statements. `None` when nothing matches.
pub fn detect_format(bytes: &[u8]) -> Option<MeshFormat> {
    if bytes.starts_with(b"PK\x03\x04") {
        return Some(MeshFormat::ThreeMf);
    }
    if bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r") {
        return Some(ply::encoding_hint(bytes));
    }
    if stl::binary_size_matches(bytes) || stl::binary_count_unfilled(bytes) {
        return Some(MeshFormat::StlBinary);
    }
    let mut first_tokens = text::Lines::new(bytes)
        .filter_map(|(_, line)| text::tokens(line).next())
        .filter(|t| !t.starts_with(b"#"))
        .take(64);
    let first = first_tokens.next()?;
    if off::split_off_keyword(first).is_some() {
        return Some(MeshFormat::Off);
    }
    if first.eq_ignore_ascii_case(b"solid") {
        return Some(MeshFormat::StlAscii);
    }
    let obj_keyword = |t: &[u8]| {
        matches!(
            t,
            b"v" | b"vt" | b"vn" | b"f" | b"o" | b"g" | b"mtllib" | b"usemtl" | b"s"
        )
    };
    if obj_keyword(first) || first_tokens.any(obj_keyword) {
        return Some(MeshFormat::Obj);
    }
    None
}

/// Writes `mesh` in `format` to `out` (not atomic; see [`save_mesh`]).
pub fn write_mesh<W: Write>(
    mesh: &Mesh,
    format: MeshFormat,
    options: SaveOptions,
    out: &mut W,
) -> Result<(), SaveError> {
    check_indices(mesh)?;
    match format {
        MeshFormat::StlBinary => stl::write_binary(mesh, options.lossy_f32, out),
        MeshFormat::StlAscii => stl::write_ascii(mesh, out),
        MeshFormat::Obj => obj::write(mesh, out),
        MeshFormat::Off => off::write(mesh, out),
        MeshFormat::PlyAscii
        | MeshFormat::PlyBinaryLittleEndian
        | MeshFormat::PlyBinaryBigEndian => ply::write(mesh, format, out),
        MeshFormat::ThreeMf => threemf::write(mesh, out),
    }
}

/// Writes `mesh` to `path` atomically: into a temporary file in the same
/// directory, synced, then renamed over `path`. On error no file is left.
pub fn save_mesh(
    mesh: &Mesh,
    path: &Path,
    format: MeshFormat,
    options: SaveOptions,
) -> Result<(), SaveError> {
    let io_err = |source: io::Error| SaveError::Io {
        path: path.to_path_buf(),
        source,
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut tmp = tempfile::NamedTempFile::new_in(dir).map_err(io_err)?;
    {
        let mut w = BufWriter::new(tmp.as_file_mut());
        write_mesh(mesh, format, options, &mut w).map_err(|e| match e {
            SaveError::Write { source } => io_err(source),
            other => other,
        })?;
        w.flush().map_err(io_err)?;
    }
    tmp.as_file().sync_all().map_err(io_err)?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(path)
            .map(|m| m.permissions().mode())
            .unwrap_or(0o644);
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(mode))
            .map_err(io_err)?;
    }
    tmp.persist(path).map_err(|e| io_err(e.error))?;
    Ok(())
}

impl Mesh {
    /// Reads a mesh file (see [`load`]); the report is dropped.
    pub fn load(path: &Path) -> Result<Mesh, LoadError> {
        load(path).map(|(mesh, _)| mesh)
    }

    /// Writes the mesh atomically, the format chosen by the extension:
    /// `.stl` binary STL, `.obj`, `.off`, `.ply` binary little-endian PLY,
    /// `.3mf`.
    pub fn save(&self, path: &Path) -> Result<(), SaveError> {
        let format = path
            .extension()
            .and_then(|e| e.to_str())
            .and_then(MeshFormat::from_extension)
            .ok_or_else(|| SaveError::UnknownFormat {
                path: path.to_path_buf(),
            })?;
        self.save_as(path, format)
    }

    /// Writes the mesh atomically in the given format (e.g. ASCII STL or
    /// ASCII PLY, whatever the extension).
    pub fn save_as(&self, path: &Path, format: MeshFormat) -> Result<(), SaveError> {
        save_mesh(self, path, format, SaveOptions::default())
    }

    /// Writes the mesh atomically with explicit options.
    pub fn save_with(
        &self,
        path: &Path,
        format: MeshFormat,
        options: SaveOptions,
    ) -> Result<(), SaveError> {
        save_mesh(self, path, format, options)
    }
}

/// Every writer dereferences faces: refuse out-of-range ids up front.
fn check_indices(mesh: &Mesh) -> Result<(), SaveError> {
    let n = mesh.positions.len();
    for (f, tri) in mesh.faces.iter().enumerate() {
        for &v in tri {
            if v.idx() >= n {
                return Err(SaveError::IndexOutOfRange {
                    face: FaceId::from_idx(f),
                    vertex: v,
                    vertices: n,
                });
            }
        }
    }
    Ok(())
}

/// Maps a writer's I/O error.
fn write_err(source: io::Error) -> SaveError {
    SaveError::Write { source }
}

/// The three corner positions of a face (indices checked beforehand).
fn corners(mesh: &Mesh, tri: &[VertexId; 3]) -> [[f64; 3]; 3] {
    let p = |v: VertexId| {
        mesh.positions
            .get(v.idx())
            .copied()
            .unwrap_or([f64::NAN; 3])
    };
    [p(tri[0]), p(tri[1]), p(tri[2])]
}

#[cfg(test)]
mod tests {
    use super::read_file;

    /// Small and large files (pieces in parallel, the last one short) read
    /// back exactly.
    #[test]
    fn files_read_whole() {
        let dir = tempfile::tempdir().unwrap();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        for len in [0, 10, (8 << 20) + 12_345, 20 << 20] {
            let bytes: Vec<u8> = (0..len).map(|k| (k % 253 + k / 65_536) as u8).collect();
            let path = dir.path().join(format!("f{len}"));
            std::fs::write(&path, &bytes).unwrap();
            assert!(pool.install(|| read_file(&path)).unwrap() == bytes, "{len}");
        }
        assert!(read_file(&dir.path().join("missing")).is_err());
    }
}
