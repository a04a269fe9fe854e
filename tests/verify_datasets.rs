//! Input: every built-in dataset at every vertex height and between them,
//! a snapped dataset, and random closed slabs (ties everywhere), sliced and
//! written as exact JSON. Output: the verifier accepts every result, and
//! catches every deleted or reversed loop of the random slabs.

mod common;

use proptest::prelude::*;
use wmslice::datasets;
use wmslice::exact::rational::Rat;
use wmslice::levelset::check::vertex_heights;
use wmslice::output::json::{to_json, Exactness, MeshHeader};
use wmslice::verify::{outline, verify, Verifier};
use wmslice::{Mesh, Slicer};

/// Every vertex height of `mesh` and the midpoints between them.
fn heights_and_midpoints(mesh: &Mesh) -> Vec<Rat> {
    let zs = vertex_heights(mesh);
    let two = Rat::from_integer(2.into());
    let mids: Vec<Rat> = zs.windows(2).map(|w| (&w[0] + &w[1]) / &two).collect();
    zs.into_iter().chain(mids).collect()
}

/// Slices `mesh` at `levels` (grid `unit`), writes exact JSON, verifies it.
fn slice_and_verify(name: &str, mesh: &Mesh, unit: Option<&Rat>, levels: &[Rat]) {
    let slicer = Slicer::with_unit(
        mesh,
        unit.cloned().unwrap_or_else(|| Rat::from_integer(1.into())),
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    let sets: Vec<_> = levels
        .iter()
        .map(|c| {
            slicer
                .slice_at(c)
                .unwrap_or_else(|e| panic!("{name} at {c}: {e}"))
        })
        .collect();
    let text = to_json(&MeshHeader::new(mesh, unit), &sets, Exactness::WithExact);
    let report = verify(mesh, unit, &text).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(
        report.passed(),
        "{name}: {}\n{}",
        report.summary(),
        report
            .violations
            .iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// The outline counts a result's levels, and the verifier reports each
/// one done, in order, once (what `wmslice verify`'s progress bar shows).
#[test]
fn the_outline_counts_the_levels_the_verifier_reports_done() {
    let mesh = datasets::by_name("double_torus").unwrap().build();
    let levels = heights_and_midpoints(&mesh);
    let slicer = Slicer::new(&mesh).unwrap();
    let sets: Vec<_> = levels.iter().map(|c| slicer.slice_at(c).unwrap()).collect();
    let text = to_json(&MeshHeader::new(&mesh, None), &sets, Exactness::WithExact);
    let (header, count) = outline(&text).unwrap();
    assert_eq!(count, levels.len());
    assert_eq!(header.faces, mesh.num_faces() as u64);
    let mut done = Vec::new();
    let report = Verifier::new(&mesh, None)
        .unwrap()
        .verify_with(&text, |n| done.push(n))
        .unwrap();
    assert!(report.passed(), "{}", report.summary());
    assert_eq!(done, (1..=count).collect::<Vec<_>>());
}

#[test]
fn every_dataset_verifies_at_every_height_and_between() {
    for d in datasets::all() {
        let mesh = d.build();
        slice_and_verify(d.name, &mesh, None, &heights_and_midpoints(&mesh));
    }
}

#[test]
fn a_snapped_mesh_verifies_in_true_units() {
    // The double torus on a grid of 1/4: stored coordinates are grid
    // indices, the result is in true units.
    let mesh = datasets::by_name("double_torus").unwrap().build();
    let q = Rat::new(1.into(), 4.into());
    let snapped = wmslice::mesh::snap::snap(&mesh, &q).unwrap();
    let levels: Vec<Rat> = heights_and_midpoints(&mesh);
    slice_and_verify("double_torus/4", &snapped.mesh, Some(&q), &levels);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn random_slabs_verify_at_every_vertex_height(s in common::slab()) {
        let mesh = s.mesh();
        slice_and_verify(&format!("{s:?}"), &mesh, None, &heights_and_midpoints(&mesh));
    }
}

/// The loop lists of the first level: `(family, loops)`, mutable.
fn loop_lists(
    doc: &mut wmslice::verify::json::Value,
) -> Vec<&mut Vec<wmslice::verify::json::Value>> {
    let lv = &mut doc.get_mut("levels").unwrap().as_array_mut().unwrap()[0];
    let wmslice::verify::json::Value::Object(fields) = lv else {
        panic!("a level is an object")
    };
    let mut out = Vec::new();
    for (k, v) in fields.iter_mut() {
        match k.as_str() {
            "contours" | "below" | "above" => out.push(v.as_array_mut().unwrap()),
            "faces" => {
                for r in v.as_array_mut().unwrap() {
                    out.push(r.get_mut("boundary").unwrap().as_array_mut().unwrap());
                }
            }
            _ => {}
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn random_slabs_catch_every_deleted_or_reversed_loop(s in common::slab(), pick in 0usize..64) {
        let mesh = s.mesh();
        let zs = heights_and_midpoints(&mesh);
        let c = &zs[pick % zs.len()];
        let ls = Slicer::new(&mesh).unwrap().slice_at(c).unwrap();
        let text = to_json(&MeshHeader::new(&mesh, None), &[ls], Exactness::WithExact);
        let clean = wmslice::verify::json::parse(&text).unwrap();
        let counts: Vec<usize> = loop_lists(&mut clean.clone()).iter().map(|l| l.len()).collect();
        for (f, &n) in counts.iter().enumerate() {
            for l in 0..n {
                let mut doc = clean.clone();
                loop_lists(&mut doc)[f].remove(l);
                let r = verify(&mesh, None, &doc.to_json()).unwrap();
                prop_assert!(!r.passed(), "deleting loop {l} of list {f} at {c} passed");
                let mut doc = clean.clone();
                let lp = &mut loop_lists(&mut doc)[f][l];
                // A collapsed limit (around an extremum, along a ridge and
                // back) may read the same both ways.
                if reads_the_same_reversed(lp.get_mut("on").unwrap().as_array_mut().unwrap()) {
                    continue;
                }
                for k in ["points", "exact", "on"] {
                    lp.get_mut(k).unwrap().as_array_mut().unwrap().reverse();
                }
                let r = verify(&mesh, None, &doc.to_json()).unwrap();
                prop_assert!(!r.passed(), "reversing loop {l} of list {f} at {c} passed");
            }
        }
    }
}

/// Whether a cyclic sequence reversed is one of its rotations (a limit
/// collapsed onto a point, or onto a path it runs along and back).
fn reads_the_same_reversed(on: &[wmslice::verify::json::Value]) -> bool {
    let text: Vec<String> = on.iter().map(|v| v.to_json()).collect();
    let mut back = text.clone();
    back.reverse();
    (0..text.len()).any(|r| back[r..].iter().chain(&back[..r]).eq(text.iter())) || text.is_empty()
}
