//! Input: exact level sets (to write) or the bytes of a Common Layer
//! Interface file (to read). Output: CLI files, ASCII or binary, and a
//! typed reader for both. ("CLI" here is the layer file format of additive
//! manufacturing machines, not the command line.)
//!
//! # What is written
//!
//! - Header (ASCII in both variants), one command per line:
//!   `$$HEADERSTART`, `$$ASCII` or `$$BINARY`, `$$UNITS/1`, `$$VERSION/200`,
//!   `$$LABEL/1,name`, `$$DATE/ddmmyy`, `$$DIMENSION/x1,y1,z1,x2,y2,z2`
//!   (the mesh's bounding box), `$$LAYERS/n`, `$$HEADEREND`.
//! - Units: coordinates are written in the mesh's units (times the snap
//!   grid when snapped) and `$$UNITS/1` declares one file unit = 1 mm, so a
//!   mesh is taken to be in millimetres.
//! - ASCII geometry: `$$GEOMETRYSTART`, per layer `$$LAYER/z` in strictly
//!   ascending order of the exact levels (equal levels are written once),
//!   `$$POLYLINE/id,dir,n,p1x,p1y,...`, `$$GEOMETRYEND`. Numbers are the
//!   shortest decimals that read back as the nearest `f64` of the exact
//!   values.
//! - Binary geometry right after `$$HEADEREND` (no newline): 16-bit
//!   little-endian command codes; 127 = start layer long (`f32` z), 130 =
//!   polyline long (`i32` id, `i32` dir, `i32` n, then `2n` `f32`).
//!   Values are the nearest `f64`, then rounded to `f32`.
//! - Polylines: id 1 (the `$$LABEL`); dir 1 = counter-clockwise (outer
//!   loop), 0 = clockwise (hole), 2 = open line. A closed loop repeats its
//!   first point at the end (n counts it), the usual CLI convention for a
//!   closed contour; a closed S_NO ridge is written as an open line (dir 2)
//!   that also returns to its first point.
//! - Which loops: [`LoopChoice`] — L- (default: the material just below the
//!   plane, what a layer whose top is the plane prints), L+, or S_O; S_NO
//!   ridges and valleys are added as dir 2 on request.
//!
//! # What is read
//!
//! Both variants, as the standard allows: `//` comments (to the next `//`
//! or the end of the line), commands split across lines or several on one
//! line, CR LF line ends, unknown header commands (kept as text), layer
//! long and short (127, 128), polyline long and short (130, 129), hatches
//! long and short (132, 131, and `$$HATCHES` in ASCII). Short-form integer
//! values are returned as numbers in file units like the long forms. Every
//! defect is a [`CliError`] naming the line or byte offset; nothing panics
//! and no allocation exceeds the input's size (declared counts are checked
//! against the bytes that remain before anything is reserved).
//!
//! Writing is in `write.rs`, reading in `read.rs`.

mod read;
mod write;

pub use read::{read, CliError, Problem};
pub use write::{
    check_binary, date_ddmmyy, from_level_sets, write, write_ascii, write_binary, CliWriteError,
};

/// ASCII or binary geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// `$$ASCII`.
    Ascii,
    /// `$$BINARY`.
    Binary,
}

/// A polyline's direction code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// 0: clockwise, an internal boundary (hole).
    Clockwise = 0,
    /// 1: counter-clockwise, an external boundary (outer).
    CounterClockwise = 1,
    /// 2: an open line.
    Open = 2,
}

impl Direction {
    /// The code in the file.
    pub fn code(self) -> i32 {
        self as i32
    }

    /// The direction of a code, if valid.
    pub fn from_code(c: i64) -> Option<Self> {
        match c {
            0 => Some(Direction::Clockwise),
            1 => Some(Direction::CounterClockwise),
            2 => Some(Direction::Open),
            _ => None,
        }
    }
}

/// One polyline.
#[derive(Clone, Debug, PartialEq)]
pub struct Polyline {
    /// The part id (a `$$LABEL` id).
    pub id: i32,
    /// Direction.
    pub dir: Direction,
    /// Points in file units, as in the file (a closed loop repeats its
    /// first point at the end).
    pub points: Vec<[f64; 2]>,
}

/// One hatch block (read only; the writer emits none).
#[derive(Clone, Debug, PartialEq)]
pub struct Hatches {
    /// The part id.
    pub id: i32,
    /// Line segments `[start, end]`.
    pub lines: Vec<[[f64; 2]; 2]>,
}

/// One layer.
#[derive(Clone, Debug, PartialEq)]
pub struct Layer {
    /// Height in file units.
    pub z: f64,
    /// Its polylines.
    pub polylines: Vec<Polyline>,
    /// Its hatches.
    pub hatches: Vec<Hatches>,
}

/// The header.
#[derive(Clone, Debug, PartialEq)]
pub struct Header {
    /// ASCII or binary geometry.
    pub encoding: Encoding,
    /// Millimetres per file unit.
    pub units: f64,
    /// `$$VERSION` (200 = 2.0).
    pub version: u32,
    /// `$$LABEL/id,text` entries.
    pub labels: Vec<(i32, String)>,
    /// `$$DATE`, as written (ddmmyy).
    pub date: Option<String>,
    /// `$$DIMENSION/x1,y1,z1,x2,y2,z2`.
    pub dimension: Option<[f64; 6]>,
    /// `$$LAYERS/n`.
    pub layers: Option<u64>,
    /// Other header commands, verbatim (without `$$`), written back as
    /// they are.
    pub other: Vec<String>,
}

/// A whole CLI file.
#[derive(Clone, Debug, PartialEq)]
pub struct CliFile {
    /// The header.
    pub header: Header,
    /// The layers, ascending.
    pub layers: Vec<Layer>,
}

/// Which loops of a level set become the polylines of its layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LoopChoice {
    /// L-: the material just below the plane (the default: what a layer
    /// whose top is the plane prints).
    #[default]
    Below,
    /// L+: the material just above the plane.
    Above,
    /// S_O: the weak-Morse contour itself.
    Contour,
}

/// How to build a CLI file from level sets.
#[derive(Clone, Debug, PartialEq)]
pub struct CliOptions {
    /// ASCII or binary.
    pub encoding: Encoding,
    /// Which loops.
    pub side: LoopChoice,
    /// Add S_NO ridges and valleys as open polylines.
    pub with_ridges: bool,
    /// The part name for `$$LABEL/1,name`.
    pub label: String,
    /// `$$DATE` (ddmmyy; see [`date_ddmmyy`]).
    pub date: String,
}
/// Binary command codes.
mod code {
    pub const LAYER_LONG: u16 = 127;
    pub const LAYER_SHORT: u16 = 128;
    pub const POLYLINE_SHORT: u16 = 129;
    pub const POLYLINE_LONG: u16 = 130;
    pub const HATCHES_SHORT: u16 = 131;
    pub const HATCHES_LONG: u16 = 132;
}
