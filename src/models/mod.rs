//! Physical models that run as [`crate::render::source::RenderSource`]s.
//!
//! - [`string`]: stiff string against a unilateral obstacle (sitar, tanpura), modal exact
//!   linear scheme with an energy-conserving contact force (SEED.md section 3.2).

pub mod string;
