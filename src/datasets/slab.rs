//! Input: a small description of a slab (grid size, two integer height
//! fields, cell diagonals, an axis rotation), or arbitrary bytes.
//! Output: a closed, outward-oriented, genus-0 [`Mesh`] with small integer
//! coordinates, where ties are everywhere (flat regions, ridges, saddles,
//! in-plane walls): closed random meshes for property tests
//! (`tests/common/mod.rs`) and fuzzing (`fuzz/fuzz_targets/slice_*.rs`).
//!
//! [`check_slab`] is the check of the `slice_invariants` fuzz target, shared
//! with `tests/fuzz_regressions.rs` so a crash found by the fuzzer replays
//! as a plain test.

use crate::exact::rational::{rat_to_string, Rat};
use crate::exact::{Level, Point2};
use crate::levelset::check::{check_level_invariants, check_volume_identity, vertex_heights};
use crate::levelset::{LevelSet, Slicer};
use crate::mesh::validate::validate;
use crate::mesh::Mesh;
use crate::segment::CutPoint;
use num_bigint::BigInt;
use std::fmt::Write as _;

/// A slab between two height fields over an `nx` x `ny` grid of unit
/// cells: bottom heights `bot`, top heights `bot + thick` (`thick > 0`),
/// both indexed `j * (nx + 1) + i`; cell `(i, j)` (index `j * nx + i`) is
/// split along the diagonal `(i, j)-(i+1, j+1)` when `diag` is set, else
/// along `(i+1, j)-(i, j+1)`. Closed, oriented outward, genus 0. The axes
/// are then rotated cyclically `rot % 3` times (orientation-preserving), so
/// walls and caps lie in every direction.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Slab {
    /// Cells along x (>= 1).
    pub nx: usize,
    /// Cells along y (>= 1).
    pub ny: usize,
    /// Bottom height of each grid point, `(nx + 1) * (ny + 1)` of them.
    pub bot: Vec<i32>,
    /// Thickness (> 0) of each grid point.
    pub thick: Vec<i32>,
    /// The diagonal of each cell, `nx * ny` of them.
    pub diag: Vec<bool>,
    /// Cyclic axis rotations (taken mod 3).
    pub rot: u8,
}

/// Reads bytes, yielding 0 once they run out.
struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn byte(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos = (self.pos + 1).min(self.data.len());
        b
    }

    fn rest(&self) -> &'a [u8] {
        &self.data[self.pos..]
    }
}

impl Slab {
    /// Builds the closed mesh.
    ///
    /// # Panics
    /// When the field lengths do not match `nx` and `ny` (see [`Slab`]).
    pub fn mesh(&self) -> Mesh {
        let (nx, ny) = (self.nx, self.ny);
        let idx = |i: usize, j: usize| j * (nx + 1) + i;
        let n = (nx + 1) * (ny + 1);
        let mut pos = Vec::with_capacity(2 * n);
        for layer in 0..2 {
            for j in 0..=ny {
                for i in 0..=nx {
                    let k = idx(i, j);
                    let z = if layer == 0 {
                        self.bot[k]
                    } else {
                        self.bot[k] + self.thick[k]
                    };
                    pos.push([i as f64, j as f64, f64::from(z)]);
                }
            }
        }
        let b = |i, j| idx(i, j) as u32;
        let t = |i, j| (n + idx(i, j)) as u32;
        let mut faces = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let d = self.diag[j * nx + i];
                let (p00, p10, p11, p01) = ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1));
                let quads: [[(usize, usize); 3]; 2] = if d {
                    [[p00, p10, p11], [p00, p11, p01]]
                } else {
                    [[p00, p10, p01], [p10, p11, p01]]
                };
                for q in quads {
                    faces.push([t(q[0].0, q[0].1), t(q[1].0, q[1].1), t(q[2].0, q[2].1)]);
                    faces.push([b(q[0].0, q[0].1), b(q[2].0, q[2].1), b(q[1].0, q[1].1)]);
                }
            }
        }
        // Boundary ring counter-clockwise seen from above.
        let mut ring = Vec::new();
        for i in 0..nx {
            ring.push((i, 0));
        }
        for j in 0..ny {
            ring.push((nx, j));
        }
        for i in (1..=nx).rev() {
            ring.push((i, ny));
        }
        for j in (1..=ny).rev() {
            ring.push((0, j));
        }
        for k in 0..ring.len() {
            let p = ring[k];
            let q = ring[(k + 1) % ring.len()];
            faces.push([b(p.0, p.1), b(q.0, q.1), t(q.0, q.1)]);
            faces.push([b(p.0, p.1), t(q.0, q.1), t(p.0, p.1)]);
        }
        for _ in 0..self.rot % 3 {
            for p in &mut pos {
                *p = [p[2], p[0], p[1]];
            }
        }
        Mesh::from_raw(pos, faces)
    }

    /// A small slab built deterministically from arbitrary bytes (missing
    /// bytes read as 0; never panics): `nx`, `ny` in `1..=4`, bottoms in
    /// `-2..=2`, thicknesses from 1, with many ties. See
    /// [`Slab::split_bytes`].
    pub fn from_bytes(data: &[u8]) -> Slab {
        Slab::split_bytes(data).0
    }

    /// [`Slab::from_bytes`], also returning the bytes it did not read.
    ///
    /// Byte 0: `nx = 1 + b % 4`, `ny = 1 + (b >> 2) % 4`,
    /// `rot = (b >> 4) % 4 % 3`. Byte 1: the number of distinct fresh
    /// bottoms `1 + b % 5` (from -2 up) and of fresh thicknesses
    /// `1 + (b >> 3) % 3` (from 1 up); small palettes give ties. Then one
    /// byte per grid point for its bottom and one for its top, row by row:
    /// top two bits 0 or 1 take a fresh value from the low six bits, 2
    /// copies the left neighbour's value, 3 the lower neighbour's (a fresh
    /// value on the first column or row; a copied top at or below the
    /// bottom falls back to a fresh thickness). Then the diagonals, eight
    /// cells per byte.
    pub fn split_bytes(data: &[u8]) -> (Slab, &[u8]) {
        let mut r = Reader { data, pos: 0 };
        let b0 = r.byte();
        let (nx, ny) = (1 + usize::from(b0 % 4), 1 + usize::from((b0 >> 2) % 4));
        let rot = (b0 >> 4) % 4 % 3;
        let b1 = r.byte();
        let kb = 1 + i32::from(b1 % 5);
        let kt = 1 + i32::from((b1 >> 3) % 3);
        let n = (nx + 1) * (ny + 1);
        let idx = |i: usize, j: usize| j * (nx + 1) + i;
        // The neighbour a mode copies from, if any.
        let source = |mode: u8, i: usize, j: usize| match mode {
            2 if i > 0 => Some(idx(i - 1, j)),
            3 if j > 0 => Some(idx(i, j - 1)),
            _ => None,
        };
        let mut bot = vec![0; n];
        for j in 0..=ny {
            for i in 0..=nx {
                let b = r.byte();
                bot[idx(i, j)] = match source(b >> 6, i, j) {
                    Some(s) => bot[s],
                    None => -2 + i32::from(b & 0x3f) % kb,
                };
            }
        }
        let mut thick = vec![0; n];
        for j in 0..=ny {
            for i in 0..=nx {
                let k = idx(i, j);
                let b = r.byte();
                let fresh = 1 + i32::from(b & 0x3f) % kt;
                thick[k] = match source(b >> 6, i, j) {
                    Some(s) if bot[s] + thick[s] > bot[k] => bot[s] + thick[s] - bot[k],
                    _ => fresh,
                };
            }
        }
        let mut diag = Vec::with_capacity(nx * ny);
        let mut bits = 0u8;
        for c in 0..nx * ny {
            if c % 8 == 0 {
                bits = r.byte();
            }
            diag.push(bits >> (c % 8) & 1 == 1);
        }
        let slab = Slab {
            nx,
            ny,
            bot,
            thick,
            diag,
            rot,
        };
        (slab, r.rest())
    }

    /// The slab as a Rust expression (`Slab { nx: .., bot: vec![..], .. }`)
    /// to paste into a regression test.
    pub fn pasteable(&self) -> String {
        format!(
            "Slab {{ nx: {}, ny: {}, bot: vec!{:?}, thick: vec!{:?}, diag: vec!{:?}, rot: {} }}",
            self.nx, self.ny, self.bot, self.thick, self.diag, self.rot
        )
    }
}

/// Reads a little-endian unsigned integer of up to 16 bytes.
fn uint(r: &mut Reader<'_>, len: usize) -> BigInt {
    let mut v = BigInt::from(0);
    for k in 0..len {
        v += BigInt::from(r.byte()) << (8 * k);
    }
    v
}

/// A few exact levels in `[zmin - 1, zmax + 1]` of `mesh` (its vertex
/// height range) read from arbitrary bytes, for fuzzing: per level one
/// byte `s` picks a width `w` of 1, 2, 4, 8 or 16 bytes (small ones more
/// often), then `w` bytes give a denominator `q - 1` and `w` more a
/// numerator `r` (little-endian); the level is
/// `zmin - 1 + (r mod (span + 2) q) / q`. Denominators up to 2^128
/// exercise both the `i128` fast path of [`Point2::on_edge`] and its
/// big-rational fallback. At most 4 levels; none for empty input.
pub fn levels_from_bytes(mesh: &Mesh, data: &[u8]) -> Vec<Rat> {
    const WIDTHS: [usize; 8] = [1, 1, 1, 2, 2, 4, 8, 16];
    let zs = vertex_heights(mesh);
    let (Some(lo), Some(hi)) = (zs.first(), zs.last()) else {
        return Vec::new();
    };
    let one = Rat::from_integer(1.into());
    let lo = lo - &one;
    let span = hi + &one - &lo;
    let mut r = Reader { data, pos: 0 };
    let mut out = Vec::new();
    while !r.rest().is_empty() && out.len() < 4 {
        let w = WIDTHS[usize::from(r.byte() % 8)];
        let q = uint(&mut r, w) + 1;
        let num = uint(&mut r, w);
        // (num mod span q) / q, with span = a / b: (num mod a q) / (b q).
        let t = Rat::new(num % (span.numer() * &q), span.denom() * &q);
        out.push(&lo + t);
    }
    out
}

/// Every distinct vertex height of `mesh` and the midpoints between
/// consecutive ones, ascending.
pub fn heights_and_midpoints(mesh: &Mesh) -> Vec<Rat> {
    let zs = vertex_heights(mesh);
    let two = Rat::from_integer(2.into());
    let mut out = zs.clone();
    out.extend(zs.windows(2).map(|w| (&w[0] + &w[1]) / &two));
    out.sort();
    out
}

/// Checks that every point on an edge of every loop (S_O, L-, L+) of `ls`
/// equals the big-rational reference crossing and rounds to the same
/// doubles, and that the fast path [`Point2::on_edge`] returns the same
/// reduced rational as [`Point2::on_edge_reference`].
pub fn check_edge_points(slicer: &Slicer<'_>, ls: &LevelSet) -> Result<(), String> {
    let mesh = slicer.mesh();
    let level = Level::new(ls.level.clone());
    let families = [("S_O", &ls.contours), ("L-", &ls.below), ("L+", &ls.above)];
    for (what, loops) in families {
        for (li, l) in loops.iter().enumerate() {
            for (cut, p) in l.cuts.iter().zip(&l.points) {
                let CutPoint::OnEdge(e) = *cut else {
                    continue;
                };
                let [a, b] = slicer.topology().edge(e).v;
                let (pa, pb) = (mesh.pos(a), mesh.pos(b));
                let reference = Point2::on_edge_reference(pa, pb, &level);
                if p.to_f64() != reference.to_f64() {
                    return Err(format!(
                        "{what} loop {li}, edge {e}: rounded to {:?}, the reference to {:?}",
                        p.to_f64(),
                        reference.to_f64()
                    ));
                }
                for (name, fast) in [
                    ("slicer", p.exact().into_owned()),
                    ("on_edge(a, b)", Point2::on_edge(pa, pb, &level)),
                    ("on_edge(b, a)", Point2::on_edge(pb, pa, &level)),
                ] {
                    let same = |x: &Rat, y: &Rat| x.numer() == y.numer() && x.denom() == y.denom();
                    if !same(&fast.x, &reference.x) || !same(&fast.y, &reference.y) {
                        return Err(format!(
                            "{what} loop {li}, edge {e} ({a}-{b}): {name} gives ({}/{}, {}/{}), \
                             the reference ({}, {})",
                            fast.x.numer(),
                            fast.x.denom(),
                            fast.y.numer(),
                            fast.y.denom(),
                            rat_to_string(&reference.x),
                            rat_to_string(&reference.y)
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

/// The `slice_invariants` fuzz check of one slab: the mesh validates; at
/// every vertex height, every midpoint and every level of `extra`, the
/// level set satisfies SPEC section 7's invariants 1-4
/// ([`check_level_invariants`]) and its crossing points are the exact
/// reference ones ([`check_edge_points`]); Simpson's rule over the exact
/// cross-sections gives the exact volume ([`check_volume_identity`]).
/// The error names the level and carries the slab as pasteable Rust.
pub fn check_slab(slab: &Slab, extra: &[Rat]) -> Result<(), String> {
    let fail = |e: String| {
        let mut msg = format!("{e}\nslab: {}\nextra levels: [", slab.pasteable());
        for c in extra {
            let _ = write!(msg, "\"{}\", ", rat_to_string(c));
        }
        msg.push(']');
        msg
    };
    let mesh = slab.mesh();
    let report = validate(&mesh);
    if !report.is_accepted() {
        return Err(fail(format!("the slab is rejected:\n{report}")));
    }
    let slicer = Slicer::new(&mesh).map_err(|e| fail(format!("Slicer::new failed: {e}")))?;
    let mut levels = heights_and_midpoints(&mesh);
    levels.extend(extra.iter().cloned());
    for c in &levels {
        let at = |e: String| fail(format!("at z = {}: {e}", rat_to_string(c)));
        let ls = slicer.slice_at(c).map_err(|e| at(e.to_string()))?;
        check_level_invariants(&mesh, slicer.topology(), &ls).map_err(at)?;
        check_edge_points(&slicer, &ls).map_err(at)?;
    }
    check_volume_identity(&slicer, &report.volume).map_err(fail)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_bytes_never_panics_and_gives_valid_slabs() {
        let mut inputs: Vec<Vec<u8>> = vec![vec![], vec![0xff; 200], vec![0x80; 7]];
        let mut x = 0x2545_f491_4f6c_dd1d_u64;
        for len in 0..120 {
            let v = (0..len)
                .map(|_| {
                    x ^= x << 13;
                    x ^= x >> 7;
                    x ^= x << 17;
                    x as u8
                })
                .collect();
            inputs.push(v);
        }
        for data in &inputs {
            let (s, rest) = Slab::split_bytes(data);
            assert!((1..=4).contains(&s.nx) && (1..=4).contains(&s.ny) && s.rot < 3);
            assert!(s.thick.iter().all(|&t| t > 0));
            assert!(rest.len() <= data.len());
            let mesh = s.mesh();
            assert!(validate(&mesh).is_accepted(), "{}", s.pasteable());
            let levels = levels_from_bytes(&mesh, rest);
            assert!(levels.len() <= 4);
        }
    }

    #[test]
    fn small_slabs_pass_the_fuzz_check() {
        for data in [&[][..], &[0x05, 0x02, 0x81, 7, 3], &[0xff; 64]] {
            let (s, rest) = Slab::split_bytes(data);
            let extra = levels_from_bytes(&s.mesh(), rest);
            check_slab(&s, &extra).unwrap();
        }
    }
}
