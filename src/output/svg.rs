//! Input: exact level sets and the mesh they slice (for the bounding box and
//! saddle positions). Output: SVG drawings, one per level, in which every
//! kind of the level set is told apart by a CSS class.
//!
//! | element | class | drawn as |
//! |---|---|---|
//! | S_O outer loop, with its holes cut out (`fill-rule="evenodd"`) | `so outer` | light blue fill, blue stroke |
//! | S_O hole | `so hole` | purple stroke |
//! | F region (all its dF loops, `evenodd`) | `f up`, `f down`, `f flat` | green, pink, grey fill |
//! | dF loop | `df` | dark green stroke |
//! | S_NO polyline | `sno ridge`, `sno valley` | red, cyan dashes |
//! | P | `p min`, `p max` | teal, orange dot |
//! | saddle (`data-m` = m, labelled `m=3`) | `saddle` | magenta diamond |
//! | L-, L+ loop | `lminus`, `lplus` (plus `outer`/`hole`, and `collapsed` for a limit of zero width) | amber, violet thin dashes (dotted when collapsed) |
//! | direction arrow (on request) | `arrow on-so` (`hole`), `arrow on-df` | the loop's colour |
//!
//! Each kind sits in its own group (`layer-so`, `layer-f`, `layer-sno`,
//! `layer-p`, `layer-saddle`, `layer-lminus`, `layer-lplus`), which the HTML
//! viewer toggles. Loops and regions carry their exact signed area as
//! `data-area` (`"p/q"`). Coordinates are the nearest `f64` of the exact
//! values, with `y` negated so that `+y` points up: model coordinates, or,
//! where a browser's 32-bit floats would lose the drawing (a part far from
//! the origin, or at either end of the double range), moved and scaled by
//! a power of two as the drawing's `data-frame` says ([`Frame`]; one more
//! rounding).
//! The legend uses inline styles only, never the classes above, so that
//! the classes count exactly the level set's elements.

use crate::classify::{ExtremumKind, Facing, RidgeKind};
use crate::exact::point::LoopPoint;
use crate::exact::rational::{rat_from_f64, rat_to_f64, rat_to_string, Rat};
use crate::exact::scale::{leading_exponent, times_pow2};
use crate::exact::Point2;
use crate::ids::VertexId;
use crate::levelset::{LevelSet, Loop};
use crate::mesh::Mesh;
use crate::nest::Role;
use std::fmt::Write;
use std::sync::Arc;

/// The colours of the drawing, shared by the SVG files and the HTML viewer
/// (tests look for them in screenshots).
pub mod colour {
    /// S_O outer fill.
    pub const SO_FILL: &str = "#cfe0f5";
    /// S_O outer stroke.
    pub const SO_OUTER: &str = "#1f5fbf";
    /// S_O hole stroke.
    pub const SO_HOLE: &str = "#7b2cbf";
    /// F up fill.
    pub const F_UP: &str = "#9fdf9f";
    /// F down fill.
    pub const F_DOWN: &str = "#f4a6a6";
    /// F flat fill.
    pub const F_FLAT: &str = "#cccccc";
    /// dF stroke.
    pub const DF: &str = "#2d7d2d";
    /// S_NO ridge stroke.
    pub const RIDGE: &str = "#d62828";
    /// S_NO valley stroke.
    pub const VALLEY: &str = "#0096c7";
    /// P min dot.
    pub const P_MIN: &str = "#2a9d8f";
    /// P max dot.
    pub const P_MAX: &str = "#f77f00";
    /// Saddle mark and label.
    pub const SADDLE: &str = "#c2188b";
    /// L- stroke.
    pub const L_MINUS: &str = "#e0a000";
    /// L+ stroke.
    pub const L_PLUS: &str = "#8a5cf6";
}

/// The style sheet of the classes (SVG and HTML).
pub fn style() -> String {
    use colour::*;
    format!(
        "\
.so,.df,.sno,.lminus,.lplus{{vector-effect:non-scaling-stroke;stroke-linejoin:round;stroke-linecap:round}}
.so.outer{{fill:{SO_FILL};stroke:{SO_OUTER};stroke-width:2.5px}}
.so.hole{{fill:none;stroke:{SO_HOLE};stroke-width:2.5px}}
.f{{stroke:none}}
.f.up{{fill:{F_UP}}}
.f.down{{fill:{F_DOWN}}}
.f.flat{{fill:{F_FLAT}}}
.df{{fill:none;stroke:{DF};stroke-width:2.5px}}
.sno{{fill:none;stroke-width:3px;stroke-dasharray:7 4}}
.sno.ridge{{stroke:{RIDGE}}}
.sno.valley{{stroke:{VALLEY}}}
.p{{stroke:#222;stroke-width:0.75px;vector-effect:non-scaling-stroke}}
.p.min{{fill:{P_MIN}}}
.p.max{{fill:{P_MAX}}}
.saddle path{{fill:{SADDLE};stroke:#222;stroke-width:0.75px;vector-effect:non-scaling-stroke}}
.saddle text{{fill:{SADDLE};font-family:sans-serif;font-weight:bold}}
.lminus,.lplus{{fill:none;stroke-width:2px;stroke-dasharray:4 3}}
.lminus{{stroke:{L_MINUS}}}
.lplus{{stroke:{L_PLUS}}}
.lminus.collapsed,.lplus.collapsed{{stroke-dasharray:1 3}}
.arrow.on-so{{fill:{SO_OUTER}}}
.arrow.on-so.hole{{fill:{SO_HOLE}}}
.arrow.on-df{{fill:{DF}}}
"
    )
}

/// The exact bounding box of a mesh in output units, rounded to `f64`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Smallest x, y, z.
    pub min: [f64; 3],
    /// Largest x, y, z.
    pub max: [f64; 3],
}

impl Bounds {
    /// The bounding box of the mesh's positions times `unit` (a snapped
    /// mesh) or as stored. All zeros for an empty mesh.
    pub fn of_mesh(mesh: &Mesh, unit: Option<&Rat>) -> Self {
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for p in &mesh.positions {
            for k in 0..3 {
                if p[k] < min[k] {
                    min[k] = p[k];
                }
                if p[k] > max[k] {
                    max[k] = p[k];
                }
            }
        }
        if mesh.positions.is_empty() || min.iter().chain(&max).any(|x| !x.is_finite()) {
            return Bounds {
                min: [0.0; 3],
                max: [0.0; 3],
            };
        }
        let scale = |x: f64| match unit {
            Some(u) => rat_to_f64(&(rat_from_f64(x) * u)),
            None => x,
        };
        Bounds {
            min: min.map(scale),
            max: max.map(scale),
        }
    }
}

/// What a drawing needs besides the level set: the mesh (saddle positions),
/// its snap unit, and its bounding box.
pub struct Scene<'a> {
    mesh: &'a Mesh,
    unit: Option<Rat>,
    bounds: Bounds,
    frame: Frame,
}

impl<'a> Scene<'a> {
    /// The scene of a mesh; `unit` is the snap grid when the mesh is snapped.
    pub fn new(mesh: &'a Mesh, unit: Option<&Rat>) -> Self {
        let bounds = Bounds::of_mesh(mesh, unit);
        Scene {
            mesh,
            unit: unit.cloned(),
            frame: Frame::of(&bounds),
            bounds,
        }
    }

    /// The bounding box, in output units.
    pub fn bounds(&self) -> &Bounds {
        &self.bounds
    }

    /// Where the drawing puts model coordinates.
    pub fn frame(&self) -> &Frame {
        &self.frame
    }

    /// The exact (x, y) of a vertex in output units.
    pub fn vertex_point(&self, v: VertexId) -> Point2 {
        let p = Point2::of_vertex(self.mesh.pos(v));
        match &self.unit {
            Some(u) => p.scaled(u),
            None => p,
        }
    }
}

/// Where a drawing puts a model point `(x, y)`: at `X = (x - x0) 2^k`,
/// `Y = (y0 - y) 2^k`, each rounded once to `f64` (so `+y` points up).
///
/// Browsers read SVG numbers as 32-bit floats, so model coordinates draw
/// nothing for a part `1e15` from the origin (all its points one float
/// apart) or scaled to `1e-300` or `1e300` (beyond the float's range).
/// The frame is the identity (`x0 = y0 = 0`, `k = 0`: model coordinates
/// with `y` negated) when a 32-bit float resolves the bounding box to
/// 1/32768 of its size and its size lies within `2^-60 .. 2^61`; else the
/// box's corner `(min x, max y)` goes to `(0, 0)` and `2^k` brings its
/// size to between 512 and 1024. A drawing says which as
/// `data-frame="x0 y0 k"`, from which `x = x0 + X 2^-k`, `y = y0 - Y 2^-k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// `(x0, y0)`: the model point drawn at `(0, 0)`.
    pub origin: [f64; 2],
    /// The drawing's unit is `2^-k` model units.
    pub k: i32,
}

impl Frame {
    /// Model coordinates, `y` negated.
    pub const IDENTITY: Frame = Frame {
        origin: [0.0, 0.0],
        k: 0,
    };

    /// The frame of a bounding box (see [`Frame`]).
    pub fn of(b: &Bounds) -> Frame {
        // 2^e <= size < 2^(e+1), from the wider extent (halved when the
        // difference overflows); a box of no size is drawn as it is.
        let extent = |lo: f64, hi: f64| {
            let d = hi - lo;
            if d.is_finite() {
                leading_exponent(d)
            } else {
                leading_exponent(offset(lo, hi, -1)).map(|e| e + 1)
            }
        };
        let Some(e) = extent(b.min[0], b.max[0]).max(extent(b.min[1], b.max[1])) else {
            return Frame::IDENTITY;
        };
        let far = [b.min[0], b.max[0], b.min[1], b.max[1]]
            .into_iter()
            .filter_map(leading_exponent)
            .max();
        // |coordinate| < 2^(e+9): a float's 24 bits resolve 2^(e-15).
        if (-60..=60).contains(&e) && far.is_none_or(|m| m <= e + 8) {
            Frame::IDENTITY
        } else {
            Frame {
                origin: [b.min[0], b.max[1]],
                k: 9 - e,
            }
        }
    }

    /// The drawing point of a model point.
    pub fn place(&self, [x, y]: [f64; 2]) -> [f64; 2] {
        [
            offset(self.origin[0], x, self.k),
            offset(y, self.origin[1], self.k),
        ]
    }

    /// The `data-frame` attribute value, `"x0 y0 k"`; `x0` and `y0` as the
    /// shorter of the plain and the exponent form (`1.5e-310`), each
    /// reading back as the same double.
    pub fn attr(&self) -> String {
        let short = |x: f64| {
            let (plain, exp) = (num(x), format!("{:e}", x + 0.0));
            if exp.len() < plain.len() {
                exp
            } else {
                plain
            }
        };
        format!(
            "{} {} {}",
            short(self.origin[0]),
            short(self.origin[1]),
            self.k
        )
    }
}

/// `(to - from) 2^k`, rounded once: for `k < 0` each term is scaled first
/// (exact unless it falls below `2^-1074`), so that the difference of
/// coordinates near `±f64::MAX` does not overflow; else the difference is
/// taken first and scaled exactly.
fn offset(from: f64, to: f64, k: i32) -> f64 {
    if k < 0 {
        times_pow2(to, k) - times_pow2(from, k)
    } else {
        times_pow2(to - from, k)
    }
}

/// Drawing options.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SvgOptions {
    /// Direction arrows on S_O and dF loops.
    pub arrows: bool,
}

/// The drawing of one level: the elements, placed by the scene's
/// [`Frame`], and the view box that frames the mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct Drawing {
    /// `[x, y, width, height]` of the view box.
    pub view_box: [f64; 4],
    /// Where the elements' coordinates come from.
    pub frame: Frame,
    /// The groups of elements (no `<svg>` around them).
    pub body: String,
}

impl Drawing {
    /// The `viewBox` attribute value.
    pub fn view_box_attr(&self) -> String {
        let [x, y, w, h] = self.view_box;
        format!("{} {} {} {}", num(x), num(y), num(w), num(h))
    }
}

/// A coordinate as SVG text: the shortest decimal that reads back as the
/// same `f64`; `-0` as `0`.
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{}", x + 0.0)
    } else {
        "0".into()
    }
}

/// Escapes text for XML content and attribute values.
pub fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Appends a closed (or open) subpath `M .. L .. [Z]` of drawing points.
fn subpath(d: &mut String, pts: &[[f64; 2]], closed: bool) {
    for (i, &[x, y]) in pts.iter().enumerate() {
        let _ = write!(
            d,
            "{}{} {}",
            if i == 0 {
                if d.is_empty() {
                    "M"
                } else {
                    " M"
                }
            } else {
                " L"
            },
            num(x),
            num(y)
        );
    }
    if closed && !pts.is_empty() {
        d.push_str(" Z");
    }
}

/// The drawing points of a loop's points (nearest doubles, placed).
fn placed(points: &[LoopPoint], frame: &Frame) -> Vec<[f64; 2]> {
    points.iter().map(|p| frame.place(p.to_f64())).collect()
}

fn role_class(r: Role) -> &'static str {
    match r {
        Role::Outer => "outer",
        Role::Hole => "hole",
    }
}

/// Arrow triangles along a closed loop, pointing in its direction.
fn arrows(out: &mut String, pts: &[[f64; 2]], size: f64, class: &str) {
    let n = pts.len();
    if n < 2 || size.is_nan() || size <= 0.0 {
        return;
    }
    let seg = |i: usize| (pts[i], pts[(i + 1) % n]);
    let len = |(a, b): ([f64; 2], [f64; 2])| (b[0] - a[0]).hypot(b[1] - a[1]);
    let perimeter: f64 = (0..n).map(|i| len(seg(i))).sum();
    if perimeter.is_nan() || perimeter <= 0.0 {
        return;
    }
    let k = ((perimeter / (6.0 * size)).round() as usize).clamp(1, 12);
    let step = perimeter / k as f64;
    let mut target = step / 2.0;
    let mut walked = 0.0;
    let mut placed = 0;
    for i in 0..n {
        let (a, b) = seg(i);
        let l = len((a, b));
        while placed < k && l > 0.0 && target <= walked + l {
            let t = (target - walked) / l;
            let d = [(b[0] - a[0]) / l, (b[1] - a[1]) / l];
            let c = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
            let nrm = [-d[1], d[0]];
            let h = size / 2.0;
            let w = size / 3.0;
            let tip = [c[0] + d[0] * h, c[1] + d[1] * h];
            let l1 = [c[0] - d[0] * h + nrm[0] * w, c[1] - d[1] * h + nrm[1] * w];
            let l2 = [c[0] - d[0] * h - nrm[0] * w, c[1] - d[1] * h - nrm[1] * w];
            let mut dd = String::new();
            subpath(&mut dd, &[tip, l1, l2], true);
            let _ = writeln!(out, r#"<path class="arrow {class}" d="{dd}"/>"#);
            placed += 1;
            target += step;
        }
        walked += l;
    }
}

/// Draws one level: every kind in its group, framed by the mesh's
/// bounding box.
pub fn drawing(ls: &LevelSet, scene: &Scene, opts: &SvgOptions) -> Drawing {
    let (b, frame) = (scene.bounds(), scene.frame());
    let [x0, y0] = frame.place([b.min[0], b.max[1]]);
    let [x1, y1] = frame.place([b.max[0], b.min[1]]);
    let (w0, h0) = (x1 - x0, y1 - y0);
    let size = {
        let s = w0.max(h0);
        if s > 0.0 && s.is_finite() {
            s
        } else {
            1.0
        }
    };
    let pad = 0.06 * size;
    let view_box = [
        x0 - pad + 0.0,
        y0 - pad + 0.0,
        w0 + 2.0 * pad,
        h0 + 2.0 * pad,
    ];
    let dot = 0.014 * size;
    let arrow = 0.03 * size;
    let mut s = String::new();

    // F with dF (below everything: its interior never overlaps S_O's).
    s.push_str("<g class=\"layer-f\">\n");
    for r in &ls.regions {
        let facing = match r.facing {
            Facing::Up => "up",
            Facing::Down => "down",
            Facing::Flat => "flat",
        };
        let mut d = String::new();
        for l in &r.boundary {
            subpath(&mut d, &placed(&l.points, frame), true);
        }
        let _ = writeln!(
            s,
            r#"<path class="f {facing}" fill-rule="evenodd" data-area="{}" data-faces="{}" d="{d}"/>"#,
            rat_to_string(&r.area),
            r.faces.len()
        );
    }
    for r in &ls.regions {
        for l in &r.boundary {
            let pts = placed(&l.points, frame);
            let mut d = String::new();
            subpath(&mut d, &pts, true);
            let _ = writeln!(
                s,
                r#"<path class="df {}" data-area="{}" d="{d}"/>"#,
                role_class(l.role),
                rat_to_string(&l.area())
            );
            if opts.arrows {
                arrows(&mut s, &pts, arrow, "on-df");
            }
        }
    }
    s.push_str("</g>\n");

    // Each loop's exact area, written once per family: at a regular level
    // L- and L+ are S_O itself (one shared list), and their areas are not
    // computed again (each costs a reduction to lowest terms).
    let areas = |loops: &[Loop]| -> Vec<String> {
        loops.iter().map(|l| rat_to_string(&l.area())).collect()
    };
    let contour_areas = areas(&ls.contours);

    // L- and L+ (under S_O, which hides them where they coincide).
    for (group, class, loops) in [
        ("layer-lminus", "lminus", &ls.below),
        ("layer-lplus", "lplus", &ls.above),
    ] {
        let _ = writeln!(s, r#"<g class="{group}">"#);
        if Arc::ptr_eq(loops, &ls.contours) {
            loops_as_paths(&mut s, class, loops, &contour_areas, frame);
        } else {
            loops_as_paths(&mut s, class, loops, &areas(loops), frame);
        }
        s.push_str("</g>\n");
    }

    // S_O: one filled path per outer loop with its holes, then the holes.
    s.push_str("<g class=\"layer-so\">\n");
    for (i, l) in ls.contours.iter().enumerate() {
        if l.role != Role::Outer {
            continue;
        }
        let mut d = String::new();
        subpath(&mut d, &placed(&l.points, frame), true);
        for h in ls
            .contours
            .iter()
            .filter(|h| h.role == Role::Hole && h.parent == Some(i))
        {
            subpath(&mut d, &placed(&h.points, frame), true);
        }
        let _ = writeln!(
            s,
            r#"<path class="so outer" fill-rule="evenodd" data-area="{}" d="{d}"/>"#,
            contour_areas[i]
        );
    }
    for (l, area) in ls.contours.iter().zip(&contour_areas) {
        if l.role != Role::Hole {
            continue;
        }
        let mut d = String::new();
        subpath(&mut d, &placed(&l.points, frame), true);
        let _ = writeln!(s, r#"<path class="so hole" data-area="{area}" d="{d}"/>"#);
    }
    if opts.arrows {
        for l in ls.contours.iter() {
            let class = match l.role {
                Role::Outer => "on-so",
                Role::Hole => "on-so hole",
            };
            arrows(&mut s, &placed(&l.points, frame), arrow, class);
        }
    }
    s.push_str("</g>\n");

    // S_NO.
    s.push_str("<g class=\"layer-sno\">\n");
    for r in &ls.ridges {
        let kind = match r.kind {
            RidgeKind::Ridge => "ridge",
            RidgeKind::Valley => "valley",
        };
        let mut d = String::new();
        let points: Vec<[f64; 2]> = r.points.iter().map(|p| frame.place(p.to_f64())).collect();
        subpath(&mut d, &points, r.closed);
        let _ = writeln!(
            s,
            r#"<path class="sno {kind}" data-closed="{}" d="{d}"/>"#,
            r.closed
        );
    }
    s.push_str("</g>\n");

    // P.
    s.push_str("<g class=\"layer-p\">\n");
    for p in &ls.extrema {
        let kind = match p.kind {
            ExtremumKind::Min => "min",
            ExtremumKind::Max => "max",
        };
        let [x, y] = frame.place(p.point.to_f64());
        let _ = writeln!(
            s,
            r#"<circle class="p {kind}" data-vertex="{}" cx="{}" cy="{}" r="{}"/>"#,
            p.vertex.0,
            num(x),
            num(y),
            num(dot)
        );
    }
    s.push_str("</g>\n");

    // Saddles.
    s.push_str("<g class=\"layer-saddle\">\n");
    for sd in &ls.saddles {
        let [x, y] = frame.place(scene.vertex_point(sd.vertex).to_f64());
        let r = 1.6 * dot;
        let m = sd.m();
        let _ = writeln!(
            s,
            r#"<g class="saddle" data-m="{m}" data-vertex="{}"><path d="M{} {} L{} {} L{} {} L{} {} Z"/><text x="{}" y="{}" font-size="{}">m={m}</text></g>"#,
            sd.vertex.0,
            num(x),
            num(y - r),
            num(x + r),
            num(y),
            num(x),
            num(y + r),
            num(x - r),
            num(y),
            num(x + 1.3 * r),
            num(y - 1.3 * r),
            num(0.045 * size)
        );
    }
    s.push_str("</g>\n");
    Drawing {
        view_box,
        frame: *frame,
        body: s,
    }
}

/// The loops as paths, `areas[k]` the exact area text of loop `k`.
fn loops_as_paths(s: &mut String, class: &str, loops: &[Loop], areas: &[String], frame: &Frame) {
    for (l, area) in loops.iter().zip(areas) {
        let mut d = String::new();
        subpath(&mut d, &placed(&l.points, frame), true);
        // Limits are drawn as lines, never filled; a collapsed one is
        // marked so that a viewer can tell it bounds nothing.
        let collapsed = if l.collapsed { " collapsed" } else { "" };
        let _ = writeln!(
            s,
            r#"<path class="{class} {}{collapsed}" data-area="{area}" d="{d}"/>"#,
            role_class(l.role),
        );
    }
}

/// The legend rows: label, and how the swatch is drawn.
enum Swatch {
    Fill(&'static str, &'static str),
    Line(&'static str, &'static str, f64),
    Dot(&'static str),
    Diamond(&'static str),
}

/// `z = ` and the exact level when its text has at most `fit` characters,
/// else `z ≈ ` and its nearest double with `digits` digits after the
/// point (a label in a column of fixed width; the exact level belongs in
/// a title).
pub(crate) fn level_label(level: &Rat, fit: usize, digits: usize) -> String {
    let exact = rat_to_string(level);
    if exact.len() <= fit {
        format!("z = {exact}")
    } else {
        format!("z \u{2248} {:.*e}", digits, rat_to_f64(level))
    }
}

fn legend(out: &mut String, x0: f64, heading: &str) {
    use colour::*;
    let rows: [(&str, Swatch); 12] = [
        ("S_O outer", Swatch::Fill(SO_FILL, SO_OUTER)),
        ("S_O hole", Swatch::Line(SO_HOLE, "", 2.5)),
        ("F up", Swatch::Fill(F_UP, "none")),
        ("F down", Swatch::Fill(F_DOWN, "none")),
        ("dF", Swatch::Line(DF, "", 2.5)),
        ("S_NO ridge", Swatch::Line(RIDGE, "7 4", 3.0)),
        ("S_NO valley", Swatch::Line(VALLEY, "7 4", 3.0)),
        ("P min", Swatch::Dot(P_MIN)),
        ("P max", Swatch::Dot(P_MAX)),
        ("saddle (m)", Swatch::Diamond(SADDLE)),
        ("L- below", Swatch::Line(L_MINUS, "4 3", 2.0)),
        ("L+ above", Swatch::Line(L_PLUS, "4 3", 2.0)),
    ];
    let _ = writeln!(
        out,
        r#"<g class="legend" font-family="sans-serif" font-size="13"><text x="{x0}" y="24" font-weight="bold">{}</text>"#,
        xml_escape(heading)
    );
    for (i, (label, sw)) in rows.iter().enumerate() {
        let y = 52.0 + 24.0 * i as f64;
        let (sx, sy) = (x0, y - 5.0);
        match sw {
            Swatch::Fill(fill, stroke) => {
                let _ = write!(
                    out,
                    r#"<rect x="{sx}" y="{}" width="22" height="14" style="fill:{fill};stroke:{stroke};stroke-width:2"/>"#,
                    sy - 7.0
                );
            }
            Swatch::Line(c, dash, w) => {
                let _ = write!(
                    out,
                    r#"<line x1="{sx}" y1="{sy}" x2="{}" y2="{sy}" style="stroke:{c};stroke-width:{w};stroke-dasharray:{}"/>"#,
                    sx + 22.0,
                    if dash.is_empty() { "none" } else { dash }
                );
            }
            Swatch::Dot(c) => {
                let _ = write!(
                    out,
                    r#"<circle cx="{}" cy="{sy}" r="5" style="fill:{c};stroke:#222;stroke-width:0.75"/>"#,
                    sx + 11.0
                );
            }
            Swatch::Diamond(c) => {
                let cx = sx + 11.0;
                let _ = write!(
                    out,
                    r#"<path d="M{cx} {} L{} {sy} L{cx} {} L{} {sy} Z" style="fill:{c};stroke:#222;stroke-width:0.75"/>"#,
                    sy - 7.0,
                    cx + 7.0,
                    sy + 7.0,
                    cx - 7.0
                );
            }
        }
        let _ = writeln!(out, r#"<text x="{}" y="{}">{label}</text>"#, x0 + 30.0, y);
    }
    out.push_str("</g>\n");
}

/// Side of the square drawing area of a standalone SVG, in pixels.
const DRAW_PX: f64 = 640.0;
/// Width of the legend column, in pixels.
const LEGEND_PX: f64 = 170.0;

/// A standalone SVG document of one level: the drawing, a legend, and the
/// exact level in `<title>` (`name` is the mesh's name, for the title).
pub fn level_svg(ls: &LevelSet, scene: &Scene, name: &str, opts: &SvgOptions) -> String {
    let d = drawing(ls, scene, opts);
    let level = rat_to_string(&ls.level);
    let (w, h) = (DRAW_PX + LEGEND_PX, DRAW_PX);
    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" data-level="{level}">"#
    );
    let _ = writeln!(
        out,
        "<title>wmslice: {} at z = {level}</title>",
        xml_escape(name)
    );
    let _ = writeln!(out, "<style>\n{}</style>", style());
    let _ = writeln!(
        out,
        r##"<rect x="0" y="0" width="{w}" height="{h}" style="fill:#ffffff"/>"##
    );
    let _ = writeln!(
        out,
        r#"<svg x="0" y="0" width="{DRAW_PX}" height="{DRAW_PX}" viewBox="{}" data-frame="{}" preserveAspectRatio="xMidYMid meet">"#,
        d.view_box_attr(),
        d.frame.attr()
    );
    out.push_str(&d.body);
    out.push_str("</svg>\n");
    // The legend's column holds 17 characters of a level.
    legend(&mut out, DRAW_PX + 10.0, &level_label(&ls.level, 17, 6));
    out.push_str("</svg>\n");
    out
}

/// Exact levels longer than this are named by their nearest double: file
/// systems limit a name to 255 bytes, and a level of a mesh at `1e-300`
/// has hundreds of digits.
const EXACT_NAME_MAX: usize = 64;

/// The file name of a level's SVG: `layer-0003_z=3_5.svg` for the level
/// `3/5` at index 3 (`/` becomes `_`); when the exact level is longer than
/// 64 characters, `layer-0003_z~7.2e-301.svg` with its nearest double
/// (`~`: rounded; the index keeps names distinct, and the SVG's legend
/// holds the exact level).
pub fn level_file_name(index: usize, level: &Rat) -> String {
    let exact = rat_to_string(level).replace('/', "_");
    if exact.len() <= EXACT_NAME_MAX {
        format!("layer-{index:04}_z={exact}.svg")
    } else {
        format!("layer-{index:04}_z~{:e}.svg", rat_to_f64(level))
    }
}

/// Whether `name` has the form [`level_file_name`] gives (`layer-`, four
/// or more digits, `_z=` or `_z~`, anything, `.svg`): what a directory of
/// level SVGs holds from an earlier run, and nothing a user names
/// otherwise.
pub fn is_level_file_name(name: &str) -> bool {
    let Some(rest) = name.strip_prefix("layer-") else {
        return false;
    };
    let digits = rest.bytes().take_while(u8::is_ascii_digit).count();
    let rest = &rest[digits..];
    digits >= 4
        && (rest.starts_with("_z=") || rest.starts_with("_z~"))
        && rest.len() > ".svg".len() + 3
        && rest.ends_with(".svg")
}
