//! The parameter and state cases of `conform` (see `conform.rs`): random parameter sets, the
//! range bounds, and the state round trip. Each case takes a fresh instance, sets its values
//! with `params.flush` while inactive, activates it at 48 kHz with 512-frame blocks and renders
//! a note (key 60, velocity 1).
//!
//! What must hold: `activate` returns true for every combination of values inside the ranges
//! (an unbuildable combination keeps the last good model and reports it, it does not refuse
//! the host), and the output is finite and within ±1.0. The renders are short (0.1 s): a plate
//! at the top of the `modes` range costs seconds of CPU per second of sound.
//!
//! Threads: the test host's main thread.

use clack_extensions::params::PluginParams;
use clack_host::prelude::*;
use std::ffi::CString;

use crate::conform_render::{
    load_state, read_values, render, save_state, set_values, RenderSpec, Rng, Session,
};
use crate::host::{text_of, TestHost};
use crate::runner::Runner;

/// Render length of the parameter cases, seconds.
const SHORT: f64 = 0.1;

/// Process CPU seconds a parameter case's blocks may take (64-frame blocks, so a case stops
/// within a block of it): a plate at the top of the quality ranges (2000 modes, 200 in-plane
/// modes, a 400 kHz simulation rate) needs minutes of CPU for 0.1 s; the first blocks hold the
/// strike, where the level peaks, and every block is checked all the same.
const CASE_CPU: f64 = 2.0;

/// Every parameter's display name and text, `name=text` separated by commas (for the log of a
/// failing case, so it can be reproduced with `render --set`).
fn describe(s: &Session, inst: &mut PluginInstance<TestHost>) -> String {
    let Some(ext) = inst.plugin_handle().get_extension::<PluginParams>() else {
        return "(no params extension)".into();
    };
    let Ok(values) = read_values(inst, &s.params) else {
        return "(values unreadable)".into();
    };
    s.params
        .iter()
        .zip(values)
        .map(|(p, v)| {
            let text = text_of(&ext, inst, p.id, v).unwrap_or_else(|e| e);
            format!("{}={text}", p.name)
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The display text of parameter `name` in `inst` (for the case lines).
fn shown(s: &Session, inst: &mut PluginInstance<TestHost>, name: &str) -> String {
    let ext = inst.plugin_handle().get_extension::<PluginParams>();
    let text = s.index_of(name).and_then(|k| {
        let p = &s.params[k];
        let v = ext
            .and_then(|e| e.get_value(&inst.plugin_handle(), p.id))
            .ok_or("get_value failed")?;
        text_of(&ext.ok_or("no params extension")?, inst, p.id, v)
    });
    text.unwrap_or_else(|e| e)
}

/// Fresh instance, `values` flushed, a short note rendered in 64-frame blocks within
/// [`CASE_CPU`]; the line names the model and the quality parameters, and on failure every
/// parameter's value.
fn set_and_render(s: &Session, values: &[f64], need_sound: bool) -> Result<String, String> {
    let mut inst = s.instance()?;
    set_values(&mut inst, &s.params, values)?;
    let what = format!(
        "model {}, modes {}, in-plane {}, sim rate {}, band {}",
        shown(s, &mut inst, "Model"),
        shown(s, &mut inst, "Modes"),
        shown(s, &mut inst, "In-plane modes"),
        shown(s, &mut inst, "Simulation rate"),
        shown(s, &mut inst, "Band limit"),
    );
    let spec = RenderSpec {
        cpu_budget: Some(CASE_CPU),
        ..RenderSpec::note(48_000.0, 64, SHORT)
    };
    match render(&mut inst, &spec).and_then(|r| Ok((r.verdict(need_sound)?, r.cpu_line()))) {
        Ok((figures, cpu)) => Ok(format!("{what}: {figures} (CPU: {cpu})")),
        Err(e) => Err(format!(
            "{what}: {e}\n     values: {}",
            describe(s, &mut inst)
        )),
    }
}

/// `count` random sets (every parameter uniform in its CLAP range, stepped ones on whole
/// steps), seeded by `seed`.
pub(crate) fn permutations(s: &Session, seed: u64, count: usize, run: &mut Runner) {
    let mut rng = Rng::new(seed);
    for i in 0..count {
        let values: Vec<f64> = s.params.iter().map(|p| rng.value_of(p)).collect();
        run.case(&format!("params: random set {}/{count}", i + 1), || {
            set_and_render(s, &values, false)
        });
    }
}

/// Models under which each parameter goes to its bounds alone: the default (a gong) and the
/// two strings (a plate parameter's bounds under a string model, and the reverse, are also
/// combinations a host can set). The other plates are left to the random sets: each of their
/// 84 renders would cost a modal basis build (about 0.45 s).
const BOUND_MODELS: [&str; 3] = ["gong (circular, free edge)", "sitar", "tanpura"];

/// Every parameter at its minimum, every one at its maximum, then each alone at its minimum and
/// at its maximum with the others at their defaults, under each of [`BOUND_MODELS`].
pub(crate) fn bounds(s: &Session, run: &mut Runner) {
    let mins: Vec<f64> = s.params.iter().map(|p| p.min).collect();
    let maxs: Vec<f64> = s.params.iter().map(|p| p.max).collect();
    run.case("bounds: every parameter at its minimum", || {
        set_and_render(s, &mins, false)
    });
    run.case("bounds: every parameter at its maximum", || {
        set_and_render(s, &maxs, false)
    });
    let model = match s.index_of("Model") {
        Ok(k) => k,
        Err(e) => return run.case("bounds: the model parameter", || Err(e)),
    };
    for name in BOUND_MODELS {
        let base = match s
            .instance()
            .and_then(|mut i| clap_value(s, &mut i, "Model", name))
        {
            Ok((_, v)) => v,
            Err(e) => return run.case(&format!("bounds: model `{name}`"), || Err(e)),
        };
        let short = name.split_whitespace().next().unwrap_or(name);
        for (k, p) in s.params.iter().enumerate().filter(|(k, _)| *k != model) {
            for (end, v) in [("minimum", p.min), ("maximum", p.max)] {
                let mut values = s.defaults();
                values[model] = base;
                values[k] = v;
                run.case(&format!("bounds: {short}, {} at its {end}", p.name), || {
                    set_and_render(s, &values, false)
                });
            }
        }
    }
}

/// Values per parameter the `conversions` case tries: evenly spaced over the range, ends
/// included (clap-validator's `param-conversions` found "Band limit" at 19/68 of its range).
const CONVERSION_STEPS: usize = 2040;

/// Value → text → value → text gives the same text for every parameter at
/// [`CONVERSION_STEPS`] + 1 values of its range (clap-validator's `param-conversions`: the
/// host shows the text it reads back, so the round trip must be consistent).
pub(crate) fn conversions(s: &Session, run: &mut Runner) {
    run.case(
        &format!(
            "bounds: value to text to value to text, {} values per parameter",
            CONVERSION_STEPS + 1
        ),
        || {
            let mut inst = s.instance()?;
            let ext: PluginParams = inst
                .plugin_handle()
                .get_extension()
                .ok_or("no params extension")?;
            let mut checked = 0;
            for p in &s.params {
                for step in 0..=CONVERSION_STEPS {
                    let mut v = p.min + (p.max - p.min) * step as f64 / CONVERSION_STEPS as f64;
                    if p.stepped {
                        v = v.round();
                    }
                    let text = text_of(&ext, &mut inst, p.id, v)?;
                    let c =
                        CString::new(text.as_str()).map_err(|_| format!("bad text `{text}`"))?;
                    let back = ext
                        .text_to_value(&inst.plugin_handle(), p.id, &c)
                        .ok_or_else(|| format!("{}: cannot parse its own `{text}`", p.name))?;
                    let again = text_of(&ext, &mut inst, p.id, back)?;
                    if again != text {
                        return Err(format!(
                            "{}: {v} shows `{text}`, read back as {back}, which shows `{again}`",
                            p.name
                        ));
                    }
                    checked += 1;
                }
            }
            Ok(format!("{checked} round trips consistent"))
        },
    );
}

/// The CLAP value the plugin gives for display text `text` of parameter `name`.
pub(crate) fn clap_value(
    s: &Session,
    inst: &mut PluginInstance<TestHost>,
    name: &str,
    text: &str,
) -> Result<(usize, f64), String> {
    let k = s.index_of(name)?;
    let ext: PluginParams = inst
        .plugin_handle()
        .get_extension()
        .ok_or("no params extension")?;
    let c = CString::new(text).map_err(|_| format!("bad text `{text}`"))?;
    let v = ext
        .text_to_value(&inst.plugin_handle(), s.params[k].id, &c)
        .ok_or_else(|| format!("`{name}`: the plugin cannot parse `{text}`"))?;
    Ok((k, v))
}

/// State round trips: the default values and two random sets (with `Threads` = 1, the audio
/// thread alone, `Output gain` = 0 dB, and at most 64 modes and 8 in-plane modes). Instance A: set, save.
/// Instance B (fresh): load. Every CLAP value must be equal exactly, B's saved state must be
/// the same bytes, and A's and B's renders of a 0.3 s note must agree to 1e-6 (the engine's
/// output does not depend on its thread count; the tolerance is 1e-6 all the same, about
/// 2^-20 of full scale, far below any audible difference and far above f32 rounding of a
/// deterministic computation, which gives exactly 0).
pub(crate) fn state(s: &Session, seed: u64, run: &mut Runner) {
    let mut rng = Rng::new(seed ^ 0x57a7e);
    for round in 0..3 {
        let name = if round == 0 {
            "state: round trip of the defaults".to_string()
        } else {
            format!("state: round trip of random set {round}")
        };
        let random: Vec<f64> = s.params.iter().map(|p| rng.value_of(p)).collect();
        run.case(&name, || {
            let mut a = s.instance()?;
            let mut values = if round == 0 { s.defaults() } else { random };
            let (kt, one) = clap_value(s, &mut a, "Threads", "1")?;
            values[kt] = one;
            let (kg, zero_db) = clap_value(s, &mut a, "Output gain", "0")?;
            values[kg] = zero_db;
            // The renders compare two instances, not the model's cost: a random set's
            // quality is capped (a draw of 1900 modes took 263 s of CPU for its two renders;
            // the bounds and params groups cover the full ranges within a CPU budget).
            for (name, cap) in [("Modes", "64"), ("In-plane modes", "8")] {
                let (k, capped) = clap_value(s, &mut a, name, cap)?;
                values[k] = values[k].min(capped);
            }
            set_values(&mut a, &s.params, &values)?;
            let blob = save_state(&mut a)?;
            let mut b = s.instance()?;
            load_state(&mut b, &blob)?;
            let va = read_values(&mut a, &s.params)?;
            let vb = read_values(&mut b, &s.params)?;
            let differ: Vec<String> = s
                .params
                .iter()
                .zip(va.iter().zip(&vb))
                .filter(|(_, (x, y))| x.to_bits() != y.to_bits())
                .map(|(p, (x, y))| format!("`{}` {x} -> {y}", p.name))
                .collect();
            if !differ.is_empty() {
                return Err(format!(
                    "{} of {} values changed: {}",
                    differ.len(),
                    s.params.len(),
                    differ.join(", ")
                ));
            }
            let blob_b = save_state(&mut b)?;
            if blob_b != blob {
                return Err(format!(
                    "the loaded instance saves different bytes ({} vs {} bytes)",
                    blob_b.len(),
                    blob.len()
                ));
            }
            let what = format!(
                "model {}, modes {}",
                shown(s, &mut a, "Model"),
                shown(s, &mut a, "Modes")
            );
            let spec = RenderSpec::note(48_000.0, 512, 0.3);
            let ra = render(&mut a, &spec).map_err(|e| format!("{what}: instance A: {e}"))?;
            let rb = render(&mut b, &spec).map_err(|e| format!("{what}: instance B: {e}"))?;
            // The defaults must sound (a silent pair would compare vacuously); a random set
            // may be quiet (a 0.01 N strike is -130 dBFS) and is then compared all the same.
            let figures = ra
                .verdict(round == 0)
                .map_err(|e| format!("{what}: {e}\n     values: {}", describe(s, &mut a)))?;
            let diff = ra.max_diff(&rb);
            if diff > 1e-6 {
                return Err(format!(
                    "{what}: renders of the saved and the loaded instance differ by {diff:e}"
                ));
            }
            Ok(format!(
                "{what}: {} bytes, {} values equal, same bytes re-saved, {figures}, \
                 renders differ by {diff:e}",
                blob.len(),
                s.params.len()
            ))
        });
    }
}
