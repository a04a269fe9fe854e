//! The command line on a 3MF file as slicers write them: the object in its
//! own decimal coordinates, placed on the bed by a build item's
//! translation. `125 + fl(0.1)` is not a double, so without a grid the
//! file is refused by name; on a grid each vertex is snapped from its exact
//! image, and the slices equal those of the same box written at its placed
//! decimal coordinates (an OBJ, read as nearest doubles, snapped to the
//! same grid).

mod common;

use std::io::Write;
use std::process::Command;

/// The box `[0.1, 10.3] x [-0.7, 5.2] x [0, 7.9]`, its corners in the
/// order of `common::unit_box`, whose outward triangles it takes.
const CORNERS: [[&str; 3]; 8] = [
    ["0.1", "-0.7", "0"],
    ["10.3", "-0.7", "0"],
    ["10.3", "5.2", "0"],
    ["0.1", "5.2", "0"],
    ["0.1", "-0.7", "7.9"],
    ["10.3", "-0.7", "7.9"],
    ["10.3", "5.2", "7.9"],
    ["0.1", "5.2", "7.9"],
];

fn placed_3mf() -> Vec<u8> {
    let vertices: String = CORNERS
        .iter()
        .map(|[x, y, z]| format!(r#"<vertex x="{x}" y="{y}" z="{z}"/>"#))
        .collect();
    let triangles: String = common::unit_box(1.0)
        .1
        .iter()
        .map(|[a, b, c]| format!(r#"<triangle v1="{a}" v2="{b}" v3="{c}"/>"#))
        .collect();
    let xml = format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<model unit="millimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"><resources>
<object id="1" type="model"><mesh><vertices>{vertices}</vertices><triangles>{triangles}</triangles></mesh></object>
</resources><build><item objectid="1" transform="1 0 0 0 1 0 0 0 1 125 105 24"/></build></model>"#
    );
    let mut zw = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    zw.start_file("3D/3dmodel.model", options).unwrap();
    zw.write_all(xml.as_bytes()).unwrap();
    zw.finish().unwrap().into_inner()
}

/// The same box at its placed coordinates, typed as decimals (by hand:
/// `CORNERS` plus `(125, 105, 24)`).
const PLACED: [[&str; 3]; 8] = [
    ["125.1", "104.3", "24"],
    ["135.3", "104.3", "24"],
    ["135.3", "110.2", "24"],
    ["125.1", "110.2", "24"],
    ["125.1", "104.3", "31.9"],
    ["135.3", "104.3", "31.9"],
    ["135.3", "110.2", "31.9"],
    ["125.1", "110.2", "31.9"],
];

fn placed_obj() -> String {
    let mut obj = String::new();
    for [x, y, z] in PLACED {
        obj += &format!("v {x} {y} {z}\n");
    }
    for [a, b, c] in common::unit_box(1.0).1 {
        obj += &format!("f {} {} {}\n", a + 1, b + 1, c + 1);
    }
    obj
}

fn wmslice(args: &[&std::ffi::OsStr]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn a_box_placed_on_the_bed_slices_as_the_box_typed_at_its_place() {
    let dir = tempfile::tempdir().unwrap();
    let three_mf = dir.path().join("placed.3mf");
    let obj = dir.path().join("placed.obj");
    std::fs::write(&three_mf, placed_3mf()).unwrap();
    std::fs::write(&obj, placed_obj()).unwrap();

    // Without a grid: refused by name, as bad input, with the way out.
    let out = wmslice(&["check".as_ref(), three_mf.as_os_str()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(4), "{err}");
    assert!(
        err.contains("build item 0, object 1, vertex 0") && err.contains("snap to a grid"),
        "{err}"
    );

    let slice = |mesh: &std::path::Path, json: &std::path::Path| {
        let out = wmslice(&[
            "slice".as_ref(),
            mesh.as_os_str(),
            "--snap".as_ref(),
            "1/1000".as_ref(),
            "--at".as_ref(),
            "28".as_ref(),
            "--at".as_ref(),
            "31.9".as_ref(),
            "--format".as_ref(),
            "json".as_ref(),
            "-o".as_ref(),
            json.as_os_str(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stderr).unwrap()
    };
    let notes = slice(&three_mf, &dir.path().join("a.json"));
    assert!(
        notes.contains("8 vertices placed by a transform have no exact double"),
        "{notes}"
    );
    slice(&obj, &dir.path().join("b.json"));
    let a = std::fs::read_to_string(dir.path().join("a.json")).unwrap();
    let b = std::fs::read_to_string(dir.path().join("b.json")).unwrap();
    assert_eq!(a, b);

    // The section at 28 is the placed rectangle: its corners (the nearest
    // doubles of the decimals) and one point inside each side, where the
    // side's diagonal edge crosses the plane.
    let v: serde_json::Value = serde_json::from_str(&a).unwrap();
    let points: Vec<(f64, f64)> = v["levels"][0]["contours"][0]["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect();
    assert_eq!(points.len(), 8, "{points:?}");
    for corner in [
        (125.1, 104.3),
        (125.1, 110.2),
        (135.3, 104.3),
        (135.3, 110.2),
    ] {
        assert!(points.contains(&corner), "{corner:?} not in {points:?}");
    }
    for (x, y) in &points {
        let on_side = [125.1, 135.3].contains(x) && (104.3..=110.2).contains(y)
            || [104.3, 110.2].contains(y) && (125.1..=135.3).contains(x);
        assert!(on_side, "({x}, {y}) is off the rectangle");
    }
    // 31.9 is the top: one flat region facing up.
    let top = &v["levels"][1];
    assert_eq!(top["contours"].as_array().unwrap().len(), 0, "{top}");
}
