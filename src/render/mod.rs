//! Offline rendering: the render loop over any [`source::RenderSource`], WAV output and
//! sample-rate conversion.

pub mod accuracy;
pub mod auto;
pub mod metrics;
pub mod midi;
pub mod offline;
pub mod play;
pub mod preset_accuracy;
pub mod preset_engine;
pub mod report;
pub mod resample;
pub mod scene;
pub mod shape_plot;
pub mod step_join;
pub use noether_core::models::source;
pub mod wav;
