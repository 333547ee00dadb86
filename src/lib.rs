//! # Noether (offline)
//!
//! The offline side of Noether, on top of the real-time core [`noether_core`]: scene files,
//! the offline render loop (WAV, band-limited resampling, reports), accuracy and `auto` model
//! selection studies, the extremes sweep, PNG plots, the lecture's integrator lab and the
//! `noether` command line.
//!
//! - [`scene`], [`render`]: scene files (TOML, deserialised into the core's typed model
//!   specifications) and the offline render loop;
//! - [`analysis`]: the core's measurements plus spectrograms;
//! - [`lab`]: the lecture's experiments as runnable, reportable configurations;
//! - [`plot`]: PNG figures (waveforms, energies, phase portraits, spectrograms);
//! - [`stress`]: sweeps of every model and scheme over extreme parameters (`tests/robustness/extremes.rs`,
//!   `noether stress`).
//!
//! The core's modules are re-exported under their own names ([`engine`], [`models`],
//! [`modal`], [`schemes`]); [`error`] extends the core's parameter errors with
//! [`Error`], the one error type of the offline crate.

pub use error::{Error, ParamError};
pub use noether_core::{clock, engine, modal, models, schemes};

pub mod analysis;
pub mod error;
pub mod lab;
pub mod plot;
pub mod render;
pub mod scene;
pub mod stress;
