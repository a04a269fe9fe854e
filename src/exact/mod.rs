//! Input: `f64` coordinates (exact dyadic rationals) and levels typed by the
//! user. Output: exact signs, exact rationals and correctly rounded `f64`s.
//!
//! This is the only module that does arithmetic on coordinates. Every
//! predicate returns a [`Sign`] or an exact [`Rat`], never a raw float
//! determinant; floats appear only as (exact) inputs and as rounded output.

pub mod area;
pub mod crossing;
pub mod dyadic;
pub mod face_area;
pub mod filter;
pub mod frame;
pub mod grid;
pub mod homogeneous;
pub mod level;
pub mod orient_filter;
pub mod perturbed;
pub mod planar;
pub mod point;
pub mod predicates;
pub mod rational;
pub mod scale;
pub mod volume;
pub mod wide;

pub use level::Level;
pub use point::Point2;
pub use predicates::Sign;
pub use rational::{parse_rational, Rat, RationalParseError};
