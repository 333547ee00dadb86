//! The tanpura: four to six strings with their jawari on one moving bridge
//! ([`crate::models::network`]), tuned to Sa in the standard tunings ([`tuning`]), tuned by ear
//! ([`tune`], over a range of keys by [`key_map`]) and plucked in the drone's cycle ([`cycle`]).

pub mod cycle;
pub mod instrument;
pub mod key_map;
pub mod spec;
pub mod tune;
pub mod tuning;
pub mod tuning_cache;

pub use cycle::{Pattern, PluckCycle, PluckEvent};
pub use instrument::Tanpura;
pub use key_map::SaMap;
pub use spec::TanpuraSpec;
pub use tuning::{Metal, TanpuraString, Tuning};
pub use tuning_cache::{tune_cached, TunedStrings, TuningSource};
