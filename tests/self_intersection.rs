//! Self-intersection (SPEC section 1: two faces that meet anywhere but in
//! the vertices and edges they share), on hand-made meshes whose answer is
//! derived by hand: the exact face pairs for small bodies that overlap,
//! touch at a point, along an edge or over a face's area, or where a vertex
//! pokes through a face; the verdict of a second body moved across the
//! first, which flips exactly where the geometry of two boxes says; nested
//! shells, which do not intersect; and the listing (ascending, capped,
//! counted, or counted up to a bound and then the same listing) on meshes
//! with thousands of pairs, against the whole answer.

use proptest::prelude::*;
use std::collections::HashMap;
use wmslice::ids::FaceId;
use wmslice::mesh::intersect::{self_intersections, separate_face_pairs, Tally};
use wmslice::mesh::topology::Topology;
use wmslice::mesh::validate::{accept, validate, Defect, MAX_COUNTED_PAIRS, MAX_LISTED_DEFECTS};
use wmslice::Mesh;

const TETRA_POS: [[f64; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
/// Faces 0..3: in z = 0, y = 0, x = 0, and x + y + z = 1.
const TETRA: [[u32; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

/// The unit tetrahedron with each vertex mapped by `f`; `mirror` when `f`
/// reverses orientation (faces are then reversed to stay outward).
fn tetra_by(f: impl Fn([f64; 3]) -> [f64; 3], mirror: bool) -> Mesh {
    let faces = TETRA
        .iter()
        .map(|t| if mirror { [t[0], t[2], t[1]] } else { *t })
        .collect();
    Mesh::from_raw(TETRA_POS.iter().map(|&p| f(p)).collect(), faces)
}

/// Both meshes in one, the second's ids after the first's.
fn union(a: &Mesh, b: &Mesh) -> Mesh {
    let n = a.positions.len() as u32;
    let mut m = a.clone();
    m.positions.extend(&b.positions);
    m.faces.extend(
        b.faces
            .iter()
            .map(|t| t.map(|v| wmslice::VertexId(v.0 + n))),
    );
    m
}

fn pairs(list: &[(u32, u32)]) -> Vec<(FaceId, FaceId)> {
    list.iter().map(|&(a, b)| (FaceId(a), FaceId(b))).collect()
}

fn intersections(m: &Mesh) -> Vec<(FaceId, FaceId)> {
    let (topo, issues) = Topology::build(m);
    assert!(issues.is_empty(), "{issues:?}");
    self_intersections(m, &topo)
}

/// The defects validation names as self-intersections.
fn named(m: &Mesh) -> Vec<(FaceId, FaceId)> {
    validate(m)
        .defects
        .iter()
        .filter_map(|d| match d {
            Defect::SelfIntersection { a, b } => Some((*a, *b)),
            _ => None,
        })
        .collect()
}

#[test]
fn overlapping_tetrahedra_name_the_three_pairs_that_cross() {
    // The copy shifted by 1/4 on every axis lies in x, y, z >= 1/4 and
    // x + y + z <= 7/4: the first one's faces 0, 1, 2 (at a coordinate 0)
    // miss it, the copy's slanted face 7 (x + y + z = 7/4) misses the
    // first one (x + y + z <= 1). The first one's face 3 (x + y + z = 1)
    // crosses each of the copy's faces 4, 5, 6 (z, y, x = 1/4): in z = 1/4
    // along x + y = 3/4 with x, y >= 1/4, and likewise.
    let t = tetra_by(|p| p, false);
    let m = union(&t, &tetra_by(|p| p.map(|x| x + 0.25), false));
    let want = pairs(&[(3, 4), (3, 5), (3, 6)]);
    assert_eq!(intersections(&m), want);
    assert_eq!(named(&m), want);
    assert!(accept(&m).is_err());
}

/// A triangle and its reverse (a closed two-face "pillow", as in a GEBCO
/// terrain STL of pyvista's vtk-data) fold onto each other along all three
/// edges: validation names the three folds, the pair list names the pair
/// once (CGAL's `self_intersections` does too).
#[test]
fn a_two_face_pillow_is_one_pair_folded_along_three_edges() {
    let pillow = Mesh::from_raw(
        vec![[3., 0., 0.], [4., 0., 0.], [3., 1., 0.]],
        vec![[0, 1, 2], [0, 2, 1]],
    );
    let m = union(&tetra_by(|p| p, false), &pillow);
    assert_eq!(intersections(&m), pairs(&[(4, 5)]));
    let folds = validate(&m)
        .defects
        .iter()
        .filter(|d| matches!(d, Defect::Fold { .. }))
        .count();
    assert_eq!(folds, 3);
}

#[test]
fn bodies_touching_at_one_point_intersect() {
    // The copy shifted by (1, 0, 0) lies in x >= 1, the first one in
    // x + y + z <= 1: they share the point (1, 0, 0) only, the first one's
    // vertex 1 and the copy's vertex 4 (another id). The faces through it:
    // 0, 1, 3 and 4, 5, 6; every such pair meets there and nowhere else.
    let t = tetra_by(|p| p, false);
    let m = union(&t, &tetra_by(|p| [p[0] + 1.0, p[1], p[2]], false));
    let mut want = Vec::new();
    for a in [0, 1, 3] {
        for b in [4, 5, 6] {
            want.push((a, b));
        }
    }
    assert_eq!(intersections(&m), pairs(&want));
    // One step of the last bit apart: nothing.
    let apart = union(
        &t,
        &tetra_by(|p| [p[0] + 1.0f64.next_up(), p[1], p[2]], false),
    );
    assert!(intersections(&apart).is_empty());
    assert!(validate(&apart).is_accepted());
}

#[test]
fn bodies_touching_along_an_edge_intersect() {
    // The copy turned half a turn about the z axis, (x, y, z) -> (-x, -y,
    // z), lies in x, y <= 0; the first one in x, y >= 0: they share the
    // segment O-Z from (0, 0, 0) to (0, 0, 1). On it, the first one's face
    // 0 (z = 0) holds O only, faces 1 and 2 the whole segment, face 3 Z
    // only; the copy's faces 4..7 likewise. Pairs meet where those parts
    // do: all but (0, 7) and (3, 4).
    let t = tetra_by(|p| p, false);
    let m = union(&t, &tetra_by(|p| [-p[0], -p[1], p[2]], false));
    let mut want = Vec::new();
    for a in 0..4 {
        for b in 4..8 {
            if (a, b) != (0, 7) && (a, b) != (3, 4) {
                want.push((a, b));
            }
        }
    }
    assert_eq!(intersections(&m), pairs(&want));
}

#[test]
fn bodies_sharing_a_face_area_intersect_everywhere_on_it() {
    // The mirror image in the plane x = 0 shares the triangle D in x = 0
    // with the first one (ids apart). Each face of either meets D in an
    // edge of D or in D, and any two edges of a triangle meet: all 16
    // pairs.
    let t = tetra_by(|p| p, false);
    let m = union(&t, &tetra_by(|p| [-p[0], p[1], p[2]], true));
    let want: Vec<(u32, u32)> = (0..4).flat_map(|a| (4..8).map(move |b| (a, b))).collect();
    assert_eq!(intersections(&m), pairs(&want));
}

#[test]
fn a_vertex_poking_through_a_face_crosses_it_with_its_three_faces() {
    // A small tetrahedron with its base at z = -1/2 and its apex at
    // (1/4, 1/4, 1/8), inside the unit one: its three faces through the
    // apex cross the unit one's bottom (face 0, z = 0) inside it, around
    // (1/4, 1/4) (its cut with z = 0 has corners (9/40, 9/40), (3/10,
    // 9/40), (9/40, 3/10)); everything of it above z = 0 has x, y >= 9/40
    // and x + y + z <= 5/8, so it meets no other face.
    let small = Mesh::from_raw(
        vec![
            [0.125, 0.125, -0.5],
            [0.5, 0.125, -0.5],
            [0.125, 0.5, -0.5],
            [0.25, 0.25, 0.125],
        ],
        TETRA.to_vec(),
    );
    let m = union(&tetra_by(|p| p, false), &small);
    assert!(validate(&small).is_accepted());
    assert_eq!(intersections(&m), pairs(&[(0, 5), (0, 6), (0, 7)]));
}

/// A cube `[lo, lo + size]^3` with each side split into `n x n` squares
/// (two triangles each), outward, its vertices shared.
fn cube(lo: [f64; 3], size: f64, n: usize) -> Mesh {
    let mut ids: HashMap<[usize; 3], u32> = HashMap::new();
    let mut pos = Vec::new();
    let mut id = |g: [usize; 3], pos: &mut Vec<[f64; 3]>| {
        *ids.entry(g).or_insert_with(|| {
            pos.push(std::array::from_fn(|k| {
                lo[k] + size * g[k] as f64 / n as f64
            }));
            (pos.len() - 1) as u32
        })
    };
    let mut faces = Vec::new();
    for a in 0..3 {
        let (u, v) = ((a + 1) % 3, (a + 2) % 3);
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let corner = |di: usize, dj: usize| {
                        let mut g = [0; 3];
                        g[a] = side;
                        g[u] = i + di;
                        g[v] = j + dj;
                        g
                    };
                    let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)]
                        .map(|g| id(g, &mut pos));
                    // Counter-clockwise about +a for the far side.
                    if side == n {
                        faces.push([q[0], q[1], q[2]]);
                        faces.push([q[0], q[2], q[3]]);
                    } else {
                        faces.push([q[0], q[2], q[1]]);
                        faces.push([q[0], q[3], q[2]]);
                    }
                }
            }
        }
    }
    Mesh::from_raw(pos, faces)
}

#[test]
fn nested_shells_do_not_intersect() {
    let outer = cube([0.0; 3], 4.0, 3);
    assert!(validate(&outer).is_accepted());
    for (lo, size) in [([1.0; 3], 2.0), ([0.5, 1.0, 2.0], 1.0)] {
        // Facing inward, the inner cube is a cavity: accepted. Facing
        // outward it intersects nothing either, but is a solid inside a
        // solid: refused for that alone.
        let mut cavity = cube(lo, size, 2);
        for t in &mut cavity.faces {
            t.swap(1, 2);
        }
        let m = union(&outer, &cavity);
        assert!(intersections(&m).is_empty());
        assert!(validate(&m).is_accepted(), "{}", validate(&m));
        let m = union(&outer, &cube(lo, size, 2));
        assert!(intersections(&m).is_empty());
        let r = validate(&m);
        let errors: Vec<_> = r.errors().collect();
        assert!(
            errors.len() == 1 && matches!(errors[0], Defect::MisnestedShell { winding: 1, .. }),
            "{r}"
        );
    }
    // Moved out to touch the outer wall from inside: they intersect.
    let touching = union(&outer, &cube([3.0, 1.0, 1.0], 1.0, 2));
    assert!(!intersections(&touching).is_empty());
}

/// A translation that keeps every cube vertex exact (multiples of 2^-40
/// below 8).
fn shift() -> impl Strategy<Value = f64> {
    let near = |t: f64| prop_oneof![Just(t), Just(t + 2f64.powi(-40)), Just(t - 2f64.powi(-40)),];
    prop_oneof![
        near(1.0),
        near(-1.0),
        near(0.0),
        near(0.25),
        near(-0.75),
        (-3i64 << 40..3i64 << 40).prop_map(|k| k as f64 * 2f64.powi(-40)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Two unit cubes (closed surfaces), the second moved by `d`: as
    /// closed boxes they meet exactly when `|d_k| <= 1` on every axis, and
    /// then their surfaces meet too (neither can hold the other strictly
    /// inside), touching included.
    #[test]
    fn a_cube_moved_across_another_intersects_exactly_when_the_boxes_meet(
        d in [shift(), shift(), shift()],
        n in 1usize..3,
    ) {
        let m = union(&cube([0.0; 3], 1.0, n), &cube(d, 1.0, 2));
        let meet = d.iter().all(|x| x.abs() <= 1.0);
        prop_assert_eq!(!intersections(&m).is_empty(), meet, "{:?}", d);
        prop_assert_eq!(accept(&m).is_ok(), !meet);
    }

    /// A cube of side 1/2 moved by `d` from `[1/4, 3/4]^3` inside the unit
    /// cube: the surfaces meet exactly when the boxes meet and the small
    /// one is not strictly inside (some side at or beyond the big one's).
    #[test]
    fn a_small_cube_moved_out_of_a_big_one_intersects_exactly_at_its_walls(
        d in [shift(), shift(), shift()],
    ) {
        let lo = d.map(|x| 0.25 + x);
        let m = union(&cube([0.0; 3], 1.0, 2), &cube(lo, 0.5, 1));
        let boxes_meet = lo.iter().all(|&l| l <= 1.0 && l + 0.5 >= 0.0);
        let strictly_inside = lo.iter().all(|&l| l > 0.0 && l + 0.5 < 1.0);
        prop_assert_eq!(
            !intersections(&m).is_empty(),
            boxes_meet && !strictly_inside,
            "{:?}", d
        );
    }
}

#[test]
fn thousands_of_pairs_are_listed_ascending_capped_and_counted() {
    // Two finely split cubes, the second moved by (1/2, 1/3, 1/5)-ish:
    // many crossing pairs.
    let m = union(
        &cube([0.0; 3], 1.0, 24),
        &cube([0.5, 0.375, 0.1875], 1.0, 24),
    );
    let all = intersections(&m);
    assert!(all.len() > MAX_LISTED_DEFECTS, "{}", all.len());
    assert!(all.windows(2).all(|w| w[0] < w[1]));
    assert!(all.iter().all(|(a, b)| a < b));
    let r = validate(&m);
    assert_eq!(named(&m), all[..MAX_LISTED_DEFECTS].to_vec());
    assert_eq!(r.defects.len() + r.unlisted, all.len());
    // No fold among them: the listing from validation counts them all.
    let (topo, _) = Topology::build(&m);
    let bounded = separate_face_pairs(&m, &topo, 10, usize::MAX);
    assert_eq!(bounded.pairs, all[..10].to_vec());
    assert_eq!(bounded.unlisted, all.len() - 10);
    assert_eq!(bounded.tally, Tally::Exact);
}

#[test]
fn a_search_that_stops_counting_lists_the_same_pairs() {
    // The two cubes' faces share no vertex: every pair is one the count
    // may stop at. The whole answer (never stopped) is the reference.
    let m = union(
        &cube([0.0; 3], 1.0, 24),
        &cube([0.5, 0.375, 0.1875], 1.0, 24),
    );
    let all = intersections(&m);
    let n = all.len();
    let (topo, _) = Topology::build(&m);
    for (keep, stop_at) in [(10, 1), (10, 100), (100, 100), (10, n - 1), (10, n)] {
        let found = separate_face_pairs(&m, &topo, keep, stop_at);
        assert_eq!(found.pairs, all[..keep].to_vec(), "{keep} {stop_at}");
        assert_eq!(found.tally, Tally::AtLeast, "{keep} {stop_at}");
        assert_eq!(
            found.unlisted,
            stop_at.saturating_sub(keep),
            "{keep} {stop_at}"
        );
    }
    // One more than there are: counted to the end.
    let found = separate_face_pairs(&m, &topo, 10, n + 1);
    assert_eq!(found.pairs, all[..10].to_vec());
    assert_eq!((found.unlisted, found.tally), (n - 10, Tally::Exact));
}

/// A closed cube's faces with every vertex moved to a random point of
/// the unit cube (on the 1/1024 grid): a soup of large crossing faces, as
/// a fuzzer makes of a mesh file's coordinates.
fn soup() -> Mesh {
    let mut m = cube([0.0; 3], 1.0, 6);
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    for p in &mut m.positions {
        for c in p.iter_mut() {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            *c = (state >> 54) as f64 / 1024.0;
        }
    }
    m
}

#[test]
fn a_fan_folded_every_which_way_stops_counting_with_the_same_listing() {
    // A double cone: apexes 0 (top) and 1 (bottom), each with a fan of 300
    // faces over a ring of 300 random points of the unit cube: pairs of
    // faces sharing an apex by the thousand, and pairs sharing none.
    let n = 300u32;
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        (state >> 54) as f64 / 1024.0
    };
    let mut positions = vec![[0.5, 0.5, 2.0], [0.5, 0.5, -1.0]];
    positions.extend((0..n).map(|_| [next(), next(), next()]));
    let mut faces = Vec::new();
    for i in 0..n {
        let (a, b) = (2 + i, 2 + (i + 1) % n);
        faces.push([0, a, b]);
        faces.push([1, b, a]);
    }
    let m = Mesh::from_raw(positions, faces);
    let (topo, issues) = Topology::build(&m);
    assert!(issues.is_empty(), "{issues:?}");
    let all = separate_face_pairs(&m, &topo, usize::MAX, usize::MAX).pairs;
    let shares = |&(a, b): &(FaceId, FaceId)| {
        let [fa, fb] = [a, b].map(|f| m.faces[f.idx()]);
        fa.iter().any(|v| fb.contains(v))
    };
    let at_apexes = all.iter().filter(|p| shares(p)).count();
    assert!(
        at_apexes > 1000 && at_apexes < all.len(),
        "{at_apexes} of {}",
        all.len()
    );
    for stop_at in [1, 1000, at_apexes, all.len()] {
        let found = separate_face_pairs(&m, &topo, 100, stop_at);
        assert_eq!(found.pairs, all[..100].to_vec(), "{stop_at}");
        assert_eq!(found.tally, Tally::AtLeast, "{stop_at}");
    }
    let found = separate_face_pairs(&m, &topo, 100, all.len() + 1);
    assert_eq!(found.pairs, all[..100].to_vec());
    assert_eq!(
        (found.unlisted, found.tally),
        (all.len() - 100, Tally::Exact)
    );
}

#[test]
fn validation_of_a_soup_with_more_pairs_than_it_counts_says_at_least() {
    let m = soup();
    let all = intersections(&m);
    assert!(all.len() > MAX_COUNTED_PAIRS, "{}", all.len());
    let r = validate(&m);
    assert_eq!(named(&m), all[..MAX_LISTED_DEFECTS].to_vec());
    assert_eq!(r.tally, Tally::AtLeast);
    // At least the bound, less than all: the count stopped.
    assert!(
        r.unlisted >= MAX_COUNTED_PAIRS - MAX_LISTED_DEFECTS,
        "{}",
        r.unlisted
    );
    assert!(r.unlisted < all.len(), "{} of {}", r.unlisted, all.len());
    let text = r.to_string();
    assert!(
        text.contains(&format!("... and at least {} more", r.unlisted)),
        "{text}"
    );
}

#[test]
fn check_json_says_when_its_count_is_a_lower_bound() {
    let m = soup();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("soup.off");
    m.save(&path).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(["check", "--json"])
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["unlisted_count"], "at_least");
    assert_eq!(json["unlisted_defects"], validate(&m).unlisted);
}

#[test]
fn the_listing_does_not_depend_on_the_number_of_threads() {
    let m = union(
        &cube([0.0; 3], 1.0, 40),
        &cube([0.5, 0.375, 0.1875], 1.0, 40),
    );
    assert!(m.num_faces() > 1 << 14);
    let (topo, _) = Topology::build(&m);
    let on = |threads: usize, stop_at: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| separate_face_pairs(&m, &topo, 100, stop_at))
    };
    let one = on(1, usize::MAX);
    assert_eq!(one.pairs.len(), 100);
    for threads in [2, 3] {
        assert_eq!(on(threads, usize::MAX), one);
    }
    // Nor when the count stops, early or late.
    let all = one.pairs.len() + one.unlisted;
    for stop_at in [1000, all] {
        let one_thread = on(1, stop_at);
        assert_eq!(one_thread.pairs, one.pairs);
        assert_eq!(one_thread.tally, Tally::AtLeast);
        for threads in [2, 3] {
            assert_eq!(on(threads, stop_at), one_thread);
        }
    }
}
