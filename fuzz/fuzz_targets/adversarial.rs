//! Input: arbitrary bytes -> a closed slab (`Slab::split_bytes`) made
//! adversarial as real files are: slivers (a vertex on an edge, its zero
//! area face in or out of a slicing plane), a second copy of the body
//! overlapping, touching or apart, coordinates rounded to `f32`, and the
//! whole mesh scaled by `2^k` for `k` across the double range, or snapped
//! to a coarse grid (which collapses faces and folds slivers); prepared as
//! the CLI prepares a mesh, welded or not (`--weld`: a touching copy's
//! corners merge with the body's), collapsed faces refused or dropped
//! (`--drop-collapsed`).
//! Output: nothing; panics on a bug. The mesh must be refused by name
//! (degenerate faces repaired first, as the CLI does), or sliced at every
//! vertex height and between with every invariant of SPEC section 7
//! (`check_level_invariants`), and its critical values
//! (`critical::analyze`) must equal the slow path's (the full level set
//! at every vertex height, `critical::brute_force`), and the slicer must
//! agree with its z- and x-mirrors, with itself renumbered, turned a
//! quarter about z, moved and scaled, and with the regular levels beside
//! each vertex height
//! (`datasets::cross_check`). An internal error on an accepted mesh is
//! the failure this target exists to find.
#![no_main]

use libfuzzer_sys::fuzz_target;
use wmslice::critical::{analyze, brute_force};
use wmslice::datasets::cross_check::{
    check_all_neighbours, check_mirror, check_transformed, check_x_mirror,
};
use wmslice::datasets::slab::{heights_and_midpoints, Slab};
use wmslice::exact::predicates::is_degenerate_triangle;
use wmslice::exact::rational::Rat;
use wmslice::ids::VertexId;
use wmslice::levelset::check::check_level_invariants;
use wmslice::levelset::SliceError;
use wmslice::mesh::prepare::{prepare_with, Repairs};
use wmslice::Mesh;

/// Replaces face `f = (a, b, c)` by `(a, m, c)`, `(m, b, c)` and the sliver
/// `(a, b, m)` with `m` strictly inside `ab` (the exact midpoint, when it
/// is a double): still closed and oriented.
fn add_sliver(mesh: &mut Mesh, f: usize, corner: usize) {
    let t = mesh.faces[f];
    let (a, b, c) = (t[corner], t[(corner + 1) % 3], t[(corner + 2) % 3]);
    let (pa, pb) = (mesh.pos(a), mesh.pos(b));
    let mid = [0, 1, 2].map(|k| pa[k] / 2.0 + pb[k] / 2.0);
    // Scaling may have made coordinates infinite (validation refuses them
    // later); the exact predicates take finite ones only.
    if [pa, pb, mid].iter().flatten().any(|v| !v.is_finite()) {
        return;
    }
    let inside = is_degenerate_triangle(pa, pb, mid) && mid != pa && mid != pb;
    if !inside {
        return;
    }
    let m = VertexId(mesh.positions.len() as u32);
    mesh.positions.push(mid);
    mesh.faces[f] = [a, m, c];
    mesh.faces.push([m, b, c]);
    mesh.faces.push([a, b, m]);
}

/// Adds a translated copy of the mesh (its own vertex ids).
fn add_copy(mesh: &mut Mesh, shift: [f64; 3]) {
    let n = mesh.positions.len() as u32;
    let pos: Vec<[f64; 3]> = mesh
        .positions
        .iter()
        .map(|p| [0, 1, 2].map(|k| p[k] + shift[k]))
        .collect();
    let faces: Vec<[VertexId; 3]> = mesh
        .faces
        .iter()
        .map(|t| t.map(|v| VertexId(v.0 + n)))
        .collect();
    mesh.positions.extend(pos);
    mesh.faces.extend(faces);
}

/// The adversarial mesh, the snap grid when one was asked for, and the
/// repairs asked for (welding the copies' touching corners; faces that
/// repeat a vertex dropped).
fn adversarial(data: &[u8]) -> (Mesh, Option<Rat>, Repairs) {
    let (slab, rest) = Slab::split_bytes(data);
    let mut mesh = slab.mesh();
    let mut snap = None;
    let mut ops = rest.chunks_exact(3);
    for op in ops.by_ref().take(6) {
        if op[0] >= 240 {
            // A grid of 1/64 to 3 units (the slab's steps are whole
            // units): corners merge, faces collapse, slivers fold.
            let step = Rat::new((1 + op[1] % 3).into(), (1u32 << (op[2] % 7)).into());
            snap = Some(step);
            continue;
        }
        match op[0] % 4 {
            0 => {
                let f = usize::from(op[1]) % mesh.num_faces();
                add_sliver(&mut mesh, f, usize::from(op[2]) % 3);
            }
            1 => {
                // Overlapping (half steps), touching (whole steps) or apart.
                let s = |b: u8| f64::from(i32::from(b % 9) - 4) / 2.0;
                add_copy(&mut mesh, [s(op[1]), s(op[2]), s(op[1] / 9)]);
            }
            2 => {
                // As a CAD tool stores it: rounded to f32 after a shear.
                let k = f64::from(op[1]) / 7.0;
                for p in &mut mesh.positions {
                    p[0] = f64::from((p[0] + k * p[2]) as f32);
                }
            }
            _ => {
                let k = i32::from(i16::from_le_bytes([op[1], op[2]])) % 1000;
                for p in &mut mesh.positions {
                    *p = p.map(|v| v * 2f64.powi(k));
                }
            }
        }
    }
    let repairs = Repairs::from_flags(rest.len() % 4 >= 2, rest.len() % 2 == 1);
    (mesh, snap, repairs)
}

fuzz_target!(|data: &[u8]| {
    let (mesh, snap, repairs) = adversarial(data);
    // Welded or not, snapped, the collapsed faces dropped or kept,
    // degenerate faces
    // flipped away: as the CLI prepares a mesh. A grid the coordinates
    // are too far out for is refused by name (a typed error).
    let Ok(prepared) = prepare_with(mesh, snap.as_ref(), repairs) else {
        return;
    };
    let mesh = prepared.mesh;
    let slicer = match wmslice::Slicer::new(&mesh) {
        Ok(s) => s,
        Err(SliceError::InvalidMesh(report)) => {
            // Refused by name: at least one blocking defect listed.
            assert!(report.errors().next().is_some(), "refused without a defect");
            return;
        }
        Err(e) => panic!("validation failed without a report: {e}"),
    };
    let levels = heights_and_midpoints(&mesh);
    for c in levels.iter().take(40) {
        let ls = match slicer.slice_at(c) {
            Ok(ls) => ls,
            Err(e) => panic!("internal error on an accepted mesh at {c}: {e}\n{mesh:?}"),
        };
        if let Err(e) = check_level_invariants(&mesh, slicer.topology(), &ls) {
            panic!("invariant violated at {c}: {e}\n{mesh:?}");
        }
    }
    let report = match analyze(&slicer) {
        Ok(r) => r,
        Err(e) => panic!("critical values of an accepted mesh: {e}\n{mesh:?}"),
    };
    match brute_force::classify_all(&slicer) {
        Ok(slow) => assert!(
            report.levels == slow,
            "critical values differ from the slow path\n{mesh:?}"
        ),
        Err(e) => panic!("internal error on an accepted mesh (slow path): {e}\n{mesh:?}"),
    }
    // The slicer against itself: its z- and x-mirrors, a renumbering of its
    // vertices and faces, the mesh turned a quarter about z, moved as far
    // as its coordinates stay exact and scaled to both ends of the double
    // range, and the regular levels beside each vertex height
    // (`datasets::cross_check`).
    let some = &levels[..levels.len().min(12)];
    if let Err(e) = check_mirror(&mesh, some)
        .and_then(|()| check_x_mirror(&mesh, some))
        .and_then(|()| check_transformed(&slicer, some).map(|_| ()))
        .and_then(|()| check_all_neighbours(&slicer, some))
    {
        panic!("{e}\n{mesh:?}");
    }
});
