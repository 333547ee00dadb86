//! Tuning by ear: a player plucks each string, listens to it after the attack and turns the
//! peg until it sounds its note. Here: each string is plucked alone in the whole network (the
//! other strings on the bridge, unplucked), its first partial's frequency is measured from its
//! first modal coordinate `q_1` (the first partial itself, read without a filter) over
//! [`LISTEN_FROM`] to [`LISTEN_TO`] after the pluck, and its tension is scaled by
//! `(f_target / f_measured)²`; [`TUNE_PASSES`] passes. The seat, the moving bridge, the
//! jawari (which raises a grazing string's pitch) and the string's stiffness all move the
//! sounding pitch off the ideal string's `√(T/μ)/2L`; this puts it back.
//!
//! Control (or worker) thread: builds networks and runs `TUNE_PASSES · strings` seconds of
//! simulation.

use super::spec::TanpuraSpec;
use crate::error::ParamError;
use crate::models::network::{NetworkConfig, StringNetwork};
use crate::models::string::TrianglePluck;

/// Passes of the tuning.
pub const TUNE_PASSES: usize = 2;

/// Start of the listening window after the pluck, s.
pub const LISTEN_FROM: f64 = 0.3;

/// End of the listening window after the pluck, s.
pub const LISTEN_TO: f64 = 1.0;

/// The frequency (Hz) of string `string`'s first modal coordinate over `[from, to]` s from
/// now, from its upward zero crossings (linearly interpolated between steps): the number of
/// periods between the first and the last crossing over the time between them. `None` with
/// fewer than three crossings. Steps the network to `to`.
pub fn first_partial_hz(net: &mut StringNetwork, string: usize, from: f64, to: f64) -> Option<f64> {
    let h = net.h();
    let (start, end) = ((from / h).round() as u64, (to / h).round() as u64);
    let (mut first, mut last, mut count) = (None, 0.0, 0u64);
    let mut prev = net.strings()[string].modal_displacement()[0];
    for n in 1..=end {
        net.step();
        let q = net.strings()[string].modal_displacement()[0];
        if n > start && prev < 0.0 && q >= 0.0 {
            let t = (n as f64 - 1.0 + prev / (prev - q)) * h;
            first.get_or_insert(t);
            last = t;
            count += 1;
        }
        prev = q;
    }
    let first = first?;
    (count >= 3).then(|| (count - 1) as f64 / (last - first))
}

/// The pluck of every string in `spec` (position and amplitude).
pub fn pluck_of(spec: &TanpuraSpec) -> TrianglePluck {
    TrianglePluck {
        position: spec.pluck_position * spec.length,
        amplitude: spec.pluck_amplitude,
    }
}

/// Each string's tension over its nominal tension after tuning by ear (all 1 when
/// `spec.tune_by_ear` is off).
pub fn tension_scales(spec: &TanpuraSpec) -> Result<Vec<f64>, ParamError> {
    if !spec.tune_by_ear {
        return Ok(vec![1.0; spec.strings]);
    }
    let targets: Vec<f64> = (0..spec.strings).map(|i| spec.target_hz(i)).collect();
    let plucks = vec![pluck_of(spec); spec.strings];
    tune_by_ear(|scale| spec.network(scale), &targets, &plucks)
}

/// Tunes the strings of the network `build(scale)` builds (string `i` at `scale[i]` times its
/// nominal tension) to `targets` (Hz), each plucked alone by its `plucks[i]`; returns the
/// scales ([`TUNE_PASSES`] passes, module doc).
pub fn tune_by_ear(
    build: impl Fn(&[f64]) -> Result<NetworkConfig, ParamError>,
    targets: &[f64],
    plucks: &[TrianglePluck],
) -> Result<Vec<f64>, ParamError> {
    let mut scale = vec![1.0; targets.len()];
    for _ in 0..TUNE_PASSES {
        let config = build(&scale)?;
        for (s, k) in scale.iter_mut().enumerate() {
            let mut net = StringNetwork::new(&config)?;
            net.pluck(s, &plucks[s])?;
            if let Some(f) = first_partial_hz(&mut net, s, LISTEN_FROM, LISTEN_TO) {
                *k *= (targets[s] / f).powi(2);
            }
        }
    }
    Ok(scale)
}

/// Tunes string `string` alone of the network `build(scale)` builds to `target` Hz by ear,
/// starting from `scale` (the other strings kept at theirs), plucked by `pluck`; returns the
/// string's scale ([`TUNE_PASSES`] passes, module doc). A sitar's fret or a meend's target:
/// the same string at another note.
pub fn tune_string_by_ear(
    build: impl Fn(&[f64]) -> Result<NetworkConfig, ParamError>,
    scale: &[f64],
    string: usize,
    target: f64,
    pluck: &TrianglePluck,
) -> Result<f64, ParamError> {
    let mut scale = scale.to_vec();
    for _ in 0..TUNE_PASSES {
        let mut net = StringNetwork::new(&build(&scale)?)?;
        net.pluck(string, pluck)?;
        if let Some(f) = first_partial_hz(&mut net, string, LISTEN_FROM, LISTEN_TO) {
            scale[string] *= (target / f).powi(2);
        }
    }
    Ok(scale[string])
}
