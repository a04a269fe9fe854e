//! Input: every built-in dataset, and random closed meshes: unions of
//! random slabs and boxes on small integer grids, moved so that they
//! overlap, touch (at a corner, along an edge, over an area) or stay
//! apart; the same with every coordinate rounded to `f32` after a random
//! scale, shift and jitter (centred at the origin).
//! Output: a pass when this crate's exact self-intersection test agrees
//! with CGAL's (`CGAL::Polygon_mesh_processing::does_self_intersect` and
//! `self_intersections` on an Epeck `Surface_mesh`, the `cgal-oracle`
//! feature): the same verdict, and the same face pairs.
//!
//! What each side counts (SPEC 1: two faces that meet anywhere but in the
//! vertices and edges they share). CGAL 5.5
//! (`Polygon_mesh_processing/self_intersections.h`, `do_faces_intersect`):
//! - faces on an edge intersect when coplanar with their opposite vertices
//!   on one side: exactly our fold ([`EdgeOverlap::Fold`]), which
//!   validation names as a fold rather than a self-intersection; both are
//!   refusals, and [`self_intersections`] lists the fold's two faces;
//! - faces on one vertex `v` intersect when the edge of one opposite `v`
//!   meets the other (closed sets). That is SPEC 1's notion for proper
//!   triangles: if `t1` and `t2` share `v` and meet elsewhere, their
//!   intersection (convex) has an extreme point `p != v`, on the boundary
//!   of both; if it lies on neither opposite edge it lies on an edge
//!   through `v` of each, so those edges overlap along a ray from `v` and
//!   `p` is the nearer of their far ends, say `t1`'s vertex `a`: then
//!   `a` is on `t1`'s opposite edge and in `t2`, which CGAL sees;
//! - other faces intersect when the closed triangles meet: touching counts
//!   on both sides (SPEC 1 allows meeting only in shared elements);
//! - a degenerate face `f` (collinear vertices) is reported as `(f, f)` and
//!   in no other pair (CGAL makes no box for it). Validation refuses such a
//!   face by name (`DegenerateFace`) and may also find it meeting other
//!   faces; so on meshes with degenerate faces the comparison is: CGAL's
//!   `(f, f)` are exactly the faces our exact test finds degenerate, and
//!   the pairs of non-degenerate faces agree.
#![cfg(feature = "cgal-oracle")]

mod common;
#[path = "../bench/meshgen.rs"]
#[allow(dead_code)]
mod meshgen;

use common::Slab;
use proptest::prelude::*;
use wmslice::exact::predicates::is_degenerate_triangle;
use wmslice::mesh::intersect::EdgeOverlap;
use wmslice::mesh::topology::Topology;
use wmslice::oracle::compare::compare_self_intersections as compare;
use wmslice::oracle::oracle_self_intersections;
use wmslice::{Mesh, VertexId};

/// Both meshes in one, the second's ids after the first's.
fn union(a: &Mesh, b: &Mesh) -> Mesh {
    let n = a.positions.len() as u32;
    let mut m = a.clone();
    m.positions.extend(&b.positions);
    m.faces
        .extend(b.faces.iter().map(|t| t.map(|v| VertexId(v.0 + n))));
    m
}

fn moved(m: &Mesh, d: [f64; 3]) -> Mesh {
    let mut m = m.clone();
    for p in &mut m.positions {
        *p = std::array::from_fn(|k| p[k] + d[k]);
    }
    m
}

/// The box `[lo, hi]` (12 faces, outward).
fn block(lo: [f64; 3], hi: [f64; 3]) -> Mesh {
    let p = |i: usize| {
        [
            if i & 1 == 0 { lo[0] } else { hi[0] },
            if i & 2 == 0 { lo[1] } else { hi[1] },
            if i & 4 == 0 { lo[2] } else { hi[2] },
        ]
    };
    let faces = vec![
        [0, 2, 3],
        [0, 3, 1], // z = lo
        [4, 5, 7],
        [4, 7, 6], // z = hi
        [0, 1, 5],
        [0, 5, 4], // y = lo
        [2, 6, 7],
        [2, 7, 3], // y = hi
        [0, 4, 6],
        [0, 6, 2], // x = lo
        [1, 3, 7],
        [1, 7, 5], // x = hi
    ];
    Mesh::from_raw((0..8).map(p).collect(), faces)
}

#[test]
fn the_oracle_refuses_what_is_not_a_closed_manifold() {
    let open = Mesh::from_raw(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    );
    assert!(oracle_self_intersections(&open).is_err());
}

/// A face naming a vertex the mesh does not have (tinyobjloader's
/// `invalid-relative-texture-index.obj`: one face, no vertex) or a
/// coordinate that is not finite has no edge tables to compare: nothing
/// to compare, not a panic in building them.
#[test]
fn faces_naming_missing_vertices_and_non_finite_coordinates_are_not_compared() {
    let no_vertices = Mesh::from_raw(vec![], vec![[0, 0, 0]]);
    assert_eq!(compare(&no_vertices), Ok(None));
    let mut tetra = Mesh::from_raw(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
    );
    assert_eq!(compare(&tetra), Ok(Some(false)));
    let beyond = Mesh::from_raw(tetra.positions.clone(), vec![[0, 2, 1], [0, 1, 9]]);
    assert_eq!(compare(&beyond), Ok(None));
    tetra.positions[3][2] = f64::NAN;
    assert_eq!(compare(&tetra), Ok(None));
}

#[test]
fn every_dataset_agrees_with_cgal() {
    let mut failures = Vec::new();
    let mut compared = 0;
    for d in wmslice::datasets::all() {
        match compare(&d.build()) {
            Ok(Some(_)) => compared += 1,
            Ok(None) => {}
            Err(e) => failures.push(format!("dataset {}: {e}", d.name)),
        }
    }
    println!("compared {compared} datasets with CGAL");
    assert!(compared >= 10, "only {compared} datasets compared");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Touching bodies, by hand: unit boxes meeting a unit box over a face's
/// area, along an edge, at a corner, and a vertex of a tetrahedron on the
/// interior of a face; each intersects (SPEC 1: the bodies' faces meet,
/// and share no element). Moved apart by the smallest step, none does.
#[test]
fn touching_bodies_intersect_on_both_sides_and_apart_ones_do_not() {
    let unit = block([0.0; 3], [1.0; 3]);
    let tetra = Mesh::from_raw(
        vec![
            [0.5, 0.5, 1.0],
            [0.0, 0.0, 2.0],
            [1.0, 0.0, 2.0],
            [0.0, 1.0, 2.0],
        ],
        // Apex down at the top face's interior point (1/2, 1/2, 1).
        vec![[0, 2, 1], [0, 3, 2], [0, 1, 3], [1, 2, 3]],
    );
    let step = 1.0f64.next_up() - 1.0;
    for (what, other, apart) in [
        ("face", moved(&unit, [1.0, 0.0, 0.0]), [step, 0.0, 0.0]),
        ("edge", moved(&unit, [1.0, 1.0, 0.0]), [step, 0.0, 0.0]),
        ("corner", moved(&unit, [1.0, 1.0, 1.0]), [0.0, 0.0, step]),
        ("half face", moved(&unit, [0.5, 0.5, 1.0]), [0.0, 0.0, step]),
        ("vertex on a face", tetra.clone(), [0.0, 0.0, step]),
    ] {
        let touching = union(&unit, &other);
        assert_eq!(compare(&touching), Ok(Some(true)), "{what}");
        let separate = union(&unit, &moved(&other, apart));
        assert_eq!(compare(&separate), Ok(Some(false)), "{what} apart");
    }
}

/// A triangle and its reverse beside a block: CGAL names the pair once,
/// as the list does (it once held the pair three times, once per folded
/// edge: a GEBCO terrain STL in pyvista's vtk-data).
#[test]
fn a_two_face_pillow_agrees_with_cgal() {
    let pillow = Mesh::from_raw(
        vec![[3., 0., 0.], [4., 0., 0.], [3., 1., 0.]],
        vec![[0, 1, 2], [0, 2, 1]],
    );
    let m = union(&block([0.0; 3], [1.0; 3]), &pillow);
    assert_eq!(compare(&m), Ok(Some(true)));
}

/// CAD-like stepped parts (`bench/meshgen.rs`: a hole, caps and 100 step
/// flats, each a flat ring of long radial faces whose pairs the search
/// skips once the ring is certified), in `f32` and turned `f64`, alone and
/// as two bodies: overlapping, touching along flats (moved one step up),
/// and apart. CGAL tests every pair its boxes pass.
#[test]
fn stepped_parts_agree_with_cgal() {
    for part in [meshgen::steps(8).to_mesh(), meshgen::steps_f64(8).to_mesh()] {
        assert_eq!(compare(&part), Ok(Some(false)));
        for (d, meets) in [
            ([0.5, 0.25, 0.0], true),
            ([0.0, 0.0, 1.25], true),
            ([100.0, 0.0, 0.0], false),
        ] {
            let two = union(&part, &moved(&part, d));
            assert_eq!(compare(&two), Ok(Some(meets)), "moved by {d:?}");
        }
    }
}

/// A small random slab moved by a grid offset.
fn placed_slab() -> impl Strategy<Value = (Slab, [i32; 3])> {
    (common::slab(), proptest::array::uniform3(-5i32..=5))
}

/// A box with integer corners in a small range.
fn small_block() -> impl Strategy<Value = Mesh> {
    (
        proptest::array::uniform3(-3i32..=3),
        proptest::array::uniform3(1i32..=3),
    )
        .prop_map(|(lo, size)| {
            let lo = lo.map(f64::from);
            block(lo, std::array::from_fn(|k| lo[k] + f64::from(size[k])))
        })
}

/// One to three bodies (slabs or boxes) in one mesh.
fn bodies() -> impl Strategy<Value = Mesh> {
    let body = prop_oneof![
        placed_slab().prop_map(|(s, d)| moved(&s.mesh(), d.map(f64::from))),
        small_block(),
    ];
    proptest::collection::vec(body, 1..=3).prop_map(|bs| {
        bs.iter()
            .skip(1)
            .fold(bs[0].clone(), |acc, b| union(&acc, b))
    })
}

/// `f32` coordinates: the mesh centred near the origin, each coordinate
/// jittered by up to `j` grid units, moved by `off` (then taken back
/// exactly: `off` a power of two, it only coarsens the rounding, to
/// `2^-22 off`), scaled by `2^e`, all in `f32` arithmetic.
fn to_f32(m: &Mesh, e: i32, jitter: &[f32], j: f32, off: f32) -> Mesh {
    let mut m = m.clone();
    let s = 2f64.powi(e) as f32;
    for (i, p) in m.positions.iter_mut().enumerate() {
        *p = std::array::from_fn(|k| {
            let r = jitter[(3 * i + k) % jitter.len()] * j;
            f64::from(((((p[k] - 0.5) as f32 + r) + off) - off) * s)
        });
    }
    m
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1500))]

    /// Integer grids: bodies overlapping, touching or apart (slab walls and
    /// box faces are often coplanar, so touching is common).
    #[test]
    fn grid_bodies_agree_with_cgal(m in bodies()) {
        let r = compare(&m);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }

    /// The same bodies with f32 coordinates centred at the origin, with and
    /// without jitter (rounding makes faces almost coplanar, almost
    /// touching, and now and then folded or degenerate).
    #[test]
    fn f32_bodies_agree_with_cgal(
        m in bodies(),
        e in -30i32..30,
        jitter in proptest::collection::vec(-1.0f32..1.0, 1..64),
        j in prop_oneof![Just(0.0f32), Just(1e-6f32), Just(0.01f32), Just(0.3f32)],
        off in prop_oneof![3 => Just(0.0f32), 1 => Just(4194304.0f32), 1 => Just(8388608.0f32)],
    ) {
        let m = to_f32(&m, e, &jitter, j, off);
        let r = compare(&m);
        prop_assert!(r.is_ok(), "{}", r.unwrap_err());
    }
}

/// The random meshes above reach both verdicts, folds and degenerate
/// faces included (else the comparison would prove little).
#[test]
fn the_random_meshes_reach_every_kind_of_answer() {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]),
    );
    let (mut yes, mut no, mut folds, mut degenerate) = (0, 0, 0, 0);
    for i in 0..300 {
        let m = bodies().new_tree(&mut runner).unwrap().current();
        let m = if i % 2 == 0 {
            m
        } else {
            // Rounded to a grid of step 1/2 or 1: folds and degenerate
            // faces.
            let off = if i % 4 == 1 { 4194304.0 } else { 8388608.0 };
            to_f32(&m, 0, &[0.4, -0.3, 0.2, 0.1, -0.45, 0.35, -0.15], 0.6, off)
        };
        let (topo, issues) = Topology::build(&m);
        if !issues.is_empty() {
            continue;
        }
        folds += usize::from(
            wmslice::mesh::intersect::edge_overlaps(&m, &topo)
                .iter()
                .any(|(_, k)| *k == EdgeOverlap::Fold),
        );
        degenerate += usize::from(m.faces.iter().any(|f| {
            let [a, b, c] = f.map(|v| m.pos(v));
            is_degenerate_triangle(a, b, c)
        }));
        match compare(&m) {
            Ok(Some(true)) => yes += 1,
            Ok(Some(false)) => no += 1,
            Ok(None) => {}
            Err(e) => panic!("{e}"),
        }
    }
    println!(
        "intersecting {yes}, not {no}, with folds {folds}, with degenerate faces {degenerate}"
    );
    assert!(yes >= 30 && no >= 30, "intersecting {yes}, not {no}");
    assert!(
        folds >= 3 && degenerate >= 3,
        "folds {folds}, degenerate {degenerate}"
    );
}
