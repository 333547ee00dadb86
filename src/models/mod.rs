//! Physical models, each runnable as a [`crate::render::source::RenderSource`]:
//!
//! - [`plate`]: modal von Kármán plate (gongs, plates; SEED.md section 3.1);
//! - [`string`]: stiff string against a unilateral obstacle (sitar, tanpura), modal exact
//!   linear scheme with an energy-conserving contact force (SEED.md section 3.2).

pub mod plate;
pub mod string;
