//! The tanpura: four to six strings with their jawari on one moving bridge
//! ([`crate::models::network`]), tuned to Sa in the standard tunings ([`tuning`]), tuned by ear
//! ([`tune`]) and plucked in the drone's cycle ([`cycle`]).

pub mod cycle;
pub mod instrument;
pub mod spec;
pub mod tune;
pub mod tuning;

pub use cycle::{Pattern, PluckCycle, PluckEvent};
pub use instrument::Tanpura;
pub use spec::TanpuraSpec;
pub use tuning::{Metal, TanpuraString, Tuning};
