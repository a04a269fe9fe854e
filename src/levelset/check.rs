//! Input: a mesh, its topology and a computed level set. Output: `Ok` or
//! the first violated invariant of SPEC section 7 (1 to 4 here; 5 and 6 need
//! several levels and live in [`check_volume_identity`] and
//! [`same_structure`]). Shared by tests and fuzz targets; exact throughout.
//! The crossing test is quadratic: meant for test-sized meshes.

use super::{total_area, LevelSet, Loop, Slicer};
use crate::classify::vertex_signs;
use crate::exact::area::signed_area;
use crate::exact::predicates::orient2d_rat;
use crate::exact::rational::{rat_from_f64, rat_to_f64, rat_to_string, Rat};
use crate::exact::{Level, Point2, Sign};
use crate::ids::{EdgeId, FaceId};
use crate::mesh::topology::Topology;
use crate::mesh::Mesh;
use crate::nest::Role;
use crate::segment::CutPoint;
use num_traits::{One, Signed, Zero};
use std::cmp::Ordering;
use std::collections::{HashMap, HashSet};

/// Checks invariants 1 (cover), 2 (closure), 3 (orientation) and 4 (no
/// crossing) of one level set.
pub fn check_level_invariants(mesh: &Mesh, topo: &Topology, ls: &LevelSet) -> Result<(), String> {
    let level = Level::new(ls.level.clone());
    let signs = vertex_signs(mesh, &level);
    let zero = |v: crate::ids::VertexId| signs[v.idx()] == Sign::Zero;

    // Cover of faces: in-plane faces exactly once in F.
    let mut in_f: HashSet<FaceId> = HashSet::new();
    for r in &ls.regions {
        for &f in &r.faces {
            if !in_f.insert(f) {
                return Err(format!("face {f} in two regions"));
            }
            if !mesh.faces[f.idx()].iter().all(|&v| zero(v)) {
                return Err(format!("face {f} in F is not in the plane"));
            }
        }
    }
    let in_plane_faces = mesh
        .faces
        .iter()
        .filter(|t| t.iter().all(|&v| zero(v)))
        .count();
    if in_plane_faces != in_f.len() {
        return Err(format!(
            "{in_plane_faces} faces lie in the plane, F has {}",
            in_f.len()
        ));
    }

    // Cover of strictly crossed edges: each exactly once in S_O.
    let mut crossings: HashMap<EdgeId, usize> = HashMap::new();
    for l in ls.contours.iter() {
        for c in &l.cuts {
            if let CutPoint::OnEdge(e) = c {
                *crossings.entry(*e).or_default() += 1;
            }
        }
    }
    for (k, e) in topo.edges.iter().enumerate() {
        let (a, b) = (signs[e.v[0].idx()], signs[e.v[1].idx()]);
        let crossed = a != Sign::Zero && b != Sign::Zero && a != b;
        let got = crossings.get(&EdgeId::from_idx(k)).copied().unwrap_or(0);
        if got != usize::from(crossed) {
            return Err(format!(
                "edge e{k} crossed {} but appears {got} times in S_O",
                crossed
            ));
        }
    }

    // Cover of vertices: an on-plane vertex that is an extremum is in P and
    // in nothing else.
    for p in &ls.extrema {
        if !zero(p.vertex) {
            return Err(format!("extremum {} is not on the plane", p.vertex));
        }
        let on_loop = ls
            .contours
            .iter()
            .any(|l| l.cuts.contains(&CutPoint::AtVertex(p.vertex)));
        if on_loop {
            return Err(format!("extremum {} also lies on S_O", p.vertex));
        }
    }

    // Points lie where their cuts say, exactly.
    let families: [(&str, &[Loop], Option<Rat>); 3] = [
        ("S_O", &ls.contours, None),
        ("L-", &ls.below, Some(-Rat::one())),
        ("L+", &ls.above, Some(Rat::one())),
    ];
    for (name, loops, side) in families {
        let areas: Vec<Rat> = loops.iter().map(|l| signed_area(&l.points)).collect();
        for (i, l) in loops.iter().enumerate() {
            if l.points.len() != l.cuts.len() || l.points.is_empty() {
                return Err(format!("{name} loop {i} is empty or malformed"));
            }
            for (c, p) in l.cuts.iter().zip(&l.points) {
                if !lies_on(mesh, topo, &ls.level, *c, &p.exact()) {
                    return Err(format!(
                        "{name} loop {i}: point {:?} is not on {c:?}",
                        p.to_f64()
                    ));
                }
            }
            let area = &areas[i];
            let rounded: Vec<[f64; 2]> = l.points.iter().map(|p| p.to_f64()).collect();
            let approx = l.rounded_area(&rounded);
            // The rounded area's own sign (it may be infinite beyond
            // f64::MAX). A loop whose exact area is nearer to 0 than to any
            // other double (|area| < 2^-1075, a body scaled far down) has
            // the rounded area 0, its nearest double (README): only then
            // may the signs differ.
            let rounded_sign = Sign::of_cmp(approx.partial_cmp(&0.0));
            let underflows = approx == 0.0 && rat_to_f64(area) == 0.0;
            if rounded_sign != Sign::of_rat(area) && !underflows {
                return Err(format!(
                    "{name} loop {i}: rounded area {approx} has the wrong sign"
                ));
            }
            // The orientation at c -/+ epsilon: the first non-zero term of
            // the area in epsilon, from the crossings, in plain rationals.
            let sign = match &side {
                Some(s) if !l.crossings.is_empty() => {
                    check_limit_cuts(mesh, topo, &ls.level, l)
                        .map_err(|e| format!("{name} loop {i}: {e}"))?;
                    let terms = limit_area_terms(mesh, topo, &ls.level, &l.crossings, s);
                    terms
                        .iter()
                        .map(Sign::of_rat)
                        .find(|&t| t != Sign::Zero)
                        .unwrap_or(Sign::Zero)
                }
                _ => Sign::of_rat(area),
            };
            if sign != l.orientation {
                return Err(format!(
                    "{name} loop {i}: stored orientation is not the exact area's sign"
                ));
            }
            let ok = match l.role {
                Role::Outer => sign == Sign::Positive,
                Role::Hole => sign == Sign::Negative,
            };
            if !ok {
                return Err(format!(
                    "{name} loop {i}: {:?} with area {} (sign {sign:?} at c -/+ epsilon)",
                    l.role,
                    rat_to_string(area)
                ));
            }
        }
        check_collapsed(loops, &areas, side.is_some()).map_err(|e| format!("{name}: {e}"))?;
        // Limits may run both ways along an edge (the two sides of a thin
        // band); S_O never does.
        no_crossing(loops, name != "S_O").map_err(|e| format!("{name}: {e}"))?;
    }
    for (r, region) in ls.regions.iter().enumerate() {
        let total = total_area(&region.boundary);
        // dF follows the faces: its signed area is the region's signed area.
        let expect = match region.facing {
            crate::classify::Facing::Up => region.area.clone(),
            crate::classify::Facing::Down => -region.area.clone(),
            crate::classify::Facing::Flat => Rat::zero(),
        };
        if total != expect {
            return Err(format!(
                "region {r}: dF encloses {} but the faces cover {}",
                total, expect
            ));
        }
    }
    Ok(())
}

/// The collapsed flags of a family against the exact limit areas: a loop
/// is collapsed exactly when a region it bounds (the loop minus its
/// children, or its parent minus the parent's children) has zero area.
/// S_O loops never are.
fn check_collapsed(loops: &[Loop], areas: &[Rat], limits: bool) -> Result<(), String> {
    let mut region: Vec<Rat> = areas.to_vec();
    for (i, l) in loops.iter().enumerate() {
        if let Some(p) = l.parent {
            region[p] += &areas[i];
        }
    }
    for (i, l) in loops.iter().enumerate() {
        let zero = |k: usize| region[k].is_zero();
        let expect = limits && (zero(i) || l.parent.is_some_and(zero));
        if l.collapsed != expect {
            return Err(format!(
                "loop {i} is marked collapsed: {}, but the regions it bounds say {expect}",
                l.collapsed
            ));
        }
    }
    Ok(())
}

/// The crossing of edge `e` at `c + s epsilon`: `(p0, d)` with the point
/// `p0 + epsilon d`, in plain rationals.
fn moving_crossing(
    mesh: &Mesh,
    topo: &Topology,
    level: &Rat,
    e: EdgeId,
    s: &Rat,
) -> (Point2, Point2) {
    let [a, b] = topo.edge(e).v.map(|v| mesh.pos(v).map(rat_from_f64));
    let dz = &b[2] - &a[2];
    let t = (level - &a[2]) / &dz;
    let p0 = Point2 {
        x: &a[0] + (&b[0] - &a[0]) * &t,
        y: &a[1] + (&b[1] - &a[1]) * &t,
    };
    let d = Point2 {
        x: (&b[0] - &a[0]) * s / &dz,
        y: (&b[1] - &a[1]) * s / &dz,
    };
    (p0, d)
}

/// The signed area of a loop of crossings at `c + s epsilon` as
/// `[a0, a1, a2]` (area `a0 + a1 epsilon + a2 epsilon^2`).
fn limit_area_terms(
    mesh: &Mesh,
    topo: &Topology,
    level: &Rat,
    crossings: &[EdgeId],
    s: &Rat,
) -> [Rat; 3] {
    let pts: Vec<(Point2, Point2)> = crossings
        .iter()
        .map(|&e| moving_crossing(mesh, topo, level, e, s))
        .collect();
    let cross = |u: &Point2, v: &Point2| &u.x * &v.y - &u.y * &v.x;
    let mut t = [Rat::zero(), Rat::zero(), Rat::zero()];
    let n = pts.len();
    for i in 0..n {
        let ((p, dp), (q, dq)) = (&pts[i], &pts[(i + 1) % n]);
        t[0] += cross(p, q);
        t[1] += cross(p, dq) + cross(dp, q);
        t[2] += cross(dp, dq);
    }
    let half = Rat::new(1.into(), 2.into());
    t.map(|x| x * &half)
}

/// The cuts of a limit loop are its crossings' limits (an edge's end on
/// the plane, or the edge), consecutive equal ones merged.
fn check_limit_cuts(mesh: &Mesh, topo: &Topology, level: &Rat, l: &Loop) -> Result<(), String> {
    let on_plane = |v: crate::ids::VertexId| rat_from_f64(mesh.pos(v)[2]) == *level;
    let mut merged: Vec<CutPoint> = Vec::new();
    for &e in &l.crossings {
        let [a, b] = topo.edge(e).v;
        let c = if on_plane(a) {
            CutPoint::AtVertex(a)
        } else if on_plane(b) {
            CutPoint::AtVertex(b)
        } else {
            CutPoint::OnEdge(e)
        };
        if merged.last() != Some(&c) {
            merged.push(c);
        }
    }
    if merged.len() > 1 && merged.first() == merged.last() {
        merged.pop();
    }
    if merged != l.cuts {
        return Err(format!(
            "its cuts {:?} are not the limits of its crossings {:?}",
            l.cuts, merged
        ));
    }
    Ok(())
}

fn lies_on(mesh: &Mesh, topo: &Topology, level: &Rat, c: CutPoint, p: &Point2) -> bool {
    match c {
        CutPoint::AtVertex(v) => {
            let q = mesh.pos(v);
            rat_from_f64(q[2]) == *level && Point2::of_vertex(q) == *p
        }
        CutPoint::OnEdge(e) => {
            // p = a + t (b - a) with t = (c - za) / (zb - za) strictly in (0, 1).
            let [a, b] = topo.edge(e).v.map(|v| mesh.pos(v).map(rat_from_f64));
            let dz = &b[2] - &a[2];
            if dz.is_zero() {
                return false;
            }
            let t = (level - &a[2]) / dz;
            t.is_positive()
                && t < Rat::from_integer(1.into())
                && p.x == &a[0] + (&b[0] - &a[0]) * &t
                && p.y == &a[1] + (&b[1] - &a[1]) * &t
        }
    }
}

/// A pass of a loop through a point: directions back to the previous and on
/// to the next point.
type Pass = ((Rat, Rat), (Rat, Rat));

/// Exact comparison of the directions of two non-zero vectors by angle in
/// `[0, 2 pi)`.
fn angle_cmp(u: &(Rat, Rat), v: &(Rat, Rat)) -> Ordering {
    let half = |w: &(Rat, Rat)| {
        if w.1.is_positive() || (w.1.is_zero() && w.0.is_positive()) {
            0
        } else {
            1
        }
    };
    half(u).cmp(&half(v)).then_with(|| {
        let cross = &u.0 * &v.1 - &u.1 * &v.0;
        if cross.is_positive() {
            Ordering::Less
        } else if cross.is_negative() {
            Ordering::Greater
        } else {
            Ordering::Equal
        }
    })
}

/// Invariant 4: no two segments of a family cross properly, no two overlap,
/// and no two passes through a shared point cross there.
fn no_crossing(loops: &[Loop], opposite_overlap_ok: bool) -> Result<(), String> {
    /// A segment with its exact bounding box.
    struct Seg<'a> {
        owner: usize,
        p: &'a Point2,
        q: &'a Point2,
        x: [&'a Rat; 2],
        y: [&'a Rat; 2],
    }
    fn sorted<'r>(a: &'r Rat, b: &'r Rat) -> [&'r Rat; 2] {
        if a <= b {
            [a, b]
        } else {
            [b, a]
        }
    }
    let exact: Vec<Vec<Point2>> = loops
        .iter()
        .map(|l| l.points.iter().map(|p| p.exact().into_owned()).collect())
        .collect();
    let mut segs: Vec<Seg<'_>> = Vec::new();
    for (i, points) in exact.iter().enumerate() {
        let n = points.len();
        for k in 0..n {
            let (p, q) = (&points[k], &points[(k + 1) % n]);
            if p != q {
                segs.push(Seg {
                    owner: i,
                    p,
                    q,
                    x: sorted(&p.x, &q.x),
                    y: sorted(&p.y, &q.y),
                });
            }
        }
    }
    // Two segments can only meet if their exact bounding boxes do: sweep
    // them in order of their least x, pairing only overlapping boxes.
    segs.sort_by(|a, b| a.x[0].cmp(b.x[0]));
    for (x, s) in segs.iter().enumerate() {
        for t in &segs[x + 1..] {
            if t.x[0] > s.x[1] {
                break;
            }
            if t.y[0] > s.y[1] || s.y[0] > t.y[1] {
                continue;
            }
            let (p1, p2, q1, q2) = (s.p, s.q, t.p, t.q);
            let d1 = orient2d_rat(p1, p2, q1);
            let d2 = orient2d_rat(p1, p2, q2);
            let d3 = orient2d_rat(q1, q2, p1);
            let d4 = orient2d_rat(q1, q2, p2);
            let strict = |a: Sign, b: Sign| a != Sign::Zero && b != Sign::Zero && a != b;
            if strict(d1, d2) && strict(d3, d4) {
                return Err(format!(
                    "segments of loops {} and {} cross",
                    s.owner, t.owner
                ));
            }
            let reversed = p1 == q2 && p2 == q1;
            if [d1, d2, d3, d4].iter().all(|&d| d == Sign::Zero)
                && overlap(p1, p2, q1, q2)
                && !(opposite_overlap_ok && reversed)
            {
                return Err(format!(
                    "segments of loops {} and {} overlap",
                    s.owner, t.owner
                ));
            }
            // Neither segment's interior may touch the other's ends.
            let interior = |a: &Point2, b: &Point2, p: &Point2, o: Sign| {
                o == Sign::Zero && p != a && p != b && between(a, b, p)
            };
            for (inner, outer, hit) in [
                (
                    t.owner,
                    s.owner,
                    interior(p1, p2, q1, d1) || interior(p1, p2, q2, d2),
                ),
                (
                    s.owner,
                    t.owner,
                    interior(q1, q2, p1, d3) || interior(q1, q2, p2, d4),
                ),
            ] {
                if hit {
                    return Err(format!(
                        "a point of loop {inner} lies inside a segment of loop {outer}"
                    ));
                }
            }
        }
    }
    // Passes through a shared point must not interleave.
    let mut passes: HashMap<&Point2, Vec<Pass>> = HashMap::new();
    for points in &exact {
        let n = points.len();
        for k in 0..n {
            let prev = &points[(k + n - 1) % n];
            let here = &points[k];
            let next = &points[(k + 1) % n];
            if prev == here || next == here {
                continue;
            }
            let d = |a: &Point2| (&a.x - &here.x, &a.y - &here.y);
            passes.entry(here).or_default().push((d(prev), d(next)));
        }
    }
    for (p, list) in passes {
        for i in 0..list.len() {
            for j in i + 1..list.len() {
                if interleave(&list[i], &list[j]) {
                    return Err(format!("two passes cross at {:?}", p.to_f64()));
                }
            }
        }
    }
    Ok(())
}

fn between(a: &Point2, b: &Point2, p: &Point2) -> bool {
    let in_range = |x: &Rat, y: &Rat, z: &Rat| (x <= z && z <= y) || (y <= z && z <= x);
    in_range(&a.x, &b.x, &p.x) && in_range(&a.y, &b.y, &p.y)
}

fn overlap(p1: &Point2, p2: &Point2, q1: &Point2, q2: &Point2) -> bool {
    // Collinear: overlap in more than a point iff some interior point is shared.
    let key = |p: &Point2| (p.x.clone(), p.y.clone());
    let (a, b) = if key(p1) <= key(p2) {
        (key(p1), key(p2))
    } else {
        (key(p2), key(p1))
    };
    let (c, d) = if key(q1) <= key(q2) {
        (key(q1), key(q2))
    } else {
        (key(q2), key(q1))
    };
    let lo = if a > c { a } else { c };
    let hi = if b < d { b } else { d };
    lo < hi
}

/// Whether two passes (in-direction, out-direction) through one point cross:
/// the directions of one separate those of the other in angular order.
fn interleave(a: &Pass, b: &Pass) -> bool {
    let mut dirs = [(&a.0, 0), (&a.1, 0), (&b.0, 1), (&b.1, 1)];
    if dirs.iter().enumerate().any(|(i, x)| {
        dirs[i + 1..]
            .iter()
            .any(|y| angle_cmp(x.0, y.0) == Ordering::Equal)
    }) {
        // Shared directions mean touching along a ray: not a proper crossing.
        return false;
    }
    dirs.sort_by(|x, y| angle_cmp(x.0, y.0));
    dirs[0].1 == dirs[2].1 && dirs[1].1 == dirs[3].1 && dirs[0].1 != dirs[1].1
}

/// The distinct vertex heights of a mesh, exact and ascending.
pub fn vertex_heights(mesh: &Mesh) -> Vec<Rat> {
    let mut zs: Vec<f64> = mesh.positions.iter().map(|p| p[2]).collect();
    zs.sort_by(f64::total_cmp);
    zs.dedup_by(|a, b| a == b);
    zs.into_iter().map(rat_from_f64).collect()
}

/// Invariant 6: Simpson's rule on the cross-section areas (L+ at the bottom
/// of each interval between consecutive vertex heights, L- at its top, S_O
/// area at the midpoint) sums exactly to the mesh volume. Also checks that
/// at a regular midpoint L-, L+ and S_O have one area.
pub fn check_volume_identity(slicer: &Slicer<'_>, volume: &Rat) -> Result<(), String> {
    let zs = vertex_heights(slicer.mesh());
    let mut total = Rat::zero();
    let six = Rat::from_integer(6.into());
    let two = Rat::from_integer(2.into());
    let mut prev: Option<(Rat, Rat)> = None; // (z, area of L+ at z)
    for z in &zs {
        let ls = slicer.slice_at(z).map_err(|e| e.to_string())?;
        if let Some((z0, a0)) = prev {
            let mid = (&z0 + z) / &two;
            let m = slicer.slice_at(&mid).map_err(|e| e.to_string())?;
            let am = total_area(&m.contours);
            if total_area(&m.below) != am || total_area(&m.above) != am {
                return Err(format!("at regular level {mid}: L-, S_O, L+ areas differ"));
            }
            total +=
                (z - &z0) / &six * (a0 + am * Rat::from_integer(4.into()) + total_area(&ls.below));
        }
        prev = Some((z.clone(), total_area(&ls.above)));
    }
    if &total != volume {
        return Err(format!(
            "Simpson sum {} != volume {}",
            rat_to_string(&total),
            rat_to_string(volume)
        ));
    }
    Ok(())
}

/// The loop structure of a family: for each loop its role and parent's
/// role, sorted (an isomorphism-invariant fingerprint for invariant 5).
pub fn structure(loops: &[Loop]) -> Vec<(Role, Option<Role>, usize)> {
    let mut v: Vec<_> = loops
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let children = loops.iter().filter(|c| c.parent == Some(i)).count();
            (l.role, l.parent.map(|p| loops[p].role), children)
        })
        .collect();
    v.sort_by_key(|x| (x.0 as u8, x.1.map(|r| r as u8), x.2));
    v
}

/// Invariant 5 between two regular levels of one open interval: same number
/// of loops and same nesting fingerprint.
pub fn same_structure(a: &LevelSet, b: &LevelSet) -> bool {
    structure(&a.contours) == structure(&b.contours)
}
