//! Input: a seeded stream. Output: a slab whose top is an egg-crate field
//! `base + A s(i) s(j)` for a periodic integer wave `s` (zeros on whole
//! grid lines: transversal in-plane edges and saddles where the lines
//! cross; isolated peaks and pits, or flat 2x2 peaks for the wider
//! waves), with monkey-saddle patches stamped on it: around a grid point
//! with eight neighbours, `h = h0 + Re((dx + i dy)^m)` for m = 3 (six
//! branches) or m = 4 (eight), turned by a quarter turn or mirrored in
//! height at random.
//!
//! Over the union-jack triangulation (every grid point with `i + j` even
//! has all eight neighbours in its link), with a flat bottom below the
//! lowest point: closed, oriented and free of self-intersections by
//! construction (see [`super::grid`]).

use super::grid::{lines, GridSlab};
use super::rng::Rng;
use crate::mesh::Mesh;

/// Periodic waves: a single peak per period, a flat-topped one, a tall one.
const WAVES: [&[i64]; 3] = [
    &[0, 1, 0, -1],
    &[0, 1, 1, 0, -1, -1],
    &[0, 1, 2, 1, 0, -1, -2, -1],
];

/// `Re((x + i y)^m)` for m = 2, 3, 4.
fn harmonic(m: u32, x: i64, y: i64) -> i64 {
    match m {
        2 => x * x - y * y,
        3 => x * x * x - 3 * x * y * y,
        _ => x * x * x * x - 6 * x * x * y * y + y * y * y * y,
    }
}

/// One random egg crate with monkey saddles.
pub(super) fn build(rng: &mut Rng) -> Mesh {
    let nx = rng.size(6, 12);
    let ny = rng.size(6, 12);
    let wave = *rng.pick(&WAVES);
    let p = wave.len() as i64;
    let (fx, fy) = (rng.range(0, p - 1), rng.range(0, p - 1));
    let amp = rng.range(1, 2);
    let base = rng.range(-1, 1);
    let s = |t: i64| wave[(t.rem_euclid(p)) as usize];
    let np = (nx + 1) * (ny + 1);
    let at = |i: usize, j: usize| j * (nx + 1) + i;
    let mut top = vec![0i64; np];
    for j in 0..=ny {
        for i in 0..=nx {
            top[at(i, j)] = base + amp * s(i as i64 + fx) * s(j as i64 + fy);
        }
    }
    // Monkey-saddle patches around eight-neighbour grid points, apart.
    let mut centres: Vec<(usize, usize)> = Vec::new();
    for _ in 0..rng.size(1, 3) {
        let (i, j) = (rng.size(1, nx - 1), rng.size(1, ny - 1));
        let (i, j) = if (i + j) % 2 == 0 { (i, j) } else { (i + 1, j) };
        if i >= nx
            || centres
                .iter()
                .any(|&(a, b)| a.abs_diff(i) < 4 && b.abs_diff(j) < 4)
        {
            continue;
        }
        centres.push((i, j));
        let m = if rng.below(3) == 0 { 4 } else { 3 };
        let quarter = rng.below(2) == 1;
        let sign = if rng.below(2) == 0 { 1 } else { -1 };
        let radius = rng.range(1, 2);
        let h0 = top[at(i, j)];
        for dy in -radius..=radius {
            for dx in -radius..=radius {
                let (x, y) = (i as i64 + dx, j as i64 + dy);
                if x < 0 || y < 0 || x > nx as i64 || y > ny as i64 {
                    continue;
                }
                let (u, w) = if quarter { (-dy, dx) } else { (dx, dy) };
                top[at(x as usize, y as usize)] = h0 + sign * harmonic(m, u, w);
            }
        }
    }
    let lo = *top.iter().min().unwrap_or(&0);
    let bottom = (lo - rng.range(1, 2)) as f64;
    let slab = GridSlab {
        xs: lines(rng, nx, 0, 1, 1),
        ys: lines(rng, ny, 0, 1, 1),
        present: vec![true; nx * ny],
        diag: GridSlab::union_jack(nx, ny),
        top: top.iter().map(|&z| z as f64).collect(),
        bot: vec![bottom; np],
    };
    slab.mesh()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sign changes of `Re((x + i y)^m)` around the eight neighbours
    /// (zeros skipped, as in-plane edges between opposite sides count as
    /// one branch): 2m for m = 2, 3, 4.
    #[test]
    fn harmonics_alternate_2m_times_around_a_point() {
        let ring = [
            (1, 0),
            (1, 1),
            (0, 1),
            (-1, 1),
            (-1, 0),
            (-1, -1),
            (0, -1),
            (1, -1),
        ];
        for m in 2..=4 {
            let signs: Vec<i64> = ring
                .iter()
                .map(|&(x, y)| harmonic(m, x, y).signum())
                .filter(|&s| s != 0)
                .collect();
            let changes = (0..signs.len())
                .filter(|&k| signs[k] != signs[(k + 1) % signs.len()])
                .count();
            assert_eq!(changes, 2 * m as usize, "m = {m}");
        }
    }
}
