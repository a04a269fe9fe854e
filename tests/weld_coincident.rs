//! `--weld`: an indexed file whose faces do not share vertices where they
//! meet (each face written with its own corners, as some exporters write
//! a mesh, or seams split for texture coordinates) is refused as read,
//! with its coincident vertices named, and welded on request: exactly, by
//! equal coordinates, nothing moved. The answers are derived by hand.

mod common;

use wmslice::ids::VertexId;
use wmslice::mesh::io::{load_bytes_exact, MeshFormat};
use wmslice::mesh::prepare::{prepare_with, CoincidentVertices, CollapsedFaces, Repairs};
use wmslice::mesh::validate::{validate, Defect};
use wmslice::Mesh;

/// The unit tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), outward.
fn tetra() -> Mesh {
    Mesh::from_raw(
        vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    )
}

/// [`tetra`] as an OBJ file that gives every face its own three vertices
/// (twelve; one copy of the origin written `-0`): nothing connects.
const FACE_BY_FACE_OBJ: &str = "\
# each face with its own corners
v 0 0 0
v 0 1 0
v 1 0 0
v 0 0 0
v 1 0 0
v 0 0 1
v 0 -0 0
v 0 0 1
v 0 1 0
v 1 0 0
v 0 1 0
v 0 0 1
f 1 2 3
f 4 5 6
f 7 8 9
f 10 11 12
";

fn read(text: &str) -> Mesh {
    load_bytes_exact(text.as_bytes(), Some(MeshFormat::Obj))
        .unwrap()
        .0
}

const WELD: Repairs = Repairs {
    coincident: CoincidentVertices::Weld,
    collapsed: CollapsedFaces::Refuse,
};

#[test]
fn a_tetrahedron_written_face_by_face_welds_to_the_tetrahedron() {
    let read = read(FACE_BY_FACE_OBJ);
    assert_eq!(read.num_vertices(), 12);
    // As read: open edges, and each copy named beside its first vertex.
    let r = validate(&read);
    assert!(!r.is_accepted());
    assert!(r.errors().all(|d| matches!(d, Defect::OpenEdge { .. })));
    let coincident: Vec<(u32, u32)> = r
        .defects
        .iter()
        .filter_map(|d| match d {
            Defect::CoincidentVertex { vertex, first } => Some((vertex.0, first.0)),
            _ => None,
        })
        .collect();
    assert_eq!(
        coincident,
        [
            (3, 0),
            (4, 2),
            (6, 0),
            (7, 5),
            (8, 1),
            (9, 2),
            (10, 1),
            (11, 5)
        ]
    );
    // Welded: the tetrahedron itself, vertices in first-seen order
    // (0, (0,1,0), (1,0,0), (0,0,1)), eight merged; nothing moved.
    let p = prepare_with(read, None, WELD).unwrap();
    assert_eq!(p.welded, Some(8));
    let want = Mesh::from_raw(
        vec![[0., 0., 0.], [0., 1., 0.], [1., 0., 0.], [0., 0., 1.]],
        vec![[0, 1, 2], [0, 2, 3], [0, 3, 1], [2, 1, 3]],
    );
    assert_eq!(p.mesh, want);
    assert!(validate(&p.mesh).is_accepted());
    // The same solid as `tetra()` (vertices 1 and 2 swapped).
    let swap = |v: VertexId| VertexId([0, 2, 1, 3][v.idx()]);
    let renamed: Vec<[VertexId; 3]> = p.mesh.faces.iter().map(|f| f.map(swap)).collect();
    let mut faces = tetra().faces;
    let canon = |f: &[VertexId; 3]| {
        let k = (0..3).min_by_key(|&i| f[i]).unwrap();
        [f[k], f[(k + 1) % 3], f[(k + 2) % 3]]
    };
    let mut got: Vec<_> = renamed.iter().map(canon).collect();
    faces = faces.iter().map(canon).collect();
    got.sort();
    faces.sort();
    assert_eq!(got, faces);
    // Not asked for: nothing welded, and no count.
    let kept = prepare_with(self::read(FACE_BY_FACE_OBJ), None, Repairs::default()).unwrap();
    assert_eq!((kept.welded, kept.mesh.num_vertices()), (None, 12));
}

/// The command line: refused as read with a hint, accepted with `--weld`,
/// the header counts the merged vertices, the level at z = 1/2 is the
/// triangle (0,0), (1/2,0), (0,1/2), and `verify` welds as the header
/// says (without the key it reads the file as given and refuses it).
#[test]
fn weld_on_the_command_line_is_recorded_and_verified() {
    let dir = tempfile::tempdir().unwrap();
    let path = |n: &str| dir.path().join(n).to_str().unwrap().to_owned();
    let (file, out) = (path("faces.obj"), path("out.json"));
    std::fs::write(&file, FACE_BY_FACE_OBJ).unwrap();

    let (code, said, err) = common::wmslice(&["check", &file]);
    assert_eq!(code, 3, "{said}{err}");
    let text = said + &err;
    assert!(
        text.contains("vertex v3 lies exactly where vertex v0 does"),
        "{text}"
    );
    assert!(text.contains("--weld merges"), "{text}");

    let (code, said, err) = common::wmslice(&["check", &file, "--weld"]);
    assert_eq!(code, 0, "{said}{err}");
    let text = said + &err;
    assert!(text.contains("welded 8 vertices"), "{text}");
    assert!(text.contains("volume     1/6"), "{text}");

    let (code, _, err) = common::wmslice(&[
        "slice", &file, "--weld", "--at", "1/2", "--format", "json", "--exact", "-o", &out,
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["mesh"]["welded"], 8);
    assert_eq!(doc["mesh"]["vertices"], 4);
    let contours = doc["levels"][0]["contours"].as_array().unwrap();
    assert_eq!(contours.len(), 1);
    let mut points: Vec<(String, String)> = contours[0]["exact"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_str().unwrap().into(), p[1].as_str().unwrap().into()))
        .collect();
    points.sort();
    let s = |a: &str, b: &str| (a.to_owned(), b.to_owned());
    assert_eq!(points, [s("0", "0"), s("0", "1/2"), s("1/2", "0")]);

    let (code, said, err) = common::wmslice(&["verify", &file, &out]);
    assert_eq!(code, 0, "{said}{err}");
    let bare = path("bare.json");
    std::fs::write(&bare, text.replace(r#","welded":8"#, "")).unwrap();
    assert_ne!(std::fs::read_to_string(&bare).unwrap(), text);
    let (code, _, err) = common::wmslice(&["verify", &file, &bare]);
    assert_eq!(code, 3, "{err}");
}

/// Welding can make a face use one vertex twice (two of its corners were
/// distinct vertices at one point): refused by name, or removed with
/// `--drop-collapsed`, after which the tetrahedron is left.
#[test]
fn a_face_welding_collapses_is_refused_or_dropped() {
    // The tetrahedron as given, plus a vertex 4 at the origin and a face
    // (0, 4, 1) that welding turns into (0, 0, 1).
    let mut m = tetra();
    m.positions.push([0., 0., 0.]);
    m.faces.push([VertexId(0), VertexId(4), VertexId(1)]);
    let p = prepare_with(m.clone(), None, WELD).unwrap();
    assert_eq!(p.welded, Some(1));
    let r = validate(&p.mesh);
    assert!(r
        .errors()
        .any(|d| matches!(d, Defect::RepeatedVertex { face } if face.0 == 4)));
    let both = Repairs {
        coincident: CoincidentVertices::Weld,
        collapsed: CollapsedFaces::Drop,
    };
    let p = prepare_with(m.clone(), None, both).unwrap();
    assert_eq!(p.mesh, tetra());
    assert_eq!(p.dropped.as_ref().map(|d| d[0].0), Some(4));

    let dir = tempfile::tempdir().unwrap();
    let path = |n: &str| dir.path().join(n).to_str().unwrap().to_owned();
    let (file, out) = (path("extra.obj"), path("out.json"));
    let mut obj = String::new();
    for p in &m.positions {
        obj += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for f in &m.faces {
        obj += &format!("f {} {} {}\n", f[0].0 + 1, f[1].0 + 1, f[2].0 + 1);
    }
    std::fs::write(&file, obj).unwrap();
    let (code, said, err) = common::wmslice(&["check", &file, "--weld"]);
    assert_eq!(code, 3, "{err}");
    let text = said + &err;
    assert!(
        text.contains("welding merged two corners of 1 faces"),
        "{text}"
    );
    let (code, _, err) = common::wmslice(&[
        "slice",
        &file,
        "--weld",
        "--drop-collapsed",
        "--at",
        "1/4",
        "--format",
        "json",
        "--exact",
        "-o",
        &out,
    ]);
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(doc["mesh"]["welded"], 1);
    assert_eq!(doc["mesh"]["dropped_collapsed"], 1);
    assert_eq!(
        doc["mesh"]["sha256"].as_str().unwrap(),
        wmslice::output::json::mesh_sha256(&tetra())
    );
    let (code, said, err) = common::wmslice(&["verify", &file, &out]);
    assert_eq!(code, 0, "{said}{err}");
}
