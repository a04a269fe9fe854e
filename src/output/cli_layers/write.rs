//! Level sets to CLI files: the polylines chosen, then ASCII or binary
//! bytes (`f32` values checked first).

use super::super::svg::Bounds;
use super::*;
use crate::exact::rational::{rat_to_f64, Rat};
use crate::levelset::{LevelSet, Loop};
use crate::nest::Role;
use std::fmt::Write;

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
