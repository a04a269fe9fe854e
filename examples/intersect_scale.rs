//! Times the self-intersection test and the whole validation on bench
//! meshes (`bench/meshgen.rs`): the torus centred at the origin with `f32`
//! coordinates (`torus_f32`), the tilted torus scaled by `2^16` and rounded
//! to integers (`torus_int`, an integer grid), and the stepped CAD-like
//! part (`steps`, `f32`, faces in coordinate planes):
//!
//! ```sh
//! cargo run --release --example intersect_scale -- 1000000 2 9
//! ```
//!
//! Arguments: triangles (about), threads, runs (the median is printed),
//! optionally `torus_f32`, `torus_int` or `steps` for one mesh only (`all`
//! for every one), and any fifth argument to time the search alone.

#[path = "../bench/meshgen.rs"]
#[allow(dead_code)] // the STL writer is for the example
mod meshgen;

use std::time::{Duration, Instant};
use wmslice::mesh::intersect::face_pairs;
use wmslice::mesh::topology::Topology;
use wmslice::mesh::validate::{accept, validate};

/// User plus system CPU time of the process so far (zero off Linux).
fn cpu() -> Duration {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: getrusage writes only the struct passed.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) };
        let t = |v: libc::timeval| Duration::new(v.tv_sec as u64, v.tv_usec as u32 * 1000);
        t(u.ru_utime) + t(u.ru_stime)
    }
    #[cfg(not(target_os = "linux"))]
    Duration::ZERO
}

fn median(mut t: Vec<Duration>) -> f64 {
    t.sort();
    t[t.len() / 2].as_secs_f64() * 1e3
}

fn main() {
    let arg = |i: usize, d: usize| {
        std::env::args()
            .nth(i)
            .and_then(|s| s.parse().ok())
            .unwrap_or(d)
    };
    let (triangles, threads, runs) = (arg(1, 1_000_000), arg(2, 2), arg(3, 9));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    let only = std::env::args().nth(4);
    for name in ["torus_f32", "torus_int", "steps"] {
        if only.as_deref().is_some_and(|o| o != "all" && o != name) {
            continue;
        }
        let mesh = match name {
            "torus_f32" => meshgen::torus_origin_of(triangles).to_mesh(),
            "torus_int" => {
                let mut m = meshgen::torus_of(triangles).to_mesh();
                for p in &mut m.positions {
                    *p = p.map(|x| (x * 65536.0).round());
                }
                m
            }
            _ => meshgen::steps_of(triangles).to_mesh(),
        };
        let (topo, issues) = Topology::build(&mesh);
        if !issues.is_empty() {
            eprintln!("{name}: not a closed manifold");
            continue;
        }
        let time = |f: &(dyn Fn() -> usize + Sync)| -> (f64, f64, usize) {
            let (mut ts, mut cs) = (Vec::new(), Vec::new());
            let mut out = 0;
            for _ in 0..runs {
                let (t, c) = (Instant::now(), cpu());
                out = pool.install(f);
                ts.push(t.elapsed());
                cs.push(cpu() - c);
            }
            (median(ts), median(cs), out)
        };
        let (search, search_cpu, n) = time(&|| {
            let (edges, p) = face_pairs(&mesh, &topo, 1000, usize::MAX);
            edges.len() + p.pairs.len() + p.unlisted
        });
        if std::env::args().nth(5).is_some() {
            println!("{name}: search {search:.1} ({search_cpu:.1}) {n}");
            continue;
        }
        let (val, val_cpu, _) = time(&|| usize::from(validate(&mesh).is_accepted()));
        let (acc, acc_cpu, ok) = time(&|| usize::from(accept(&mesh).is_ok()));
        println!(
            "{name}: {} faces, {threads} threads, medians of {runs}, wall (CPU) ms: search (edges, fans, patches, tree) {search:.1} ({search_cpu:.1}), {n} found; validate {val:.1} ({val_cpu:.1}); accept {acc:.1} ({acc_cpu:.1}), accepted {ok}",
            mesh.num_faces()
        );
    }
}
