//! Measures nesting where it is hardest: `k` square frames (each a closed
//! prism around a square hole, so two loops at mid-height) nested one
//! inside the next, `2k` loops `2k` deep, against the same frames side by
//! side (`2k` loops, depth at most 1). Times slicing one level of each mesh
//! (best of 5) and the nesting alone.
//!
//! `cargo run --release --example nest_scale -- 5000` (5000 frames, 10 000
//! loops; the default).

use std::time::{Duration, Instant};
use wmslice::exact::parse_rational;
use wmslice::ids::VertexId;
use wmslice::levelset::Loop;
use wmslice::{Mesh, Slicer};

/// Adds the frame between the squares of half-widths `inner < outer`
/// centred at `(cx, cy)`, from z = 0 to 1: 16 vertices, 32 outward faces.
fn frame(m: &mut Mesh, cx: f64, cy: f64, inner: f64, outer: f64) {
    let base = m.positions.len() as u32;
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    // Vertex index: ring r (0 outer, 1 inner), level z (0, 1), corner k.
    let v = |r: u32, z: u32, k: u32| VertexId(base + r * 8 + z * 4 + k % 4);
    for r in [outer, inner] {
        for z in [0.0, 1.0] {
            for (sx, sy) in corners {
                m.positions.push([cx + sx * r, cy + sy * r, z]);
            }
        }
    }
    for k in 0..4 {
        let (a, b) = (k, k + 1);
        // Outer wall, facing out; inner wall, facing the hole.
        m.faces.push([v(0, 0, a), v(0, 0, b), v(0, 1, b)]);
        m.faces.push([v(0, 0, a), v(0, 1, b), v(0, 1, a)]);
        m.faces.push([v(1, 0, b), v(1, 0, a), v(1, 1, a)]);
        m.faces.push([v(1, 0, b), v(1, 1, a), v(1, 1, b)]);
        // Top (up) and bottom (down) of the annulus.
        m.faces.push([v(0, 1, a), v(0, 1, b), v(1, 1, b)]);
        m.faces.push([v(0, 1, a), v(1, 1, b), v(1, 1, a)]);
        m.faces.push([v(0, 0, b), v(0, 0, a), v(1, 0, a)]);
        m.faces.push([v(0, 0, b), v(1, 0, a), v(1, 0, b)]);
    }
}

fn best_of<T>(runs: usize, mut f: impl FnMut() -> T) -> (Duration, T) {
    let mut best = Duration::MAX;
    let mut out = None;
    for _ in 0..runs {
        let t = Instant::now();
        let r = f();
        best = best.min(t.elapsed());
        out = Some(r);
    }
    (best, out.expect("at least one run"))
}

fn measure(name: &str, mesh: &Mesh) -> Duration {
    let slicer = Slicer::new(mesh).expect("frames are valid");
    let mid = parse_rational("1/2").expect("a level");
    let (t, ls) = best_of(5, || slicer.slice_at(&mid).expect("slices"));
    let depth = |l: &Loop| {
        let mut d = 0;
        let mut p = l.parent;
        while let Some(i) = p {
            d += 1;
            p = ls.contours[i].parent;
        }
        d
    };
    let deepest = ls.contours.iter().map(depth).max().unwrap_or(0);
    println!(
        "{name:>12}: {} faces, {} loops, deepest nesting {deepest}: slicing one level {:.1} ms",
        mesh.num_faces(),
        ls.contours.len(),
        t.as_secs_f64() * 1e3
    );
    t
}

fn main() {
    let k: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5000);
    let mut nested = Mesh::default();
    for i in 0..k {
        let r = 2.0 * i as f64;
        frame(&mut nested, 0.0, 0.0, r + 1.0, r + 2.0);
    }
    let side = (k as f64).sqrt().ceil() as usize;
    let mut apart = Mesh::default();
    for i in 0..k {
        let (x, y) = ((i % side) as f64 * 5.0, (i / side) as f64 * 5.0);
        frame(&mut apart, x, y, 1.0, 2.0);
    }
    let a = measure("side by side", &apart);
    let n = measure("nested", &nested);
    println!(
        "nested / side by side: {:.2}x",
        n.as_secs_f64() / a.as_secs_f64()
    );
}
