//! WAV output through `hound`: 32-bit float or 24-bit integer PCM, any channel count.

use crate::error::Error;
use std::path::Path;

/// Sample format of a written WAV file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WavFormat {
    /// IEEE 32-bit float, samples written as they are (no normalisation).
    Float32,
    /// 24-bit integer PCM; samples are scaled by `1 / peak` when the peak exceeds 1.
    Int24,
}

/// Writes interleaved channels (`channels[c][n]`) to `path` at `sample_rate` Hz.
pub fn write_wav(
    path: &Path,
    channels: &[Vec<f64>],
    sample_rate: u32,
    format: WavFormat,
) -> Result<(), Error> {
    let n_ch = channels.len();
    if n_ch == 0 {
        return Err(Error::Empty {
            what: "channels to write",
        });
    }
    let len = channels[0].len();
    let (bits, sample_format) = match format {
        WavFormat::Float32 => (32, hound::SampleFormat::Float),
        WavFormat::Int24 => (24, hound::SampleFormat::Int),
    };
    let spec = hound::WavSpec {
        channels: n_ch as u16,
        sample_rate,
        bits_per_sample: bits,
        sample_format,
    };
    let ctx = |source: hound::Error| Error::Wav {
        path: path.to_path_buf(),
        source,
    };
    let mut w = hound::WavWriter::create(path, spec).map_err(ctx)?;
    let peak = channels
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let scale = if peak > 1.0 { 1.0 / peak } else { 1.0 };
    for n in 0..len {
        for ch in channels {
            match format {
                WavFormat::Float32 => w.write_sample(ch[n] as f32).map_err(ctx)?,
                WavFormat::Int24 => w
                    .write_sample((ch[n] * scale * 8_388_607.0).round() as i32)
                    .map_err(ctx)?,
            }
        }
    }
    w.finalize().map_err(ctx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_float() {
        let path = std::env::temp_dir().join(format!("noether-wav-{}.wav", std::process::id()));
        let ch = vec![vec![0.0, 0.5, -0.25], vec![1.0, -1.0, 0.125]];
        write_wav(&path, &ch, 48_000, WavFormat::Float32).unwrap();
        let mut r = hound::WavReader::open(&path).unwrap();
        assert_eq!(r.spec().channels, 2);
        assert_eq!(r.spec().sample_rate, 48_000);
        let s: Vec<f32> = r.samples::<f32>().map(|x| x.unwrap()).collect();
        assert_eq!(s, vec![0.0, 1.0, 0.5, -1.0, -0.25, 0.125]);
        std::fs::remove_file(&path).ok();
    }
}
