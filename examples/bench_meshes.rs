//! Writes the benchmark meshes of `bench/compare` (see `bench/meshgen.rs`)
//! as binary STL with a small JSON description beside each:
//!
//! ```sh
//! cargo run --release --example bench_meshes -- OUT_DIR 200k 1m
//! ```
//!
//! Writes `torus_<size>.stl` and `steps_<size>.stl` (on one small binary
//! grid), and the classes with real coordinate patterns:
//! `torus0_<size>.stl` (centred at the origin, `f32` noise near zero),
//! `knot_<size>.obj` (six decimals), `steps64_<size>.obj` (`f64`,
//! turned: CAD-like) and `plate64_<size>.obj` (six decimals, walls
//! parallel to the axes: a perforated plate). Sizes: `200k` and `1m`
//! (about 200 000 and 1 000 000 triangles), or a number of triangles
//! (`50000`).

#[path = "../bench/meshgen.rs"]
#[allow(dead_code)] // the criterion benches use the rest
mod meshgen;

use std::path::Path;

fn parse_size(s: &str) -> Option<usize> {
    match s.to_ascii_lowercase().as_str() {
        "200k" => Some(200_000),
        "1m" => Some(1_000_000),
        other => other.parse().ok(),
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 {
        return Err(
            "usage: bench_meshes OUT_DIR SIZE... (SIZE: 200k, 1m or a triangle count)".into(),
        );
    }
    let dir = Path::new(&args[0]);
    std::fs::create_dir_all(dir)?;
    for label in &args[1..] {
        let target = parse_size(label).ok_or(format!("bad size {label}"))?;
        for (name, mesh, ext) in [
            ("torus", meshgen::torus_of(target), "stl"),
            ("steps", meshgen::steps_of(target), "stl"),
            ("torus0", meshgen::torus_origin_of(target), "stl"),
            ("knot", meshgen::knot_of(target), "obj"),
            ("steps64", meshgen::steps_f64_of(target), "obj"),
            ("plate64", meshgen::plate_of(target), "obj"),
        ] {
            let stem = format!("{name}_{}", label.to_ascii_lowercase());
            let path = dir.join(format!("{stem}.{ext}"));
            match (ext, name) {
                ("stl", _) => mesh.write_stl(&path)?,
                (_, "knot" | "plate64") => mesh.write_obj(&path, Some(6))?,
                _ => mesh.write_obj(&path, None)?,
            }
            let (lo, hi) = mesh.z_range();
            let meta = format!(
                "{{\"name\": \"{stem}\", \"file\": \"{stem}.{ext}\", \"triangles\": {}, \"vertices\": {}, \"zmin\": {:?}, \"zmax\": {:?}}}\n",
                mesh.tris.len(),
                mesh.pos.len(),
                lo,
                hi
            );
            std::fs::write(dir.join(format!("{stem}.json")), &meta)?;
            print!("{meta}");
        }
    }
    Ok(())
}
