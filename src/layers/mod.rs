//! Input: a slicer and a plan of many levels. Output: their level sets, one
//! at a time and in ascending order, computed by a plane sweep over the
//! faces (only the faces touching a plane are visited for it) on one or
//! several threads, with identical results whatever the thread count.

pub mod plan;
pub mod sweep;

pub use plan::{height_range, plan_levels, LayerPlan, PlanError};
pub use sweep::{
    max_threads, slice_levels, slice_levels_then, slice_plan_then, thread_count, SweepError,
    SweepPlan, TooManyThreads,
};
