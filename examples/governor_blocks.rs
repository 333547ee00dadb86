//! Block times of random parameter sets played as a live host plays them, without and with
//! the CPU governor (`engine/governor.rs`): the measurement behind docs/robustness.md,
//! "Processing in bounded time".
//!
//! Each set draws every parameter as the soak does (`noether_testkit::soak::Draw::value`:
//! uniform over its range, logarithmically where the table says so, and exactly its minimum or
//! its maximum one time in ten each; the seed is fixed, so the sets are the same on every
//! run), except `threads` (0: every core) and `cpu_budget` (0: 70 % of the cores). The engine activates and builds the
//! model (the time is printed), then plays four notes 0.25 s apart at velocity 1 in blocks of
//! 512 samples at 48 kHz for `SECONDS`, timing every block on the wall clock against its
//! duration (10.7 ms). Without the governor a run stops after 20 s of wall time (a model of
//! the top of the quality ranges costs minutes per second of audio); the row then shows the
//! blocks it played.
//!
//! `cargo run --release --example governor_blocks [-- SETS [SECONDS [on [PAUSE]]]]` (defaults
//! 20 and 2; `on`: the governed runs only, for many sets, the ungoverned column left empty;
//! `PAUSE`: seconds to wait before each set, so the machine settles after the previous one:
//! a set at the top of the ranges frees gigabytes and writes its modes to the disk cache, and
//! the kernel's work on that lands in the next sets' blocks).

use noether::engine::{Engine, Event, EventKind, ParamId, ParamValues, SharedParams, PARAMS};
use noether_testkit::soak::Draw;
use std::sync::Arc;
use std::time::{Duration, Instant};

const RATE: f64 = 48_000.0;
const BLOCK: usize = 512;

/// Block-time ratios (wall over duration) of one run.
struct Run {
    blocks: usize,
    mean: f64,
    max: f64,
    cut: bool,
    counts: (u64, u64),
}

/// Activates `e` with the governor on or off (a string bank is fitted to the budget when it
/// is built, so each mode activates on its own), then plays.
fn run(e: &mut Engine, seconds: f64, governor: bool) -> Run {
    e.set_governor(governor);
    if let Err(err) = e.activate(RATE, BLOCK) {
        panic!("re-activation refused: {err}");
    }
    let n = (seconds * RATE) as usize / BLOCK;
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let (mut sum, mut max, mut blocks) = (0.0, 0.0f64, 0);
    let start = Instant::now();
    let before = e.governor_counts();
    let mut cut = false;
    for b in 0..n {
        let t = b * BLOCK;
        let note = (0..4).find(|k| t == (k * 12_000 / BLOCK) * BLOCK);
        let ev = note.map(|k| {
            [Event::new(
                0,
                EventKind::NoteOn {
                    key: 48 + 5 * k as u8,
                    velocity: 1.0,
                },
            )]
        });
        let events: &[Event] = ev.as_ref().map_or(&[], |e| &e[..]);
        let t0 = Instant::now();
        e.process_events(events, &mut l, &mut r);
        let ratio = t0.elapsed().as_secs_f64() / (BLOCK as f64 / RATE);
        sum += ratio;
        max = max.max(ratio);
        blocks += 1;
        if !governor && start.elapsed() > Duration::from_secs(20) {
            cut = true;
            break;
        }
    }
    let after = e.governor_counts();
    Run {
        blocks,
        mean: sum / blocks.max(1) as f64,
        max,
        cut,
        counts: (after.0 - before.0, after.1 - before.1),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let sets: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(20);
    let seconds: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(2.0);
    let only_on = args.get(3).is_some_and(|a| a == "on");
    let pause: f64 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(0.0);
    let mut draw = Draw::new(0x005e_ed0f_b10c);
    println!(
        "| set | model, modes x in-plane, band, polyphony | build s | off: blocks, mean, max | on: mean, max | narrowed, ended | string fitted |"
    );
    println!("| --- | --- | ---: | --- | --- | --- | --- |");
    let (mut worst_on, mut mean_on_max) = (0.0f64, 0.0f64);
    let (mut worsts, mut means) = (Vec::new(), Vec::new());
    for i in 0..sets {
        let mut v = ParamValues::defaults();
        for p in PARAMS {
            v.0[p.id.index()] = draw.value(p);
        }
        v.0[ParamId::Threads.index()] = 0.0;
        v.0[ParamId::CpuBudget.index()] = 0.0;
        let params = Arc::new(SharedParams::new());
        if let Err(err) = params.set_all(&v) {
            println!("| {i} | refused: {err} | | | | | |");
            continue;
        }
        std::thread::sleep(Duration::from_secs_f64(pause));
        let (mut e, _h) = Engine::new(params);
        let t0 = Instant::now();
        e.set_governor(true);
        if let Err(err) = e.activate(RATE, BLOCK) {
            println!("| {i} | not built: {err} | | | | | |");
            continue;
        }
        let build = t0.elapsed().as_secs_f64();
        let fitted = e.modes_fitted();
        // The governor first, from the bank's prior cost (the run without it teaches nothing
        // the governor would use, but keep the order honest).
        let on = run(&mut e, seconds, true);
        let off = if only_on {
            Run {
                blocks: 0,
                mean: f64::NAN,
                max: f64::NAN,
                cut: false,
                counts: (0, 0),
            }
        } else {
            run(&mut e, seconds, false)
        };
        worst_on = worst_on.max(on.max);
        mean_on_max = mean_on_max.max(on.mean);
        worsts.push(on.max);
        means.push(on.mean);
        let name = noether::engine::MODEL_NAMES
            .get(v.index_of(ParamId::Model))
            .copied()
            .unwrap_or("?");
        println!(
            "| {i} | {}, {} x {}, {:.0} Hz, {} | {build:.1} | {}{}, {:.2}, {:.1} | {:.2}, {:.2} | {}, {} | {} |",
            name.split_whitespace().next().unwrap_or(name),
            v.index_of(ParamId::Modes),
            v.index_of(ParamId::InPlaneModes),
            v.get(ParamId::BandLimit),
            v.index_of(ParamId::Polyphony),
            off.blocks,
            if off.cut { " (cut)" } else { "" },
            off.mean,
            off.max,
            on.mean,
            on.max,
            on.counts.0,
            on.counts.1,
            fitted.map_or("-".to_string(), |f| format!("{} of {}", f.built, f.wanted)),
        );
    }
    println!("with the governor: worst block {worst_on:.2} of its duration, largest mean {mean_on_max:.2}");
    worsts.sort_by(f64::total_cmp);
    means.sort_by(f64::total_cmp);
    let at = |v: &[f64], q: f64| v[((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1];
    if !worsts.is_empty() {
        println!(
            "{} sets built: worst block median {:.2}, p99 {:.2}; mean median {:.2}, p99 {:.2}; {} sets with a block above 2, {} with a mean above 1",
            worsts.len(),
            at(&worsts, 0.5),
            at(&worsts, 0.99),
            at(&means, 0.5),
            at(&means, 0.99),
            worsts.iter().filter(|&&w| w > 2.0).count(),
            means.iter().filter(|&&m| m > 1.0).count()
        );
    }
}
