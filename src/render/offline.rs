//! The offline render loop: run a [`RenderSource`] for a duration, record its pickups and
//! energy, resample to the output rate, and measure the run.

use super::resample::{advance, resample};
use super::source::{EnergyTerms, RenderSource, ShapeSnapshot};
use crate::error::Error;
use serde::Serialize;
use std::time::Instant;

/// Steps per block handed to the source.
pub const BLOCK: usize = 512;

/// Everything an offline render produced.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// Pickup signals at the simulation rate, `sim[c][n]`.
    pub sim: Vec<Vec<f64>>,
    /// Pickup signals resampled to the output rate, `out[c][n]`.
    pub out: Vec<Vec<f64>>,
    /// Energy terms sampled every `energy_stride` steps (first entry: before the first step).
    pub energy: Vec<EnergyTerms>,
    /// Steps between energy samples.
    pub energy_stride: usize,
    /// Figures of the run.
    pub stats: RenderStats,
    /// Shapes at the requested instants (models with a 1-D shape only).
    pub shapes: Vec<ShapeSnapshot>,
}

/// Energy figures of a run (all relative errors divided by the largest total energy seen,
/// which is the natural scale for struck or plucked models that start at rest).
#[derive(Debug, Clone, Serialize)]
pub struct EnergyStats {
    /// Discrete energy before the first step (J).
    pub initial: f64,
    /// Largest discrete energy during the run (J).
    pub max: f64,
    /// Discrete energy at the end (J).
    pub last: f64,
    /// Largest `|total_n - total_0| / max` (meaningful for lossless, unforced runs).
    pub max_rel_drift: f64,
    /// Largest `|balance_n - balance_0| / max`, balance = energy + dissipated - work.
    pub max_balance_error: f64,
    /// Energy dissipated by damping over the run (J).
    pub dissipated: f64,
    /// Work done by the excitation over the run (J).
    pub work: f64,
}

/// Figures of a run.
#[derive(Debug, Clone, Serialize)]
pub struct RenderStats {
    /// Simulated duration (s).
    pub seconds: f64,
    /// Simulation steps taken.
    pub steps: u64,
    /// Number of non-finite output or energy values.
    pub nan_count: u64,
    /// Largest absolute output value (after gain).
    pub peak: f64,
    /// Wall-clock seconds spent simulating (excludes resampling and file output).
    pub wall_seconds: f64,
    /// Simulated seconds per wall-clock second.
    pub realtime_factor: f64,
    /// Energy figures.
    pub energy: EnergyStats,
}

/// Runs `source` for `seconds`, applies `gain`, resamples to `out_rate`; `progress` is called
/// with the fraction done (0 to 1) after each block.
pub fn render(
    source: &mut dyn RenderSource,
    seconds: f64,
    out_rate: u32,
    gain: f64,
    energy_points: usize,
    progress: impl FnMut(f64),
) -> Result<Rendered, Error> {
    render_with_shapes(
        source,
        seconds,
        out_rate,
        gain,
        energy_points,
        &[],
        progress,
    )
}

/// [`render`], also recording the model's shape ([`RenderSource::shape`]) after the step
/// nearest to each instant of `snapshot_times` (s; instants outside the run are skipped).
pub fn render_with_shapes(
    source: &mut dyn RenderSource,
    seconds: f64,
    out_rate: u32,
    gain: f64,
    energy_points: usize,
    snapshot_times: &[f64],
    mut progress: impl FnMut(f64),
) -> Result<Rendered, Error> {
    let fs = source.sim_rate();
    let steps = (seconds * fs).round().max(1.0) as u64;
    let mut snap_steps: Vec<u64> = snapshot_times
        .iter()
        .filter(|t| t.is_finite() && **t >= 0.0)
        .map(|t| (t * fs).round() as u64)
        .filter(|&n| n <= steps)
        .collect();
    snap_steps.sort_unstable();
    snap_steps.dedup();
    let mut next_snap = 0usize;
    let mut shapes = Vec::new();
    let channels = source.channels();
    let stride = ((steps as usize) / energy_points.max(1)).max(1);
    let mut sim = vec![Vec::with_capacity(steps as usize); channels];
    let mut block = vec![vec![0.0; BLOCK]; channels];
    let mut energy = Vec::with_capacity(steps as usize / stride + 2);
    energy.push(source.energy());
    let start = Instant::now();
    let mut done: u64 = 0;
    let mut nan_count = 0u64;
    let mut since_energy = 0usize;
    while done < steps || next_snap < snap_steps.len() {
        while next_snap < snap_steps.len() && snap_steps[next_snap] <= done {
            shapes.extend(source.shape(done as f64 / fs));
            next_snap += 1;
        }
        if done >= steps {
            break;
        }
        // Blocks end on energy-sample and snapshot boundaries so energy is sampled exactly
        // every `stride` and shapes at their steps.
        let to_snap = snap_steps
            .get(next_snap)
            .map_or(u64::MAX, |&n| n.saturating_sub(done).max(1));
        let frames = (steps - done)
            .min(BLOCK as u64)
            .min(to_snap)
            .min((stride - since_energy) as u64) as usize;
        source.process(&mut block, frames);
        for (s, b) in sim.iter_mut().zip(&block) {
            for &x in &b[..frames] {
                if !x.is_finite() {
                    nan_count += 1;
                }
                s.push(x * gain);
            }
        }
        done += frames as u64;
        since_energy += frames;
        if since_energy == stride || done == steps {
            let e = source.energy();
            if !e.balance().is_finite() {
                nan_count += 1;
            }
            energy.push(e);
            since_energy = 0;
        }
        progress(done as f64 / steps as f64);
    }
    let wall = start.elapsed().as_secs_f64();
    let mut out = resample(&sim, fs.round() as u32, out_rate)?;
    for (c, ch) in out.iter_mut().enumerate() {
        // Sample m then lies at t = m / out_rate: y[m] = x(m - delay · out_rate).
        advance(ch, -source.output_delay(c) * out_rate as f64);
    }
    let peak = out.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let stats = RenderStats {
        seconds,
        steps,
        nan_count,
        peak,
        wall_seconds: wall,
        realtime_factor: if wall > 0.0 {
            seconds / wall
        } else {
            f64::INFINITY
        },
        energy: energy_stats(&energy),
    };
    Ok(Rendered {
        sim,
        out,
        energy,
        energy_stride: stride,
        stats,
        shapes,
    })
}

/// Computes [`EnergyStats`] from sampled energy terms.
pub fn energy_stats(e: &[EnergyTerms]) -> EnergyStats {
    let first = e.first().copied().unwrap_or_default();
    let last = e.last().copied().unwrap_or_default();
    let max = e.iter().map(|t| t.total().abs()).fold(0.0, f64::max);
    let scale = if max > 0.0 { max } else { 1.0 };
    let dev = |f: &dyn Fn(&EnergyTerms) -> f64| {
        e.iter()
            .map(|t| (f(t) - f(&first)).abs() / scale)
            .fold(0.0, |m: f64, x| {
                if x.is_nan() || m.is_nan() {
                    f64::NAN
                } else {
                    m.max(x)
                }
            })
    };
    EnergyStats {
        initial: first.total(),
        max,
        last: last.total(),
        max_rel_drift: dev(&|t| t.total()),
        max_balance_error: dev(&|t| t.balance()),
        dissipated: last.dissipated,
        work: last.work,
    }
}
