//! `conform PLUGIN.clap`: what the published validators (clap-validator, Steinberg's VST3
//! validator, pluginval) check a plugin for, run through the project's own CLAP host so that CI
//! catches it (the validators themselves are on no package registry the CI reaches).
//!
//! Cases, each reported as one `PASS` or `FAIL` line with its figures and the process CPU time
//! it took:
//! - `rate`: activation at host rates from 1234.57 Hz to 1.5 MHz must succeed, and a note (key 60,
//!   velocity 1, 0.5 s) must come out finite, at most 0 dBFS and not silent;
//! - `block`: fixed block sizes 1 to 8192 (the maximum given at activation) and block sizes
//!   varying within one run, shorter than the maximum: every frame asked for written, finite,
//!   at most 0 dBFS, not silent;
//! - `params` and `bounds` (in `conform_params.rs`): random parameter sets and the range
//!   bounds, each activated and rendered;
//! - `state` (in `conform_params.rs`): save, load into a fresh instance, compare values,
//!   re-saved bytes and renders;
//! - `flush`: `params.flush` without processing (inactive, and active but not processing);
//! - `silence`: `process` before any note gives finite silence;
//! - `events` and `activate` (in `conform_live.rs`): note ends in time order across a block
//!   split, and `activate()` within 20 ms at the 99th percentile on a real-time instance.
//!
//! Every other case runs the plugin in CLAP's offline render mode (a bounce: activation waits
//! for the model, so a note at the first sample sounds and renders repeat).
//!
//! Every sample must lie within ±1.0: the engine's output stage bounds it at 0 dBFS whatever
//! the parameters (the validators' checks are finiteness; the bound is this product's own).
//! Exit status non-zero if any case fails.
//!
//! Threads: the test host's main thread plays both the main and the audio thread.

use clack_extensions::params::PluginParams;
use clack_host::events::event_types::ParamValueEvent;
use clack_host::prelude::*;
use std::path::PathBuf;

use crate::args::{parse_num, path_arg};
use crate::conform_render::{
    process_cpu_seconds, read_values, render, set_values, RenderSpec, Rendered, Rng, Session,
};
use crate::runner::Runner;

/// Host rates of the `rate` cases, Hz: clap-validator's fractional 1234.57 Hz (refused before
/// any positive rate activated), the telephone and low rates, the CD and video families and
/// their multiples, up to 1.5 MHz.
pub(crate) const RATES: [f64; 13] = [
    1_234.567_7,
    8_000.0,
    11_025.0,
    16_000.0,
    22_050.0,
    44_100.0,
    48_000.0,
    96_000.0,
    176_400.0,
    192_000.0,
    384_000.0,
    768_000.0,
    1_500_000.0,
];

/// Fixed block sizes of the `block` cases (each also the maximum given at activation): the
/// smallest, odd and prime sizes that split any internal chunk unevenly, and the largest.
pub(crate) const BLOCKS: [u32; 8] = [1, 2, 3, 7, 64, 511, 4096, 8192];

/// Options of `conform`.
#[derive(Debug, Clone)]
pub struct ConformOptions {
    /// The `.clap` file under test.
    pub plugin: PathBuf,
    /// Seed of the random parameter sets.
    pub seed: u64,
    /// How many random parameter sets the `params` cases try.
    pub permutations: usize,
    /// Case groups to run (`rate`, `block`, `events`, `load`, `params`, `bounds`, `state`,
    /// `flush`, `silence`, `activate`);
    /// empty: all.
    pub only: Vec<String>,
}

/// The case groups, in the order they run.
pub(crate) const GROUPS: [&str; 10] = [
    "silence", "flush", "rate", "block", "events", "load", "state", "bounds", "params", "activate",
];

impl ConformOptions {
    /// Parses `PLUGIN [--seed N] [--permutations N] [--only GROUP[,GROUP...]]`.
    pub fn parse(args: &[String]) -> Result<Self, String> {
        let mut it = args.iter();
        let plugin = path_arg("PLUGIN.clap", it.next())?;
        let mut o = Self {
            plugin,
            seed: 1,
            permutations: 50,
            only: Vec::new(),
        };
        while let Some(flag) = it.next() {
            match flag.as_str() {
                "--seed" => o.seed = parse_num(flag, it.next())?,
                "--permutations" => o.permutations = parse_num(flag, it.next())?,
                "--only" => {
                    let list = it.next().ok_or("--only needs GROUP[,GROUP...]")?;
                    for g in list.split(',') {
                        if !GROUPS.contains(&g) {
                            return Err(format!("--only: `{g}` is none of {GROUPS:?}"));
                        }
                        o.only.push(g.to_string());
                    }
                }
                other => return Err(format!("unknown option `{other}`")),
            }
        }
        Ok(o)
    }

    fn runs(&self, group: &str) -> bool {
        self.only.is_empty() || self.only.iter().any(|g| g == group)
    }
}

/// `conform`: runs the selected groups and fails if any case failed.
pub fn conform(o: &ConformOptions) -> Result<(), String> {
    let c0 = process_cpu_seconds();
    let t0 = std::time::Instant::now();
    // The plugin logs to this file (nice-plug reads `NICE_LOG` when the plugin is first
    // created, below; the test host is single-threaded here), read by the last case.
    let log = std::env::temp_dir().join(format!("noether-conform-{}.log", std::process::id()));
    let _ = std::fs::remove_file(&log);
    std::env::set_var("NICE_LOG", &log);
    let s = Session::load(&o.plugin)?;
    println!(
        "conform {}: {} parameters, seed {}, {} random sets",
        o.plugin.display(),
        s.params.len(),
        o.seed,
        o.permutations
    );
    let mut run = Runner::default();
    for group in GROUPS.iter().filter(|g| o.runs(g)) {
        let g0 = process_cpu_seconds();
        match *group {
            "silence" => silence(&s, &mut run),
            "flush" => flush(&s, o.seed, &mut run),
            "rate" => rates(&s, &mut run),
            "block" => blocks(&s, &mut run),
            "state" => crate::conform_params::state(&s, o.seed, &mut run),
            "bounds" => {
                crate::conform_params::conversions(&s, &mut run);
                crate::conform_params::bounds(&s, &mut run);
            }
            "params" => crate::conform_params::permutations(&s, o.seed, o.permutations, &mut run),
            "events" => crate::conform_live::events(&s, &mut run),
            "load" => crate::conform_live::load(&s, &mut run),
            "activate" => crate::conform_live::activate(&s, o.seed, o.permutations, &mut run),
            _ => unreachable!("GROUPS lists the groups"),
        }
        println!("group {group}: {:.1} s CPU", process_cpu_seconds() - g0);
    }
    crate::conform_live::log_is_clean(&log, &mut run);
    let _ = std::fs::remove_file(&log);
    println!(
        "conform: {} passed, {} failed, {:.1} s CPU (all threads), {:.1} s wall",
        run.passed,
        run.failed.len(),
        process_cpu_seconds() - c0,
        t0.elapsed().as_secs_f64()
    );
    if run.failed.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "{} conformance cases failed: {}",
            run.failed.len(),
            run.failed.join("; ")
        ))
    }
}

/// `process` with no note after activation: finite, written, and silent to -120 dBFS (nothing
/// was excited; any output is a leak of state from construction).
fn silence(s: &Session, run: &mut Runner) {
    run.case("silence: 1 s of process before any note", || {
        let mut inst = s.instance()?;
        let spec = RenderSpec {
            note: None,
            ..RenderSpec::note(48_000.0, 512, 1.0)
        };
        let r = render(&mut inst, &spec)?;
        let figures = r.verdict(false)?;
        let peak = r.stats().peak;
        if peak > 1e-6 {
            return Err(format!("not silent: {figures} (more than -120 dBFS)"));
        }
        Ok(figures)
    });
}

/// `params.flush` on an inactive instance (every parameter to a random value, then an empty
/// flush) and on an active instance that is not processing (the gain), each read back.
fn flush(s: &Session, seed: u64, run: &mut Runner) {
    run.case("flush: every parameter, inactive, no processing", || {
        let mut inst = s.instance()?;
        let mut rng = Rng::new(seed ^ 0xf1);
        let sent: Vec<f64> = s.params.iter().map(|p| rng.value_of(p)).collect();
        set_values(&mut inst, &s.params, &sent)?;
        let got = read_values(&mut inst, &s.params)?;
        check_read_back(s, &sent, &got)?;
        // An empty flush changes nothing.
        set_values(&mut inst, &[], &[])?;
        let again = read_values(&mut inst, &s.params)?;
        if again != got {
            return Err("an empty flush changed parameter values".into());
        }
        Ok(format!("{} values read back", s.params.len()))
    });
    run.case(
        "flush: gain, active and not processing, then a note",
        || {
            let mut inst = s.instance()?;
            let k = s.index_of("Output gain")?;
            let p = s.params[k].clone();
            let ext: PluginParams = inst
                .plugin_handle()
                .get_extension()
                .ok_or("no params extension")?;
            let config = PluginAudioConfiguration {
                sample_rate: 48_000.0,
                min_frames_count: 1,
                max_frames_count: 512,
            };
            let mut stopped = inst
                .activate(|_, _| (), config)
                .map_err(|e| format!("activate(48000 Hz, blocks 1..=512) failed: {e:?}"))?;
            // A quarter of the way up the normalised gain range (-30 dB).
            let want = p.min + 0.25 * (p.max - p.min);
            let mut events = EventBuffer::new();
            events.push(&ParamValueEvent::new(0, p.id, Pckn::match_all(), want));
            let mut out = EventBuffer::new();
            ext.flush_active(
                &mut stopped.plugin_handle(),
                &InputEvents::from_buffer(&events),
                &mut OutputEvents::from_buffer(&mut out),
            );
            let got = ext
                .get_value(&inst.plugin_handle(), p.id)
                .ok_or("get_value failed")?;
            inst.deactivate(stopped);
            // f32 storage of the normalised value: 1e-6 of the range is a few ulps.
            if (got - want).abs() > 1e-6 * (p.max - p.min) {
                return Err(format!("gain flushed to {want}, reads back {got}"));
            }
            let r = render(&mut inst, &RenderSpec::note(48_000.0, 512, 0.3))?;
            Ok(format!("gain reads back {got}; note {}", r.verdict(true)?))
        },
    );
}

/// Read-back check of a flush. Stepped values within 2^-20 of the step count of the whole
/// number sent: nice-plug reports them as its f32 normalised value times the step count
/// (`Modes` 1223 of 1996 steps reads back 1222.99997), off by up to steps x 2^-24; a wrong step
/// is off by 1. Continuous ones within 1e-4 of the CLAP range: nice-plug keeps the plain value
/// and recomputes the normalised one through the skewed range's f32 `powf`, which moves it by
/// up to about 1e-5; a wrong value is off by far more.
fn check_read_back(s: &Session, sent: &[f64], got: &[f64]) -> Result<(), String> {
    for ((p, &x), &y) in s.params.iter().zip(sent).zip(got) {
        let tol = if p.stepped {
            (p.max - p.min).max(1.0) / f64::from(1u32 << 20)
        } else {
            1e-4 * (p.max - p.min)
        };
        if (x - y).abs() > tol || !y.is_finite() {
            return Err(format!(
                "`{}` flushed to {x}, reads back {y} (tolerance {tol:e})",
                p.name
            ));
        }
    }
    Ok(())
}

/// Activation at every host rate on a fresh instance, then a note.
fn rates(s: &Session, run: &mut Runner) {
    for rate in RATES {
        run.case(&format!("rate {rate} Hz: activate, note 0.5 s"), || {
            let mut inst = s.instance()?;
            let r = render(&mut inst, &RenderSpec::note(rate, 512, 0.5))?;
            r.verdict(true)
        });
    }
}

/// Fixed block sizes (each the maximum given at activation) and two varying plans; each
/// render is compared with the 64-frame one (reported, not judged: block splitting may move
/// parameter smoothing by a block).
fn blocks(s: &Session, run: &mut Runner) {
    let seconds = 0.5;
    let mut reference: Option<Rendered> = None;
    let mut plans: Vec<(String, RenderSpec)> = BLOCKS
        .iter()
        .map(|&b| {
            (
                format!("block {b} (max {b})"),
                RenderSpec::note(48_000.0, b, seconds),
            )
        })
        .collect();
    let vary = [1, 8192, 3, 511, 7, 4096, 64, 2, 1000, 8191];
    plans.push((
        format!("block varying {vary:?} (max 8192)"),
        RenderSpec {
            blocks: vary.to_vec(),
            ..RenderSpec::note(48_000.0, 8192, seconds)
        },
    ));
    let shorter = [512, 1, 37, 511, 2, 500, 7, 128];
    plans.push((
        format!("block varying {shorter:?} (max 512)"),
        RenderSpec {
            blocks: shorter.to_vec(),
            ..RenderSpec::note(48_000.0, 512, seconds)
        },
    ));
    // The 64-frame render first, as the reference of the others.
    plans.sort_by_key(|(_, spec)| spec.blocks != [64]);
    for (name, spec) in plans {
        run.case(&name, || {
            let mut inst = s.instance()?;
            let r = render(&mut inst, &spec)?;
            let figures = r.verdict(true)?;
            let diff = match &reference {
                Some(base) => format!(
                    ", max |difference| from 64-frame blocks {:.2e}",
                    r.max_diff(base)
                ),
                None => String::new(),
            };
            let line = format!("{} frames in {} blocks, {figures}{diff}", r.asked, r.blocks);
            if reference.is_none() {
                reference = Some(r);
            }
            Ok(line)
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(a: &[&str]) -> Vec<String> {
        a.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn options_parse_and_unknown_groups_are_refused() {
        let o = ConformOptions::parse(&args(&["p.clap", "--seed", "9", "--only", "rate,state"]))
            .unwrap();
        assert_eq!((o.seed, o.permutations), (9, 50));
        assert!(o.runs("rate") && o.runs("state") && !o.runs("params"));
        let e = ConformOptions::parse(&args(&["p.clap", "--only", "rates"])).unwrap_err();
        assert!(e.contains("`rates`"), "{e}");
        assert!(ConformOptions::parse(&args(&["p.clap"]))
            .unwrap()
            .runs("params"));
    }

    #[test]
    fn a_failed_case_is_counted_and_named() {
        let mut run = Runner::default();
        run.case("good", || Ok("fine".into()));
        run.case("bad", || Err("broken".into()));
        assert_eq!(run.passed, 1);
        assert_eq!(run.failed, vec!["bad".to_string()]);
    }
}
