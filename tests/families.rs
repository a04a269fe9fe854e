//! The random families of `wmslice gen --random SEED --family NAME`:
//! every mesh is accepted (closed, oriented, no fold, no
//! self-intersection, no degenerate face), generation is deterministic,
//! each family hits the degeneracies it claims, and the answers equal an
//! independent plain exact classification (`common/exact_levels.rs`,
//! written from the SPEC alone) at every level they list, which are
//! exactly the critical heights and the midpoints between them.

#[path = "common/exact_levels.rs"]
mod exact_levels;

use exact_levels::ExactMesh;
use std::collections::BTreeSet;
use wmslice::datasets::families::answers::{answers, LevelKind};
use wmslice::datasets::families::{all, by_name, Family};
use wmslice::exact::rational::{rat_to_string, Rat};
use wmslice::mesh::io::MeshFormat;
use wmslice::mesh::validate::validate;

fn family(name: &str) -> &'static Family {
    by_name(name).unwrap_or_else(|| panic!("family {name}"))
}

#[test]
fn there_are_five_families_with_distinct_names() {
    let names: BTreeSet<&str> = all().iter().map(|f| f.name).collect();
    assert_eq!(names.len(), 5);
    for n in [
        "height_field",
        "polycube",
        "terraced",
        "egg_crate",
        "handles",
    ] {
        assert!(names.contains(n), "{n}");
    }
    assert_eq!(
        family("terraced").snap(),
        Some(Rat::new(1.into(), 1000.into()))
    );
    assert!(by_name("nope").is_none());
}

#[test]
fn every_family_makes_accepted_meshes_for_many_seeds() {
    for f in all() {
        for seed in (0..60).chain([u64::MAX, 1 << 40]) {
            let mesh = f.generate(seed);
            let report = validate(&mesh);
            assert!(report.is_accepted(), "{} seed {seed}:\n{report}", f.name);
            if let Some(q) = f.snap() {
                let p = wmslice::mesh::prepare::prepare(mesh, Some(&q)).expect("snaps");
                assert!(
                    p.flips.is_empty(),
                    "{} seed {seed}: no degenerate face",
                    f.name
                );
                assert_eq!(p.snap.as_ref().map(|s| s.merged), Some(0));
                let report = validate(&p.mesh);
                assert!(
                    report.is_accepted(),
                    "{} seed {seed} snapped:\n{report}",
                    f.name
                );
            }
        }
    }
}

/// The bytes of a mesh file and of the answers, with `threads` rayon
/// workers.
fn generated_bytes(f: &Family, seed: u64, threads: usize) -> (Vec<u8>, Vec<u8>, String) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a pool");
    pool.install(|| {
        let dir = tempfile::tempdir().expect("a temporary directory");
        let mesh = f.generate(seed);
        let (obj, stl) = (dir.path().join("m.obj"), dir.path().join("m.stl"));
        mesh.save_as(&obj, MeshFormat::Obj).expect("writes OBJ");
        mesh.save_as(&stl, MeshFormat::StlBinary)
            .expect("writes STL");
        let a = answers(mesh, f.snap().as_ref()).expect("answers");
        (
            std::fs::read(obj).expect("reads"),
            std::fs::read(stl).expect("reads"),
            a.to_json(f, seed),
        )
    })
}

#[test]
fn generation_is_deterministic_across_calls_and_thread_counts() {
    for f in all() {
        for seed in [0, 7] {
            let one = generated_bytes(f, seed, 1);
            let two = generated_bytes(f, seed, 2);
            assert_eq!(one, two, "{} seed {seed}", f.name);
            assert_ne!(
                f.generate(seed),
                f.generate(seed + 1),
                "{} seeds differ",
                f.name
            );
        }
    }
}

#[test]
fn each_family_hits_the_degeneracies_it_claims() {
    let mut seen: std::collections::BTreeMap<&str, BTreeSet<String>> = Default::default();
    for f in all() {
        let set = seen.entry(f.name).or_default();
        for seed in 0..12 {
            let mesh = f.generate(seed);
            let report = validate(&mesh);
            if report.stats.genus.unwrap_or(0) > 0 {
                set.insert("genus".into());
            }
            if report.stats.components > Some(1) {
                set.insert("components".into());
            }
            let a = answers(mesh, f.snap().as_ref()).expect("answers");
            for l in &a.levels {
                let s = &l.summary;
                let mut add = |k: &str, yes: bool| {
                    if yes {
                        set.insert(k.to_string());
                    }
                };
                add("flat_up", s.f_up > 0);
                add("flat_down", s.f_down > 0);
                add("ridge", s.s_no_ridges > 0);
                add("valley", s.s_no_valleys > 0);
                add("min", s.p_min > 0);
                add("max", s.p_max > 0);
                add("collapsed", s.l_minus_collapsed + s.l_plus_collapsed > 0);
                add(
                    "hole_in_region",
                    s.f_regions > 0 && s.l_minus_loops + s.l_plus_loops > 2,
                );
                add("mixed", l.kind == LevelKind::Mixed);
                for m in &s.saddles {
                    add(&format!("m{m}"), true);
                }
                add("decimal", l.critical && l.z.denom() % 5u32 == 0.into());
            }
        }
    }
    let wants: [(&str, &[&str]); 5] = [
        (
            "height_field",
            &[
                "flat_up",
                "flat_down",
                "ridge",
                "valley",
                "min",
                "max",
                "m2",
                "mixed",
                "genus",
            ],
        ),
        (
            "polycube",
            &["flat_up", "flat_down", "genus", "hole_in_region"],
        ),
        ("terraced", &["flat_up", "flat_down", "decimal"]),
        (
            "egg_crate",
            &["m2", "m3", "m4", "min", "max", "flat_up", "mixed"],
        ),
        (
            "handles",
            &[
                "ridge",
                "valley",
                "m2",
                "flat_up",
                "flat_down",
                "collapsed",
                "genus",
                "components",
            ],
        ),
    ];
    for (name, want) in wants {
        for w in want {
            assert!(
                seen[name].contains(*w),
                "{name} never shows {w}: {:?}",
                seen[name]
            );
        }
    }
}

#[test]
fn terraced_flats_lie_at_f32_values_and_snap_to_their_decimals() {
    let f = family("terraced");
    let mut decimals = BTreeSet::new();
    for seed in 0..10 {
        let mesh = f.generate(seed);
        // As stored: every height is an f32 value.
        for p in &mesh.positions {
            assert_eq!(f64::from(p[2] as f32), p[2]);
        }
        let a = answers(mesh, f.snap().as_ref()).expect("answers");
        for l in a.levels.iter().filter(|l| l.critical) {
            // Snapped: the decimals of the design, thousandths at most.
            assert_eq!(1000u32 % l.z.denom(), 0.into(), "{}", rat_to_string(&l.z));
            decimals.insert(rat_to_string(&l.z));
        }
    }
    for d in ["0", "1/5", "207/20"] {
        assert!(decimals.contains(d), "{d} not among {decimals:?}");
    }
}

/// The answers at every listed level equal the independent
/// classification, and the listed levels are exactly the critical
/// heights (found independently at every vertex height) and the
/// midpoints between consecutive ones.
fn check_against_independent_classification(f: &Family, seed: u64) {
    let mesh = f.generate(seed);
    let snap = f.snap();
    let x = ExactMesh::new(&mesh, snap.as_ref());
    let a = answers(mesh, snap.as_ref()).expect("answers");
    let at =
        |what: &str, z: &Rat| format!("{} seed {seed} z = {}: {what}", f.name, rat_to_string(z));
    let critical: Vec<Rat> = x
        .heights
        .iter()
        .filter(|c| x.classify(c).is_critical())
        .cloned()
        .collect();
    let listed_critical: Vec<Rat> = a
        .levels
        .iter()
        .filter(|l| l.critical)
        .map(|l| l.z.clone())
        .collect();
    assert_eq!(
        listed_critical, critical,
        "{} seed {seed}: the critical heights",
        f.name
    );
    assert_eq!(a.levels.len(), 2 * critical.len() - 1);
    let two = Rat::from_integer(2.into());
    for (k, l) in a.levels.iter().enumerate() {
        if k % 2 == 1 {
            assert!(!l.critical);
            assert_eq!(l.z, (&a.levels[k - 1].z + &a.levels[k + 1].z) / &two);
        }
        let z = &l.z;
        let s = &l.summary;
        let c = x.classify(z);
        assert_eq!(s.f_regions, c.f_regions, "{}", at("F regions", z));
        assert_eq!(
            (s.f_up, s.f_down),
            (c.f_up, c.f_down),
            "{}",
            at("F facing", z)
        );
        assert_eq!(s.f_area, c.f_area, "{}", at("F area", z));
        assert_eq!(
            (s.s_no_ridges, s.s_no_valleys),
            (c.s_no_ridges, c.s_no_valleys),
            "{}",
            at("S_NO", z)
        );
        assert_eq!(s.s_no_polylines, c.s_no_ridges + c.s_no_valleys);
        assert_eq!((s.p_min, s.p_max), (c.p_min, c.p_max), "{}", at("P", z));
        assert_eq!(s.saddles, c.saddles, "{}", at("saddles", z));
        assert_eq!(s.s_o_loops, c.s_o_loops, "{}", at("S_O loops", z));
        assert_eq!(s.s_o_area, c.s_o_area, "{}", at("S_O area", z));
        let below = x.limit(z, true);
        let above = x.limit(z, false);
        // Loop counts and exact areas. The collapsed counts are not
        // compared: the classifier flags a loop whose own limit area is 0,
        // SPEC 6 (and the slicer) a loop bounding a region of zero limit
        // area (a ridge ring's two loops each bound a disc, yet the ring
        // between them vanishes); the verifier checks the flag exactly.
        assert_eq!(
            (s.l_minus_loops, &s.l_minus_area),
            (below.loops, &below.area),
            "{}",
            at("L-", z)
        );
        assert_eq!(
            (s.l_plus_loops, &s.l_plus_area),
            (above.loops, &above.area),
            "{}",
            at("L+", z)
        );
        // Material just below but not just above lies on up faces, and
        // the other way round: S_O's region is L-'s less the up regions.
        assert_eq!(
            &below.area - &c.f_up_area,
            c.s_o_area,
            "{}",
            at("L- = S_O + F up", z)
        );
        assert_eq!(
            &above.area - &c.f_down_area,
            c.s_o_area,
            "{}",
            at("L+ = S_O + F down", z)
        );
        // A midpoint can be the height of a vertex that is not critical;
        // elsewhere the level holds no vertex and its loops are counted
        // directly.
        if !l.critical && x.heights.binary_search(z).is_err() {
            let regular = x.regular(z);
            assert_eq!(regular.len(), s.s_o_loops, "{}", at("a regular level", z));
        }
        assert_eq!(
            l.kind == LevelKind::Regular,
            !l.critical,
            "{}",
            at("kind", z)
        );
    }
    // Between critical heights nothing changes: at every vertex height
    // that is not critical, L- and L+ have one structure and one area.
    for h in x.heights.iter().filter(|h| !critical.contains(h)) {
        let (b, u) = (x.limit(h, true), x.limit(h, false));
        assert_eq!(
            (b.loops, &b.area),
            (u.loops, &u.area),
            "{}",
            at("regular vertex height", h)
        );
        assert_eq!(
            b.collapsed + u.collapsed,
            0,
            "{}",
            at("regular vertex height", h)
        );
    }
}

#[test]
fn answers_equal_an_independent_classification_height_field() {
    for seed in 0..6 {
        check_against_independent_classification(family("height_field"), seed);
    }
}

#[test]
fn answers_equal_an_independent_classification_polycube() {
    for seed in 0..4 {
        check_against_independent_classification(family("polycube"), seed);
    }
}

#[test]
fn answers_equal_an_independent_classification_terraced() {
    for seed in 0..5 {
        check_against_independent_classification(family("terraced"), seed);
    }
}

#[test]
fn answers_equal_an_independent_classification_egg_crate() {
    for seed in 0..4 {
        check_against_independent_classification(family("egg_crate"), seed);
    }
}

#[test]
fn answers_equal_an_independent_classification_handles() {
    for seed in 0..8 {
        check_against_independent_classification(family("handles"), seed);
    }
}

#[test]
fn independent_classification_on_hand_derived_datasets() {
    // The classifier itself against the datasets' hand-derived facts.
    let cube = wmslice::datasets::by_name("unit_cube").unwrap().build();
    let x = ExactMesh::new(&cube, None);
    let half = Rat::new(1.into(), 2.into());
    let c = x.classify(&half);
    assert_eq!(
        (c.s_o_loops, c.s_o_area.clone()),
        (1, Rat::from_integer(1.into()))
    );
    let top = x.classify(&Rat::from_integer(1.into()));
    assert_eq!((top.f_up, top.s_o_loops), (1, 0));
    assert_eq!(
        x.limit(&Rat::from_integer(1.into()), true).area,
        Rat::from_integer(1.into())
    );
    let torus = wmslice::datasets::by_name("upright_torus").unwrap().build();
    let x = ExactMesh::new(&torus, None);
    for z in [-1, 1] {
        let c = x.classify(&Rat::from_integer(z.into()));
        assert_eq!(c.saddles, vec![2], "ordinary saddle at z = {z}");
    }
    let lying = wmslice::datasets::by_name("lying_torus").unwrap().build();
    let x = ExactMesh::new(&lying, None);
    let top = x.classify(&Rat::from_integer(2.into()));
    assert_eq!((top.s_no_ridges, top.s_o_loops), (1, 0));
    // Just below the top ridge ring: two loops, around and inside the
    // ring, whose signed areas cancel in the limit (the ring has no area).
    let below = x.limit(&Rat::from_integer(2.into()), true);
    assert_eq!((below.loops, below.area), (2, Rat::from_integer(0.into())));
    let saddle8 = wmslice::datasets::by_name("saddle8").unwrap().build();
    let x = ExactMesh::new(&saddle8, None);
    assert_eq!(x.classify(&Rat::from_integer(2.into())).saddles, vec![4]);
    let double = wmslice::datasets::by_name("double_torus").unwrap().build();
    let x = ExactMesh::new(&double, None);
    assert_eq!(x.classify(&Rat::from_integer(2.into())).saddles, vec![3]);
}

#[test]
fn the_gen_command_lists_families_and_writes_a_mesh_with_its_answers() {
    let run = |args: &[&str]| {
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_wmslice"))
            .args(args)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
        )
    };
    let (code, out) = run(&["gen", "--families"]);
    assert_eq!(code, Some(0));
    let names: Vec<&str> = out
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .collect();
    let expected: Vec<&str> = all().iter().map(|f| f.name).collect();
    assert_eq!(names, expected);
    let dir = tempfile::tempdir().unwrap();
    let write = |tag: &str| {
        let (m, a) = (
            dir.path().join(format!("{tag}.obj")),
            dir.path().join(format!("{tag}.json")),
        );
        let (code, _) = run(&[
            "gen",
            "--random",
            "7",
            "--family",
            "terraced",
            "-o",
            m.to_str().unwrap(),
            "--answers",
            a.to_str().unwrap(),
        ]);
        assert_eq!(code, Some(0));
        (
            std::fs::read(m).unwrap(),
            std::fs::read_to_string(a).unwrap(),
        )
    };
    let (mesh, text) = write("a");
    assert_eq!((mesh.clone(), text.clone()), write("b"), "deterministic");
    let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["format"], "wmslice-answers");
    assert_eq!(
        (doc["family"].as_str(), doc["seed"].as_u64()),
        (Some("terraced"), Some(7))
    );
    assert_eq!(doc["mesh"]["snap"], "1/1000");
    let levels = doc["levels"].as_array().unwrap();
    assert_eq!(
        levels.len() % 2,
        1,
        "critical heights and the midpoints between"
    );
    assert!(levels.iter().step_by(2).all(|l| l["critical"] == true));
    let (code, _) = run(&["gen", "--random", "1", "--family", "nope", "-o", "x.obj"]);
    assert_eq!(code, Some(2));
}
