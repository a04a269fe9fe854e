//! Issue 16.4 acceptance: a degenerate face whose vertex lies inside its
//! opposite edge is flipped away (SPEC 1), and the level sets of the
//! repaired mesh equal those of the same mesh built without the sliver
//! (counts of every kind, exact areas of S_O, L-, L+ and of the F
//! regions), in the slicing plane and elsewhere; what no flip repairs is
//! refused by name (exit 3, no output file); the command line says how
//! many faces it flipped, and `verify` accepts the output.
//!
//! A sliver is made by splitting an edge `p-q` of a closed mesh at points
//! `m_i` strictly inside it on one side only: the face `(p, q, r)` becomes
//! the fan `(p, m_1, r), (m_1, m_2, r), ..., (m_k, q, r)`, and the gap
//! against the unchanged face `(q, p, s)` is closed by the zero-area fan
//! `(p, q, m_k), (p, m_k, m_(k-1)), ..., (p, m_2, m_1)`. The mesh without
//! the sliver is the original one.

mod common;

use wmslice::classify::{ExtremumKind, Facing, RidgeKind};
use wmslice::datasets::{self, expected::expected};
use wmslice::exact::rational::Rat;
use wmslice::ids::{FaceId, VertexId};
use wmslice::levelset::{LevelSet, Loop};
use wmslice::mesh::flip::{repair_degenerate, Unflippable};
use wmslice::mesh::io::ExactPositions;
use wmslice::mesh::prepare::{prepare_exact_with, CollapsedFaces, Repairs};
use wmslice::mesh::validate::{validate, Defect};
use wmslice::nest::Role;
use wmslice::{Mesh, Slicer};

/// `mesh` with edge `(t[k], t[k+1])` of face `face` split at the points
/// `p + (q - p) j / (n + 1)`, `j = 1..=n` (exact for dyadic coordinates
/// and `n + 1` a power of two), on that face's side only, and the gap
/// closed by a fan of `n` zero-area faces.
fn with_sliver_fan(mesh: &Mesh, face: usize, k: usize, n: usize) -> Mesh {
    let mut m = mesh.clone();
    let t = m.faces[face];
    let (p, q, r) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
    let (pp, pq) = (m.pos(p), m.pos(q));
    let first = m.positions.len() as u32;
    for j in 1..=n {
        let f = j as f64 / (n + 1) as f64;
        m.positions
            .push([0, 1, 2].map(|i| pp[i] + (pq[i] - pp[i]) * f));
    }
    let mid = |j: usize| VertexId(first + j as u32 - 1);
    // The face's side: p, m_1, ..., m_n, q.
    let chain: Vec<VertexId> = std::iter::once(p)
        .chain((1..=n).map(mid))
        .chain(std::iter::once(q))
        .collect();
    m.faces[face] = [chain[0], chain[1], r];
    for w in chain.windows(2).skip(1) {
        m.faces.push([w[0], w[1], r]);
    }
    // The zero-area fan from p.
    m.faces.push([p, q, mid(n)]);
    for j in (2..=n).rev() {
        m.faces.push([p, mid(j), mid(j - 1)]);
    }
    m
}

/// Counts of every kind and the exact areas of a level set.
fn summary(ls: &LevelSet) -> String {
    let sum = |l: &[Loop]| {
        l.iter()
            .fold(Rat::from_integer(0.into()), |a, l| a + l.area())
    };
    let outer = ls.contours.iter().filter(|l| l.role == Role::Outer).count();
    let facing = |f: Facing| ls.regions.iter().filter(|r| r.facing == f).count();
    let area_f = |f: Facing| {
        ls.regions
            .iter()
            .filter(|r| r.facing == f)
            .fold(Rat::from_integer(0.into()), |a, r| a + &r.area)
    };
    let mut region_areas: Vec<Rat> = ls.regions.iter().map(|r| r.area.clone()).collect();
    region_areas.sort();
    let ridges = |k: RidgeKind, c: bool| {
        ls.ridges
            .iter()
            .filter(|r| r.kind == k && r.closed == c)
            .count()
    };
    let pts = |k: ExtremumKind| ls.extrema.iter().filter(|p| p.kind == k).count();
    let mut saddles: Vec<u32> = ls.saddles.iter().map(|s| s.branches).collect();
    saddles.sort_unstable();
    let loops = |l: &[Loop]| (l.len(), l.iter().filter(|l| l.role == Role::Hole).count());
    format!(
        "S_O {outer}+{} {} | L- {:?} {} | L+ {:?} {} | F up {} down {} flat {} {} {} {region_areas:?} | ridges {} {} valleys {} {} | min {} max {} | saddles {saddles:?}",
        ls.contours.len() - outer,
        sum(&ls.contours),
        loops(&ls.below),
        sum(&ls.below),
        loops(&ls.above),
        sum(&ls.above),
        facing(Facing::Up),
        facing(Facing::Down),
        facing(Facing::Flat),
        area_f(Facing::Up),
        area_f(Facing::Down),
        ridges(RidgeKind::Ridge, false),
        ridges(RidgeKind::Ridge, true),
        ridges(RidgeKind::Valley, false),
        ridges(RidgeKind::Valley, true),
        pts(ExtremumKind::Min),
        pts(ExtremumKind::Max),
    )
}

/// The slices of `got` and `want` at `levels` agree; `got` is repaired
/// first and must need exactly `flips` flips and validate cleanly.
fn same_levels(name: &str, got: &Mesh, want: &Mesh, levels: &[Rat], flips: usize) {
    let repaired = repair_degenerate(got);
    assert_eq!(repaired.flips.len(), flips, "{name}: {:?}", repaired.flips);
    let report = validate(&repaired.mesh);
    assert!(report.defects.is_empty(), "{name}: {report}");
    assert_eq!(report.volume, validate(want).volume, "{name}: volume");
    let (a, b) = (
        Slicer::new(&repaired.mesh).unwrap(),
        Slicer::new(want).unwrap(),
    );
    for c in levels {
        let (x, y) = (a.slice_at(c), b.slice_at(c));
        let (x, y) = (
            x.unwrap_or_else(|e| panic!("{name} at {c}: {e}")),
            y.unwrap(),
        );
        assert_eq!(summary(&x), summary(&y), "{name} at {c}");
    }
}

/// The dataset's hand-derived levels and the midpoints between them.
fn levels_of(name: &str) -> Vec<Rat> {
    let zs: Vec<Rat> = expected()
        .iter()
        .filter(|e| e.dataset == name)
        .map(|e| Rat::new(e.level.0.into(), e.level.1.into()))
        .collect();
    let two = Rat::from_integer(2.into());
    let mids: Vec<Rat> = zs.windows(2).map(|w| (&w[0] + &w[1]) / &two).collect();
    zs.into_iter().chain(mids).collect()
}

#[test]
fn a_sliver_on_any_edge_of_any_dataset_is_flipped_away_and_the_levels_are_unchanged() {
    let mut in_plane = 0;
    for d in datasets::all() {
        let mesh = d.build();
        let levels = levels_of(d.name);
        // A spread of faces and each of their edges, including horizontal
        // edges at degenerate heights (slivers in the slicing plane).
        let step = (mesh.num_faces() / 7).max(1);
        for face in (0..mesh.num_faces()).step_by(step) {
            for k in 0..3 {
                let t = mesh.faces[face];
                let (p, q) = (mesh.pos(t[k]), mesh.pos(t[(k + 1) % 3]));
                if p[2] == q[2] && levels.iter().any(|c| *c == Rat::from_float(p[2]).unwrap()) {
                    in_plane += 1;
                }
                let got = with_sliver_fan(&mesh, face, k, 1);
                same_levels(
                    &format!("{} f{face} corner {k}", d.name),
                    &got,
                    &mesh,
                    &levels,
                    1,
                );
            }
        }
    }
    assert!(in_plane >= 10, "only {in_plane} slivers in a slicing plane");
}

#[test]
fn a_fan_of_slivers_on_one_edge_is_flipped_away_in_order() {
    for d in ["unit_cube", "double_torus", "peg_cube"] {
        let mesh = datasets::by_name(d).unwrap().build();
        for (face, n) in [(0, 3), (1, 7), (5, 1)] {
            let got = with_sliver_fan(&mesh, face, 0, n);
            let deg = validate(&got)
                .defects
                .iter()
                .filter(|x| matches!(x, Defect::DegenerateFace { .. }))
                .count();
            assert_eq!(deg, n, "{d}: the unrepaired mesh has {n} degenerate faces");
            same_levels(
                &format!("{d} f{face} fan of {n}"),
                &got,
                &mesh,
                &levels_of(d),
                n,
            );
        }
    }
}

#[test]
fn an_unrepaired_sliver_is_refused_by_the_slicer_and_named_flippable() {
    let mesh = datasets::by_name("unit_cube").unwrap().build();
    let got = with_sliver_fan(&mesh, 0, 0, 1);
    let t = mesh.faces[0];
    let report = validate(&got);
    assert!(!report.is_accepted());
    let sliver = FaceId::from_idx(got.num_faces() - 1);
    assert!(
        report.defects.iter().any(|d| matches!(d,
            Defect::DegenerateFace { face, why: Unflippable::Flippable { apex, edge, .. } }
                if *face == sliver && *apex == VertexId(8) && *edge == [t[0], t[1]])),
        "{report}"
    );
    assert!(matches!(
        Slicer::new(&got),
        Err(wmslice::SliceError::InvalidMesh(_))
    ));
}

#[test]
fn repair_is_the_same_on_every_thread_count() {
    let mesh = datasets::by_name("grid").unwrap().build();
    let mut got = mesh.clone();
    for face in [3, 30, 60, 90] {
        got = with_sliver_fan(&got, face, 1, 3);
    }
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let r = repair_degenerate(&got);
                (r.mesh.into_owned(), r.flips)
            })
    };
    let one = on(1);
    assert_eq!(one.1.len(), 12);
    for threads in [2, 3] {
        assert_eq!(on(threads), one);
    }
}

/// Two vertices at one position: no flip removes the face. The message
/// names the remedy, and the remedy works: welded, with the faces that
/// then repeat a vertex dropped, the mesh is the cube again.
#[test]
fn coincident_vertices_are_refused_by_name() {
    let mesh = datasets::by_name("unit_cube").unwrap().build();
    let mut got = with_sliver_fan(&mesh, 0, 0, 1);
    let p = mesh.faces[0][0];
    got.positions[8] = got.pos(p);
    let r = repair_degenerate(&got);
    assert!(r.flips.is_empty());
    let report = validate(&r.mesh);
    let named = report.defects.iter().find(|d| {
        matches!(d,
        Defect::DegenerateFace { why: Unflippable::CoincidentVertices { a, b }, .. }
            if [*a, *b].contains(&p) && [*a, *b].contains(&VertexId(8)))
    });
    let named = named.unwrap_or_else(|| panic!("{report}"));
    assert!(
        named
            .to_string()
            .contains("--weld merges them, and --drop-collapsed"),
        "{named}"
    );
    let repaired = prepare_exact_with(
        got,
        &ExactPositions::default(),
        None,
        Repairs::from_flags(true, true),
    )
    .unwrap();
    let report = validate(&repaired.mesh);
    assert!(report.is_accepted(), "{report}");
    assert_eq!(repaired.mesh.num_faces(), mesh.num_faces());
}

/// Two collinear faces on the same three vertices: the face beyond is the
/// same triangle.
#[test]
fn a_flat_pillow_is_refused_by_name() {
    let m = Mesh::from_raw(
        vec![[0.0, 0.0, 0.0], [2.0, 2.0, 2.0], [1.0, 1.0, 1.0]],
        vec![[0, 1, 2], [1, 0, 2]],
    );
    let r = repair_degenerate(&m);
    assert!(r.flips.is_empty());
    let report = validate(&r.mesh);
    assert!(
        report.defects.iter().any(|d| matches!(
            d,
            Defect::DegenerateFace {
                why: Unflippable::SameTriangleBeyond {
                    apex: VertexId(2),
                    ..
                },
                ..
            }
        )),
        "{report}"
    );
    assert!(!report.is_accepted());
}

/// A sliver on an open edge: no face beyond to flip with.
#[test]
fn a_sliver_on_an_open_edge_is_refused_by_name() {
    let mesh = datasets::by_name("unit_cube").unwrap().build();
    let t = mesh.faces[0];
    let mut got = with_sliver_fan(&mesh, 0, 0, 1);
    // Remove the face beyond the split edge (the one with q -> p).
    let beyond = got
        .faces
        .iter()
        .position(|f| (0..3).any(|k| f[k] == t[1] && f[(k + 1) % 3] == t[0]))
        .unwrap();
    got.faces.remove(beyond);
    let r = repair_degenerate(&got);
    assert!(r.flips.is_empty());
    let report = validate(&r.mesh);
    assert!(
        report.defects.iter().any(|d| matches!(
            d,
            Defect::DegenerateFace {
                why: Unflippable::NoFaceBeyond {
                    apex: VertexId(8),
                    ..
                },
                ..
            }
        )),
        "{report}"
    );
    assert!(report
        .defects
        .iter()
        .any(|d| matches!(d, Defect::OpenEdge { .. })));
}

/// The unit box with its top at the `f32` `0.6` and a vertex meant to lie
/// on the diagonal `0-5` of the side face `(0, 1, 5)` (at a tenth of it),
/// written as `f32` decimals, as a CAD export has it: as read the vertex is
/// a hair off the diagonal; snapped to 1/1000 it is exactly on it, and the
/// sliver is flipped away.
fn cad_box_with_sliver() -> (Mesh, Mesh) {
    let (p, f) = common::unit_box(f64::from(0.6f32));
    let mesh = Mesh::from_raw(p, f);
    assert_eq!(mesh.faces[4], [VertexId(0), VertexId(1), VertexId(5)]);
    let mut got = with_sliver_fan(&mesh, 4, 2, 1);
    got.positions[8] = [f64::from(0.1f32), 0.0, f64::from(0.06f32)];
    (got, mesh)
}

#[test]
fn a_cad_sliver_made_exact_by_snapping_is_flipped_sliced_and_verified() {
    let (got, mesh) = cad_box_with_sliver();
    let degenerate = |m: &Mesh| {
        validate(m)
            .defects
            .iter()
            .filter(|d| matches!(d, Defect::DegenerateFace { .. }))
            .count()
    };
    assert_eq!(
        degenerate(&got),
        0,
        "as read, the vertex is off the diagonal"
    );
    let q = Rat::new(1.into(), 1000.into());
    let snapped = wmslice::mesh::snap::snap(&got, &q).unwrap();
    let plain = wmslice::mesh::snap::snap(&mesh, &q).unwrap();
    assert_eq!(degenerate(&snapped.mesh), 1);
    // Levels in grid units: the bottom, the sliver's height, the top, and
    // between.
    let levels: Vec<Rat> = [0, 30, 60, 300, 600]
        .iter()
        .map(|&z| Rat::from_integer(z.into()))
        .collect();
    same_levels("snapped CAD box", &snapped.mesh, &plain.mesh, &levels, 1);

    // The command line: the flip is noted, the result verifies.
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("cad.off");
    let mut text = format!("OFF\n{} {} 0\n", got.num_vertices(), got.num_faces());
    for p in &got.positions {
        let f = p.map(|x| x as f32);
        text += &format!("{} {} {}\n", f[0], f[1], f[2]);
    }
    for t in &got.faces {
        text += &format!("3 {} {} {}\n", t[0].0, t[1].0, t[2].0);
    }
    std::fs::write(&file, text).unwrap();
    let out = dir.path().join("out.json");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_owned();
    let (code, _, err) = common::wmslice(&[
        "slice",
        &s(&file),
        "--snap",
        "0.001",
        "--at",
        "0.06",
        "--at",
        "0.6",
        "--at",
        "0",
        "--format",
        "json",
        "--exact",
        "-o",
        &s(&out),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("flipped 1 degenerate faces"), "{err}");
    let (code, said, err) = common::wmslice(&["verify", &s(&file), &s(&out)]);
    assert_eq!(code, 0, "{said}{err}");
    // The header's hash is that of the mesh as sliced (repaired).
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let repaired = repair_degenerate(&snapped.mesh).mesh.into_owned();
    assert_eq!(
        doc["mesh"]["sha256"].as_str().unwrap(),
        wmslice::output::json::mesh_sha256(&repaired)
    );
}

/// `mesh` as OFF text, every coordinate exactly (shortest round-trip).
fn off_text(mesh: &Mesh) -> String {
    let mut text = format!("OFF\n{} {} 0\n", mesh.num_vertices(), mesh.num_faces());
    for p in &mesh.positions {
        text += &format!("{:?} {:?} {:?}\n", p[0], p[1], p[2]);
    }
    for t in &mesh.faces {
        text += &format!("3 {} {} {}\n", t[0].0, t[1].0, t[2].0);
    }
    text
}

/// `mesh` written as OFF ([`off_text`]) to `name` in a fresh directory:
/// the directory (removed when dropped), the file's path and an output
/// path beside it.
fn off_in_tempdir(mesh: &Mesh, name: &str) -> (tempfile::TempDir, String, String) {
    let dir = tempfile::tempdir().unwrap();
    let path = |n: &str| dir.path().join(n).to_str().unwrap().to_owned();
    let (file, out) = (path(name), path("out.json"));
    std::fs::write(&file, off_text(mesh)).unwrap();
    (dir, file, out)
}

#[test]
fn an_unrepairable_mesh_exits_3_naming_the_face_and_writes_nothing() {
    let (mut got, _) = cad_box_with_sliver();
    got.positions[8] = got.positions[0];
    let (_dir, file, out) = off_in_tempdir(&got, "bad.off");
    let (code, _, err) = common::wmslice(&[
        "slice", &file, "--at", "0.3", "--format", "json", "-o", &out,
    ]);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains(
            "is degenerate (its vertices are collinear): vertices v0 and v8 are at one position"
        ),
        "{err}"
    );
    assert!(!std::path::Path::new(&out).exists());
    let (code, said, _) = common::wmslice(&["check", &file]);
    assert_eq!(code, 3);
    assert!(said.contains("error: face f13 is degenerate"), "{said}");
}

/// A vertex a CAD export puts a hair from another (here 1e-4 along the
/// box's diagonal from vertex 0, as `f32`) is a valid mesh as read; on the
/// grid 1/1000 both land on one grid point, two faces repeat a vertex, and
/// the mesh is refused (no edge flip removes a face with two corners on
/// one vertex). The command line says snapping did it and how to avoid
/// it, and reports the refused mesh in the file's units, not in grid
/// steps.
/// [`cad_box_with_sliver`] with the sliver's vertex a hair from vertex 0
/// (1e-4 along the box's diagonal, as `f32`), and the box without it.
fn cad_box_with_near_vertex() -> (Mesh, Mesh) {
    let (mut got, mesh) = cad_box_with_sliver();
    got.positions[8] = [f64::from(1e-4f32), 0.0, f64::from(6e-5f32)];
    (got, mesh)
}

#[test]
fn faces_snapping_collapses_are_refused_with_the_snap_named() {
    let (got, _) = cad_box_with_near_vertex();
    assert!(validate(&got).is_accepted(), "{}", validate(&got));
    let (_dir, file, out) = off_in_tempdir(&got, "near.off");
    let (code, _, err) =
        common::wmslice(&["slice", &file, "--snap", "0.001", "--at", "0.3", "-o", &out]);
    assert_eq!(code, 3, "{err}");
    assert!(!std::path::Path::new(&out).exists());
    assert!(err.contains("1 vertices merged"), "{err}");
    assert!(
        err.contains("snapping put two corners of 2 faces on one grid point"),
        "{err}"
    );
    assert!(err.contains("repeats a vertex"), "{err}");
    // The box is 1 x 1 x 0.6 in the file's units (1000 x 1000 x 600 grid
    // steps).
    assert!(err.contains("bbox       [0, 0, 0] .. [1, 1, 0.6]"), "{err}");
    // The same file on a grid fine enough keeps the vertices apart.
    let (code, _, err) = common::wmslice(&["check", &file, "--snap", "0.000001"]);
    assert_eq!(code, 0, "{err}");
}

/// The file of the test above with `--drop-collapsed`: the two faces
/// snapping collapsed are removed (they have no area), what is left is the
/// box built without the extra vertex (the same levels, exactly), the
/// header says how many went, and `verify` removes them too. Without the
/// header's key, `verify` loads the mesh as the default mode does and
/// refuses it.
#[test]
fn faces_snapping_collapses_are_dropped_on_request_and_verified() {
    let (got, mesh) = cad_box_with_near_vertex();
    let q = Rat::new(1.into(), 1000.into());
    let p = prepare_exact_with(
        got.clone(),
        &ExactPositions::default(),
        Some(&q),
        CollapsedFaces::Drop.into(),
    )
    .unwrap();
    assert_eq!(p.dropped.as_ref().map(Vec::len), Some(2));
    assert!(p.flips.is_empty());
    let plain = wmslice::mesh::snap::snap(&mesh, &q).unwrap();
    let levels: Vec<Rat> = [0, 30, 60, 300, 600]
        .iter()
        .map(|&z| Rat::from_integer(z.into()))
        .collect();
    same_levels("collapsed faces dropped", &p.mesh, &plain.mesh, &levels, 0);
    // The default mode leaves them for validation to refuse.
    let kept = prepare_exact_with(
        got.clone(),
        &ExactPositions::default(),
        Some(&q),
        CollapsedFaces::Refuse.into(),
    )
    .unwrap();
    assert!(kept.dropped.is_none());
    assert!(!validate(&kept.mesh).is_accepted());

    let (dir, file, out) = off_in_tempdir(&got, "near.off");
    let (code, _, err) = common::wmslice(&[
        "slice",
        &file,
        "--snap",
        "0.001",
        "--drop-collapsed",
        "--at",
        "0.06",
        "--at",
        "0.3",
        "--format",
        "json",
        "--exact",
        "-o",
        &out,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("removed 2 faces that use one vertex twice"),
        "{err}"
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["mesh"]["dropped_collapsed"], 2);
    assert_eq!(
        doc["mesh"]["sha256"].as_str().unwrap(),
        wmslice::output::json::mesh_sha256(&p.mesh)
    );
    let (code, said, err) = common::wmslice(&["verify", &file, &out]);
    assert_eq!(code, 0, "{said}{err}");
    let bare = dir.path().join("bare.json");
    std::fs::write(&bare, text.replace(r#","dropped_collapsed":2"#, "")).unwrap();
    let (code, _, err) = common::wmslice(&["verify", &file, bare.to_str().unwrap()]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("repeats a vertex"), "{err}");
}
