//! Input: one file per defect class (the bad-input matrix), run through the
//! command line. Output: each row's documented exit code (0 ok, 1 internal,
//! 2 usage, 3 invalid mesh, 4 input unreadable, 5 output error, 6
//! verification failed), never 101 (a panic), a message on stderr (stdout
//! for `check`) naming the defect, and no output file and no certificate
//! left behind when it fails.

mod common;
use common::wmslice;

use std::io::Write;
use std::path::Path;

const TETRA_POS: [[f64; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
const TETRA: [[u32; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

fn off(pos: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<u8> {
    let mut s = format!("OFF\n{} {} 0\n", pos.len(), faces.len());
    for p in pos {
        s += &format!("{:?} {:?} {:?}\n", p[0], p[1], p[2]);
    }
    for t in faces {
        s += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    s.into_bytes()
}

fn tetra_with(edit: impl FnOnce(&mut Vec<[u32; 3]>)) -> Vec<u8> {
    let mut faces = TETRA.to_vec();
    edit(&mut faces);
    off(&TETRA_POS, &faces)
}

/// Two tetrahedra, the second shifted and renumbered through `map`.
fn two_tetras(shift: [f64; 3], map: [u32; 4]) -> Vec<u8> {
    let mut pos = TETRA_POS.to_vec();
    for p in TETRA_POS {
        pos.push([p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]]);
    }
    let mut faces = TETRA.to_vec();
    for f in TETRA {
        faces.push(f.map(|v| map[v as usize]));
    }
    off(&pos, &faces)
}

fn binary_stl(count: u32, corners: &[[f32; 3]]) -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend(count.to_le_bytes());
    for tri in corners.chunks(3) {
        b.extend([0u8; 12]); // normal
        for c in tri {
            for x in c {
                b.extend(x.to_le_bytes());
            }
        }
        b.extend([0u8; 2]);
    }
    b
}

fn tetra_corners() -> Vec<[f32; 3]> {
    TETRA
        .iter()
        .flat_map(|f| f.map(|v| TETRA_POS[v as usize].map(|x| x as f32)))
        .collect()
}

fn obj(coord: &str, last_face: &str) -> Vec<u8> {
    format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 {coord}\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf {last_face}\n")
        .into_bytes()
}

/// A tetrahedron's 3MF model part.
fn tetra_model_xml() -> String {
    r#"<?xml version="1.0" encoding="UTF-8"?>
<model unit="millimeter" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02"><resources><object id="1" type="model"><mesh><vertices><vertex x="0" y="0" z="0"/><vertex x="1" y="0" z="0"/><vertex x="0" y="1" z="0"/><vertex x="0" y="0" z="1"/></vertices><triangles><triangle v1="0" v2="2" v3="1"/><triangle v1="0" v2="1" v3="3"/><triangle v1="1" v2="2" v3="3"/><triangle v1="2" v2="0" v3="3"/></triangles></mesh></object></resources><build><item objectid="1"/></build></model>"#
        .to_string()
}

/// A 3MF package holding `model` as its root model part.
fn zip_model(model: &str) -> Vec<u8> {
    let mut zw = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated);
    zw.start_file("3D/3dmodel.model", options).unwrap();
    zw.write_all(model.as_bytes()).unwrap();
    zw.finish().unwrap().into_inner()
}

fn zip_bomb_3mf() -> Vec<u8> {
    zip_model(&(tetra_model_xml() + &" ".repeat(8 << 20)))
}

/// How a row is run.
#[derive(Clone, Copy, Debug)]
enum Run {
    /// `slice FILE --at Z --format json --exact -o OUT --certificate CERT`.
    Slice(&'static str),
    /// `check FILE` (defects are listed on stdout).
    Check,
    /// `verify unit_cube FILE`.
    Verify,
    /// `slice FILE --layer-height H --format json -o OUT` (the layer sweep).
    Layers(&'static str),
    /// `check --snap Q FILE`.
    CheckSnapped(&'static str),
}

struct Row {
    defect: &'static str,
    file: &'static str,
    bytes: Vec<u8>,
    run: Run,
    code: i32,
    names: &'static str,
}

fn rows() -> Vec<Row> {
    let row = |defect, file, bytes, run, code, names| Row {
        defect,
        file,
        bytes,
        run,
        code,
        names,
    };
    let s = Run::Slice("1/2");
    let lying_ply = "ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    // Vertex 4 at the midpoint of edge 0-1: face [0, 1, 4] has zero area.
    let mut zero_pos = TETRA_POS.to_vec();
    zero_pos.push([0.5, 0., 0.]);
    let zero_faces = [
        [0, 2, 1],
        [0, 1, 4],
        [0, 4, 3],
        [4, 1, 3],
        [0, 3, 2],
        [1, 2, 3],
    ];
    // Vertex 4 at vertex 0's position: faces 1 and 2 are degenerate and no
    // flip removes them.
    let mut coincident_pos = zero_pos.clone();
    coincident_pos[4] = coincident_pos[0];
    let good_stl = binary_stl(4, &tetra_corners());
    let mut nan_stl = tetra_corners();
    nan_stl[5][2] = f32::NAN;
    let inverted: Vec<[u32; 3]> = TETRA.iter().map(|f| [f[0], f[2], f[1]]).collect();
    vec![
        row("empty file", "empty.stl", Vec::new(), s, 4, "the mesh file is empty (0 bytes)"),
        row(
            "truncated binary STL",
            "truncated.stl",
            good_stl[..good_stl.len() - 30].to_vec(),
            s,
            4,
            "truncated",
        ),
        row(
            "header claims more triangles than the file holds",
            "claims.stl",
            binary_stl(1000, &tetra_corners()),
            s,
            4,
            "claims 1000 triangle",
        ),
        row(
            "ASCII STL with garbage",
            "garbage.stl",
            b"solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 zz\n".to_vec(),
            s,
            4,
            "parse error (line 4)",
        ),
        row("NaN coordinate (OBJ)", "nan.obj", obj("nan", "2 3 4"), s, 3, "non-finite coordinate"),
        row("NaN coordinate (binary STL)", "nan.stl", binary_stl(4, &nan_stl), s, 3, "non-finite coordinate"),
        row("infinite coordinate", "inf.obj", obj("inf", "2 3 4"), s, 3, "non-finite coordinate"),
        row("open mesh", "open.off", tetra_with(|f| { f.pop(); }), s, 3, "open edge"),
        row(
            "non-manifold edge",
            "nonmanifold.off",
            two_tetras([0., -1., -1.], [0, 1, 6, 7]),
            s,
            3,
            "non-manifold edge v0-v1",
        ),
        row(
            "bowtie vertex",
            "bowtie.off",
            two_tetras([-1., -1., -1.], [4, 5, 6, 0]),
            s,
            3,
            "bowtie vertex v0",
        ),
        row("flipped face", "flipped.off", tetra_with(|f| f[3] = [1, 3, 2]), s, 3, "face f3 is flipped"),
        row(
            "inverted mesh (negative volume)",
            "inverted.off",
            off(&TETRA_POS, &inverted),
            s,
            3,
            "signed volume -1/6 is not positive",
        ),
        row(
            "duplicate face",
            "duplicate.off",
            tetra_with(|f| f.push(f[2])),
            s,
            3,
            "face f4 duplicates face f2, the same way round (one face written twice)",
        ),
        row(
            "degenerate face (flipped away, noted by check)",
            "zero_area.off",
            off(&zero_pos, &zero_faces),
            Run::Check,
            0,
            "flipped 1 degenerate faces",
        ),
        row(
            "degenerate face in the plane (flipped away, sliced, verified)",
            "zero_area_sliced.off",
            off(&zero_pos, &zero_faces),
            Run::Slice("0"),
            0,
            "",
        ),
        // The tetrahedron and a copy shifted by 1/4 on every axis, with
        // their own vertex ids: the first's faces in x = 0, y = 0, z = 0
        // miss the copy (x, y, z >= 1/4 on it); its slanted face f3 meets
        // the copy's bottom f4 (z = 1/4: at (3/8, 3/8, 1/4), where
        // x + y + z = 1 and x, y >= 1/4).
        row(
            "overlapping bodies (self-intersection), sliced",
            "overlap.off",
            two_tetras([0.25, 0.25, 0.25], [4, 5, 6, 7]),
            s,
            3,
            "error: faces f3 and f4 intersect",
        ),
        row(
            "overlapping bodies (self-intersection), checked",
            "overlap_check.off",
            two_tetras([0.25, 0.25, 0.25], [4, 5, 6, 7]),
            Run::Check,
            3,
            "error: faces f3 and f4 intersect",
        ),
        row(
            "overlapping bodies (self-intersection), sliced in layers",
            "overlap_layers.off",
            two_tetras([0.25, 0.25, 0.25], [4, 5, 6, 7]),
            Run::Layers("1/8"),
            3,
            "error: faces f3 and f4 intersect",
        ),
        // The copy's corner v4 at (1/4, 1/4, 1/2 + 2^-20): just beyond the
        // first one's slanted face f3 (x + y + z = 1 there; the copy has
        // x + y + z >= 1 + 2^-20 everywhere), so apart and accepted. Snapped
        // to 2^-10 it lands on f3's interior (1/4 + 1/4 + 1/2 = 1, each
        // coordinate positive), moving nothing else (multiples of 1/4):
        // the copy's faces through v4, f4, f5 and f6, touch f3 there. The
        // check runs on the mesh as sliced.
        row(
            "bodies apart by 2^-20 (accepted)",
            "gap.off",
            two_tetras([0.25, 0.25, 0.5 + 1.0 / 1048576.0], [4, 5, 6, 7]),
            Run::Check,
            0,
            "accepted for slicing",
        ),
        row(
            "bodies apart by 2^-20, touching once snapped to 2^-10",
            "gap_snapped.off",
            two_tetras([0.25, 0.25, 0.5 + 1.0 / 1048576.0], [4, 5, 6, 7]),
            Run::CheckSnapped("0.0009765625"),
            3,
            "error: faces f3 and f4 intersect",
        ),
        // The copy shifted by (1, 0, 0): its corner v4 = (1, 0, 0) sits on
        // the first one's corner v1 with another id; bodies touching at a
        // point self-intersect (faces f0 and f4 share that point).
        row(
            "bodies touching at one point with separate ids",
            "touch.off",
            two_tetras([1.0, 0.0, 0.0], [4, 5, 6, 7]),
            s,
            3,
            "error: faces f0 and f4 intersect",
        ),
        row(
            "degenerate face with coincident vertices (refused)",
            "coincident.off",
            off(&coincident_pos, &zero_faces),
            s,
            3,
            "face f1 is degenerate (its vertices are collinear): vertices",
        ),
        row(
            "OBJ index out of range",
            "range.obj",
            obj("1", "2 3 9"),
            s,
            3,
            "refers to vertex 8, but there are only 4 vertices",
        ),
        row(
            "PLY with a lying element count",
            "lying.ply",
            lying_ply.as_bytes().to_vec(),
            s,
            4,
            "claims 100 vertex elements",
        ),
        row("3MF zip bomb", "bomb.3mf", zip_bomb_3mf(), s, 4, "looks like a zip bomb"),
        row(
            "3MF that is no zip archive",
            "junk.3mf",
            b"PK\x03\x04 not a zip archive".to_vec(),
            s,
            4,
            "3MF: broken zip archive: invalid Zip archive",
        ),
        row(
            "3MF model part outside its package",
            "bare.3mf",
            tetra_model_xml().into_bytes(),
            s,
            4,
            "3MF: parse error: the file is XML, not a zip package",
        ),
        row(
            "3MF with malformed XML",
            "malformed.3mf",
            zip_model(&tetra_model_xml().replace("</build>", "</buil")),
            s,
            4,
            "3MF: malformed XML in `3D/3dmodel.model`",
        ),
        row(
            "result that is not JSON",
            "not_json.json",
            b"{\"format\": \"wmslice-levelset\", ".to_vec(),
            Run::Verify,
            4,
            "not valid JSON: unexpected end of text at line 1",
        ),
        row(
            "result with wrong keys",
            "wrong_keys.json",
            br#"{"format": "wmslice-levelset", "version": 1, "mesh": {"vertices": 8}, "levels": []}"#.to_vec(),
            Run::Verify,
            4,
            "$.mesh: missing key `faces`",
        ),
        row(
            "result of another format",
            "other.json",
            br#"{"type": "FeatureCollection"}"#.to_vec(),
            Run::Verify,
            4,
            "missing key `format`",
        ),
        row(
            "result written without --exact",
            "rounded.json",
            br#"{"format":"wmslice-levelset","version":1,"mesh":{"vertices":8,"faces":12,"sha256":"x","snap":null},"levels":[{"z":"1/2","contours":[{"points":[[0.0,0.0]],"area":0.0,"role":"outer","parent":null}],"faces":[],"ridges":[],"points":[],"saddles":[],"below":[],"above":[]}]}"#.to_vec(),
            Run::Verify,
            4,
            "written without --exact",
        ),
    ]
}

/// A cause that a message says twice: the text after some `": "` (12
/// bytes or more) that the message already holds before it, as when an
/// error's chain of causes is printed after a message that names them.
fn repeated_cause(message: &str) -> Option<&str> {
    message.lines().find_map(|line| {
        line.match_indices(": ").find_map(|(i, _)| {
            let tail = &line[i + 2..];
            (tail.len() >= 12 && line[..i].contains(tail)).then_some(tail)
        })
    })
}

#[test]
fn a_cause_said_twice_is_seen() {
    let twice = "error: 3MF: broken zip archive: invalid Zip archive: no EOCD: invalid Zip archive: no EOCD";
    assert_eq!(repeated_cause(twice), Some("invalid Zip archive: no EOCD"));
    assert_eq!(
        repeated_cause("error: 3MF: broken zip archive: invalid Zip archive: no EOCD"),
        None
    );
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn every_defect_class_has_its_exit_code_and_message_and_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for r in rows() {
        let input = dir.path().join(r.file);
        std::fs::write(&input, &r.bytes).unwrap();
        let out = dir.path().join(format!("{}.out.json", r.file));
        let cert = dir.path().join(format!("{}.cert.json", r.file));
        let (code, stdout, stderr) = match r.run {
            Run::Slice(z) => wmslice(&[
                "slice",
                s(&input),
                "--at",
                z,
                "--format",
                "json",
                "--exact",
                "-o",
                s(&out),
                "--certificate",
                s(&cert),
                "--quiet",
            ]),
            Run::Check => wmslice(&["check", s(&input)]),
            Run::CheckSnapped(q) => wmslice(&["check", "--snap", q, s(&input)]),
            Run::Layers(h) => wmslice(&[
                "slice",
                s(&input),
                "--layer-height",
                h,
                "--format",
                "json",
                "-o",
                s(&out),
                "--quiet",
            ]),
            Run::Verify => wmslice(&["verify", "unit_cube", s(&input)]),
        };
        let said = if matches!(r.run, Run::Check | Run::CheckSnapped(_)) {
            &stdout
        } else {
            &stderr
        };
        let left = out.exists() || cert.exists();
        let repeated = repeated_cause(said);
        let ok = code == r.code
            && repeated.is_none()
            && code != 101
            && said.contains(r.names)
            && (code == 0 || !left)
            && (code != 0 || !matches!(r.run, Run::Slice(_)) || (out.exists() && cert.exists()))
            && (code != 0 || !matches!(r.run, Run::Layers(_)) || out.exists());
        if !ok {
            failures.push(format!(
                "{}: exit {code} (want {}), output left: {left}, cause said twice: {repeated:?}, wanted {:?} in:\n{said}",
                r.defect, r.code, r.names
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn usage_and_output_errors_have_their_codes_and_leave_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let cert = dir.path().join("cert.json");
    // An unparsable level: 2.
    let (code, _, err) = wmslice(&[
        "slice",
        "unit_cube",
        "--at",
        "zero",
        "--certificate",
        s(&cert),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("'zero' is not a number"), "{err}");
    // A layer height whose first plane (z_min + H/2) is above the mesh's
    // top: 2, and the message says so (the unit cube spans z 0 to 1).
    let out = dir.path().join("thin.json");
    let (code, _, err) = wmslice(&[
        "slice",
        "unit_cube",
        "--layer-height",
        "3",
        "--format",
        "json",
        "-o",
        s(&out),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("first plane of the layer height 3 is z = 3/2 (~1.5), above the last bound z = 1 (the mesh spans z 0 to 1)"),
        "{err}"
    );
    assert!(!out.exists());
    // A negative layer height or snap grid reaches the check that names
    // it (not the argument parser, which took `-1` for an option): 2.
    for (args, said) in [
        (
            &["slice", "unit_cube", "--layer-height", "-1"][..],
            "layer height must be positive, got -1",
        ),
        (
            &["critical", "unit_cube", "--layer-height", "-1/5"][..],
            "layer height must be positive, got -1/5",
        ),
        (
            &["slice", "unit_cube", "--snap", "-1e-3", "--at", "1/2"][..],
            "snap grid must be positive, got -1/1000",
        ),
        (
            &["check", "unit_cube", "--snap", "0"][..],
            "snap grid must be positive, got 0",
        ),
        // Idle workers search each other's queues: 40 000 of them on 2
        // cores did not slice the unit cube in 100 s.
        (
            &["slice", "unit_cube", "--at", "1/2", "--threads", "1000000"][..],
            "--threads 1000000: at most",
        ),
        (
            &["critical", "unit_cube", "--threads", "1000000"][..],
            "--threads 1000000: at most",
        ),
        // An output name with no format the writer knows: an argument
        // (exit 5 before, as if the disk had failed), nothing written.
        (
            &["gen", "unit_cube", "-o", "never-written.xyz"][..],
            "cannot tell the output format of never-written.xyz",
        ),
    ] {
        let (code, _, err) = wmslice(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(said), "{args:?}: {err}");
    }
    assert!(!std::path::Path::new("never-written.xyz").exists());
    // No levels asked for: said before the mesh is read (a large file
    // was read, welded and validated first).
    let (code, _, err) = wmslice(&["slice", "unit_cube"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no levels: give --at Z"), "{err}");
    assert!(!err.contains("note:"), "refused before reading: {err}");
    // A levels file with comments and blank lines only: 2, named, even
    // beside --at (a wrong path or a failed export, not a plan).
    let levels = dir.path().join("levels.txt");
    std::fs::write(&levels, "# heights\n\n   # none yet\n").unwrap();
    let (code, _, err) = wmslice(&[
        "slice",
        "unit_cube",
        "--at",
        "1/2",
        "--levels-file",
        s(&levels),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("levels.txt holds no level"), "{err}");
    // An output under a regular file: 5.
    let blocker = dir.path().join("file");
    std::fs::write(&blocker, b"x").unwrap();
    let out = blocker.join("r.json");
    let (code, _, err) = wmslice(&[
        "slice",
        "unit_cube",
        "--at",
        "1/2",
        "--format",
        "json",
        "-o",
        s(&out),
        "--quiet",
    ]);
    assert_eq!(code, 5, "{err}");
    assert!(err.contains("cannot write"), "{err}");
    // A missing mesh, a missing result: 4.
    let (code, _, err) = wmslice(&["verify", "unit_cube", s(&dir.path().join("none.json"))]);
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("cannot read"), "{err}");
    let (code, _, _) = wmslice(&["verify", "no_such_mesh", s(&blocker)]);
    assert_eq!(code, 4);
    assert!(!cert.exists() && !out.exists());
}

#[test]
fn an_output_naming_the_mesh_a_levels_file_or_another_output_is_refused_before_any_work() {
    // Before, `slice part.stl -o part.stl` renamed the result over the
    // part (exit 0, the mesh gone) and `-o r.json --certificate r.json`
    // kept only the certificate.
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("part.off");
    let bytes = off(
        &[
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ],
        &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    );
    std::fs::write(&mesh, &bytes).unwrap();
    let levels = dir.path().join("levels.txt");
    std::fs::write(&levels, "1/2\n").unwrap();
    let link = dir.path().join("link.off");
    std::os::unix::fs::symlink(&mesh, &link).unwrap();
    let result = dir.path().join("r.json");
    let spelled = dir.path().join(".").join("part.off");
    // Command lines as words (the temporary paths hold no spaces).
    let (m, l, lv, r) = (s(&mesh), s(&link), s(&levels), s(&result));
    for (line, said) in [
        (
            format!("slice {m} --at 1/2 --format json -o {}", s(&spelled)),
            "names the same file as the mesh",
        ),
        (
            format!("slice {l} --at 1/2 --format svg -o {m}"),
            "names the same file as the mesh",
        ),
        (
            format!("slice {m} --levels-file {lv} --format json -o {lv}"),
            "names the same file as --levels-file",
        ),
        (
            format!("slice {m} --at 1/2 --format json -o {r} --certificate {r}"),
            "one output would replace the other",
        ),
        (
            format!("critical {m} --format json -o {m}"),
            "names the same file as the mesh",
        ),
    ] {
        let args: Vec<&str> = line.split_whitespace().collect();
        let (code, _, err) = wmslice(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(said), "{args:?}: {err}");
        assert!(!err.contains("note: read"), "refused before reading: {err}");
    }
    assert_eq!(
        std::fs::read(&mesh).unwrap(),
        bytes,
        "the mesh is untouched"
    );
    assert_eq!(std::fs::read_to_string(&levels).unwrap(), "1/2\n");
    assert!(!result.exists());
    // Distinct paths still work.
    let line = format!("slice {m} --levels-file {lv} --format json -o {r} --quiet");
    let (code, _, err) = wmslice(&line.split_whitespace().collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
}

/// The unit cube sliced at 1/2 with exact JSON into `dir` (a result
/// `verify` reads).
fn exact_cube_result(dir: &Path) -> std::path::PathBuf {
    let result = dir.join("cube.json");
    let (code, _, err) = wmslice(&[
        "slice",
        "unit_cube",
        "--at",
        "1/2",
        "--format",
        "json",
        "--exact",
        "-o",
        s(&result),
    ]);
    assert_eq!(code, 0, "{err}");
    result
}

#[test]
fn verify_against_an_invalid_mesh_exits_3() {
    let dir = tempfile::tempdir().unwrap();
    let result = exact_cube_result(dir.path());
    let open = dir.path().join("open.off");
    std::fs::write(
        &open,
        tetra_with(|f| {
            f.pop();
        }),
    )
    .unwrap();
    let (code, _, err) = wmslice(&["verify", s(&open), s(&result)]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("open edge"), "{err}");
}

/// A part snapped to a grid as coarse as itself (a mesh in metres on a
/// millimetre grid) collapses every face: the refusal says so once, with
/// the part's size, instead of "the mesh has no faces" (`--drop-collapsed`)
/// or each face repeating a vertex (without it; gmsh's 8e-8 m `demo1.stl`
/// on a 1e-6 grid listed 308 of them).
#[test]
fn a_grid_coarser_than_the_part_is_named_with_the_part_size() {
    let dir = tempfile::tempdir().unwrap();
    let tiny = dir.path().join("tip.off");
    let pos: Vec<[f64; 3]> = TETRA_POS.iter().map(|p| p.map(|c| c * 2e-4)).collect();
    std::fs::write(&tiny, off(&pos, &TETRA)).unwrap();
    for cmd in ["check", "slice"] {
        for drop in [true, false] {
            let mut args = vec![cmd, s(&tiny), "--snap", "0.001"];
            args.extend(drop.then_some("--drop-collapsed"));
            if cmd == "slice" {
                args.extend(["--at", "0"]);
            }
            let (code, _, err) = wmslice(&args);
            assert_eq!(code, 3, "{args:?}: {err}");
            assert!(
                err.contains(
                    "snapping to the grid 1/1000 collapsed every one of the 4 faces: the mesh spans 2.000e-4 x 2.000e-4 x 2.000e-4"
                ),
                "{args:?}: {err}"
            );
            assert!(!err.contains("repeats a vertex"), "{args:?}: {err}");
        }
    }
    // On a grid finer than the part, it is accepted.
    let (code, _, err) = wmslice(&["check", s(&tiny), "--snap", "1e-6"]);
    assert_eq!(code, 0, "{err}");
}

/// Every command writing to a full disk (Linux's `/dev/full`, whose every
/// write fails with ENOSPC), on stdout or through `-o`: exit 5 with the
/// system's reason, never a panic (Rust's `println!` panics on such a
/// write) and never success with nothing written.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_an_output_error_for_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let result = exact_cube_result(dir.path());
    let to_stdout: &[&[&str]] = &[
        &["--help"],
        &["--version"],
        &["slice", "--help"],
        &["demo"],
        &["gen", "--list"],
        &["check", "unit_cube"],
        &["critical", "unit_cube"],
        &["critical", "unit_cube", "--format", "json"],
        &["slice", "unit_cube", "--at", "1/2"],
        &["slice", "unit_cube", "--at", "1/2", "--format", "json"],
        &["slice", "unit_cube", "--at", "1/2", "--format", "cli"],
        &["slice", "unit_cube", "--at", "1/2", "--format", "html"],
        &["verify", "unit_cube", s(&result)],
    ];
    for args in to_stdout {
        let full = std::fs::File::create("/dev/full").unwrap();
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_wmslice"))
            .args(*args)
            .stdout(full)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(5), "{args:?}: {err}");
        assert!(err.contains("No space left on device"), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    for format in ["json", "svg", "html", "cli", "cli-binary"] {
        let args = [
            "slice",
            "unit_cube",
            "--at",
            "1/2",
            "--format",
            format,
            "-o",
            "/dev/full",
        ];
        let (code, _, err) = wmslice(&args);
        assert_eq!(code, 5, "{format}: {err}");
        assert!(err.contains("No space left on device"), "{format}: {err}");
    }
}
