//! One hand-made bad mesh per defect class: the exact defect kind and
//! element ids, and `wmslice check` exiting non-zero naming the defect.

use std::process::Command;
use wmslice::datasets;
use wmslice::ids::{FaceId, VertexId};
use wmslice::mesh::validate::{accept, validate, Defect, Turn};
use wmslice::Mesh;

const TETRA_POS: [[f64; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
const TETRA: [[u32; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

fn tetra() -> Mesh {
    Mesh::from_raw(TETRA_POS.to_vec(), TETRA.to_vec())
}

/// Two tetrahedra: the second shifted by `shift` and with vertices
/// renumbered through `map` (so they can share vertices).
fn two_tetras(shift: [f64; 3], map: [u32; 4]) -> Mesh {
    let mut pos = TETRA_POS.to_vec();
    for p in TETRA_POS {
        pos.push([p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]]);
    }
    let mut faces = TETRA.to_vec();
    for f in TETRA {
        faces.push(f.map(|v| map[v as usize]));
    }
    Mesh::from_raw(pos, faces)
}

fn v(i: u32) -> VertexId {
    VertexId(i)
}
fn f(i: u32) -> FaceId {
    FaceId(i)
}

#[test]
fn the_unit_tetrahedron_is_accepted_with_exact_volume() {
    let r = validate(&tetra());
    assert!(r.is_accepted(), "{r}");
    assert_eq!(r.stats.volume.as_deref(), Some("1/6"));
    assert_eq!(
        (
            r.stats.edges,
            r.stats.components,
            r.stats.euler_characteristic,
            r.stats.genus
        ),
        (Some(6), Some(1), Some(2), Some(0))
    );
}

#[test]
fn open_edges_name_their_single_face() {
    let mut m = tetra();
    m.faces.pop(); // drop face 3 = [1, 2, 3]
    let r = validate(&m);
    assert!(!r.is_accepted());
    let mut open: Vec<_> = r
        .defects
        .iter()
        .filter_map(|d| match d {
            Defect::OpenEdge { a, b, face } => Some((*a, *b, *face)),
            _ => None,
        })
        .collect();
    open.sort();
    assert_eq!(
        open,
        vec![(v(1), v(2), f(0)), (v(1), v(3), f(1)), (v(2), v(3), f(2))]
    );
}

#[test]
fn an_edge_in_four_faces_is_non_manifold() {
    // The second tetrahedron reuses vertices 0 and 1: edge 0-1 has 4 faces.
    let m = two_tetras([0., -1., -1.], [0, 1, 6, 7]);
    let r = validate(&m);
    assert!(
        r.defects.iter().any(|d| matches!(d,
        Defect::NonManifoldEdge { a, b, faces } if (*a, *b) == (v(0), v(1)) && faces.len() == 4)),
        "{r}"
    );
}

#[test]
fn two_tetrahedra_sharing_a_vertex_make_a_bowtie() {
    let m = two_tetras([-1., -1., -1.], [4, 5, 6, 0]);
    let r = validate(&m);
    assert!(
        r.defects.contains(&Defect::BowtieVertex {
            vertex: v(0),
            cycles: 2
        }),
        "{r}"
    );
}

#[test]
fn one_reversed_face_is_named_flipped() {
    let mut m = tetra();
    m.faces[3] = [v(1), v(3), v(2)];
    let r = validate(&m);
    assert_eq!(
        r.errors().cloned().collect::<Vec<_>>(),
        vec![Defect::FlippedFace { face: f(3) }]
    );
}

#[test]
fn an_inside_out_mesh_has_negative_volume() {
    let mut m = tetra();
    for t in &mut m.faces {
        t.swap(1, 2);
    }
    let r = validate(&m);
    assert_eq!(
        r.errors().cloned().collect::<Vec<_>>(),
        vec![Defect::NotOutward {
            volume: "-1/6".into()
        }]
    );
}

#[test]
fn a_flattened_tetrahedron_folds() {
    // Vertex 3 inside triangle 0-1-2 in the plane z = 0: faces 0 and 1 lie
    // in one plane on the same side of edge 0-1.
    let mut m = tetra();
    m.positions[3] = [0.25, 0.25, 0.0];
    let r = validate(&m);
    assert!(
        r.defects.contains(&Defect::Fold {
            a: v(0),
            b: v(1),
            faces: vec![f(0), f(1)]
        }),
        "{r}"
    );
}

#[test]
fn out_of_range_repeated_and_non_finite_are_named() {
    let mut m = tetra();
    m.faces.push([v(0), v(7), v(1)]);
    m.faces.push([v(2), v(2), v(1)]);
    m.positions[1][2] = f64::NAN;
    let r = validate(&m);
    assert!(r.defects.contains(&Defect::IndexOutOfRange {
        face: f(4),
        corner: 1,
        index: 7,
        vertices: 4
    }));
    assert!(r.defects.contains(&Defect::RepeatedVertex { face: f(5) }));
    assert!(r
        .defects
        .contains(&Defect::NonFiniteCoordinate { vertex: v(1) }));
}

/// Without proper triangles no edge table is built: the counts read "not
/// counted", never a zero that looks measured; the volume needs only
/// indices in range (a face repeating a vertex adds zero to it).
#[test]
fn counts_not_taken_are_reported_as_such_not_as_zero() {
    let mut m = tetra();
    m.faces.push([v(2), v(2), v(1)]);
    let r = validate(&m);
    assert_eq!(
        (
            r.stats.edges,
            r.stats.components,
            r.stats.euler_characteristic
        ),
        (None, None, None)
    );
    assert_eq!(r.stats.volume.as_deref(), Some("1/6"));
    let text = r.to_string();
    assert!(text.contains("edges      - (not counted"), "{text}");
    assert!(text.contains("volume     1/6"), "{text}");

    let mut m = tetra();
    m.faces.push([v(0), v(7), v(1)]);
    let r = validate(&m);
    assert_eq!((r.stats.edges, r.stats.volume.as_deref()), (None, None));
    assert!(r.to_string().contains("volume     - (not computed"), "{r}");
}
#[test]
fn duplicate_faces_are_named() {
    let mut m = tetra();
    m.faces.push(m.faces[2]);
    let r = validate(&m);
    assert!(
        r.defects.contains(&Defect::DuplicateFace {
            face: f(4),
            first: f(2),
            turn: Turn::Same,
        }),
        "{r}"
    );
}

/// Two bodies touching along a face (as a multibody file holds them): the
/// tetrahedron and its mirror below the plane z = 0, sharing the three
/// vertices there. The mirror's top face [0, 1, 2] is the tetrahedron's
/// bottom face [0, 2, 1] turned the other way.
#[test]
fn a_face_two_bodies_share_is_a_duplicate_turned_the_other_way() {
    let mut pos = TETRA_POS.to_vec();
    pos.push([0., 0., -1.]);
    let mut faces = TETRA.to_vec();
    faces.extend([[0, 1, 2], [0, 4, 1], [0, 2, 4], [1, 4, 2]]);
    let r = validate(&Mesh::from_raw(pos, faces));
    let duplicate = Defect::DuplicateFace {
        face: f(4),
        first: f(0),
        turn: Turn::Reversed,
    };
    assert!(r.defects.contains(&duplicate), "{r}");
    assert!(
        duplicate
            .to_string()
            .contains("turned the other way (two bodies"),
        "{duplicate}"
    );
    assert!(!r.is_accepted());
}

/// The tetrahedron with vertex 3 at `apex` and a vertex 4 at the midpoint
/// of edge 0-1, so that face 1 = [0, 1, 4] has zero area.
fn with_sliver(apex: [f64; 3]) -> Mesh {
    let mut pos = TETRA_POS.to_vec();
    pos[3] = apex;
    pos.push([0.5, 0., 0.]);
    Mesh::from_raw(
        pos,
        vec![
            [0, 2, 1],
            [0, 1, 4],
            [0, 4, 3],
            [4, 1, 3],
            [0, 3, 2],
            [1, 2, 3],
        ],
    )
}

#[test]
fn an_unrepaired_degenerate_face_is_refused_and_named_flippable() {
    // Face 1 = [0, 1, 4] is the segment v0-v1 with v4 at its midpoint (a
    // T-junction). Face 0 = [0, 2, 1] holds that whole segment; face 2 =
    // [0, 4, 3] holds v0-v4 and shares only v0 with it, face 3 = [4, 1, 3]
    // holds v4-v1 and shares only v1: both meet face 0 along a segment
    // outside their shared elements (SPEC 1), so unrepaired the mesh also
    // self-intersects. Every other pair meets only in what it shares:
    // faces 2 and 3 lie in the plane y = 0 on either side of their edge
    // v4-v3, face 1 meets its neighbours along its edges' line only where
    // they hold its edges.
    let m = with_sliver(TETRA_POS[3]);
    let r = validate(&m);
    assert!(!r.is_accepted(), "{r}");
    assert_eq!(
        r.defects,
        vec![
            Defect::DegenerateFace {
                face: f(1),
                why: wmslice::mesh::flip::Unflippable::Flippable {
                    apex: v(4),
                    edge: [v(0), v(1)],
                    beyond: f(0)
                }
            },
            Defect::SelfIntersection { a: f(0), b: f(2) },
            Defect::SelfIntersection { a: f(0), b: f(3) },
        ]
    );
    // Flipping edge 0-1 of faces 1 and 0 leaves an accepted mesh: no
    // T-junction is left, so no self-intersection either.
    let repaired = wmslice::mesh::flip::repair_degenerate(&m);
    assert_eq!(repaired.flips.len(), 1);
    assert_eq!(repaired.mesh.faces[1], [v(0), v(2), v(4)]);
    assert_eq!(repaired.mesh.faces[0], [v(2), v(1), v(4)]);
    let r = validate(&repaired.mesh);
    assert!(r.defects.is_empty(), "{r}");
}

#[test]
fn an_empty_mesh_is_rejected() {
    assert_eq!(validate(&Mesh::default()).defects, vec![Defect::Empty]);
}

fn write_off(dir: &std::path::Path, name: &str, m: &Mesh) -> std::path::PathBuf {
    let mut s = format!("OFF\n{} {} 0\n", m.positions.len(), m.faces.len());
    for p in &m.positions {
        s += &format!("{:?} {:?} {:?}\n", p[0], p[1], p[2]);
    }
    for t in &m.faces {
        s += &format!("3 {} {} {}\n", t[0].0, t[1].0, t[2].0);
    }
    let path = dir.join(name);
    std::fs::write(&path, s).unwrap();
    path
}

#[test]
fn check_exits_3_and_names_the_defect() {
    let dir = tempfile::tempdir().unwrap();
    let mut open = tetra();
    open.faces.pop();
    let mut flipped = tetra();
    flipped.faces[3] = [v(1), v(3), v(2)];
    let cases = [
        ("open.off", open, "open edge"),
        ("flipped.off", flipped, "is flipped"),
        (
            "bowtie.off",
            two_tetras([-1., -1., -1.], [4, 5, 6, 0]),
            "bowtie vertex v0",
        ),
    ];
    for (name, mesh, needle) in cases {
        let path = write_off(dir.path(), name, &mesh);
        let out = Command::new(env!("CARGO_BIN_EXE_wmslice"))
            .arg("check")
            .arg(&path)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(3), "{name}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains(needle), "{name}: {text}");
    }
    let good = write_off(dir.path(), "good.off", &tetra());
    let out = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(["check", "--json"])
        .arg(&good)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["stats"]["volume"], "1/6");
    assert_eq!(json["accepted"], true);
    assert_eq!(
        (
            json["unlisted_defects"].as_u64(),
            json["unlisted_count"].as_str()
        ),
        (Some(0), Some("exact"))
    );
}

#[test]
fn check_after_snapping_reports_measures_in_the_files_units() {
    // The unit tetrahedron scaled by 0.3 (stored as the double nearest
    // 0.3), snapped to 0.1: the corners become exactly 3/10, so the volume
    // is (3/10)^3 / 6 = 9/2000 and the box ends at the double nearest 0.3,
    // not at 3 grid steps.
    let mut m = tetra();
    for p in &mut m.positions {
        *p = p.map(|x| x * 0.3);
    }
    let dir = tempfile::tempdir().unwrap();
    let path = write_off(dir.path(), "small.off", &m);
    let out = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(["check", "--json", "--snap", "0.1"])
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["stats"]["volume"], "9/2000");
    assert_eq!(json["stats"]["bounding_box"][1][0].as_f64(), Some(0.3));
    assert_eq!(json["stats"]["bounding_box"][0][2].as_f64(), Some(0.0));
}

/// `check --json` reports a mesh that snapping refuses as JSON too (it
/// printed nothing on standard output): not accepted, one defect with the
/// kind and elements the Python package names, exit 3. A grid that is no
/// grid stays an argument error (exit 2, nothing on standard output).
#[test]
fn check_json_reports_a_refusal_by_snapping() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = tetra();
    for p in &mut m.positions {
        *p = p.map(|x| x * 2e-4);
    }
    let path = write_off(dir.path(), "tiny.off", &m);
    let check = |grid: &str| {
        Command::new(env!("CARGO_BIN_EXE_wmslice"))
            .args(["check", "--json", "--snap", grid])
            .arg(&path)
            .output()
            .unwrap()
    };
    // A millimetre grid under a 0.2 mm part: every face collapses.
    let out = check("0.001");
    assert_eq!(out.status.code(), Some(3));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["accepted"], false);
    assert!(json["stats"].is_null());
    let d = &json["defects"][0];
    assert_eq!(
        (&d["kind"], &d["faces"], &d["grid"], &d["severity"]),
        (
            &"snap_collapsed_everything".into(),
            &4.into(),
            &"1/1000".into(),
            &"error".into()
        )
    );
    assert_eq!(json["defects"].as_array().unwrap().len(), 1);
    // A grid so fine that a corner at 2e-4 is more than 2^53 steps out:
    // vertex 1 is the first such.
    let out = check("1e-300");
    assert_eq!(out.status.code(), Some(3));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(json["defects"][0]["kind"], "snap_out_of_range");
    assert_eq!(json["defects"][0]["vertex"], 1);
    let out = check("0");
    assert_eq!(out.status.code(), Some(2));
    assert!(out.stdout.is_empty());
}

#[test]
fn snapping_that_flattens_a_sliver_is_caught_and_named() {
    // A flat tetrahedron, apex 0.0001 above its base: valid as read, but
    // snapping to 0.001 puts the apex in the base plane, inside the base
    // triangle, folding faces onto each other.
    let mut m = tetra();
    m.positions[3] = [0.25, 0.25, 0.0001];
    assert!(validate(&m).is_accepted());
    let dir = tempfile::tempdir().unwrap();
    let path = write_off(dir.path(), "sliver.off", &m);
    let out = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(["check", "--snap", "0.001"])
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("fold onto each other"), "{text}");
    assert!(
        text.contains("snapped to grid 1/1000: 1 vertices moved"),
        "{text}"
    );
}

#[test]
fn validation_reports_the_same_on_one_and_on_several_threads() {
    // Volume, duplicates, topology, zero-area faces, folds and
    // self-intersections are found by passes that run side by side on a
    // pool: the report must not depend on its size.
    let mut duplicated = tetra();
    duplicated.faces.push(duplicated.faces[2]);
    duplicated.faces.push(duplicated.faces[0]);
    let flat_with_sliver = with_sliver([0.25, 0.25, 0.0]);
    let on = |m: &Mesh, threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| validate(m))
    };
    let mut kinds = Vec::new();
    for m in [&duplicated, &flat_with_sliver] {
        let one = on(m, 1);
        for d in &one.defects {
            kinds.push(std::mem::discriminant(d));
        }
        for threads in [2, 3] {
            let many = on(m, threads);
            assert_eq!(many.defects, one.defects);
            assert_eq!(many.stats, one.stats);
        }
    }
    // The meshes exercise every parallel pass's defect kind.
    for kind in [
        Defect::DuplicateFace {
            face: f(0),
            first: f(0),
            turn: Turn::Same,
        },
        Defect::DegenerateFace {
            face: f(0),
            why: wmslice::mesh::flip::Unflippable::CoincidentVertices { a: v(0), b: v(0) },
        },
        Defect::SelfIntersection { a: f(0), b: f(0) },
        Defect::Fold {
            a: v(0),
            b: v(0),
            faces: vec![],
        },
    ] {
        assert!(kinds.contains(&std::mem::discriminant(&kind)), "{kind:?}");
    }
}

#[test]
fn accepting_for_slicing_agrees_with_validation() {
    // `accept` skips the exact volume when a certified float sum shows it
    // positive: the verdict, and the report of a rejected mesh (volume
    // included), must be validation's.
    let mut inside_out = tetra();
    inside_out.faces.iter_mut().for_each(|t| t.swap(1, 2));
    let mut open = tetra();
    open.faces.pop();
    // Moved off the origin and without face 0: the three faces left sum to
    // 1/6 (the tetrahedron) minus face 0's -1/6 (det of (1,1,1), (1,2,1),
    // (2,1,1) is -1): 1/3, positive, so the filter decides it and the exact
    // value is made only for the report.
    let mut open_moved = tetra();
    open_moved
        .positions
        .iter_mut()
        .flatten()
        .for_each(|x| *x += 1.0);
    open_moved.faces.remove(0);
    let mut flat = tetra();
    flat.positions[3] = [0.25, 0.25, 0.0];
    let mut meshes = vec![
        ("inside out".to_string(), inside_out),
        ("open".to_string(), open),
        ("open, moved".to_string(), open_moved),
        ("flat".to_string(), flat),
        ("sliver".to_string(), with_sliver(TETRA_POS[3])),
        (
            "two tetrahedra".to_string(),
            two_tetras([3., 0., 0.], [4, 5, 6, 7]),
        ),
    ];
    for d in datasets::all() {
        meshes.push((d.name.to_string(), d.build()));
    }
    let mut rejected = 0;
    for (name, m) in &meshes {
        let full = validate(m);
        match accept(m) {
            Ok(topo) => {
                assert!(full.is_accepted(), "{name}: accepted, but {full}");
                assert_eq!(Some(topo.num_edges()), full.stats.edges, "{name}");
                assert_eq!(Some(topo.face_edges), full.topology.map(|t| t.face_edges));
            }
            Err(report) => {
                rejected += 1;
                assert!(!full.is_accepted(), "{name}: rejected, but {full}");
                assert_eq!(report.defects, full.defects, "{name}");
                assert_eq!(report.stats, full.stats, "{name}");
                assert_eq!(report.volume, full.volume, "{name}");
                if name == "open, moved" {
                    assert_eq!(report.stats.volume.as_deref(), Some("1/3"));
                }
            }
        }
    }
    // The sliver is not repaired here (`accept` takes the mesh as given).
    assert_eq!(rejected, 5);
}

#[test]
fn a_solid_inside_a_solid_is_refused_by_check_and_slice_not_sliced() {
    // A unit tetrahedron at (1, 1, 1) inside one scaled by 10 (x + y + z
    // <= 10 holds its corners), both facing outward: every face is sound
    // and the total volume positive, but the inner solid is counted twice.
    // Facing inward it is a cavity, and accepted.
    let mut nested = two_tetras([1., 1., 1.], [4, 5, 6, 7]);
    for p in &mut nested.positions[..4] {
        *p = p.map(|x| x * 10.0);
    }
    let mut cavity = nested.clone();
    for t in &mut cavity.faces[4..] {
        t.swap(1, 2);
    }
    assert!(validate(&cavity).is_accepted());
    let r = validate(&nested);
    assert_eq!(
        r.errors().cloned().collect::<Vec<_>>(),
        vec![Defect::MisnestedShell {
            face: f(4),
            facing: wmslice::mesh::validate::ShellFacing::Outward,
            winding: 1,
        }]
    );
    assert!(accept(&nested).is_err());
    let dir = tempfile::tempdir().unwrap();
    let path = write_off(dir.path(), "nested.off", &nested);
    let out_json = dir.path().join("out.json");
    for args in [vec!["check"], vec!["slice", "--at", "3/2", "-o"]] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_wmslice"));
        cmd.args(&args);
        if args[0] == "slice" {
            cmd.arg(&out_json);
        }
        let out = cmd.arg(&path).output().unwrap();
        assert_eq!(out.status.code(), Some(3), "{args:?}");
        let text = String::from_utf8_lossy(&out.stdout) + String::from_utf8_lossy(&out.stderr);
        assert!(
            text.contains("the shell of face f4 faces outward"),
            "{args:?}: {text}"
        );
        assert!(!text.contains("internal error"), "{text}");
    }
    assert!(!out_json.exists());
}

#[test]
fn open_edges_from_coincident_vertices_say_so() {
    // The tetrahedron with its last face on copies of its vertices (as an
    // indexed file with seams holds them; -0 equals +0): open edges, and
    // each copy named beside the vertex it coincides with. A closed mesh
    // gets no such note (its coincident vertices would intersect).
    let mut m = tetra();
    m.positions
        .extend([[1., -0.0, 0.], [0., 1., 0.], [0., 0., 1.]]);
    m.faces[3] = [v(4), v(5), v(6)];
    let r = validate(&m);
    assert!(!r.is_accepted());
    let notes: Vec<_> = r
        .defects
        .iter()
        .filter(|d| matches!(d, Defect::CoincidentVertex { .. }))
        .cloned()
        .collect();
    assert_eq!(
        notes,
        [(4, 1), (5, 2), (6, 3)].map(|(a, b)| Defect::CoincidentVertex {
            vertex: v(a),
            first: v(b)
        })
    );
    assert!(r.errors().all(|d| matches!(d, Defect::OpenEdge { .. })));
    assert!(validate(&tetra())
        .defects
        .iter()
        .all(|d| !matches!(d, Defect::CoincidentVertex { .. })));
}

/// Warnings never hide an error, nor refuse a mesh: a 3MF beam lattice
/// leaves thousands of vertices no face uses (warnings), and validation
/// listed only the first 1000 defects and refused the mesh for any
/// defect beyond them, with no error to name.
#[test]
fn more_warnings_than_are_listed_do_not_refuse_or_hide_an_error() {
    let unused = 1500;
    let with_unused = |m: Mesh| {
        let mut pos = m.positions.clone();
        pos.extend((0..unused).map(|i| [10.0 + f64::from(i), 0.0, 0.0]));
        let faces = m.faces.iter().map(|t| t.map(|v| v.0)).collect();
        Mesh::from_raw(pos, faces)
    };
    let r = validate(&with_unused(tetra()));
    assert!(r.is_accepted());
    assert_eq!(r.defects.len(), 1000);
    assert_eq!((r.unlisted, r.unlisted_errors), (unused as usize - 1000, 0));
    assert!(accept(&with_unused(tetra())).is_ok());

    // Two tetrahedra that cross: the self-intersections, found after the
    // unused vertices, are listed and refuse the mesh.
    let r = validate(&with_unused(two_tetras([0.25, 0.25, 0.25], [4, 5, 6, 7])));
    assert!(!r.is_accepted());
    assert!(
        r.errors()
            .any(|d| matches!(d, Defect::SelfIntersection { .. })),
        "{r}"
    );
    assert_eq!(r.unlisted_errors, 0);
}
