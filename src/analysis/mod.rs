//! Measurements on simulated signals: the core's closed forms, dispersion, frequency and
//! energy-drift tools ([`noether_core::analysis`]), plus spectrograms (FFT, offline only).

pub use noether_core::analysis::*;

pub mod formant;
pub mod fundamental;
pub mod glide;
pub mod spectrogram;
