//! Input: `slice --certificate FILE` runs on a dataset, a snapped file and a
//! summary. Output: the hashes name the exact input and result bytes, the
//! levels are exact, the numeric mode and largest snap move are right, the
//! verdict is the verifier's, and the same input and options give
//! byte-identical results and certificates.

mod common;

use sha2::{Digest, Sha256};
use std::path::Path;
use std::process::{Command, Output};

fn wmslice(args: &[&str]) -> Output {
    let out = Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(args)
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn sha(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn read_json(p: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(p).unwrap()).unwrap()
}

#[test]
fn same_input_and_options_give_byte_identical_results_and_certificates() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cert) = (dir.path().join("r.json"), dir.path().join("c.json"));
    let args = [
        "slice",
        "double_torus",
        "--at",
        "2",
        "--at",
        "0.6",
        "--layer-height",
        "1",
        "--exact",
        "--format",
        "json",
        "-o",
        s(&out),
        "--certificate",
        s(&cert),
        "--quiet",
    ];
    wmslice(&args);
    let (r1, c1) = (std::fs::read(&out).unwrap(), std::fs::read(&cert).unwrap());
    std::fs::remove_file(&out).unwrap();
    std::fs::remove_file(&cert).unwrap();
    wmslice(&args);
    assert_eq!(std::fs::read(&out).unwrap(), r1, "results differ");
    assert_eq!(std::fs::read(&cert).unwrap(), c1, "certificates differ");

    let c = read_json(&cert);
    assert_eq!(c["format"], "wmslice-certificate");
    assert_eq!(c["tool"]["version"], env!("CARGO_PKG_VERSION"));
    assert_eq!(c["input"]["kind"], "dataset");
    let mesh = wmslice::datasets::by_name("double_torus").unwrap().build();
    assert_eq!(
        c["input"]["sha256"],
        wmslice::output::json::mesh_sha256(&mesh)
    );
    assert_eq!(c["result"]["sha256"], sha(&r1));
    assert_eq!(c["result"]["bytes"], r1.len());
    assert_eq!(c["numeric"]["mode"], "exact");
    assert_eq!(c["verification"]["verdict"], "pass");
    let zs: Vec<&str> = c["levels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["z"].as_str().unwrap())
        .collect();
    assert!(zs.contains(&"3/5") && zs.contains(&"2"), "{zs:?}");
    let at2 = c["levels"]
        .as_array()
        .unwrap()
        .iter()
        .find(|l| l["z"] == "2")
        .unwrap();
    assert_eq!(
        (at2["contours"].as_u64(), at2["saddles"].as_u64()),
        (Some(4), Some(1))
    );
    // The certified result verifies on its own, too (`--quiet`: as the
    // slicer, no progress; here stderr is no terminal anyway).
    let v = wmslice(&["verify", "double_torus", s(&out), "--quiet"]);
    assert_eq!(v.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&v.stdout).contains("verified"));
}

#[test]
fn a_snapped_file_certificate_hashes_the_file_and_reports_the_largest_move() {
    let dir = tempfile::tempdir().unwrap();
    // A unit cube whose top is stored as f32 0.6 (0.60000002...).
    let z = 0.6f32 as f64;
    let text = common::cad_cube_off(z);
    let mesh = dir.path().join("cad.off");
    std::fs::write(&mesh, &text).unwrap();
    let cert = dir.path().join("c.json");
    // Result to stdout: the certificate hashes the bytes printed.
    let out = wmslice(&[
        "slice",
        s(&mesh),
        "--at",
        "0.6",
        "--snap",
        "0.0001",
        "--exact",
        "--format",
        "json",
        "--certificate",
        s(&cert),
        "--quiet",
    ]);
    let c = read_json(&cert);
    assert_eq!(c["input"]["kind"], "file");
    assert_eq!(c["input"]["sha256"], sha(text.as_bytes()));
    assert_eq!(c["result"]["destination"], "stdout");
    assert_eq!(c["result"]["sha256"], sha(&out.stdout));
    assert_eq!(c["numeric"]["mode"], "snapped");
    assert_eq!(c["numeric"]["grid"], "1/10000");
    // |0.6f32 - 3/5| = 1/41943040, exactly.
    assert_eq!(c["numeric"]["largest_move"], "1/41943040");
    assert_eq!(c["numeric"]["moved_vertices"], 4);
    assert_eq!(c["levels"][0]["z"], "3/5");
    assert_eq!(c["levels"][0]["regions_up"], 1);
    assert_eq!(c["verification"]["verdict"], "pass");
    // The result on stdout verifies with the grid its header names.
    let result = dir.path().join("r.json");
    std::fs::write(&result, &out.stdout).unwrap();
    wmslice(&["verify", s(&mesh), s(&result)]);
}

#[test]
fn a_summary_certificate_hashes_the_summary_file() {
    let dir = tempfile::tempdir().unwrap();
    let (out, cert) = (dir.path().join("r.txt"), dir.path().join("c.json"));
    wmslice(&[
        "slice",
        "saddle8",
        "--at",
        "2",
        "-o",
        s(&out),
        "--certificate",
        s(&cert),
        "--quiet",
    ]);
    let c = read_json(&cert);
    assert_eq!(c["options"]["format"], "summary");
    assert_eq!(c["result"]["sha256"], sha(&std::fs::read(&out).unwrap()));
    assert_eq!(c["levels"][0]["saddles"], 1);
}
