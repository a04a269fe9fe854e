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

use super::svg::Bounds;
use crate::exact::rational::{rat_to_f64, Rat};
use crate::levelset::{LevelSet, Loop};
use crate::nest::Role;
use std::fmt::Write;

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

fn loop_polyline(l: &Loop) -> Polyline {
    let mut points: Vec<[f64; 2]> = l.points.iter().map(|p| p.to_f64()).collect();
    if let Some(&first) = points.first() {
        points.push(first);
    }
    Polyline {
        id: 1,
        dir: match l.role {
            Role::Outer => Direction::CounterClockwise,
            Role::Hole => Direction::Clockwise,
        },
        points,
    }
}

/// The CLI file of `sets`: layers sorted ascending by exact level (equal
/// levels once), the loops `opts.side` picks, ridges on request.
pub fn from_level_sets<'a>(
    sets: impl IntoIterator<Item = &'a LevelSet>,
    bounds: &Bounds,
    opts: &CliOptions,
) -> CliFile {
    let mut order: Vec<&LevelSet> = sets.into_iter().collect();
    order.sort_by(|a, b| a.level.cmp(&b.level));
    order.dedup_by(|a, b| a.level == b.level);
    let layers: Vec<Layer> = order
        .into_iter()
        .map(|ls| {
            let loops = match opts.side {
                LoopChoice::Below => &ls.below,
                LoopChoice::Above => &ls.above,
                LoopChoice::Contour => &ls.contours,
            };
            // A collapsed limit bounds no material: nothing to print.
            let mut polylines: Vec<Polyline> = loops
                .iter()
                .filter(|l| !l.collapsed)
                .map(loop_polyline)
                .collect();
            if opts.with_ridges {
                for r in &ls.ridges {
                    let mut points: Vec<[f64; 2]> = r.points.iter().map(|p| p.to_f64()).collect();
                    if r.closed {
                        if let Some(&first) = points.first() {
                            points.push(first);
                        }
                    }
                    polylines.push(Polyline {
                        id: 1,
                        dir: Direction::Open,
                        points,
                    });
                }
            }
            Layer {
                z: level_f64(&ls.level),
                polylines,
                hatches: Vec::new(),
            }
        })
        .collect();
    CliFile {
        header: Header {
            encoding: opts.encoding,
            units: 1.0,
            version: 200,
            labels: vec![(1, sanitize_label(&opts.label))],
            date: Some(opts.date.clone()),
            dimension: Some([
                bounds.min[0],
                bounds.min[1],
                bounds.min[2],
                bounds.max[0],
                bounds.max[1],
                bounds.max[2],
            ]),
            layers: Some(layers.len() as u64),
            other: Vec::new(),
        },
        layers,
    }
}

fn level_f64(c: &Rat) -> f64 {
    rat_to_f64(c)
}

/// A label without line breaks, `$$` or `//` (which would end it early).
fn sanitize_label(s: &str) -> String {
    let t: String = s
        .chars()
        .map(|c| if c.is_control() { '_' } else { c })
        .collect();
    let t = t.replace("$$", "_").replace("//", "_");
    if t.trim().is_empty() {
        "part".into()
    } else {
        t
    }
}

/// `ddmmyy` of the UTC day containing `unix_seconds`.
pub fn date_ddmmyy(unix_seconds: i64) -> String {
    // Howard Hinnant's civil_from_days.
    let z = unix_seconds.div_euclid(86_400) + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!("{d:02}{m:02}{:02}", y.rem_euclid(100))
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{}", x + 0.0)
    } else {
        "0".into()
    }
}

fn header_text(file: &CliFile) -> String {
    let h = &file.header;
    let mut s = String::from("$$HEADERSTART\n");
    s.push_str(match h.encoding {
        Encoding::Ascii => "$$ASCII\n",
        Encoding::Binary => "$$BINARY\n",
    });
    let _ = writeln!(s, "$$UNITS/{}", num(h.units));
    let _ = writeln!(s, "$$VERSION/{}", h.version);
    for (id, text) in &h.labels {
        let _ = writeln!(s, "$$LABEL/{id},{}", sanitize_label(text));
    }
    if let Some(d) = &h.date {
        let _ = writeln!(s, "$$DATE/{}", sanitize_label(d));
    }
    if let Some(d) = &h.dimension {
        let v: Vec<String> = d.iter().map(|x| num(*x)).collect();
        let _ = writeln!(s, "$$DIMENSION/{}", v.join(","));
    }
    let _ = writeln!(s, "$$LAYERS/{}", file.layers.len());
    for o in &h.other {
        let _ = writeln!(s, "$${}", sanitize_label(o));
    }
    s.push_str("$$HEADEREND");
    s
}

/// The file in its header's encoding.
pub fn write(file: &CliFile) -> Vec<u8> {
    match file.header.encoding {
        Encoding::Ascii => write_ascii(file).into_bytes(),
        Encoding::Binary => write_binary(file),
    }
}

/// The ASCII variant (whatever the header's encoding says, `$$ASCII` is
/// written).
pub fn write_ascii(file: &CliFile) -> String {
    let mut f = file.clone();
    f.header.encoding = Encoding::Ascii;
    let mut s = header_text(&f);
    s.push_str("\n$$GEOMETRYSTART\n");
    for layer in &file.layers {
        let _ = writeln!(s, "$$LAYER/{}", num(layer.z));
        for p in &layer.polylines {
            let _ = write!(s, "$$POLYLINE/{},{},{}", p.id, p.dir.code(), p.points.len());
            for [x, y] in &p.points {
                let _ = write!(s, ",{},{}", num(*x), num(*y));
            }
            s.push('\n');
        }
        for h in &layer.hatches {
            let _ = write!(s, "$$HATCHES/{},{}", h.id, h.lines.len());
            for [[a, b], [c, d]] in &h.lines {
                let _ = write!(s, ",{},{},{},{}", num(*a), num(*b), num(*c), num(*d));
            }
            s.push('\n');
        }
    }
    s.push_str("$$GEOMETRYEND\n");
    s
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

/// Why a file cannot be written as binary CLI, whose values are `f32`.
#[derive(Debug, thiserror::Error, Clone, Copy, PartialEq)]
pub enum CliWriteError {
    /// A height or coordinate beyond `f32` (it would be written as an
    /// infinity).
    #[error(
        "binary CLI holds f32 values, and {value:e} lies beyond them (3.4e38): \
         write ASCII CLI (--format cli) or JSON"
    )]
    BeyondF32 {
        /// The value.
        value: f64,
    },
    /// A part smaller than `f32` resolves: its largest coordinate below
    /// `2^-100`, where `f32` keeps fewer than 24 bits (or none).
    #[error(
        "binary CLI holds f32 values, and this part spans only {extent:e} \
         (f32 loses its precision below 7.9e-31): write ASCII CLI (--format cli) or JSON"
    )]
    BelowF32 {
        /// The largest coordinate magnitude of the part.
        extent: f64,
    },
    /// A part so far from the origin for its size that `f32` keeps fewer
    /// than 8 bits of it: its points would move by 1/256 of its width or
    /// more (a part `40` wide at `1e15` would be one point). A block `1`
    /// wide at `14678` (`f32` steps of `2^-10` there) is written.
    #[error(
        "binary CLI holds f32 values, which lie {step:e} apart at {at:e}, where this part \
         lies, and it is only {width:e} wide: f32 keeps fewer than 8 bits of it; write \
         ASCII CLI (--format cli) or JSON, or move the part nearer the origin"
    )]
    CoarseF32 {
        /// The largest `|x|` or `|y|` of the part.
        at: f64,
        /// The distance between consecutive `f32`s there.
        step: f64,
        /// The part's width (the larger of its `x` and `y` extents).
        width: f64,
    },
    /// Two layers whose heights round to one `f32`.
    #[error(
        "binary CLI holds f32 values, and the layers at z = {lower:e} and z = {upper:e} \
         would both be written at {written:e}: write ASCII CLI (--format cli) or JSON, \
         or slice thicker layers"
    )]
    LayersMerge {
        /// The lower layer's height.
        lower: f64,
        /// The upper layer's height.
        upper: f64,
        /// The `f32` both round to.
        written: f32,
    },
}

/// Whether `file` can be written as binary CLI without an infinity, a
/// part lost among the subnormal `f32`s or too far out for `f32` to keep
/// its shape, or two layers at one `f32` height. (A single value far below the
/// part's size may still round to zero: an error below `2^-149` file
/// units, as every rounding to `f32` makes one.)
pub fn check_binary(file: &CliFile) -> Result<(), CliWriteError> {
    let values = file.layers.iter().flat_map(|l| {
        std::iter::once(l.z).chain(
            l.polylines
                .iter()
                .flat_map(|p| p.points.iter().flatten().copied()),
        )
    });
    let dimension = file.header.dimension.into_iter().flatten();
    let mut extent = 0.0f64;
    for v in values.chain(dimension) {
        if (v as f32).is_infinite() {
            return Err(CliWriteError::BeyondF32 { value: v });
        }
        extent = extent.max(v.abs());
    }
    // 2^-100: a part this small keeps 24 bits in f32 only above 2^-126.
    if extent > 0.0 && extent < f64::from_bits((1023 - 100) << 52) {
        return Err(CliWriteError::BelowF32 { extent });
    }
    for w in file.layers.windows(2) {
        let (lower, upper) = (w[0].z, w[1].z);
        if lower as f32 == upper as f32 {
            return Err(CliWriteError::LayersMerge {
                lower,
                upper,
                written: lower as f32,
            });
        }
    }
    coarse_check(file)
}

/// [`CliWriteError::CoarseF32`] when `f32`'s step at the part's largest
/// `|x|` or `|y|` exceeds 1/256 of its width.
fn coarse_check(file: &CliFile) -> Result<(), CliWriteError> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in file.layers.iter().flat_map(|l| &l.polylines) {
        for q in &p.points {
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
    }
    // Every value fits f32 here ([`check_binary`] refused the others), so
    // no difference overflows.
    let width = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if width <= 0.0 {
        return Ok(()); // no points, or all at one point: nothing to resolve
    }
    let at = [lo[0], hi[0], lo[1], hi[1]]
        .into_iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let a = at as f32;
    // The distance from the f32 nearest `at` to the next one up (from
    // the largest f32, the one below), exact in f64.
    let next = f32::from_bits(a.to_bits() + 1);
    let step = if next.is_finite() {
        f64::from(next) - f64::from(a)
    } else {
        f64::from(a) - f64::from(f32::from_bits(a.to_bits() - 1))
    };
    if width < 256.0 * step {
        return Err(CliWriteError::CoarseF32 { at, step, width });
    }
    Ok(())
}

/// The binary variant (`$$BINARY` is written whatever the header says).
pub fn write_binary(file: &CliFile) -> Vec<u8> {
    let mut f = file.clone();
    f.header.encoding = Encoding::Binary;
    let mut out = header_text(&f).into_bytes();
    let f32le = |out: &mut Vec<u8>, x: f64| out.extend_from_slice(&(x as f32).to_le_bytes());
    let i32le = |out: &mut Vec<u8>, x: i32| out.extend_from_slice(&x.to_le_bytes());
    let count = |n: usize| i32::try_from(n).unwrap_or(i32::MAX);
    for layer in &file.layers {
        out.extend_from_slice(&code::LAYER_LONG.to_le_bytes());
        f32le(&mut out, layer.z);
        for p in &layer.polylines {
            out.extend_from_slice(&code::POLYLINE_LONG.to_le_bytes());
            i32le(&mut out, p.id);
            i32le(&mut out, p.dir.code());
            let n = count(p.points.len());
            i32le(&mut out, n);
            for [x, y] in p.points.iter().take(n as usize) {
                f32le(&mut out, *x);
                f32le(&mut out, *y);
            }
        }
        for h in &layer.hatches {
            out.extend_from_slice(&code::HATCHES_LONG.to_le_bytes());
            i32le(&mut out, h.id);
            let n = count(h.lines.len());
            i32le(&mut out, n);
            for [[a, b], [c, d]] in h.lines.iter().take(n as usize) {
                for v in [a, b, c, d] {
                    f32le(&mut out, *v);
                }
            }
        }
    }
    out
}

/// What is wrong with a command's parameters or a binary value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Problem {
    /// A value does not parse as a number.
    #[error("a value is not a number")]
    NotANumber,
    /// A value is infinite or NaN.
    #[error("a value is not finite")]
    NotFinite,
    /// A count, id or code is not an integer in range.
    #[error("a count, id or code is not an integer in range")]
    NotAnInteger,
    /// Fewer or more values than the command takes.
    #[error("expected {expected} values, found {found}")]
    ValueCount {
        /// Expected.
        expected: usize,
        /// Found.
        found: usize,
    },
    /// The direction is not 0, 1 or 2.
    #[error("direction {0} is not 0, 1 or 2")]
    Direction(i64),
    /// A declared count is negative.
    #[error("negative count {0}")]
    NegativeCount(i64),
    /// `$$UNITS` is not positive.
    #[error("units must be positive")]
    NonPositiveUnits,
}

/// Why a CLI file cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CliError {
    /// The file does not start with `$$HEADERSTART`.
    #[error("not a CLI file: it does not start with $$HEADERSTART")]
    NotCli,
    /// No `$$HEADEREND`.
    #[error("the header has no $$HEADEREND")]
    MissingHeaderEnd,
    /// Neither `$$ASCII` nor `$$BINARY`.
    #[error("the header says neither $$ASCII nor $$BINARY")]
    MissingEncoding,
    /// Both `$$ASCII` and `$$BINARY`.
    #[error("the header says both $$ASCII and $$BINARY")]
    ConflictingEncoding,
    /// `$$ALIGN` (4-byte aligned binary data) is not supported.
    #[error("$$ALIGN binary files are not supported")]
    AlignUnsupported,
    /// A command's parameters are wrong.
    #[error("line {line}: $${command}: {problem}")]
    BadParameters {
        /// 1-based line.
        line: usize,
        /// The command (without `$$`).
        command: String,
        /// What is wrong.
        problem: Problem,
    },
    /// An unknown geometry command.
    #[error("line {line}: unknown geometry command $${command}")]
    UnknownCommand {
        /// 1-based line.
        line: usize,
        /// The command (without `$$`).
        command: String,
    },
    /// Text that is not a `$$` command.
    #[error("line {line}: text outside any command")]
    StrayText {
        /// 1-based line.
        line: usize,
    },
    /// Geometry before the first `$$LAYER`.
    #[error("line {line}: $${command} before the first $$LAYER")]
    OutsideLayer {
        /// 1-based line.
        line: usize,
        /// The command.
        command: String,
    },
    /// Binary geometry before the first layer command.
    #[error("byte {offset}: {what} before the first layer")]
    OutsideLayerAt {
        /// Offset of the command.
        offset: usize,
        /// The command.
        what: &'static str,
    },
    /// ASCII geometry does not start with `$$GEOMETRYSTART`.
    #[error("line {line}: expected $$GEOMETRYSTART")]
    MissingGeometryStart {
        /// 1-based line.
        line: usize,
    },
    /// ASCII geometry does not end with `$$GEOMETRYEND`.
    #[error("no $$GEOMETRYEND")]
    MissingGeometryEnd,
    /// Commands after `$$GEOMETRYEND`.
    #[error("line {line}: commands after $$GEOMETRYEND")]
    AfterGeometryEnd {
        /// 1-based line.
        line: usize,
    },
    /// A layer lies below the one before it.
    #[error("layer {index}: z = {z} is below the previous layer's z = {previous}")]
    NotAscending {
        /// 0-based layer index.
        index: usize,
        /// Its z.
        z: f64,
        /// The previous layer's z.
        previous: f64,
    },
    /// `$$LAYERS` disagrees with the layers in the file.
    #[error("$$LAYERS/{declared} but the file holds {found} layers")]
    LayerCount {
        /// Declared.
        declared: u64,
        /// Found.
        found: usize,
    },
    /// An unknown binary command code.
    #[error("byte {offset}: unknown binary command code {code}")]
    UnknownCode {
        /// Offset of the code.
        offset: usize,
        /// The code.
        code: u16,
    },
    /// Binary data ends inside a command.
    #[error("byte {offset}: {what} needs {needed} bytes, only {available} left")]
    Truncated {
        /// Offset where the data was expected.
        offset: usize,
        /// What was being read.
        what: &'static str,
        /// Bytes needed.
        needed: u64,
        /// Bytes left.
        available: usize,
    },
    /// A wrong binary value.
    #[error("byte {offset}: {what}: {problem}")]
    BadBinary {
        /// Offset of the command.
        offset: usize,
        /// The command.
        what: &'static str,
        /// What is wrong.
        problem: Problem,
    },
}

/// One `$$` command of the ASCII text.
struct Command {
    line: usize,
    name: String,
    params: String,
}

/// Splits text into `$$` commands: comments removed, line breaks inside a
/// command's parameters joined. `first_line` is the 1-based line of the
/// text's start.
fn commands(text: &str, first_line: usize) -> Result<Vec<Command>, CliError> {
    let mut out: Vec<Command> = Vec::new();
    for (i, raw) in text.split('\n').enumerate() {
        let line = first_line + i;
        let code = strip_comments(raw.trim_end_matches('\r'));
        let mut rest = code.as_str();
        if let Some(pos) = rest.find("$$") {
            let before = rest[..pos].trim();
            if !before.is_empty() {
                match out.last_mut() {
                    Some(c) => c.params.push_str(before),
                    None => return Err(CliError::StrayText { line }),
                }
            }
            rest = &rest[pos..];
        } else {
            let t = rest.trim();
            if !t.is_empty() {
                match out.last_mut() {
                    Some(c) => c.params.push_str(t),
                    None => return Err(CliError::StrayText { line }),
                }
            }
            continue;
        }
        for piece in rest.split("$$").skip(1) {
            let (name, params) = match piece.find('/') {
                Some(p) => (&piece[..p], &piece[p + 1..]),
                None => (piece, ""),
            };
            out.push(Command {
                line,
                name: name.trim().to_ascii_uppercase(),
                params: params.trim().to_string(),
            });
        }
    }
    Ok(out)
}

/// A line without its `// ... //` comments (a comment runs to the next
/// `//` or to the end of the line).
fn strip_comments(line: &str) -> String {
    let mut out = String::new();
    let mut rest = line;
    while let Some(p) = rest.find("//") {
        out.push_str(&rest[..p]);
        rest = &rest[p + 2..];
        match rest.find("//") {
            Some(q) => rest = &rest[q + 2..],
            None => return out,
        }
    }
    out.push_str(rest);
    out
}

fn split_params(c: &Command) -> Vec<&str> {
    if c.params.trim().is_empty() {
        return Vec::new();
    }
    c.params.split(',').map(str::trim).collect()
}

fn bad(c: &Command, problem: Problem) -> CliError {
    CliError::BadParameters {
        line: c.line,
        command: c.name.clone(),
        problem,
    }
}

fn real(c: &Command, t: &str) -> Result<f64, CliError> {
    let x: f64 = t.parse().map_err(|_| bad(c, Problem::NotANumber))?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(bad(c, Problem::NotFinite))
    }
}

fn integer(c: &Command, t: &str) -> Result<i64, CliError> {
    t.parse::<i64>().map_err(|_| bad(c, Problem::NotAnInteger))
}

fn exactly<'a>(c: &Command, v: &'a [&'a str], n: usize) -> Result<&'a [&'a str], CliError> {
    if v.len() == n {
        Ok(v)
    } else {
        Err(bad(
            c,
            Problem::ValueCount {
                expected: n,
                found: v.len(),
            },
        ))
    }
}

fn id_i32(c: &Command, t: &str) -> Result<i32, CliError> {
    i32::try_from(integer(c, t)?).map_err(|_| bad(c, Problem::NotAnInteger))
}

fn parse_header(cmds: &[Command]) -> Result<Header, CliError> {
    let mut encoding = None;
    let mut h = Header {
        encoding: Encoding::Ascii,
        units: 1.0,
        version: 0,
        labels: Vec::new(),
        date: None,
        dimension: None,
        layers: None,
        other: Vec::new(),
    };
    for (i, c) in cmds.iter().enumerate() {
        let v = split_params(c);
        match c.name.as_str() {
            "HEADERSTART" if i == 0 => {}
            "ASCII" | "BINARY" => {
                let e = if c.name == "ASCII" {
                    Encoding::Ascii
                } else {
                    Encoding::Binary
                };
                if encoding.is_some_and(|x| x != e) {
                    return Err(CliError::ConflictingEncoding);
                }
                encoding = Some(e);
            }
            "ALIGN" => return Err(CliError::AlignUnsupported),
            "UNITS" => {
                let u = real(c, exactly(c, &v, 1)?[0])?;
                if u <= 0.0 {
                    return Err(bad(c, Problem::NonPositiveUnits));
                }
                h.units = u;
            }
            "VERSION" => {
                let x = integer(c, exactly(c, &v, 1)?[0])?;
                h.version = u32::try_from(x).map_err(|_| bad(c, Problem::NotAnInteger))?;
            }
            "LABEL" => {
                let (id, text) = match c.params.split_once(',') {
                    Some((a, b)) => (a, b),
                    None => {
                        return Err(bad(
                            c,
                            Problem::ValueCount {
                                expected: 2,
                                found: 1,
                            },
                        ))
                    }
                };
                h.labels
                    .push((id_i32(c, id.trim())?, text.trim().to_string()));
            }
            "DATE" => h.date = Some(c.params.trim().to_string()),
            "DIMENSION" => {
                let v = exactly(c, &v, 6)?;
                let mut d = [0.0; 6];
                for (k, t) in v.iter().enumerate() {
                    d[k] = real(c, t)?;
                }
                h.dimension = Some(d);
            }
            "LAYERS" => {
                let x = integer(c, exactly(c, &v, 1)?[0])?;
                h.layers = Some(u64::try_from(x).map_err(|_| bad(c, Problem::NegativeCount(x)))?);
            }
            _ => h.other.push(if c.params.is_empty() {
                c.name.clone()
            } else {
                format!("{}/{}", c.name, c.params)
            }),
        }
    }
    h.encoding = encoding.ok_or(CliError::MissingEncoding)?;
    Ok(h)
}

/// Checks that layer `index` at `z` is not below the previous one.
fn check_ascending(layers: &[Layer], z: f64) -> Result<(), CliError> {
    if let Some(prev) = layers.last() {
        if z < prev.z {
            return Err(CliError::NotAscending {
                index: layers.len(),
                z,
                previous: prev.z,
            });
        }
    }
    Ok(())
}

fn parse_ascii_geometry(cmds: &[Command]) -> Result<Vec<Layer>, CliError> {
    let mut it = cmds.iter();
    match it.next() {
        Some(c) if c.name == "GEOMETRYSTART" => {}
        Some(c) => return Err(CliError::MissingGeometryStart { line: c.line }),
        None => return Err(CliError::MissingGeometryEnd),
    }
    let mut layers: Vec<Layer> = Vec::new();
    let mut ended = false;
    for c in it {
        if ended {
            return Err(CliError::AfterGeometryEnd { line: c.line });
        }
        let v = split_params(c);
        match c.name.as_str() {
            "GEOMETRYEND" => ended = true,
            "LAYER" => {
                let z = real(c, exactly(c, &v, 1)?[0])?;
                check_ascending(&layers, z)?;
                layers.push(Layer {
                    z,
                    polylines: Vec::new(),
                    hatches: Vec::new(),
                });
            }
            "POLYLINE" | "HATCHES" => {
                let per = if c.name == "POLYLINE" { 2 } else { 4 };
                let head = if c.name == "POLYLINE" { 3 } else { 2 };
                if v.len() < head {
                    return Err(bad(
                        c,
                        Problem::ValueCount {
                            expected: head,
                            found: v.len(),
                        },
                    ));
                }
                let id = id_i32(c, v[0])?;
                let n = integer(c, v[head - 1])?;
                if n < 0 {
                    return Err(bad(c, Problem::NegativeCount(n)));
                }
                let values = &v[head..];
                // n is bounded by the values present, never trusted first.
                if (values.len() as u128) != (n as u128) * per as u128 {
                    return Err(bad(
                        c,
                        Problem::ValueCount {
                            expected: head + (n as usize).saturating_mul(per),
                            found: v.len(),
                        },
                    ));
                }
                let nums = values
                    .iter()
                    .map(|t| real(c, t))
                    .collect::<Result<Vec<f64>, _>>()?;
                let layer = layers.last_mut().ok_or_else(|| CliError::OutsideLayer {
                    line: c.line,
                    command: c.name.clone(),
                })?;
                if c.name == "POLYLINE" {
                    let d = integer(c, v[1])?;
                    let dir =
                        Direction::from_code(d).ok_or_else(|| bad(c, Problem::Direction(d)))?;
                    layer.polylines.push(Polyline {
                        id,
                        dir,
                        points: nums.chunks_exact(2).map(|p| [p[0], p[1]]).collect(),
                    });
                } else {
                    layer.hatches.push(Hatches {
                        id,
                        lines: nums
                            .chunks_exact(4)
                            .map(|p| [[p[0], p[1]], [p[2], p[3]]])
                            .collect(),
                    });
                }
            }
            _ => {
                return Err(CliError::UnknownCommand {
                    line: c.line,
                    command: c.name.clone(),
                })
            }
        }
    }
    if !ended {
        return Err(CliError::MissingGeometryEnd);
    }
    Ok(layers)
}

/// A cursor over binary geometry.
struct Bin<'a> {
    data: &'a [u8],
    base: usize,
    pos: usize,
}

impl<'a> Bin<'a> {
    fn offset(&self) -> usize {
        self.base + self.pos
    }

    fn left(&self) -> usize {
        self.data.len() - self.pos
    }

    fn need(&self, bytes: u64, what: &'static str) -> Result<(), CliError> {
        if bytes > self.left() as u64 {
            Err(CliError::Truncated {
                offset: self.offset(),
                what,
                needed: bytes,
                available: self.left(),
            })
        } else {
            Ok(())
        }
    }

    fn take<const N: usize>(&mut self, what: &'static str) -> Result<[u8; N], CliError> {
        self.need(N as u64, what)?;
        let mut b = [0u8; N];
        b.copy_from_slice(&self.data[self.pos..self.pos + N]);
        self.pos += N;
        Ok(b)
    }

    fn u16(&mut self, what: &'static str) -> Result<u16, CliError> {
        Ok(u16::from_le_bytes(self.take(what)?))
    }

    fn i32(&mut self, what: &'static str) -> Result<i32, CliError> {
        Ok(i32::from_le_bytes(self.take(what)?))
    }

    fn f32(&mut self, what: &'static str, at: usize) -> Result<f64, CliError> {
        let x = f32::from_le_bytes(self.take(what)?);
        if x.is_finite() {
            Ok(f64::from(x))
        } else {
            Err(CliError::BadBinary {
                offset: at,
                what,
                problem: Problem::NotFinite,
            })
        }
    }
}

fn count_of(n: i64, at: usize, what: &'static str) -> Result<u64, CliError> {
    u64::try_from(n).map_err(|_| CliError::BadBinary {
        offset: at,
        what,
        problem: Problem::NegativeCount(n),
    })
}

fn parse_binary_geometry(data: &[u8], base: usize) -> Result<Vec<Layer>, CliError> {
    let mut b = Bin { data, base, pos: 0 };
    let mut layers: Vec<Layer> = Vec::new();
    while b.left() > 0 {
        let at = b.offset();
        let c = b.u16("command code")?;
        let outside = |what: &'static str| CliError::OutsideLayerAt { offset: at, what };
        match c {
            code::LAYER_LONG | code::LAYER_SHORT => {
                let z = if c == code::LAYER_LONG {
                    b.f32("layer long", at)?
                } else {
                    f64::from(b.u16("layer short")?)
                };
                check_ascending(&layers, z)?;
                layers.push(Layer {
                    z,
                    polylines: Vec::new(),
                    hatches: Vec::new(),
                });
            }
            code::POLYLINE_LONG | code::POLYLINE_SHORT => {
                let long = c == code::POLYLINE_LONG;
                let what = if long {
                    "polyline long"
                } else {
                    "polyline short"
                };
                let (id, d, n) = if long {
                    (
                        b.i32(what)?,
                        i64::from(b.i32(what)?),
                        i64::from(b.i32(what)?),
                    )
                } else {
                    (
                        i32::from(b.u16(what)?),
                        i64::from(b.u16(what)?),
                        i64::from(b.u16(what)?),
                    )
                };
                let dir = Direction::from_code(d).ok_or(CliError::BadBinary {
                    offset: at,
                    what,
                    problem: Problem::Direction(d),
                })?;
                let n = count_of(n, at, what)?;
                let size = if long { 8 } else { 4 };
                b.need(n * size, what)?;
                let mut points = Vec::with_capacity(n as usize);
                for _ in 0..n {
                    points.push(if long {
                        [b.f32(what, at)?, b.f32(what, at)?]
                    } else {
                        [f64::from(b.u16(what)?), f64::from(b.u16(what)?)]
                    });
                }
                layers
                    .last_mut()
                    .ok_or_else(|| outside(what))?
                    .polylines
                    .push(Polyline { id, dir, points });
            }
            code::HATCHES_LONG | code::HATCHES_SHORT => {
                let long = c == code::HATCHES_LONG;
                let what = if long {
                    "hatches long"
                } else {
                    "hatches short"
                };
                let (id, n) = if long {
                    (b.i32(what)?, i64::from(b.i32(what)?))
                } else {
                    (i32::from(b.u16(what)?), i64::from(b.u16(what)?))
                };
                let n = count_of(n, at, what)?;
                let size = if long { 16 } else { 8 };
                b.need(n * size, what)?;
                let mut lines = Vec::with_capacity(n as usize);
                for _ in 0..n {
                    let mut v = [0.0; 4];
                    for x in &mut v {
                        *x = if long {
                            b.f32(what, at)?
                        } else {
                            f64::from(b.u16(what)?)
                        };
                    }
                    lines.push([[v[0], v[1]], [v[2], v[3]]]);
                }
                layers
                    .last_mut()
                    .ok_or_else(|| outside(what))?
                    .hatches
                    .push(Hatches { id, lines });
            }
            _ => {
                return Err(CliError::UnknownCode {
                    offset: at,
                    code: c,
                })
            }
        }
    }
    Ok(layers)
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Where `$$HEADERSTART` should be: after a byte-order mark, white space
/// and `//` comments.
fn header_start(bytes: &[u8]) -> usize {
    let mut i = if bytes.starts_with(b"\xEF\xBB\xBF") {
        3
    } else {
        0
    };
    loop {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        if !bytes[i..].starts_with(b"//") {
            return i;
        }
        i += 2;
        let line_end = bytes[i..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(bytes.len(), |p| i + p);
        i = match find(&bytes[i..line_end], b"//") {
            Some(p) => i + p + 2,
            None => line_end,
        };
    }
}

/// Reads a CLI file, ASCII or binary (told apart by its header).
pub fn read(bytes: &[u8]) -> Result<CliFile, CliError> {
    let start = header_start(bytes);
    if !bytes[start..].starts_with(b"$$HEADERSTART") {
        return Err(CliError::NotCli);
    }
    const END: &[u8] = b"$$HEADEREND";
    let end = find(&bytes[start..], END)
        .map(|p| p + start)
        .ok_or(CliError::MissingHeaderEnd)?;
    let header_text = String::from_utf8_lossy(&bytes[start..end]);
    let first_line = 1 + bytes[..start].iter().filter(|&&b| b == b'\n').count();
    let header = parse_header(&commands(&header_text, first_line)?)?;
    let after = end + END.len();
    let layers = match header.encoding {
        Encoding::Binary => {
            // An optional line break after $$HEADEREND (no command code
            // starts with byte 10 or 13).
            let mut skip = after;
            while skip < bytes.len() && skip < after + 2 && matches!(bytes[skip], b'\r' | b'\n') {
                skip += 1;
            }
            parse_binary_geometry(&bytes[skip..], skip)?
        }
        Encoding::Ascii => {
            let text = String::from_utf8_lossy(&bytes[after..]);
            let line = 1 + bytes[..after].iter().filter(|&&b| b == b'\n').count();
            parse_ascii_geometry(&commands(&text, line)?)?
        }
    };
    if let Some(declared) = header.layers {
        if declared != layers.len() as u64 {
            return Err(CliError::LayerCount {
                declared,
                found: layers.len(),
            });
        }
    }
    Ok(CliFile { header, layers })
}
