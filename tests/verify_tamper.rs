//! Input: correct exact results for the datasets, and one named mutation of
//! each (a reversed loop, a dropped segment, a point moved by one unit in
//! the last place, rounded or exact, a swapped parent, a deleted ridge, a
//! spurious extremum, a relabelled region, ...). Output: the verifier
//! passes the clean result and catches every mutation, with the expected
//! kind of violation at the expected place.

mod common;
use common::wmslice;

use wmslice::exact::parse_rational;
use wmslice::exact::rational::{rat_from_f64, rat_to_string};
use wmslice::output::json::{to_json, Exactness, MeshHeader};
use wmslice::verify::json::{parse, Value};
use wmslice::verify::{verify, Family, Problem, Report};
use wmslice::{datasets, Mesh, Slicer};

/// A dataset and the exact JSON of its level sets at `levels`.
fn result(name: &str, levels: &[&str]) -> (Mesh, String) {
    let mesh = datasets::by_name(name).unwrap().build();
    let slicer = Slicer::new(&mesh).unwrap();
    let sets: Vec<_> = levels
        .iter()
        .map(|z| slicer.slice_at(&parse_rational(z).unwrap()).unwrap())
        .collect();
    let text = to_json(&MeshHeader::new(&mesh, None), &sets, Exactness::WithExact);
    (mesh, text)
}

fn listing(r: &Report) -> String {
    r.violations
        .iter()
        .map(|v| v.to_string())
        .collect::<Vec<_>>()
        .join("\n")
}

/// Verifies the untouched result, then the result with `mutate` applied;
/// returns the second report, which must fail.
fn tamper(name: &str, levels: &[&str], mutate: impl FnOnce(&mut Value)) -> Report {
    let (mesh, text) = result(name, levels);
    let clean = verify(&mesh, None, &text).unwrap();
    assert!(
        clean.passed(),
        "{name}: the clean result must verify:\n{}",
        listing(&clean)
    );
    let mut doc = parse(&text).unwrap();
    // Parsing and writing back changes nothing the verifier sees.
    let same = verify(&mesh, None, &doc.to_json()).unwrap();
    assert!(same.passed(), "{}", listing(&same));
    mutate(&mut doc);
    let report = verify(&mesh, None, &doc.to_json()).unwrap();
    assert!(!report.passed(), "{name}: the tampered result passed");
    report
}

fn level(doc: &mut Value, i: usize) -> &mut Value {
    &mut doc.get_mut("levels").unwrap().as_array_mut().unwrap()[i]
}

fn list<'a>(v: &'a mut Value, key: &str) -> &'a mut Vec<Value> {
    v.get_mut(key).unwrap().as_array_mut().unwrap()
}

fn num(x: f64) -> Value {
    Value::Number(format!("{x:?}"))
}

fn text(s: &str) -> Value {
    Value::String(s.to_owned())
}

/// Whether some violation matches.
fn has(r: &Report, f: impl Fn(&wmslice::verify::Violation) -> bool) -> bool {
    r.violations.iter().any(f)
}

#[test]
fn reversed_contour_loop_is_caught() {
    let r = tamper("double_torus", &["2"], |d| {
        let l = &mut list(level(d, 0), "contours")[3];
        for k in ["points", "exact", "on"] {
            l.get_mut(k).unwrap().as_array_mut().unwrap().reverse();
        }
        l.set("area", num(-24.0));
        l.set("area_exact", text("-24"));
    });
    assert!(
        has(&r, |v| v.place.family == Family::Contours
            && v.place.item == Some(3)
            && matches!(
                v.problem,
                Problem::LoopReversed { segments: 40 }
            )),
        "{}",
        listing(&r)
    );
    assert!(has(&r, |v| matches!(
        v.problem,
        Problem::Orientation { .. }
    )));
}

#[test]
fn dropped_segment_is_caught() {
    // Drop point 5 of the outer contour: the segments 4 -> 5 -> 6 become
    // one segment 4 -> 6 that no face gives.
    let r = tamper("double_torus", &["1"], |d| {
        let l = &mut list(level(d, 0), "contours")[0];
        for k in ["points", "exact", "on"] {
            l.get_mut(k).unwrap().as_array_mut().unwrap().remove(5);
        }
    });
    assert!(
        has(&r, |v| v.place.point == Some(4)
            && matches!(v.problem, Problem::NotAPiece { .. })),
        "{}",
        listing(&r)
    );
    assert!(has(&r, |v| matches!(v.problem, Problem::Missing { .. })));
}

#[test]
fn rounded_point_moved_by_one_ulp_is_caught() {
    let r = tamper("double_torus", &["2"], |d| {
        let p = &mut list(&mut list(level(d, 0), "contours")[0], "points")[1];
        let x: f64 = p.as_array().unwrap()[0]
            .as_number()
            .unwrap()
            .parse()
            .unwrap();
        p.as_array_mut().unwrap()[0] = num(x.next_up());
    });
    assert_eq!(r.violations.len(), 1, "{}", listing(&r));
    let v = &r.violations[0];
    assert_eq!(
        (v.place.family, v.place.item, v.place.point),
        (Family::Contours, Some(0), Some(1))
    );
    assert!(
        matches!(
            v.problem,
            Problem::NotNearest {
                what: "rounded x",
                ..
            }
        ),
        "{v}"
    );
}

#[test]
fn exact_point_moved_by_one_ulp_is_caught() {
    // -1/3 becomes the double next to it: a different exact point.
    let r = tamper("double_torus", &["2"], |d| {
        let e = &mut list(&mut list(level(d, 0), "contours")[0], "exact")[1];
        let moved = rat_from_f64((-1.0f64 / 3.0).next_up());
        e.as_array_mut().unwrap()[0] = text(&rat_to_string(&moved));
    });
    assert!(
        has(&r, |v| v.place.point == Some(1)
            && matches!(v.problem, Problem::WrongPoint { .. })),
        "{}",
        listing(&r)
    );
}

#[test]
fn swapped_hole_parent_is_caught() {
    // At z = 1 loop 0 is the outer boundary, loops 1 and 2 its holes.
    let r = tamper("double_torus", &["1"], |d| {
        let l = &mut list(level(d, 0), "contours")[1];
        assert_eq!(l.get("role").unwrap().as_str(), Some("hole"));
        l.set("parent", Value::Number("2".into()));
    });
    assert_eq!(r.violations.len(), 1, "{}", listing(&r));
    assert!(matches!(
        r.violations[0].problem,
        Problem::WrongParent {
            claimed: Some(2),
            expected: Some(0)
        }
    ));
}

#[test]
fn deleted_ridge_is_caught() {
    let r = tamper("lying_torus", &["2"], |d| {
        let ridges = list(level(d, 0), "ridges");
        assert_eq!(ridges.len(), 1);
        ridges.clear();
    });
    assert!(
        r.violations
            .iter()
            .all(|v| matches!(v.problem, Problem::RidgeEdgeMissing { kind: "ridge", .. })),
        "{}",
        listing(&r)
    );
}

#[test]
fn spurious_extremum_is_caught() {
    // Vertex 12 lies on the plane at z = 1 but is a contour vertex.
    let r = tamper("double_torus", &["1"], |d| {
        let p = parse(r#"{"vertex": 12, "kind": "min", "point": [-1.0, 0.0]}"#).unwrap();
        list(level(d, 0), "points").push(p);
    });
    assert_eq!(r.violations.len(), 1, "{}", listing(&r));
    assert_eq!(r.violations[0].problem, Problem::NotExtremum(12));
    assert_eq!(r.violations[0].place.family, Family::Points);
}

#[test]
fn up_region_relabelled_down_is_caught() {
    let r = tamper("double_torus", &["4"], |d| {
        let region = &mut list(level(d, 0), "faces")[0];
        assert_eq!(region.get("facing").unwrap().as_str(), Some("up"));
        region.set("facing", text("down"));
    });
    assert!(
        has(&r, |v| matches!(
            v.problem,
            Problem::WrongFacing { expected: "up", .. }
        )),
        "{}",
        listing(&r)
    );
    assert!(has(&r, |v| v.place.family == Family::Boundary
        && matches!(v.problem, Problem::Orientation { .. })));
    assert!(has(&r, |v| matches!(
        v.problem,
        Problem::BoundarySum { .. }
    )));
}

#[test]
fn deleted_contour_loop_is_caught() {
    let r = tamper("double_torus", &["1"], |d| {
        list(level(d, 0), "contours").remove(2);
    });
    assert!(has(&r, |v| matches!(v.problem, Problem::Missing { .. })));
}

#[test]
fn wrong_saddle_branch_count_and_missing_saddle_are_caught() {
    let r = tamper("double_torus", &["2"], |d| {
        let s = &mut list(level(d, 0), "saddles")[0];
        s.set("branches", Value::Number("4".into()));
    });
    assert!(matches!(
        r.violations[..],
        [wmslice::verify::Violation {
            problem: Problem::WrongBranches {
                vertex: 17,
                claimed: 4,
                actual: 6
            },
            ..
        }]
    ));
    let r = tamper("double_torus", &["2"], |d| {
        list(level(d, 0), "saddles").clear()
    });
    assert!(matches!(
        r.violations[0].problem,
        Problem::SaddleMissing {
            vertex: 17,
            branches: 6
        }
    ));
}

#[test]
fn ridge_relabelled_valley_is_caught() {
    let r = tamper("lying_torus", &["2"], |d| {
        list(level(d, 0), "ridges")[0].set("kind", text("valley"));
    });
    assert!(r.violations.iter().all(|v| matches!(
        v.problem,
        Problem::WrongRidgeKind {
            expected: "ridge",
            ..
        }
    )));
}

#[test]
fn extremum_of_the_wrong_kind_and_missing_extremum_are_caught() {
    let r = tamper("grid", &["1"], |d| {
        let points = list(level(d, 0), "points");
        assert_eq!(points.len(), 9);
        points[0].set("kind", text("max"));
        points.pop();
    });
    assert!(has(&r, |v| matches!(
        v.problem,
        Problem::WrongExtremum {
            expected: "min",
            ..
        }
    )));
    assert!(has(&r, |v| matches!(
        v.problem,
        Problem::ExtremumMissing { kind: "min", .. }
    )));
}

#[test]
fn face_dropped_from_a_region_is_caught() {
    let r = tamper("cylinder", &["2"], |d| {
        let region = &mut list(level(d, 0), "faces")[0];
        list(region, "faces").pop();
    });
    assert!(
        has(&r, |v| matches!(v.problem, Problem::FaceMissing(_))),
        "{}",
        listing(&r)
    );
    assert!(has(&r, |v| matches!(
        v.problem,
        Problem::WrongRegionArea { .. }
    )));
}

#[test]
fn region_split_in_two_is_caught() {
    let r = tamper("cylinder", &["2"], |d| {
        let regions = list(level(d, 0), "faces");
        let mut second = regions[0].clone();
        let moved = list(&mut regions[0], "faces").pop().unwrap();
        *list(&mut second, "faces") = vec![moved];
        list(&mut second, "boundary").clear();
        regions.push(second);
    });
    assert!(
        has(&r, |v| v.place.item == Some(1)
            && matches!(
                v.problem,
                Problem::RegionsJoined { other: 0, .. }
            )),
        "{}",
        listing(&r)
    );
}

#[test]
fn reversed_one_sided_loop_is_caught() {
    let r = tamper("double_torus", &["1"], |d| {
        let l = &mut list(level(d, 0), "below")[1];
        for k in ["points", "exact", "on"] {
            l.get_mut(k).unwrap().as_array_mut().unwrap().reverse();
        }
    });
    assert!(
        has(&r, |v| v.place.family == Family::Below
            && matches!(v.problem, Problem::LoopReversed { .. })),
        "{}",
        listing(&r)
    );
}

#[test]
fn result_of_another_level_is_caught() {
    let r = tamper("double_torus", &["1"], |d| {
        level(d, 0).set("z", text("3/2"))
    });
    assert!(
        has(&r, |v| matches!(
            v.problem,
            Problem::VertexOffPlane { vertex: 12, .. }
        )),
        "{}",
        listing(&r)
    );
    assert!(has(&r, |v| matches!(v.problem, Problem::WrongPoint { .. })));
}

#[test]
fn result_of_another_mesh_is_caught() {
    let r = tamper("unit_cube", &["1/2"], |d| {
        d.get_mut("mesh")
            .unwrap()
            .set("sha256", text(&"0".repeat(64)));
    });
    assert!(matches!(r.violations[0].problem, Problem::MeshHash { .. }));
}

#[test]
fn rational_not_in_lowest_terms_is_caught() {
    let r = tamper("unit_cube", &["1/2"], |d| {
        list(level(d, 0), "contours")[0].set("area_exact", text("2/2"));
    });
    assert!(matches!(
        r.violations[0].problem,
        Problem::NotCanonical { .. }
    ));
}

/// A claimed area in lowest terms is taken once it equals the exact sum
/// (cross-multiplied): one of another value is reported with the true
/// area, reduced by hand (the unit cube's section has area 1).
#[test]
fn wrong_area_in_lowest_terms_is_caught_with_the_true_area() {
    let r = tamper("unit_cube", &["1/2"], |d| {
        list(level(d, 0), "contours")[0].set("area_exact", text("3/2"));
    });
    assert!(
        has(&r, |v| matches!(
            &v.problem,
            Problem::WrongArea { claimed, actual } if claimed == "3/2" && actual == "1"
        )),
        "{}",
        listing(&r)
    );
}

#[test]
fn the_command_line_exits_0_on_a_correct_result_and_6_listing_violations() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.json");
    let o = out.to_str().unwrap();
    let (code, _, err) = wmslice(&[
        "slice",
        "double_torus",
        "--at",
        "1",
        "--at",
        "2",
        "--at",
        "4",
        "--exact",
        "--format",
        "json",
        "-o",
        o,
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, stdout, _) = wmslice(&["verify", "double_torus", o]);
    assert_eq!(code, 0);
    assert_eq!(stdout.lines().count(), 1, "{stdout}");
    assert!(stdout.contains("verified: 3 levels"), "{stdout}");

    let mut doc = parse(&std::fs::read_to_string(&out).unwrap()).unwrap();
    list(level(&mut doc, 1), "saddles").clear();
    list(level(&mut doc, 2), "ridges").pop();
    std::fs::write(&out, doc.to_json()).unwrap();
    let (code, stdout, stderr) = wmslice(&["verify", "double_torus", o]);
    assert_eq!(code, 6, "{stdout}{stderr}");
    assert!(
        stdout.contains(
            "level 1 (z = 2): saddle: vertex v17 has 6 S_O branches but is not listed as a saddle"
        ),
        "{stdout}"
    );
    assert!(
        stdout.contains("level 2 (z = 4): S_NO ridge: ridge edge"),
        "{stdout}"
    );
    assert!(
        stderr.contains("verification FAILED: 2 violations"),
        "{stderr}"
    );
}

/// A mutation of one loop.
type Mutation = fn(&mut Value);

/// The loop families of level `i`: `(name, path to the list)`.
fn families(doc: &Value, i: usize) -> Vec<(String, Vec<String>)> {
    let lv = &doc.get("levels").unwrap().as_array().unwrap()[i];
    let mut out: Vec<(String, Vec<String>)> = ["contours", "below", "above"]
        .iter()
        .map(|k| (k.to_string(), vec![k.to_string()]))
        .collect();
    let regions = lv.get("faces").unwrap().as_array().unwrap().len();
    for r in 0..regions {
        out.push((
            format!("faces[{r}].boundary"),
            vec!["faces".into(), r.to_string(), "boundary".into()],
        ));
    }
    out
}

fn family_mut<'a>(lv: &'a mut Value, path: &[String]) -> &'a mut Vec<Value> {
    let mut v = lv;
    for key in path {
        v = match key.parse::<usize>() {
            Ok(i) => &mut v.as_array_mut().unwrap()[i],
            Err(_) => v.get_mut(key).unwrap(),
        };
    }
    v.as_array_mut().unwrap()
}

#[test]
fn every_dataset_catches_reversed_deleted_and_shortened_loops_and_moved_roundings() {
    let mut tried = 0;
    for d in datasets::all() {
        for &(p, q) in d.degenerate_levels {
            let z = format!("{p}/{q}");
            let (mesh, text) = result(d.name, &[&z]);
            let clean = parse(&text).unwrap();
            assert!(
                verify(&mesh, None, &text).unwrap().passed(),
                "{} at {z}",
                d.name
            );
            for (name, path) in families(&clean, 0) {
                let count = family_mut(level(&mut clean.clone(), 0), &path).len();
                for l in 0..count {
                    let mutations: [(&str, Mutation); 3] = [
                        ("reverse", |lp| {
                            for k in ["points", "exact", "on"] {
                                lp.get_mut(k).unwrap().as_array_mut().unwrap().reverse();
                            }
                        }),
                        ("drop point 0", |lp| {
                            for k in ["points", "exact", "on"] {
                                lp.get_mut(k).unwrap().as_array_mut().unwrap().remove(0);
                            }
                        }),
                        ("move rounded y by one ulp", |lp| {
                            let p = &mut list(lp, "points")[0].as_array_mut().unwrap()[1];
                            let y: f64 = p.as_number().unwrap().parse().unwrap();
                            *p = num(y.next_down());
                        }),
                    ];
                    for (what, mutate) in mutations {
                        let mut doc = clean.clone();
                        let lp = &mut family_mut(level(&mut doc, 0), &path)[l];
                        // A collapsed limit (around an extremum, along a
                        // ridge and back) may read the same both ways.
                        if what == "reverse" && reads_the_same_reversed(list(lp, "on")) {
                            continue;
                        }
                        mutate(lp);
                        let r = verify(&mesh, None, &doc.to_json()).unwrap();
                        assert!(
                            !r.passed(),
                            "{} at {z}: {what} of {name}[{l}] passed",
                            d.name
                        );
                        tried += 1;
                    }
                    // Deleting the loop leaves its pieces missing (or, for
                    // a limit collapsed to one point, the loop itself).
                    let mut doc = clean.clone();
                    family_mut(level(&mut doc, 0), &path).remove(l);
                    let r = verify(&mesh, None, &doc.to_json()).unwrap();
                    assert!(
                        r.violations.iter().any(|v| matches!(
                            v.problem,
                            Problem::Missing { .. } | Problem::LimitLoopMissing { .. }
                        )),
                        "{} at {z}: deleting {name}[{l}] is not caught as missing pieces",
                        d.name
                    );
                }
            }
        }
    }
    assert!(tried > 100, "{tried}");
}

/// Whether a cyclic sequence reversed is one of its rotations (a limit
/// collapsed onto a point, or onto a path it runs along and back).
fn reads_the_same_reversed(on: &[wmslice::verify::json::Value]) -> bool {
    let text: Vec<String> = on.iter().map(|v| v.to_json()).collect();
    let mut back = text.clone();
    back.reverse();
    (0..text.len()).any(|r| back[r..].iter().chain(&back[..r]).eq(text.iter())) || text.is_empty()
}

#[test]
fn a_result_checked_against_a_refused_mesh_names_the_count_and_first_defect() {
    let (mesh, text) = result("double_torus", &["2"]);
    // One face removed: its three edges are open.
    let mut open = mesh.clone();
    open.faces.remove(0);
    let message = verify(&open, None, &text).unwrap_err().to_string();
    assert!(
        message.contains("(3 blocking defects; first: open edge"),
        "{message}"
    );
    // One coordinate made NaN: one defect, named in the singular.
    let mut nan = mesh;
    nan.positions[0][2] = f64::NAN;
    let message = verify(&nan, None, &text).unwrap_err().to_string();
    assert!(
        message.contains("(1 blocking defect; first: vertex v0"),
        "{message}"
    );
}
