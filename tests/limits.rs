//! The one-sided limits L- and L+ (SPEC section 6), checked three
//! independent ways:
//!
//! - hand-derived loop counts (outer, hole, collapsed) of every dataset at
//!   every degenerate height, with the reasoning beside each row;
//! - a z-mirror: mirroring the mesh in z (faces turned to stay outward)
//!   turns the material just above `c` into the material just below `-c`,
//!   so the mirror's L- at `-c` is the original's L+ at `c`, loop for loop
//!   (same elements in the same order, roles, parents, collapse, areas);
//! - the neighbouring regular levels: L+ at `c` crosses exactly the edges,
//!   in the same order, of the contour at every regular level just above
//!   (L- likewise below), with the same roles and parents, and each
//!   loop's exact area is the limit at `c` of that loop's area, which is a
//!   quadratic in the level there (extrapolated exactly from three levels).

mod common;

use num_traits::{One, Zero};
use proptest::prelude::*;
use std::collections::HashMap;
use wmslice::datasets;
use wmslice::datasets::cross_check::{self, limit_shape};
use wmslice::datasets::slab::{heights_and_midpoints, Slab};
use wmslice::exact::{parse_rational, Rat};
use wmslice::levelset::check::vertex_heights;
use wmslice::levelset::Loop;
use wmslice::nest::Role;
use wmslice::segment::CutPoint;
use wmslice::{Mesh, Slicer};

/// Loop counts of a limit: outer, hole, collapsed.
type Counts = (usize, usize, usize);

fn counts(loops: &[Loop]) -> Counts {
    let outer = loops.iter().filter(|l| l.role == Role::Outer).count();
    let collapsed = loops.iter().filter(|l| l.collapsed).count();
    (outer, loops.len() - outer, collapsed)
}

/// `(dataset, z, L-, L+, why)`, derived from the constructions in
/// DATASETS.md. A collapsed loop bounds, with its neighbours, a region of
/// zero area at the level: around an extremum, or both sides of a ridge or
/// valley.
const LIMITS: &[(&str, &str, Counts, Counts, &str)] = &[
    ("unit_cube", "0", (0, 0, 0), (1, 0, 0), "bottom face: nothing below, the square above"),
    ("unit_cube", "1", (1, 0, 0), (0, 0, 0), "top face: the square below, nothing above"),
    ("octahedron", "-1", (0, 0, 0), (1, 0, 1), "bottom vertex, a minimum: just above, a small square around it, collapsed onto it"),
    ("octahedron", "0", (1, 0, 0), (1, 0, 0), "equator of transversal edges: the square on both sides"),
    ("octahedron", "1", (1, 0, 1), (0, 0, 0), "top vertex, a maximum: just below, a square collapsing onto it"),
    ("pyramid", "0", (0, 0, 0), (1, 0, 0), "base face: the base square just above"),
    ("pyramid", "1", (1, 0, 1), (0, 0, 0), "apex: a small square just below, collapsed onto the apex"),
    ("upright_torus", "-3", (0, 0, 0), (1, 0, 1), "bottom vertex, a minimum"),
    ("upright_torus", "-2", (1, 0, 0), (1, 0, 0), "regular vertices (2 branches): one diamond each side"),
    ("upright_torus", "-1", (1, 0, 0), (2, 0, 0), "lower saddle: one region below (1 < |z| < 3), two diamonds above (|z| < 1); they touch at the saddle in the limit"),
    ("upright_torus", "0", (2, 0, 0), (2, 0, 0), "two tube sections of transversal edges: two diamonds on both sides"),
    ("upright_torus", "1", (2, 0, 0), (1, 0, 0), "upper saddle: two diamonds below, one region above"),
    ("upright_torus", "2", (1, 0, 0), (1, 0, 0), "regular vertices: one diamond each side"),
    ("upright_torus", "3", (1, 0, 1), (0, 0, 0), "top vertex, a maximum"),
    ("lying_torus", "-1", (0, 0, 0), (1, 1, 2), "bottom valley ring: just above, the annulus (outer + hole) on both sides of the ring, both collapsed onto it (the annulus has zero area in the limit; each loop alone has area +-56)"),
    ("lying_torus", "0", (1, 1, 0), (1, 1, 0), "inner equator of transversal edges: the annulus on both sides"),
    ("lying_torus", "1", (1, 1, 0), (1, 1, 0), "outer equator of transversal edges: the annulus on both sides"),
    ("lying_torus", "2", (1, 1, 2), (0, 0, 0), "top ridge ring: just below, the annulus collapsing onto the ring"),
    ("double_torus", "0", (0, 0, 0), (1, 2, 0), "bottom face: the domain with its two holes just above"),
    ("double_torus", "1", (1, 2, 0), (1, 3, 1), "pit (0,-1) at z = 1 opens a new hole just above, collapsed onto it; the rim points (1,1), (-1,0) only reshape holes E and W"),
    ("double_torus", "2", (1, 3, 0), (1, 1, 0), "monkey saddle: below, the three notches are separate holes (as at 3/2); above, they have met around v and joined holes W and E into one hole (as at 5/2)"),
    ("double_torus", "4", (1, 1, 0), (0, 0, 0), "top: just below, the structure of the open interval (2, 4): one outer and one hole bounding the two flat parts joined by thin bands along the rim ridges; nothing above"),
    ("grid", "0", (0, 0, 0), (1, 0, 0), "bottom face: the square just above"),
    ("grid", "1", (1, 0, 0), (1, 9, 9), "nine pits (minima): just above, the square with nine small holes, each collapsed onto its pit"),
    ("grid", "2", (1, 9, 10), (0, 0, 0), "ridge network: just below, the square with nine holes (as at 3/2), the material between them a thin band along the ridges: every loop collapsed (9 - 9 * 1 = 0)"),
    ("cylinder", "0", (0, 0, 0), (1, 0, 0), "bottom face"),
    ("cylinder", "2", (1, 0, 0), (0, 0, 0), "top face: the rim below"),
    ("internal_torus", "-2", (0, 0, 0), (1, 0, 0), "box bottom"),
    ("internal_torus", "-1", (1, 0, 0), (2, 1, 2), "cavity valley ring inside the material: just above, the box and the cavity's two walls (hole, pillar), the cavity walls collapsed onto the ring"),
    ("internal_torus", "0", (2, 1, 0), (2, 1, 0), "inner equator of transversal edges"),
    ("internal_torus", "1", (2, 1, 0), (2, 1, 0), "outer equator of transversal edges"),
    ("internal_torus", "2", (2, 1, 2), (1, 0, 0), "cavity ridge ring: just below, the cavity walls collapsing onto the ring; above, the box alone"),
    ("internal_torus", "3", (1, 0, 0), (0, 0, 0), "box top"),
    ("peg_cube", "0", (0, 0, 0), (1, 0, 0), "cube bottom"),
    ("peg_cube", "1", (1, 0, 0), (1, 0, 0), "right peg bottom: cube below, cube + peg above, one loop each"),
    ("peg_cube", "3", (1, 0, 0), (1, 0, 0), "cube + right peg below, cube + left peg above"),
    ("peg_cube", "7/2", (1, 0, 0), (1, 0, 0), "cube + left peg below, cube above"),
    ("peg_cube", "4", (1, 0, 0), (0, 0, 0), "cube top"),
    ("chamfered_cylinder", "0", (0, 0, 0), (1, 0, 0), "bottom face"),
    ("chamfered_cylinder", "2", (1, 0, 0), (1, 0, 0), "ring of transversal edges"),
    ("chamfered_cylinder", "3", (1, 0, 0), (0, 0, 0), "top face"),
    ("platform_grid", "0", (0, 0, 0), (1, 0, 0), "bottom face"),
    ("platform_grid", "1", (1, 0, 0), (4, 0, 0), "platform top: the platform below, the four plateaus above"),
    ("platform_grid", "2", (4, 0, 0), (0, 0, 0), "plateau tops"),
    ("saddle8", "0", (0, 0, 0), (1, 0, 0), "bottom face"),
    ("saddle8", "1", (1, 0, 0), (1, 0, 0), "regular corners: the square with notches, one loop"),
    ("saddle8", "2", (1, 0, 0), (4, 0, 0), "8-branch saddle: one region below, four triangles above, touching at v in the limit"),
    ("saddle8", "3", (4, 0, 4), (0, 0, 0), "four maxima on the rim: four triangles below, each collapsing onto its vertex"),
];

#[test]
fn limits_have_the_hand_derived_loops_at_every_degenerate_height() {
    for d in datasets::all() {
        let mesh = d.build();
        let slicer = Slicer::new(&mesh).unwrap();
        for &(p, q) in d.degenerate_levels {
            let z = format!("{p}/{q}");
            let c = parse_rational(&z).unwrap();
            let row = LIMITS
                .iter()
                .find(|r| r.0 == d.name && parse_rational(r.1).unwrap() == c)
                .unwrap_or_else(|| panic!("no hand-derived row for {} at {z}", d.name));
            let ls = slicer.slice_at(&c).unwrap();
            assert_eq!(
                counts(&ls.below),
                row.2,
                "{} at {z}: L- ({})",
                d.name,
                row.4
            );
            assert_eq!(
                counts(&ls.above),
                row.3,
                "{} at {z}: L+ ({})",
                d.name,
                row.4
            );
        }
    }
}

/// The apex, the top ring and a ridge network in detail: points, areas.
#[test]
fn collapsed_loops_in_detail() {
    let at = |name: &str, z: &str| {
        let mesh = datasets::by_name(name).unwrap().build();
        let ls = Slicer::new(&mesh)
            .unwrap()
            .slice_at(&parse_rational(z).unwrap())
            .unwrap();
        (mesh, ls)
    };
    // Pyramid apex (0,0,1), vertex 5: L- is one point, outer (the square
    // just below is counter-clockwise), area 0.
    let (mesh, ls) = at("pyramid", "1");
    let apex = mesh
        .positions
        .iter()
        .position(|p| *p == [0.0, 0.0, 1.0])
        .unwrap();
    let l = &ls.below[0];
    assert_eq!(
        l.cuts,
        vec![CutPoint::AtVertex(wmslice::ids::VertexId(apex as u32))]
    );
    assert!(l.collapsed && l.role == Role::Outer && l.area().is_zero());
    assert_eq!(l.crossings.len(), 4, "the four edges down from the apex");
    // Lying torus top ring (8 vertices at z = 2, gauge s = 2: area 14 * 4
    // = 56): an outer loop and a hole along the ring, each of area +-56,
    // together zero.
    let (_, ls) = at("lying_torus", "2");
    let mut areas: Vec<Rat> = ls.below.iter().map(Loop::area).collect();
    areas.sort();
    assert_eq!(
        areas,
        vec![
            Rat::from_integer((-56).into()),
            Rat::from_integer(56.into())
        ]
    );
    let hole = ls.below.iter().position(|l| l.role == Role::Hole).unwrap();
    let outer = 1 - hole;
    assert_eq!(ls.below[hole].parent, Some(outer));
    assert_eq!(ls.below[outer].cuts.len(), 8, "the ring's 8 vertices");
    assert!(ls.below.iter().all(|l| l.collapsed));
    // Grid ridge network at z = 2: the outer square (area 9) and nine
    // unit holes, all collapsed.
    let (_, ls) = at("grid", "2");
    let total: Rat = ls.below.iter().map(Loop::area).sum();
    assert!(total.is_zero());
    let outer: Vec<&Loop> = ls.below.iter().filter(|l| l.role == Role::Outer).collect();
    assert_eq!(outer.len(), 1);
    assert_eq!(outer[0].area(), Rat::from_integer(9.into()));
    assert!(ls
        .below
        .iter()
        .filter(|l| l.role == Role::Hole)
        .all(|l| l.area() == -Rat::one() && l.parent.is_some()));
}

/// A closed ridge ring with material on both sides (found by the
/// `adversarial` fuzz target): a 2 x 2 cell slab whose bottom has its
/// corners and centre at z = -4 and its edge midpoints at -3, each cell
/// split along the diagonal between two midpoints, so those diagonals form
/// a diamond ring at exactly -3 (a ridge of the bottom); the top has its
/// corners and centre at -3 and its midpoints at -2 (a pit at the centre).
/// Just below -3 the material is the diamond's inside (area 2) and four
/// corner triangles (area 1/2 each), apart along the ring: five loops,
/// none collapsed, though every piece of each runs along the ridge. Just
/// above, one outer loop of area 4 with a collapsed hole at the pit.
#[test]
fn a_ridge_ring_with_material_on_both_sides_is_not_collapsed() {
    let g = |i: usize, j: usize| [i as f64 - 2.0, j as f64 - 1.5];
    let mut positions = Vec::new();
    for (lo, hi) in [(-4.0, -3.0), (-3.0, -2.0)] {
        for j in 0..3 {
            for i in 0..3 {
                let [x, y] = g(i, j);
                positions.push([x, y, if (i + j) % 2 == 0 { lo } else { hi }]);
            }
        }
    }
    let top = |k: u32| k + 9;
    let mut faces: Vec<[u32; 3]> = Vec::new();
    for (j, i) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
        let v = |di: usize, dj: usize| (3 * (j + dj) + i + di) as u32;
        let (a, b, c, d) = (v(0, 0), v(1, 0), v(1, 1), v(0, 1));
        // The diagonal between the two midpoints of the cell.
        let (q, r, s, t) = if (i + j) % 2 == 0 {
            (b, c, d, a)
        } else {
            (a, b, c, d)
        };
        faces.extend([
            [q, s, r],
            [q, t, s],
            [top(q), top(r), top(s)],
            [top(q), top(s), top(t)],
        ]);
    }
    let border = [0u32, 1, 2, 5, 8, 7, 6, 3];
    for k in 0..8 {
        let (p, q) = (border[k], border[(k + 1) % 8]);
        faces.extend([[p, q, top(q)], [p, top(q), top(p)]]);
    }
    let mesh = Mesh::from_raw(positions, faces);
    let ls = Slicer::new(&mesh)
        .unwrap()
        .slice_at(&parse_rational("-3").unwrap())
        .unwrap();
    let mut below: Vec<Rat> = ls.below.iter().map(Loop::area).collect();
    below.sort();
    let half = Rat::new(1.into(), 2.into());
    let two = Rat::from_integer(2.into());
    assert_eq!(
        below,
        vec![half.clone(), half.clone(), half.clone(), half, two]
    );
    assert!(ls
        .below
        .iter()
        .all(|l| !l.collapsed && l.role == Role::Outer));
    assert_eq!(counts(&ls.above), (1, 1, 1));
    let pit = ls.above.iter().find(|l| l.role == Role::Hole).unwrap();
    assert!(pit.collapsed && pit.area().is_zero());
}

/// The z-mirror at every vertex height and between them
/// ([`wmslice::datasets::cross_check::check_mirror`]), the x-mirror
/// ([`wmslice::datasets::cross_check::check_x_mirror`]), and the
/// relabelling, the quarter turn, the far translation and the scales to
/// both ends of the double range
/// ([`wmslice::datasets::cross_check::check_transformed`]), all always
/// made: these meshes' coordinates are small integers.
fn check_transformed(mesh: &Mesh) -> Result<(), TestCaseError> {
    let levels = heights_and_midpoints(mesh);
    let slicer = Slicer::new(mesh).map_err(|e| TestCaseError::fail(e.to_string()))?;
    cross_check::check_mirror(mesh, &levels)
        .and_then(|()| cross_check::check_x_mirror(mesh, &levels))
        .and_then(|()| cross_check::check_transformed(&slicer, &levels))
        .map_err(TestCaseError::fail)
        .and_then(|done| match (done.moved, done.scales.len()) {
            (Some(_), 2) => Ok(()),
            _ => Err(TestCaseError::fail("no far translation or scale was made")),
        })
}

#[test]
fn every_dataset_agrees_with_itself_transformed() {
    for d in datasets::all() {
        check_transformed(&d.build()).unwrap_or_else(|e| panic!("{}: {e}", d.name));
    }
}

/// Both limits at every vertex height against the regular levels beside
/// them ([`wmslice::datasets::cross_check::check_all_neighbours`]).
fn check_all_neighbours(mesh: &Mesh) -> Result<(), TestCaseError> {
    let slicer = Slicer::new(mesh).unwrap();
    cross_check::check_all_neighbours(&slicer, &vertex_heights(mesh)).map_err(TestCaseError::fail)
}

#[test]
fn every_dataset_limit_is_its_neighbouring_regular_contour() {
    for d in datasets::all() {
        check_all_neighbours(&d.build()).unwrap_or_else(|e| panic!("{}: {e}", d.name));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn random_slabs_agree_with_themselves_transformed(s in common::slab()) {
        check_transformed(&s.mesh())?;
    }

    #[test]
    fn random_slab_limits_are_their_neighbouring_regular_contours(s in common::slab()) {
        check_all_neighbours(&s.mesh())?;
    }
}

/// Every limit loop's elements in the table above are distinct from the
/// mirror's only by the side: a sanity check that the two tests compare
/// what they claim (a loop's sequence is not empty, keys are unique).
#[test]
fn shapes_are_keyed_by_distinct_sequences() {
    let mesh = datasets::by_name("upright_torus").unwrap().build();
    let slicer = Slicer::new(&mesh).unwrap();
    let ls = slicer.slice_at(&parse_rational("-1").unwrap()).unwrap();
    let s = limit_shape(slicer.topology(), &ls.above);
    let keys: HashMap<_, _> = s.iter().map(|x| (x.0.clone(), ())).collect();
    assert_eq!(keys.len(), 2);
    assert!(s.iter().all(|x| !x.0.is_empty()));
}

/// Found by the `adversarial` fuzz target's scale check: this slab of
/// small integers, scaled so that its coordinates are the least
/// subnormals (`k 2^-1074`), at the level `2^-1074`. Crossings a third of
/// the way along an edge from 0 to `2^-1074` round to zero; a lazily held
/// crossing whose nearest double was zero was taken for exactly zero, the
/// nesting decided on it, and L- got a hole with a positive area ("internal
/// error"). Such crossings are now held exactly (`LoopPoint::on_edge_with`).
#[test]
fn a_slab_among_the_least_subnormals_slices_as_the_slab() {
    let slab = Slab {
        nx: 4,
        ny: 4,
        bot: vec![
            -1, 2, -1, 1, 1, 2, -1, 2, -1, 1, -2, 2, -1, 1, -2, -2, 2, -1, 1, -2, -1, 1, -1, 1, -2,
        ],
        thick: vec![1; 25],
        diag: vec![false; 16],
        rot: 0,
    };
    let mesh = slab.mesh();
    let slicer = Slicer::new(&mesh).unwrap();
    let levels = heights_and_midpoints(&mesh);
    let done = cross_check::check_transformed(&slicer, &levels).unwrap();
    // Coordinates up to 4 = 2^2: the 1s go to 2^-1074, the 4s to 2^1023.
    assert_eq!(done.scales, vec![-1074, 1021]);
}
