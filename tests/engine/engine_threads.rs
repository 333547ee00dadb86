//! The voice pool: the same events give the same output, bit for bit, whatever the number of
//! threads sharing the voices (`threads` 1, 0 = every core, 2), and nothing allocates, neither
//! in `process` on the audio thread (`assert_no_alloc`) nor in the workers' job loop (the test
//! allocator counts allocations on threads inside it, `noether_testkit::alloc`).
//!
//! The comparisons give the workers a 10 s wait (`Engine::set_job_wait`): a late job (a
//! pre-empted worker past the real-time wait) leaves its voice's chunk out of the mix by
//! design, which would make the outputs differ for a reason other than the arithmetic; the
//! tests check that no job was late.

use assert_no_alloc::assert_no_alloc;
use noether::engine::{Engine, Event, EventKind, ParamId, SharedParams};
use std::sync::Arc;
use std::time::Duration;

/// Plays `events` (one list per block) in blocks of `block(b)` samples with `threads` cycling
/// through `0..thread_counts`, each block under `assert_no_alloc` (which aborts the binary on
/// an allocation on the audio thread) with finite output, then deactivates the engine; returns
/// the allocations the test allocator counted inside the voice pool's job loops meanwhile.
pub fn job_allocations(
    e: &mut Engine,
    params: &SharedParams,
    events: &[Vec<Event>],
    block: impl Fn(usize) -> usize,
    thread_counts: usize,
) -> u64 {
    assert!(noether_testkit::alloc::installed());
    let before = noether_testkit::alloc::voice_job_allocations();
    let longest = (0..events.len()).map(&block).max().unwrap_or(0);
    let (mut l, mut r) = (vec![0.0f32; longest], vec![0.0f32; longest]);
    for (b, ev) in events.iter().enumerate() {
        let n = block(b);
        params
            .set(ParamId::Threads, (b % thread_counts) as f32)
            .unwrap();
        assert_no_alloc(|| e.process_events(ev, &mut l[..n], &mut r[..n]));
        assert!(l[..n].iter().chain(&r[..n]).all(|x| x.is_finite()));
    }
    e.deactivate();
    noether_testkit::alloc::voice_job_allocations() - before
}

/// Whether this machine gives the engine at least one worker (two cores or more).
pub fn has_workers() -> bool {
    std::thread::available_parallelism().is_ok_and(|n| n.get() >= 2)
}

/// A gong engine (the gong-40N preset with 4 voices at 60 modes and 10 in-plane modes, so a
/// test renders quickly) with `threads` participants, activated at 48 kHz, blocks of 256.
pub fn gong(threads: f32) -> (Engine, Arc<SharedParams>) {
    let (mut e, params) = super::engine_with(
        "gong-40N",
        &[
            (ParamId::Polyphony, 4.0),
            (ParamId::Modes, 60.0),
            (ParamId::InPlaneModes, 10.0),
            (ParamId::Threads, threads),
        ],
    );
    e.set_job_wait(Some(Duration::from_secs(10)));
    (e, params)
}

/// A polyphonic sequence: per 256-sample block, the events of that block. Four overlapping
/// notes (a fifth voice steals one), pitch bend, mod wheel, sustain and note-offs at offsets
/// inside the blocks, over `blocks` blocks.
pub fn sequence(blocks: usize, velocity: f32) -> Vec<Vec<Event>> {
    let keys = [48u8, 55, 60, 64, 67];
    (0..blocks)
        .map(|b| {
            let mut ev = Vec::new();
            if b % 12 == 0 && b / 12 < keys.len() {
                let key = keys[b / 12];
                ev.push(Event::new(17, EventKind::NoteOn { key, velocity }));
            }
            if b == 30 {
                ev.push(Event::new(100, EventKind::PitchBend(0.3)));
                ev.push(Event::new(101, EventKind::ModWheel(0.9)));
                ev.push(Event::new(200, EventKind::Sustain(true)));
            }
            if b == 40 {
                ev.push(Event::new(5, EventKind::NoteOff { key: 48 }));
                ev.push(Event::new(250, EventKind::Sustain(false)));
            }
            if b == 60 {
                ev.push(Event::new(0, EventKind::NoteOff { key: 55 }));
                ev.push(Event::new(0, EventKind::NoteOn { key: 72, velocity }));
            }
            ev
        })
        .collect()
}

/// Plays `seq` (one event list per 256-sample block) on `e`, each block under
/// `assert_no_alloc`; returns the interleaved stereo output.
pub fn interleaved(e: &mut Engine, seq: &[Vec<Event>]) -> Vec<f32> {
    let (mut l, mut r) = (vec![0.0f32; 256], vec![0.0f32; 256]);
    let mut out = Vec::with_capacity(seq.len() * 512);
    for ev in seq {
        assert_no_alloc(|| e.process_events(ev, &mut l, &mut r));
        out.extend(l.iter().zip(&r).flat_map(|(a, b)| [*a, *b]));
    }
    out
}

/// Renders `seq` with `threads`; returns the interleaved output and the engine.
fn render(threads: f32, seq: &[Vec<Event>]) -> (Vec<f32>, Engine) {
    let (mut e, _p) = gong(threads);
    (interleaved(&mut e, seq), e)
}

/// Index and values of the first sample where `a` and `b` differ in bits.
pub fn first_difference(a: &[f32], b: &[f32]) -> Option<(usize, f32, f32)> {
    a.iter()
        .zip(b)
        .enumerate()
        .find(|(_, (x, y))| x.to_bits() != y.to_bits())
        .map(|(i, (x, y))| (i, *x, *y))
}

/// Tolerance: none (bit for bit). Each voice writes its own buffer and the audio thread sums
/// them in voice order, so the threads change which core computes a voice, not one
/// floating-point operation. Negative control: the same comparison between two renders whose
/// only difference is one velocity (0.8 against 0.8001) finds a difference.
#[test]
fn threaded_output_is_bit_identical_to_the_audio_thread_alone() {
    let blocks = 90; // 0.48 s at 48 kHz
    let seq = sequence(blocks, 0.8);
    let (one, e1) = render(1.0, &seq);
    assert_eq!(e1.threads_used(), 1);
    assert_eq!(e1.worker_jobs(), 0, "threads = 1 must not use the workers");
    let peak = one.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    assert!(
        peak > 1e-3 && peak.is_finite(),
        "the sequence is silent: {peak}"
    );
    for threads in [0.0, 2.0] {
        let (many, e) = render(threads, &seq);
        assert_eq!(e.late_jobs(), 0, "threads {threads}: a job was late");
        if has_workers() {
            assert!(e.threads_used() >= 2, "threads {threads}");
            assert!(
                e.worker_jobs() > 0,
                "threads {threads}: no job ran on a worker"
            );
        }
        println!(
            "threads {threads}: {} participants, {} of the jobs on workers, peak {peak}",
            e.threads_used(),
            e.worker_jobs()
        );
        assert_eq!(
            first_difference(&one, &many),
            None,
            "threads {threads} differs from threads 1"
        );
    }
    // Negative control: the comparison sees a one-velocity change.
    let (other, _) = render(1.0, &sequence(blocks, 0.8001));
    assert!(first_difference(&one, &other).is_some());
}

/// `process` with the voices shared by every core: no allocation on the audio thread
/// (`assert_no_alloc` aborts the binary) nor on any worker inside its job loop (counted by the
/// test allocator; tolerance 0). Checked to run jobs on the workers, so it is not vacuous; the
/// counter itself was shown to catch an allocation planted in the job loop (one `Vec` per
/// wake of a worker: this test then failed with 630 allocations counted).
#[test]
fn threaded_process_never_allocates_in_any_thread() {
    let (mut e, params) = gong(0.0);
    // Block lengths 1 to 8192 samples; `threads` 0 to 3 changes block to block (no rebuild).
    let block = |b: usize| [256usize, 1, 64, 4000, 8192, 333][b % 6].min(256 + 31 * b);
    let during = job_allocations(&mut e, &params, &sequence(90, 1.0), block, 4);
    println!(
        "{} jobs on workers, {} allocations in job loops",
        e.worker_jobs(),
        during
    );
    if has_workers() {
        assert!(e.worker_jobs() > 0, "no job ran on a worker");
    }
    assert_eq!(during, 0, "allocations inside the voice pool's job loop");
}
