//! The command line on the paper's showcase levels: the exact slicer and
//! the naive one side by side.

mod common;

use std::process::Command;

fn run(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
    )
}

#[test]
fn lying_torus_top_ring_is_one_closed_ridge_and_no_contour() {
    let (code, text) = run(&["slice", "lying_torus", "--at", "2", "--quiet"]);
    assert_eq!(code, 0);
    assert!(text.contains("contours S_O : 0 loops"), "{text}");
    assert!(
        text.contains("ridges S_NO  : 1 ridges (0 open, 1 closed)"),
        "{text}"
    );
    // The naive slicer fills the ring instead.
    let (code, naive) = run(&["slice", "lying_torus", "--at", "2", "--naive", "--quiet"]);
    assert_eq!(code, 0);
    assert!(!naive.contains(" 0 filled contours"), "{naive}");
    assert!(naive.contains("zero-length"), "{naive}");
}

#[test]
fn cylinder_top_is_one_up_region_and_no_contour() {
    let (code, text) = run(&["slice", "cylinder", "--at", "2", "--quiet"]);
    assert_eq!(code, 0);
    assert!(text.contains("contours S_O : 0 loops"), "{text}");
    assert!(
        text.contains("faces F      : 1 regions (1 up, 0 down, 0 flat)"),
        "{text}"
    );
    let (_, naive) = run(&["slice", "cylinder", "--at", "2", "--naive", "--quiet"]);
    assert!(!naive.contains(" 0 filled contours"), "{naive}");
}

#[test]
fn levels_are_parsed_exactly_and_bad_ones_exit_2() {
    let (code, text) = run(&[
        "slice",
        "unit_cube",
        "--at",
        "0.1",
        "--at",
        "3/5",
        "--at",
        "-1e-3",
        "--quiet",
    ]);
    assert_eq!(code, 0);
    assert!(text.contains("level z = 1/10"), "{text}");
    assert!(text.contains("level z = 3/5"), "{text}");
    assert!(text.contains("level z = -1/1000"), "{text}");
    assert_eq!(run(&["slice", "unit_cube", "--at", "1/0"]).0, 2);
    assert_eq!(run(&["slice", "unit_cube"]).0, 2);
    assert_eq!(run(&["slice", "no_such_mesh_or_file", "--at", "1"]).0, 4);
}

#[test]
fn snapping_makes_the_cad_plane_exact() {
    // A unit cube whose top corners were stored as f32 0.6 (0.60000002...):
    // exactly at 3/5 only after snapping to 1/10000.
    let dir = tempfile::tempdir().unwrap();
    let z = 0.6f32 as f64;
    let s = common::cad_cube_off(z);
    let path = dir.path().join("cad.off");
    std::fs::write(&path, s).unwrap();
    let p = path.to_str().unwrap();
    let (_, raw) = run(&["slice", p, "--at", "0.6", "--quiet"]);
    assert!(raw.contains("faces F      : 0 regions"), "{raw}");
    let (code, snapped) = run(&["slice", p, "--at", "0.6", "--snap", "0.0001", "--quiet"]);
    assert_eq!(code, 0);
    assert!(
        snapped.contains("faces F      : 1 regions (1 up"),
        "{snapped}"
    );
}

#[test]
fn output_bytes_are_identical_for_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let mut outputs = Vec::new();
    for threads in ["1", "2", "3"] {
        let path = dir.path().join(format!("t{threads}.json"));
        let p = path.to_str().unwrap();
        let (code, _) = run(&[
            "slice",
            "double_torus",
            "--layer-height",
            "1/8",
            "--first",
            "0",
            "--exact",
            "--format",
            "json",
            "--threads",
            threads,
            "--quiet",
            "-o",
            p,
        ]);
        assert_eq!(code, 0);
        outputs.push(std::fs::read(&path).unwrap());
    }
    assert!(outputs.iter().all(|o| o == &outputs[0]));
    // The summary is also made on the workers.
    let summaries: Vec<String> = ["1", "2", "3"]
        .iter()
        .map(|t| {
            let args = ["slice", "double_torus", "--layer-height", "1/8"];
            let (code, text) = run(&[&args[..], &["--threads", t, "--quiet"]].concat());
            assert_eq!(code, 0);
            text
        })
        .collect();
    assert!(summaries.iter().all(|s| s == &summaries[0]));
    assert_eq!(summaries[0].matches("level z = ").count(), 32);
    let v: serde_json::Value = serde_json::from_slice(&outputs[0]).unwrap();
    // 0, 1/8, ..., up to the top of the double torus at z = 4: 33 planes.
    assert_eq!(v["levels"].as_array().unwrap().len(), 33);
    assert_eq!(v["levels"][16]["z"], "2");
}

#[test]
fn uniform_layers_start_mid_layer_and_merge_with_explicit_levels() {
    let (code, text) = run(&[
        "slice",
        "unit_cube",
        "--layer-height",
        "0.25",
        "--at",
        "1",
        "--quiet",
    ]);
    assert_eq!(code, 0);
    let zs: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("level z = "))
        .collect();
    let zs: Vec<&str> = zs.iter().map(|l| l.split(' ').next().unwrap()).collect();
    assert_eq!(zs, ["1/8", "3/8", "5/8", "7/8", "1"]);
    assert_eq!(run(&["slice", "unit_cube", "--layer-height", "0"]).0, 2);
}

/// Runs the binary with `input` on its standard input: exit code, stdout,
/// stderr.
fn piped(input: &[u8], args: &[&str]) -> (i32, Vec<u8>, String) {
    use std::io::Write;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(input).unwrap();
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code().unwrap_or(-1), out.stdout, err)
}

/// `-` reads the mesh from standard input, its format recognised by
/// content: the same levels as from the file, byte for byte, in every
/// format `gen` writes; an empty input is refused by name (exit 4).
#[test]
fn a_mesh_on_standard_input_slices_as_its_file() {
    let dir = tempfile::tempdir().unwrap();
    for ext in ["stl", "obj", "off", "ply"] {
        let file = dir.path().join(format!("double_torus.{ext}"));
        let path = file.to_str().unwrap();
        let (code, _) = run(&["gen", "double_torus", "-o", path]);
        assert_eq!(code, 0, "{ext}");
        let levels = ["--at", "2", "--at", "4", "--format", "json", "--exact"];
        let from_file = Command::new(env!("CARGO_BIN_EXE_wmslice"))
            .args(["slice", path])
            .args(levels)
            .output()
            .unwrap();
        assert_eq!(from_file.status.code(), Some(0), "{ext}");
        let bytes = std::fs::read(&file).unwrap();
        let args: Vec<&str> = ["slice", "-"].iter().chain(&levels).copied().collect();
        let (code, from_stdin, err) = piped(&bytes, &args);
        assert_eq!(code, 0, "{ext}: {err}");
        assert!(err.contains("note: read standard input as"), "{ext}: {err}");
        assert!(
            !from_stdin.is_empty() && from_stdin == from_file.stdout,
            "{ext}"
        );
    }
    let (code, _, err) = piped(b"", &["check", "-"]);
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("the mesh file is empty (0 bytes)"), "{err}");
}

/// `--levels-file -` reads the levels from standard input (`seq ... |
/// wmslice slice part.stl --levels-file -`): the same levels as the file,
/// comments and all; not beside a mesh read from there too (exit 2), and
/// bytes that are not text are named (exit 4). Before, `-` was a file
/// name ("cannot read -").
#[test]
fn levels_on_standard_input_are_the_levels_file() {
    let dir = tempfile::tempdir().unwrap();
    let text = "0.25\n# the middle\n1/2\n\n-1e-3\n";
    let file = dir.path().join("levels.txt");
    std::fs::write(&file, text).unwrap();
    let from_file = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args([
            "slice",
            "unit_cube",
            "--levels-file",
            file.to_str().unwrap(),
        ])
        .args(["--format", "json", "--exact"])
        .output()
        .unwrap();
    assert_eq!(from_file.status.code(), Some(0));
    let args = [
        "slice",
        "unit_cube",
        "--levels-file",
        "-",
        "--format",
        "json",
        "--exact",
    ];
    let (code, from_stdin, err) = piped(text.as_bytes(), &args);
    assert_eq!(code, 0, "{err}");
    assert!(!from_stdin.is_empty() && from_stdin == from_file.stdout);
    let (code, _, err) = piped(b"1/2\n", &["slice", "-", "--levels-file", "-"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot both be standard input"), "{err}");
    let (code, _, err) = piped(b"\xff\n", &["slice", "unit_cube", "--levels-file", "-"]);
    assert_eq!(code, 4, "{err}");
    assert!(
        err.contains("cannot read the levels from standard input"),
        "{err}"
    );
}

/// `-o -` is standard output, as no `-o` is, for `slice` and `critical`:
/// the same bytes, and no file named `-` (it used to make one).
#[test]
fn output_dash_is_standard_output() {
    let dir = tempfile::tempdir().unwrap();
    let in_dir = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_wmslice"))
            .args(args)
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(0), "{args:?}");
        out.stdout
    };
    for args in [
        &["slice", "double_torus", "--at", "2", "--format", "json"][..],
        &["slice", "double_torus", "--at", "2", "--format", "cli"][..],
        &["critical", "double_torus", "--format", "json"][..],
    ] {
        let plain = in_dir(args);
        let dashed = in_dir(&[args, &["-o", "-"]].concat());
        assert!(!plain.is_empty() && dashed == plain, "{args:?}");
        assert!(!dir.path().join("-").exists(), "{args:?}");
    }
}

/// `verify MESH -` reads the result from standard input (`slice ... -o -
/// | wmslice verify MESH -`): an exact result passes, the same result with
/// one rounded coordinate moved fails with the point named (exit 6), and
/// the mesh and the result cannot both be standard input (exit 2).
#[test]
fn a_result_on_standard_input_is_verified() {
    let (code, result) = run(&[
        "slice",
        "double_torus",
        "--at",
        "2",
        "--format",
        "json",
        "--exact",
        "-o",
        "-",
        "--quiet",
    ]);
    assert_eq!(code, 0);
    let (code, out, err) = piped(result.as_bytes(), &["verify", "double_torus", "-"]);
    assert_eq!(code, 0, "{err}");
    assert!(String::from_utf8_lossy(&out).starts_with("standard input: verified: 1 levels"));
    // The first point of the first contour, moved (a rounded value that is
    // no longer the exact point's nearest double).
    let at = result.find("\"points\":[[").unwrap() + "\"points\":[[".len();
    let tampered = format!(
        "{}1e300{}",
        &result[..at],
        &result[at + result[at..].find(',').unwrap()..]
    );
    let (code, out, err) = piped(tampered.as_bytes(), &["verify", "double_torus", "-"]);
    assert_eq!(code, 6, "{err}");
    assert!(
        String::from_utf8_lossy(&out)
            .contains("point 0: rounded x 1e300 is not the double nearest"),
        "{err}"
    );
    let (code, _, err) = piped(b"", &["verify", "-", "-"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cannot both be standard input"), "{err}");
}
