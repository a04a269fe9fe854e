//! Input: a vertex and its fan (the faces around it, in surface order).
//! Output: the pairs of its faces that share only that vertex and meet
//! elsewhere.
//!
//! A fan that projects as a star (along some direction every face has the
//! same non-zero orientation, and the faces turn once around the vertex)
//! has none, and most fans do: two faces that are not neighbours in such a
//! fan project into wedges that share only the vertex, and a face projects
//! one to one, so the faces share only the vertex. Tried first along the
//! coordinate axis nearest the fan's float normal (exact orient2d and
//! coordinate comparisons), then along that normal itself (exact orient3d
//! against a point off the vertex: creases of CAD parts, where faces stand
//! on every coordinate plane). The direction is a heuristic, and so is
//! giving up on a direction where an orientation is too close to zero for
//! the floating-point filter to show its sign; every sign used is exact
//! ([`crate::exact::orient_filter`]), and any direction where the tests
//! pass proves the claim. Other fans (folded, wavy) test every pair with
//! [`vertex_faces_overlap`].

use super::narrow::{vertex_faces_overlap, P};
use super::{Found, Stop};
use crate::exact::orient_filter::Filter;
use crate::exact::predicates::Sign;
use crate::ids::{FaceId, VertexId};
use crate::mesh::topology::{FanEntry, Topology};
use crate::mesh::Mesh;

/// Adds the improper pairs among the faces of `v`'s fan that share no
/// edge, each counted on `stop`; once `stop` is reached, stops early (the
/// pairs added are then some of them).
#[inline(never)]
pub(super) fn fan_pairs(
    f: Filter,
    mesh: &Mesh,
    v: VertexId,
    fan: &[FanEntry],
    stop: &Stop,
    found: &mut Found,
) {
    let k = fan.len();
    if k < 4 || stop.reached() {
        // Every two faces of a fan of three share an edge.
        return;
    }
    let pv = mesh.pos(v);
    // The neighbours' positions, the first repeated at the end, on the
    // stack for ordinary fans.
    let mut small = [[0.0; 3]; 17];
    let mut large = Vec::new();
    let n: &[P] = if k < small.len() {
        for (slot, e) in small.iter_mut().zip(fan) {
            *slot = mesh.pos(e.neighbour);
        }
        small[k] = small[0];
        &small[..=k]
    } else {
        large.extend(fan.iter().map(|e| mesh.pos(e.neighbour)));
        large.push(large[0]);
        &large
    };
    let normal = float_normal(pv, n);
    if is_axis_star(f, pv, n, &normal) || is_star_along(f, pv, n, &normal) {
        return;
    }
    for i in 0..k {
        if stop.reached() {
            return;
        }
        for j in i + 2..k {
            if i == 0 && j == k - 1 {
                continue; // neighbours across the cycle's seam
            }
            if vertex_faces_overlap(f, pv, n[i], n[i + 1], n[j], n[j + 1]) {
                stop.count();
                found.push(fan[i].face, fan[j].face);
            }
        }
    }
}

/// A face after another in the input that shares one vertex with it: the
/// later face, the vertex, and the two faces' places in its fan.
#[derive(Clone, Copy, Debug)]
pub(super) struct AtVertex {
    pub(super) face: FaceId,
    v: VertexId,
    i: usize,
    j: usize,
}

/// Adds to `out` the faces after `a` in the input that share exactly one
/// vertex with it (those [`fan_pairs`] would test with `a`, or show apart
/// by a star), in no particular order.
pub(super) fn later_partners(mesh: &Mesh, topo: &Topology, a: FaceId, out: &mut Vec<AtVertex>) {
    for v in mesh.faces[a.idx()] {
        let fan = topo.fan(v);
        let k = fan.len();
        let Some(i) = fan.iter().position(|e| e.face == a) else {
            continue;
        };
        for (j, e) in fan.iter().enumerate() {
            let neighbours = j == i || (j + 1) % k == i || (i + 1) % k == j;
            if !neighbours && e.face > a {
                out.push(AtVertex {
                    face: e.face,
                    v,
                    i,
                    j,
                });
            }
        }
    }
}

/// Whether the two faces of `p` meet beyond their shared vertex.
pub(super) fn meet(f: Filter, mesh: &Mesh, topo: &Topology, p: &AtVertex) -> bool {
    let fan = topo.fan(p.v);
    let n = |k: usize| mesh.pos(fan[k % fan.len()].neighbour);
    // In fan order, as `fan_pairs` asks.
    let (i, j) = (p.i.min(p.j), p.i.max(p.j));
    vertex_faces_overlap(f, mesh.pos(p.v), n(i), n(i + 1), n(j), n(j + 1))
}

/// The sum of the faces' cross products, in floating point (a heuristic
/// direction).
fn float_normal(v: P, n: &[P]) -> [f64; 3] {
    let mut normal = [0.0f64; 3];
    for w in n.windows(2) {
        let (a, b) = (w[0], w[1]);
        let u = [a[0] - v[0], a[1] - v[1], a[2] - v[2]];
        let w = [b[0] - v[0], b[1] - v[1], b[2] - v[2]];
        normal[0] += u[1] * w[2] - u[2] * w[1];
        normal[1] += u[2] * w[0] - u[0] * w[2];
        normal[2] += u[0] * w[1] - u[1] * w[0];
    }
    normal
}

/// Whether the faces `(v, n_i, n_{i+1})` project on the coordinate plane
/// facing `normal` most with one non-zero orientation, turning once around
/// `v`.
///
/// Turning once: with every face's angle at `v` in `(0, pi)`, the angles
/// sum to `2 pi w`, where `w` counts the faces whose wedge passes the ray
/// from `v` along the first projected axis. With the half-open halves
/// "upper" (`y > v_y`, or `y = v_y` and `x > v_x`) and "lower" (the rest), a
/// counter-clockwise wedge passes that ray exactly when it runs from lower
/// to upper (clockwise: from upper to lower), which coordinate comparisons
/// decide.
fn is_axis_star(f: Filter, v: P, n: &[P], normal: &[f64; 3]) -> bool {
    let axis = (0..3)
        .max_by(|&p, &q| normal[p].abs().total_cmp(&normal[q].abs()))
        .unwrap_or(2);
    let (x, y) = ((axis + 1) % 3, (axis + 2) % 3);
    let orient = |a: P, b: P| f.orient2d_axes(v, a, b, x, y);
    let Some(s) = orient(n[0], n[1]) else {
        return false;
    };
    if n.windows(2).skip(1).any(|w| orient(w[0], w[1]) != Some(s)) {
        return false;
    }
    let upper = |p: &P| p[y] > v[y] || (p[y] == v[y] && p[x] > v[x]);
    let passes = n
        .windows(2)
        .filter(|w| {
            let (from, to) = (upper(&w[0]), upper(&w[1]));
            match s {
                Sign::Positive => !from && to,
                _ => from && !to,
            }
        })
        .count();
    passes == 1
}

/// Whether the faces project along `v -> p` (`p` near `v + normal`, a
/// double, so the direction is exact) with one non-zero orientation,
/// turning once around `v`. Projected along `p - v`, the orientation of
/// `(v, a, b)` is the sign of `orient3d(v, a, b, p)`.
///
/// Turning once, with every angle in `(0, pi)`: the direction of `n_0`
/// lies in the half-open wedge `[n_0, n_1)` and must lie in no other
/// `[n_i, n_{i+1})`, `0 < i < k - 1` (the last one, `[n_{k-1}, n_0)`,
/// leaves it out): lying there is `orient(n_i, n_0) >= 0` and
/// `orient(n_0, n_{i+1}) > 0` (the second excludes the ray opposite
/// `n_i`, on which the first is zero too), with orientations relative to
/// the faces' common sign.
fn is_star_along(f: Filter, v: P, n: &[P], normal: &[f64; 3]) -> bool {
    // Scale the normal to the fan's size, so that v + normal is a point
    // clearly off v.
    let reach = n
        .iter()
        .map(|a| (0..3).map(|k| (a[k] - v[k]).abs()).fold(0.0, f64::max))
        .fold(0.0, f64::max);
    let size = normal.iter().map(|x| x.abs()).fold(0.0, f64::max);
    if !(size > 0.0 && size.is_finite() && reach.is_finite()) {
        return false;
    }
    // p is not a mesh point: the filter is extended to it.
    let p: P = std::array::from_fn(|k| v[k] + normal[k] / size * reach);
    if !p.iter().all(|x| x.is_finite()) || p == v {
        return false;
    }
    let f = f.with(&[p]);
    let orient = |a: P, b: P| f.orient3d(v, a, b, p);
    let Some(s) = orient(n[0], n[1]) else {
        return false;
    };
    if n.windows(2).skip(1).any(|w| orient(w[0], w[1]) != Some(s)) {
        return false;
    }
    // An unknown sign (a filtered zero or near zero) counts as possibly
    // putting n_0 in that wedge: the test then fails.
    // The last wedge, [n_{k-1}, n_0), leaves n_0's own ray out.
    let first = n[0];
    let possibly = |x: Option<Sign>| x.is_none() || x == Some(s);
    let inner = &n[1..n.len() - 1];
    !inner
        .windows(2)
        .any(|w| possibly(orient(w[0], first)) && possibly(orient(first, w[1])))
}
