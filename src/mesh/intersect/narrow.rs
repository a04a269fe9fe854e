//! Input: the positions of two faces (exact doubles) and which vertex ids
//! they share. Output: whether the two closed triangles meet anywhere but
//! in the convex hull of their shared vertices (SPEC section 1), decided
//! exactly.
//!
//! Every decision is a sign of [`orient3d`] or [`orient2d_axes`] on input
//! points, or an exact comparison of two coordinates; nothing is
//! constructed. Three cases, by the number of shared vertex ids:
//!
//! - none ([`faces_meet`]): the closed triangles must not meet at all, so
//!   touching at a point counts;
//! - one, `v` ([`vertex_faces_overlap`]): two convex sets that both hold
//!   `v` meet elsewhere exactly when their tangent cones at `v` share a
//!   ray, which the signs below decide;
//! - two, an edge `ab` ([`edge_faces`]): a fold, or two degenerate
//!   faces running on along the edge's line past the same end.
//!
//! A zero-area face (accepted by validation, with a warning) is the segment
//! or point its vertices span, and is tested as such.
//!
//! A plane side is taken as a coordinate comparison when a face lies in a
//! plane `x_k = c` (flat faces of CAD parts), and with [`orient3d`]
//! otherwise. The quick rejections (every vertex of one face strictly on
//! one side of the other's plane) look at filtered signs first
//! ([`crate::exact::orient_filter`]), so that an exactly zero sign (a
//! vertex in the other plane, common on CAD parts, and slow to prove) is
//! computed only when the other plane does not already decide; a projection onto the axes `(i, j)` is used only where the
//! points lie in one plane that projects one to one there, so it keeps
//! every orientation (up to one common sign).

use crate::exact::orient_filter::{orient2d_axes_filter, Filter};
use crate::exact::predicates::{is_degenerate_triangle, orient2d_axes, orient3d, Sign};

/// A position, exact as stored.
pub(crate) type P = [f64; 3];

/// Two coordinate axes to project on.
#[derive(Clone, Copy, Debug)]
pub(super) struct Axes(usize, usize);

const AXES: [Axes; 3] = [Axes(0, 1), Axes(1, 2), Axes(2, 0)];

impl Axes {
    /// The exact orientation of `(a, b, c)` projected on these axes: the
    /// floating-point filter's sign when its proven bound shows it
    /// ([`orient2d_axes_filter`], range-checked per call), else the exact
    /// predicate.
    #[inline]
    pub(super) fn o2(self, a: P, b: P, c: P) -> Sign {
        orient2d_axes_filter(a, b, c, self.0, self.1)
            .unwrap_or_else(|| orient2d_axes(a, b, c, self.0, self.1))
    }
}

/// The sign of `x - c`, exactly.
#[inline]
fn cmp_sign(x: f64, c: f64) -> Sign {
    Sign::of_cmp(x.partial_cmp(&c))
}

/// The axis `k` when the three points have the same `k` coordinate.
#[inline]
fn flat_axis(t: &[P; 3]) -> Option<usize> {
    (0..3).find(|&k| t[0][k] == t[1][k] && t[1][k] == t[2][k])
}

/// The side of `x` against a plane holding the triangle `t`: the plane
/// `x_k = c` when `t` lies in one, else `t`'s own plane (all zero when `t`
/// is degenerate and in no such plane). Exact; signs of different points
/// against one `t` are comparable (one common factor).
#[inline]
fn side(t: &[P; 3], flat: Option<usize>, x: P) -> Sign {
    match flat {
        Some(k) => cmp_sign(x[k], t[0][k]),
        None => orient3d(t[0], t[1], t[2], x),
    }
}

/// [`side`] when a filter or a comparison shows it.
#[inline]
fn side_filtered(f: Filter, t: &[P; 3], flat: Option<usize>, x: P) -> Option<Sign> {
    match flat {
        Some(k) => Some(cmp_sign(x[k], t[0][k])),
        None => f.orient3d(t[0], t[1], t[2], x),
    }
}

/// Whether every sign is the same non-zero sign.
#[inline]
fn one_strict_side(s: &[Sign]) -> bool {
    s[0] != Sign::Zero && s.iter().all(|&x| x == s[0])
}

/// [`one_strict_side`] of signs that are all known.
#[inline]
fn known_one_strict_side(s: &[Option<Sign>]) -> bool {
    s.iter().all(Option::is_some) && s[0] != Some(Sign::Zero) && s.iter().all(|&x| x == s[0])
}

/// The sides of `x` against `t`'s plane: the filtered ones, the others
/// exactly.
#[inline]
fn sides<const N: usize>(
    t: &[P; 3],
    flat: Option<usize>,
    x: [P; N],
    known: [Option<Sign>; N],
) -> [Sign; N] {
    std::array::from_fn(|i| known[i].unwrap_or_else(|| side(t, flat, x[i])))
}

/// Whether the signs hold both a positive and a negative one.
#[inline]
fn straddles(s: &[Sign]) -> bool {
    s.contains(&Sign::Positive) && s.contains(&Sign::Negative)
}

/// What the point set of a face is.
#[derive(Clone, Copy, Debug)]
enum Shape {
    /// Three equal positions.
    Point(P),
    /// Collinear positions, not all equal: the segment between the two
    /// extreme ones.
    Segment(P, P),
    /// A proper triangle, with axes it projects one to one on and its
    /// orientation there.
    Triangle([P; 3], Axes, Sign),
}

impl Shape {
    fn of(f: Filter, t: [P; 3]) -> Shape {
        if let Some(k) = flat_axis(&t) {
            // In the plane x_k = c: the projection on the other two axes
            // is an isometry of that plane.
            let ax = Axes((k + 1) % 3, (k + 2) % 3);
            let s = ax.o2(t[0], t[1], t[2]);
            if s != Sign::Zero {
                return Shape::Triangle(t, ax, s);
            }
        } else if let Some((ax, s)) = projection(f, t[0], t[1], t[2]) {
            return Shape::Triangle(t, ax, s);
        }
        // Collinear: order along an axis on which the points differ (the
        // order along the line).
        match (0..3).find(|&k| !(t[0][k] == t[1][k] && t[1][k] == t[2][k])) {
            None => Shape::Point(t[0]),
            Some(k) => {
                let lo = t
                    .iter()
                    .copied()
                    .fold(t[0], |m, p| if p[k] < m[k] { p } else { m });
                let hi = t
                    .iter()
                    .copied()
                    .fold(t[0], |m, p| if p[k] > m[k] { p } else { m });
                Shape::Segment(lo, hi)
            }
        }
    }
}

/// Axes on which `(a, b, c)` projects with non-zero area, and its
/// orientation there; `None` when the three points are collinear.
pub(super) fn projection(f: Filter, a: P, b: P, c: P) -> Option<(Axes, Sign)> {
    // Filtered first: an exactly zero orientation (a face standing on that
    // plane) is slow to prove.
    AXES.iter()
        .find_map(|&ax| f.orient2d_axes(a, b, c, ax.0, ax.1).map(|s| (ax, s)))
        .or_else(|| {
            AXES.iter().find_map(|&ax| {
                let s = ax.o2(a, b, c);
                (s != Sign::Zero).then_some((ax, s))
            })
        })
}

// ---------------------------------------------------------------------------
// In one plane, projected on axes that keep orientations.

/// `x` in the closed triangle `t` of orientation `s` (non-zero).
fn point_in_triangle_2d(ax: Axes, t: &[P; 3], s: Sign, x: P) -> bool {
    (0..3).all(|i| ax.o2(t[i], t[(i + 1) % 3], x) != s.flip())
}

/// The closed segment `xy` meets the closed triangle `t` (orientation `s`).
///
/// Two convex polygons are disjoint exactly when one lies strictly beyond
/// the line of an edge of the other (the Minkowski difference's edges are
/// parallel to theirs): a triangle edge with both ends outside, or the
/// segment's line with the triangle strictly on one side.
fn segment_meets_triangle_2d(ax: Axes, t: &[P; 3], s: Sign, x: P, y: P) -> bool {
    if x == y {
        return point_in_triangle_2d(ax, t, s, x);
    }
    let out = s.flip();
    for i in 0..3 {
        let (a, b) = (t[i], t[(i + 1) % 3]);
        if ax.o2(a, b, x) == out && ax.o2(a, b, y) == out {
            return false;
        }
    }
    let sides = [ax.o2(x, y, t[0]), ax.o2(x, y, t[1]), ax.o2(x, y, t[2])];
    !one_strict_side(&sides)
}

/// Two closed triangles of orientations `sp`, `sq` (non-zero) meet: no edge
/// of either has the other strictly beyond it.
fn triangles_meet_2d(ax: Axes, p: &[P; 3], sp: Sign, q: &[P; 3], sq: Sign) -> bool {
    let beyond = |t: &[P; 3], s: Sign, u: &[P; 3]| {
        (0..3).any(|i| {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            u.iter().all(|&x| ax.o2(a, b, x) == s.flip())
        })
    };
    !beyond(p, sp, q) && !beyond(q, sq, p)
}

/// The closed segments `xy` and `uw` (each with distinct ends) meet, for
/// four points in a plane that `ax` projects one to one, not all on one
/// line.
fn segments_meet_2d(ax: Axes, x: P, y: P, u: P, w: P) -> bool {
    let (d1, d2) = (ax.o2(x, y, u), ax.o2(x, y, w));
    if d1 == d2 && d1 != Sign::Zero {
        return false;
    }
    let (d3, d4) = (ax.o2(u, w, x), ax.o2(u, w, y));
    !(d3 == d4 && d3 != Sign::Zero)
}

/// The closed segments `xy` and `uw` (each with distinct ends) meet, for
/// four points in a plane that `ax` projects one to one, collinear or not:
/// apart when one segment's ends are strictly on one side of the other's
/// line, else (four points on one line) when their intervals along an axis
/// on which `x` and `y` differ (so it orders that line) are apart.
pub(super) fn closed_segments_meet_2d(ax: Axes, x: P, y: P, u: P, w: P) -> bool {
    let (d1, d2) = (ax.o2(x, y, u), ax.o2(x, y, w));
    if d1 != Sign::Zero || d2 != Sign::Zero {
        return segments_meet_2d(ax, x, y, u, w);
    }
    let k = axis_apart(x, y);
    let (lo, hi) = (x[k].min(y[k]), x[k].max(y[k]));
    !(u[k].max(w[k]) < lo || hi < u[k].min(w[k]))
}

/// A direction point `x` (not at `v`) lies in the closed wedge at `v`
/// spanned by `a` and `b`, of orientation `s` (non-zero, so the wedge is
/// narrower than a half-plane and is the meet of two closed half-planes).
fn ray_in_wedge_2d(ax: Axes, v: P, a: P, b: P, s: Sign, x: P) -> bool {
    ax.o2(v, a, x) != s.flip() && ax.o2(v, x, b) != s.flip()
}

// ---------------------------------------------------------------------------
// Along one line.

/// An axis on which two distinct points differ.
fn axis_apart(x: P, y: P) -> usize {
    (0..3).find(|&k| x[k] != y[k]).unwrap_or(0)
}

/// `z` on the closed segment `xy` (`x != y`).
fn on_segment(x: P, y: P, z: P) -> bool {
    if !is_degenerate_triangle(x, y, z) {
        return false;
    }
    let k = axis_apart(x, y);
    let (lo, hi) = if x[k] < y[k] {
        (x[k], y[k])
    } else {
        (y[k], x[k])
    };
    lo <= z[k] && z[k] <= hi
}

/// The rays from `v` through `u` and through `w` (both not at `v`) are one.
fn same_ray(v: P, u: P, w: P) -> bool {
    if !is_degenerate_triangle(v, u, w) {
        return false;
    }
    // Collinear: w - v = l (u - v) with l != 0; its sign on an axis where
    // u differs from v.
    let k = axis_apart(v, u);
    cmp_sign(u[k], v[k]) == cmp_sign(w[k], v[k])
}

// ---------------------------------------------------------------------------
// Faces with no shared vertex.

/// The closed line through `x` and `y`, crossing the plane of the proper
/// triangle `t` at one point, passes through `t` (the three orient3d of the
/// line with `t`'s edges are the in-plane orientations of the crossing
/// point with those edges, times one common non-zero factor).
fn line_meets_triangle(x: P, y: P, t: &[P; 3]) -> bool {
    let s = [
        orient3d(x, y, t[0], t[1]),
        orient3d(x, y, t[1], t[2]),
        orient3d(x, y, t[2], t[0]),
    ];
    !straddles(&s)
}

/// The closed point sets of two faces with no shared vertex id meet.
pub(crate) fn faces_meet(f: Filter, p: [P; 3], q: [P; 3]) -> bool {
    let (fp, fq) = (flat_axis(&p), flat_axis(&q));
    if let (Some(k), Some(l)) = (fp, fq) {
        if k == l {
            // Both in planes x_k = c: parallel, or one plane, where the
            // projection on the other two axes is an isometry.
            if p[0][k] != q[0][k] {
                return false;
            }
            let ax = Axes((k + 1) % 3, (k + 2) % 3);
            let (op, oq) = (ax.o2(p[0], p[1], p[2]), ax.o2(q[0], q[1], q[2]));
            if op != Sign::Zero && oq != Sign::Zero {
                return triangles_meet_2d(ax, &p, op, &q, oq);
            }
            return shapes_meet(f, Shape::of(f, p), Shape::of(f, q));
        }
    }
    if fp.is_none() && fq.is_some() {
        // Sides against a plane x_k = c first: comparisons.
        return faces_meet(f, q, p);
    }
    let fsq = q.map(|x| side_filtered(f, &p, fp, x));
    if known_one_strict_side(&fsq) {
        return false;
    }
    let fsp = p.map(|x| side_filtered(f, &q, fq, x));
    if known_one_strict_side(&fsp) {
        return false;
    }
    let (Shape::Triangle(_, ap, op), Shape::Triangle(_, aq, oq)) =
        (Shape::of(f, p), Shape::of(f, q))
    else {
        return shapes_meet(f, Shape::of(f, p), Shape::of(f, q));
    };
    // Before any exact side (a vertex in the other plane, as a vertex of a
    // coplanar neighbour often is on CAD parts, is slow to prove): faces
    // whose projections are apart are apart.
    if projections_apart(f, ap, &p, op, &q) {
        return false;
    }
    // Both proper, so the sides are against their planes; each exact side
    // is computed only once it decides something.
    let sq = sides(&p, fp, q, fsq);
    if one_strict_side(&sq) {
        return false;
    }
    if sq.iter().all(|&s| s == Sign::Zero) {
        let oq_in_ap = ap.o2(q[0], q[1], q[2]);
        return triangles_meet_2d(ap, &p, op, &q, oq_in_ap);
    }
    if !straddles(&sq) {
        // q meets p's plane in a vertex or an edge only.
        return touching_part_meets(&q, &sq, &p, ap, op);
    }
    let sp = sides(&q, fq, p, fsp);
    if one_strict_side(&sp) {
        return false;
    }
    if !straddles(&sp) {
        return touching_part_meets(&p, &sp, &q, aq, oq);
    }
    // Both cross the other's plane: the two triangles' cuts with the
    // planes' common line are intervals; they meet exactly when an end of
    // one lies in the other triangle, and every end is where an edge
    // crosses (or a vertex touches) the other plane.
    crossing_edges_meet(&q, &sq, &p) || crossing_edges_meet(&p, &sp, &q)
}

/// Whether the projections on `ax` of the proper triangle `p` (of
/// orientation `op` there) and of `q` are apart, shown by filtered signs:
/// `q` strictly beyond an edge of `p`, or (when `q` projects with a shown
/// orientation) `p` strictly beyond an edge of `q`. Two faces whose
/// projections are apart do not meet.
fn projections_apart(f: Filter, ax: Axes, p: &[P; 3], op: Sign, q: &[P; 3]) -> bool {
    let o2 = |a: P, b: P, c: P| f.orient2d_axes(a, b, c, ax.0, ax.1);
    let beyond = |t: &[P; 3], out: Sign, u: &[P; 3]| {
        (0..3).any(|i| {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            u.iter().all(|&x| o2(a, b, x) == Some(out))
        })
    };
    if beyond(p, op.flip(), q) {
        return true;
    }
    match o2(q[0], q[1], q[2]) {
        Some(oq) => beyond(q, oq.flip(), p),
        None => false,
    }
}

/// `t` touches the plane of the proper triangle `u` without crossing it
/// (`s`: its vertices' sides, some zero, none of opposite signs): its part
/// in that plane (a vertex or an edge) meets `u`.
fn touching_part_meets(t: &[P; 3], s: &[Sign; 3], u: &[P; 3], ax: Axes, o: Sign) -> bool {
    let mut on = [[0.0; 3]; 3];
    let mut n = 0;
    for i in 0..3 {
        if s[i] == Sign::Zero {
            on[n] = t[i];
            n += 1;
        }
    }
    match n {
        1 => point_in_triangle_2d(ax, u, o, on[0]),
        _ => segment_meets_triangle_2d(ax, u, o, on[0], on[1]),
    }
}

/// Some edge of `t` that crosses or touches the plane of the proper
/// triangle `u` (sides `s`, not all zero) does so inside `u`.
fn crossing_edges_meet(t: &[P; 3], s: &[Sign; 3], u: &[P; 3]) -> bool {
    (0..3).any(|i| {
        let j = (i + 1) % 3;
        let apart = s[i] == s[j] && s[i] != Sign::Zero;
        let in_plane = s[i] == Sign::Zero && s[j] == Sign::Zero;
        !apart && !in_plane && line_meets_triangle(t[i], t[j], u)
    })
}

/// Two shapes, at least one degenerate, meet (closed sets).
fn shapes_meet(f: Filter, a: Shape, b: Shape) -> bool {
    use Shape::*;
    match (a, b) {
        (Point(x), Point(y)) => x == y,
        (Point(x), Segment(u, w)) | (Segment(u, w), Point(x)) => on_segment(u, w, x),
        (Point(x), Triangle(t, ax, o)) | (Triangle(t, ax, o), Point(x)) => {
            orient3d(t[0], t[1], t[2], x) == Sign::Zero && point_in_triangle_2d(ax, &t, o, x)
        }
        (Segment(x, y), Segment(u, w)) => segments_meet_3d(f, x, y, u, w),
        (Segment(x, y), Triangle(t, ax, o)) | (Triangle(t, ax, o), Segment(x, y)) => {
            let (sx, sy) = (orient3d(t[0], t[1], t[2], x), orient3d(t[0], t[1], t[2], y));
            if sx == sy && sx != Sign::Zero {
                false
            } else if sx == Sign::Zero && sy == Sign::Zero {
                segment_meets_triangle_2d(ax, &t, o, x, y)
            } else {
                line_meets_triangle(x, y, &t)
            }
        }
        (Triangle(p, ..), Triangle(q, ..)) => {
            // Not reached from `faces_meet`, which decides two proper
            // triangles itself; kept total: two triangles meet exactly when
            // an edge of one meets the other.
            (0..3).any(|i| shapes_meet(f, Segment(p[i], p[(i + 1) % 3]), b))
                || (0..3).any(|i| shapes_meet(f, Segment(q[i], q[(i + 1) % 3]), a))
        }
    }
}

/// Two closed segments in space (each with distinct ends) meet.
fn segments_meet_3d(f: Filter, x: P, y: P, u: P, w: P) -> bool {
    if orient3d(x, y, u, w) != Sign::Zero {
        return false;
    }
    let (cu, cw) = (
        is_degenerate_triangle(x, y, u),
        is_degenerate_triangle(x, y, w),
    );
    if cu && cw {
        // All on one line: intervals along an axis where x and y differ.
        let k = axis_apart(x, y);
        let (a0, a1) = (x[k].min(y[k]), x[k].max(y[k]));
        let (b0, b1) = (u[k].min(w[k]), u[k].max(w[k]));
        return a0 <= b1 && b0 <= a1;
    }
    let third = if cu { w } else { u };
    match projection(f, x, y, third) {
        Some((ax, _)) => segments_meet_2d(ax, x, y, u, w),
        None => unreachable!("a non-collinear triple projects with non-zero area on some axes"),
    }
}

// ---------------------------------------------------------------------------
// Faces sharing one vertex.

/// Faces `(v, a, b)` and `(v, c, d)` sharing only the vertex `v` meet
/// somewhere else.
///
/// Both are convex and hold `v`, so they meet elsewhere exactly when their
/// tangent cones at `v` share a ray. For two proper triangles in different
/// planes, the second cone meets the first plane in one ray (towards `c`,
/// `d`, or the point `q` where the edge `cd` crosses it), which must lie in
/// the first wedge: `q` is on `b`'s side of the line `va` exactly when
/// `orient3d(v, a, c, q)` (a positive multiple of `orient3d(v, a, c, d)`)
/// is zero or has the sign of `orient3d(v, a, c, b)`, as the plane through
/// `v`, `a`, `c` cuts the first plane along that line. In one plane, two
/// wedges narrower than a half-plane share a ray exactly when one holds a
/// side of the other. A zero-area face's cone is the rays towards its
/// other vertices (none when they sit at `v`).
pub(crate) fn vertex_faces_overlap(f: Filter, v: P, a: P, b: P, c: P, d: P) -> bool {
    let (t1, t2) = ([v, a, b], [v, c, d]);
    let (f1, f2) = (flat_axis(&t1), flat_axis(&t2));
    if f1.is_none() && f2.is_some() {
        // Sides against a plane x_k = c first: comparisons.
        return vertex_faces_overlap(f, v, c, d, a, b);
    }
    let fcd = [side_filtered(f, &t1, f1, c), side_filtered(f, &t1, f1, d)];
    if known_one_strict_side(&fcd) {
        return false;
    }
    let fab = [side_filtered(f, &t2, f2, a), side_filtered(f, &t2, f2, b)];
    if known_one_strict_side(&fab) {
        return false;
    }
    // The exact sides of c and d (the rest does not need a and b's: they
    // served only to reject early).
    let [sc, sd] = sides(&t1, f1, [c, d], fcd);
    if sc == sd && sc != Sign::Zero {
        return false;
    }
    match (Shape::of(f, t1), Shape::of(f, t2)) {
        (Shape::Triangle(_, ax1, o1), Shape::Triangle(_, _, _)) => {
            let in_wedge1 = |x: P| ray_in_wedge_2d(ax1, v, a, b, o1, x);
            match (sc, sd) {
                (Sign::Zero, Sign::Zero) => {
                    let o2 = ax1.o2(v, c, d);
                    let in_wedge2 = |x: P| ray_in_wedge_2d(ax1, v, c, d, o2, x);
                    in_wedge1(c) || in_wedge1(d) || in_wedge2(a) || in_wedge2(b)
                }
                (Sign::Zero, _) => in_wedge1(c),
                (_, Sign::Zero) => in_wedge1(d),
                _ => {
                    let oa = orient3d(v, a, c, d);
                    let ob = orient3d(v, b, c, d);
                    (oa == Sign::Zero || oa == orient3d(v, a, c, b))
                        && (ob == Sign::Zero || ob == orient3d(v, b, c, a))
                }
            }
        }
        (s1, s2) => {
            let rays1: Vec<P> = [a, b].into_iter().filter(|&x| x != v).collect();
            let rays2: Vec<P> = [c, d].into_iter().filter(|&x| x != v).collect();
            match (s1, s2) {
                (Shape::Triangle(_, ax, o), _) => rays2
                    .iter()
                    .any(|&u| ray_in_triangle_cone(ax, o, v, a, b, u)),
                (_, Shape::Triangle(_, ax, o)) => rays1
                    .iter()
                    .any(|&u| ray_in_triangle_cone(ax, o, v, c, d, u)),
                _ => rays1
                    .iter()
                    .any(|&u| rays2.iter().any(|&w| same_ray(v, u, w))),
            }
        }
    }
}

/// The ray from `v` through `u` (not at `v`) lies in the tangent cone at
/// `v` of the proper triangle `(v, a, b)` (projected on `ax` with
/// orientation `o`).
fn ray_in_triangle_cone(ax: Axes, o: Sign, v: P, a: P, b: P, u: P) -> bool {
    orient3d(v, a, b, u) == Sign::Zero && ray_in_wedge_2d(ax, v, a, b, o, u)
}

// ---------------------------------------------------------------------------
// Faces sharing an edge.

/// How the two faces on an edge meet.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeOverlap {
    /// Only along the edge.
    Proper,
    /// Both proper triangles, in one plane, on the same side of the edge:
    /// a zero-thickness fold (reported as `Defect::Fold`).
    Fold,
    /// Both of zero area on the edge's line, running on past the same end
    /// of the edge (or, on an edge of zero length, along one ray).
    Collinear,
}

/// Faces `(a, b, c)` and `(b, a, d)` on the edge `ab`.
///
/// Two faces in different planes meet only along the line `ab`, where a
/// proper triangle holds exactly its edge; in one plane, two proper
/// triangles overlap when their third vertices are on the same side of the
/// edge. A zero-area face lies on the line `ab` (when `a` and `b` differ),
/// so it meets a proper neighbour only along the edge, and a zero-area
/// neighbour beyond the edge only if both run on past the same end.
///
/// Also whether the faces are *flat neighbours*: both proper, in one plane, facing the same way there (`c` and `d`
/// strictly on opposite sides of `ab`, so the two have the same
/// orientation in every projection).
pub(crate) fn edge_faces(f: Filter, a: P, b: P, c: P, d: P) -> (EdgeOverlap, bool) {
    // When (a, b, c) lies in a plane x_k = c0 and is degenerate, d off
    // that plane makes (a, b, d) proper, and the answer below is `Proper`
    // either way.
    let coplanar = match flat_axis(&[a, b, c]) {
        Some(k) => d[k] == a[k],
        None => {
            f.orient3d(a, b, c, d)
                .unwrap_or_else(|| orient3d(a, b, c, d))
                == Sign::Zero
        }
    };
    if !coplanar {
        return (EdgeOverlap::Proper, false);
    }
    match (projection(f, a, b, c), projection(f, a, b, d)) {
        // (a, b, d) proper: d is off the line ab, on one side.
        (Some((ax, s)), Some(_)) => {
            if ax.o2(a, b, d) == s {
                (EdgeOverlap::Fold, false)
            } else {
                (EdgeOverlap::Proper, true)
            }
        }
        (Some(_), None) | (None, Some(_)) => (EdgeOverlap::Proper, false),
        (None, None) => {
            let overlap = if a != b {
                let k = axis_apart(a, b);
                let beyond = |x: P, from: P, to: P| {
                    cmp_sign(x[k], to[k]) == cmp_sign(to[k], from[k])
                        && cmp_sign(x[k], to[k]) != Sign::Zero
                };
                (beyond(c, a, b) && beyond(d, a, b)) || (beyond(c, b, a) && beyond(d, b, a))
            } else {
                c != a && d != a && same_ray(a, c, d)
            };
            let kind = if overlap {
                EdgeOverlap::Collinear
            } else {
                EdgeOverlap::Proper
            };
            (kind, false)
        }
    }
}
