//! One heavy voice on two cores: a plate voice whose coupling tensor has at least
//! `SPLIT_MIN_ENTRIES` entries offers the second half of each step to the voice pool's workers
//! (`models::plate::step_board`), with a bounded wait and the owner computing the half itself
//! when no worker takes it in time.
//!
//! - The output does not depend on the thread count, bit for bit: the split's summation order
//!   is fixed whoever runs the half (with `threads` 1 the voice runs both halves itself).
//!   Tolerance: none. Negative control: a 1e-4 change of the velocity changes the output.
//! - With workers, they do run halves (the test is not vacuous).
//! - Nothing allocates, on the audio thread (`assert_no_alloc`) or in a worker's job loop,
//!   which includes its help on the board (the test allocator; tolerance 0).

use super::engine_threads::{first_difference, has_workers, interleaved, job_allocations};
use assert_no_alloc::assert_no_alloc;
use noether::engine::{Engine, Event, EventKind, ParamId, SharedParams};
use noether::models::plate::SPLIT_MIN_ENTRIES;
use std::sync::Arc;

/// The gong-40N preset with a 9 kHz band: its root key keeps about 800 strike-mirror modes
/// (15 in-plane), a tensor of about 2e5 entries, above `SPLIT_MIN_ENTRIES`; one voice.
fn heavy_gong(threads: f32) -> (Engine, Arc<SharedParams>) {
    super::engine_with(
        "gong-40N",
        &[
            (ParamId::Polyphony, 1.0),
            (ParamId::BandLimit, 9000.0),
            (ParamId::Modes, 900.0),
            (ParamId::Threads, threads),
        ],
    )
}

/// One root-key note (C4) struck at `velocity`, `blocks` blocks of 256 samples.
fn note(blocks: usize, velocity: f32) -> Vec<Vec<Event>> {
    (0..blocks)
        .map(|b| {
            if b == 0 {
                vec![Event::new(7, EventKind::NoteOn { key: 60, velocity })]
            } else {
                Vec::new()
            }
        })
        .collect()
}

/// Renders `seq` with `threads`; returns the interleaved output and the engine.
fn render(threads: f32, seq: &[Vec<Event>]) -> (Vec<f32>, Engine) {
    let (mut e, _p) = heavy_gong(threads);
    (interleaved(&mut e, seq), e)
}

#[test]
fn a_split_voice_sounds_the_same_on_one_or_two_threads() {
    let seq = note(40, 1.0); // 0.21 s
    let (one, e1) = render(1.0, &seq);
    let model = e1.voice_model(0).expect("the note's voice");
    println!(
        "root key: {} x {} modes at {} Hz; split from {SPLIT_MIN_ENTRIES} entries",
        model.n_phi, model.n_psi, model.sim_rate
    );
    assert_eq!(e1.shared_step_halves(), 0, "threads = 1 shares nothing");
    let peak = one.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    assert!(peak > 1e-3 && peak.is_finite(), "silent: {peak}");
    let (two, e2) = render(0.0, &seq);
    println!(
        "threads 0: {} halves on a worker, {} late",
        e2.shared_step_halves(),
        e2.late_step_halves()
    );
    if has_workers() {
        assert!(e2.shared_step_halves() > 0, "no half ran on a worker");
    }
    assert_eq!(
        first_difference(&one, &two),
        None,
        "threads 0 differs from threads 1"
    );
    let (other, _) = render(1.0, &note(40, 0.9999));
    assert!(first_difference(&one, &other).is_some());
}

#[test]
fn split_steps_never_allocate_in_any_thread() {
    let (mut e, params) = heavy_gong(0.0);
    // Block lengths 1 to 4096; `threads` 0 to 2 changes block to block (no rebuild).
    let block = |b: usize| [256usize, 1, 64, 4096, 333][b % 5];
    let during = job_allocations(&mut e, &params, &note(30, 1.0), block, 3);
    println!(
        "{} halves on a worker, {} allocations in job loops",
        e.shared_step_halves(),
        during
    );
    if has_workers() {
        assert!(e.shared_step_halves() > 0, "no half ran on a worker");
    }
    assert_eq!(during, 0, "allocations inside the voice pool's job loop");
}

/// A rebuild while the split voice sounds: the old bank (whose voice may still have a half on
/// the board or with a worker) cross-fades out and leaves the audio thread only when the pool
/// is quiescent; nothing allocates, the output stays finite, and the new bank's voice splits
/// its steps too.
#[test]
fn a_rebuild_under_a_split_voice_is_safe() {
    let (mut e, params) = heavy_gong(0.0);
    let (mut l, mut r) = (vec![0.0f32; 256], vec![0.0f32; 256]);
    let first = e.bank_id();
    let on = [Event::new(
        0,
        EventKind::NoteOn {
            key: 60,
            velocity: 1.0,
        },
    )];
    let mut swapped_at = None;
    // At most 20 000 blocks (107 s of audio): the rebuild takes about a second of wall time.
    for b in 0..20_000 {
        if b == 10 {
            params.set(ParamId::InPlaneModes, 14.0).unwrap();
        }
        let ev: &[Event] = if b == 0 || swapped_at == Some(b) {
            &on
        } else {
            &[]
        };
        assert_no_alloc(|| e.process_events(ev, &mut l, &mut r));
        assert!(l.iter().chain(&r).all(|x| x.is_finite()), "block {b}");
        if swapped_at.is_none() && e.bank_id() != first {
            swapped_at = Some(b + 1);
        }
        if swapped_at.is_some_and(|s| b > s + 20) {
            break;
        }
    }
    let swapped = swapped_at.expect("the rebuild arrived");
    let halves = e.shared_step_halves();
    println!("bank swapped at block {swapped}; {halves} halves on a worker");
    if has_workers() {
        assert!(halves > 0, "no half ran on a worker");
    }
    e.deactivate();
}
