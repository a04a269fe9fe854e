//! Where the broad phase builds its volumes: one frame per mesh, moved,
//! scaled and perhaps turned ([`VolumeFrame`]), and the `f32` bounds that
//! hold a coordinate known within a margin ([`down32`], [`up32`]).

use super::super::turn::Turn;
use crate::exact::rational::decompose;
use crate::exact::scale::{leading_exponent, times_pow2};
use crate::ids::VertexId;
use crate::mesh::Mesh;

/// `2^-22` and `2^-140`: the margins of [`down32`] and [`up32`].
const REL: f64 = 1.0 / 4_194_304.0;
const ABS: f64 = 7.174648137343064e-43;

/// An `f32` not above any value within `e` of `x` (`x` may be infinite,
/// not NaN; `e >= 0` finite).
///
/// `m = (|x| + e) 2^-22 + 2^-140 + e` is subtracted in `f64` and the
/// result rounded to the nearest `f32`: computing `m` and subtracting it
/// err by at most `2^-52 (|x| + m)`, the conversion by at most
/// `2^-24 |z| + 2^-150` (`z` its input, `2^-150` half the smallest
/// subnormal `f32`), together less than `2^-23 (|x| + m) + 2^-150`, which
/// is below `m - e = (|x| + e) 2^-22 + 2^-140` (as `|x| + m` is below
/// `(|x| + e)(1 + 2^-21) + 2^-139`). Beyond the `f32` range the
/// conversion gives an infinity (and `x = inf` a NaN), which `min` turns
/// into `f32::MAX`, below such an `x`; `-inf` stays. With `e = 0` (every
/// frame but a turned one) this is `x - (|x| 2^-22 + 2^-140)`, as it
/// always was.
#[inline]
pub(super) fn down32(x: f64, e: f64) -> f32 {
    ((x - ((x.abs() + e) * REL + ABS + e)) as f32).min(f32::MAX)
}

/// An `f32` not below any value within `e` of `x` (`x` may be infinite,
/// not NaN); see [`down32`].
#[inline]
pub(super) fn up32(x: f64, e: f64) -> f32 {
    ((x + ((x.abs() + e) * REL + ABS + e)) as f32).max(f32::MIN)
}

/// The largest coordinate magnitudes (after the shift) at which
/// [`VolumeFrame`] does not scale: `2^-60` to `2^60`.
const UNSCALED: std::ops::RangeInclusive<i32> = -60..=60;

/// Where the volumes are built: each coordinate `x` of axis `k` as
/// `(x - shift[k]) 2^s`.
///
/// The shift is the axis' lowest coordinate when the axis' coordinates lie
/// farther from zero than they span and every difference from the lowest
/// is exact (the coordinates are multiples of `2^q` and span less than
/// `2^(q + 52)`), else zero; then `s` brings the largest magnitude to
/// `[1, 2)` when its leading exponent lies outside [`UNSCALED`], else
/// `s = 0`. Without them, a part far from the origin (at `1e9`, where an
/// `f32` is 64 apart) or a mesh near `1e-300` (every bound rounded to
/// `+-2^-140`) or `1e300` (every bound infinite) would have volumes that
/// all meet, and every pair of faces would be tested (quadratic time).
///
/// Which closed volumes meet is the same in every such frame: the shift
/// is an exact translation, and `times_pow2` is exact but where a product
/// underflows (a coordinate far below the largest one), then off by at
/// most `2^-1074`, far inside the `2^-140` margin of [`down32`] and
/// [`up32`]; the diagonal sums stay finite (every magnitude is below 4).
///
/// Then, when a plane dominates the mesh off the axes, the frame is also
/// *turned* ([`Turn`]): each coordinate becomes a rounded dot product
/// with a row of a rotation, and every bound is widened by `margin`, a
/// proven bound on that rounding (see [`VolumeFrame::of`]). Two faces
/// that meet have a common point, and so have their images under any
/// linear map: their turned volumes meet. Which volumes meet may change
/// (that is the point), which pairs the exact tests find does not.
#[derive(Clone, Copy, Debug)]
pub(super) struct VolumeFrame {
    shift: [f64; 3],
    s: i32,
    pub(super) turn: Option<Turn>,
    /// How far a turned coordinate, or the sum of two, may lie from the
    /// exact one (zero when not turned).
    pub(super) margin: f64,
}

impl VolumeFrame {
    /// The frame of `mesh` (its triangles `tris`), whose coordinates lie
    /// in `lo ..= hi` per axis.
    pub(super) fn of(
        mesh: &Mesh,
        tris: &[[VertexId; 3]],
        lo: [f64; 3],
        hi: [f64; 3],
    ) -> VolumeFrame {
        let shift = std::array::from_fn(|k| {
            let span = hi[k] - lo[k];
            if !(lo[k] > span || -hi[k] > span) {
                // Near the origin (or empty): a shift would gain little.
                return 0.0;
            }
            let grid = mesh
                .positions
                .iter()
                .filter_map(|p| decompose(p[k]))
                .map(|(_, e)| e)
                .min();
            match grid {
                Some(q) if q <= 1023 - 52 && span < pow2_any(q + 52) => lo[k],
                _ => 0.0,
            }
        });
        let top = (0..3)
            .flat_map(|k| [lo[k] - shift[k], hi[k] - shift[k]])
            .filter(|x| x.is_finite())
            .map(f64::abs)
            .fold(0.0, f64::max);
        let s = match leading_exponent(top) {
            Some(e) if !UNSCALED.contains(&e) => -e,
            _ => 0,
        };
        let mut frame = VolumeFrame {
            shift,
            s,
            turn: None,
            margin: 0.0,
        };
        let placed = |v: usize| frame.place_all([mesh.positions[v]])[0];
        let turn = if turning() {
            Turn::of(tris, placed)
        } else {
            None
        };
        if let Some(turn) = turn {
            // Every placed coordinate is at most `q = top 2^s` in
            // magnitude. A turned one, the dot product `(r0 x0 + r1 x1) +
            // r2 x2` in doubles, lies within `3u / (1 - 3u) < 2^-51` of
            // `|r0 x0| + |r1 x1| + |r2 x2| <= row_norm q` of the exact value
            // (the inner-product bound, Higham, "Accuracy and Stability of
            // Numerical Algorithms", 3.1), plus `2^-1075` for each of the
            // three products that underflows: within `turn_error`, twice
            // that bound (its own rounding is a relative `2^-51` at most).
            // The sum of two turned coordinates is within twice that.
            frame.margin = 2.0 * turn_error(&turn, times_pow2(top, s));
            frame.turn = Some(turn);
        }
        frame
    }

    /// Points in this frame (a triangle's corners, read before any
    /// arithmetic so that their loads overlap; as they are in the frame of
    /// most meshes, which neither shifts nor scales).
    #[inline(always)]
    pub(super) fn place_all<const N: usize>(&self, ps: [[f64; 3]; N]) -> [[f64; 3]; N] {
        if let Some(t) = &self.turn {
            self.turned(t, ps)
        } else if self.shift == [0.0; 3] && self.s == 0 {
            ps
        } else {
            self.moved(ps)
        }
    }

    /// Points shifted and scaled (not turned).
    #[inline(always)]
    fn moved<const N: usize>(&self, ps: [[f64; 3]; N]) -> [[f64; 3]; N] {
        ps.map(|p| std::array::from_fn(|k| times_pow2(p[k] - self.shift[k], self.s)))
    }

    /// Points shifted, scaled and turned by `t` (kept out of line: most
    /// meshes are not turned).
    #[inline(never)]
    fn turned<const N: usize>(&self, t: &Turn, ps: [[f64; 3]; N]) -> [[f64; 3]; N] {
        self.moved(ps).map(|p| t.apply(p))
    }
}

#[cfg(test)]
std::thread_local! {
    /// Whether frames may be turned: always, but in the tests of this
    /// module that count or compare volumes along the axes.
    pub(super) static TURNING: std::cell::Cell<bool> = const { std::cell::Cell::new(true) };
}

/// Whether frames may be turned (always, but where a test of this module
/// has switched it off: `TURNING`).
fn turning() -> bool {
    #[cfg(test)]
    return TURNING.with(|t| t.get());
    #[cfg(not(test))]
    true
}

/// A bound on how far `turn.apply(x)` lies from the exact dot products
/// for any point `x` whose coordinates are at most `q` in magnitude (see
/// [`VolumeFrame::of`]).
pub(super) fn turn_error(turn: &Turn, q: f64) -> f64 {
    turn.row_norm() * q * pow2_any(-50) + pow2_any(-1000)
}

/// `2^k` for any `k` up to 1023 (zero below the subnormals).
fn pow2_any(k: i32) -> f64 {
    times_pow2(1.0, k.max(-1100))
}
