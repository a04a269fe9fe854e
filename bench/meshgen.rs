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
//! Every coordinate of those two is an exact `f32` on one small binary grid
//! (the integer fast path of `exact/grid.rs` holds). Real files rarely
//! are; three more shapes carry the coordinate patterns of real files:
//!
//! - [`torus_origin`]: the torus centred at the origin and tilted, in
//!   `f32`, its rings starting on the axes, so that `cos(pi/2)` leaves
//!   noise such as `1e-15` beside coordinates of 40 (about 80 bits of one
//!   grid).
//! - [`knot`]: a (2, 3) torus knot tube written as a decimal OBJ with six
//!   decimals (`f64` values with scattered exponents).
//! - [`steps_f64`]: the stepped part in `f64`, turned about z by an odd
//!   angle (full 53-bit mantissas, near-zero noise), flats still at
//!   `z = k * 1.25`: a CAD-like export.
//! - [`plate`]: a perforated plate (a printer bed, a panel) as a decimal
//!   OBJ: every wall parallel to x or y, so each level's many loops have
//!   crossings that share a coordinate, ties the nesting decides.
//!
//! Vertices are shared, so a file of the mesh welds back to the same mesh.

use std::f64::consts::TAU;
use std::io::{BufWriter, Write};
use std::path::Path;

/// A mesh being built: positions (`f64`, rounded to `f32` on the way in
/// unless [`Builder::double`]) and outward CCW triangles.
#[derive(Default)]
pub struct Builder {
    /// Vertex positions.
    pub pos: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise seen from outside.
    pub tris: Vec<[u32; 3]>,
    /// Keep `f64` positions (else each is rounded to `f32`).
    pub double: bool,
}

impl Builder {
    /// Adds a ring of `n` vertices, returns the index of its first one.
    fn ring(&mut self, n: usize, at: impl Fn(usize) -> [f64; 3]) -> u32 {
        let base = self.pos.len() as u32;
        for j in 0..n {
            let p = at(j);
            let p = if self.double {
                p
            } else {
                p.map(|c| f64::from(c as f32))
            };
            self.pos.push(p);
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
    pub fn z_range(&self) -> (f64, f64) {
        self.pos.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
            (lo.min(p[2]), hi.max(p[2]))
        })
    }

    /// Writes an OBJ, each coordinate with `decimals` decimals, or the
    /// shortest text that reads back as the same double when `None`.
    pub fn write_obj(&self, path: &Path, decimals: Option<usize>) -> std::io::Result<()> {
        let mut w = BufWriter::new(std::fs::File::create(path)?);
        for p in &self.pos {
            match decimals {
                Some(d) => writeln!(w, "v {:.d$} {:.d$} {:.d$}", p[0], p[1], p[2])?,
                None => writeln!(w, "v {:?} {:?} {:?}", p[0], p[1], p[2])?,
            }
        }
        for t in &self.tris {
            writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
        }
        w.flush()
    }

    /// The positions as a file holding them reads back: decimals rounded
    /// to the nearest double, as an OBJ reader parses them.
    pub fn rounded_to_decimals(mut self, decimals: usize) -> Builder {
        for p in &mut self.pos {
            *p = p.map(|c| format!("{c:.decimals$}").parse().expect("a decimal"));
        }
        self
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
                    w.write_all(&(c as f32).to_le_bytes())?;
                }
            }
            w.write_all(&[0u8; 2])?;
        }
        w.flush()
    }
}

/// A torus of `nu x nv` quads (2 nu nv triangles), tilted.
pub fn torus(nu: usize, nv: usize) -> Builder {
    torus_at(nu, nv, 0.25, 0.5)
}

/// The torus centred at the origin with its rings starting on the axes
/// (`u = 2 pi i / nu`): `cos(pi / 2)` and `sin(pi)` leave noise of about
/// `1e-15` beside coordinates of 40 in the `f32` values (`nu` a multiple
/// of 4). Tilted and turned as [`torus`].
pub fn torus_origin(nu: usize, nv: usize) -> Builder {
    torus_at(nu, nv, 0.0, 0.0)
}

fn torus_at(nu: usize, nv: usize, u0: f64, v0: f64) -> Builder {
    let (big, small) = (40.0f64, 15.0f64);
    let (tilt, turn) = (0.4f64, 0.3f64);
    let mut b = Builder::default();
    let rings: Vec<u32> = (0..nv)
        .map(|j| {
            let v = TAU * (j as f64 + v0) / nv as f64;
            b.ring(nu, |i| {
                let u = TAU * (i as f64 + u0) / nu as f64;
                let rr = big + small * v.cos();
                let (x, y, z) = (rr * u.cos(), rr * u.sin(), small * v.sin());
                // Tilt about x, then turn about z.
                let (y, z) = (
                    y * tilt.cos() - z * tilt.sin(),
                    y * tilt.sin() + z * tilt.cos(),
                );
                let (x, y) = if u0 == 0.0 {
                    // Turning would mix the noise away: keep it.
                    (x, y)
                } else {
                    (
                        x * turn.cos() - y * turn.sin(),
                        x * turn.sin() + y * turn.cos(),
                    )
                };
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
    steps_in(n, false, 0.0)
}

/// The stepped tube in `f64`, turned by `0.1` rad about z: full mantissas
/// and near-zero noise in x and y, flats still at `z = k * 1.25`.
pub fn steps_f64(n: usize) -> Builder {
    steps_in(n, true, 0.1)
}

fn steps_in(n: usize, double: bool, turn: f64) -> Builder {
    const STEPS: usize = 100;
    const STEP: f64 = 1.25;
    const TOP: f64 = 125.5;
    const HOLE: f64 = 10.0;
    let zigzag = [0.0, 1.0, 2.0, 3.0, 4.0, 3.0, 2.0, 1.0];
    let radius = |k: usize| 30.0 + 2.0 * zigzag[k % 8];
    let mut b = Builder {
        double,
        ..Builder::default()
    };
    let circle = |r: f64, z: f64| {
        move |j: usize| {
            let t = TAU * j as f64 / n as f64 + turn;
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

/// [`torus_origin`] with about `triangles` triangles (`nu` a multiple of 4).
pub fn torus_origin_of(triangles: usize) -> Builder {
    let nv = ((triangles as f64 / 5.0).sqrt().round() as usize).max(4) / 4 * 4;
    let nu = ((triangles / (2 * nv)) / 4 * 4).max(4);
    torus_origin(nu, nv)
}

/// [`steps_f64`] with about `triangles` triangles.
pub fn steps_f64_of(triangles: usize) -> Builder {
    steps_f64((triangles / 404).max(3))
}

/// A (2, 3) torus knot swept by a circle of radius 0.4 (`n` rings of `m`
/// vertices, `2 n m` triangles), centred at the origin, as a decimal OBJ
/// with six decimals reads back ([`Builder::rounded_to_decimals`]).
pub fn knot(n: usize, m: usize) -> Builder {
    let curve = |t: f64| {
        let r = 2.0 + (3.0 * t).cos();
        [r * (2.0 * t).cos(), r * (2.0 * t).sin(), -(3.0 * t).sin()]
    };
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let unit = |a: [f64; 3]| {
        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        a.map(|c| c / l)
    };
    let mut b = Builder {
        double: true,
        ..Builder::default()
    };
    let rings: Vec<u32> = (0..n)
        .map(|i| {
            let t = TAU * i as f64 / n as f64;
            let (p, q) = (curve(t), curve(t + 1e-4));
            let tangent = unit(sub(q, p));
            let normal = unit(cross(tangent, [0.0, 0.0, 1.0]));
            let binormal = cross(tangent, normal);
            b.ring(m, |j| {
                let a = TAU * j as f64 / m as f64;
                let (c, s) = (0.4 * a.cos(), 0.4 * a.sin());
                [0, 1, 2].map(|k| p[k] + c * normal[k] + s * binormal[k])
            })
        })
        .collect();
    for i in 0..n {
        b.strip(m, rings[i], rings[(i + 1) % n]);
    }
    b.rounded_to_decimals(6)
}

/// [`knot`] with about `triangles` triangles (`n = 8 m`).
pub fn knot_of(triangles: usize) -> Builder {
    let m = ((triangles as f64 / 16.0).sqrt().round() as usize).max(3);
    knot(8 * m, m)
}

/// A perforated plate as CAD tools export a printer bed or a panel: an
/// axis-aligned slab with `m x m` square through holes, and a notch in
/// each side at every row of holes (mounting slots), on grid lines with
/// six decimals (off every binary grid, placed where PrusaSlicer's `A.obj`
/// test part lies); every wall parallel to x or y and cut into `bands`
/// horizontal strips at six-decimal heights. Each level crosses every
/// wall: `m^2 + 1` loops whose crossings share their y with the outline's
/// notches (ties the nesting decides exactly).
pub fn plate(m: usize, bands: usize) -> Builder {
    // Columns: a notch column, a bar, then holes (even i) between bars,
    // a bar and a notch column; rows: holes at odd j.
    let (columns, rows) = (2 * m + 3, 2 * m + 1);
    let hole = |i: usize, j: usize| j % 2 == 1 && i % 2 == 0 && (2..=2 * m).contains(&i);
    let notch = |i: usize, j: usize| j % 2 == 1 && (i == 0 || i == columns - 1);
    let decimal = |v: f64| (v * 1e6).round() / 1e6;
    let lines = |origin: f64, widths: Vec<f64>| -> Vec<f64> {
        let mut at = origin;
        let mut out = vec![decimal(at)];
        for w in widths {
            at += w;
            out.push(decimal(at));
        }
        out
    };
    let xs = lines(
        513.075989,
        (0..columns)
            .map(|i| match i {
                _ if hole(i, 1) => 2.5,
                _ if notch(i, 1) => 1.2,
                _ => 1.7,
            })
            .collect(),
    );
    let ys = lines(
        51.607433,
        (0..rows)
            .map(|j| if j % 2 == 1 { 2.5 } else { 1.7 })
            .collect(),
    );
    let zs: Vec<f64> = (0..=bands)
        .map(|l| decimal(24.001101 + 11.999799 * l as f64 / bands as f64))
        .collect();
    let mut b = Builder {
        double: true,
        ..Builder::default()
    };
    let mut ids = std::collections::HashMap::new();
    let mut at = |b: &mut Builder, i: usize, j: usize, l: usize| {
        *ids.entry((i, j, l)).or_insert_with(|| {
            b.pos.push([xs[i], ys[j], zs[l]]);
            (b.pos.len() - 1) as u32
        })
    };
    let solid = |i: isize, j: isize| {
        (0..columns as isize).contains(&i)
            && (0..rows as isize).contains(&j)
            && !hole(i as usize, j as usize)
            && !notch(i as usize, j as usize)
    };
    for i in 0..columns {
        for j in 0..rows {
            let (ii, jj) = (i as isize, j as isize);
            if !solid(ii, jj) {
                continue;
            }
            // Top (facing +z, counter-clockwise from above) and bottom.
            let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
            let top = corners.map(|(x, y)| at(&mut b, x, y, bands));
            let bottom = corners.map(|(x, y)| at(&mut b, x, y, 0));
            b.tris.push([top[0], top[1], top[2]]);
            b.tris.push([top[0], top[2], top[3]]);
            b.tris.push([bottom[0], bottom[2], bottom[1]]);
            b.tris.push([bottom[0], bottom[3], bottom[2]]);
            // A wall wherever the neighbour is empty: its cell edge from
            // `p` to `q`, counter-clockwise seen from outside the solid.
            let walls = [
                (solid(ii + 1, jj), (i + 1, j), (i + 1, j + 1)),
                (solid(ii, jj + 1), (i + 1, j + 1), (i, j + 1)),
                (solid(ii - 1, jj), (i, j + 1), (i, j)),
                (solid(ii, jj - 1), (i, j), (i + 1, j)),
            ];
            for (filled, p, q) in walls {
                if filled {
                    continue;
                }
                for l in 0..bands {
                    let [p0, q0, q1, p1] = [(p, l), (q, l), (q, l + 1), (p, l + 1)]
                        .map(|((x, y), l)| at(&mut b, x, y, l));
                    b.tris.push([p0, q0, q1]);
                    b.tris.push([p0, q1, p1]);
                }
            }
        }
    }
    b
}

/// [`plate`] with 8 x 8 holes and about `triangles` triangles (360 walls
/// of `2 bands` triangles each, 972 on the faces).
pub fn plate_of(triangles: usize) -> Builder {
    plate(8, (triangles.saturating_sub(972) / 720).max(1))
}

impl Builder {
    /// The mesh as `wmslice` holds it (exact `f64` of the `f32` values).
    pub fn to_mesh(&self) -> wmslice::Mesh {
        wmslice::Mesh::from_raw(self.pos.clone(), self.tris.clone())
    }
}
