//! Meshes with the coordinate patterns of real files (bench/meshgen.rs:
//! an origin-centred `f32` torus with noise near zero, a decimal OBJ knot,
//! an `f64` CAD-like part) take the per-edge, certified and wide number
//! paths; their level sets are checked by the independent verifier (SPEC 7
//! from the exact JSON) and by the invariants, and every rounded point of
//! the JSON is the nearest double of its exact value.

#[path = "../bench/meshgen.rs"]
#[allow(dead_code)]
mod meshgen;

use wmslice::exact::crossing::{path_counts, NumberPath};
use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_to_f64, Rat};
use wmslice::levelset::check::{check_level_invariants, vertex_heights};
use wmslice::output::json::{to_json, Exactness, MeshHeader};
use wmslice::{LevelSet, Slicer};

/// Decimal levels across the height range, and every fifth vertex height
/// (degenerate levels).
fn levels(mesh: &wmslice::Mesh) -> Vec<Rat> {
    let zs = vertex_heights(mesh);
    let (lo, hi) = (zs[0].clone(), zs[zs.len() - 1].clone());
    let mut out: Vec<Rat> = (1..12)
        .map(|k| {
            let t = &lo + (&hi - &lo) * Rat::new(k.into(), 12.into());
            // Rounded to four decimals: a decimal level as a user types it.
            let scaled = (t * Rat::from_integer(10000.into())).round();
            scaled / Rat::from_integer(10000.into())
        })
        .collect();
    out.extend(zs.iter().step_by(5).cloned());
    out.push(parse_rational("1/3").unwrap());
    // Simple fractions of the stepped part's 1.25 steps: its f64 edges cut
    // there give exact ties between two doubles (the wide path).
    out.extend(["3/8", "7/8", "21/8"].map(|c| parse_rational(c).unwrap()));
    out.retain(|c| *c > lo && *c < hi);
    out
}

fn check(name: &str, b: &meshgen::Builder) {
    let mesh = b.to_mesh();
    let slicer = Slicer::new(&mesh).unwrap_or_else(|e| panic!("{name}: {e}"));
    let sets: Vec<LevelSet> = levels(&mesh)
        .iter()
        .map(|c| {
            slicer
                .slice_at(c)
                .unwrap_or_else(|e| panic!("{name} at {c}: {e}"))
        })
        .collect();
    for ls in &sets {
        check_level_invariants(&mesh, slicer.topology(), ls)
            .unwrap_or_else(|e| panic!("{name} at {}: {e}", ls.level));
        for l in ls
            .contours
            .iter()
            .chain(ls.below.iter())
            .chain(ls.above.iter())
        {
            for p in &l.points {
                let e = p.exact();
                assert_eq!(p.to_f64(), [rat_to_f64(&e.x), rat_to_f64(&e.y)], "{name}");
            }
        }
    }
    let header = MeshHeader::new(&mesh, None);
    let text = to_json(&header, &sets, Exactness::WithExact);
    let report = wmslice::verify::verify(&mesh, None, &text).unwrap();
    assert!(report.passed(), "{name}: {report:?}");
}

#[test]
fn real_coordinate_patterns_slice_exactly_and_off_the_grid() {
    let before = path_counts();
    check("torus0", &meshgen::torus_origin(40, 16));
    check("knot", &meshgen::knot(48, 8));
    check("steps64", &meshgen::steps_f64(12));
    let after = path_counts();
    let taken = |p: NumberPath| after[p as usize] - before[p as usize];
    // The decimal knot and the f64 part are on no grid of i128 crossings:
    // their crossings are certified (the counts are shared with the other
    // tests of this binary, so only growth is asserted).
    assert!(taken(NumberPath::Certified) > 100, "{after:?}");
    assert!(taken(NumberPath::Edge) > 0, "{after:?}");
    assert!(taken(NumberPath::Wide) > 0, "{after:?}");
}

#[test]
fn origin_centred_f32_torus_has_noise_near_zero() {
    let b = meshgen::torus_origin(40, 16);
    let tiny = b
        .pos
        .iter()
        .flatten()
        .filter(|&&c| c != 0.0 && c.abs() < 1e-10)
        .count();
    assert!(tiny > 0);
    // Every coordinate is an f32.
    assert!(b.pos.iter().flatten().all(|&c| f64::from(c as f32) == c));
}

#[test]
fn verbose_prints_the_number_paths() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(["slice", "unit_cube", "--at", "1/2", "--quiet", "--verbose"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    // The unit cube is on the grid: every point takes it.
    let line = err
        .lines()
        .find(|l| l.starts_with("number paths (loop points): grid "))
        .unwrap_or_else(|| panic!("{err}"));
    assert!(
        line.ends_with("per-edge 0, certified 0, wide 0, big 0"),
        "{line}"
    );
    assert!(!line.contains("grid 0,"), "{line}");
}

/// The `time (s):` line of a `--verbose` run: the steps in order, each a
/// finite non-negative number of seconds.
fn step_times(args: &[&str]) -> Vec<(String, f64)> {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(args)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let line = err
        .lines()
        .find_map(|l| l.strip_prefix("time (s): "))
        .unwrap_or_else(|| panic!("{err}"));
    line.split(", ")
        .map(|step| {
            let (name, t) = step.rsplit_once(' ').unwrap_or_else(|| panic!("{line}"));
            let t: f64 = t.parse().unwrap_or_else(|_| panic!("{line}"));
            assert!(t.is_finite() && t >= 0.0, "{line}");
            (name.to_owned(), t)
        })
        .collect()
}

#[test]
fn verbose_prints_the_time_of_each_step() {
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("cube.svg");
    let streamed = step_times(&["slice", "unit_cube", "--at", "1/2", "--quiet", "--verbose"]);
    let kept = step_times(&[
        "slice",
        "unit_cube",
        "--at",
        "1/2",
        "--format",
        "svg",
        "-o",
        svg.to_str().unwrap(),
        "--quiet",
        "--verbose",
    ]);
    for steps in [streamed, kept] {
        let names: Vec<&str> = steps.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["reading", "validation", "levels", "output"]);
    }
    assert!(svg.exists());
}
