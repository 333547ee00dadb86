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
//! simulation. Within a pass the strings are measured independently (each on its own copy of
//! the network), so [`tune_by_ear`] shares them among up to [`tuning_threads`] scoped threads;
//! the result does not depend on how many.

use super::spec::TanpuraSpec;
use crate::error::ParamError;
use crate::models::network::{NetworkConfig, StringNetwork};
use crate::models::string::TrianglePluck;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Passes of the tuning.
pub const TUNE_PASSES: usize = 2;

/// Threads [`tune_by_ear`] may use (0: not set, [`tuning_threads`] chooses).
static TUNING_THREADS: AtomicUsize = AtomicUsize::new(0);

/// Sets how many threads tuning by ear may use in this process (at least 1). An offline
/// render, with nothing else to run, gives it every core; a plugin keeps the default, which
/// leaves one core to the audio thread. Any thread.
pub fn set_tuning_threads(threads: usize) {
    TUNING_THREADS.store(threads.max(1), Ordering::Relaxed);
}

/// Threads tuning by ear uses: as set by [`set_tuning_threads`], else one fewer than the
/// machine's cores (at least 1). Any thread.
pub fn tuning_threads() -> usize {
    match TUNING_THREADS.load(Ordering::Relaxed) {
        0 => std::thread::available_parallelism()
            .map_or(1, |n| n.get().saturating_sub(1))
            .max(1),
        n => n,
    }
}

/// Whether a first partial heard at `f` Hz can be the note `target` Hz: within a semitone of
/// it. A string whose fundamental lies near a strong mode of its bridge (the sitar's played
/// string fretted near the main bridge's 190 Hz bounce) hands its fundamental to the bridge
/// within a few tenths of a second, a wolf note, and its first modal coordinate is then
/// driven at the second partial: zero crossings counted over the whole window give a
/// frequency between the two, which is no pitch to tune to. Such a measurement is left out,
/// and the string keeps its tension there (measured over the window's start instead, the
/// wolf's pitch is no steadier: a fret tuned on it sounds 141 cents sharp, against 23 cents
/// for the tension law).
fn heard_as_its_note(f: f64, target: f64) -> bool {
    (12.0 * (f / target).log2()).abs() < 1.0
}

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
        let heard = first_partials(&config, plucks, targets, tuning_threads())?;
        for ((k, f), target) in scale.iter_mut().zip(heard).zip(targets) {
            if let Some(f) = f {
                *k *= (target / f).powi(2);
            }
        }
    }
    Ok(scale)
}

/// Each string's first partial (Hz) in the network `config`, the string plucked alone by its
/// `plucks[s]` and heard as its note `targets[s]` ([`heard_partial`]), measured on up to
/// `threads` threads ([`map_on_threads`]). The same values for any `threads`.
fn first_partials(
    config: &NetworkConfig,
    plucks: &[TrianglePluck],
    targets: &[f64],
    threads: usize,
) -> Result<Vec<Option<f64>>, ParamError> {
    map_on_threads(plucks.len(), threads, |s| {
        heard_partial(config, s, &plucks[s], targets[s])
    })
}

/// String `string`'s first partial (Hz) in the network `config`, plucked alone by `pluck`,
/// over the listening window ([`first_partial_hz`]), if it is heard as the note `target`
/// ([`heard_as_its_note`]); else `None` (the tuning leaves the string's tension as it is).
fn heard_partial(
    config: &NetworkConfig,
    string: usize,
    pluck: &TrianglePluck,
    target: f64,
) -> Result<Option<f64>, ParamError> {
    let mut net = StringNetwork::new(config)?;
    net.pluck(string, pluck)?;
    let heard = first_partial_hz(&mut net, string, LISTEN_FROM, LISTEN_TO);
    Ok(heard.filter(|&f| heard_as_its_note(f, target)))
}

/// `[f(0), ..., f(n - 1)]`, computed on up to `threads` scoped threads, the indices dealt to
/// them in turn (`f` must not depend on the order); the first error in index order, if any.
/// A panic in `f` is passed on. Control (or worker) thread.
pub(crate) fn map_on_threads<T: Send>(
    n: usize,
    threads: usize,
    f: impl Fn(usize) -> Result<T, ParamError> + Sync,
) -> Result<Vec<T>, ParamError> {
    let threads = threads.clamp(1, n.max(1));
    if threads == 1 {
        return (0..n).map(f).collect();
    }
    let mut out: Vec<Option<Result<T, ParamError>>> = (0..n).map(|_| None).collect();
    std::thread::scope(|scope| {
        let f = &f;
        let workers: Vec<_> = (0..threads)
            .map(|w| {
                scope.spawn(move || {
                    (w..n)
                        .step_by(threads)
                        .map(|i| (i, f(i)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        for worker in workers {
            let part = worker
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            for (i, r) in part {
                out[i] = Some(r);
            }
        }
    });
    out.into_iter()
        .map(|r| r.expect("every index computed"))
        .collect()
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
        if let Some(f) = heard_partial(&build(&scale)?, string, pluck, target)? {
            scale[string] *= (target / f).powi(2);
        }
    }
    Ok(scale[string])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Measuring the strings on several threads gives the values one thread gives, bit for bit
    /// (each string on its own network): a four-string drone of 400 modes at 32 kHz, measured
    /// on 1, 2 and 3 threads (3 does not divide 4: the dealing is uneven). An error in one
    /// index is returned, the first in index order.
    #[test]
    fn threads_measure_what_one_thread_measures() {
        let mut spec = TanpuraSpec::at(138.59);
        spec.modes = 400;
        spec.sim_rate = 32_000.0;
        let config = spec.network(&vec![1.0; spec.strings]).unwrap();
        let plucks = vec![pluck_of(&spec); spec.strings];
        let targets: Vec<f64> = (0..spec.strings).map(|i| spec.target_hz(i)).collect();
        let one = first_partials(&config, &plucks, &targets, 1).unwrap();
        assert!(one.iter().all(|f| f.is_some_and(|f| f > 50.0)), "{one:?}");
        for threads in [2, 3] {
            assert_eq!(
                first_partials(&config, &plucks, &targets, threads).unwrap(),
                one
            );
        }
        let failing = map_on_threads(5, 2, |i| {
            if i % 2 == 1 {
                Err(ParamError::new("index", i, "even"))
            } else {
                Ok(i)
            }
        });
        assert_eq!(failing.unwrap_err().value, "1");
        assert_eq!(map_on_threads(4, 8, Ok).unwrap(), vec![0, 1, 2, 3]);
    }
}
