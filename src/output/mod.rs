//! Input: exact level sets. Output: the interchange JSON (SPEC section 9),
//! a readable summary, SVG, the HTML viewer and Common Layer Interface
//! files. This is where exact values are rounded to the nearest `f64`, and
//! only for writing.

pub mod atomic;
/// Common Layer Interface (the AM layer format): writer and reader.
pub mod cli_layers;
/// The self-contained HTML layer viewer.
pub mod html;
pub mod json;
pub mod summary;
/// SVG drawings of level sets, one class per kind.
pub mod svg;
