//! Exact sums of dyadic rationals `m * 2^e`: every double is one, and so
//! are sums and products of doubles (face areas, tetrahedron volumes).

use super::rational::Rat;
use num_bigint::BigInt;
use num_traits::{One, Signed, Zero};

/// An exact dyadic rational `m * 2^e`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Dyadic {
    m: BigInt,
    e: i32,
}

impl Dyadic {
    /// `m * 2^e`.
    pub fn new(m: BigInt, e: i32) -> Dyadic {
        Dyadic { m, e }
    }

    /// The sign of the value, exactly.
    pub fn sign(&self) -> super::Sign {
        super::Sign::of_int(&self.m)
    }

    /// Adds `|x|` exactly.
    pub fn add_abs(&mut self, x: &Dyadic) {
        self.add(&x.m.abs(), x.e);
    }

    /// Adds `x` exactly.
    pub fn add_dyadic(&mut self, x: &Dyadic) {
        self.add(&x.m, x.e);
    }

    /// Adds `m * 2^e` exactly.
    pub fn add(&mut self, m: &BigInt, e: i32) {
        if m.is_zero() {
            return;
        }
        if self.m.is_zero() {
            self.m = m.clone();
            self.e = e;
            return;
        }
        if e < self.e {
            self.m <<= (self.e - e) as u32;
            self.e = e;
        }
        self.m += m << (e - self.e) as u32;
    }

    /// The value as a rational in lowest terms, times `2^shift`.
    pub fn to_rat_times_pow2(&self, shift: i32) -> Rat {
        if self.m.is_zero() {
            return Rat::zero();
        }
        let e = self.e + shift;
        let m = self.m.clone();
        if e >= 0 {
            Rat::from_integer(m << e as u32)
        } else {
            // Cancel the powers of two the mantissa holds.
            let tz = m.trailing_zeros().unwrap_or(0).min((-e) as u64);
            Rat::new_raw(m >> tz, BigInt::one() << ((-e) as u64 - tz))
        }
    }
}
