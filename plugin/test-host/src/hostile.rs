//! `--hostile-automation`: every block, the host sends one CLAP parameter event per parameter
//! with a value the plugin must not take as it is: below the minimum, above the maximum, NaN,
//! +∞, −∞, or (one time in six) a valid value, rotating so that each parameter sees every kind.
//! After each block the host reads every value back and checks what the host layer (nice-plug's
//! CLAP wrapper) did: finite values out of range are clamped to the nearest bound, non-finite
//! values are dropped (the previous value stays), valid values are taken. Any other outcome is an
//! error naming the parameter, the value sent and the value read back; the counts are printed as
//! the report of the clamping.
//!
//! The render itself must stay finite and within ±1.0 (0 dBFS) whatever the automation does:
//! [`check_output`] fails it otherwise (the engine's output stage bounds the level; gain at its
//! +60 dB maximum with a hard strike must not reach the host above full scale).
//!
//! Threads: all on the test host's single thread, between `process` calls (as a DAW's offline
//! bounce would send automation).

use clack_extensions::params::PluginParams;
use clack_host::events::event_types::ParamValueEvent;
use clack_host::prelude::*;

use crate::host::{text_of, Param, TestHost};

/// What the host sent to one parameter in one block.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Sent {
    /// A finite value below the minimum (by one range width).
    Below(f64),
    /// A finite value above the maximum (by two range widths).
    Above(f64),
    /// NaN or ±∞.
    NonFinite(f64),
    /// A value inside the range.
    Valid(f64),
}

impl Sent {
    fn value(self) -> f64 {
        match self {
            Self::Below(x) | Self::Above(x) | Self::NonFinite(x) | Self::Valid(x) => x,
        }
    }
}

/// Counts of what was sent and how the plugin's values came back.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct HostileReport {
    /// Events sent with a finite value below the minimum; each read back as the minimum.
    pub clamped_low: u64,
    /// Events sent with a finite value above the maximum; each read back as the maximum.
    pub clamped_high: u64,
    /// Events sent with NaN or ±∞; each left the previous value in place.
    pub dropped_non_finite: u64,
    /// Events sent with a value in range; each read back as sent (to the stepping).
    pub valid: u64,
}

/// The hostile automation of one render: the parameters, their last values, the counts.
pub(crate) struct HostileAutomation {
    params: Vec<Param>,
    last: Vec<f64>,
    sent: Vec<Sent>,
    block: u64,
    /// The running counts.
    pub report: HostileReport,
}

impl HostileAutomation {
    /// Starts from the instance's current values.
    pub(crate) fn new(params: &[Param], current: Vec<f64>) -> Self {
        Self {
            params: params.to_vec(),
            sent: vec![Sent::Valid(0.0); params.len()],
            last: current,
            block: 0,
            report: HostileReport::default(),
        }
    }

    /// Pushes this block's events (time 0) into `events`.
    pub(crate) fn push_events(&mut self, events: &mut EventBuffer) {
        for (k, p) in self.params.iter().enumerate() {
            let span = (p.max - p.min).max(1.0);
            // A valid value that walks through the range: (0.37 b mod 1) of the way.
            let frac = (0.37 * (self.block + k as u64) as f64).fract();
            let s = match (self.block + 2 * k as u64) % 6 {
                0 => Sent::Below(p.min - span),
                1 => Sent::Above(p.max + 2.0 * span),
                2 => Sent::NonFinite(f64::NAN),
                3 => Sent::NonFinite(f64::INFINITY),
                4 => Sent::NonFinite(f64::NEG_INFINITY),
                _ => Sent::Valid(p.min + frac * (p.max - p.min)),
            };
            self.sent[k] = s;
            events.push(&ParamValueEvent::new(0, p.id, Pckn::match_all(), s.value()));
        }
        self.block += 1;
    }

    /// Reads every value back after the block and checks it against what was sent.
    pub(crate) fn check(&mut self, instance: &mut PluginInstance<TestHost>) -> Result<(), String> {
        let ext: PluginParams = instance
            .plugin_handle()
            .get_extension()
            .ok_or("no params extension")?;
        for k in 0..self.params.len() {
            let p = self.params[k].clone();
            let got = ext
                .get_value(&instance.plugin_handle(), p.id)
                .ok_or_else(|| format!("get_value({}) failed", p.name))?;
            // Bounds and kept values come back exactly up to f32 storage (relative 6e-8):
            // allow 1e-6 of the range. A valid value sent to a stepped parameter comes back
            // rounded to the step grid: allow half a step. A valid continuous value goes through
            // the skewed range's f32 `powf` and back: allow 1e-4, or else the same display text
            // (a wide skewed range such as the contact stiffness maps its lowest normalised
            // values to plain values equal to the minimum in f32).
            let tol = 1e-6 * (p.max - p.min).max(1.0);
            let (want, ok) = match self.sent[k] {
                Sent::Below(_) => {
                    self.report.clamped_low += 1;
                    (p.min, (got - p.min).abs() <= tol)
                }
                Sent::Above(_) => {
                    self.report.clamped_high += 1;
                    (p.max, (got - p.max).abs() <= tol)
                }
                Sent::NonFinite(_) => {
                    self.report.dropped_non_finite += 1;
                    (self.last[k], (got - self.last[k]).abs() <= tol)
                }
                Sent::Valid(x) => {
                    self.report.valid += 1;
                    let close = if p.stepped {
                        (got - x).abs() <= 0.5 + tol
                    } else {
                        (got - x).abs() <= 1e-4
                            || text_of(&ext, instance, p.id, x)?
                                == text_of(&ext, instance, p.id, got)?
                    };
                    (x, close)
                }
            };
            if !got.is_finite() || got < p.min - tol || got > p.max + tol || !ok {
                return Err(format!(
                    "hostile automation, block {}: parameter `{}` sent {:?}, reads back {got} \
                     (expected {want}, range [{}, {}])",
                    self.block, p.name, self.sent[k], p.min, p.max
                ));
            }
            self.last[k] = got;
        }
        Ok(())
    }

    /// One line per kind, for the log.
    pub(crate) fn summary(&self) -> String {
        let r = self.report;
        format!(
            "hostile automation over {} blocks x {} parameters: {} values below the minimum \
             clamped to it, {} above the maximum clamped to it, {} non-finite values dropped, \
             {} valid values taken; every value read back stayed in its range",
            self.block,
            self.params.len(),
            r.clamped_low,
            r.clamped_high,
            r.dropped_non_finite,
            r.valid
        )
    }
}

/// Checks the interleaved output of a hostile-automation render: every sample finite and
/// |x| <= 1.0 (0 dBFS). Returns the peak line for the log, or an error with the counts, the
/// peak and the first bad frame (stereo frames: `channels` samples each).
pub(crate) fn check_output(samples: &[f32], channels: usize, rate: f64) -> Result<String, String> {
    let mut peak = 0.0f64;
    let mut non_finite = 0usize;
    let mut over = 0usize;
    let mut first = None;
    for (i, &x) in samples.iter().enumerate() {
        let bad = if x.is_finite() {
            let a = f64::from(x.abs());
            peak = peak.max(a);
            a > 1.0
        } else {
            true
        };
        if bad {
            if x.is_finite() {
                over += 1;
            } else {
                non_finite += 1;
            }
            first.get_or_insert(i / channels.max(1));
        }
    }
    let level = if peak > 0.0 {
        format!("{:+.1} dBFS", 20.0 * peak.log10())
    } else {
        "silent".to_string()
    };
    match first {
        None => Ok(format!(
            "hostile automation output: {} samples finite, peak {level} (at most 0 dBFS)",
            samples.len()
        )),
        Some(f) => Err(format!(
            "hostile automation output: {non_finite} samples NaN or infinite, {over} above \
             0 dBFS (peak of the finite ones {level}), first at frame {f} ({:.3} s)",
            f as f64 / rate
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::check_output;

    #[test]
    fn full_scale_passes_and_anything_beyond_fails() {
        assert!(check_output(&[0.0, 1.0, -1.0, 0.5], 2, 48_000.0).is_ok());
        let above = f32::from_bits(1.0f32.to_bits() + 1);
        let e = check_output(&[0.0, 0.0, 0.1, -above], 2, 48_000.0).unwrap_err();
        assert!(e.contains("1 above 0 dBFS") && e.contains("frame 1"), "{e}");
        // A +50 dBFS render (what the hostile automation produced before the output stage).
        let e = check_output(&[316.0, -316.0], 2, 48_000.0).unwrap_err();
        assert!(e.contains("+50.0 dBFS"), "{e}");
        for x in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let e = check_output(&[0.0, x], 2, 48_000.0).unwrap_err();
            assert!(e.contains("1 samples NaN or infinite"), "{e}");
        }
    }
}
