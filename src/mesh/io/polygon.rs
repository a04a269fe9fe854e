//! Input: a polygon face as a file gives it (vertex ids in order) and the
//! positions as read. Output: its triangles, when the fan `(0, i, i + 1)`
//! the readers make would fold and another triangulation does not.
//!
//! A flat face that is not convex (an L-shaped side, a slot, a notch: as
//! Blender, Meshlab and other tools write faces to OBJ, OFF and PLY;
//! tinyobjloader's `issue-319-002.obj`, a Meshlab export, holds two) fans
//! into triangles that face both ways when its first vertex does not see
//! every other one: validation then refuses a sound mesh with a fold of
//! the reader's own making. Such a polygon is split by ear clipping
//! instead. Every decision is an exact orientation of the coordinates as
//! read (no tolerance), and only a polygon that is exactly planar, whose
//! fan has triangles facing both ways (a fold validation refuses), and
//! that ear clipping splits completely is changed: a mesh accepted before
//! reads the same.

use crate::exact::predicates::{orient2d_axes, orient3d, Sign};

/// The work ear clipping may do for one file, in orientation tests: each
/// polygon of `n` vertices is charged `n^3`, its worst case (so a hostile
/// file of many large folding polygons is read in bounded time; a part
/// would need a million non-convex ten-gons to reach it). Past it, folding
/// fans are left as they are (and validation names the folds).
pub(super) const EAR_CLIPPING_BUDGET: u64 = 1 << 30;

/// The triangles of polygon `ids` (at least four vertices) when its fan
/// folds and ear clipping splits it within what is left of `budget`;
/// `None` keeps the fan. Ids out of range and coordinates that are not
/// finite keep the fan (validation and the reader name them).
pub(super) fn untangled(
    ids: &[u32],
    positions: &[[f64; 3]],
    budget: &mut u64,
) -> Option<Vec<[u32; 3]>> {
    if ids.len() < 4 {
        return None;
    }
    let p: Vec<[f64; 3]> = ids
        .iter()
        .map(|&v| positions.get(v as usize).copied())
        .collect::<Option<_>>()?;
    if p.iter().flatten().any(|c| !c.is_finite()) {
        return None;
    }
    let (b, c) = spanning(&p)?;
    let (i, j) = projection(p[0], b, c)?;
    let fan = |k: usize| orient2d_axes(p[0], p[k], p[k + 1], i, j);
    let signs: Vec<Sign> = (1..p.len() - 1).map(fan).collect();
    let folds = signs.contains(&Sign::Positive) && signs.contains(&Sign::Negative);
    // Exactly in the plane of `p[0]`, `b`, `c`.
    if !folds || !p.iter().all(|&d| orient3d(p[0], b, c, d) == Sign::Zero) {
        return None;
    }
    let n = p.len() as u64;
    *budget = budget.checked_sub(n.saturating_mul(n).saturating_mul(n))?;
    let turn = orientation(&p, i, j)?;
    ear_clip(&p, i, j, turn).map(|tris| {
        tris.into_iter()
            .map(|[a, b, c]| [ids[a], ids[b], ids[c]])
            .collect()
    })
}

/// The three planes of projection, as the axes `(i, j)` they keep.
const PLANES: [(usize, usize); 3] = [(1, 2), (2, 0), (0, 1)];

/// Two consecutive vertices that span a plane with the first vertex (not
/// on one line with it, exactly); `None` when every vertex lies on one
/// line.
fn spanning(p: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    p[1..].windows(2).find_map(|w| {
        PLANES
            .iter()
            .any(|&(i, j)| orient2d_axes(p[0], w[0], w[1], i, j) != Sign::Zero)
            .then_some((w[0], w[1]))
    })
}

/// The axes `(i, j)` of a projection that keeps the plane of `a`, `b`,
/// `c` (not on one line) from collapsing: of the three, the one with the
/// largest projected area (a choice; any with a non-zero one keeps every
/// orientation of a planar polygon, exactly).
fn projection(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<(usize, usize)> {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    // The cross product in doubles picks the plane; the exact orientation
    // confirms it is not edge-on.
    let n = [
        (u[1] * v[2] - u[2] * v[1]).abs(),
        (u[2] * v[0] - u[0] * v[2]).abs(),
        (u[0] * v[1] - u[1] * v[0]).abs(),
    ];
    let mut order = [0, 1, 2];
    order.sort_by(|&x, &y| n[y].total_cmp(&n[x]));
    order
        .into_iter()
        .map(|k| PLANES[k])
        .find(|&(i, j)| orient2d_axes(a, b, c, i, j) != Sign::Zero)
}

/// The polygon's turning sense in the projection: that of its corner at
/// the least vertex (by `i`, then `j`), which is convex in a simple
/// polygon. `None` when that corner is flat or a neighbour repeats it.
fn orientation(p: &[[f64; 3]], i: usize, j: usize) -> Option<Sign> {
    let n = p.len();
    let key = |k: usize| (p[k][i], p[k][j]);
    let m = (0..n).min_by(|&x, &y| {
        key(x)
            .partial_cmp(&key(y))
            .unwrap_or(std::cmp::Ordering::Equal)
    })?;
    let s = orient2d_axes(p[(m + n - 1) % n], p[m], p[(m + 1) % n], i, j);
    (s != Sign::Zero).then_some(s)
}

/// Ear clipping in the projection `(i, j)` of a polygon turning `turn`:
/// repeatedly cuts off a corner that turns the polygon's way and holds no
/// other remaining vertex inside or on it. The triangles keep the
/// polygon's order (so its facing). `None` when it gets stuck (the polygon
/// crosses or touches itself): the fan stays.
fn ear_clip(p: &[[f64; 3]], i: usize, j: usize, turn: Sign) -> Option<Vec<[usize; 3]>> {
    let o = |a: usize, b: usize, c: usize| orient2d_axes(p[a], p[b], p[c], i, j);
    let mut ring: Vec<usize> = (0..p.len()).collect();
    let mut out = Vec::with_capacity(p.len() - 2);
    while ring.len() > 3 {
        let n = ring.len();
        let ear = (0..n).find(|&k| {
            let (a, b, c) = (ring[(k + n - 1) % n], ring[k], ring[(k + 1) % n]);
            o(a, b, c) == turn
                && ring.iter().all(|&d| {
                    d == a || d == b || d == c || {
                        // Inside or on the corner's triangle: it blocks.
                        let sides = [o(a, b, d), o(b, c, d), o(c, a, d)];
                        sides.iter().any(|&s| s != turn && s != Sign::Zero)
                    }
                })
        })?;
        out.push([ring[(ear + n - 1) % n], ring[ear], ring[(ear + 1) % n]]);
        ring.remove(ear);
    }
    (o(ring[0], ring[1], ring[2]) == turn).then(|| {
        out.push([ring[0], ring[1], ring[2]]);
        out
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::{rat_from_f64 as r, Rat};

    /// Twice the exact signed area in the (x, y) plane of triangles over
    /// `p`.
    fn twice_area(p: &[[f64; 3]], tris: &[[u32; 3]]) -> Rat {
        tris.iter().fold(Rat::from_integer(0.into()), |acc, t| {
            let [a, b, c] = t.map(|k| p[k as usize]);
            acc + (r(b[0]) - r(a[0])) * (r(c[1]) - r(a[1]))
                - (r(b[1]) - r(a[1])) * (r(c[0]) - r(a[0]))
        })
    }

    fn split(ids: &[u32], p: &[[f64; 3]]) -> Option<Vec<[u32; 3]>> {
        untangled(ids, p, &mut EAR_CLIPPING_BUDGET.clone())
    }

    /// The L of area 3, from its corner (2, 0): that corner does not see
    /// (1, 2), so the fan folds.
    fn l_shape(z: f64) -> Vec<[f64; 3]> {
        [
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [1.0, 2.0],
            [0.0, 2.0],
            [0.0, 0.0],
        ]
        .iter()
        .map(|&[x, y]| [x, y, z])
        .collect()
    }

    #[test]
    fn an_l_whose_fan_folds_is_split_into_four_triangles_covering_it() {
        let p = l_shape(0.5);
        let ids: Vec<u32> = (0..6).collect();
        let fan: Vec<[u32; 3]> = (1..5).map(|k| [0, k, k + 1]).collect();
        let signs: Vec<Sign> = fan
            .iter()
            .map(|t| orient2d_axes(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize], 0, 1))
            .collect();
        assert!(signs.contains(&Sign::Negative), "the fan folds: {signs:?}");
        let tris = split(&ids, &p).expect("ear clipped");
        assert_eq!(tris.len(), 4);
        for t in &tris {
            let [a, b, c] = t.map(|k| p[k as usize]);
            assert_eq!(orient2d_axes(a, b, c, 0, 1), Sign::Positive, "{t:?}");
        }
        // Every triangle counter-clockwise and together twice the L's area:
        // they cover it once (winding numbers add up to the L's).
        assert_eq!(twice_area(&p, &tris), Rat::from_integer(6.into()));
        // Turned the other way round from the same corner, the triangles
        // turn with it.
        let back: Vec<u32> = vec![0, 5, 4, 3, 2, 1];
        let tris = split(&back, &p).expect("ear clipped");
        assert_eq!(twice_area(&p, &tris), Rat::from_integer((-6).into()));
    }

    #[test]
    fn a_fan_that_does_not_fold_and_a_polygon_out_of_its_plane_are_left() {
        // From the reflex corner (1, 1) the fan covers the L.
        let p = l_shape(0.0);
        let from_reflex: Vec<u32> = vec![2, 3, 4, 5, 0, 1];
        assert_eq!(split(&from_reflex, &p), None);
        // A convex square with a vertex on an edge: flat fan triangles, no
        // fold.
        let sq = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [2.0, 2.0, 0.0],
            [0.0, 2.0, 0.0],
        ];
        assert_eq!(split(&[0, 1, 2, 3, 4], &sq), None);
        // The folding L with one vertex lifted by the least step: not
        // planar, so the file's own fan stays (validation judges it).
        let mut lifted = l_shape(0.0);
        lifted[3][2] = f64::from_bits(1);
        assert_eq!(split(&(0..6).collect::<Vec<_>>(), &lifted), None);
        // An id beyond the positions, a NaN: left to the reader and
        // validation.
        assert_eq!(split(&[0, 1, 2, 3, 4, 9], &p), None);
        let mut nan = l_shape(0.0);
        nan[1][0] = f64::NAN;
        assert_eq!(split(&(0..6).collect::<Vec<_>>(), &nan), None);
    }

    #[test]
    fn a_tilted_l_is_split_in_the_projection_of_its_plane() {
        // The L in the plane x = z (a 45 degree slope), seen from x: its
        // (x, y) projection folds the same way.
        let p: Vec<[f64; 3]> = l_shape(0.0).iter().map(|&[x, y, _]| [x, y, x]).collect();
        let tris = split(&(0..6).collect::<Vec<_>>(), &p).expect("ear clipped");
        assert_eq!(twice_area(&p, &tris), Rat::from_integer(6.into()));
        // The same L on its side (the plane y = 0): only the (z, x) view
        // shows it, turned clockwise (z to the right, x up: the axes
        // swapped), and so every triangle.
        let side: Vec<[f64; 3]> = l_shape(0.0).iter().map(|&[x, y, _]| [x, 0.0, y]).collect();
        let tris = split(&(0..6).collect::<Vec<_>>(), &side).expect("ear clipped");
        assert_eq!(tris.len(), 4);
        for t in &tris {
            let [a, b, c] = t.map(|k| side[k as usize]);
            assert_eq!(orient2d_axes(a, b, c, 2, 0), Sign::Negative, "{t:?}");
        }
    }

    #[test]
    fn ear_clipping_is_charged_the_cube_of_the_vertices_and_stops_at_the_budget() {
        let p = l_shape(0.0);
        let ids: Vec<u32> = (0..6).collect();
        let mut budget = 6 * 6 * 6 - 1;
        assert_eq!(untangled(&ids, &p, &mut budget), None);
        assert_eq!(budget, 6 * 6 * 6 - 1, "nothing charged when refused");
        budget += 1;
        assert!(untangled(&ids, &p, &mut budget).is_some());
        assert_eq!(budget, 0);
        // A fan that does not fold costs nothing.
        assert_eq!(untangled(&[2, 3, 4, 5, 0, 1], &p, &mut budget), None);
    }

    #[test]
    fn a_polygon_that_crosses_itself_keeps_its_fan() {
        // A bow tie of six vertices: no triangulation without a fold.
        let p = [
            [0.0, 0.0, 0.0],
            [2.0, 2.0, 0.0],
            [3.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [-1.0, 1.0, 0.0],
        ];
        assert_eq!(split(&(0..6).collect::<Vec<_>>(), &p), None);
    }
}
