//! `noether glide`: the pitch glide of one partial of a WAV file (an opera gong's rising or
//! falling fundamental), in Hz per second, with a PNG of the track and a zoomed spectrogram
//! (`noether::analysis::glide`).

use std::path::PathBuf;

use clap::Args;
use noether::analysis::glide::{glide_rate, track_partial};
use noether::analysis::spectrogram::spectrogram;
use noether::plot::spectrogram::{write_spectrogram_png, FreqAxis};
use noether::plot::{write_png, Mark, Panel, Series};
use noether::{Error, ParamError};

/// Arguments of `noether glide`.
#[derive(Debug, Args)]
pub struct GlideArgs {
    /// The WAV file (any rate, 16/24/32-bit integer or float).
    pub wav: PathBuf,
    /// The partial's approximate frequency in Hz (e.g. the fundamental read off a
    /// spectrogram or from `noether modes`).
    #[arg(long)]
    pub near: f64,
    /// Half-width in Hz of the band that isolates the partial: wide enough for the whole
    /// glide, narrow enough to exclude the neighbouring partials (default: 10 % of --near,
    /// at least 20 Hz).
    #[arg(long)]
    pub band: Option<f64>,
    /// Channel to analyse (0 = left).
    #[arg(long, default_value_t = 0)]
    pub channel: usize,
    /// Analysis window in seconds.
    #[arg(long, default_value_t = 0.05)]
    pub window: f64,
    /// Start of the fitted span in seconds (after the strike's transient).
    #[arg(long, default_value_t = 0.05)]
    pub from: f64,
    /// End of the fitted span in seconds (default: the end of the file).
    #[arg(long)]
    pub to: Option<f64>,
    /// Write a PNG of the track (frequency and level over time) here, and the zoomed
    /// spectrogram next to it (`<stem>-spectrogram.png`).
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

/// Runs `noether glide`.
pub fn run(a: GlideArgs) -> Result<(), Error> {
    let (x, rate) = read_channel(&a)?;
    if !(a.near > 0.0 && a.near < 0.5 * rate) {
        return Err(ParamError::new(
            "--near",
            a.near,
            format!("0 to {} Hz (Nyquist)", 0.5 * rate),
        )
        .into());
    }
    let band = a.band.unwrap_or((0.1 * a.near).max(20.0));
    if !(band > 0.0 && band < a.near) {
        return Err(ParamError::new("--band", band, format!("0 to --near = {} Hz", a.near)).into());
    }
    let seconds = x.len() as f64 / rate;
    if !(a.window >= 0.005 && a.window <= 0.25 * seconds) {
        return Err(ParamError::new(
            "--window",
            a.window,
            format!("0.005 to a quarter of the file, {} s", 0.25 * seconds),
        )
        .into());
    }
    let to = a.to.unwrap_or(seconds);
    let track = track_partial(&x, rate, a.near, band, a.window, 0.5 * a.window);
    let fit = glide_rate(&track, a.from, to).ok_or_else(|| {
        ParamError::new(
            "--near",
            a.near,
            format!(
                "a frequency with a partial within ±{band} Hz in at least 3 windows between {} and {to} s",
                a.from
            ),
        )
    })?;
    println!(
        "partial near {} Hz (band ±{band} Hz), {} windows of {} s from {:.3} to {:.3} s:",
        a.near, fit.windows, a.window, fit.from, fit.to
    );
    println!(
        "  {:.3} Hz -> {:.3} Hz: glide {:+.3} Hz/s ({:+.1} cents), residual {:.3} Hz",
        fit.start_hz,
        fit.end_hz,
        fit.hz_per_second,
        fit.cents(),
        fit.residual_hz
    );
    if let Some(path) = &a.plot {
        let top = track
            .levels
            .iter()
            .fold(0.0f64, |m, &v| m.max(v))
            .max(f64::MIN_POSITIVE);
        let db: Vec<f64> = track
            .levels
            .iter()
            .map(|v| 20.0 * (v / top).log10())
            .collect();
        let line_t = vec![fit.from, fit.to];
        let line_f = vec![fit.start_hz, fit.end_hz];
        let panels = [
            Panel::new("frequency of the partial", "time (s)", "frequency (Hz)")
                .push(
                    Series::line("measured", track.times.clone(), track.freqs.clone())
                        .with_mark(Mark::Points),
                )
                .push(Series::line(
                    format!("fit {:+.2} Hz/s", fit.hz_per_second),
                    line_t,
                    line_f,
                )),
            Panel::new(
                "level of the partial",
                "time (s)",
                "dB (re its loudest window)",
            )
            .push(Series::line("level", track.times.clone(), db)),
        ];
        let title = format!(
            "glide of the partial near {} Hz: {}",
            a.near,
            a.wav.display()
        );
        write_png(path, &title, &panels, 1, (900, 380))?;
        let spec = spectrogram(&x, rate, 8192, 1024);
        let zoom = path.with_file_name(format!(
            "{}-spectrogram.png",
            path.file_stem().and_then(|s| s.to_str()).unwrap_or("glide")
        ));
        let axis = FreqAxis::Log {
            min: (a.near - 3.0 * band).max(10.0),
            max: a.near + 3.0 * band,
        };
        write_spectrogram_png(&zoom, &title, &spec, axis, 80.0)?;
        println!("wrote {} and {}", path.display(), zoom.display());
    }
    Ok(())
}

/// The chosen channel of the WAV file as `f64` samples, and its rate.
fn read_channel(a: &GlideArgs) -> Result<(Vec<f64>, f64), Error> {
    let bad = |e: hound::Error| {
        ParamError::new("wav", a.wav.display(), format!("a readable WAV file ({e})"))
    };
    let mut r = hound::WavReader::open(&a.wav).map_err(bad)?;
    let spec = r.spec();
    let ch = spec.channels as usize;
    if a.channel >= ch {
        return Err(ParamError::new("--channel", a.channel, format!("0 to {}", ch - 1)).into());
    }
    let all: Vec<f64> = match spec.sample_format {
        hound::SampleFormat::Float => r
            .samples::<f32>()
            .map(|s| s.map(f64::from))
            .collect::<Result<_, _>>()
            .map_err(bad)?,
        hound::SampleFormat::Int => {
            let scale = 1.0 / (1u64 << (spec.bits_per_sample - 1)) as f64;
            r.samples::<i32>()
                .map(|s| s.map(|v| v as f64 * scale))
                .collect::<Result<_, _>>()
                .map_err(bad)?
        }
    };
    Ok((
        all.into_iter().skip(a.channel).step_by(ch).collect(),
        f64::from(spec.sample_rate),
    ))
}
