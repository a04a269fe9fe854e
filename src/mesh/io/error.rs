//! Input: what went wrong while reading or writing a mesh file. Output: the
//! typed [`LoadError`] and [`SaveError`] enums, each variant naming the
//! format, the element and the numbers involved (no catch-all string).

use std::fmt;
use std::io;
use std::path::PathBuf;

use super::MeshFormat;
use crate::ids::{FaceId, VertexId};

/// Why a face index in the file cannot be a vertex id at all (indices that
/// are merely `>=` the vertex count still load; validation reports them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InvalidIndexReason {
    /// OBJ indices start at 1; `0` means nothing.
    Zero,
    /// A negative (relative) OBJ index points before the first vertex.
    BeforeFirstVertex,
    /// A negative index where the format has no relative indices.
    Negative,
    /// The index does not fit in a `u32` vertex id.
    TooLarge,
    /// The index is not an integer.
    NotAnInteger,
}

impl fmt::Display for InvalidIndexReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            InvalidIndexReason::Zero => "OBJ indices start at 1",
            InvalidIndexReason::BeforeFirstVertex => {
                "the relative index points before the first vertex"
            }
            InvalidIndexReason::Negative => "negative index",
            InvalidIndexReason::TooLarge => "the index does not fit in 32 bits",
            InvalidIndexReason::NotAnInteger => "not an integer",
        })
    }
}

/// Formats an optional line number as ` (line N)` or nothing.
struct AtLine(Option<usize>);

impl fmt::Display for AtLine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            Some(l) => write!(f, " (line {l})"),
            None => Ok(()),
        }
    }
}

/// Reading a mesh failed. Every variant names what was wrong and where.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: io::Error,
    },
    /// The file is a Git LFS pointer (a repository cloned without `git
    /// lfs`), not a mesh in any format.
    #[error("the file is a Git LFS pointer{}, not the mesh: fetch the content (`git lfs pull` in its repository)", match size { Some(n) => format!(" to a file of {n} bytes"), None => String::new() })]
    GitLfsPointer {
        /// The size of the file it stands for, as the pointer says.
        size: Option<u64>,
    },
    /// The input holds no byte.
    #[error("the mesh file is empty (0 bytes)")]
    Empty,
    /// Neither the extension nor the content names a supported format.
    #[error("unknown mesh format{}: the content is not STL, OBJ, OFF, PLY or 3MF", match extension { Some(e) => format!(" (extension `.{e}`)"), None => String::new() })]
    UnknownFormat {
        /// The file's extension, if it had one.
        extension: Option<String>,
    },
    /// The data ends before what the file itself declares.
    #[error("{format}: truncated: expected {expected} {what}, got {got}")]
    Truncated {
        /// The format being read.
        format: MeshFormat,
        /// What was counted ("bytes", "vertices", "faces").
        what: &'static str,
        /// How many the file declares.
        expected: u64,
        /// How many are there.
        got: u64,
    },
    /// A count in a header cannot possibly fit in the bytes that follow;
    /// refused before allocating anything for it.
    #[error("{format}: the header claims {claimed} {element} elements, but only {available_bytes} bytes follow")]
    ClaimedCountTooLarge {
        /// The format being read.
        format: MeshFormat,
        /// The element whose count is too large ("triangle", "vertex", ...).
        element: String,
        /// The claimed count.
        claimed: u64,
        /// Bytes left in the input after the header.
        available_bytes: u64,
    },
    /// The text or binary layout does not follow the format.
    #[error("{format}: parse error{}: {message}", AtLine(*line))]
    Parse {
        /// The format being read.
        format: MeshFormat,
        /// 1-based line, for text formats.
        line: Option<usize>,
        /// What was expected and what was found.
        message: String,
    },
    /// A face index cannot be a vertex id at all.
    #[error("{format}: invalid vertex index `{text}`{}: {reason}", AtLine(*line))]
    InvalidIndex {
        /// The format being read.
        format: MeshFormat,
        /// 1-based line, for text formats.
        line: Option<usize>,
        /// The index as written in the file.
        text: String,
        /// Why it is invalid.
        reason: InvalidIndexReason,
    },
    /// A face index is out of range in a format (3MF) whose objects are
    /// concatenated, so that the raw index cannot be kept for validation.
    #[error("{format}: object {object}, triangle {triangle}: vertex index {index} out of range ({vertices} vertices)")]
    IndexOutOfRange {
        /// The format being read.
        format: MeshFormat,
        /// The object id in the file.
        object: u64,
        /// The triangle's position in its object.
        triangle: usize,
        /// The index found.
        index: u64,
        /// The object's vertex count.
        vertices: usize,
    },
    /// A face with fewer than three vertices: it cannot be triangulated.
    #[error("{format}: face {face} has {arity} vertices; a face needs at least 3")]
    NonTriangleFace {
        /// The format being read.
        format: MeshFormat,
        /// The face's position among the file's faces (0-based).
        face: usize,
        /// Its number of vertices.
        arity: usize,
    },
    /// More vertices or faces than a `u32` id (or a loader limit) allows.
    #[error("{format}: more than {limit} {what}")]
    TooManyElements {
        /// The format being read.
        format: MeshFormat,
        /// What overflowed ("vertices", "faces", "instanced vertices", ...).
        what: &'static str,
        /// The limit.
        limit: u64,
    },
    /// A valid file using a feature this reader does not implement.
    #[error("{format}: unsupported: {feature}")]
    Unsupported {
        /// The format being read.
        format: MeshFormat,
        /// The feature (e.g. "binary OFF", "3MF production extension path").
        feature: String,
    },
    /// The 3MF zip container is broken.
    #[error("3MF: broken zip archive: {source}")]
    ZipArchive {
        /// The zip reader's error.
        #[source]
        source: zip::result::ZipError,
    },
    /// A required part of a 3MF package is missing.
    #[error("3MF: the package has no part `{name}`")]
    ZipEntryMissing {
        /// The part name.
        name: String,
    },
    /// A 3MF part declares a larger size than the reader accepts.
    #[error("3MF: part `{name}` declares {declared} bytes; the limit is {limit}")]
    EntryTooLarge {
        /// The part name.
        name: String,
        /// Its declared uncompressed size.
        declared: u64,
        /// The limit.
        limit: u64,
    },
    /// A 3MF part inflates far beyond its compressed size, or beyond what
    /// it declares: a decompression bomb.
    #[error("3MF: part `{name}` looks like a zip bomb: {compressed} compressed bytes inflate to {inflated} bytes or more (ratio limit {ratio_limit})")]
    ZipBomb {
        /// The part name.
        name: String,
        /// Its compressed size.
        compressed: u64,
        /// The declared or actually inflated size.
        inflated: u64,
        /// The accepted ratio of inflated to compressed bytes.
        ratio_limit: u64,
    },
    /// The 3MF XML is malformed.
    #[error("3MF: malformed XML in `{part}` at byte {position}: {source}")]
    Xml {
        /// The part name.
        part: String,
        /// Byte offset in the part.
        position: u64,
        /// The XML reader's error.
        #[source]
        source: quick_xml::Error,
    },
    /// The 3MF XML nests deeper than the reader accepts.
    #[error("3MF: XML in `{part}` nests deeper than {limit} elements")]
    XmlTooDeep {
        /// The part name.
        part: String,
        /// The depth limit.
        limit: usize,
    },
    /// A required XML attribute is missing or not a number.
    #[error("3MF: <{element}> attribute `{attribute}` {problem}")]
    BadAttribute {
        /// The element name.
        element: &'static str,
        /// The attribute name.
        attribute: &'static str,
        /// "is missing", "is not a number: `...`", ...
        problem: String,
    },
    /// A build item or component names an object that does not exist.
    #[error("3MF: no object with id {id}")]
    UnknownObject {
        /// The object id referred to.
        id: u64,
    },
    /// A build item places an object of type `other`, which the 3MF core
    /// specification says is not to be printed.
    #[error("3MF: build item {item} places object {object}, of type `other` (not to be printed)")]
    PlacesOther {
        /// The build item (0-based).
        item: usize,
        /// The object.
        object: u64,
    },
    /// Two objects share an id.
    #[error("3MF: two objects have id {id}")]
    DuplicateObject {
        /// The object id.
        id: u64,
    },
    /// Components refer back to an object being expanded.
    #[error("3MF: object {object} contains itself through its components")]
    ComponentCycle {
        /// The object id.
        object: u64,
    },
    /// Components nest deeper than the reader accepts.
    #[error("3MF: components of object {object} nest deeper than {limit}")]
    ComponentsTooDeep {
        /// The object id where the limit was hit.
        object: u64,
        /// The depth limit.
        limit: usize,
    },
    /// A transform attribute is not 12 finite numbers.
    #[error("3MF: <{element}> has an invalid transform `{text}`")]
    InvalidTransform {
        /// "item" or "component".
        element: &'static str,
        /// The attribute text.
        text: String,
    },
    /// Applying a transform would round a coordinate: the exact image of a
    /// vertex is not a binary64 number. Without a grid such a vertex has no
    /// exact place; snapping places it from its exact image.
    #[error("3MF: build item {item}, object {object}, vertex {vertex}: the transformed coordinate is not exactly representable as f64 (snap to a grid to place it from its exact value)")]
    InexactTransform {
        /// The build item (0-based).
        item: usize,
        /// The mesh object whose vertex it is.
        object: u64,
        /// The vertex's position in that object.
        vertex: usize,
    },
}

/// Writing a mesh failed.
#[derive(Debug, thiserror::Error)]
pub enum SaveError {
    /// Writing or renaming the file failed (the target is left untouched).
    #[error("cannot write {}: {source}", path.display())]
    Io {
        /// The target file.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: io::Error,
    },
    /// Writing to the output stream failed.
    #[error("cannot write the mesh: {source}")]
    Write {
        /// The I/O error.
        #[source]
        source: io::Error,
    },
    /// Building the 3MF zip package failed.
    #[error("cannot build the 3MF package: {source}")]
    Zip {
        /// The zip writer's error.
        #[source]
        source: zip::result::ZipError,
    },
    /// The extension does not name a format the writer knows.
    #[error("cannot tell the output format of {} from its extension", path.display())]
    UnknownFormat {
        /// The target file.
        path: PathBuf,
    },
    /// Binary STL stores `f32`; this coordinate would be rounded. Ask for
    /// `SaveOptions { lossy_f32: true, .. }` to round on purpose.
    #[error("binary STL stores f32: vertex {vertex} coordinate {value:?} is not exactly representable (ask for lossy output to round)")]
    NotF32Exact {
        /// The vertex.
        vertex: VertexId,
        /// The coordinate that would round.
        value: f64,
    },
    /// The format cannot hold a non-finite coordinate.
    #[error("{format} cannot store the non-finite coordinate of vertex {vertex}")]
    NonFinite {
        /// The target format.
        format: MeshFormat,
        /// The vertex.
        vertex: VertexId,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but the mesh has {vertices} vertices")]
    IndexOutOfRange {
        /// The face.
        face: FaceId,
        /// The missing vertex.
        vertex: VertexId,
        /// The vertex count.
        vertices: usize,
    },
    /// More faces than the format's count field holds.
    #[error("{format} holds at most {limit} faces")]
    TooManyFaces {
        /// The target format.
        format: MeshFormat,
        /// The limit.
        limit: u64,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    fn is_send_sync<T: Send + Sync + 'static>() {}

    #[test]
    fn errors_cross_threads_and_box_into_anyhow() {
        is_send_sync::<LoadError>();
        is_send_sync::<SaveError>();
        let e = LoadError::NonTriangleFace {
            format: MeshFormat::Obj,
            face: 3,
            arity: 2,
        };
        assert_eq!(
            e.to_string(),
            "OBJ: face 3 has 2 vertices; a face needs at least 3"
        );
        let e = LoadError::Parse {
            format: MeshFormat::StlAscii,
            line: Some(7),
            message: "expected `loop`".into(),
        };
        assert_eq!(
            e.to_string(),
            "ASCII STL: parse error (line 7): expected `loop`"
        );
    }
}
