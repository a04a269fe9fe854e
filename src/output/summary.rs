//! Input: a level set. Output: a short human-readable summary (counts of
//! each kind, exact areas, saddles). Areas are printed exactly and rounded
//! (rounded only, when the exact fraction would run to thousands of digits).

use crate::classify::{ExtremumKind, Facing, RidgeKind};
use crate::exact::area::AreaSum;
use crate::exact::rational::rat_to_string_with_nearest;
use crate::levelset::{LevelSet, Loop};
use crate::nest::Role;
use std::fmt::Write;
use std::sync::Arc;

/// Exact denominators past this many bits are not printed: the fraction
/// would be unreadable and reducing it costs more than the slicing.
const EXACT_TEXT_BITS: u64 = 4096;

/// The area a family of loops encloses: exact and rounded, or rounded
/// only when the exact fraction is huge (crossings on many edges with
/// distinct denominators); `--format json --exact` has each loop's.
fn loops_area_text(loops: &[Loop]) -> String {
    let polygons = || loops.iter().map(|l| l.points.as_slice());
    let bound = AreaSum::denominator_bits_bound(polygons());
    if bound <= EXACT_TEXT_BITS {
        let sum = AreaSum::of(polygons());
        if sum.denominator_bits() <= EXACT_TEXT_BITS {
            return rat_to_string_with_nearest(&sum.reduce());
        }
    }
    // The loops' certified roundings, summed (not built exactly: a
    // fraction this size costs more than the slicing).
    let approx: f64 = loops
        .iter()
        .map(|l| {
            let rounded: Vec<[f64; 2]> = l.points.iter().map(|p| p.to_f64()).collect();
            l.rounded_area(&rounded)
        })
        .sum();
    format!("~{approx} (exact denominator up to {bound} bits: see --format json --exact)")
}

fn roles(loops: &[Loop]) -> (usize, usize) {
    let outer = loops.iter().filter(|l| l.role == Role::Outer).count();
    (outer, loops.len() - outer)
}

/// A few lines describing one level.
pub fn summary(ls: &LevelSet) -> String {
    let mut s = String::new();
    let (o, h) = roles(&ls.contours);
    let _ = writeln!(s, "level z = {}", rat_to_string_with_nearest(&ls.level));
    // L- and L+ share S_O's loops when no vertex lies on the plane: their
    // area is then computed once.
    let contours_area = loops_area_text(&ls.contours);
    let area_of = |loops: &Arc<Vec<Loop>>| {
        if Arc::ptr_eq(loops, &ls.contours) {
            contours_area.clone()
        } else {
            loops_area_text(loops)
        }
    };
    let _ = writeln!(
        s,
        "  contours S_O : {} loops ({o} outer, {h} hole), area {}",
        ls.contours.len(),
        contours_area
    );
    let count = |f: Facing| ls.regions.iter().filter(|r| r.facing == f).count();
    let _ = writeln!(
        s,
        "  faces F      : {} regions ({} up, {} down, {} flat)",
        ls.regions.len(),
        count(Facing::Up),
        count(Facing::Down),
        count(Facing::Flat)
    );
    for r in &ls.regions {
        let _ = writeln!(
            s,
            "    {:?} region: {} faces, area {}, {} boundary loops",
            r.facing,
            r.faces.len(),
            rat_to_string_with_nearest(&r.area),
            r.boundary.len()
        );
    }
    let rc = |k: RidgeKind, closed: bool| {
        ls.ridges
            .iter()
            .filter(|r| r.kind == k && r.closed == closed)
            .count()
    };
    let _ = writeln!(
        s,
        "  ridges S_NO  : {} ridges ({} open, {} closed), {} valleys ({} open, {} closed)",
        rc(RidgeKind::Ridge, false) + rc(RidgeKind::Ridge, true),
        rc(RidgeKind::Ridge, false),
        rc(RidgeKind::Ridge, true),
        rc(RidgeKind::Valley, false) + rc(RidgeKind::Valley, true),
        rc(RidgeKind::Valley, false),
        rc(RidgeKind::Valley, true)
    );
    let pc = |k: ExtremumKind| ls.extrema.iter().filter(|p| p.kind == k).count();
    let _ = writeln!(
        s,
        "  points P     : {} min, {} max",
        pc(ExtremumKind::Min),
        pc(ExtremumKind::Max)
    );
    if ls.saddles.is_empty() {
        let _ = writeln!(s, "  saddles      : none");
    } else {
        let list: Vec<String> = ls
            .saddles
            .iter()
            .map(|x| format!("{} (m = {})", x.vertex, x.m()))
            .collect();
        let _ = writeln!(s, "  saddles      : {}", list.join(", "));
    }
    let limit = |loops: &Arc<Vec<Loop>>| {
        let (outer, hole) = roles(loops);
        let collapsed = loops.iter().filter(|l| l.collapsed).count();
        let note = if collapsed > 0 {
            format!(", {collapsed} collapsed")
        } else {
            String::new()
        };
        format!(
            "{} loops ({outer} outer, {hole} hole{note}), area {}",
            loops.len(),
            area_of(loops)
        )
    };
    let _ = writeln!(s, "  below L-     : {}", limit(&ls.below));
    let _ = write!(s, "  above L+     : {}", limit(&ls.above));
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::{rat_to_f64, Rat};
    use crate::exact::{Point2, Sign};
    use crate::segment::CutPoint;

    /// A convex polygon whose vertices have distinct prime denominators:
    /// its exact area's denominator runs to thousands of bits.
    fn many_denominators(n: usize) -> Vec<Point2> {
        let primes: Vec<i64> = (1009i64..)
            .filter(|p| (2..*p).take_while(|d| d * d <= *p).all(|d| p % d != 0))
            .take(n)
            .collect();
        (0..n)
            .map(|k| {
                let t = k as f64 / n as f64 * std::f64::consts::TAU;
                let p = primes[k];
                let r = |v: f64| Rat::new(((v * 1000.0) as i64 * p / 1000).into(), p.into());
                Point2 {
                    x: r(100.0 * t.cos()),
                    y: r(100.0 * t.sin()),
                }
            })
            .collect()
    }

    /// The unit cube, by hand: at z = 1/2 the three contours are one square
    /// of area 1 (S_O's loops shared with L- and L+); at the top, z = 1,
    /// S_O is empty, L- the top square (area 1) and L+ empty.
    #[test]
    fn each_family_prints_its_own_area() {
        let mesh = crate::datasets::by_name("unit_cube").unwrap().build();
        let slicer = crate::Slicer::new(&mesh).unwrap();
        let line = |text: &str, key: &str| {
            let l = text.lines().find(|l| l.contains(key)).unwrap().to_string();
            l.split("area ").nth(1).unwrap().to_string()
        };
        let mid = slicer.slice_at(&Rat::new(1.into(), 2.into())).unwrap();
        assert!(Arc::ptr_eq(&mid.below, &mid.contours) && Arc::ptr_eq(&mid.above, &mid.contours));
        let text = summary(&mid);
        for key in ["S_O", "L-", "L+"] {
            assert_eq!(line(&text, key), "1 (~1)", "{key} in\n{text}");
        }
        let top = slicer.slice_at(&Rat::from_integer(1.into())).unwrap();
        let text = summary(&top);
        assert_eq!(line(&text, "S_O"), "0 (~0)", "{text}");
        assert_eq!(line(&text, "L-"), "1 (~1)", "{text}");
        assert_eq!(line(&text, "L+"), "0 (~0)", "{text}");
    }

    #[test]
    fn huge_exact_areas_are_printed_rounded_and_small_ones_exactly() {
        let ls = |points: Vec<Point2>| LevelSet {
            level: Rat::default(),
            contours: std::sync::Arc::new(vec![Loop {
                cuts: vec![CutPoint::AtVertex(crate::ids::VertexId(0)); points.len()],
                points: points.into_iter().map(Into::into).collect(),
                orientation: Sign::Positive,
                role: Role::Outer,
                parent: None,
                collapsed: false,
                crossings: vec![],
            }]),
            regions: vec![],
            ridges: vec![],
            extrema: vec![],
            saddles: vec![],
            below: Default::default(),
            above: Default::default(),
        };
        let big = many_denominators(600);
        let exact = crate::exact::area::signed_area(&big);
        assert!(exact.denom().bits() > EXACT_TEXT_BITS);
        let text = summary(&ls(big));
        // The certified rounding from the points' nearest doubles: within
        // its bound (about n u d (4m + 3d), here below 1e-8) of the exact.
        let printed: f64 = text
            .split("area ~")
            .nth(1)
            .and_then(|t| t.split(' ').next())
            .and_then(|t| t.parse().ok())
            .unwrap_or(f64::NAN);
        assert!((printed - rat_to_f64(&exact)).abs() < 1e-8, "{text}");
        assert!(text.contains("(exact denominator"), "{text}");
        let small = many_denominators(4);
        let exact = crate::exact::area::signed_area(&small);
        let text = summary(&ls(small));
        assert!(text.contains(&rat_to_string_with_nearest(&exact)), "{text}");
    }
}
