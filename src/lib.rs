//! # wmslice: exact level sets of closed triangle meshes
//!
//! The reference implementation of weak-Morse mesh slicing (Mejia-Parra et
//! al., 2020): every degenerate case (faces in the plane, ridge edges,
//! isolated extrema, ordinary and monkey saddles) is decided with exact
//! arithmetic and no epsilon. Coordinates are rounded only when written out.
//!
//! The modules follow the pipeline:
//! mesh input ([`mesh`]) -> exact numbers ([`exact`]) -> classification
//! ([`classify`]) -> chaining ([`chain`]) -> nesting ([`nest`]) -> level sets
//! ([`levelset`]) -> output ([`output`]).

pub mod datasets;
pub mod ids;
pub mod mesh;

pub use ids::{EdgeId, FaceId, VertexId};
pub use mesh::Mesh;
pub mod chain;
pub mod classify;
pub mod critical;
pub mod exact;
pub mod layers;
pub mod levelset;
pub mod nest;
pub mod segment;

pub use levelset::{LevelSet, SliceError, Slicer};
pub mod naive;
pub mod output;
mod par;
pub mod verify;

/// The README's examples, compiled and run as doc tests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
#[cfg(feature = "cgal-oracle")]
pub mod oracle;
