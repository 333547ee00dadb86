//! Synthetic WAV files for the unit tests of `check` and `compare` (test builds only).

use std::path::PathBuf;

/// Writes a stereo WAV (both channels equal) of `seconds` s at `rate` Hz into the temporary
/// directory, sample `i` being `x(i / rate)`: 16-bit integer (rounded to 1/32767 of full scale)
/// or, with `float`, 32-bit float. Returns its path; the caller removes it.
pub(crate) fn write(
    name: &str,
    rate: u32,
    seconds: f64,
    float: bool,
    x: impl Fn(f64) -> f64,
) -> PathBuf {
    let path = std::env::temp_dir().join(format!(
        "noether-test-host-{}-{name}.wav",
        std::process::id()
    ));
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: rate,
        bits_per_sample: if float { 32 } else { 16 },
        sample_format: if float {
            hound::SampleFormat::Float
        } else {
            hound::SampleFormat::Int
        },
    };
    let mut w = hound::WavWriter::create(&path, spec).unwrap();
    for i in 0..(seconds * f64::from(rate)).round() as usize {
        let v = x(i as f64 / f64::from(rate));
        for _ in 0..2 {
            if float {
                w.write_sample(v as f32).unwrap();
            } else {
                w.write_sample((v * 32767.0).round() as i16).unwrap();
            }
        }
    }
    w.finalize().unwrap();
    path
}
