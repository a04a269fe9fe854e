//! Every JSON the slicer writes validates against the shipped copy of
//! `levelset.schema.json`, and its exact values agree with the rounded ones.

mod common;

use common::slab;
use proptest::prelude::*;
use wmslice::exact::parse_rational;
use wmslice::levelset::check::vertex_heights;
use wmslice::output::json::{to_json, Exactness, MeshHeader};
use wmslice::Slicer;

fn schema() -> jsonschema::Validator {
    let text = include_str!("../schema/levelset.schema.json");
    let schema: serde_json::Value = serde_json::from_str(text).unwrap();
    jsonschema::validator_for(&schema).unwrap()
}

fn assert_valid(doc: &str) -> serde_json::Value {
    let v: serde_json::Value = serde_json::from_str(doc).unwrap();
    let validator = schema();
    let errors: Vec<String> = validator
        .iter_errors(&v)
        .map(|e| format!("{e} at {}", e.instance_path))
        .collect();
    assert!(errors.is_empty(), "schema violations: {errors:?}");
    v
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, .. ProptestConfig::default() })]
    #[test]
    fn json_of_random_slabs_matches_the_schema(s in slab()) {
        let mesh = s.mesh();
        let slicer = Slicer::new(&mesh).unwrap();
        let sets: Vec<_> = vertex_heights(&mesh).iter().map(|z| slicer.slice_at(z).unwrap()).collect();
        for ex in [Exactness::Rounded, Exactness::WithExact] {
            let v = assert_valid(&to_json(&MeshHeader::new(&mesh, None), &sets, ex));
            prop_assert_eq!(v["levels"].as_array().unwrap().len(), sets.len());
            if ex == Exactness::WithExact {
                // Each rounded point is the nearest double of its exact twin.
                for level in v["levels"].as_array().unwrap() {
                    for lp in level["contours"].as_array().unwrap() {
                        for (p, e) in lp["points"].as_array().unwrap().iter().zip(lp["exact"].as_array().unwrap()) {
                            for k in 0..2 {
                                let exact = parse_rational(e[k].as_str().unwrap()).unwrap();
                                prop_assert_eq!(p[k].as_f64().unwrap(), wmslice::exact::rational::rat_to_f64(&exact));
                            }
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn cli_writes_schema_valid_json_atomically() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("nested/dir/cube.json");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args([
            "slice",
            "unit_cube",
            "--at",
            "1",
            "--at",
            "0.5",
            "--exact",
            "--format",
            "json",
            "-o",
        ])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let v = assert_valid(&std::fs::read_to_string(&out).unwrap());
    // Levels come out ascending.
    assert_eq!(v["levels"][0]["z"], "1/2");
    assert_eq!(v["levels"][1]["z"], "1");
    // Nothing else was left in the directory (no temporary file).
    assert_eq!(std::fs::read_dir(out.parent().unwrap()).unwrap().count(), 1);
    // A bad level leaves no file behind and exits 2.
    let bad = dir.path().join("bad.json");
    let st = std::process::Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(["slice", "unit_cube", "--at", "x", "--format", "json", "-o"])
        .arg(&bad)
        .status()
        .unwrap();
    assert_eq!(st.code(), Some(2));
    assert!(!bad.exists());
}
