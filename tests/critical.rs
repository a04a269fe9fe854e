//! The critical values and the Reeb graph (`wmslice::critical`), checked
//! against answers derived by hand, against the independent slow path
//! (`critical::brute_force`: the full level set at every vertex height),
//! against the loops of the slicer at the regular heights between them,
//! and against the z-mirror of the mesh and the mesh renumbered.

mod common;

use common::slab;
use proptest::prelude::*;
use wmslice::critical::{self, brute_force, CriticalReport, NodeKind};
use wmslice::datasets::cross_check;
use wmslice::exact::rational::Rat;
use wmslice::{datasets, Mesh, Slicer};

fn report(mesh: &Mesh) -> CriticalReport {
    critical::analyze(&Slicer::new(mesh).expect("accepted")).expect("no internal error")
}

fn kinds(r: &CriticalReport) -> Vec<NodeKind> {
    r.reeb.nodes.iter().map(|n| n.kind).collect()
}

fn heights(r: &CriticalReport) -> Vec<String> {
    r.levels.iter().map(|l| l.z.to_string()).collect()
}

fn loop_counts(r: &CriticalReport) -> Vec<(usize, usize)> {
    r.levels.iter().map(|l| (l.below, l.above)).collect()
}

/// Everything the report claims, checked independently:
/// - its levels equal the slow classification at every vertex height;
/// - between consecutive critical heights (and below the first, above the
///   last) the arcs crossing the midpoint number the slicer's loops there;
/// - node heights are level heights, arcs go up, and at each level the
///   nodes' below/above counts are at most the level's (regular contours
///   passing a critical height are not in a node);
/// - the Reeb graph has the mesh's components, and its cycles plus the
///   nodes' genus are the mesh's genus (from validation, not from the
///   report).
fn check(mesh: &Mesh) -> Result<(), TestCaseError> {
    let slicer = Slicer::new(mesh).expect("accepted");
    let r = critical::analyze(&slicer).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let slow = brute_force::classify_all(&slicer).expect("slices");
    prop_assert_eq!(&r.levels, &slow);
    let two = Rat::from_integer(2.into());
    for w in r.levels.windows(2) {
        let mid = (&w[0].z + &w[1].z) / &two;
        let ls = slicer.slice_at(&mid).expect("slices");
        prop_assert_eq!(r.reeb.arcs_across(&mid), ls.contours.len(), "at {}", mid);
        prop_assert_eq!(w[0].above, ls.contours.len());
        prop_assert_eq!(w[1].below, ls.contours.len());
    }
    if let (Some(first), Some(last)) = (r.levels.first(), r.levels.last()) {
        prop_assert_eq!(first.below, 0);
        prop_assert_eq!(last.above, 0);
    }
    for &[a, b] in &r.reeb.arcs {
        prop_assert!(r.reeb.nodes[a].z < r.reeb.nodes[b].z);
    }
    for (i, l) in r.levels.iter().enumerate() {
        let at: Vec<_> = r.reeb.nodes.iter().filter(|n| n.level == i).collect();
        prop_assert!(!at.is_empty(), "level {} has no node", l.z);
        prop_assert!(at.iter().all(|n| n.z == l.z));
        let (b, u) = at
            .iter()
            .fold((0, 0), |(b, u), n| (b + n.below, u + n.above));
        prop_assert!(b <= l.below && u <= l.above);
        // What passes the level without a node is one loop below and one
        // above, so the differences agree.
        prop_assert_eq!(l.below - b, l.above - u);
        let saddles: usize = at.iter().map(|n| n.saddles.len()).sum();
        prop_assert_eq!(saddles, l.saddles.len());
    }
    let v = wmslice::mesh::validate::validate(mesh);
    prop_assert_eq!(Some(r.components), v.stats.components);
    prop_assert_eq!(Some(r.reeb.components()), v.stats.components);
    let genus = u64::try_from(v.stats.genus.expect("closed")).expect("orientable");
    prop_assert_eq!(r.genus, genus);
    let node_genus: u64 = r.reeb.nodes.iter().map(|n| n.genus).sum();
    prop_assert_eq!(r.reeb.cycles() + node_genus, genus);
    Ok(())
}

/// The mesh reflected in `z = 0`, faces turned to stay outward.
fn mirror(mesh: &Mesh) -> Mesh {
    let mut out = mesh.clone();
    for p in &mut out.positions {
        p[2] = -p[2];
    }
    for f in &mut out.faces {
        f.swap(1, 2);
    }
    out
}

/// Mirroring swaps below and above, minima and maxima, faces up and down,
/// ridges and valleys, and negates the heights; saddles keep their `m`.
fn check_mirror(mesh: &Mesh) -> Result<(), TestCaseError> {
    let a = report(mesh);
    let b = report(&mirror(mesh));
    prop_assert_eq!(a.levels.len(), b.levels.len());
    for (x, y) in a.levels.iter().zip(b.levels.iter().rev()) {
        prop_assert_eq!(&x.z, &-y.z.clone());
        prop_assert_eq!((x.below, x.above), (y.above, y.below));
        prop_assert_eq!((x.minima, x.maxima), (y.maxima, y.minima));
        prop_assert_eq!((x.faces_up, x.faces_down), (y.faces_down, y.faces_up));
        prop_assert_eq!((x.ridges, x.valleys), (y.valleys, y.ridges));
        let (mut s, mut t) = (x.saddles.clone(), y.saddles.clone());
        s.sort_unstable();
        t.sort_unstable();
        prop_assert_eq!(s, t);
    }
    prop_assert_eq!(a.reeb.arcs.len(), b.reeb.arcs.len());
    prop_assert_eq!(a.reeb.nodes.len(), b.reeb.nodes.len());
    Ok(())
}

/// Renumbering the vertices and faces (`cross_check::relabelled`, on the
/// mesh as sliced) changes nothing but the order of saddles, which are
/// listed by vertex id; the Reeb graph keeps its nodes' kinds and its
/// arcs.
fn check_relabelled(mesh: &Mesh) -> Result<(), TestCaseError> {
    let slicer = Slicer::new(mesh).expect("accepted");
    let a = critical::analyze(&slicer).map_err(|e| TestCaseError::fail(e.to_string()))?;
    let (m, _, _) = cross_check::relabelled(slicer.mesh());
    let b = report(&m);
    let sorted = |r: &CriticalReport| {
        let mut levels = r.levels.clone();
        for l in &mut levels {
            l.saddles.sort_unstable();
        }
        let mut kinds = kinds(r);
        kinds.sort_unstable();
        (levels, kinds, r.reeb.arcs.len())
    };
    prop_assert_eq!(sorted(&a), sorted(&b));
    Ok(())
}

#[test]
fn every_dataset_agrees_with_the_slow_path_and_its_mirror() {
    for d in datasets::all() {
        let mesh = d.build();
        check(&mesh).unwrap_or_else(|e| panic!("{}: {e}", d.name));
        check(&mirror(&mesh)).unwrap_or_else(|e| panic!("{} mirrored: {e}", d.name));
        check_mirror(&mesh).unwrap_or_else(|e| panic!("{}: {e}", d.name));
        check_relabelled(&mesh).unwrap_or_else(|e| panic!("{} relabelled: {e}", d.name));
    }
}

/// The unit cube: a down flat at 0 and an up flat at 1, one contour
/// between them.
#[test]
fn unit_cube_is_two_plateaus_and_one_arc() {
    let r = report(&datasets::by_name("unit_cube").unwrap().build());
    assert_eq!(heights(&r), ["0", "1"]);
    assert_eq!(kinds(&r), [NodeKind::Plateau, NodeKind::Plateau]);
    assert_eq!(r.reeb.arcs, [[0, 1]]);
    assert_eq!((r.levels[0].faces_down, r.levels[1].faces_up), (1, 1));
    assert_eq!(loop_counts(&r), [(0, 1), (1, 0)]);
}

/// The lying torus: its bottom is a closed valley ring at -1 (just above
/// it two loops, inside and outside the ring), its top a closed ridge ring
/// at 2. The equator rings at 0 and 1 are transversal (regular): the two
/// loops pass them. Two arcs between the two rings, one cycle = genus 1.
#[test]
fn lying_torus_is_two_rings_and_two_arcs() {
    let r = report(&datasets::by_name("lying_torus").unwrap().build());
    assert_eq!(heights(&r), ["-1", "2"]);
    assert_eq!(kinds(&r), [NodeKind::Valley, NodeKind::Ridge]);
    assert_eq!(r.reeb.arcs, [[0, 1], [0, 1]]);
    assert_eq!(loop_counts(&r), [(0, 2), (2, 0)]);
    assert_eq!((r.levels[0].valleys, r.levels[1].ridges), (1, 1));
    assert_eq!((r.reeb.cycles(), r.genus), (1, 1));
}

/// The genus-2 slab (see `datasets::shapes::double_torus`):
/// - z = 0: the bottom, one flat region with two holes; above it three
///   wall loops (outside, hole W, hole E).
/// - z = 1: of the three vertices at 1, `(1, 1)` and `(-1, 0)` lie on the
///   rims of holes E and W (their walls go down: regular), `(0, -1)` is an
///   isolated minimum (a pit): a new loop above it.
/// - z = 2: `(0, 0)` is a monkey saddle whose three low sectors lead to
///   the dips at `(1, 1)`, `(-1, 0)`, `(0, -1)`: the E-hole loop, the
///   W-hole loop and the pit loop merge into one. The outer loop passes.
/// - z = 4: everything left is one connected level set (flat tops, the
///   ridges and the rims): one node of mixed kind, where both loops end.
///
/// Nodes 4, arcs 5 (three from the bottom, two of them to the saddle), one
/// component: 2 cycles = genus 2.
#[test]
fn double_torus_reeb_graph_by_hand() {
    let r = report(&datasets::by_name("double_torus").unwrap().build());
    assert_eq!(heights(&r), ["0", "1", "2", "4"]);
    assert_eq!(
        kinds(&r),
        [
            NodeKind::Plateau,
            NodeKind::Min,
            NodeKind::Saddle,
            NodeKind::Mixed
        ]
    );
    assert_eq!(r.reeb.arcs, [[0, 2], [0, 2], [0, 3], [1, 2], [2, 3]]);
    assert_eq!(loop_counts(&r), [(0, 3), (3, 4), (4, 2), (2, 0)]);
    assert_eq!(r.levels[2].saddles, [3]);
    let saddle = &r.reeb.nodes[2];
    assert_eq!((saddle.below, saddle.above, saddle.genus), (3, 1, 0));
    assert_eq!((r.reeb.cycles(), r.genus), (2, 2));
}

/// A lying torus with a flat top and bottom: the square annulus between
/// `[-1, 1]^2` and `[-2, 2]^2`, from z = 0 to 1. Its bottom is one down
/// flat (a node), its top one up flat; between them two wall loops,
/// outside and inside: 2 plateau nodes, 2 arcs, one cycle = genus 1.
#[test]
fn flat_lying_torus_is_two_plateaus_and_two_arcs() {
    let ring = |r: f64| [[-r, -r], [r, -r], [r, r], [-r, r]];
    let mut pos = Vec::new();
    for (r, z) in [(2.0, 0.0), (1.0, 0.0), (2.0, 1.0), (1.0, 1.0)] {
        pos.extend(ring(r).iter().map(|p| [p[0], p[1], z]));
    }
    let (ob, ib, ot, it) = (
        |k: usize| k % 4,
        |k: usize| 4 + k % 4,
        |k: usize| 8 + k % 4,
        |k: usize| 12 + k % 4,
    );
    let mut faces = Vec::new();
    for k in 0..4 {
        for q in [
            [ot(k), ot(k + 1), it(k + 1), it(k)],
            [ob(k), ib(k), ib(k + 1), ob(k + 1)],
            [ob(k), ob(k + 1), ot(k + 1), ot(k)],
            [ib(k), it(k), it(k + 1), ib(k + 1)],
        ] {
            let q = q.map(|v| v as u32);
            faces.push([q[0], q[1], q[2]]);
            faces.push([q[0], q[2], q[3]]);
        }
    }
    let r = report(&Mesh::from_raw(pos, faces));
    assert_eq!(heights(&r), ["0", "1"]);
    assert_eq!(kinds(&r), [NodeKind::Plateau, NodeKind::Plateau]);
    assert_eq!(r.reeb.arcs, [[0, 1], [0, 1]]);
    assert_eq!(loop_counts(&r), [(0, 2), (2, 0)]);
    assert_eq!((r.levels[0].faces_down, r.levels[1].faces_up), (1, 1));
    assert_eq!((r.reeb.cycles(), r.genus), (1, 1));
}

/// A box with a toroidal cavity: two components (the box, the cavity's
/// torus). The box's bottom and top are plateaus joined by one arc; the
/// cavity's valley ring (-1) and ridge ring (2) by two. Cycles
/// `5 arcs... 3 arcs - 4 nodes + 2 components = 1` = the cavity's genus.
#[test]
fn internal_torus_has_two_components() {
    let r = report(&datasets::by_name("internal_torus").unwrap().build());
    assert_eq!(heights(&r), ["-2", "-1", "2", "3"]);
    assert_eq!(
        kinds(&r),
        [
            NodeKind::Plateau,
            NodeKind::Valley,
            NodeKind::Ridge,
            NodeKind::Plateau
        ]
    );
    assert_eq!(r.reeb.arcs, [[0, 3], [1, 2], [1, 2]]);
    assert_eq!((r.reeb.components(), r.components), (2, 2));
    assert_eq!((r.reeb.cycles(), r.genus), (1, 1));
    assert_eq!(loop_counts(&r), [(0, 1), (1, 3), (3, 1), (1, 0)]);
}

/// A torus of `nu x nv` quads around the z axis, tilted about x by
/// `tilt`, with `noise` (in units of 1/8) added to each height, stored as
/// `f32` like an STL: a surface of genus 1 with many extrema and saddles
/// and no ties by construction except those the rounding makes.
fn noisy_torus(nu: usize, nv: usize, tilt: f64, noise: &[i8]) -> Mesh {
    let (big, small) = (8.0, 3.0);
    let mut pos = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        let u = std::f64::consts::TAU * i as f64 / nu as f64;
        for j in 0..nv {
            let v = std::f64::consts::TAU * j as f64 / nv as f64;
            let r = big + small * v.cos();
            let (x, y, z) = (r * u.cos(), r * u.sin(), small * v.sin());
            let (y, z) = (
                y * tilt.cos() - z * tilt.sin(),
                y * tilt.sin() + z * tilt.cos(),
            );
            let z = z + f64::from(noise[(i * nv + j) % noise.len()]) / 8.0;
            pos.push([x, y, z].map(|c| f64::from(c as f32)));
        }
    }
    let id = |i: usize, j: usize| ((i % nu) * nv + j % nv) as u32;
    let mut faces = Vec::with_capacity(2 * nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    Mesh::from_raw(pos, faces)
}

/// Quantizes every height of `mesh` to a multiple of `1 / q`: many
/// vertices at one height, flats and ridges appear.
fn quantized(mesh: &Mesh, q: f64) -> Mesh {
    let mut out = mesh.clone();
    for p in &mut out.positions {
        p[2] = (p[2] * q).round() / q;
    }
    out
}

/// `mesh` with every coordinate times `2^e` (exact for these meshes at
/// the exponents used: no bit falls below the subnormal range).
fn scaled(mesh: &Mesh, e: i32) -> Mesh {
    let mut out = mesh.clone();
    let f = 2f64.powi(e);
    for p in &mut out.positions {
        *p = p.map(|c| c * f);
    }
    out
}

/// The same report with every height times `2^e`.
fn check_scaled(mesh: &Mesh, e: i32) -> Result<(), TestCaseError> {
    let a = report(mesh);
    let b = report(&scaled(mesh, e));
    let f = if e >= 0 {
        Rat::from_integer(num_bigint::BigInt::from(1) << e as usize)
    } else {
        Rat::new(1.into(), num_bigint::BigInt::from(1) << (-e) as usize)
    };
    let mut want = a.levels.clone();
    for l in &mut want {
        l.z = &l.z * &f;
    }
    prop_assert_eq!(&b.levels, &want);
    prop_assert_eq!(&b.reeb.arcs, &a.reeb.arcs);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    /// Scaled by a power of two to either end of the double range, a mesh
    /// has the scaled critical heights and the same Reeb graph.
    #[test]
    fn scaled_meshes_give_scaled_answers(
        s in slab(), nu in 6usize..10, noise in proptest::collection::vec(-12i8..=12, 1..20),
        e in prop_oneof![Just(-1000), Just(-300), Just(300), Just(1000)],
    ) {
        check_scaled(&s.mesh(), e)?;
        let torus = noisy_torus(nu, 6, 0.7, &noise);
        prop_assume!(wmslice::mesh::validate::validate(&torus).is_accepted());
        check_scaled(&torus, e)?;
    }

    /// Slabs with integer heights: plateaus, ridges, valleys, saddles with
    /// ties everywhere, turned on their side (`rot`) so walls are flat.
    #[test]
    fn slabs_agree_with_the_slow_path(s in slab()) {
        let mesh = s.mesh();
        check(&mesh)?;
        check_mirror(&mesh)?;
        check_relabelled(&mesh)?;
    }

    /// Two slabs side by side or stacked with a gap: two components.
    #[test]
    fn two_slabs_agree_with_the_slow_path(a in slab(), b in slab(), up in any::<bool>()) {
        let (ma, mb) = (a.mesh(), b.mesh());
        let mut pos = ma.positions.clone();
        let n = pos.len() as u32;
        let shift = if up { [0.0, 0.0, 20.0] } else { [20.0, 0.0, 0.0] };
        pos.extend(mb.positions.iter().map(|p| [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]]));
        let mut faces: Vec<[u32; 3]> = ma.faces.iter().map(|f| f.map(|v| v.0)).collect();
        faces.extend(mb.faces.iter().map(|f| f.map(|v| v.0 + n)));
        check(&Mesh::from_raw(pos, faces))?;
    }

    /// Noisy tilted tori (genus 1, `f32` coordinates, many saddles), and
    /// the same with heights quantized so that ties make flats, ridges and
    /// degenerate saddles.
    #[test]
    fn noisy_tori_agree_with_the_slow_path(
        nu in 6usize..14, nv in 5usize..10, tilt in 0.0f64..1.6,
        noise in proptest::collection::vec(-12i8..=12, 1..40), q in 1u32..4,
    ) {
        let mesh = noisy_torus(nu, nv, tilt, &noise);
        prop_assume!(wmslice::mesh::validate::validate(&mesh).is_accepted());
        check(&mesh)?;
        check_mirror(&mesh)?;
        check_relabelled(&mesh)?;
        let flat = quantized(&mesh, f64::from(q));
        prop_assume!(wmslice::mesh::validate::validate(&flat).is_accepted());
        check(&flat)?;
    }
}
