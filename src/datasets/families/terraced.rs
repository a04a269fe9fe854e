//! Input: a seeded stream. Output: a CAD-like terraced part: columns on a
//! rectilinear grid whose lines and terrace heights are decimals in
//! millimetres (0.2, 0.6, 2.45, 10.35, ...), stored as the nearest `f32`
//! values, as CAD tools store them. Flat terraces, up-facing tops and
//! pockets at decimal heights; sometimes a through-hole.
//!
//! Sliced as stored, the flats lie at `f32` values such as
//! 0.20000000298..., never at 1/5; snapped to the family's grid of
//! 1/1000 mm they lie at the decimals the designer meant (every
//! coordinate is below 64 mm, so its `f32` is within half the spacing
//! 2^-18 of the decimal, far inside half a grid step), and the answers
//! are given at those.
//!
//! A column set (cells filled from the bottom) can only fail to be
//! well-composed by a horizontal checkerboard (two diagonal columns taller
//! than the other two at some height); those are removed by raising the
//! lower column, so the boundary is a closed 2-manifold (see
//! [`super::voxels`]).

use super::rng::Rng;
use super::voxels::Voxels;
use crate::mesh::Mesh;

/// Terrace height steps, in thousandths of a millimetre (the decimals a
/// CAD part is drawn with: 0.35, 1.25, 3.15 mm); geometry, not a tolerance.
const STEPS: [i64; 9] = [350, 500, 800, 1200, 1250, 2000, 2500, 3150, 4000];

/// Terrace heights, in thousandths of a millimetre.
const HEIGHTS: [i64; 10] = [200, 600, 1000, 1800, 2450, 3300, 5050, 7500, 10350, 12700];

/// The nearest `f32` to `t / 1000` (correctly rounded by the standard
/// library's decimal parser), as an exact `f64`.
fn f32_of_thousandths(t: i64) -> f64 {
    debug_assert!(t >= 0);
    let text = format!("{}.{:03}", t / 1000, t % 1000);
    let v: f32 = text.parse().expect("a decimal literal");
    f64::from(v)
}

/// Grid line positions from `start`, `n` random decimal steps.
fn decimal_lines(rng: &mut Rng, n: usize, start: i64) -> Vec<f64> {
    let mut t = start;
    let mut out = vec![f32_of_thousandths(t)];
    for _ in 0..n {
        t += *rng.pick(&STEPS);
        out.push(f32_of_thousandths(t));
    }
    out
}

/// Raises columns until no 2x2 block of cells has its two diagonal
/// columns both taller than the two others.
fn remove_checkerboards(h: &mut [usize], nx: usize, ny: usize) {
    loop {
        let mut changed = false;
        for j in 0..ny.saturating_sub(1) {
            for i in 0..nx.saturating_sub(1) {
                let k = [
                    j * nx + i,
                    j * nx + i + 1,
                    (j + 1) * nx + i + 1,
                    (j + 1) * nx + i,
                ];
                for (hi_pair, lo_pair) in [([0, 2], [1, 3]), ([1, 3], [0, 2])] {
                    let top = h[k[hi_pair[0]]].min(h[k[hi_pair[1]]]);
                    let low = h[k[lo_pair[0]]].max(h[k[lo_pair[1]]]);
                    if top > low {
                        let (a, b) = (k[lo_pair[0]], k[lo_pair[1]]);
                        let raise = if h[a] <= h[b] { a } else { b };
                        h[raise] = top;
                        changed = true;
                    }
                }
            }
        }
        if !changed {
            return;
        }
    }
}

/// One random terraced part.
pub(super) fn build(rng: &mut Rng) -> Mesh {
    let nx = rng.size(3, 6);
    let ny = rng.size(3, 6);
    let x0 = *rng.pick(&[0, 12700]);
    let xs = decimal_lines(rng, nx, x0);
    let y0 = *rng.pick(&[0, 5050]);
    let ys = decimal_lines(rng, ny, y0);
    // Terrace heights: the bottom at 0, then an increasing subset.
    let layers = rng.size(2, 5);
    let mut chosen: Vec<i64> = Vec::new();
    while chosen.len() < layers {
        let t = *rng.pick(&HEIGHTS);
        if !chosen.contains(&t) {
            chosen.push(t);
        }
    }
    chosen.sort_unstable();
    let mut zs = vec![0.0];
    zs.extend(chosen.iter().map(|&t| f32_of_thousandths(t)));
    // Column heights (number of layers filled): raised rectangles per
    // terrace, then a pocket, then perhaps a through-hole.
    let mut h = vec![1usize; nx * ny];
    let rect = |rng: &mut Rng, h: &mut [usize], value: usize| {
        let (i0, j0) = (rng.size(0, nx - 1), rng.size(0, ny - 1));
        let (i1, j1) = ((i0 + rng.size(1, 3)).min(nx), (j0 + rng.size(1, 3)).min(ny));
        for j in j0..j1 {
            for i in i0..i1 {
                h[j * nx + i] = value;
            }
        }
    };
    for t in 2..=layers {
        for _ in 0..rng.size(1, 2) {
            rect(rng, &mut h, t);
        }
    }
    if rng.below(2) == 0 {
        let v = rng.size(1, layers);
        rect(rng, &mut h, v);
    }
    if rng.below(3) == 0 {
        let (i, j) = (rng.size(1, nx - 2), rng.size(1, ny - 2));
        h[j * nx + i] = 0;
    }
    remove_checkerboards(&mut h, nx, ny);
    let mut v = Voxels::new([nx, ny, layers]);
    for j in 0..ny {
        for i in 0..nx {
            v.fill([i, j, 0], [i + 1, j + 1, h[j * nx + i]], true);
        }
    }
    v.mesh(&xs, &ys, &zs)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The coordinates here are below 64 mm (at most 12.7 + 6 x 4 along
    /// x), where the nearest `f32` is within half its spacing 2^-18 of the
    /// decimal it was parsed from: far inside half the 1/1000 mm snap
    /// grid, so snapping recovers each decimal exactly.
    const DECIMAL_ERROR: f64 = 1.0 / (1u64 << 19) as f64;

    #[test]
    fn decimals_are_stored_as_their_nearest_f32() {
        assert_eq!(f32_of_thousandths(200), f64::from(0.2f32));
        assert_eq!(f32_of_thousandths(10350), f64::from(10.35f32));
        assert_ne!(f32_of_thousandths(200), 0.2);
        // Every terrace height and every grid line the generator can make.
        let lines = (0..=6 * 4000).chain(12700..=12700 + 6 * 4000);
        for t in HEIGHTS.iter().copied().chain(lines) {
            let err = (f32_of_thousandths(t) - t as f64 / 1000.0).abs();
            assert!(err <= DECIMAL_ERROR, "{t}");
        }
    }

    #[test]
    fn checkerboards_are_raised_away() {
        // 1 2 / 2 1: the diagonal of 2s is taller than the 1s.
        let mut h = vec![2, 1, 1, 2];
        remove_checkerboards(&mut h, 2, 2);
        let v = {
            let mut v = Voxels::new([2, 2, 2]);
            for (c, &t) in h.iter().enumerate() {
                v.fill([c % 2, c / 2, 0], [c % 2 + 1, c / 2 + 1, t], true);
            }
            v
        };
        assert!(v.is_well_composed(), "{h:?}");
    }
}
