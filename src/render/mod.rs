//! Offline rendering support: WAV output and sample-rate conversion.

pub mod resample;
pub mod wav;
