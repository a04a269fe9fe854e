//! Input: mesh positions and faces. Output: the exact signed volume
//! `1/6 sum det(v0, v1, v2)` as a rational, or only its sign when a
//! floating-point sum with a certified error bound decides it.
//!
//! Every finite double is `k * 2^e`; all coordinates are brought to the
//! smallest exponent present, so each determinant is an integer. When the
//! integers are small (the usual case: integer, dyadic or snapped meshes)
//! the sum runs in `i128`; otherwise in `BigInt`. Both are exact.

use super::dyadic::Dyadic;
use super::predicates::Sign;
use super::rational::{decompose, Rat};
use super::scale::{leading_exponent, times_pow2};
use crate::mesh::Mesh;
use num_bigint::BigInt;
use num_traits::Zero;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

/// The smallest exponent `e0` such that every coordinate is an integer
/// multiple of `2^e0`, and the largest such integer's bit length.
fn common_grid(mesh: &Mesh) -> (i32, u32) {
    let mut e0 = i32::MAX;
    let mut top = i32::MIN;
    for p in &mesh.positions {
        for &x in p {
            if let Some((m, e)) = decompose(x) {
                e0 = e0.min(e);
                top = top.max(e + 64 - m.unsigned_abs().leading_zeros() as i32);
            }
        }
    }
    if e0 == i32::MAX {
        return (0, 0);
    }
    (e0, (top - e0).max(0) as u32)
}

/// Exact signed volume of a mesh (positive for a closed, outward-oriented
/// one). Faces with out-of-range indices are skipped; non-finite
/// coordinates count as zero (validation rejects both before slicing).
pub fn signed_volume(mesh: &Mesh) -> Rat {
    let (e0, bits) = common_grid(mesh);
    let corners = |tri: &[crate::ids::VertexId; 3]| -> Option<[[f64; 3]; 3]> {
        let p = |k: usize| mesh.positions.get(tri[k].idx()).copied();
        Some([p(0)?, p(1)?, p(2)?])
    };
    // Integers below 2^31 on the mesh's grid: each det term < 2^93, six
    // terms and 2^31 faces stay below 2^127.
    if bits <= 31 && mesh.num_faces() < (1 << 31) {
        let to_i = |x: f64| -> i128 {
            match decompose(x) {
                Some((m, e)) => (m as i128) << (e - e0),
                None => 0,
            }
        };
        // Every partial sum is bounded as the whole one is: any order fits.
        let acc: i128 = mesh
            .faces
            .par_iter()
            .with_min_len(crate::par::MIN_LEN)
            .filter_map(corners)
            .map(|t| {
                let [a, b, c] = t.map(|p| p.map(to_i));
                det3_i128(a, b, c)
            })
            .sum();
        return Dyadic::new(BigInt::from(acc), 3 * e0).to_rat_times_pow2(0)
            / Rat::from_integer(6.into());
    }
    // Otherwise each face on its own grid (f32 meshes spread over many
    // binary exponents, but one face rarely does), its determinant summed
    // in i128 per exponent; a face or sum that does not fit goes to BigInt.
    // Faces in parallel; exact sums do not depend on the order.
    let sum = mesh
        .faces
        .par_chunks(1 << 12)
        .map(|chunk| {
            let mut sum = FaceSum::default();
            for t in chunk.iter().filter_map(corners) {
                sum.add_face(t);
            }
            sum
        })
        .reduce(FaceSum::default, FaceSum::merge);
    let mut wide = sum.wide;
    for (e, v) in sum.buckets {
        wide.add(&BigInt::from(v), e);
    }
    wide.to_rat_times_pow2(0) / Rat::from_integer(6.into())
}

/// The exact sign of the signed volume of some faces of a mesh (one shell:
/// positive when it faces outward). The faces' indices are in range.
pub fn volume_sign_of(mesh: &Mesh, faces: &[crate::ids::FaceId]) -> Sign {
    let mut sum = FaceSum::default();
    for &f in faces {
        sum.add_face(mesh.faces[f.idx()].map(|v| mesh.pos(v)));
    }
    let mut wide = sum.wide;
    for (e, v) in sum.buckets {
        wide.add(&BigInt::from(v), e);
    }
    wide.sign()
}

/// The sign of [`signed_volume`] when a floating-point sum decides it,
/// else `None` (then only the exact sum can tell).
///
/// The volume's sign does not change when every coordinate is multiplied
/// by one power of two `2^s`. When the largest magnitude `max|x|` lies
/// outside `[2^-100, 2^100]`, the coordinates are so multiplied, as they
/// are read, to bring it into `[1, 2)` (exactly: a scale up cannot lose a
/// bit, and a scale down is taken only as far as keeps the smallest
/// non-zero magnitude normal), so that meshes at extreme scales (`2^-540`,
/// `2^1000`) are decided as often as at scale 1. Below, `x` stands for the
/// scaled coordinates.
///
/// Each determinant `a . (b x c)` is computed in `f64` with five roundings
/// per product `a_i b_j c_k` (error at most `5u/(1-5u)` times the face's
/// permanent `sum |a_i b_j c_k|`, `u = 2^-53`), and the terms are summed in
/// any order (error at most `(n-1)u/(1-(n-1)u)` times the sum of their
/// magnitudes). Underflow: a product whose result is below `2^-1022` may
/// err by `2^-1075` absolutely besides its relative error (sums and
/// differences are exact there), so `b_j c_k` and `b_k c_j` add at most
/// `2^-1074` to `p - q`, which `a_i` multiplies, and `a_i (p - q)` adds
/// `2^-1075`: at most `(|a|_1 + 3/2) 2^-1074 <= (3 max|x| + 3/2) 2^-1074`
/// per face, half the term below (the other half covers the growth of
/// these terms through the later roundings, and the permanent's own
/// underflow, which enters the bound only times `6u`). The sum decides
/// when it exceeds the bound `6u P + (n+1)u A + (6 max|x| + 3)(n+1)
/// 2^-1074` times 17/16 (the spare covers the rounding of the bound itself
/// and the growth of the factors for `n < 2^40`; the underflow term is at
/// least `3 2^-1074`, so its own rounding loses at most a sixth of it).
/// Non-finite coordinates, an overflow, or a face with an index out of
/// range give `None`.
pub fn volume_sign_filter(mesh: &Mesh) -> Option<Sign> {
    // The unit roundoff of `f64`, for the certified bound (not a
    // tolerance: a sum the bound does not decide goes to the exact sum).
    const U: f64 = f64::EPSILON / 2.0;
    let n = mesh.num_faces();
    if n >= 1 << 40 {
        return None;
    }
    // The largest and the smallest non-zero magnitude.
    let (max_abs, min_abs) =
        mesh.positions
            .iter()
            .flatten()
            .try_fold((0.0f64, f64::INFINITY), |(hi, lo), &x| {
                let a = x.abs();
                x.is_finite()
                    .then(|| (hi.max(a), if a == 0.0 { lo } else { lo.min(a) }))
            })?;
    let s = filter_scale(max_abs, min_abs);
    let max_abs = times_pow2(max_abs, s);
    // Per face: its determinant, the determinant's magnitude, and its
    // permanent; `None` for a face with an index out of range.
    let face = |tri: &[crate::ids::VertexId; 3]| -> Option<[f64; 3]> {
        let p = |k: usize| {
            let v = mesh.positions.get(tri[k].idx()).copied()?;
            Some(if s == 0 {
                v
            } else {
                v.map(|x| times_pow2(x, s))
            })
        };
        let (a, b, c) = (p(0)?, p(1)?, p(2)?);
        let products = [
            [b[1] * c[2], b[2] * c[1]],
            [b[2] * c[0], b[0] * c[2]],
            [b[0] * c[1], b[1] * c[0]],
        ];
        let mut det = 0.0;
        let mut permanent = 0.0;
        for (ai, [p, q]) in a.iter().zip(products) {
            det += ai * (p - q);
            permanent += ai.abs() * (p.abs() + q.abs());
        }
        Some([det, det.abs(), permanent])
    };
    let add = |x: [f64; 3], y: [f64; 3]| Some([x[0] + y[0], x[1] + y[1], x[2] + y[2]]);
    let [sum, magnitudes, permanents] = mesh
        .faces
        .par_iter()
        .with_min_len(crate::par::MIN_LEN)
        .map(face)
        .try_reduce(|| [0.0; 3], add)?;
    let m = n as f64 + 1.0;
    let underflow = (6.0 * max_abs + 3.0) * m * f64::from_bits(1);
    let bound = (6.0 * U * permanents + m * U * magnitudes + underflow) * 1.0625;
    if !(sum.is_finite() && bound.is_finite()) {
        None
    } else if sum > bound {
        Some(Sign::Positive)
    } else if sum < -bound {
        Some(Sign::Negative)
    } else {
        None
    }
}

/// The power of two `s` the filter multiplies coordinates by: `0` when
/// the largest magnitude is within `[2^-100, 2^100]` (or every coordinate
/// is zero), else the `s` that brings it into `[1, 2)`, but never so far
/// down that the smallest non-zero magnitude leaves the normal range (a
/// scale down could then drop bits). Every product `x 2^s` is then exact.
fn filter_scale(max_abs: f64, min_abs: f64) -> i32 {
    const LOW: f64 = 1.0 / (1u128 << 100) as f64;
    const HIGH: f64 = (1u128 << 100) as f64;
    let Some(top) = leading_exponent(max_abs) else {
        return 0;
    };
    if (LOW..=HIGH).contains(&max_abs) {
        return 0;
    }
    let s = -top;
    if s > 0 {
        return s;
    }
    // The smallest magnitude times 2^s must stay at or above 2^-1022.
    let bottom = leading_exponent(min_abs).unwrap_or(top);
    s.max(-1022 - bottom).min(0)
}

/// A partial sum of face determinants: `i128` buckets per exponent, and
/// what did not fit.
#[derive(Default)]
struct FaceSum {
    buckets: FxHashMap<i32, i128>,
    wide: Dyadic,
}

impl FaceSum {
    /// Adds `det * 2^e`.
    fn add(&mut self, det: i128, e: i32) {
        let slot = self.buckets.entry(e).or_insert(0);
        match slot.checked_add(det) {
            Some(v) => *slot = v,
            None => {
                self.wide.add(&BigInt::from(*slot), e);
                *slot = det;
            }
        }
    }

    fn merge(mut self, other: FaceSum) -> FaceSum {
        for (e, v) in other.buckets {
            self.add(v, e);
        }
        self.wide.add_dyadic(&other.wide);
        self
    }

    /// Adds the determinant of one face, on the face's own grid: the
    /// smallest exponent of its nine coordinates.
    fn add_face(&mut self, t: [[f64; 3]; 3]) {
        // Zero coordinates: mantissa 0, no exponent.
        let mut m = [0i64; 9];
        let mut ex = [i32::MAX; 9];
        for (i, &x) in t.iter().flatten().enumerate() {
            if let Some((mi, ei)) = decompose(x) {
                (m[i], ex[i]) = (mi, ei);
            }
        }
        let e = ex.iter().copied().min().filter(|&e| e != i32::MAX);
        let Some(e) = e else { return };
        let mut k = [0i128; 9];
        let mut fits = true;
        for i in 0..9 {
            if m[i] == 0 {
                continue;
            }
            let shift = (ex[i] - e) as u32;
            // Below 2^40 each: products below 2^120, the determinant below 2^123.
            let ki = (shift < 40).then(|| i128::from(m[i]) << shift);
            match ki.filter(|ki| ki.unsigned_abs() < 1 << 40) {
                Some(ki) => k[i] = ki,
                None => {
                    fits = false;
                    break;
                }
            }
        }
        if fits {
            let row = |r: usize| [k[3 * r], k[3 * r + 1], k[3 * r + 2]];
            self.add(det3_i128(row(0), row(1), row(2)), 3 * e);
            return;
        }
        let big = |i: usize| {
            if m[i] == 0 {
                BigInt::zero()
            } else {
                BigInt::from(m[i]) << (ex[i] - e) as u32
            }
        };
        let [a, b, c] = [0, 1, 2].map(|r| [big(3 * r), big(3 * r + 1), big(3 * r + 2)]);
        let det = &a[0] * (&b[1] * &c[2] - &b[2] * &c[1]) - &a[1] * (&b[0] * &c[2] - &b[2] * &c[0])
            + &a[2] * (&b[0] * &c[1] - &b[1] * &c[0]);
        self.wide.add(&det, 3 * e);
    }
}

fn det3_i128(a: [i128; 3], b: [i128; 3], c: [i128; 3]) -> i128 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::rational::rat_from_f64;
    use num_traits::Signed;

    fn reference(mesh: &Mesh) -> Rat {
        let mut acc = Rat::zero();
        for tri in &mesh.faces {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[tri[k].idx()].map(rat_from_f64));
            acc += &a[0] * (&b[1] * &c[2] - &b[2] * &c[1])
                - &a[1] * (&b[0] * &c[2] - &b[2] * &c[0])
                + &a[2] * (&b[0] * &c[1] - &b[1] * &c[0]);
        }
        acc / Rat::from_integer(6.into())
    }

    fn tetra(s: f64, t: [f64; 3]) -> Mesh {
        let p = |x: f64, y: f64, z: f64| [x * s + t[0], y * s + t[1], z * s + t[2]];
        Mesh::from_raw(
            vec![p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.), p(0., 0., 1.)],
            vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
        )
    }

    #[test]
    fn decompose_is_exact() {
        assert_eq!(decompose(6.0), Some((3, 1)));
        assert_eq!(decompose(-0.375), Some((-3, -3)));
        assert_eq!(decompose(0.0), None);
        assert_eq!(decompose(f64::NAN), None);
        let (m, e) = decompose(0.1).unwrap();
        assert_eq!(
            rat_from_f64(0.1),
            Rat::from_integer(m.into()) * Rat::new(1.into(), BigInt::from(1) << (-e) as usize)
        );
    }

    #[test]
    fn the_filter_decides_ordinary_meshes() {
        // Every power-of-two scale a double holds: the filter scales the
        // coordinates back near 1 (exactly), so it still decides.
        for e in -1074..=1023 {
            let mut m = tetra(crate::exact::scale::times_pow2(1.0, e), [0.0; 3]);
            assert_eq!(volume_sign_filter(&m), Some(Sign::Positive), "2^{e}");
            m.faces.iter_mut().for_each(|t| t.swap(1, 2));
            assert_eq!(volume_sign_filter(&m), Some(Sign::Negative), "2^{e}");
        }
        for d in crate::datasets::all() {
            for e in [0, -540, 500, -1000, 1000] {
                let mut m = d.build();
                let s = crate::exact::scale::times_pow2(1.0, e);
                m.positions.iter_mut().flatten().for_each(|x| *x *= s);
                assert_eq!(
                    volume_sign_filter(&m),
                    Some(Sign::Positive),
                    "{} 2^{e}",
                    d.name
                );
            }
        }
        // The largest magnitude beside the smallest: no scale brings both
        // into range, the products overflow, and nothing is decided.
        let mut m = tetra(1e300, [0.0; 3]);
        m.positions[0][0] = f64::from_bits(1);
        assert_eq!(volume_sign_filter(&m), None);
    }

    #[test]
    fn tetrahedron_volume_both_paths() {
        // Small integers: i128 path.
        let m = tetra(6.0, [0.0, 0.0, 0.0]);
        assert_eq!(signed_volume(&m), Rat::from_integer(36.into()));
        // Odd decimals and a huge offset: BigInt path, still exact.
        for (s, t) in [
            (0.1, [1e9, 0.3, -7.7]),
            (3.0e-9, [1.0, 2.0, 3.0]),
            (1.5, [0.0; 3]),
        ] {
            let m = tetra(s, t);
            assert_eq!(signed_volume(&m), reference(&m));
        }
    }

    proptest::proptest! {
        /// The i128 path and the BigInt path both equal the plain rational
        /// reference, on tetrahedra with random dyadic or decimal
        /// coordinates (small ones take the i128 path, others the BigInt one).
        #[test]
        fn fast_and_wide_paths_equal_the_rational_reference(
            s in -1000i32..1000, t in proptest::array::uniform3(-1_000_000i64..1_000_000),
            scale_exp in -40i32..10, decimal in proptest::bool::ANY
        ) {
            let s = if s == 0 { 1.0 } else { f64::from(s) };
            let f = if decimal { 0.1 } else { 2f64.powi(scale_exp) };
            let m = tetra(s * f, t.map(|x| x as f64 * f));
            proptest::prop_assert_eq!(signed_volume(&m), reference(&m));
        }

        /// The filter's sign, when it gives one, is the exact volume's (so
        /// none on flat, zero-volume tetrahedra); far from the origin
        /// (cancellation), at subnormal and at huge scales it may give
        /// none, but never a wrong sign.
        #[test]
        fn the_filtered_sign_is_never_wrong(
            s in -1000i32..1000, t in proptest::array::uniform3(-1_000_000i64..1_000_000),
            scale_exp in -1100i32..1000, offset_exp in -60i32..60, flat in proptest::bool::ANY,
        ) {
            let s = if s == 0 { 1.0 } else { f64::from(s) };
            let f = 2f64.powi(scale_exp);
            let o = 2f64.powi(offset_exp);
            let mut m = tetra(s * f, t.map(|x| x as f64 * o));
            if flat {
                // The apex into the base's plane: volume exactly zero.
                let base = m.positions[0][2];
                m.positions[3][2] = base;
            }
            let exact = signed_volume(&m);
            let sign = if exact.is_zero() {
                Sign::Zero
            } else if exact.is_positive() {
                Sign::Positive
            } else {
                Sign::Negative
            };
            if let Some(filtered) = volume_sign_filter(&m) {
                proptest::prop_assert_eq!(filtered, sign);
            }
        }

        /// Meshes of f32 coordinates spread over many binary exponents
        /// take the per-face path (and the per-face BigInt fallback when a
        /// face itself spans too many bits): still exact.
        #[test]
        fn per_face_grids_equal_the_rational_reference(
            v in proptest::collection::vec(proptest::array::uniform3(-1.0e4f32..1.0e4), 4),
            tiny in proptest::bool::ANY,
        ) {
            let mut pos: Vec<[f64; 3]> = v.iter().map(|p| p.map(f64::from)).collect();
            if tiny {
                pos[0][0] = 1.0e-30;
            }
            let m = Mesh::from_raw(pos, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
            proptest::prop_assert_eq!(signed_volume(&m), reference(&m));
        }
    }
}
