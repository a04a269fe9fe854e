//! Closed random meshes with small integer coordinates (ties everywhere),
//! shared by the property tests. The slab itself lives in the library
//! (`wmslice::datasets::slab`, also used by the fuzz targets); the proptest
//! strategy stays here.
#![allow(dead_code)]

use proptest::prelude::*;
pub use wmslice::datasets::slab::Slab;

/// Random slabs: up to 4 x 4 cells, heights in a small range.
pub fn slab() -> impl Strategy<Value = Slab> {
    (1usize..=4, 1usize..=4).prop_flat_map(|(nx, ny)| {
        let n = (nx + 1) * (ny + 1);
        (
            proptest::collection::vec(-2i32..=2, n),
            proptest::collection::vec(1i32..=3, n),
            proptest::collection::vec(any::<bool>(), nx * ny),
            0u8..3,
        )
            .prop_map(move |(bot, thick, diag, rot)| Slab {
                nx,
                ny,
                bot,
                thick,
                diag,
                rot,
            })
    })
}

/// A box `[0, 1]^2 x [0, z_top]`: corners, then outward counter-clockwise
/// faces.
pub fn unit_box(z_top: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let p = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, z_top],
        [1.0, 0.0, z_top],
        [1.0, 1.0, z_top],
        [0.0, 1.0, z_top],
    ];
    let f = vec![
        [0, 2, 1],
        [0, 3, 2],
        [4, 5, 6],
        [4, 6, 7],
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    (p, f)
}

/// The unit box as OFF text, its top at `z_top` (a CAD export's f32 `0.6`
/// is `0.60000002...`).
pub fn cad_cube_off(z_top: f64) -> String {
    let (p, f) = unit_box(z_top);
    let mut s = format!("OFF\n{} {} 0\n", p.len(), f.len());
    for [x, y, z] in p {
        s += &format!("{x:?} {y:?} {z:?}\n");
    }
    for [a, b, c] in f {
        s += &format!("3 {a} {b} {c}\n");
    }
    s
}

/// Runs the `wmslice` binary: exit code (-1 when killed), stdout, stderr.
pub fn wmslice(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_wmslice"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}
