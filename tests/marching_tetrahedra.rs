//! Isosurfaces as scan segmentation and implicit modelling make them (the
//! medical class): a field sampled on a voxel grid of decimal spacing, its
//! zero set extracted tetrahedron by tetrahedron (every cube split along
//! its main diagonal into six, so neighbouring cubes share their faces'
//! diagonals and the surface is closed). Every vertex lies on a grid edge:
//! on an edge in a grid plane `z = z0 + k h` its height is that plane's,
//! so hundreds of vertices share each voxel plane, and slicing there is
//! degenerate everywhere at once (vertices on the plane by the hundred,
//! edges along it, ridges and saddles where the surface turns).
//!
//! Held out before (scikit-image's marching cubes, `bench/RESULTS.md`),
//! made here so that it stays in the suite: `f64` positions as computed
//! (decimal spacings, origins away from zero) and the same rounded to
//! `f32` as STL exporters store them. At every voxel plane the vertices
//! lie on: the exact invariants of SPEC 7 (`check_level_invariants`), the
//! verifier on the exact JSON, the z- and x-mirrors, the relabelling,
//! quarter turn, far move and scales, and the neighbouring regular levels
//! (`datasets::cross_check`).

use std::collections::HashMap;
use wmslice::datasets::cross_check;
use wmslice::exact::rational::{rat_from_f64, Rat};
use wmslice::levelset::check::check_level_invariants;
use wmslice::output::json::{to_json, Exactness, MeshHeader};
use wmslice::{Mesh, Slicer};

/// The six tetrahedra of a unit cube around its diagonal from corner 0 to
/// corner 7 (corner `c` at offset `(c & 1, c >> 1 & 1, c >> 2 & 1)`).
const TETS: [[usize; 4]; 6] = [
    [0, 1, 3, 7],
    [0, 1, 5, 7],
    [0, 2, 3, 7],
    [0, 2, 6, 7],
    [0, 4, 5, 7],
    [0, 4, 6, 7],
];

/// The even permutations of `0..4` (the orientation-keeping relabellings
/// of a tetrahedron).
fn even_permutations() -> Vec<[usize; 4]> {
    let mut out = Vec::new();
    for a in 0..4 {
        for b in 0..4 {
            for c in 0..4 {
                for d in 0..4 {
                    let p = [a, b, c, d];
                    let distinct = (0..4).all(|i| (0..i).all(|j| p[i] != p[j]));
                    let inversions = (0..4)
                        .flat_map(|i| (i + 1..4).map(move |j| (i, j)))
                        .filter(|&(i, j)| p[i] > p[j])
                        .count();
                    if distinct && inversions % 2 == 0 {
                        out.push(p);
                    }
                }
            }
        }
    }
    out
}

/// The sign of the volume of four integer grid points (exact).
fn orientation(p: [[i64; 3]; 4]) -> i64 {
    let d = |k: usize| [0, 1, 2].map(|i| p[k][i] - p[0][i]);
    let (u, v, w) = (d(1), d(2), d(3));
    let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
        + u[2] * (v[0] * w[1] - v[1] * w[0]);
    det.signum()
}

/// The zero set of `field` (negative inside) on an `n`^3 grid of spacing
/// `h` from `origin`, its faces turned outward; positions rounded by
/// `round` (to `f32` or not). Every face's orientation follows from its
/// tetrahedron's (exact, on grid indices), not from a float normal.
fn isosurface(
    field: impl Fn([f64; 3]) -> f64,
    n: i64,
    h: f64,
    origin: [f64; 3],
    round: fn(f64) -> f64,
) -> Mesh {
    let at = |g: [i64; 3]| [0, 1, 2].map(|i| origin[i] + g[i] as f64 * h);
    // Outside on the grid's border, so the surface closes; never zero on
    // a grid point, so no vertex sits on one.
    let value = |g: [i64; 3]| {
        if g.iter().any(|&c| c == 0 || c == n - 1) {
            1.0
        } else {
            let f = field(at(g));
            if f == 0.0 {
                1e-9
            } else {
                f
            }
        }
    };
    let evens = even_permutations();
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut on_edge: HashMap<([i64; 3], [i64; 3]), u32> = HashMap::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let mut vertex = |a: [i64; 3], b: [i64; 3]| -> u32 {
        let key = if a < b { (a, b) } else { (b, a) };
        *on_edge.entry(key).or_insert_with(|| {
            let (fa, fb) = (value(key.0), value(key.1));
            let t = fa / (fa - fb);
            let (pa, pb) = (at(key.0), at(key.1));
            positions.push([0, 1, 2].map(|i| round(pa[i] + t * (pb[i] - pa[i]))));
            (positions.len() - 1) as u32
        })
    };
    for x in 0..n - 1 {
        for y in 0..n - 1 {
            for z in 0..n - 1 {
                let corner = |c: usize| {
                    [
                        x + (c & 1) as i64,
                        y + (c >> 1 & 1) as i64,
                        z + (c >> 2 & 1) as i64,
                    ]
                };
                for tet in TETS {
                    let mut g = tet.map(corner);
                    if orientation(g) < 0 {
                        g.swap(2, 3);
                    }
                    let inside = g.map(|p| value(p) < 0.0);
                    let count = inside.iter().filter(|&&b| b).count();
                    match count {
                        1 | 3 => {
                            // The lone vertex i, with (i, j, k, l) even: the
                            // triangle on its edges faces away from it.
                            let lone = (0..4).find(|&i| inside[i] == (count == 1)).unwrap();
                            let [i, j, k, l] = *evens.iter().find(|p| p[0] == lone).unwrap();
                            let t = [vertex(g[i], g[j]), vertex(g[i], g[k]), vertex(g[i], g[l])];
                            // Outward: away from the lone vertex when it is
                            // the inside one, towards it otherwise.
                            faces.push(if count == 1 { t } else { [t[0], t[2], t[1]] });
                        }
                        2 => {
                            // (i, j, k, l) even with i, j inside: the quad
                            // (ik, il, jl, jk) faces from {i, j} to {k, l}.
                            let [i, j, k, l] =
                                *evens.iter().find(|p| inside[p[0]] && inside[p[1]]).unwrap();
                            let q = [
                                vertex(g[i], g[k]),
                                vertex(g[i], g[l]),
                                vertex(g[j], g[l]),
                                vertex(g[j], g[k]),
                            ];
                            faces.push([q[0], q[1], q[2]]);
                            faces.push([q[0], q[2], q[3]]);
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    Mesh::from_raw(positions, faces)
}

/// A field, negative inside.
type Field = fn([f64; 3]) -> f64;

fn torus([x, y, z]: [f64; 3]) -> f64 {
    let r = (x * x + y * y).sqrt() - 0.8;
    r * r + z * z - 0.09
}

fn two_balls([x, y, z]: [f64; 3]) -> f64 {
    let a = x * x + y * y + (z - 0.35) * (z - 0.35) - 0.25;
    let b = (x - 0.2) * (x - 0.2) + y * y + (z + 0.4) * (z + 0.4) - 0.3025;
    a.min(b)
}

fn as_f32(v: f64) -> f64 {
    v as f32 as f64
}

fn as_is(v: f64) -> f64 {
    v
}

/// The heights at least `min` vertices share, ascending (the voxel planes).
fn shared_heights(mesh: &Mesh, min: usize) -> Vec<f64> {
    let mut count: HashMap<u64, usize> = HashMap::new();
    for p in &mesh.positions {
        *count.entry(p[2].to_bits()).or_default() += 1;
    }
    let mut zs: Vec<f64> = count
        .into_iter()
        .filter(|&(_, c)| c >= min)
        .map(|(z, _)| f64::from_bits(z))
        .collect();
    zs.sort_by(f64::total_cmp);
    zs
}

fn check(name: &str, mesh: &Mesh) {
    let slicer = Slicer::new(mesh).unwrap_or_else(|e| panic!("{name}: refused: {e}"));
    let planes = shared_heights(mesh, 8);
    assert!(
        planes.len() >= 6,
        "{name}: the voxel planes hold many vertices each ({} planes)",
        planes.len()
    );
    let levels: Vec<Rat> = planes.iter().map(|&z| rat_from_f64(z)).collect();
    let mut sets = Vec::new();
    let mut limits_differ = 0;
    for c in &levels {
        let ls = slicer
            .slice_at(c)
            .unwrap_or_else(|e| panic!("{name} at {c}: {e}"));
        check_level_invariants(mesh, slicer.topology(), &ls)
            .unwrap_or_else(|e| panic!("{name} at {c}: SPEC 7: {e}"));
        limits_differ += usize::from(ls.below.len() != ls.above.len() || !ls.saddles.is_empty());
        sets.push(ls);
    }
    let text = to_json(&MeshHeader::new(mesh, None), &sets, Exactness::WithExact);
    let report = wmslice::verify::verify(mesh, None, &text).unwrap();
    assert!(report.passed(), "{name}: {report:?}");
    cross_check::check_mirror(mesh, &levels).unwrap_or_else(|e| panic!("{name}: z-mirror: {e}"));
    cross_check::check_x_mirror(mesh, &levels).unwrap_or_else(|e| panic!("{name}: x-mirror: {e}"));
    cross_check::check_all_neighbours(&slicer, &levels)
        .unwrap_or_else(|e| panic!("{name}: neighbouring levels: {e}"));
    cross_check::check_transformed(&slicer, &levels)
        .unwrap_or_else(|e| panic!("{name}: transformed: {e}"));
    eprintln!(
        "{name}: {} faces, {} voxel planes, {limits_differ} with L- and L+ differing or saddles",
        mesh.num_faces(),
        levels.len()
    );
}

#[test]
fn isosurfaces_sliced_at_their_voxel_planes_agree_with_every_cross_check() {
    let cases: [(&str, Field, i64, f64, [f64; 3]); 3] = [
        ("torus", torus, 16, 0.2, [12.3, -4.5, 100.0]),
        ("two balls", two_balls, 15, 0.25, [-1.7, -1.75, -1.65]),
        ("torus, coarse", torus, 13, 0.3, [-1.75, -1.8, 0.1]),
    ];
    for (name, field, n, h, origin) in cases {
        // The field is centred on the grid, wherever the grid lies.
        let mid = [0, 1, 2].map(|i| origin[i] + (n - 1) as f64 * h / 2.0);
        let centred = move |p: [f64; 3]| field([0, 1, 2].map(|i| p[i] - mid[i]));
        for (kind, round) in [("f64", as_is as fn(f64) -> f64), ("f32", as_f32)] {
            let mesh = isosurface(centred, n, h, origin, round);
            check(&format!("{name} ({kind}, h = {h})"), &mesh);
        }
    }
}
