//! Input: nothing. Output: one [`Mesh`] per built-in dataset.
//!
//! Every coordinate is an integer or a dyadic rational with |x| < 2^20, so
//! every intended degeneracy is exact. Each function states the construction,
//! its exact volume and its Euler characteristic; `DATASETS.md` and
//! [`super::expected`] derive the level sets by hand from these comments.

use super::build::{Builder, P3, X, Y, Z};
use crate::mesh::Mesh;

/// The octagon used as a ring by the cylinders and the lying torus:
/// counter-clockwise, area 14 (the square `[-2, 2]^2` minus four corner
/// triangles of area 1/2); `s * OCTAGON` has area `14 s^2`.
pub(crate) const OCTAGON: [[f64; 2]; 8] = [
    [2.0, -1.0],
    [2.0, 1.0],
    [1.0, 2.0],
    [-1.0, 2.0],
    [-2.0, 1.0],
    [-2.0, -1.0],
    [-1.0, -2.0],
    [1.0, -2.0],
];

/// The square `[-1, 1]^2`, counter-clockwise, area 4.
const SQUARE: [[f64; 2]; 4] = [[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]];

/// The diamond `|u| + |w| <= 1`, counter-clockwise, area 2.
const DIAMOND: [[f64; 2]; 4] = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];

/// The tube cross-section shared by the lying torus and the internal torus's
/// cavity, in `(s, z)`, counter-clockwise: inner equator `(1, 0)`, bottom
/// `(2, -1)`, outer equator `(3, 1)`, top `(2, 2)`. Area 3, centroid `s = 2`
/// (both triangles cut by the inner-outer diagonal have centroid `s = 2`).
/// At height `z` its `s`-range is `[a(z), b(z)]` with
/// `a = 1 - z` (z <= 0), `a = 1 + z/2` (z >= 0),
/// `b = (z + 5)/2` (z <= 1), `b = 4 - z` (z >= 1).
const KITE: [[f64; 2]; 4] = [[1.0, 0.0], [2.0, -1.0], [3.0, 1.0], [2.0, 2.0]];

/// `[0, 1]^3`. V = 8, F = 12, volume 1, chi = 2.
pub(crate) fn unit_cube() -> Mesh {
    let mut b = Builder::new();
    b.voxels(&[0.0, 1.0], &[0.0, 1.0], &[0.0, 1.0], |_, _, _| true);
    b.finish()
}

/// Vertices `(+-1, 0, 0), (0, +-1, 0), (0, 0, +-1)`. V = 6, F = 8,
/// volume 2 * (area 2 * height 1 / 3) = 4/3, chi = 2.
pub(crate) fn octahedron() -> Mesh {
    let mut b = Builder::new();
    b.sweep(
        &DIAMOND,
        &[[0.0, -1.0], [1.0, 0.0], [0.0, 1.0]],
        false,
        [X, Y, Z],
    );
    b.finish()
}

/// Base `[-1, 1]^2` at z = 0 (a fan of 4 triangles around `(0, 0, 0)`),
/// apex `(0, 0, 1)`. V = 6, F = 8, volume 4 * 1 / 3 = 4/3, chi = 2.
pub(crate) fn pyramid() -> Mesh {
    let mut b = Builder::new();
    b.sweep(
        &SQUARE,
        &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        false,
        [X, Y, Z],
    );
    b.finish()
}

/// Torus with a horizontal axis (y). Ring: the diamond `|x| + |z| <= 1`
/// (in the right-handed frame U = z, W = x, A = y); tube cross-section: the
/// diamond `|s - 2| + |y| <= 1`, i.e. `(s, y)` = (1, 0), (2, -1), (3, 0),
/// (2, 1). The solid is exactly `{ (|x| + |z|, y) in tube }`.
///
/// Vertex `(i, j)` is `s_j * ring_i + y_j * Y`, so its height is
/// `z = s_j * ring_i.z` with `ring_i.z` in {0, -1, 0, 1} and `s_j` in
/// {1, 2, 3, 2}: heights -3 (bottom, one vertex: minimum), -2 (two
/// vertices), -1 (one vertex, bottom of the hole), 0 (two whole tube
/// sections of 4 vertices each, at x = +-s), 1 (top of the hole), 2, 3
/// (top vertex `(0, 0, 3)`: maximum).
///
/// Saddles: the vertex `(0, 0, 1)` has its ring neighbours `(+-1, 0, 0)`
/// below and its tube neighbours `(0, +-1, 2)` above; the quad diagonals
/// add neighbours `(+-2, +-1, 0)` (below), each between a below and an above
/// neighbour, so the link reads below, above, below, above (4 sign
/// changes): an ordinary saddle. `(0, 0, -1)` is its mirror image.
///
/// V = 16, F = 32, chi = 0. Volume: for each y the slice
/// `{a(y) <= |x| + |z| <= b(y)}` has area `2 (b^2 - a^2)`, so the volume is
/// `int_tube 4 s ds dy = 4 * area 2 * centroid 2 = 16`.
pub(crate) fn upright_torus() -> Mesh {
    let mut b = Builder::new();
    // In (U, W) = (z, x): x = 1, z = -1 (bottom), x = -1, z = 1 (top).
    let ring = [[0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]];
    let tube = [[1.0, 0.0], [2.0, -1.0], [3.0, 0.0], [2.0, 1.0]];
    b.sweep(&ring, &tube, true, [Z, X, Y]);
    b.finish()
}

/// Torus with a vertical axis: ring [`OCTAGON`] (area 14), tube [`KITE`].
/// Height of vertex `(i, j)` is `z_j` in {0 (inner equator ring, s = 1),
/// -1 (bottom ring, s = 2), 1 (outer equator ring, s = 3), 2 (top ring,
/// s = 2)}: every ring of 8 vertices lies at one height.
///
/// The slice at height z is the octagonal annulus `a(z) <= gauge <= b(z)`
/// of area `14 (b^2 - a^2)`. V = 32, F = 64, chi = 0. Volume
/// `int_tube 2 * 14 * s ds dz = 28 * area 3 * centroid 2 = 168`.
pub(crate) fn lying_torus() -> Mesh {
    let mut b = Builder::new();
    b.sweep(&OCTAGON, &KITE, true, [X, Y, Z]);
    b.finish()
}

/// Genus-2 slab with a monkey saddle. Domain: the grid square cells of
/// `[-3, 3] x [-2, 2]` without the four cells of the two holes
/// `W = [-2, -1] x [-1, 1]` and `E = [1, 2] x [-1, 1]` (20 cells, area 20);
/// every cell `[i, i+1] x [j, j+1]` is split along `(i, j)-(i+1, j+1)`.
/// Bottom flat at z = 0. Top heights: 4 everywhere except
/// `v = (0, 0)` at 2 and the three low neighbours `(1, 1)`, `(-1, 0)`,
/// `(0, -1)` at 1.
///
/// Monkey saddle proof: with the diagonal direction (1, 1) the six faces
/// around `v` are `(v, (1,0), (1,1))`, `(v, (1,1), (0,1))`,
/// `(v, (0,1), (-1,0))`, `(v, (-1,0), (-1,-1))`, `(v, (-1,-1), (0,-1))`,
/// `(v, (0,-1), (1,0))`, so its link in order is
/// (1,0) (1,1) (0,1) (-1,0) (-1,-1) (0,-1) with heights 4 1 4 1 4 1,
/// i.e. signs + - + - + - relative to z(v) = 2: six sign changes, m = 3.
///
/// V = 2 * 35 = 70 (no grid point is interior to a hole), F = 40 top + 40
/// bottom + 2 * (20 outer + 12 hole) wall triangles = 144, E = 216, chi = -2.
/// Volume = 4 * 20 - deficit; each top triangle has area 1/2, so the
/// deficit is `(1/6) sum_v (4 - z_v) * (top triangles at v)`
/// = (2*6 + 3*6 + 3*5 + 3*3) / 6 = 9 (v has 6 triangles, (0,-1) 6, (1,1) 5,
/// (-1,0) 3): volume 71.
pub(crate) fn double_torus() -> Mesh {
    let hole = |i: i32, j: i32| (i == -2 || i == 1) && (j == -1 || j == 0);
    let height = |x: i32, y: i32| match (x, y) {
        (0, 0) => 2.0,
        (1, 1) | (-1, 0) | (0, -1) => 1.0,
        _ => 4.0,
    };
    let mut top: Vec<P3> = Vec::new();
    let id = |x: i32, y: i32| ((x + 3) * 5 + (y + 2)) as usize;
    for x in -3..=3 {
        for y in -2..=2 {
            top.push([f64::from(x), f64::from(y), height(x, y)]);
        }
    }
    let mut tris = Vec::new();
    for i in -3..3 {
        for j in -2..2 {
            if hole(i, j) {
                continue;
            }
            tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut b = Builder::new();
    b.slab(&top, &tris, 0.0);
    b.finish()
}

/// Height-field box over `[0, 3]^2`, bottom z = 0: the top is a 3 x 3 grid
/// of square pits. Grid points `(i, j)` are at z = 2, each cell centre
/// `(i + 1/2, j + 1/2)` at z = 1, and each cell is 4 triangles from its
/// sides to its centre (an inverted pyramid). Every grid edge of the top is
/// a ridge at z = 2 (both faces go down: a pit, or a pit and a wall); every
/// centre is an isolated minimum (pit) at z = 1.
///
/// V = 2 * (16 + 9) = 50, F = 36 + 36 + 2 * 12 = 96, chi = 2.
/// Volume = 3 * 3 * 2 - 9 pits * (1 * 1 / 3) = 15.
pub(crate) fn grid() -> Mesh {
    const N: usize = 3;
    let mut top: Vec<P3> = Vec::new();
    for i in 0..=N {
        for j in 0..=N {
            top.push([i as f64, j as f64, 2.0]);
        }
    }
    let g = |i: usize, j: usize| i * (N + 1) + j;
    let mut tris = Vec::new();
    for i in 0..N {
        for j in 0..N {
            let c = top.len();
            top.push([i as f64 + 0.5, j as f64 + 0.5, 1.0]);
            let corners = [g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1)];
            for k in 0..4 {
                tris.push([corners[k], corners[(k + 1) % 4], c]);
            }
        }
    }
    let mut b = Builder::new();
    b.slab(&top, &tris, 0.0);
    b.finish()
}

/// Octagonal prism: [`OCTAGON`] (area 14) from z = 0 to z = 2, each cap a
/// fan around its centre. V = 18, F = 32, chi = 2, volume 28.
pub(crate) fn cylinder() -> Mesh {
    let mut b = Builder::new();
    let profile = [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.0, 2.0]];
    b.sweep(&OCTAGON, &profile, false, [X, Y, Z]);
    b.finish()
}

/// Box `[-4, 4]^2 x [-2, 3]` (12 triangles) with a toroidal cavity: the
/// sweep of the square ring `[-1, 1]^2` (area 4) along the tube [`KITE`],
/// faces reversed so that the normals point out of the material, into the
/// cavity. Cavity rings: bottom (s = 2) at z = -1, inner equator (s = 1) at
/// z = 0, outer equator (s = 3) at z = 1, top (s = 2) at z = 2.
///
/// V = 8 + 16 = 24, F = 12 + 32 = 44, chi = 2 + 0.
/// Volume = 8 * 8 * 5 - int_tube 2 * 4 * s = 320 - 8 * 3 * 2 = 272.
pub(crate) fn internal_torus() -> Mesh {
    let mut b = Builder::new();
    b.voxels(&[-4.0, 4.0], &[-4.0, 4.0], &[-2.0, 3.0], |_, _, _| true);
    let start = b.face_count();
    b.sweep(&SQUARE, &KITE, true, [X, Y, Z]);
    b.reverse_from(start);
    b.finish()
}

/// Cube `[0, 4]^3` with two square pegs: `[4, 6] x [1, 3] x [1, 3]` on the
/// +x side (down-facing bottom at z = 1, up-facing top at z = 3) and
/// `[-2, 0] x [1, 3] x [3, 7/2]` on the -x side (down-facing bottom at
/// z = 3, up-facing top at z = 7/2). Built as boxes on the grid
/// x {-2, 0, 4, 6}, y {0, 1, 3, 4}, z {0, 1, 3, 7/2, 4}, so the cube's side
/// faces carry grid edges at every one of those heights.
///
/// F = 2 * 46 = 92, chi = 2. Volume 64 + 2 * 2 * 2 + 2 * 2 * 1/2 = 74.
pub(crate) fn peg_cube() -> Mesh {
    let mut b = Builder::new();
    b.voxels(
        &[-2.0, 0.0, 4.0, 6.0],
        &[0.0, 1.0, 3.0, 4.0],
        &[0.0, 1.0, 3.0, 3.5, 4.0],
        |i, j, k| i == 1 || (i == 2 && j == 1 && k == 1) || (i == 0 && j == 1 && k == 2),
    );
    b.finish()
}

/// [`OCTAGON`] prism from z = 0 to z = 2 (area 14), then a chamfer up to
/// the half-size octagon (area 14/4 = 7/2) at z = 3; caps are fans around
/// their centres. The ring at z = 2 is a loop of transversal mesh edges.
///
/// V = 26, F = 48, chi = 2. Volume 14 * 2 + int_0^1 14 (1 - t/2)^2 dt
/// = 28 + 14 * 7/12 = 217/6.
pub(crate) fn chamfered_cylinder() -> Mesh {
    let mut b = Builder::new();
    let profile = [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.5, 3.0], [0.0, 3.0]];
    b.sweep(&OCTAGON, &profile, false, [X, Y, Z]);
    b.finish()
}

/// Platform `[0, 6]^2 x [0, 1]` with four plateaus reaching z = 2 on the
/// grid x, y in {0, 1, 2, 3, 5, 6}: `[1, 2]^2` (area 1), `[1, 2] x [3, 5]`
/// (2), `[3, 5] x [1, 2]` (2), `[3, 5]^2` (4). At z = 2 there are four
/// separate up-facing flat regions of total area 9; at z = 1 one up-facing
/// region (area 36 - 9 = 27) with four holes.
///
/// F = 172, chi = 2. Volume 36 + 9 = 45.
pub(crate) fn platform_grid() -> Mesh {
    let xs = [0.0, 1.0, 2.0, 3.0, 5.0, 6.0];
    let mut b = Builder::new();
    b.voxels(&xs, &xs, &[0.0, 1.0, 2.0], |i, j, k| {
        k == 0 || (matches!(i, 1 | 3) && matches!(j, 1 | 3))
    });
    b.finish()
}

/// Box over `[-2, 2]^2`, bottom z = 0, whose top is 8 triangles around
/// `v = (0, 0, 2)`. Link of v, counter-clockwise: (2, 0, 3), (2, 2, 1),
/// (0, 2, 3), (-2, 2, 1), (-2, 0, 3), (-2, -2, 1), (0, -2, 3), (2, -2, 1):
/// heights 3 1 3 1 3 1 3 1 against z(v) = 2, signs + - + - + - + -, eight
/// sign changes: a saddle with 8 branches (m = 4). The four side midpoints
/// at z = 3 are maxima.
///
/// V = 18, F = 8 + 8 + 16 = 32, chi = 2. Volume: each top triangle has
/// area 2 and mean height (2 + 3 + 1) / 3 = 2, so 8 * 2 * 2 = 32.
pub(crate) fn saddle8() -> Mesh {
    let mut top: Vec<P3> = vec![[0.0, 0.0, 2.0]];
    let ring = [
        [2.0, 0.0],
        [2.0, 2.0],
        [0.0, 2.0],
        [-2.0, 2.0],
        [-2.0, 0.0],
        [-2.0, -2.0],
        [0.0, -2.0],
        [2.0, -2.0],
    ];
    for (k, p) in ring.iter().enumerate() {
        let z = if k % 2 == 0 { 3.0 } else { 1.0 };
        top.push([p[0], p[1], z]);
    }
    let tris: Vec<[usize; 3]> = (0..8).map(|k| [0, 1 + k, 1 + (k + 1) % 8]).collect();
    let mut b = Builder::new();
    b.slab(&top, &tris, 0.0);
    b.finish()
}
