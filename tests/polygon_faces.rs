//! Polygon faces as OBJ, OFF and PLY files give them: a flat face that is
//! not convex (an L-shaped end, as Blender writes the ends of an extruded
//! L) was split into a fan from its first vertex, and when that vertex
//! does not see every other one the fan folded and validation refused a
//! sound part. Such a face is now split by ear clipping; a fan that does
//! not fold, and a face out of its plane, are read as before. The answers
//! (volumes, areas) are derived by hand or from the polygon itself.

use num_rational::BigRational;
use proptest::prelude::*;
use wmslice::exact::rational::{rat_from_f64, Rat};
use wmslice::levelset::total_area;
use wmslice::mesh::io::{load_bytes, LoadNote, MeshFormat};
use wmslice::mesh::prepare::prepare;
use wmslice::mesh::validate::validate;
use wmslice::{Mesh, Slicer};

/// A prism over the polygon `base` (counter-clockwise, integer corners)
/// from z = 0 to z = `h`, its ends written as one face each starting at
/// corner `start` and its sides as quads: `(vertices, faces)` with 0-based
/// ids, the bottom ring first.
fn prism(base: &[[i64; 2]], h: i64, start: usize) -> (Vec<[i64; 3]>, Vec<Vec<usize>>) {
    let n = base.len();
    let mut v: Vec<[i64; 3]> = base.iter().map(|&[x, y]| [x, y, 0]).collect();
    v.extend(base.iter().map(|&[x, y]| [x, y, h]));
    let top: Vec<usize> = (0..n).map(|k| n + (start + k) % n).collect();
    // The bottom faces down: the same ring, clockwise seen from above.
    let bottom: Vec<usize> = (0..n).map(|k| (start + n - k) % n).collect();
    let mut faces = vec![bottom, top];
    for k in 0..n {
        let j = (k + 1) % n;
        faces.push(vec![k, j, n + j, n + k]);
    }
    (v, faces)
}

fn obj(v: &[[i64; 3]], faces: &[Vec<usize>]) -> String {
    let mut s = String::from("# written as Blender writes n-gons\n");
    for p in v {
        s += &format!("v {} {} {}\n", p[0], p[1], p[2]);
    }
    for f in faces {
        let ids: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        s += &format!("f {}\n", ids.join(" "));
    }
    s
}

fn off(v: &[[i64; 3]], faces: &[Vec<usize>]) -> String {
    let mut s = format!("OFF\n{} {} 0\n", v.len(), faces.len());
    for p in v {
        s += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    for f in faces {
        let ids: Vec<String> = f.iter().map(usize::to_string).collect();
        s += &format!("{} {}\n", f.len(), ids.join(" "));
    }
    s
}

fn ply(v: &[[i64; 3]], faces: &[Vec<usize>]) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty double x\nproperty double y\n\
         property double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        v.len(),
        faces.len()
    );
    for p in v {
        s += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    for f in faces {
        let ids: Vec<String> = f.iter().map(usize::to_string).collect();
        s += &format!("{} {}\n", f.len(), ids.join(" "));
    }
    s
}

fn read(text: &str, format: MeshFormat) -> (Mesh, Vec<LoadNote>) {
    let (mesh, report) = load_bytes(text.as_bytes(), Some(format)).expect("reads");
    (mesh, report.notes)
}

fn ear_clipped(notes: &[LoadNote]) -> usize {
    notes
        .iter()
        .find_map(|n| match n {
            LoadNote::Triangulated { ear_clipped, .. } => Some(*ear_clipped),
            _ => None,
        })
        .unwrap_or(0)
}

/// The exact area of a counter-clockwise polygon (shoelace, in integers).
fn area(base: &[[i64; 2]]) -> Rat {
    let n = base.len();
    let twice: i64 = (0..n)
        .map(|k| {
            let ([x0, y0], [x1, y1]) = (base[k], base[(k + 1) % n]);
            x0 * y1 - x1 * y0
        })
        .sum();
    BigRational::new(twice.into(), 2.into())
}

/// Checks a prism read back, prepared as the command line prepares it
/// (a fan triangle of zero area, where a corner lies on the fan's
/// diagonal, flipped away: SPEC 1): accepted, volume `area(base) h`, and
/// its section at `h / 2` one outer loop of area `area(base)`.
fn assert_sound_prism(mesh: &Mesh, base: &[[i64; 2]], h: i64) -> Result<(), TestCaseError> {
    let prepared = prepare(mesh.clone(), None).expect("no snap");
    let mesh = &prepared.mesh;
    let report = validate(mesh);
    prop_assert!(report.is_accepted(), "{:?}", report.defects);
    let a = area(base);
    prop_assert_eq!(&report.volume, &(&a * Rat::from_integer(h.into())));
    let slicer = Slicer::new(mesh).expect("accepted");
    let ls = slicer
        .slice_at(&BigRational::new(h.into(), 2.into()))
        .expect("slices");
    prop_assert_eq!(ls.contours.len(), 1);
    prop_assert_eq!(total_area(&ls.contours), a);
    Ok(())
}

/// An L of area 3: its corner (2, 0), index 0, does not see (1, 2).
const L: [[i64; 2]; 6] = [[2, 0], [2, 1], [1, 1], [1, 2], [0, 2], [0, 0]];

#[test]
fn an_extruded_l_whose_ends_fan_into_folds_reads_as_a_sound_part_in_every_format() {
    let (v, faces) = prism(&L, 5, 0);
    for (text, format) in [
        (obj(&v, &faces), MeshFormat::Obj),
        (off(&v, &faces), MeshFormat::Off),
        (ply(&v, &faces), MeshFormat::PlyAscii),
    ] {
        let (mesh, notes) = read(&text, format);
        // 2 hexagons (4 triangles each) and 6 quads (2 each).
        assert_eq!(mesh.num_faces(), 20, "{format:?}");
        assert_eq!(ear_clipped(&notes), 2, "{format:?}: {notes:?}");
        let note = notes
            .iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("; ");
        assert!(
            note.contains("2 flat ones that are not convex by ear clipping"),
            "{note}"
        );
        // Volume 3 x 5 = 15, section area 3.
        assert_sound_prism(&mesh, &L, 5).unwrap();
    }
}

#[test]
fn ends_whose_fans_do_not_fold_read_as_their_fans() {
    // From the reflex corner (1, 1), index 2, the fan covers the L.
    let (v, faces) = prism(&L, 5, 2);
    let (mesh, notes) = read(&obj(&v, &faces), MeshFormat::Obj);
    assert_eq!(ear_clipped(&notes), 0);
    // The top end's fan, as the file lists it: (1,1) (1,2) (0,2) (0,0)
    // (2,0) (2,1), lifted to the top ring (ids + 6).
    let top = [8, 9, 10, 11, 6, 7];
    for k in 0..4 {
        let want = [top[0], top[k + 1], top[k + 2]];
        assert!(
            mesh.faces.iter().any(|f| f.map(|v| v.0) == want),
            "fan triangle {want:?} missing"
        );
    }
    assert_sound_prism(&mesh, &L, 5).unwrap();
}

#[test]
fn an_end_out_of_its_plane_keeps_its_fan_and_is_refused_for_its_fold() {
    // The top end's vertex (1, 2) lifted by 2^-40: the end is no longer
    // flat, so the reader does not choose a triangulation for it; its fan
    // folds and validation names it, as before.
    let (v, faces) = prism(&L, 5, 0);
    let mut text = obj(&v, &faces);
    text = text.replacen(
        "v 1 2 5\n",
        &format!("v 1 2 {:?}\n", 5.0 + 2f64.powi(-40)),
        1,
    );
    let (mesh, notes) = read(&text, MeshFormat::Obj);
    assert_eq!(ear_clipped(&notes), 1, "only the flat bottom end");
    assert_eq!(mesh.positions[9][2], 5.0 + 2f64.powi(-40));
    assert!(!validate(&mesh).is_accepted());
}

/// A star-shaped polygon: corners at increasing angles (`steps` of a
/// full turn of 64), each at its own integer radius from the origin,
/// rounded to integers (so collinear corners happen too).
fn star() -> impl Strategy<Value = Vec<[i64; 2]>> {
    prop::collection::btree_set(0u32..64, 4..16)
        .prop_flat_map(|angles| {
            let n = angles.len();
            (Just(angles), prop::collection::vec(3i64..40, n))
        })
        .prop_map(|(angles, radii)| {
            angles
                .iter()
                .zip(radii)
                .map(|(&a, r)| {
                    let t = f64::from(a) * std::f64::consts::TAU / 64.0;
                    [
                        (r as f64 * t.cos()).round() as i64,
                        (r as f64 * t.sin()).round() as i64,
                    ]
                })
                .collect::<Vec<[i64; 2]>>()
        })
        .prop_filter("a simple polygon turning counter-clockwise", |p| {
            simple_ccw(p)
        })
}

/// A comb: teeth 1 wide and 2 to 9 tall on a bar 1 high, counter-
/// clockwise from its corner (0, 0). Not star-shaped once two teeth are
/// tall: no corner sees every other one.
fn comb() -> impl Strategy<Value = Vec<[i64; 2]>> {
    prop::collection::vec(2i64..10, 2..8).prop_map(|h| {
        let n = h.len() as i64;
        let mut p = vec![[0, 0], [2 * n - 1, 0]];
        for i in (0..n).rev() {
            let t = h[i as usize];
            p.extend([[2 * i + 1, t], [2 * i, t]]);
            if i > 0 {
                p.extend([[2 * i, 1], [2 * i - 1, 1]]);
            }
        }
        p
    })
}

/// Whether the polygon is simple (no two edges meet but neighbours at
/// their shared corner, no repeated corner) and turns counter-clockwise,
/// decided exactly in integers.
fn simple_ccw(p: &[[i64; 2]]) -> bool {
    let n = p.len();
    let o = |a: [i64; 2], b: [i64; 2], c: [i64; 2]| {
        ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).signum()
    };
    let on = |a: [i64; 2], b: [i64; 2], c: [i64; 2]| {
        o(a, b, c) == 0
            && c[0] >= a[0].min(b[0])
            && c[0] <= a[0].max(b[0])
            && c[1] >= a[1].min(b[1])
            && c[1] <= a[1].max(b[1])
    };
    let meet = |a: [i64; 2], b: [i64; 2], c: [i64; 2], d: [i64; 2]| {
        let (d1, d2, d3, d4) = (o(c, d, a), o(c, d, b), o(a, b, c), o(a, b, d));
        (d1 * d2 < 0 && d3 * d4 < 0) || on(c, d, a) || on(c, d, b) || on(a, b, c) || on(a, b, d)
    };
    for i in 0..n {
        for j in i + 1..n {
            if p[i] == p[j] {
                return false;
            }
            let neighbours = j == i + 1 || (i == 0 && j == n - 1);
            if neighbours {
                continue;
            }
            if meet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]) {
                return false;
            }
        }
    }
    // A neighbour folding back onto its edge is a touch too.
    let folds_back = |k: usize| {
        let (a, b, c) = (p[k], p[(k + 1) % n], p[(k + 2) % n]);
        on(a, b, c) || on(b, c, a)
    };
    !(0..n).any(folds_back) && area(p) > Rat::from_integer(0.into())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Simple polygons (star-shaped, combs) extruded, their ends written
    /// from any corner: read as sound parts (exact volume and section area
    /// the polygon's own), whether the fans fold or not.
    #[test]
    fn a_prism_over_a_star_or_a_comb_reads_as_a_sound_part_from_any_corner(
        base in prop_oneof![star(), comb().prop_filter("simple", |p| simple_ccw(p))],
        start in 0usize..32,
        h in 1i64..9,
    ) {
        let start = start % base.len();
        let (v, faces) = prism(&base, h, start);
        let (mesh, _) = read(&obj(&v, &faces), MeshFormat::Obj);
        assert_sound_prism(&mesh, &base, h)?;
        // The bottom's corners are as written, exactly.
        for (k, &[x, y]) in base.iter().enumerate() {
            prop_assert_eq!(rat_from_f64(mesh.positions[k][0]), Rat::from_integer(x.into()));
            prop_assert_eq!(rat_from_f64(mesh.positions[k][1]), Rat::from_integer(y.into()));
        }
    }
}
