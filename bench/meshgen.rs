//! The benchmark meshes, shared by `examples/bench_meshes.rs` (which writes
//! them for `bench/compare`) and `benches/kernel.rs` (criterion), included
//! by both with `#[path]`.
//!
//! - [`torus`]: a finely tessellated torus (R = 40, r = 15), tilted by
//!   0.4 rad about x (and turned about z) so that no vertex ring is
//!   horizontal: planes cross it at generic heights.
//! - [`steps`]: a CAD-like part: a tube with a round through hole and a
//!   stepped outer wall, 100 steps of 1.25 (an exact binary value), the
//!   outer radius going up and down so the step flats face up and down,
//!   all at `z = k * 1.25`; the last step is 1.75 tall (top at 125.5).
//!   Layer plans `k * 1.25` and `k * 0.125` hit the flats exactly.
//!
//! Every coordinate is an exact `f32`; vertices are shared, so a binary STL
//! of the mesh welds back to the same mesh.

use std::f64::consts::TAU;
use std::io::{BufWriter, Write};
use std::path::Path;

/// A mesh being built: `f32` positions and outward CCW triangles.
#[derive(Default)]
pub struct Builder {
    /// Vertex positions.
    pub pos: Vec<[f32; 3]>,
    /// Triangles, counter-clockwise seen from outside.
    pub tris: Vec<[u32; 3]>,
}

impl Builder {
    /// Adds a ring of `n` vertices, returns the index of its first one.
    fn ring(&mut self, n: usize, at: impl Fn(usize) -> [f64; 3]) -> u32 {
        let base = self.pos.len() as u32;
        for j in 0..n {
            let p = at(j);
            self.pos.push([p[0] as f32, p[1] as f32, p[2] as f32]);
        }
        base
    }

    /// Joins ring `a` to ring `b` (both of `n` vertices, same angular
    /// order) with quads split in two: the normal is `(a1 - a0) x (b0 - a0)`.
    fn strip(&mut self, n: usize, a: u32, b: u32) {
        let n32 = n as u32;
        for j in 0..n32 {
            let k = (j + 1) % n32;
            let (a0, a1, b0, b1) = (a + j, a + k, b + j, b + k);
            self.tris.push([a0, a1, b1]);
            self.tris.push([a0, b1, b0]);
        }
    }

    /// The lowest and highest vertex heights.
    pub fn z_range(&self) -> (f32, f32) {
        self.pos.iter().fold((f32::MAX, f32::MIN), |(lo, hi), p| {
            (lo.min(p[2]), hi.max(p[2]))
        })
    }

    /// Writes a binary STL (facet normals left zero, as many exporters do).
    pub fn write_stl(&self, path: &Path) -> std::io::Result<()> {
        let mut w = BufWriter::new(std::fs::File::create(path)?);
        let mut header = [0u8; 80];
        let text = b"wmslice bench mesh (binary STL, exact f32 vertices)";
        header[..text.len()].copy_from_slice(text);
        w.write_all(&header)?;
        w.write_all(&(self.tris.len() as u32).to_le_bytes())?;
        for t in &self.tris {
            w.write_all(&[0u8; 12])?;
            for &v in t {
                for c in self.pos[v as usize] {
                    w.write_all(&c.to_le_bytes())?;
                }
            }
            w.write_all(&[0u8; 2])?;
        }
        w.flush()
    }
}

/// A torus of `nu x nv` quads (2 nu nv triangles), tilted.
pub fn torus(nu: usize, nv: usize) -> Builder {
    let (big, small) = (40.0f64, 15.0f64);
    let (tilt, turn) = (0.4f64, 0.3f64);
    let mut b = Builder::default();
    let rings: Vec<u32> = (0..nv)
        .map(|j| {
            let v = TAU * (j as f64 + 0.5) / nv as f64;
            b.ring(nu, |i| {
                let u = TAU * (i as f64 + 0.25) / nu as f64;
                let rr = big + small * v.cos();
                let (x, y, z) = (rr * u.cos(), rr * u.sin(), small * v.sin());
                // Tilt about x, then turn about z.
                let (y, z) = (
                    y * tilt.cos() - z * tilt.sin(),
                    y * tilt.sin() + z * tilt.cos(),
                );
                let (x, y) = (
                    x * turn.cos() - y * turn.sin(),
                    x * turn.sin() + y * turn.cos(),
                );
                [x, y, z]
            })
        })
        .collect();
    for j in 0..nv {
        b.strip(nu, rings[j], rings[(j + 1) % nv]);
    }
    b
}

/// The stepped tube with `n` vertices per ring (404 n triangles).
pub fn steps(n: usize) -> Builder {
    const STEPS: usize = 100;
    const STEP: f64 = 1.25;
    const TOP: f64 = 125.5;
    const HOLE: f64 = 10.0;
    let zigzag = [0.0, 1.0, 2.0, 3.0, 4.0, 3.0, 2.0, 1.0];
    let radius = |k: usize| 30.0 + 2.0 * zigzag[k % 8];
    let mut b = Builder::default();
    let circle = |r: f64, z: f64| {
        move |j: usize| {
            let t = TAU * j as f64 / n as f64;
            [r * t.cos(), r * t.sin(), z]
        }
    };
    let hole_bottom = b.ring(n, circle(HOLE, 0.0));
    let hole_top = b.ring(n, circle(HOLE, TOP));
    // The outer wall of step k runs from z_k (ring `lower`) to z_{k+1}.
    let mut lower = b.ring(n, circle(radius(0), 0.0));
    b.strip(n, hole_bottom, lower); // bottom cap, facing down
    for k in 0..STEPS {
        let z_top = if k + 1 == STEPS {
            TOP
        } else {
            (k + 1) as f64 * STEP
        };
        let upper = b.ring(n, circle(radius(k), z_top));
        b.strip(n, lower, upper); // outer wall, facing out
        if k + 1 == STEPS {
            b.strip(n, upper, hole_top); // top cap, facing up
        } else {
            // The step flat at z_{k+1}: up if the radius shrinks, else down.
            let next = b.ring(n, circle(radius(k + 1), z_top));
            b.strip(n, upper, next);
            lower = next;
        }
    }
    b.strip(n, hole_top, hole_bottom); // the hole's wall, facing the axis
    b
}

/// A torus of about `triangles` triangles (`nu = 2.5 nv`).
pub fn torus_of(triangles: usize) -> Builder {
    let nv = ((triangles as f64 / 5.0).sqrt().round() as usize).max(3);
    let nu = (triangles / (2 * nv)).max(3);
    torus(nu, nv)
}

/// The stepped part with about `triangles` triangles (`404 n`).
pub fn steps_of(triangles: usize) -> Builder {
    steps((triangles / 404).max(3))
}

impl Builder {
    /// The mesh as `wmslice` holds it (exact `f64` of the `f32` values).
    pub fn to_mesh(&self) -> wmslice::Mesh {
        let pos = self.pos.iter().map(|p| p.map(f64::from)).collect();
        wmslice::Mesh::from_raw(pos, self.tris.clone())
    }
}
