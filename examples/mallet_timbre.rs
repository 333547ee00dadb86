//! Velocity changes the timbre: the lecture's gong (`assets/scenes/gong-mallet.toml`: 0.4 m,
//! 1 mm steel, free edge, 510 strike-mirror modes, SAV at 16 kHz) struck by its felt mallet at
//! speeds from 0.1 to 5 m/s. For each speed: the first contact's duration and peak force (the
//! mallet's force, step by step) and the spectral centroid of the first pickup over 0.5 s
//! (power-weighted mean frequency of its Hann-windowed spectrum). The contact duration is
//! compared with Hertz's law on a rigid target,
//! `t_c = 2 (δ_m / v) ∫₀¹ dx / √(1 - x^{α+1})`, `δ_m = ((α+1) M v² / 2K)^{1/(α+1)}`
//! (Hunt & Crossley, J. Appl. Mech. 42, 1975; the integral is `B(1/(α+1), 1/2)/(α+1)`, taken
//! here by the midpoint rule in `x = 1 - s²`), for the scene's 0.2 kg mallet and for a 0.02 kg
//! one (the gong weighs 3.9 kg: the lighter mallet meets a target closer to rigid).
//!
//! Run: `cargo run --release --example mallet_timbre [OUT_DIR]` (default `out`): prints the
//! table and writes `OUT_DIR/mallet-timbre.png`.

use noether::models::plate::voice::PlateVoice;
use noether::plot::{write_png, Mark, Panel, Scale, Series};
use noether::render::source::RenderSource;
use noether::scene::Scene;
use rustfft::{num_complex::Complex, FftPlanner};
use std::path::{Path, PathBuf};

const SPEEDS: [f64; 8] = [0.1, 0.2, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0];
/// Felt of the scene: K (N/m^α) and α.
const K: f64 = 1e8;
const ALPHA: f64 = 2.5;
const SECONDS: f64 = 0.5;

/// Hertz's contact duration (s) on a rigid target.
fn hertz(mass: f64, v: f64) -> f64 {
    let p = ALPHA + 1.0;
    let dm = (p * mass * v * v / (2.0 * K)).powf(1.0 / p);
    // ∫₀¹ (1 - x^p)^{-1/2} dx with x = 1 - s²: 2 ∫₀¹ s (1 - (1 - s²)^p)^{-1/2} ds, regular
    // at s = 0 (the integrand tends to 1/√p); midpoint rule on 20 000 cells (error ~1e-9).
    let n = 20_000;
    let integral: f64 = (0..n)
        .map(|i| {
            let s = (i as f64 + 0.5) / n as f64;
            2.0 * s / (1.0 - (1.0 - s * s).powf(p)).sqrt() / n as f64
        })
        .sum();
    2.0 * dm / v * integral
}

/// Power-weighted mean frequency (Hz) of `x` sampled at `fs`.
fn centroid(x: &[f64], fs: f64) -> f64 {
    let n = x.len();
    let mut buf: Vec<Complex<f64>> = x
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            let w = 0.5 - 0.5 * (std::f64::consts::TAU * k as f64 / n as f64).cos();
            Complex::new(v * w, 0.0)
        })
        .collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buf);
    let (mut num, mut den) = (0.0, 0.0);
    for (k, c) in buf[..n / 2].iter().enumerate() {
        let p = c.norm_sqr();
        num += p * k as f64 * fs / n as f64;
        den += p;
    }
    num / den
}

/// One strike: (contact duration s, peak force N, centroid Hz, impacts in 0.5 s).
fn strike(mass: f64, v: f64) -> (f64, f64, f64, u64) {
    let scene = Scene::load(
        Path::new("assets/scenes/gong-mallet.toml"),
        &[
            format!("plate.excitation.speed={v}"),
            format!("plate.excitation.mass={mass}"),
        ],
    )
    .expect("the mallet scene");
    let spec = scene.plate.as_ref().expect("a plate scene");
    let mut voice = PlateVoice::build(spec).expect("the gong");
    let fs = voice.sim_rate();
    let n = (SECONDS * fs) as usize;
    let mut out = vec![vec![0.0; 1]; voice.channels()];
    let (mut first, mut last, mut peak) = (None, None, 0.0f64);
    let mut y = Vec::with_capacity(n);
    for k in 0..n {
        voice.process(&mut out, 1);
        y.push(out[0][0]);
        let f = voice.mallet().expect("a mallet").force();
        if f > 0.0 && last.is_none() {
            first.get_or_insert(k);
            peak = peak.max(f);
        } else if f == 0.0 && first.is_some() && last.is_none() {
            last = Some(k);
        }
    }
    let steps = last.unwrap_or(n) - first.unwrap_or(0);
    let impacts = voice.mallet().expect("a mallet").stats().impacts;
    (steps as f64 / fs, peak, centroid(&y, fs), impacts)
}

/// One strike's figures: mallet mass (kg), speed (m/s), contact (s), Hertz's contact (s),
/// peak force (N), centroid (Hz).
struct Row {
    mass: f64,
    speed: f64,
    contact: f64,
    hertz: f64,
    force: f64,
    centroid: f64,
}

/// `(speed, f(row))` of the rows with mallet mass `m`.
fn series(rows: &[Row], m: f64, f: impl Fn(&Row) -> f64) -> (Vec<f64>, Vec<f64>) {
    rows.iter()
        .filter(|r| r.mass == m)
        .map(|r| (r.speed, f(r)))
        .unzip()
}

fn main() {
    let dir = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "out".into()));
    std::fs::create_dir_all(&dir).expect("the output folder");
    let mut rows = Vec::new();
    println!("| mass kg | speed m/s | contact ms | Hertz rigid ms | ratio | peak force N | centroid Hz | impacts |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    for mass in [0.2, 0.02] {
        for v in SPEEDS {
            let (tc, fmax, c, impacts) = strike(mass, v);
            let th = hertz(mass, v);
            println!(
                "| {mass} | {v} | {:.3} | {:.3} | {:.3} | {fmax:.1} | {c:.0} | {impacts} |",
                1e3 * tc,
                1e3 * th,
                tc / th
            );
            rows.push(Row {
                mass,
                speed: v,
                contact: tc,
                hertz: th,
                force: fmax,
                centroid: c,
            });
        }
    }
    let mut panels = Vec::new();
    let mut dur = Panel::new(
        "First contact duration",
        "mallet speed (m/s)",
        "contact (ms)",
    )
    .scales(Scale::Log10, Scale::Log10);
    let mut force = Panel::new("Peak contact force", "mallet speed (m/s)", "force (N)")
        .scales(Scale::Log10, Scale::Log10);
    let mut cent = Panel::new(
        "Spectral centroid, first 0.5 s",
        "mallet speed (m/s)",
        "centroid (Hz)",
    )
    .scales(Scale::Log10, Scale::Linear);
    for m in [0.2, 0.02] {
        let (x, y) = series(&rows, m, |r| 1e3 * r.contact);
        dur = dur
            .push(Series::line(format!("{m} kg, on the gong"), x, y).with_mark(Mark::LinePoints));
        let (x, y) = series(&rows, m, |r| 1e3 * r.hertz);
        dur = dur.push(Series::line(format!("{m} kg, Hertz rigid"), x, y));
        let (x, y) = series(&rows, m, |r| r.force);
        force = force.push(Series::line(format!("{m} kg"), x, y).with_mark(Mark::LinePoints));
        let (x, y) = series(&rows, m, |r| r.centroid);
        cent = cent.push(Series::line(format!("{m} kg"), x, y).with_mark(Mark::LinePoints));
    }
    panels.push(dur);
    panels.push(force);
    panels.push(cent);
    let png = dir.join("mallet-timbre.png");
    write_png(
        &png,
        "The lecture's gong struck by a felt mallet (K = 1e8 N/m^2.5, alpha = 2.5)",
        &panels,
        3,
        (520, 420),
    )
    .expect("the figure");
    println!("wrote {}", png.display());
}
