//! Input: a layer height, optional first and last planes, explicit levels,
//! and the mesh's height range. Output: the exact, ascending, distinct list
//! of levels to slice.
//!
//! Uniform layers are `Z0 + k H` computed exactly (`0.2` is `1/5`), so layer
//! 1000 is exactly where it should be: no drift. The default first plane is
//! mid-layer, `z_min + H / 2` (as PrusaSlicer does); the default last plane
//! is the highest `Z0 + k H` not above `z_max`.

use crate::exact::point::gcd_u128;
use crate::exact::rational::{rat_from_f64, rat_to_string, rat_to_string_with_nearest, Rat};
use crate::mesh::Mesh;
use num_bigint::BigInt;
use num_integer::Integer;
use num_traits::{One, Pow, Signed, ToPrimitive, Zero};

/// The largest number of levels one plan may hold.
pub const MAX_LEVELS: usize = 10_000_000;

/// Uniform layers.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerPlan {
    /// Layer height `H > 0`.
    pub height: Rat,
    /// First plane `Z0` (default `z_min + H / 2`).
    pub first: Option<Rat>,
    /// Last plane bound `Z1` (default `z_max`): planes `Z0 + k H <= Z1`.
    pub last: Option<Rat>,
}

/// Why a plan is refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PlanError {
    /// The layer height is zero or negative.
    #[error("layer height must be positive, got {0}")]
    NonPositiveHeight(String),
    /// Too many levels.
    #[error("the plan has {0} levels, more than the limit of {MAX_LEVELS}")]
    TooMany(String),
    /// Nothing to slice.
    #[error("no levels: give --at Z, --levels-file FILE or --layer-height H")]
    Empty,
    /// Uniform layers were asked for, and none lies in their range (a part
    /// thinner than half a layer, or a mesh snapping flattened), and no
    /// explicit level either. The heights are exact, with their nearest
    /// doubles.
    #[error(
        "no levels: the first plane of the layer height {height} is z = {first}, above the last bound z = {last} (the mesh spans z {lo} to {hi}): choose a smaller layer height, or give the planes (--first, --at, --levels-file)"
    )]
    NoPlaneInRange {
        /// The layer height.
        height: String,
        /// The first plane `Z0`.
        first: String,
        /// The last bound `Z1`.
        last: String,
        /// The mesh's lowest height.
        lo: String,
        /// The mesh's highest height.
        hi: String,
    },
}

/// An exact height for a message: `p/q (~nearest double)`, or the integer.
fn shown(r: &Rat) -> String {
    if r.is_integer() {
        rat_to_string(r)
    } else {
        rat_to_string_with_nearest(r)
    }
}

/// The exact height range of a mesh's stored vertices (used or not) in true
/// units (`unit` is the snap grid, else 1): the `z_range` of
/// [`plan_levels`]. Non-finite heights are skipped (validation refuses
/// them); a mesh without a finite height gives `(0, 0)`.
pub fn height_range(mesh: &Mesh, unit: &Rat) -> (Rat, Rat) {
    let zs = mesh.positions.iter().map(|p| p[2]);
    let lo = zs.clone().fold(f64::INFINITY, f64::min);
    let hi = zs.fold(f64::NEG_INFINITY, f64::max);
    (rat_from_f64(lo) * unit, rat_from_f64(hi) * unit)
}

/// The levels of a plan: uniform layers (if any) merged with `explicit`,
/// ascending and distinct. `z_range` is the mesh's exact height range.
pub fn plan_levels(
    uniform: Option<&LayerPlan>,
    explicit: &[Rat],
    z_range: (&Rat, &Rat),
) -> Result<Vec<Rat>, PlanError> {
    let mut levels: Vec<Rat> = explicit.to_vec();
    let mut empty_range = None;
    if let Some(p) = uniform {
        if !p.height.is_positive() {
            return Err(PlanError::NonPositiveHeight(rat_to_string(&p.height)));
        }
        let two = Rat::from_integer(2.into());
        let first = p
            .first
            .clone()
            .unwrap_or_else(|| z_range.0 + &p.height / two);
        let last = p.last.clone().unwrap_or_else(|| z_range.1.clone());
        if first <= last {
            let count = ((&last - &first) / &p.height).floor() + Rat::from_integer(1.into());
            let n = count
                .to_integer()
                .to_usize()
                .filter(|&n| n + levels.len() <= MAX_LEVELS)
                .ok_or_else(|| PlanError::TooMany(count.to_integer().to_string()))?;
            levels.reserve(n);
            if !uniform_in_i128(&first, &p.height, n, &mut levels) {
                uniform_big(&first, &p.height, n, &mut levels);
            }
        } else {
            empty_range = Some(PlanError::NoPlaneInRange {
                height: shown(&p.height),
                first: shown(&first),
                last: shown(&last),
                lo: shown(z_range.0),
                hi: shown(z_range.1),
            });
        }
    }
    // Uniform levels alone are ascending and distinct already.
    if !explicit.is_empty() {
        levels.sort_unstable();
        levels.dedup();
    }
    if levels.is_empty() {
        return Err(empty_range.unwrap_or(PlanError::Empty));
    }
    Ok(levels)
}

/// Pushes `first + k height` for `k < n` onto `levels` (in lowest terms,
/// as rational arithmetic gives them) computed in `i128` over the common
/// denominator `D`: `(a + k b) / D`, one gcd per level. Returns false,
/// pushing nothing, when the numbers do not fit.
fn uniform_in_i128(first: &Rat, height: &Rat, n: usize, levels: &mut Vec<Rat>) -> bool {
    let parts = |r: &Rat| r.numer().to_i128().zip(r.denom().to_i128());
    let (Some((fp, fq)), Some((hp, hq))) = (parts(first), parts(height)) else {
        return false;
    };
    let g = gcd_u128(fq.unsigned_abs(), hq.unsigned_abs()) as i128;
    let ints = || -> Option<(i128, i128, i128)> {
        let d = (fq / g).checked_mul(hq)?;
        let a = fp.checked_mul(d / fq)?;
        let b = hp.checked_mul(d / hq)?;
        // The last numerator fits, so every one before it does (b > 0).
        a.checked_add(b.checked_mul(i128::try_from(n).ok()?)?)?;
        Some((a, b, d))
    };
    let Some((a, b, d)) = ints() else {
        return false;
    };
    let mut num = a;
    for _ in 0..n {
        let g = gcd_u128(num.unsigned_abs(), d.unsigned_abs()) as i128;
        levels.push(Rat::new_raw((num / g).into(), (d / g).into()));
        num += b;
    }
    true
}

/// [`uniform_in_i128`] in big integers: `(a + k b) / D` over the common
/// denominator, one reduction per level (the rational sum and product
/// would take five gcds, each as long as the numbers' bit length); for a
/// decimal `D` without a gcd at all ([`DecimalDenominator`]).
fn uniform_big(first: &Rat, height: &Rat, n: usize, levels: &mut Vec<Rat>) {
    let d = first.denom().lcm(height.denom());
    let a = first.numer() * (&d / first.denom());
    let b = height.numer() * (&d / height.denom());
    let decimal = DecimalDenominator::of(&d);
    let mut num = a;
    for _ in 0..n {
        levels.push(match &decimal {
            Some(dec) => dec.reduce(num.clone()),
            None => Rat::new(num.clone(), d.clone()),
        });
        num += &b;
    }
}

/// A denominator `2^twos 5^fives` (every decimal level's): `n / D` is put
/// in lowest terms by taking out the twos `n` has (its trailing zeros) and
/// the fives (dividing by five while it divides), no gcd.
struct DecimalDenominator {
    d: BigInt,
    twos: u64,
    fives: u64,
}

impl DecimalDenominator {
    /// `Some` when `d > 0` has no prime factor but 2 and 5.
    fn of(d: &BigInt) -> Option<Self> {
        let twos = d.trailing_zeros()?;
        let (rest, fives) = take_fives(d >> twos, u64::MAX);
        if !rest.is_one() {
            return None;
        }
        Some(DecimalDenominator {
            d: d.clone(),
            twos,
            fives,
        })
    }

    /// `n / D` in lowest terms; equal to `Rat::new(n, D)`.
    fn reduce(&self, n: BigInt) -> Rat {
        let Some(tz) = n.trailing_zeros() else {
            return Rat::zero();
        };
        let twos = tz.min(self.twos);
        let (n, fives) = take_fives(n >> twos, self.fives);
        Rat::new_raw(n, (&self.d >> twos) / BigInt::from(5).pow(fives as u32))
    }
}

/// `n` divided by five as often as it divides, at most `most` times, and
/// how many times (`n != 0`).
fn take_fives(mut n: BigInt, most: u64) -> (BigInt, u64) {
    let five = BigInt::from(5);
    let mut fives = 0;
    while fives < most {
        let (q, r) = n.div_rem(&five);
        if !r.is_zero() {
            break;
        }
        (n, fives) = (q, fives + 1);
    }
    (n, fives)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::parse_rational;

    fn r(s: &str) -> Rat {
        parse_rational(s).unwrap()
    }

    #[test]
    fn uniform_layers_are_exact_and_mid_layer_by_default() {
        let p = LayerPlan {
            height: r("0.2"),
            first: None,
            last: None,
        };
        let v = plan_levels(Some(&p), &[], (&r("0"), &r("200"))).unwrap();
        assert_eq!(v.len(), 1000);
        assert_eq!(v[0], r("0.1"));
        // No drift: layer 999 is exactly 0.1 + 999 * 0.2.
        assert_eq!(v[999], r("199.9"));
    }

    proptest::proptest! {
        /// The integer path gives the rational arithmetic's levels, in
        /// lowest terms.
        #[test]
        fn integer_levels_equal_rational_ones(fp in -(1i64 << 62)..(1i64 << 62), fe in 0u32..70, hp in 1i64..100_000, hd in 0u32..12) {
            let first = Rat::new(fp.into(), num_bigint::BigInt::from(1) << fe);
            let height = Rat::new(hp.into(), num_traits::pow(num_bigint::BigInt::from(10), hd as usize));
            let mut fast = Vec::new();
            if uniform_in_i128(&first, &height, 50, &mut fast) {
                let slow: Vec<Rat> = (0..50).map(|k| &first + &height * Rat::from_integer(k.into())).collect();
                for (f, s) in fast.iter().zip(&slow) {
                    proptest::prop_assert_eq!(f.numer(), s.numer());
                    proptest::prop_assert_eq!(f.denom(), s.denom());
                }
                proptest::prop_assert_eq!(fast.len(), 50);
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::test_runner::Config::with_cases(64))]
        /// Levels past `i128` (a mesh scaled to `1e-300` takes 300-digit
        /// decimal layer heights) equal the rational arithmetic's exactly,
        /// part for part in lowest terms: decimal denominators (reduced
        /// without a gcd) and others.
        #[test]
        fn big_levels_equal_rational_ones(
            fp in proptest::num::i64::ANY, fe in 0u32..400, hp in 1i64..i64::MAX, he in 0u32..400,
            odd in proptest::sample::select(vec![1u32, 3, 77]), ten in proptest::bool::ANY
        ) {
            let base = |e: u32| {
                let b = if ten { 10 } else { 2 };
                num_traits::pow(BigInt::from(b), e as usize) * odd
            };
            let first = Rat::new(fp.into(), base(fe));
            let height = Rat::new(hp.into(), num_traits::pow(BigInt::from(10), he as usize));
            let mut fast = Vec::new();
            uniform_big(&first, &height, 12, &mut fast);
            proptest::prop_assert_eq!(fast.len(), 12);
            for (k, f) in fast.iter().enumerate() {
                let slow = &first + &height * Rat::from_integer(k.into());
                proptest::prop_assert_eq!((f.numer(), f.denom()), (slow.numer(), slow.denom()));
            }
        }
    }

    #[test]
    fn decimal_denominators_are_told_apart() {
        let d = |v: u64| DecimalDenominator::of(&BigInt::from(v)).map(|d| (d.twos, d.fives));
        assert_eq!(d(1), Some((0, 0)));
        assert_eq!(d(1000), Some((3, 3)));
        assert_eq!(d(2 * 5 * 5 * 5), Some((1, 3)));
        assert_eq!(d(3), None);
        assert_eq!(d(30), None);
        assert_eq!(d(5 * 7), None);
    }

    #[test]
    fn explicit_levels_merge_sorted_and_distinct() {
        let p = LayerPlan {
            height: r("1"),
            first: Some(r("0")),
            last: Some(r("2")),
        };
        let v = plan_levels(Some(&p), &[r("1"), r("1/2")], (&r("0"), &r("5"))).unwrap();
        assert_eq!(v, vec![r("0"), r("1/2"), r("1"), r("2")]);
    }

    #[test]
    fn bad_plans_are_typed_errors() {
        let zero = LayerPlan {
            height: r("0"),
            first: None,
            last: None,
        };
        assert!(matches!(
            plan_levels(Some(&zero), &[], (&r("0"), &r("1"))),
            Err(PlanError::NonPositiveHeight(_))
        ));
        let tiny = LayerPlan {
            height: r("1e-9"),
            first: None,
            last: None,
        };
        assert!(matches!(
            plan_levels(Some(&tiny), &[], (&r("0"), &r("1"))),
            Err(PlanError::TooMany(_))
        ));
        assert_eq!(
            plan_levels(None, &[], (&r("0"), &r("1"))),
            Err(PlanError::Empty)
        );
        // A plate 0.1 thick under layers of 0.3: the first plane, 0.15
        // above its bottom, is above its top.
        let thick = LayerPlan {
            height: r("0.3"),
            first: None,
            last: None,
        };
        let err = plan_levels(Some(&thick), &[], (&r("2"), &r("2.1"))).unwrap_err();
        assert_eq!(
            err,
            PlanError::NoPlaneInRange {
                height: "3/10 (~0.3)".into(),
                first: "43/20 (~2.15)".into(),
                last: "21/10 (~2.1)".into(),
                lo: "2".into(),
                hi: "21/10 (~2.1)".into(),
            }
        );
        assert!(err.to_string().contains("choose a smaller layer height"));
        // An explicit level alone is a plan.
        assert_eq!(
            plan_levels(Some(&thick), &[r("2.05")], (&r("2"), &r("2.1"))),
            Ok(vec![r("2.05")])
        );
    }
}
