//! Input: a mesh and a rational grid step `q`. Output: the mesh snapped to
//! the grid, stored as integer multiples of `q` (so every stored value is an
//! exact integer double), with vertices that land on one grid point welded.
//!
//! Snapping is the one explicit, reported rounding of coordinates (SPEC
//! section 2): each coordinate moves to the nearest multiple of `q` (ties
//! to even), by at most `q / 2`.

use crate::exact::level::shl;
use crate::exact::rational::{decompose, rat_from_f64, rat_to_f64, rat_to_string, Rat};
use crate::ids::VertexId;
use crate::mesh::io::ExactPositions;
use crate::mesh::weld::{weld_points, MAX_ELEMENTS};
use crate::mesh::Mesh;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{Signed, ToPrimitive, Zero};

/// The largest grid index that a double holds exactly.
pub const MAX_GRID_INDEX: i64 = 1 << 53;

/// Why snapping failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SnapError {
    /// The grid step is zero or negative.
    #[error("snap grid must be positive, got {0}")]
    NonPositive(String),
    /// A coordinate is not finite.
    #[error("vertex {0} has a non-finite coordinate")]
    NonFinite(VertexId),
    /// A coordinate is too far from zero for this grid.
    #[error(
        "vertex {vertex} is more than 2^53 grid steps of {} from the origin: choose a coarser grid",
        readable(q)
    )]
    OutOfRange {
        /// The vertex.
        vertex: VertexId,
        /// The grid, as `p/q`.
        q: String,
    },
    /// More vertices than ids.
    #[error("too many vertices to snap: more than {MAX_ELEMENTS}")]
    TooManyVertices,
    /// Every face collapsed on the grid (each repeats a vertex), whether or
    /// not collapsed faces are dropped: a grid about as coarse as the part
    /// (a mesh in metres on a grid meant for millimetres).
    #[error("snapping to the grid {} collapsed every one of the {faces} faces: the mesh spans {:.3e} x {:.3e} x {:.3e}; choose a grid much finer than the mesh", readable(q), .span[0], .span[1], .span[2])]
    CollapsedEverything {
        /// The grid, as `p/q`.
        q: String,
        /// The faces before snapping.
        faces: usize,
        /// The mesh's extent along x, y and z before snapping (rounded:
        /// for the message).
        span: [f64; 3],
    },
}

/// A grid's exact text for a message, or its nearest double when that
/// text is long (`1e-300` is `1/1000...` with 300 zeros); the JSON keeps
/// the exact text.
fn readable(q: &str) -> String {
    if q.len() <= 40 {
        return q.to_owned();
    }
    let (p, d) = q.split_once('/').unwrap_or((q, "1"));
    match (p.parse::<f64>(), d.parse::<f64>()) {
        (Ok(p), Ok(d)) if (p / d).is_normal() => format!("~{:e}", p / d),
        _ => format!("{}...", &q[..40]),
    }
}

impl SnapError {
    /// The mesh's defect this error reports, as `check --json` and the
    /// Python package's `InvalidMesh.defects` list it: its `kind` and the
    /// elements or grid it names; `None` when the fault is not the mesh's
    /// (a grid that is not positive, more vertices than ids).
    pub fn defect_json(&self) -> Option<serde_json::Value> {
        Some(match self {
            SnapError::NonPositive(_) | SnapError::TooManyVertices => return None,
            SnapError::NonFinite(v) => {
                serde_json::json!({"kind": "non_finite_coordinate", "vertex": v.0})
            }
            SnapError::OutOfRange { vertex, q } => {
                serde_json::json!({"kind": "snap_out_of_range", "vertex": vertex.0, "grid": q})
            }
            SnapError::CollapsedEverything { q, faces, span } => serde_json::json!(
                {"kind": "snap_collapsed_everything", "grid": q, "faces": faces, "span": span}
            ),
        })
    }
}

/// A snapped mesh and what snapping did.
#[derive(Debug, Clone)]
pub struct Snapped {
    /// The mesh in grid units: true coordinate = stored value * `unit`.
    pub mesh: Mesh,
    /// The grid step `q`.
    pub unit: Rat,
    /// Vertices whose position changed.
    pub moved: usize,
    /// The largest change of a single coordinate, exact.
    pub max_move: Rat,
    /// Vertices merged into another one that landed on the same point.
    pub merged: usize,
}

/// Nearest integer to `num / den` (`den > 0`), ties to even.
fn round_half_even(num: &BigInt, den: &BigInt) -> BigInt {
    let (q, rem): (BigInt, BigInt) = num.div_mod_floor(den);
    let twice: BigInt = rem * 2;
    match twice.cmp(den) {
        std::cmp::Ordering::Less => q,
        std::cmp::Ordering::Greater => q + 1,
        std::cmp::Ordering::Equal => {
            if q.is_even() {
                q
            } else {
                q + 1
            }
        }
    }
}

/// `x / q` rounded to the nearest integer `n` (ties to even), and the
/// move `|x - n q|`, in big rationals: any `x`, any `q > 0`.
fn index_rational(x: f64, q: &Rat) -> (BigInt, Rat) {
    index_of(&rat_from_f64(x), q)
}

/// As [`index_rational`], for any rational `x`. Computed on numerators
/// and denominators, with no greatest common divisor (the cost of big
/// rationals here): the move comes back unreduced, equal in value.
fn index_of(x: &Rat, q: &Rat) -> (BigInt, Rat) {
    // x / q = (xn qd) / (xd qn), qn > 0; |n q - x| = |n qn xd - xn qd| / (qd xd).
    let n = round_half_even(&(x.numer() * q.denom()), &(x.denom() * q.numer()));
    let delta = (&n * q.numer() * x.denom() - x.numer() * q.denom()).abs();
    (n, Rat::new_raw(delta, q.denom() * x.denom()))
}

/// As [`index_rational`] in `i128`, for `q = a / b` (`a`, `b > 0`): `n`
/// and the move as `t / d` times `q` (`0 <= t <= d / 2`), or `None` when
/// the products do not fit. With `x = m 2^e`, `x / q = m b 2^e / a`.
fn index_i128(x: f64, (a, b): (i128, i128)) -> Option<(i128, i128, i128)> {
    let Some((m, e)) = decompose(x) else {
        return Some((0, 0, 1));
    };
    let mb = i128::from(m).checked_mul(b)?;
    let (num, den) = if e >= 0 {
        (shl(mb, e.unsigned_abs())?, a)
    } else {
        (mb, shl(a, e.unsigned_abs())?)
    };
    let (floor, r) = if den & (den - 1) == 0 {
        // A power of two (every decimal or binary grid `1 / b` below a
        // coordinate's last bit): the floor is a shift, the remainder a
        // mask (two's complement: both exact for a negative `num`).
        (num >> den.trailing_zeros(), num & (den - 1))
    } else {
        // `i128` division is a library call. The remainder straight from
        // it: `num - floor * den` overflows when `num` is within `den` of
        // `i128::MIN` (found by the adversarial fuzz target).
        (num.div_euclid(den), num.rem_euclid(den))
    };
    let up = match r.cmp(&(den - r)) {
        std::cmp::Ordering::Less => false,
        std::cmp::Ordering::Greater => true,
        std::cmp::Ordering::Equal => floor & 1 != 0,
    };
    Some(if up {
        (floor.checked_add(1)?, den - r, den)
    } else {
        (floor, r, den)
    })
}

/// A grid index as the double that holds it exactly; `None` beyond 2^53
/// steps, where a double cannot (refused by name, not a tolerance).
fn grid_index(n: Option<i64>) -> Option<f64> {
    // |n| <= 2^53: exact as a double; +0.0 for zero. `unsigned_abs`: the
    // absolute value of `i64::MIN` (a vertex at -2^63 steps) overflows.
    n.filter(|n| n.unsigned_abs() <= MAX_GRID_INDEX.unsigned_abs())
        .map(|n| n as f64 + 0.0)
}

/// The largest move so far, exact, with its nearest double to skip the
/// exact comparison of a move that is clearly smaller.
struct LargestMove {
    exact: Rat,
    approx: f64,
}

impl LargestMove {
    /// Takes the move `t / d` times `q` (`q = a / b`, `q_f` its nearest
    /// double). Its double estimate `fl(fl(fl(t) / fl(d)) q_f)` has five
    /// correctly rounded steps (relative error below `6.01u`, `u = 2^-53`,
    /// while normal), and `approx` is within `u` of the largest: an
    /// estimate below `fl(approx (1 - 16u))` (both above `2^-1000`) is of
    /// a smaller move, as `(1 + u)^2 (1 - 16u) / (1 - 6.01u) < 1` (one `u`
    /// for `approx`, one for that product). Else the move is compared
    /// exactly. Only which move is reported depends on this, never a
    /// snapped position.
    fn offer_ratio(&mut self, t: i128, d: i128, (a, b): (i128, i128), q_f: f64) {
        const FLOOR: f64 = f64::from_bits((1023 - 1000) << 52);
        let estimate = t as f64 / d as f64 * q_f;
        let margin = 1.0 - f64::from_bits((1023 - 49) << 52);
        if estimate >= FLOOR && self.approx >= FLOOR && estimate < self.approx * margin {
            return;
        }
        self.offer(Rat::new(BigInt::from(t) * a, BigInt::from(d) * b));
    }

    fn offer(&mut self, delta: Rat) {
        if delta > self.exact {
            self.approx = rat_to_f64(&delta);
            self.exact = delta;
        }
    }
}

/// Snaps every coordinate to the nearest multiple of `q` and welds vertices
/// that coincide afterwards (exact equality). Faces keep their order.
/// Each coordinate is rounded in `i128` when `q`'s parts and the products
/// fit (every decimal grid and ordinary coordinates), else in big
/// rationals; the same result either way.
pub fn snap(mesh: &Mesh, q: &Rat) -> Result<Snapped, SnapError> {
    snap_exact(mesh, &ExactPositions::default(), q)
}

/// As [`snap`], where the vertices in `exact` are snapped from their exact
/// positions (a 3MF transform's image that is not a double), not from the
/// doubles the mesh holds for them.
pub fn snap_exact(mesh: &Mesh, exact: &ExactPositions, q: &Rat) -> Result<Snapped, SnapError> {
    if !q.is_positive() {
        return Err(SnapError::NonPositive(rat_to_string(q)));
    }
    let parts = q.numer().to_i128().zip(q.denom().to_i128());
    let q_f = rat_to_f64(q);
    let mut snapped: Vec<[f64; 3]> = Vec::with_capacity(mesh.num_vertices());
    let mut moved = 0;
    let mut largest = LargestMove {
        exact: Rat::zero(),
        approx: 0.0,
    };
    let mut exact = exact.iter().peekable();
    for (v, p) in mesh.positions.iter().enumerate() {
        let vid = VertexId::from_idx(v);
        let mut out = [0.0f64; 3];
        let mut changed = false;
        // A vertex with an exact position (not a double) is snapped from it.
        let given = exact.next_if(|(id, _)| *id == vid).map(|(_, x)| x);
        for k in 0..3 {
            if given.is_none() && !p[k].is_finite() {
                return Err(SnapError::NonFinite(vid));
            }
            let out_of_range = || SnapError::OutOfRange {
                vertex: vid,
                q: rat_to_string(q),
            };
            let fast = parts
                .filter(|_| given.is_none())
                .and_then(|ab| Some((ab, index_i128(p[k], ab)?)));
            let n64 = match fast {
                Some((ab, (n, t, d))) => {
                    if t != 0 {
                        changed = true;
                        largest.offer_ratio(t, d, ab, q_f);
                    }
                    i64::try_from(n).ok()
                }
                None => {
                    let (n, delta) = match given {
                        Some(x) => index_of(&x[k], q),
                        None => index_rational(p[k], q),
                    };
                    if !delta.is_zero() {
                        changed = true;
                        largest.offer(delta);
                    }
                    n.to_i64()
                }
            };
            out[k] = grid_index(n64).ok_or_else(out_of_range)?;
        }
        moved += changed as usize;
        snapped.push(out);
    }
    // Vertices on one grid point merged, in first-seen order (the weld's
    // prefetching table: a hash map waited for memory at every vertex).
    let (positions, remap) = weld_points(&snapped).map_err(|_| SnapError::TooManyVertices)?;
    drop(snapped);
    let merged = mesh.num_vertices() - positions.len();
    let faces = mesh
        .faces
        .iter()
        .map(|t| t.map(|v| remap.get(v.idx()).map_or(v, |&id| VertexId(id))))
        .collect();
    Ok(Snapped {
        mesh: Mesh { positions, faces },
        unit: q.clone(),
        moved,
        max_move: largest.exact.reduced(),
        merged,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::parse_rational;

    /// Messages name a grid by its exact text when it is short, else by
    /// its nearest double, marked `~` (a 300-digit denominator helps no
    /// one), else by the start of the text; the JSON keeps the text.
    #[test]
    fn a_long_grid_is_named_by_its_nearest_double() {
        let text = |g: &str| rat_to_string(&parse_rational(g).unwrap());
        assert_eq!(readable(&text("3/7")), "3/7");
        assert_eq!(readable(&text("1e-30")), format!("1/1{}", "0".repeat(30)));
        assert_eq!(readable(&text("1e-300")), "~1e-300");
        assert_eq!(readable(&text("2.5e300")), "~2.5e300");
        assert_eq!(
            readable(&text("1e-3000")),
            format!("1/1{}...", "0".repeat(37))
        );
        let e = SnapError::OutOfRange {
            vertex: VertexId(1),
            q: text("1e-300"),
        };
        assert!(e.to_string().contains("grid steps of ~1e-300 from"), "{e}");
        assert_eq!(e.defect_json().unwrap()["grid"], text("1e-300"));
    }

    /// Doubles across the whole range and the grids users pass.
    fn coordinate() -> impl proptest::strategy::Strategy<Value = f64> {
        use proptest::prelude::*;
        prop_oneof![
            any::<u64>()
                .prop_map(f64::from_bits)
                .prop_filter("finite", |v| v.is_finite()),
            any::<u32>()
                .prop_map(f32::from_bits)
                .prop_filter("finite", |v| v.is_finite())
                .prop_map(f64::from),
            (-100000i32..100000).prop_map(|k| f64::from(k) * 0.001),
            (any::<i32>(), -80i32..20).prop_map(|(m, e)| f64::from(m) * 2f64.powi(e)),
            // Near the ends of `i128` once scaled (with the coarse grids
            // below: indices up to 2^53).
            (any::<i64>(), 60i32..75).prop_map(|(m, e)| (m >> 11) as f64 * 2f64.powi(e)),
        ]
    }

    fn grid() -> impl proptest::strategy::Strategy<Value = Rat> {
        use proptest::prelude::*;
        prop_oneof![
            // Coarse grids with wide numerators, not powers of two.
            (1u64..1 << 40, 40u32..90)
                .prop_map(|(a, k)| Rat::from_integer((BigInt::from(2 * a + 1) << k) + 1)),
            (0u32..19).prop_map(|k| Rat::new(1.into(), BigInt::from(10u64).pow(k))),
            (0u32..200).prop_map(|k| Rat::new(1.into(), BigInt::from(2).pow(k))),
            (1u64..1 << 40, 1u64..1 << 40).prop_map(|(a, b)| Rat::new(a.into(), b.into())),
        ]
    }

    /// `x = -2^126` on the grid `q = (2^74 + 1) / 2`: in units of `1/2`,
    /// `x / q = -2^127 / (2^74 + 1)` rounds to `-2^53` (the last index a
    /// double holds), `floor(x / q) (2^74 + 1) = -2^127 - 2^53` is below
    /// `i128::MIN`, and the move is `2^52`. A debug build panicked on that
    /// product (found by the adversarial fuzz target, at `x = -2^126` on
    /// the grid 3/2); a release build wrapped, which gave the right
    /// remainder only because the remainder fits.
    #[test]
    fn a_remainder_at_the_end_of_i128_is_exact() {
        let x = -(2f64.powi(126));
        let a = (1i128 << 74) + 1;
        let (n, t, d) = index_i128(x, (a, 2)).expect("fits i128");
        assert_eq!(n, -(1i128 << 53));
        // The move, in grid steps: 2^52 / q = 2^53 / (2^74 + 1).
        assert_eq!(
            Rat::new(t.into(), d.into()),
            Rat::new((1i128 << 53).into(), a.into())
        );
        let q = Rat::new(a.into(), 2.into());
        let (nr, delta) = index_rational(x, &q);
        assert_eq!(BigInt::from(n), nr);
        assert_eq!(delta, Rat::from_integer((1i128 << 52).into()));
    }

    proptest::proptest! {
        /// The `i128` rounding gives the rational one's index and move.
        #[test]
        fn integer_rounding_is_the_rational_one(x in coordinate(), q in grid()) {
            // A grid too fine for i128 (2^-200) takes the rational path.
            let Some(parts) = q.numer().to_i128().zip(q.denom().to_i128()) else {
                return Ok(());
            };
            let (n, delta) = index_rational(x, &q);
            match index_i128(x, parts) {
                Some((ni, t, d)) => {
                    proptest::prop_assert_eq!(BigInt::from(ni), n);
                    proptest::prop_assert_eq!(Rat::new(t.into(), d.into()) * &q, delta);
                }
                // Coverage, not a tolerance: ordinary coordinates on an
                // ordinary grid must take the i128 path (the big path
                // would be correct, only slow).
                None => proptest::prop_assert!(
                    !(1e-6..=1e6).contains(&x.abs()) || parts.0.max(parts.1) >= 1 << 41,
                    "{} on {} took the rational path", x, q
                ),
            }
        }

        /// A whole mesh: positions and the largest move as the rational
        /// rounding of every coordinate gives them.
        #[test]
        fn snapping_is_the_rational_rounding(xs in proptest::collection::vec(coordinate(), 3..30), q in grid()) {
            let positions: Vec<[f64; 3]> = xs.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            let m = Mesh::from_raw(positions.clone(), vec![]);
            let want: Option<(Vec<[i64; 3]>, Rat)> = (|| {
                let mut largest = Rat::zero();
                let mut out = Vec::new();
                for p in &positions {
                    let mut o = [0i64; 3];
                    for k in 0..3 {
                        let (n, delta) = index_rational(p[k], &q);
                        o[k] = n.to_i64().filter(|n| n.unsigned_abs() <= MAX_GRID_INDEX.unsigned_abs())?;
                        largest = largest.max(delta);
                    }
                    out.push(o);
                }
                Some((out, largest))
            })();
            match (snap(&m, &q), want) {
                (Ok(s), Some((out, largest))) => {
                    proptest::prop_assert_eq!(s.max_move, largest);
                    for (v, o) in out.iter().enumerate() {
                        let id = s.mesh.positions.iter().position(|p| p.map(|c| c as i64) == *o);
                        proptest::prop_assert!(id.is_some(), "vertex {} not at its grid point", v);
                    }
                }
                (Err(SnapError::OutOfRange { .. }), None) => {}
                (got, want) => proptest::prop_assert!(false, "{:?} against {:?}", got.map(|s| s.max_move), want.map(|w| w.1)),
            }
        }
    }

    proptest::proptest! {
        /// A vertex given by its exact position snaps as the double with
        /// that value does (the `i128` path and the rational one agree),
        /// whichever vertices are given so.
        #[test]
        fn an_exact_position_equal_to_its_double_snaps_the_same(
            xs in proptest::collection::vec(coordinate(), 6..30),
            given in proptest::collection::vec(proptest::bool::ANY, 10),
            q in grid(),
        ) {
            let positions: Vec<[f64; 3]> = xs.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
            let m = Mesh::from_raw(positions.clone(), vec![]);
            let mut exact = ExactPositions::default();
            for (v, p) in positions.iter().enumerate() {
                if given[v] {
                    exact.push_for_test(VertexId::from_idx(v), p.map(rat_from_f64));
                }
            }
            match (snap(&m, &q), snap_exact(&m, &exact, &q)) {
                (Ok(a), Ok(b)) => {
                    proptest::prop_assert_eq!(a.mesh.positions, b.mesh.positions);
                    proptest::prop_assert_eq!(a.max_move, b.max_move);
                    proptest::prop_assert_eq!((a.moved, a.merged), (b.moved, b.merged));
                }
                (Err(a), Err(b)) => proptest::prop_assert_eq!(a, b),
                (a, b) => proptest::prop_assert!(false, "{:?} against {:?}", a.map(|s| s.moved), b.map(|s| s.moved)),
            }
        }
    }

    #[test]
    fn cad_plane_becomes_exact() {
        let m = Mesh::from_raw(vec![[0.6f32 as f64, 0.0, 1.0], [0.5, -0.25, 0.6]], vec![]);
        let q = parse_rational("1/10000").unwrap();
        let s = snap(&m, &q).unwrap();
        assert_eq!(s.mesh.positions[0], [6000.0, 0.0, 10000.0]);
        assert_eq!(s.mesh.positions[1], [5000.0, -2500.0, 6000.0]);
        assert_eq!(s.moved, 2);
        assert!(s.max_move <= &q / Rat::from_integer(2.into()));
        assert!(s.max_move.is_positive());
    }

    #[test]
    fn unwelded_corners_merge() {
        let a = 1.0f64;
        let m = Mesh::from_raw(
            vec![[a, 0.0, 0.0], [a.next_up(), 0.0, 0.0], [0.0, 0.0, 0.0]],
            vec![[0, 2, 1]],
        );
        let s = snap(&m, &parse_rational("0.001").unwrap()).unwrap();
        assert_eq!(s.merged, 1);
        assert_eq!(s.mesh.faces[0], [VertexId(0), VertexId(1), VertexId(0)]);
    }

    #[test]
    fn ties_go_to_even_and_range_is_checked() {
        assert_eq!(
            {
                let r = parse_rational("5/2").unwrap();
                round_half_even(r.numer(), r.denom())
            },
            BigInt::from(2)
        );
        assert_eq!(
            {
                let r = parse_rational("-5/2").unwrap();
                round_half_even(r.numer(), r.denom())
            },
            BigInt::from(-2)
        );
        assert_eq!(
            {
                let r = parse_rational("7/2").unwrap();
                round_half_even(r.numer(), r.denom())
            },
            BigInt::from(4)
        );
        let m = Mesh::from_raw(vec![[1e300, 0.0, 0.0]], vec![]);
        assert!(matches!(
            snap(&m, &parse_rational("1").unwrap()),
            Err(SnapError::OutOfRange { .. })
        ));
    }

    /// The bound is 2^53 steps either way, `i64::MIN` steps included: its
    /// absolute value overflows `i64`, and the `adversarial` fuzz target
    /// (a mesh scaled by 2^k, then snapped) found a debug build panicking
    /// there and a release build accepting the vertex.
    #[test]
    fn grid_indices_beyond_two_to_the_53_are_refused_at_either_sign() {
        let one = parse_rational("1").unwrap();
        for (x, fits) in [
            (-(2f64.powi(53)), true),
            (2f64.powi(53), true),
            (-(2f64.powi(53)) - 2.0, false),
            (2f64.powi(53) + 2.0, false),
            (-(2f64.powi(63)), false),
            (2f64.powi(63), false),
        ] {
            let m = Mesh::from_raw(vec![[x, 0.0, 0.0]], vec![]);
            let got = snap(&m, &one);
            assert_eq!(got.is_ok(), fits, "{x}: {got:?}");
            if !fits {
                assert!(matches!(got, Err(SnapError::OutOfRange { .. })), "{x}");
            }
        }
    }
}
