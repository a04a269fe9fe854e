//! Input: a mesh's triangles, placed in the broad phase's frame. Output: a
//! *turn*, three rows of doubles that take the mesh's dominant plane
//! parallel to two axes and the long edges in that plane along them; or
//! none, when no plane dominates or the mesh already lies that way.
//!
//! Why: the broad phase bounds faces by boxes and diagonal extents along
//! fixed axes. A flat part turned off the axes (a perforated plate
//! exported in its assembly's frame) has long thin cap faces whose boxes
//! are fat on all three axes, each meeting hundreds of faces of the
//! other cap and of the holes' walls: a turned plate of 314 000 faces took
//! 10.5 s to validate where the same plate on the axes took 0.8 s. Volumes
//! taken along the turned axes are thin again.
//!
//! Everything here is a heuristic: it chooses the axes, never an answer.
//! Which volumes meet is decided on the turned coordinates widened by a
//! proven bound on their rounding (see `VolumeFrame` in `bvh/frame.rs`); two
//! faces that meet have turned volumes that meet, for any rows at all
//! (a linear map takes a common point to a common point).

use crate::ids::VertexId;
use rustc_hash::FxHashMap as HashMap;

/// The dot product (rounded; for heuristics).
pub(super) fn dot(u: [f64; 3], v: [f64; 3]) -> f64 {
    u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
}

/// The cross product (rounded; for heuristics).
pub(super) fn cross(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|c| {
        let (k, l) = ((c + 1) % 3, (c + 2) % 3);
        u[k] * v[l] - u[l] * v[k]
    })
}

/// Triangles sampled (by stride, when there are more).
const SAMPLE: usize = 1 << 14;

/// The least share of the sampled area a plane's faces must have to
/// dominate (a heuristic).
const SHARE: f64 = 0.25;

/// Normals are gathered in cells of this many steps per unit (a
/// heuristic: a flat cap's faces, rounded after turning, stay in one).
const CELLS: f64 = 16.0;

/// Bins of the edges' directions over a quarter turn (a heuristic: half
/// a degree each).
const BINS: usize = 180;

/// The least share of the edges' weight around one direction for the
/// plane to be turned in itself (a heuristic; spread evenly, three bins
/// hold 1.7%).
const PEAK: f64 = 0.1;

/// The rows of a rotation (rounded: nearly orthonormal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Turn {
    rows: [[f64; 3]; 3],
}

impl Turn {
    /// The turn of the triangles `tris` over points `pos` (already in the
    /// broad phase's frame, so finite and within `2^±202`), or `None`.
    pub(super) fn of(tris: &[[VertexId; 3]], pos: impl Fn(usize) -> [f64; 3]) -> Option<Turn> {
        let d = dominant_normal(tris, &pos)?;
        let u = edge_axis(d, tris, &pos);
        let rows = [u, cross(d, u), d];
        // Rows on the axes (up to order, signs and a turn of a millionth
        // of a radian): nothing to gain, and the frame stays exact. A
        // threshold on rounded rows, deciding only whether the broad
        // phase's volumes are built turned (its speed), never an answer.
        let on_axes = rows
            .iter()
            .all(|r| r.iter().any(|c| c.abs() >= 1.0 - 1e-12));
        (!on_axes && rows.iter().flatten().all(|c| c.is_finite())).then_some(Turn { rows })
    }

    /// A turn with these rows (for tests of the bounds).
    #[cfg(test)]
    pub(super) fn from_rows(rows: [[f64; 3]; 3]) -> Turn {
        Turn { rows }
    }

    /// The turned coordinates of `q` (each a dot product, rounded).
    #[inline(always)]
    pub(super) fn apply(&self, q: [f64; 3]) -> [f64; 3] {
        self.rows.map(|r| r[0] * q[0] + r[1] * q[1] + r[2] * q[2])
    }

    /// The largest sum of the magnitudes of a row's entries.
    pub(super) fn row_norm(&self) -> f64 {
        self.rows
            .iter()
            .map(|r| r.iter().map(|c| c.abs()).sum::<f64>())
            .fold(0.0, f64::max)
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|k| a[k] - b[k])
}

/// `v` scaled to length 1, or `None` for a zero or non-finite `v`.
fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let len = dot(v, v).sqrt();
    (len > 0.0 && len.is_finite()).then(|| v.map(|c| c / len))
}

/// The normal of the plane that the sampled faces' area favours, when it
/// holds at least [`SHARE`] of it: unit normals, one sign per line (the
/// largest component positive), gathered in cells, weighted by area.
fn dominant_normal(tris: &[[VertexId; 3]], pos: &impl Fn(usize) -> [f64; 3]) -> Option<[f64; 3]> {
    let step = tris.len().div_ceil(SAMPLE).max(1);
    let mut cells: HashMap<[i32; 3], (f64, [f64; 3])> = HashMap::default();
    let mut total = 0.0;
    for t in tris.iter().step_by(step) {
        let [a, b, c] = t.map(|v| pos(v.idx()));
        let n = cross(sub(b, a), sub(c, a));
        let (Some(mut u), area) = (unit(n), dot(n, n).sqrt()) else {
            continue;
        };
        let k = (0..3).fold(0, |k, i| if u[i].abs() > u[k].abs() { i } else { k });
        if u[k] < 0.0 {
            u = u.map(|c| -c);
        }
        let cell = cells
            .entry(u.map(|c| (c * CELLS).round() as i32))
            .or_insert((0.0, [0.0; 3]));
        cell.0 += area;
        cell.1 = std::array::from_fn(|i| cell.1[i] + area * u[i]);
        total += area;
    }
    let (area, sum) = cells.values().max_by(|x, y| x.0.total_cmp(&y.0))?;
    (*area >= SHARE * total).then_some(())?;
    unit(*sum)
}

/// A unit vector across `d` along the direction, taken modulo a quarter
/// turn (the two sides of a rectangle vote together), that the sampled
/// faces' edges lying in the plane across `d` favour, weighted by their
/// squared lengths: the long edges of slivers, whose boxes are what a
/// turn makes thin (a round outline says nothing, CAD triangulators lay
/// their slivers along the part's own axes).
fn edge_axis(d: [f64; 3], tris: &[[VertexId; 3]], pos: &impl Fn(usize) -> [f64; 3]) -> [f64; 3] {
    use std::f64::consts::FRAC_PI_2;
    // Any two unit vectors across `d`: axes themselves when `d` is one.
    let k = (0..3).fold(0, |k, i| if d[i].abs() < d[k].abs() { i } else { k });
    let mut e = [0.0; 3];
    e[k] = 1.0;
    let a = unit(cross(d, e)).unwrap_or(e);
    let b = cross(d, a);
    let step = tris.len().div_ceil(SAMPLE).max(1);
    let mut bins = vec![(0.0, 0.0); BINS];
    for t in tris.iter().step_by(step) {
        let p = t.map(|v| pos(v.idx()));
        for i in 0..3 {
            let edge = sub(p[(i + 1) % 3], p[i]);
            let (x, y, z) = (dot(edge, a), dot(edge, b), dot(edge, d));
            let w = x * x + y * y;
            // In the plane (to a hundredth: a heuristic that picks which
            // edges vote for the axes, never an answer), and finite.
            if !(w > 0.0 && w.is_finite() && z * z <= 1e-4 * w) {
                continue;
            }
            let angle = y.atan2(x).rem_euclid(FRAC_PI_2);
            let bin = ((angle / FRAC_PI_2 * BINS as f64) as usize).min(BINS - 1);
            bins[bin].0 += w;
            bins[bin].1 += w * angle;
        }
    }
    let Some(best) = (0..BINS).max_by(|&i, &j| bins[i].0.total_cmp(&bins[j].0)) else {
        return a;
    };
    // A peak (the best bin and its neighbours) of at least `PEAK` of the
    // weight, or no turn in the plane: radial edges (an annulus, a
    // turned tube's flats) point every way, and any turn would do as
    // badly as none.
    let total: f64 = bins.iter().map(|b| b.0).sum();
    let near: f64 = [BINS - 1, 0, 1]
        .iter()
        .map(|&o| bins[(best + o) % BINS].0)
        .sum();
    if !(near > 0.0 && near >= PEAK * total) {
        return a;
    }
    // Within a bin of `a` (an axis, when `d` is one): as good as `a`.
    let angle = bins[best].1 / bins[best].0;
    let bin = FRAC_PI_2 / BINS as f64;
    if angle < bin || angle > FRAC_PI_2 - bin {
        return a;
    }
    let (s, c) = angle.sin_cos();
    unit(std::array::from_fn(|i| c * a[i] + s * b[i])).unwrap_or(a)
}

#[cfg(test)]
mod tests {
    use super::super::tests::rotation;
    use super::*;
    use crate::datasets::slab::Slab;
    use crate::mesh::Mesh;

    /// A box `w x h x 1` (12 triangles), its points then turned by `m`.
    fn plate(w: f64, h: f64, m: [[f64; 3]; 3]) -> Mesh {
        let mut mesh = Slab {
            nx: 1,
            ny: 1,
            bot: vec![0; 4],
            thick: vec![1; 4],
            diag: vec![false],
            rot: 0,
        }
        .mesh();
        for p in &mut mesh.positions {
            let q = [p[0] * w, p[1] * h, p[2]];
            *p = m.map(|r| dot(r, q));
        }
        mesh
    }

    fn turn_of(mesh: &Mesh) -> Option<Turn> {
        Turn::of(&mesh.faces, |v| mesh.positions[v])
    }

    #[test]
    fn a_turned_plate_is_turned_back_onto_the_axes() {
        // A 40 x 30 x 1 plate: its big faces (2 400 of 2 680 area units)
        // dominate; turned about a skew axis, the turn's rows are the
        // plate's own axes (up to sign and order), to rounding.
        let m = rotation(0.7, [0.3, 0.5, 0.8]);
        let t = turn_of(&plate(40.0, 30.0, m)).expect("a turned plate is turned");
        // The rows and `m` are rounded doubles (sines, cosines, unit
        // vectors): alignment is asserted to their rounding, `1e-12`.
        let column = |k: usize| [m[0][k], m[1][k], m[2][k]];
        for row in t.rows {
            let along = (0..3)
                .map(|k| dot(row, column(k)).abs())
                .fold(0.0, f64::max);
            assert!(along > 1.0 - 1e-12, "{row:?} is not along a plate axis");
        }
        // Its last row is the plate's normal (the third column of `m`).
        assert!(dot(t.rows[2], column(2)).abs() > 1.0 - 1e-12);
    }

    #[test]
    fn a_plate_on_the_axes_or_a_cube_is_not_turned() {
        let id = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(turn_of(&plate(40.0, 30.0, id)), None);
        // A turned cube: each pair of opposite faces holds a third of
        // the area, so one dominates, and the cube is turned back.
        assert!(turn_of(&plate(1.0, 1.0, rotation(0.4, [1.0, 2.0, 3.0]))).is_some());
        // Nothing to look at.
        assert_eq!(turn_of(&Mesh::default()), None);
    }

    #[test]
    fn a_plate_turned_about_its_normal_gets_its_sides_back() {
        // Turned 0.3 rad about z: the normal is z exactly, the sides come
        // from the long edges in the plane.
        let m = rotation(0.3, [0.0, 0.0, 1.0]);
        let t = turn_of(&plate(40.0, 30.0, m)).expect("turned in its plane");
        assert_eq!(t.rows[2], [0.0, 0.0, 1.0]);
        // One of the first two rows is along the turned x side (the other
        // then along the y side: the rows are orthonormal, to rounding).
        // Not a tolerance in any decision: the rows are rounded doubles
        // that only orient the broad phase's boxes (every intersection
        // test is exact and never reads them), so the test asserts their
        // alignment to rounding, `1e-12`, as the test above does.
        let side = [m[0][0], m[1][0], 0.0];
        let along = t.rows[..2]
            .iter()
            .map(|r| dot(*r, side).abs())
            .fold(0.0, f64::max);
        assert!(along > 1.0 - 1e-12, "{:?}", t.rows);
    }
}
