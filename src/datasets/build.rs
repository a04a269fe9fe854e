//! Input: exact (dyadic) coordinates and a few construction recipes. Output:
//! closed, outward-oriented [`Mesh`]es.
//!
//! Three generic recipes cover every built-in dataset:
//!
//! - [`Builder::voxels`]: the boundary of a union of boxes on a (non-uniform)
//!   rectilinear grid; every boundary rectangle becomes two triangles.
//! - [`Builder::sweep`]: a "scaled revolution": vertex `(i, j)` is
//!   `s_j * ring_i + t_j * axis` for a star-shaped ring polygon and a profile
//!   polygon `(s_j, t_j)`. Every quad `(i, j), (i+1, j), (i+1, j+1), (i, j+1)`
//!   is planar (two of its sides are parallel to `ring_{i+1} - ring_i`), so
//!   the solid is exactly `{ p : (gauge_ring(p_UW), p_A) in profile }` where
//!   `gauge_ring` is the Minkowski gauge of the ring polygon. Its horizontal
//!   or axial cross-sections are therefore scaled copies of the ring, which is
//!   what makes the hand-derived areas simple.
//! - [`Builder::slab`]: a height field over a triangulated planar domain,
//!   closed by a flat bottom (the same triangulation, reversed) and vertical
//!   walls along every boundary edge of the domain.
//!
//! Vertices are deduplicated by their exact coordinates (so a profile point
//! with `s = 0` collapses a ring into one axis vertex, and its fan triangles
//! come out of the quads that lose a vertex). Every coordinate used here is a
//! small dyadic rational, so every product and sum is exact in `f64`.

use std::collections::HashMap;

use crate::mesh::Mesh;

/// An exact position. All coordinates are small dyadic rationals.
pub(crate) type P3 = [f64; 3];

/// Collects deduplicated vertices and triangles.
#[derive(Default)]
pub(crate) struct Builder {
    positions: Vec<P3>,
    index: HashMap<[u64; 3], u32>,
    faces: Vec<[u32; 3]>,
}

/// `+0.0` for both zeros, so that `-0.0` and `0.0` are one coordinate.
fn canon(x: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else {
        x
    }
}

impl Builder {
    pub(crate) fn new() -> Self {
        Self::default()
    }

    /// The id of the vertex at `p`, created on first use.
    pub(crate) fn vertex(&mut self, p: P3) -> u32 {
        let p = [canon(p[0]), canon(p[1]), canon(p[2])];
        debug_assert!(p
            .iter()
            .all(|x| x.is_finite() && x.abs() < (1u64 << 20) as f64));
        let key = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
        if let Some(&id) = self.index.get(&key) {
            return id;
        }
        let id = u32::try_from(self.positions.len()).expect("small dataset");
        self.positions.push(p);
        self.index.insert(key, id);
        id
    }

    /// A triangle; silently skipped when two of its corners coincide (the
    /// collapsed half of a quad next to an axis vertex).
    pub(crate) fn tri(&mut self, a: u32, b: u32, c: u32) {
        if a != b && b != c && c != a {
            self.faces.push([a, b, c]);
        }
    }

    /// A planar quad, counter-clockwise seen from outside, split along `a-c`.
    pub(crate) fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.tri(a, b, c);
        self.tri(a, c, d);
    }

    /// Number of faces so far (to reverse a later batch).
    pub(crate) fn face_count(&self) -> usize {
        self.faces.len()
    }

    /// Reverses the orientation of every face created since `start`.
    pub(crate) fn reverse_from(&mut self, start: usize) {
        for f in &mut self.faces[start..] {
            f.swap(1, 2);
        }
    }

    pub(crate) fn finish(self) -> Mesh {
        Mesh::from_raw(self.positions, self.faces)
    }

    /// The boundary of the union of the boxes `[xs[i], xs[i+1]] x [ys[j],
    /// ys[j+1]] x [zs[k], zs[k+1]]` for which `solid(i, j, k)` holds. The
    /// caller keeps the union a manifold (no two boxes touching only along an
    /// edge or at a corner).
    pub(crate) fn voxels(
        &mut self,
        xs: &[f64],
        ys: &[f64],
        zs: &[f64],
        solid: impl Fn(usize, usize, usize) -> bool,
    ) {
        let axes: [&[f64]; 3] = [xs, ys, zs];
        let n = [xs.len() - 1, ys.len() - 1, zs.len() - 1];
        let inside = |c: [isize; 3]| {
            (0..3).all(|d| c[d] >= 0 && (c[d] as usize) < n[d])
                && solid(c[0] as usize, c[1] as usize, c[2] as usize)
        };
        for i in 0..n[0] {
            for j in 0..n[1] {
                for k in 0..n[2] {
                    if !solid(i, j, k) {
                        continue;
                    }
                    let cell = [i as isize, j as isize, k as isize];
                    for d in 0..3 {
                        for side in [0isize, 1] {
                            let mut nb = cell;
                            nb[d] += 2 * side - 1;
                            if inside(nb) {
                                continue;
                            }
                            // Corners in the plane of the face, in the cyclic
                            // axes e1 = d+1, e2 = d+2 (e1 x e2 = +d).
                            let e1 = (d + 1) % 3;
                            let e2 = (d + 2) % 3;
                            let corner = |u: usize, w: usize| {
                                let mut idx =
                                    [cell[0] as usize, cell[1] as usize, cell[2] as usize];
                                idx[d] += side as usize;
                                idx[e1] += u;
                                idx[e2] += w;
                                [axes[0][idx[0]], axes[1][idx[1]], axes[2][idx[2]]]
                            };
                            let q = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
                            let v = q.map(|p| self.vertex(p));
                            if side == 1 {
                                self.quad(v[0], v[1], v[2], v[3]);
                            } else {
                                self.quad(v[0], v[3], v[2], v[1]);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Scaled revolution: vertex `(i, j) = s_j (ring_i.0 U + ring_i.1 W) +
    /// t_j A` for `profile_j = (s_j, t_j)`. `(U, W, A)` must be right-handed,
    /// the ring counter-clockwise in `(U, W)` and the profile
    /// counter-clockwise in `(s, t)`; then every face is outward. A `closed`
    /// profile gives a torus; an open one must start and end on the axis
    /// (`s = 0`), giving a ball with one axis vertex at each end.
    pub(crate) fn sweep(
        &mut self,
        ring: &[[f64; 2]],
        profile: &[[f64; 2]],
        closed: bool,
        frame: [P3; 3],
    ) {
        let [u, w, a] = frame;
        let n = ring.len();
        let m = profile.len();
        let mut id = vec![vec![0u32; m]; n];
        for (i, q) in ring.iter().enumerate() {
            for (j, st) in profile.iter().enumerate() {
                let (s, t) = (st[0], st[1]);
                let p = [0, 1, 2].map(|k| s * q[0] * u[k] + s * q[1] * w[k] + t * a[k]);
                id[i][j] = self.vertex(p);
            }
        }
        let rows = if closed { m } else { m - 1 };
        for j in 0..rows {
            let j1 = (j + 1) % m;
            for i in 0..n {
                let i1 = (i + 1) % n;
                self.quad(id[i][j], id[i1][j], id[i1][j1], id[i][j1]);
            }
        }
    }

    /// A slab: the height field `top` (triangles counter-clockwise seen from
    /// above, indices into `top`), a flat bottom at `z_bottom` (the same
    /// triangulation, reversed) and one vertical wall quad under every
    /// boundary edge of the triangulated domain.
    pub(crate) fn slab(&mut self, top: &[P3], tris: &[[usize; 3]], z_bottom: f64) {
        let up: Vec<u32> = top.iter().map(|&p| self.vertex(p)).collect();
        let down: Vec<u32> = top
            .iter()
            .map(|p| self.vertex([p[0], p[1], z_bottom]))
            .collect();
        for t in tris {
            self.tri(up[t[0]], up[t[1]], up[t[2]]);
        }
        for t in tris {
            self.tri(down[t[0]], down[t[2]], down[t[1]]);
        }
        // Directed boundary edges: those whose reverse is in no triangle.
        // The domain lies on their left, so the outward wall normal points
        // to their right.
        let mut directed = std::collections::BTreeSet::new();
        for t in tris {
            for k in 0..3 {
                directed.insert((t[k], t[(k + 1) % 3]));
            }
        }
        for t in tris {
            for k in 0..3 {
                let (p, q) = (t[k], t[(k + 1) % 3]);
                if !directed.contains(&(q, p)) {
                    self.quad(down[p], down[q], up[q], up[p]);
                }
            }
        }
    }
}

/// The three coordinate axes.
pub(crate) const X: P3 = [1.0, 0.0, 0.0];
pub(crate) const Y: P3 = [0.0, 1.0, 0.0];
pub(crate) const Z: P3 = [0.0, 0.0, 1.0];
