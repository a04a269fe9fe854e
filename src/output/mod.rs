//! Input: exact level sets. Output: the interchange JSON (SPEC section 9)
//! and a readable summary. This is where exact values are rounded to the
//! nearest `f64`, and only for writing.

pub mod atomic;
pub mod json;
pub mod summary;
