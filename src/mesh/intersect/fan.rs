//! Input: a vertex and its fan (the faces around it, in surface order).
//! Output: the pairs of its faces that share only that vertex and meet
//! elsewhere.
//!
//! A fan that projects onto a coordinate plane as a star (every face with
//! the same non-zero orientation there, turning once around the vertex)
//! has none, and most fans of a tessellated surface do: two faces that are
//! not neighbours in such a fan project into wedges that share only the
//! vertex, and a face projects one to one, so the faces share only the
//! vertex. That takes one exact orient2d per face and coordinate
//! comparisons. Other fans (creases of CAD parts along coordinate planes,
//! wavy fans) test every pair with [`vertex_faces_overlap`].

use super::narrow::{vertex_faces_overlap, P};
use super::Found;
use crate::exact::predicates::{orient2d_axes, Sign};
use crate::ids::VertexId;
use crate::mesh::topology::FanEntry;
use crate::mesh::Mesh;

/// Adds the improper pairs among the faces of `v`'s fan that share no edge.
pub(super) fn fan_pairs(mesh: &Mesh, v: VertexId, fan: &[FanEntry], found: &mut Found) {
    let k = fan.len();
    if k < 4 {
        // Every two faces of a fan of three share an edge.
        return;
    }
    let pv = mesh.pos(v);
    let n: Vec<P> = fan.iter().map(|e| mesh.pos(e.neighbour)).collect();
    if is_star(pv, &n) {
        return;
    }
    for i in 0..k {
        for j in i + 2..k {
            if i == 0 && j == k - 1 {
                continue; // neighbours across the cycle's seam
            }
            let (a, b) = (n[i], n[(i + 1) % k]);
            let (c, d) = (n[j], n[(j + 1) % k]);
            if vertex_faces_overlap(pv, a, b, c, d) {
                found.push(fan[i].face, fan[j].face);
            }
        }
    }
}

/// Whether the faces `(v, n_i, n_{i+1})` project, on the coordinate plane
/// facing their summed float normal most, with one non-zero orientation and
/// turn once around `v`. The choice of plane is a heuristic (any plane
/// where the test passes proves the claim); the test is exact.
///
/// Turning once: with every face's angle at `v` in `(0, pi)`, the angles
/// sum to `2 pi w`, where `w` counts the faces whose wedge passes the ray
/// from `v` along the first projected axis. With the half-open halves
/// "upper" (`y > v_y`, or `y = v_y` and `x > v_x`) and "lower" (the rest), a
/// counter-clockwise wedge passes that ray exactly when it runs from lower
/// to upper (clockwise: from upper to lower), which coordinate comparisons
/// decide.
fn is_star(v: P, n: &[P]) -> bool {
    let k = n.len();
    let mut normal = [0.0f64; 3];
    for i in 0..k {
        let (a, b) = (n[i], n[(i + 1) % k]);
        let u = [a[0] - v[0], a[1] - v[1], a[2] - v[2]];
        let w = [b[0] - v[0], b[1] - v[1], b[2] - v[2]];
        normal[0] += u[1] * w[2] - u[2] * w[1];
        normal[1] += u[2] * w[0] - u[0] * w[2];
        normal[2] += u[0] * w[1] - u[1] * w[0];
    }
    let axis = (0..3)
        .max_by(|&p, &q| normal[p].abs().total_cmp(&normal[q].abs()))
        .unwrap_or(2);
    let (x, y) = ((axis + 1) % 3, (axis + 2) % 3);
    let s = orient2d_axes(v, n[0], n[1], x, y);
    if s == Sign::Zero {
        return false;
    }
    if (1..k).any(|i| orient2d_axes(v, n[i], n[(i + 1) % k], x, y) != s) {
        return false;
    }
    let upper = |p: &P| p[y] > v[y] || (p[y] == v[y] && p[x] > v[x]);
    let passes = (0..k)
        .filter(|&i| {
            let (from, to) = (upper(&n[i]), upper(&n[(i + 1) % k]));
            match s {
                Sign::Positive => !from && to,
                _ => from && !to,
            }
        })
        .count();
    passes == 1
}
