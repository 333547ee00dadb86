//! Memory per instance: the coupling tensors an engine holds (`Engine::memory_bytes`: its
//! banks' tier tensors and the worker's modal cache) for every factory preset and for the top
//! of the quality ranges, beside the process's resident memory, which cross-checks the count.
//! The measurement behind docs/robustness.md, "Memory in bounds".
//!
//! Each row builds one engine (blocking activation at 48 kHz, the default memory cap), reads
//! its count and the resident set (`/proc/self/statm`) before and after, then drops it.
//!
//! `cargo run --release --example memory`

use noether::engine::{Engine, ParamId, Preset};
use noether_testkit::presets::preset_params;

/// Resident memory of this process (bytes), from `/proc/self/statm` (0 where absent).
fn resident() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<u64>().ok())
        .map_or(0, |pages| pages * 4096)
}

fn row(name: &str, sets: &[(ParamId, f32)], stem: &str) {
    let params = preset_params(stem, sets);
    let v = params.snapshot();
    let before = resident();
    let (mut e, _h) = Engine::new(params);
    let t0 = std::time::Instant::now();
    let refused = e.activate(48_000.0, 512);
    let build = t0.elapsed().as_secs_f64();
    let after = resident();
    let mb = |b: u64| b as f64 / 1048576.0;
    println!(
        "| {name} | {} x {} | {:.1} | {:.1} | {:.1} | {} |",
        v.index_of(ParamId::Modes),
        v.index_of(ParamId::InPlaneModes),
        build,
        mb(e.memory_bytes()),
        mb(after.saturating_sub(before)),
        match (&refused, e.modes_fitted()) {
            (Err(err), _) => format!("not built: {err}"),
            (Ok(_), Some(f)) => format!("{} of {} modes", f.built, f.wanted),
            (Ok(_), None) => "-".into(),
        }
    );
}

fn main() {
    println!("| set | modes x in-plane | build s | tensors MB | resident growth MB | reduced |");
    println!("| --- | --- | ---: | ---: | ---: | --- |");
    for (stem, _) in Preset::factory() {
        row(stem, &[], stem);
    }
    let top = [
        (ParamId::Modes, 2000.0),
        (ParamId::InPlaneModes, 200.0),
        (ParamId::BandLimit, 20_000.0),
        (ParamId::Polyphony, 16.0),
    ];
    row("gong, top of the ranges", &top, "gong-40N");
    row("cymbal, top of the ranges", &top, "crash");
    row("rectangular, top of the ranges", &top, "rect-plate");
}
