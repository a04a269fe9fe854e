//! Issue-3 acceptance: for every dataset, at every degenerate height and a
//! regular height next to it, the counts of each kind and the exact areas
//! equal the values derived by hand from the construction
//! (`src/datasets/expected.rs`, reasoning in `DATASETS.md`).

use wmslice::classify::{ExtremumKind, Facing, RidgeKind};
use wmslice::datasets::{self, expected::expected};
use wmslice::exact::rational::Rat;
use wmslice::levelset::{LevelSet, Loop};
use wmslice::nest::Role;
use wmslice::Slicer;

fn rat((p, q): (i128, u128)) -> Rat {
    Rat::new(p.into(), q.into())
}

fn sum(loops: &[Loop]) -> Rat {
    loops
        .iter()
        .fold(Rat::from_integer(0.into()), |a, l| a + l.area())
}

fn observed(ls: &LevelSet) -> String {
    let outer = ls.contours.iter().filter(|l| l.role == Role::Outer).count();
    let facing = |f: Facing| ls.regions.iter().filter(|r| r.facing == f).count();
    let ridges = |k: RidgeKind, c: bool| {
        ls.ridges
            .iter()
            .filter(|r| r.kind == k && r.closed == c)
            .count()
    };
    let pts = |k: ExtremumKind| ls.extrema.iter().filter(|p| p.kind == k).count();
    let mut saddles: Vec<u32> = ls.saddles.iter().map(|s| s.branches).collect();
    saddles.sort_unstable();
    let area_f = |f: Facing| {
        ls.regions
            .iter()
            .filter(|r| r.facing == f)
            .fold(Rat::from_integer(0.into()), |a, r| a + &r.area)
    };
    format!(
        "S_O {}+{} | F up {} down {} flat {} | ridges {}/{} valleys {}/{} | min {} max {} | saddles {:?} | A(S_O) {} A(L-) {} A(L+) {} A(F up) {} A(F down) {}",
        outer,
        ls.contours.len() - outer,
        facing(Facing::Up),
        facing(Facing::Down),
        facing(Facing::Flat),
        ridges(RidgeKind::Ridge, false),
        ridges(RidgeKind::Ridge, true),
        ridges(RidgeKind::Valley, false),
        ridges(RidgeKind::Valley, true),
        pts(ExtremumKind::Min),
        pts(ExtremumKind::Max),
        saddles,
        sum(&ls.contours),
        sum(&ls.below),
        sum(&ls.above),
        area_f(Facing::Up),
        area_f(Facing::Down),
    )
}

#[test]
fn every_dataset_level_matches_its_hand_derived_expectation() {
    let mut failures = Vec::new();
    for e in expected() {
        let d = datasets::by_name(e.dataset).unwrap();
        let mesh = d.build();
        let slicer = Slicer::new(&mesh).unwrap();
        let c = Rat::new(e.level.0.into(), e.level.1.into());
        let ls = slicer.slice_at(&c).unwrap();
        let want = format!(
            "S_O {}+{} | F up {} down {} flat {} | ridges {}/{} valleys {}/{} | min {} max {} | saddles {:?} | A(S_O) {} A(L-) {} A(L+) {} A(F up) {} A(F down) {}",
            e.contours_outer,
            e.contours_hole,
            e.faces_up,
            e.faces_down,
            e.faces_flat,
            e.ridges_open,
            e.ridges_closed,
            e.valleys_open,
            e.valleys_closed,
            e.minima,
            e.maxima,
            e.saddles,
            rat(e.area_contours),
            rat(e.area_below),
            rat(e.area_above),
            rat(e.area_faces_up),
            rat(e.area_faces_down),
        );
        let got = observed(&ls);
        if got != want {
            failures.push(format!(
                "{} at {c}:\n  want {want}\n  got  {got}\n  why: {}",
                e.dataset, e.why
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} levels differ:\n{}",
        failures.len(),
        expected().len(),
        failures.join("\n")
    );
}
