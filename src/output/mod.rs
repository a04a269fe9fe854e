//! Input: exact level sets. Output: the interchange JSON (SPEC section 9),
//! a readable summary, SVG, the HTML viewer and Common Layer Interface
//! files. This is where exact values are rounded to the nearest `f64`, and
//! only for writing.

pub mod atomic;
pub mod certificate;
pub mod cli_layers;
pub mod critical;
pub mod html;
pub mod json;
pub mod reeb_svg;
pub mod summary;
pub mod svg;
