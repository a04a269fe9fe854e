//! Layer plans that honour the flats (`critical::fit`) and the `critical`
//! command: fitted plans checked for their promises on random slabs,
//! the uniform-plan audit and the clusters derived by hand, and the CLI's
//! JSON, SVG, errors and `slice --fit-critical`.

mod common;

use common::{slab, wmslice};
use proptest::prelude::*;
use wmslice::classify::Facing;
use wmslice::critical::fit::{audit_uniform, clusters, fit_layers, FitError};
use wmslice::critical::{self, CriticalReport};
use wmslice::exact::parse_rational;
use wmslice::exact::rational::Rat;
use wmslice::{datasets, Mesh, Slicer};

fn r(s: &str) -> Rat {
    parse_rational(s).unwrap()
}

fn report(mesh: &Mesh) -> CriticalReport {
    critical::analyze(&Slicer::new(mesh).unwrap()).unwrap()
}

/// `|d/n - h|`, exactly.
fn deviation(d: &Rat, n: usize, h: &Rat) -> Rat {
    let q = d / Rat::from_integer(n.into()) - h;
    if q < Rat::from_integer(0.into()) {
        -q
    } else {
        q
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, .. ProptestConfig::default() })]

    /// Slabs have flats at integer heights (so at least 1 apart), and
    /// `H = k/8 <= 2` keeps `H/2 <= 1`: a plan always exists. It runs from
    /// the lowest to the highest critical height without gaps, every layer
    /// is between H/2 and 3H/2, every flat is a boundary, the layers
    /// between two consecutive boundaries that must be there are equal,
    /// and their count is the closest to H of its neighbours.
    #[test]
    fn fitted_plans_keep_their_promises(s in slab(), k in 1i64..=16) {
        let rep = report(&s.mesh());
        let h = Rat::new(k.into(), 8.into());
        let layers = fit_layers(&rep, &h).unwrap();
        let (half, most) = (&h / r("2"), &h * r("3/2"));
        prop_assert_eq!(&layers[0][0], &rep.levels[0].z);
        prop_assert_eq!(&layers[layers.len() - 1][1], &rep.levels[rep.levels.len() - 1].z);
        for w in layers.windows(2) {
            prop_assert_eq!(&w[0][1], &w[1][0]);
        }
        for l in &layers {
            let t = &l[1] - &l[0];
            prop_assert!(t >= half && t <= most, "layer {:?} for H = {}", l, h);
        }
        let mut required: Vec<Rat> = vec![rep.levels[0].z.clone()];
        for l in &rep.levels {
            if l.faces_up + l.faces_down > 0 {
                prop_assert!(layers.iter().any(|b| b[0] == l.z || b[1] == l.z), "flat at {}", l.z);
                required.push(l.z.clone());
            }
        }
        required.push(rep.levels[rep.levels.len() - 1].z.clone());
        required.dedup();
        for w in required.windows(2) {
            let inside: Vec<_> = layers.iter().filter(|l| l[0] >= w[0] && l[1] <= w[1]).collect();
            let d = &w[1] - &w[0];
            let n = inside.len();
            prop_assert!(n >= 1);
            prop_assert!(inside.iter().all(|l| &l[1] - &l[0] == &d / Rat::from_integer(n.into())));
            let dev = deviation(&d, n, &h);
            if n > 1 {
                prop_assert!(dev <= deviation(&d, n - 1, &h));
            }
            prop_assert!(dev <= deviation(&d, n + 1, &h));
        }
    }
}

/// peg_cube's flats are at 0 (down), 1 (down), 3 (up and down), 7/2 (up)
/// and 4 (up). With H = 1.1, H/2 = 0.55 exceeds the gap 3..7/2.
#[test]
fn flats_closer_than_half_the_layer_height_are_refused_by_name() {
    let rep = report(&datasets::by_name("peg_cube").unwrap().build());
    match fit_layers(&rep, &r("1.1")) {
        Err(FitError::FlatsTooClose {
            lower,
            upper,
            distance,
            approx,
            ..
        }) => {
            assert_eq!((lower.as_str(), upper.as_str()), ("3", "7/2"));
            assert_eq!((distance.as_str(), approx.as_str()), ("1/2", "0.5"));
        }
        other => panic!("expected FlatsTooClose, got {other:?}"),
    }
    assert!(matches!(
        fit_layers(&rep, &r("0")),
        Err(FitError::NonPositiveHeight(_))
    ));
    // H = 1: 0..1 one layer, 1..3 two, 3..7/2 one of 1/2 (= H/2, allowed),
    // 7/2..4 one.
    let layers = fit_layers(&rep, &r("1")).unwrap();
    let tops: Vec<String> = layers.iter().map(|l| l[1].to_string()).collect();
    assert_eq!(tops, ["1", "2", "3", "7/2", "4"]);
}

/// The uniform plan `3/20 + 3k/10` (H = 0.3, first plane mid-layer),
/// derived by hand: an up flat is printed by the last plane at or below
/// it, up to that layer's top; a down flat by the first plane above it,
/// from that layer's bottom.
/// - down 0: plane 3/20 (k = 0), layer [0, 3/10], printed at 0: exact.
/// - down 1: planes 21/20 (k = 3) > 1, layer [9/10, 6/5]: 1/10 low.
/// - up 3: plane 57/20 (k = 9) <= 3, layer [27/10, 3]: exact.
/// - down 3: plane 63/20 (k = 10), layer [3, 33/10]: exact.
/// - up 7/2: plane 69/20 (k = 11), layer [33/10, 18/5]: 1/10 high.
/// - up 4: plane 15/4 (k = 12), layer [18/5, 39/10]: 1/10 low.
#[test]
fn the_uniform_audit_by_hand() {
    let rep = report(&datasets::by_name("peg_cube").unwrap().build());
    let audit = audit_uniform(&rep, &r("0.3"), &r("3/20")).unwrap();
    let got: Vec<(String, Facing, i64, String)> = audit
        .iter()
        .map(|a| {
            (
                rep.levels[a.level].z.to_string(),
                a.facing,
                a.layer,
                a.offset.to_string(),
            )
        })
        .collect();
    let want = [
        ("0", Facing::Down, 0, "0"),
        ("1", Facing::Down, 3, "-1/10"),
        ("3", Facing::Down, 10, "0"),
        ("3", Facing::Up, 9, "0"),
        ("7/2", Facing::Up, 11, "1/10"),
        ("4", Facing::Up, 12, "-1/10"),
    ];
    let want: Vec<(String, Facing, i64, String)> = want
        .iter()
        .map(|(z, f, k, o)| (z.to_string(), *f, *k, o.to_string()))
        .collect();
    assert_eq!(got, want);
}

/// Critical heights 0, 1, 3, 7/2, 4: with H = 0.6 the last three are each
/// closer than H to the next (gaps 1/2); with H = 1/2 no gap is smaller.
#[test]
fn clusters_by_hand() {
    let rep = report(&datasets::by_name("peg_cube").unwrap().build());
    assert_eq!(clusters(&rep, &r("0.6")).unwrap(), [vec![2, 3, 4]]);
    assert!(clusters(&rep, &r("1/2")).unwrap().is_empty());
    assert_eq!(
        clusters(&rep, &r("1.5")).unwrap(),
        [vec![0, 1], vec![2, 3, 4]]
    );
}

fn json(args: &[&str]) -> serde_json::Value {
    let (code, out, err) = wmslice(args);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).unwrap()
}

#[test]
fn critical_json_holds_the_levels_and_the_reeb_graph() {
    let doc = json(&["critical", "double_torus", "--format", "json"]);
    assert_eq!(doc["format"], "wmslice-critical");
    assert_eq!(doc["version"], 1);
    assert_eq!(doc["genus"], 2);
    assert_eq!(doc["components"], 1);
    assert_eq!(doc["mesh"]["faces"], 144);
    let zs: Vec<&str> = doc["critical"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["z"].as_str().unwrap())
        .collect();
    assert_eq!(zs, ["0", "1", "2", "4"]);
    assert_eq!(doc["critical"][2]["saddles"], serde_json::json!([3]));
    assert_eq!(doc["critical"][2]["below"], 4);
    assert_eq!(doc["critical"][2]["above"], 2);
    assert_eq!(doc["reeb"]["nodes"][2]["kind"], "saddle");
    assert_eq!(
        doc["reeb"]["arcs"],
        serde_json::json!([[0, 2], [0, 2], [0, 3], [1, 2], [2, 3]])
    );
}

#[test]
fn slice_fit_critical_cuts_each_fitted_layer_at_its_middle() {
    let plan = json(&[
        "critical",
        "peg_cube",
        "--layer-height",
        "0.3",
        "--fit-critical",
        "--format",
        "json",
    ]);
    let mids: Vec<Rat> = plan["layers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| (r(l[0].as_str().unwrap()) + r(l[1].as_str().unwrap())) / r("2"))
        .collect();
    assert_eq!(mids.len(), 14);
    let sliced = json(&[
        "slice",
        "peg_cube",
        "--layer-height",
        "0.3",
        "--fit-critical",
        "--format",
        "json",
        "--exact",
    ]);
    let levels: Vec<Rat> = sliced["levels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| r(l["z"].as_str().unwrap()))
        .collect();
    assert_eq!(levels, mids);
}

#[test]
fn critical_errors_exit_with_their_codes() {
    let (code, _, err) = wmslice(&[
        "critical",
        "peg_cube",
        "--layer-height",
        "1.1",
        "--fit-critical",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("z = 3 and z = 7/2"), "{err}");
    let (code, _, _) = wmslice(&["critical", "peg_cube", "--layer-height", "x"]);
    assert_eq!(code, 2);
    let (code, _, _) = wmslice(&["critical", "peg_cube", "--fit-critical"]);
    assert_eq!(code, 2);
    let (code, _, _) = wmslice(&["critical", "no_such_mesh"]);
    assert_eq!(code, 4);
    // An open box (one face missing) is refused by validation.
    let dir = std::env::temp_dir().join(format!("wmslice-critical-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("open.off");
    let (p, f) = common::unit_box(1.0);
    let mut text = format!("OFF\n{} {} 0\n", p.len(), f.len() - 1);
    for [x, y, z] in p {
        text += &format!("{x} {y} {z}\n");
    }
    for [a, b, c] in &f[1..] {
        text += &format!("3 {a} {b} {c}\n");
    }
    std::fs::write(&path, text).unwrap();
    let out = dir.join("out.json");
    let (code, _, _) = wmslice(&[
        "critical",
        path.to_str().unwrap(),
        "--format",
        "json",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 3);
    assert!(!out.exists(), "no output file for a refused mesh");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A slab's bottom split by a file's rounding, as `f32` exports leave
/// it: cell 0 at z = 0, cell 2 at z = 2^-49, a sloped cell between (three
/// cells along x, one along y). `--fit-critical` refuses the two flats by
/// name with their exact distance and suggests snapping; snapping to a
/// micron, as suggested, makes them one flat and the plan is made.
#[test]
fn flats_a_rounding_split_are_named_and_merge_when_snapped() {
    let slab = common::Slab {
        nx: 3,
        ny: 1,
        bot: vec![0; 8],
        thick: vec![1; 8],
        diag: vec![false; 3],
        rot: 0,
    };
    let mut m = slab.mesh();
    for p in &mut m.positions {
        if p[2] == 0.0 && p[0] >= 2.0 {
            p[2] = 2f64.powi(-49);
        }
    }
    let mut text = format!("OFF\n{} {} 0\n", m.positions.len(), m.faces.len());
    for [x, y, z] in &m.positions {
        text += &format!("{x:?} {y:?} {z:?}\n");
    }
    for [a, b, c] in &m.faces {
        text += &format!("3 {} {} {}\n", a.0, b.0, c.0);
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("split_bottom.off");
    std::fs::write(&path, text).unwrap();
    let file = path.to_str().unwrap();
    let fit = ["--layer-height", "0.2", "--fit-critical"];
    let (code, _, err) = wmslice(&[&["critical", file][..], &fit].concat());
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(
            "z = 0 and z = 1/562949953421312 are 1/562949953421312 apart (~1.7763568394002505e-15)"
        ),
        "{err}"
    );
    assert!(err.contains("snap the mesh: --snap Q"), "{err}");
    let (code, out, err) = wmslice(&[&["critical", file, "--snap", "1e-6"][..], &fit].concat());
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("fitted plan: 5 layers"), "{out}");
}

/// The SVG holds one circle per node plus the seven legend entries and
/// one path per arc.
#[test]
fn critical_svg_draws_every_node_and_arc() {
    let (code, svg, _) = wmslice(&["critical", "double_torus", "--format", "svg"]);
    assert_eq!(code, 0);
    assert!(svg.starts_with("<svg"));
    assert_eq!(svg.matches("<circle").count(), 4 + 7);
    assert_eq!(svg.matches("<path").count(), 5);
}

/// The README's picture is what the command draws today (regenerate with
/// `wmslice critical double_torus --format svg -o docs/reeb-double-torus.svg`).
#[test]
fn the_readme_picture_is_current() {
    let (code, svg, _) = wmslice(&["critical", "double_torus", "--format", "svg"]);
    assert_eq!(code, 0);
    let committed = std::fs::read_to_string("docs/reeb-double-torus.svg").unwrap();
    assert_eq!(svg, committed);
}

/// The document is exactly what `serde_json` writes for its own value
/// (keys in byte order at every level, one line), with every plan; each
/// cluster lists the Reeb nodes at its heights, in order.
#[test]
fn critical_json_is_the_text_of_its_own_value() {
    let mut clusters_seen = 0;
    for mesh in ["double_torus", "peg_cube", "platform_grid", "upright_torus"] {
        for plan in [
            &[][..],
            &["--layer-height", "1.5"][..],
            &["--layer-height", "0.3", "--fit-critical"][..],
        ] {
            let mut args = vec!["critical", mesh, "--format", "json"];
            args.extend_from_slice(plan);
            let (code, out, err) = wmslice(&args);
            assert_eq!(code, 0, "{mesh} {plan:?}: {err}");
            let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
            assert_eq!(out, format!("{doc}\n"), "{mesh} {plan:?}");
            let nodes = doc["reeb"]["nodes"].as_array().unwrap();
            for c in doc["clusters"].as_array().into_iter().flatten() {
                let heights = c["heights"].as_array().unwrap();
                let at: Vec<u64> = (0..nodes.len() as u64)
                    .filter(|&i| heights.contains(&nodes[i as usize]["z"]))
                    .collect();
                assert_eq!(c["nodes"], serde_json::json!(at), "{mesh} {plan:?}");
                clusters_seen += usize::from(!at.is_empty());
            }
        }
    }
    assert!(clusters_seen > 0);
}

/// Heights whose exact text outgrows the axis's margin (a part moved to
/// `2^51`) are labelled by their nearest double, each node's tooltip
/// keeping the exact height; the part drawn at home keeps exact labels.
#[test]
fn critical_svg_labels_long_heights_by_their_nearest_double() {
    use wmslice::datasets::cross_check::far_offset;
    use wmslice::exact::rational::{rat_from_f64, rat_to_string};
    use wmslice::output::reeb_svg::reeb_svg;
    let mesh = wmslice::datasets::by_name("double_torus").unwrap().build();
    let graph = |m: &wmslice::Mesh| {
        let slicer = wmslice::Slicer::new(m).unwrap();
        wmslice::critical::analyze(&slicer).unwrap().reeb
    };
    let home = reeb_svg(&graph(&mesh), "home");
    for label in ["z = 0", "z = 2", "z = 4"] {
        assert!(home.contains(&format!(">{label}</text>")), "{label}");
    }
    let (t, far) = far_offset(&mesh).unwrap();
    assert_eq!(t, 2f64.powi(51));
    let g = graph(&far);
    let svg = reeb_svg(&g, "far");
    // 2^51 + 2 = 2251799813685250: 2.25e15 to three digits.
    assert!(svg.contains(">z \u{2248} 2.25e15</text>"), "{svg}");
    let top = rat_to_string(&(rat_from_f64(t) + wmslice::exact::parse_rational("4").unwrap()));
    assert!(svg.contains(&format!("at z = {top}</title>")), "{svg}");
    assert!(!svg.contains("NaN"));

    // Heights from -2^1023 to 2^1023, whose difference overflows: the
    // nodes still sit between the margins, in order of height.
    // (z - 2) 2^1022, x and y kept: an affine map, exact, still valid.
    let mut wide = mesh.clone();
    for p in &mut wide.positions {
        p[2] = (p[2] - 2.0) * 2f64.powi(1022);
    }
    let svg = reeb_svg(&graph(&wide), "wide");
    let cy: Vec<f64> = svg
        .split("<circle cx=")
        .skip(1)
        .take(4)
        .map(|c| {
            let c = &c[c.find("cy=\"").unwrap() + 4..];
            c[..c.find('"').unwrap()].parse().unwrap()
        })
        .collect();
    assert_eq!(cy.len(), 4);
    assert!(cy.iter().all(|y| (0.0..=600.0).contains(y)), "{cy:?}");
    assert!(cy.first() > cy.last(), "{cy:?}");
}
