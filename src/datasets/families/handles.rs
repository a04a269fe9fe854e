//! Input: a seeded stream. Output: a row of one to three bodies of genus
//! one or more, side by side: tori (scaled revolutions of a polygonal
//! profile around a polygonal ring, lying with a vertical axis or upright
//! with a horizontal one) and arches (a base with pillars and a bridge,
//! a handle of voxels). All coordinates are small integers and the
//! bodies are shifted up by 0, 1 or 2, so critical heights of different
//! bodies coincide: ridge and valley rings, flat annuli, tube equators
//! of in-plane edges, ordinary saddles at the top and bottom of a hole,
//! at one level.
//!
//! Each body is closed and embedded (a torus: the surface `{p :
//! (gauge_ring(p), p_axis) in boundary(profile)}` for a simple profile
//! away from the axis, see [`crate::datasets::build::Builder::sweep`]; an
//! arch: a well-composed voxel set, see [`super::voxels`]); the bodies'
//! bounding boxes are disjoint along x, so the mesh cannot self-intersect.

use super::grid::lines;
use super::rng::Rng;
use super::voxels::Voxels;
use crate::datasets::build::{Builder, P3, X, Y, Z};
use crate::datasets::shapes::OCTAGON;
use crate::mesh::Mesh;

/// Ring polygons, counter-clockwise about the axis.
const RINGS: [&[[f64; 2]]; 4] = [
    &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
    &[[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]],
    &OCTAGON,
    &[
        [2.0, 0.0],
        [1.0, 2.0],
        [-1.0, 2.0],
        [-2.0, 0.0],
        [-1.0, -2.0],
        [1.0, -2.0],
    ],
];

/// Profile polygons `(s, t)`, counter-clockwise, `s >= 0` (shifted away
/// from the axis before use): flat top and bottom, a diamond (ridge and
/// valley rings), a triangle (flat bottom, ridge ring), a trapezoid, a
/// hexagon.
const PROFILES: [&[[f64; 2]]; 5] = [
    &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
    &[[1.0, 0.0], [2.0, 1.0], [1.0, 2.0], [0.0, 1.0]],
    &[[0.0, 0.0], [2.0, 0.0], [1.0, 2.0]],
    &[[0.0, 0.0], [3.0, 0.0], [2.0, 1.0], [1.0, 1.0]],
    &[
        [1.0, 0.0],
        [2.0, 0.0],
        [3.0, 1.0],
        [2.0, 2.0],
        [1.0, 2.0],
        [0.0, 1.0],
    ],
];

/// Right-handed frames `(U, W, A)`: lying (axis z), upright (axis x or y).
const FRAMES: [[P3; 3]; 3] = [[X, Y, Z], [Y, Z, X], [Z, X, Y]];

/// A random torus.
fn torus(rng: &mut Rng) -> Mesh {
    let ring = *rng.pick(&RINGS);
    let s0 = rng.range(1, 2) as f64;
    let t0 = rng.range(0, 1) as f64;
    let profile: Vec<[f64; 2]> = rng
        .pick(&PROFILES)
        .iter()
        .map(|&[s, t]| [s + s0, t + t0])
        .collect();
    let frame = *rng.pick(&FRAMES);
    let mut b = Builder::new();
    b.sweep(ring, &profile, true, frame);
    b.finish()
}

/// A random arch: a base slab with two or three pillars and a bridge over
/// them (genus one or two), on non-uniform integer grid lines.
fn arch(rng: &mut Rng) -> Mesh {
    let pillars = rng.size(2, 3);
    let nx = 2 * pillars - 1;
    let wide = rng.below(2) == 0;
    let ny = if wide { 3 } else { 1 };
    let mid = ny / 2;
    let mut v = Voxels::new([nx, ny, 3]);
    v.fill([0, 0, 0], [nx, ny, 1], true);
    for p in 0..pillars {
        v.set([2 * p, mid, 1], true);
    }
    v.fill([0, mid, 2], [nx, mid + 1, 3], true);
    debug_assert!(v.is_well_composed() && v.is_connected());
    let xs = lines(rng, nx, 0, 1, 2);
    let ys = lines(rng, ny, 0, 1, 2);
    let zs = lines(rng, 3, 0, 1, 2);
    v.mesh(&xs, &ys, &zs)
}

/// Appends `part` to `out`, shifted so that its smallest x is `x0` and by
/// `dz` up; returns its largest x after the shift.
fn place(out: &mut Mesh, part: Mesh, x0: f64, dz: f64) -> f64 {
    let min_x = part
        .positions
        .iter()
        .map(|p| p[0])
        .fold(f64::INFINITY, f64::min);
    let dx = x0 - min_x;
    let base = out.positions.len() as u32;
    let mut max_x = x0;
    for p in &part.positions {
        let q = [p[0] + dx, p[1], p[2] + dz];
        max_x = max_x.max(q[0]);
        out.positions.push(q);
    }
    for f in &part.faces {
        out.faces.push(f.map(|v| crate::ids::VertexId(v.0 + base)));
    }
    max_x
}

/// One random row of tori and arches.
pub(super) fn build(rng: &mut Rng) -> Mesh {
    let mut out = Mesh::default();
    let mut x = 0.0;
    let count = rng.size(1, 3);
    for k in 0..count {
        // The first body is a torus, so every mesh has one.
        let part = if k == 0 || rng.below(3) != 0 {
            torus(rng)
        } else {
            arch(rng)
        };
        let dz = rng.range(0, 2) as f64;
        x = place(&mut out, part, x, dz) + rng.range(1, 2) as f64;
    }
    out
}
