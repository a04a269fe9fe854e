//! Input: small meshes built here (cube, octahedron, a dyadic box, a
//! tetrahedron with odd `f64` coordinates). Output: assertions that every
//! writer/reader pair gives back the same mesh, coordinate for coordinate,
//! with the same exact signed volume, and that saving is atomic.

mod common;

use std::path::Path;

use num_rational::BigRational;
use num_traits::Zero;
use wmslice::mesh::io::{
    load, load_bytes, write_mesh, LoadNote, MeshFormat, SaveError, SaveOptions,
};
use wmslice::mesh::Mesh;

fn cube() -> Mesh {
    let (p, f) = common::unit_box(1.0);
    Mesh::from_raw(p, f)
}

fn octahedron() -> Mesh {
    let p = vec![
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let f = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    Mesh::from_raw(p, f)
}

/// A box with non-integer dyadic coordinates (exact in `f32` too).
fn dyadic_box() -> Mesh {
    let mut m = cube();
    for p in &mut m.positions {
        p[0] = p[0] * 0.375 + 0.5f64.powi(20);
        p[1] = p[1] * 2.75 - 1024.0;
        p[2] = p[2] * -0.0625 + 3.5;
    }
    m
}

/// A tetrahedron with coordinates `f32` cannot hold and signed zeros.
fn odd_tetrahedron() -> Mesh {
    let p = vec![
        [0.1, -0.0, 1e-7],
        [1.0 / 3.0, 0.2, -0.0],
        [0.0, 2.0f64.sqrt(), 0.3],
        [1e15 + 0.5, -7.25, 123456.789],
    ];
    let f = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
    Mesh::from_raw(p, f)
}

/// The exact signed volume, 1/6 sum det(v0, v1, v2), from the exact values
/// of the `f64` coordinates.
fn exact_volume(m: &Mesh) -> BigRational {
    let r = |x: f64| BigRational::from_float(x).expect("finite coordinate");
    let mut sum = BigRational::zero();
    for tri in &m.faces {
        let [a, b, c] = tri.map(|v| m.positions[v.idx()].map(r));
        let det = &a[0] * (&b[1] * &c[2] - &b[2] * &c[1]) - &a[1] * (&b[0] * &c[2] - &b[2] * &c[0])
            + &a[2] * (&b[0] * &c[1] - &b[1] * &c[0]);
        sum += det;
    }
    sum / BigRational::from_integer(6.into())
}

/// The corner positions of every face, in face order.
fn face_corners(m: &Mesh) -> Vec<[[f64; 3]; 3]> {
    m.faces
        .iter()
        .map(|t| t.map(|v| m.positions[v.idx()]))
        .collect()
}

/// Same faces (in order) with numerically equal corners; for indexed
/// formats, also the same vertex list bit for bit.
fn assert_same_mesh(original: &Mesh, read: &Mesh, format: MeshFormat, name: &str) {
    assert_eq!(
        face_corners(original),
        face_corners(read),
        "{name} via {format}: face corners differ"
    );
    match format {
        MeshFormat::StlBinary | MeshFormat::StlAscii => {
            assert_eq!(read.num_vertices(), original.num_vertices(), "{name}");
        }
        _ => {
            let bits = |m: &Mesh| -> Vec<[u64; 3]> {
                m.positions.iter().map(|p| p.map(f64::to_bits)).collect()
            };
            assert_eq!(bits(original), bits(read), "{name} via {format}");
            assert_eq!(original.faces, read.faces, "{name} via {format}");
        }
    }
    assert_eq!(
        exact_volume(original),
        exact_volume(read),
        "{name} via {format}: exact volume differs"
    );
}

fn round_trip(mesh: &Mesh, format: MeshFormat, name: &str) {
    let mut bytes = Vec::new();
    write_mesh(mesh, format, SaveOptions::default(), &mut bytes)
        .unwrap_or_else(|e| panic!("{name}: writing {format}: {e}"));
    for hint in [Some(format), None] {
        let (read, report) = load_bytes(&bytes, hint)
            .unwrap_or_else(|e| panic!("{name}: reading {format} (hint {hint:?}): {e}"));
        assert_eq!(report.format, format, "{name}: detected format");
        assert_same_mesh(mesh, &read, format, name);
    }
}

#[test]
fn every_format_round_trips_f32_exact_meshes() {
    for (name, mesh) in [
        ("cube", cube()),
        ("octahedron", octahedron()),
        ("dyadic box", dyadic_box()),
    ] {
        for format in MeshFormat::ALL {
            round_trip(&mesh, format, name);
        }
    }
}

#[test]
fn every_format_but_binary_stl_round_trips_odd_f64_coordinates() {
    let mesh = odd_tetrahedron();
    for format in MeshFormat::ALL {
        if format != MeshFormat::StlBinary {
            round_trip(&mesh, format, "odd tetrahedron");
        }
    }
}

#[test]
fn binary_stl_refuses_coordinates_f32_cannot_hold() {
    let mesh = odd_tetrahedron();
    let err = write_mesh(
        &mesh,
        MeshFormat::StlBinary,
        SaveOptions::default(),
        &mut Vec::new(),
    )
    .unwrap_err();
    assert!(
        matches!(err, SaveError::NotF32Exact { value, .. } if value == 0.1),
        "{err:?}"
    );
}

#[test]
fn binary_stl_rounds_to_f32_only_when_asked() {
    let mesh = odd_tetrahedron();
    let mut bytes = Vec::new();
    write_mesh(
        &mesh,
        MeshFormat::StlBinary,
        SaveOptions { lossy_f32: true },
        &mut bytes,
    )
    .unwrap();
    let (read, _) = load_bytes(&bytes, Some(MeshFormat::StlBinary)).unwrap();
    assert_eq!(read.positions[0][0], f64::from(0.1f32));
}

#[test]
fn stl_welds_signed_zeros_into_one_vertex() {
    // Two triangles sharing an edge, one corner written as -0.0.
    let soup = Mesh::from_raw(
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-0.0, 0.0, -0.0],
            [1.0, 1.0, 0.0],
        ],
        vec![[0, 1, 2], [3, 4, 1]],
    );
    let mut bytes = Vec::new();
    write_mesh(
        &soup,
        MeshFormat::StlAscii,
        SaveOptions::default(),
        &mut bytes,
    )
    .unwrap();
    let (read, report) = load_bytes(&bytes, None).unwrap();
    assert_eq!(read.num_vertices(), 4);
    assert!(report.notes.contains(&LoadNote::Welded {
        corners: 6,
        vertices: 4
    }));
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn save_and_load_through_files_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dyadic_box();
    let mut expected = Vec::new();
    for (i, format) in MeshFormat::ALL.into_iter().enumerate() {
        let name = format!("m{i}.{}", format.extension());
        let path = dir.path().join(&name);
        mesh.save_as(&path, format).unwrap();
        let (read, report) = load(&path).unwrap();
        assert_eq!(report.format, format);
        assert_same_mesh(&mesh, &read, format, "dyadic box file");
        expected.push(name);
    }
    // Extension-driven save: binary STL, binary little-endian PLY.
    let stl = dir.path().join("plain.stl");
    mesh.save(&stl).unwrap();
    assert_eq!(load(&stl).unwrap().1.format, MeshFormat::StlBinary);
    let ply = dir.path().join("plain.ply");
    mesh.save(&ply).unwrap();
    assert_eq!(
        load(&ply).unwrap().1.format,
        MeshFormat::PlyBinaryLittleEndian
    );
    expected.push("plain.ply".into());
    expected.push("plain.stl".into());
    expected.sort();
    // No temporary files left behind.
    assert_eq!(files_in(dir.path()), expected);
    assert_eq!(Mesh::load(&stl).unwrap().num_faces(), 12);
}

#[test]
fn failed_save_leaves_no_file_and_keeps_the_old_one() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("keep.stl");
    cube().save(&path).unwrap();
    let before = std::fs::read(&path).unwrap();
    let err = odd_tetrahedron().save(&path).unwrap_err();
    assert!(matches!(err, SaveError::NotF32Exact { .. }), "{err:?}");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(files_in(dir.path()), vec!["keep.stl".to_string()]);

    let fresh = dir.path().join("never.obj");
    let mut broken = cube();
    broken.faces[3][1] = wmslice::VertexId(99);
    let err = broken.save(&fresh).unwrap_err();
    assert!(matches!(err, SaveError::IndexOutOfRange { .. }), "{err:?}");
    assert!(!fresh.exists());
    assert_eq!(files_in(dir.path()), vec!["keep.stl".to_string()]);
}

#[test]
fn unknown_extension_is_refused_on_save() {
    let dir = tempfile::tempdir().unwrap();
    let err = cube().save(&dir.path().join("x.dxf")).unwrap_err();
    assert!(matches!(err, SaveError::UnknownFormat { .. }), "{err:?}");
}
