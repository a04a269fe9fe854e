//! Input: a set of voxels on a rectilinear grid. Output: whether its
//! boundary is a 2-manifold (the set is well-composed), and the closed
//! mesh of that boundary.
//!
//! A 3D set of cubes is well-composed (Latecki, "3D well-composed
//! pictures", 1997) when no 2x2 square of cells in any axis plane holds
//! two diagonal cells of one kind and the other two of the other kind,
//! and no 2x2x2 block holds exactly two antipodal cells of one kind; then
//! the boundary surface is a 2-manifold: every boundary edge lies in two
//! boundary squares and every vertex link is one cycle. The outside of
//! the grid counts as empty. Each boundary square becomes two triangles on
//! shared grid vertices; such squares meet only in whole grid edges or
//! grid points, so the surface cannot self-intersect.

use crate::datasets::build::Builder;
use crate::mesh::Mesh;

/// A voxel set on an `n[0] x n[1] x n[2]` grid of cells.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Voxels {
    pub n: [usize; 3],
    solid: Vec<bool>,
}

impl Voxels {
    /// All empty.
    pub fn new(n: [usize; 3]) -> Self {
        Voxels {
            n,
            solid: vec![false; n[0] * n[1] * n[2]],
        }
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.n[1] + c[1]) * self.n[0] + c[0]
    }

    /// Whether cell `c` (any integers; outside the grid: empty) is solid.
    pub fn get(&self, c: [i64; 3]) -> bool {
        if (0..3).any(|d| c[d] < 0 || c[d] >= self.n[d] as i64) {
            return false;
        }
        self.solid[self.index(c.map(|x| x as usize))]
    }

    /// Sets cell `c` (inside the grid).
    pub fn set(&mut self, c: [usize; 3], v: bool) {
        let k = self.index(c);
        self.solid[k] = v;
    }

    /// Sets every cell of the box `lo..hi` (half-open, clipped to the grid).
    pub fn fill(&mut self, lo: [usize; 3], hi: [usize; 3], v: bool) {
        for k in lo[2]..hi[2].min(self.n[2]) {
            for j in lo[1]..hi[1].min(self.n[1]) {
                for i in lo[0]..hi[0].min(self.n[0]) {
                    self.set([i, j, k], v);
                }
            }
        }
    }

    /// Number of solid cells.
    pub fn count(&self) -> usize {
        self.solid.iter().filter(|&&s| s).count()
    }

    /// No critical configuration anywhere (the grid padded by one empty
    /// layer): the boundary is a 2-manifold.
    pub fn is_well_composed(&self) -> bool {
        let n = self.n.map(|x| x as i64);
        for k in -1..n[2] {
            for j in -1..n[1] {
                for i in -1..n[0] {
                    let c = |a: i64, b: i64, d: i64| self.get([i + a, j + b, k + d]);
                    // The 2x2 squares at this corner in the three axis planes.
                    let squares = [
                        [c(0, 0, 0), c(1, 0, 0), c(1, 1, 0), c(0, 1, 0)],
                        [c(0, 0, 0), c(0, 1, 0), c(0, 1, 1), c(0, 0, 1)],
                        [c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)],
                    ];
                    for s in squares {
                        if s[0] == s[2] && s[1] == s[3] && s[0] != s[1] {
                            return false;
                        }
                    }
                    // The 2x2x2 block: exactly two antipodal cells of one kind.
                    let cube: Vec<bool> = (0..8)
                        .map(|b| c(b & 1, (b >> 1) & 1, (b >> 2) & 1))
                        .collect();
                    let solid = cube.iter().filter(|&&s| s).count();
                    for kind in [true, false] {
                        let of_kind = if kind { solid } else { 8 - solid };
                        if of_kind == 2 && (0..4).any(|b| cube[b] == kind && cube[7 - b] == kind) {
                            return false;
                        }
                    }
                }
            }
        }
        true
    }

    /// Whether the solid cells are face-connected (and there is one).
    pub fn is_connected(&self) -> bool {
        let total = self.count();
        let Some(start) = self.solid.iter().position(|&s| s) else {
            return false;
        };
        let n = self.n;
        let mut seen = vec![false; self.solid.len()];
        seen[start] = true;
        let mut stack = vec![start];
        let mut reached = 1;
        while let Some(k) = stack.pop() {
            let c = [k % n[0], (k / n[0]) % n[1], k / (n[0] * n[1])];
            for d in 0..3 {
                for step in [-1i64, 1] {
                    let mut nb = c.map(|x| x as i64);
                    nb[d] += step;
                    if self.get(nb) {
                        let m = self.index(nb.map(|x| x as usize));
                        if !seen[m] {
                            seen[m] = true;
                            reached += 1;
                            stack.push(m);
                        }
                    }
                }
            }
        }
        reached == total
    }

    /// The boundary mesh on the grid lines `xs`, `ys`, `zs` (`n + 1` each,
    /// strictly increasing). The set must be well-composed.
    pub fn mesh(&self, xs: &[f64], ys: &[f64], zs: &[f64]) -> Mesh {
        debug_assert!(self.is_well_composed());
        let mut b = Builder::new();
        b.voxels(xs, ys, zs, |i, j, k| {
            self.get([i as i64, j as i64, k as i64])
        });
        b.finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagonal_contacts_are_not_well_composed() {
        let mut v = Voxels::new([2, 2, 2]);
        v.set([0, 0, 0], true);
        assert!(v.is_well_composed());
        v.set([1, 1, 0], true); // edge contact
        assert!(!v.is_well_composed());
        let mut v = Voxels::new([2, 2, 2]);
        v.set([0, 0, 0], true);
        v.set([1, 1, 1], true); // corner contact
        assert!(!v.is_well_composed());
        // The complement of a corner contact inside a solid block.
        let mut v = Voxels::new([4, 4, 4]);
        v.fill([0, 0, 0], [4, 4, 4], true);
        v.set([1, 1, 1], false);
        assert!(v.is_well_composed() && v.is_connected());
        v.set([2, 2, 2], false);
        assert!(!v.is_well_composed());
    }
}
