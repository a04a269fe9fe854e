//! The layer sweep gives exactly the level sets of slicing each level
//! alone, on every dataset and on random integer meshes, for any number of
//! threads.

mod common;

use common::slab;
use proptest::prelude::*;
use std::convert::Infallible;
use wmslice::datasets;
use wmslice::exact::rational::Rat;
use wmslice::layers::slice_levels;
use wmslice::levelset::check::vertex_heights;
use wmslice::{LevelSet, Mesh, Slicer};

/// Every vertex height, the midpoints, and a quarter-step above each.
fn levels_of(mesh: &Mesh) -> Vec<Rat> {
    let zs = vertex_heights(mesh);
    let mut v = zs.clone();
    let four = Rat::from_integer(4.into());
    for w in zs.windows(2) {
        v.push((&w[0] + &w[1]) / Rat::from_integer(2.into()));
        v.push(&w[0] + (&w[1] - &w[0]) / &four);
    }
    v.sort();
    v
}

fn swept(slicer: &Slicer<'_>, levels: &[Rat], threads: usize) -> Vec<LevelSet> {
    let mut out = Vec::new();
    slice_levels::<Infallible, _>(slicer, levels, threads, |i, ls| {
        assert_eq!(i, out.len(), "levels arrive in order");
        out.push(ls);
        Ok(())
    })
    .unwrap();
    out
}

fn assert_sweep_equals_single(mesh: &Mesh, name: &str) {
    let slicer = Slicer::new(mesh).unwrap();
    let levels = levels_of(mesh);
    let single: Vec<LevelSet> = levels.iter().map(|c| slicer.slice_at(c).unwrap()).collect();
    for threads in [1, 2, 3] {
        let s = swept(&slicer, &levels, threads);
        assert_eq!(s.len(), single.len());
        for (k, (a, b)) in s.iter().zip(&single).enumerate() {
            assert!(
                a == b,
                "{name}: level {} differs with {threads} threads",
                levels[k]
            );
        }
    }
}

#[test]
fn sweep_equals_single_levels_on_every_dataset() {
    for d in datasets::all() {
        assert_sweep_equals_single(&d.build(), d.name);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, .. ProptestConfig::default() })]
    #[test]
    fn sweep_equals_single_levels_on_random_meshes(s in slab()) {
        assert_sweep_equals_single(&s.mesh(), "slab");
    }
}

/// A sink that refuses a level stops the sweep with its error, having
/// seen exactly the levels before it, in order: workers waiting for room
/// or to send are released (the test would hang otherwise), whatever the
/// thread count.
#[test]
fn a_refusing_sink_stops_the_sweep() {
    let mesh = datasets::by_name("double_torus").unwrap().build();
    let slicer = Slicer::new(&mesh).unwrap();
    let levels: Vec<Rat> = (0..200).map(|k| Rat::new(k.into(), 50.into())).collect();
    for threads in [1, 2, 3, 8] {
        for stop in [0, 1, 37, 199] {
            let mut seen = Vec::new();
            let r = slice_levels(&slicer, &levels, threads, |i, _| {
                seen.push(i);
                if i == stop {
                    Err(std::io::Error::other("full"))
                } else {
                    Ok(())
                }
            });
            assert!(
                matches!(r, Err(wmslice::layers::SweepError::Sink(ref e)) if e.to_string() == "full"),
                "{threads} threads, stop at {stop}: {r:?}"
            );
            assert_eq!(seen, (0..=stop).collect::<Vec<_>>());
        }
    }
}

/// A plan made beforehand (as the CLI makes it beside validation) slices
/// as `slice_levels` does; a plan made for another mesh (here an equal
/// copy) or for a mesh validation refuses is no trap.
#[test]
fn plans_made_beforehand_slice_the_same() {
    use wmslice::layers::{slice_plan_then, SweepPlan};
    let one = Rat::from_integer(1.into());
    let keep = |_: usize, ls: LevelSet| ls;
    for d in datasets::all() {
        let mesh = d.build();
        let copy = mesh.clone();
        let slicer = Slicer::new(&mesh).unwrap();
        let levels = levels_of(&mesh);
        let reference = swept(&slicer, &levels, 1);
        for plan in [
            SweepPlan::new(&mesh, &one, &levels),
            SweepPlan::new(&copy, &one, &levels),
        ] {
            for threads in [1, 3] {
                let mut out = Vec::new();
                slice_plan_then::<_, Infallible, _, _>(&slicer, &plan, threads, &keep, |_, ls| {
                    out.push(ls);
                    Ok(())
                })
                .unwrap();
                assert!(out == reference, "{}", d.name);
            }
        }
    }
    let mut broken = datasets::by_name("octahedron").unwrap().build();
    broken.faces[0][0] = wmslice::ids::VertexId(99);
    let levels = vec![one.clone()];
    let _ = SweepPlan::new(&broken, &one, &levels);
}
