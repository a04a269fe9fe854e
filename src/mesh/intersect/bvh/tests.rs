//! The broad phase against all pairs, and how few pairs it tests.

use super::super::turn::{dot, Turn};
use super::apart::{Plane, Side};
use super::frame::{turn_error, TURNING};
use super::*;
use crate::exact::scale::times_pow2;
use std::cell::Cell;
use std::sync::Mutex;

/// Doubles `m 2^e`, from the least subnormal to near the largest.
fn double() -> impl proptest::strategy::Strategy<Value = f64> {
    use proptest::prelude::*;
    (-(1i64 << 53)..1 << 53, -1126i32..970).prop_map(|(m, e)| times_pow2(m as f64, e))
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4096))]
    /// `down32(x, e)` is at most `x - e` and `up32(x, e)` at least
    /// `x + e`, exactly (in rationals), across the range.
    #[test]
    fn bounds_hold_every_value_within_the_margin(x in double(), e in double()) {
        use crate::exact::rational::rat_from_f64;
        let e = e.abs();
        let (lo, hi) = (down32(x, e), up32(x, e));
        let (x, e) = (rat_from_f64(x), rat_from_f64(e));
        if lo.is_finite() {
            proptest::prop_assert!(rat_from_f64(f64::from(lo)) <= &x - &e);
        }
        if hi.is_finite() {
            proptest::prop_assert!(rat_from_f64(f64::from(hi)) >= &x + &e);
        }
    }

    /// A turned coordinate lies within `turn_error` of the exact dot
    /// product (in rationals), for any rows and any point whose
    /// coordinates are at most `q` in magnitude, down to the
    /// subnormals.
    #[test]
    fn turned_coordinates_lie_within_the_turn_error(
        rows in proptest::array::uniform3(proptest::array::uniform3(-1.0f64..1.0)),
        ms in proptest::array::uniform3(-(1i64 << 53)..1 << 53),
        shifts in proptest::array::uniform3(0i32..120),
        top in -1000i32..200,
    ) {
        use crate::exact::rational::rat_from_f64;
        use num_traits::Signed;
        // Coordinates at most 2^top, some far below it.
        let x: [f64; 3] =
            std::array::from_fn(|k| times_pow2(ms[k] as f64, top - 53 - shifts[k]));
        let turn = Turn::from_rows(rows);
        let bound = rat_from_f64(turn_error(&turn, times_pow2(1.0, top)));
        for (row, got) in rows.iter().zip(turn.apply(x)) {
            let exact = (0..3).fold(crate::exact::rational::Rat::from_integer(0.into()), |s, k| {
                s + rat_from_f64(row[k]) * rat_from_f64(x[k])
            });
            // The proven bound of `VolumeFrame::of` checked in
            // rationals (it widens the broad phase's volumes; no
            // decision compares with it).
            let off = rat_from_f64(got) - exact;
            proptest::prop_assert!(off.abs() <= bound, "{:?}", x);
        }
    }
}

thread_local! {
    /// Pairs of leaves compared on this thread (a search with
    /// `parallel` off runs on the calling thread).
    pub(super) static LEAF_PAIRS: Cell<usize> = const { Cell::new(0) };
}

/// The tree of `mesh` with its volumes along the axes (never turned):
/// the tests here count and compare the volumes of that frame.
fn unturned<'m>(mesh: &'m Mesh, groups: Option<&[u32]>) -> Bvh<'m> {
    TURNING.with(|t| t.set(false));
    let tree = Bvh::build(mesh, &mesh.faces, groups, false);
    TURNING.with(|t| t.set(true));
    tree
}

/// The pairs the tree hands to its test, sorted.
fn candidates(mesh: &Mesh) -> Vec<(FaceId, FaceId)> {
    grouped_candidates(mesh, None)
}

/// [`candidates`] with the faces in groups.
fn grouped_candidates(mesh: &Mesh, groups: Option<&[u32]>) -> Vec<(FaceId, FaceId)> {
    tested_by(&unturned(mesh, groups))
}

/// The pairs `tree` hands to its test, sorted.
fn tested_by(tree: &Bvh<'_>) -> Vec<(FaceId, FaceId)> {
    let seen = Mutex::new(Vec::new());
    tree.pairs(
        &|a: FaceId, b: FaceId| {
            seen.lock().unwrap().push((a.min(b), a.max(b)));
            false
        },
        0,
        &Stop::never(),
    );
    let mut seen = seen.into_inner().unwrap();
    seen.sort_unstable();
    seen
}

/// Every pair of faces with no shared vertex id, not in one group,
/// whose boxes and diagonal extents meet, each face's volume computed
/// on its own (`mesh` in the frame that neither shifts nor scales).
fn all_meeting(mesh: &Mesh, groups: Option<&[u32]>) -> Vec<(FaceId, FaceId)> {
    let volume = |f: &[VertexId; 3]| {
        let p = f.map(|v| mesh.pos(v));
        let b = Bounds {
            lo: std::array::from_fn(|k| down32(min3(p[0][k], p[1][k], p[2][k]), 0.0)),
            hi: std::array::from_fn(|k| up32(max3(p[0][k], p[1][k], p[2][k]), 0.0)),
        };
        (b, Slabs::of(p, 0.0))
    };
    let volumes: Vec<_> = mesh.faces.iter().map(volume).collect();
    let group = |t: usize| groups.map_or(NO_GROUP, |g| g[t]);
    let mut out = Vec::new();
    for a in 0..mesh.faces.len() {
        for b in a + 1..mesh.faces.len() {
            let shares = mesh.faces[a].iter().any(|v| mesh.faces[b].contains(v));
            let grouped = group(a) != NO_GROUP && group(a) == group(b);
            let ((ba, sa), (bb, sb)) = (&volumes[a], &volumes[b]);
            if !shares && !grouped && ba.meets(bb) && sa.meets(sb) {
                out.push((FaceId::from_idx(a), FaceId::from_idx(b)));
            }
        }
    }
    out
}

/// A cone over a regular `n`-gon in the plane `z = 0`, its base a fan
/// around the centre: `n` faces around the apex, then `n` around the
/// centre. Its coordinates are cosines and sines (no grid).
fn capped_cone(n: u32) -> Mesh {
    let mut mesh = Mesh::default();
    for i in 0..n {
        let a = f64::from(i) * std::f64::consts::TAU / f64::from(n);
        mesh.positions.push([a.cos(), a.sin(), 0.0]);
    }
    mesh.positions.push([0.0, 0.0, 1.0]);
    mesh.positions.push([0.0, 0.0, 0.0]);
    let ring = |i: u32| VertexId(i % n);
    mesh.faces
        .extend((0..n).map(|i| [ring(i), ring(i + 1), VertexId(n)]));
    mesh.faces
        .extend((0..n).map(|i| [ring(i + 1), ring(i), VertexId(n + 1)]));
    mesh
}

/// The tree hands its test exactly the pairs whose volumes meet (no
/// more: its nodes' extents and hubs only skip nodes that hold none),
/// on a soup, and on a capped cone with its base as one group.
#[test]
fn the_pairs_tested_are_those_whose_volumes_meet() {
    let soup = soup_within(16);
    let reference = all_meeting(&soup, None);
    assert!(reference.len() > 100, "{}", reference.len());
    assert_eq!(candidates(&soup), reference);
    let cone = capped_cone(300);
    let groups: Vec<u32> = (0..600)
        .map(|t| if t < 300 { NO_GROUP } else { 0 })
        .collect();
    for groups in [None, Some(&groups[..])] {
        let reference = all_meeting(&cone, groups);
        assert!(!reference.is_empty());
        assert_eq!(grouped_candidates(&cone, groups), reference);
    }
}

/// A fan's faces all share its apex, and the faces of a cone and of
/// its base (a fan in another plane) are apart along the diagonals
/// but near their ring: comparing the nodes' hubs and extents, the
/// search of a capped cone compares a number of leaf pairs that grows
/// with the leaves, not with their square (boxes alone: every pair of
/// the cone's leaves, about `250^2 / 2` here).
#[test]
fn a_capped_cone_compares_few_pairs_of_leaves() {
    let n = 1000;
    let cone = capped_cone(n);
    let groups: Vec<u32> = (0..2 * n)
        .map(|t| if t < n { NO_GROUP } else { 0 })
        .collect();
    let leaves = (2 * n as usize).div_ceil(LEAF);
    LEAF_PAIRS.with(|c| c.set(0));
    let pairs = grouped_candidates(&cone, Some(&groups));
    let compared = LEAF_PAIRS.with(Cell::get);
    assert!(compared < 8 * leaves, "{compared} pairs of {leaves} leaves");
    assert_eq!(pairs, all_meeting(&cone, Some(&groups)));
}

/// `mesh` turned by the rotation of cosine 3/5 about the axis `(1, 2,
/// 2) / 3`: its entries are not dyadic, so the coordinates are
/// rounded, and no face lies in a coordinate plane or along a diagonal.
fn turned(mesh: &Mesh) -> Mesh {
    rotated(mesh, [1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0], 0.6, 0.8)
}

/// `mesh` turned about the unit axis `k` by the angle of cosine `c`
/// and sine `s` (Rodrigues' formula, rounded).
fn rotated(mesh: &Mesh, k: [f64; 3], c: f64, s: f64) -> Mesh {
    let r: [[f64; 3]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let cross = match (i, j) {
                (0, 1) => -k[2],
                (0, 2) => k[1],
                (1, 0) => k[2],
                (1, 2) => -k[0],
                (2, 0) => -k[1],
                (2, 1) => k[0],
                _ => 0.0,
            };
            let id = if i == j { c } else { 0.0 };
            id + s * cross + (1.0 - c) * k[i] * k[j]
        })
    });
    let mut m = mesh.clone();
    for p in &mut m.positions {
        let q = *p;
        *p = std::array::from_fn(|i| r[i][0] * q[0] + r[i][1] * q[1] + r[i][2] * q[2]);
    }
    m
}

/// The pairs the tree hands its test on `mesh`, and how many pairs of
/// faces have volumes that meet, after checking that the first are
/// among the second and that none of the others (those a plane set
/// apart) meets (exact test).
fn tested_and_meeting(mesh: &Mesh) -> (Vec<(FaceId, FaceId)>, usize) {
    let tested = candidates(mesh);
    let meeting = all_meeting(mesh, None);
    assert!(tested.iter().all(|p| meeting.binary_search(p).is_ok()));
    let face = |f: FaceId| mesh.faces[f.idx()].map(|v| mesh.pos(v));
    let filter = crate::exact::orient_filter::Filter::CHECKING;
    for &(a, b) in meeting.iter().filter(|p| tested.binary_search(p).is_err()) {
        assert!(
            !super::super::narrow::faces_meet(filter, face(a), face(b)),
            "{a:?} {b:?}"
        );
    }
    (tested, meeting.len())
}

/// `a` and `b` side by side in one mesh, `b` moved by `d`.
fn joined(a: &Mesh, b: &Mesh, d: [f64; 3]) -> Mesh {
    let mut m = a.clone();
    let n = a.positions.len() as u32;
    m.positions.extend(
        b.positions
            .iter()
            .map(|p| std::array::from_fn(|k| p[k] + d[k])),
    );
    m.faces
        .extend(b.faces.iter().map(|t| t.map(|v| VertexId(v.0 + n))));
    m
}

/// The pairs of faces of `mesh` (closed, manifold) that meet improperly
/// as the search finds them, checked against testing every pair.
fn found_by_search_and_by_all_pairs(mesh: &Mesh) -> Vec<(FaceId, FaceId)> {
    let (topo, issues) = crate::mesh::topology::Topology::build(mesh);
    assert!(issues.is_empty(), "{issues:?}");
    let every = super::super::tests::all_pairs(mesh);
    assert_eq!(super::super::self_intersections(mesh, &topo), every);
    every
}

/// A flat plate of long thin faces (twenty cells of 40 x 1, split
/// across), turned off the axes: along the axes each face's box holds
/// much of the plate, and the other cap's faces meet it; in the turned
/// frame (the plate's own axes) the boxes are thin again. The pairs
/// tested fall from 972 to 92 (asserted: below a fifth), and the
/// search still finds what testing every pair finds (none: the plate
/// is closed and proper).
#[test]
fn a_turned_plate_of_slivers_is_searched_along_its_own_axes() {
    let n = 21 * 5;
    let mut plate = crate::datasets::slab::Slab {
        nx: 20,
        ny: 4,
        bot: vec![0; n],
        thick: vec![1; n],
        diag: (0..80).map(|c| c % 3 == 0).collect(),
        rot: 0,
    }
    .mesh();
    for p in &mut plate.positions {
        p[0] *= 40.0;
    }
    let mesh = turned(&plate);
    let tree = Bvh::build(&mesh, &mesh.faces, None, false);
    assert!(tree.is_turned());
    let (along_axes, along_plate) = (candidates(&mesh).len(), tested_by(&tree).len());
    assert!(
        5 * along_plate < along_axes,
        "{along_plate} pairs tested turned, {along_axes} along the axes"
    );
    assert!(found_by_search_and_by_all_pairs(&mesh).is_empty());
    // On the axes, the same plate is not turned.
    assert!(!Bvh::build(&plate, &plate.faces, None, false).is_turned());
}

/// A capped cone turned away from the axes: every face's box holds a
/// stretch of the axis, and so do the diagonals, so boxes and extents
/// meet for most pairs of a side face and a base face. The fans' plane
/// sets their nodes apart wherever their arcs of the ring do not meet.
/// The pairs so skipped are among those whose volumes meet, and none
/// meets (exact test); and the pairs tested no longer grow with the
/// square of the faces (which boxes and extents alone make them do:
/// about 49 000 at 2 000 sections, 793 000 at 8 000; with the fans'
/// plane 21 000 and 164 000).
#[test]
fn a_turned_capped_cone_tests_few_pairs() {
    let tested = |n: u32| candidates(&turned(&capped_cone(n)));
    let (few, meeting) = tested_and_meeting(&turned(&capped_cone(2000)));
    assert!(2 * few.len() < meeting, "{} of {meeting}", few.len());
    let more = tested(8000).len();
    assert!(
        more < 10 * few.len(),
        "{more} pairs at 8 000 sections, {} at 2 000",
        few.len()
    );
}

/// Two turned cones, the second moved through the first: fans that
/// cross are not set apart, and the search finds every pair that
/// testing all pairs finds.
#[test]
fn crossing_fans_are_not_set_apart() {
    let one = capped_cone(64);
    let two = turned(&joined(&one, &one, [0.5, 0.25, 0.5]));
    let every = found_by_search_and_by_all_pairs(&two);
    assert!(every.len() > 50, "{}", every.len());
}

/// A cylinder of radius 1 and height `height` over a regular `n`-gon
/// in the plane `z = 0`: `2 n` side faces, each from end to end, then
/// each end a fan of `n` faces around its centre. Its coordinates are
/// cosines and sines (no grid).
fn capped_cylinder(n: u32, height: f64) -> Mesh {
    let mut mesh = Mesh::default();
    for z in [0.0, height] {
        for i in 0..n {
            let a = f64::from(i) * std::f64::consts::TAU / f64::from(n);
            mesh.positions.push([a.cos(), a.sin(), z]);
        }
    }
    mesh.positions.push([0.0, 0.0, 0.0]);
    mesh.positions.push([0.0, 0.0, height]);
    let (low, high) = (|i: u32| VertexId(i % n), |i: u32| VertexId(n + i % n));
    for i in 0..n {
        mesh.faces.push([low(i), low(i + 1), high(i + 1)]);
        mesh.faces.push([low(i), high(i + 1), high(i)]);
    }
    mesh.faces
        .extend((0..n).map(|i| [low(i + 1), low(i), VertexId(2 * n)]));
    mesh.faces
        .extend((0..n).map(|i| [high(i), high(i + 1), VertexId(2 * n + 1)]));
    mesh
}

/// A tall cylinder turned away from the axes: every side face runs
/// from end to end, so its box and diagonal extents hold most of the
/// others'. The plane along the strips sets apart the nodes of strips
/// that share no vertex: the pairs so skipped are among those whose
/// volumes meet, and none meets (exact test); and the pairs tested no
/// longer grow with the square of the faces (with boxes and extents
/// alone, every pair of side faces that share no vertex is tested:
/// 1 995 000 at 1 000 sections; with the plane 374 000, and 1 592 000
/// at 4 000). Turned instead so that its axis is nearly in the plane
/// `y = 0` (`(0.6, 0.01, 0.8)`, normalized: every node's box is thin
/// along y, and the leaves in Morton order hold arcs from both sides
/// of the circle), fewer pairs meet and the plane sets fewer apart
/// (669 000 of 1 258 000), but the growth is still far from square
/// (3 473 000 at 4 000 sections).
#[test]
fn a_turned_tall_cylinder_tests_few_pairs() {
    let (k, c): ([f64; 3], f64) = ([-0.01, 0.6, 0.0], 0.8 / 1.00005f64.sqrt());
    let norm = dot(k, k).sqrt();
    let nearly = |m: &Mesh| rotated(m, k.map(|x| x / norm), c, (1.0 - c * c).sqrt());
    for (turn, part) in [(&turned as &dyn Fn(&Mesh) -> Mesh, 5), (&nearly, 1)] {
        let tested = |n: u32| candidates(&turn(&capped_cylinder(n, 100.0)));
        let (few, meeting) = tested_and_meeting(&turn(&capped_cylinder(1000, 100.0)));
        assert!(part * few.len() < meeting, "{} of {meeting}", few.len());
        let more = tested(4000).len();
        assert!(
            more < 8 * few.len(),
            "{more} pairs at 4 000 sections, {} at 1 000",
            few.len()
        );
    }
}

/// A thin disc turned away from the axes, each cap a fan of slivers
/// from its centre to the rim: every sliver's box holds the centre, so
/// boxes and extents meet for most pairs of a sliver of one cap and
/// one of the other, and the Morton order mixes the two caps in its
/// nodes. A node whose triangles each have one of the two centres has
/// both as hubs, and the plane through them sets such nodes apart
/// wherever their arcs of the rim do not meet. The pairs so skipped
/// are among those whose volumes meet, and none meets (exact test);
/// and the pairs tested grow 6.9-fold from 1 000 to 4 000 sections
/// (62 500 to 431 000; with one hub a node, 131 800 and 1 797 000, all
/// the pairs whose volumes meet).
#[test]
fn a_turned_thin_disc_tests_fewer_pairs() {
    let disc = |n: u32| turned(&capped_cylinder(n, 0.01));
    let (few, meeting) = tested_and_meeting(&disc(1000));
    assert!(2 * few.len() < meeting, "{} of {meeting}", few.len());
    let more = candidates(&disc(4000)).len();
    assert!(
        more < 9 * few.len(),
        "{more} pairs at 4 000 sections, {} at 1 000",
        few.len()
    );
}

/// Two leaves of eight triangles, one at `x < 0` and one at `x > 0`
/// (and higher: in Morton order, the first eight apart from the rest),
/// the first corner of the first triangle of each moved to `p` and
/// `q`; [`Bvh::apart_by`] with the plane `x = 0`.
fn apart_at(p: [f64; 3], q: [f64; 3]) -> bool {
    apart_after(|mesh| {
        mesh.positions[0] = p;
        mesh.positions[24] = q;
    })
}

/// [`apart_at`]'s leaves, after `edit`: 16 triangles of three corners
/// each (vertex `3 t + k` is corner `k` of triangle `t`).
fn apart_after(edit: impl Fn(&mut Mesh)) -> bool {
    let mut mesh = Mesh::default();
    for t in 0..16u32 {
        let (x, z) = if t < 8 { (-2.0, 0.0) } else { (2.0, 4.0) };
        let y = z + f64::from(t % 8) / 8.0;
        for c in [[x, y, z], [x + 0.5, y, z + 1.0], [x, y + 0.1, z + 1.0]] {
            mesh.positions.push(c);
        }
        mesh.faces.push([3 * t, 3 * t + 1, 3 * t + 2].map(VertexId));
    }
    edit(&mut mesh);
    let tree = unturned(&mesh, None);
    let place = tree.places();
    let (a, b) = (place[0].0, place[8].0);
    assert_ne!(a, b);
    let plane = Plane([[0.0; 3], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let want = plane.side_of([-1.0, 0.0, 0.0]).unwrap();
    let side = |l: usize, want| Side {
        leaves: l..l + 1,
        nearest: l,
        hubs: Hubs::NONE,
        want,
    };
    tree.apart_by(&plane, side(a, want), side(b, want.flip()))
}

/// A plane sets two leaves apart when each is on its side, and the
/// points of one on the plane are none, or one point that is not the
/// other's one point; not when they touch the plane at one point, or
/// a vertex is on the wrong side.
#[test]
fn a_plane_sets_apart_what_touches_it_at_different_points() {
    let (off_a, off_b) = ([-2.0, 0.0, 0.0], [2.0, 4.0, 4.0]);
    assert!(apart_at(off_a, off_b));
    let (on, elsewhere) = ([0.0, 1.0, 2.0], [0.0, 3.0, 2.0]);
    assert!(apart_at(on, off_b));
    assert!(apart_at(off_a, on));
    assert!(apart_at(on, elsewhere));
    assert!(!apart_at(on, on));
    assert!(!apart_at([0.5, 1.0, 2.0], off_b));
    assert!(!apart_at(off_a, [-0.5, 1.0, 2.0]));
}

/// Each triangle may touch the plane at one vertex: a side may touch
/// it at several points, and at a vertex the other side has too (a
/// triangle of one meets one of the other there only when both have
/// that vertex: not a pair to test); not at a point where the other
/// side has another vertex, nor along an edge.
#[test]
fn a_plane_sets_apart_what_touches_it_at_shared_vertices() {
    let on = |y: f64| [0.0, y, 2.0];
    // Triangles 0 and 1 (left) and 8 (right) touch the plane.
    let several = |m: &mut Mesh| {
        (m.positions[0], m.positions[3], m.positions[24]) = (on(1.0), on(3.0), on(5.0));
    };
    assert!(apart_after(several));
    // Triangle 8's first corner is triangle 0's, on the plane.
    let shared = |m: &mut Mesh| {
        m.positions[0] = on(1.0);
        m.faces[8][0] = VertexId(0);
    };
    assert!(apart_after(shared));
    assert!(apart_after(|m| {
        several(m);
        shared(m);
    }));
    // Triangle 8's first corner moved to triangle 1's, a vertex apart.
    assert!(!apart_after(|m| {
        several(m);
        m.positions[24] = on(3.0);
    }));
    // Triangle 0's edge from its first to its second corner on it.
    assert!(!apart_after(|m| {
        (m.positions[0], m.positions[1]) = (on(1.0), on(1.5));
    }));
}

/// Two turned tall cylinders, the second moved through the first:
/// strips that cross are not set apart, and the search finds every
/// pair that testing all pairs finds.
#[test]
fn crossing_strips_are_not_set_apart() {
    let one = capped_cylinder(48, 20.0);
    let two = turned(&joined(&one, &one, [0.5, 0.25, 0.5]));
    let every = found_by_search_and_by_all_pairs(&two);
    assert!(every.len() > 50, "{}", every.len());
}

/// 300 small triangles (sides up to 4/64) at random places on the
/// `1/64` grid in `[0, 1.5]^3`, no vertex shared.
fn soup() -> Mesh {
    soup_within(92)
}

/// 300 small triangles (sides up to 4/64) at random places on the
/// `1/64` grid, their lowest corner in `[0, cells / 64)^3`, no vertex
/// shared.
fn soup_within(cells: u64) -> Mesh {
    let mut state = 7u64;
    let mut next = |n: u64| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) % n
    };
    let mut mesh = Mesh::default();
    for t in 0..300u32 {
        let base: [u64; 3] = std::array::from_fn(|_| next(cells));
        for _ in 0..3 {
            let p: [f64; 3] = std::array::from_fn(|k| (base[k] + next(5)) as f64 / 64.0);
            mesh.positions.push(p);
        }
        mesh.faces.push([3 * t, 3 * t + 1, 3 * t + 2].map(VertexId));
    }
    // The span is at least 1: the leading exponent of the volumes'
    // largest magnitude is 0 in every frame below.
    mesh.positions.push([1.5, 0.0, 0.0]);
    mesh
}

/// The same soup far from the origin (at `2^30`, where `f32` are 128
/// apart), near `2^-1000`, among the subnormals (`2^-1060`) and near
/// `2^1000`: the tree hands its test exactly the pairs it hands it for
/// the soup as made, which are far fewer than all pairs. Before the
/// frame, every `f32` volume of these met every other.
#[test]
fn far_tiny_subnormal_and_huge_copies_test_the_same_pairs() {
    let mesh = soup();
    let reference = candidates(&mesh);
    let n = mesh.faces.len();
    assert!(!reference.is_empty());
    assert!(reference.len() < n * (n - 1) / 20, "{}", reference.len());
    let moved = |f: &dyn Fn(f64) -> f64| Mesh {
        positions: mesh.positions.iter().map(|p| p.map(f)).collect(),
        faces: mesh.faces.clone(),
    };
    for (name, copy) in [
        ("far", moved(&|x| x + times_pow2(1.0, 30))),
        ("tiny", moved(&|x| times_pow2(x, -1000))),
        ("subnormal", moved(&|x| times_pow2(x, -1060))),
        ("huge", moved(&|x| times_pow2(x, 1000))),
    ] {
        assert_eq!(candidates(&copy), reference, "{name}");
    }
}

/// `later_partners`, over every triangle, gives the pairs `pairs`
/// hands to its test, each once, smaller face first (on a soup, where
/// no two nodes are fans).
#[test]
fn the_later_partners_are_the_pairs_tested() {
    let mesh = soup_within(16);
    let reference = candidates(&mesh);
    assert!(reference.len() > 100, "{}", reference.len());
    let tree = unturned(&mesh, None);
    let place = tree.places();
    let mut all = Vec::new();
    for a in 0..mesh.faces.len() {
        let mut later = Vec::new();
        tree.later_partners(&place, FaceId::from_idx(a), &mut later);
        later.sort_unstable();
        all.extend(later.into_iter().map(|b| (FaceId::from_idx(a), FaceId(b))));
    }
    assert_eq!(all, reference);
}

/// `mesh` turned by `angle` about `axis` made unit length (rounded:
/// test input, any axis will do), or about z when it is zero.
fn turned_about(mesh: &Mesh, axis: [f64; 3], angle: f64) -> Mesh {
    let norm = dot(axis, axis).sqrt();
    let k = if norm > 0.0 {
        axis.map(|x| x / norm)
    } else {
        [0.0, 0.0, 1.0]
    };
    rotated(mesh, k, angle.cos(), angle.sin())
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(40))]

    /// Two tall cylinders, each turned about a random axis, the second
    /// moved by a small offset (often through the first, or touching
    /// it along a side): the search, whose strips a plane may set
    /// apart, finds exactly the pairs that testing every pair finds.
    #[test]
    fn strips_hide_no_pair(
        sections in proptest::array::uniform2(12u32..48),
        heights in proptest::array::uniform2(4.0f64..40.0),
        axes in proptest::array::uniform2(proptest::array::uniform3(-1.0f64..1.0)),
        angles in proptest::array::uniform2(0.1f64..3.0),
        d in proptest::array::uniform3(-2.5f64..2.5),
    ) {
        let turn = |m: usize| {
            turned_about(&capped_cylinder(sections[m], heights[m]), axes[m], angles[m])
        };
        found_by_search_and_by_all_pairs(&joined(&turn(0), &turn(1), d));
    }

    /// Two thin discs (caps that are fans, mixed in the tree's nodes),
    /// every other vertex of the top rim lowered by a random amount
    /// (often through the bottom cap), each turned about a random
    /// axis, the second moved by a small offset (often through the
    /// first): the search, whose fans a plane through their hubs may
    /// set apart, finds exactly the pairs that testing every pair
    /// finds.
    #[test]
    fn fans_hide_no_pair(
        sections in proptest::array::uniform2(16u32..160),
        heights in proptest::array::uniform2(0.001f64..0.2),
        lowered in proptest::array::uniform2(0.0f64..0.3),
        axes in proptest::array::uniform2(proptest::array::uniform3(-1.0f64..1.0)),
        angles in proptest::array::uniform2(0.1f64..3.0),
        d in proptest::array::uniform3(-0.3f64..0.3),
    ) {
        let turn = |m: usize| {
            let n = sections[m] as usize;
            let mut disc = capped_cylinder(sections[m], heights[m]);
            for p in disc.positions[n..2 * n].iter_mut().step_by(2) {
                p[2] -= lowered[m];
            }
            turned_about(&disc, axes[m], angles[m])
        };
        found_by_search_and_by_all_pairs(&joined(&turn(0), &turn(1), d));
    }
}

/// `pairs` collects every accepted pair, counted on its stop, and
/// stops early once the stop is reached.
#[test]
fn the_search_counts_on_its_stop() {
    let mesh = soup_within(16);
    let n = candidates(&mesh).len();
    let tree = unturned(&mesh, None);
    let all = |_: FaceId, _: FaceId| true;
    let stop = Stop::at(n + 1);
    let found = tree.pairs(&all, 10, &stop).finish();
    assert_eq!((found.pairs.len(), found.unlisted), (10, n - 10));
    assert!(!stop.reached());
    let stop = Stop::at(n / 2);
    let found = tree.pairs(&all, 10, &stop).finish();
    assert!(stop.reached());
    assert!(found.pairs.len() + found.unlisted < n, "{n}");
}
