//! The voice pool under stress: workers that are late on purpose (a zero wait), and the
//! lifecycle (deactivate, re-activate, drop) joining the workers without hanging.

use assert_no_alloc::assert_no_alloc;
use noether::engine::{Engine, Event, EventKind, ParamId, SharedParams};
use noether_testkit::presets::preset_params;
use std::sync::mpsc;
use std::sync::Arc;
use std::time::Duration;

fn gong(voices: f32) -> (Engine, Arc<SharedParams>) {
    let params = preset_params(
        "gong-40N",
        &[
            (ParamId::Polyphony, voices),
            (ParamId::Modes, 80.0),
            (ParamId::InPlaneModes, 15.0),
            (ParamId::Threads, 0.0),
        ],
    );
    let (mut e, _h) = Engine::new(params.clone());
    e.activate(48_000.0, 512).unwrap();
    (e, params)
}

fn note(offset: u32, key: u8) -> Event {
    Event::new(offset, EventKind::NoteOn { key, velocity: 0.9 })
}

/// With a zero wait, the audio thread never waits for a worker: the workers' jobs are often
/// late, which exercises the late path (the voice's chunk left out, the bank held aside while
/// its job runs, events kept and applied when it returns). Checks, every block: no allocation
/// (`assert_no_alloc`), finite output below 1e4 (eight plate voices at velocity 0.9 peak near
/// 2; a voice run twice at once or a bank dropped under a worker would show as garbage or a
/// crash); at the end, with the wait back to 10 s: every note-on kept (none lost), every voice
/// released by the final all-notes-off and the bank back in use. Late jobs must have happened
/// (on a machine with two cores or more), or the test did not test the path.
#[test]
fn late_workers_keep_output_sound_and_events() {
    if std::thread::available_parallelism().map_or(1, |n| n.get()) < 2 {
        println!("one core: no worker, nothing to test");
        return;
    }
    let (mut e, _p) = gong(8.0);
    e.set_job_wait(Some(Duration::ZERO));
    let (mut l, mut r) = (vec![0.0f32; 512], vec![0.0f32; 512]);
    let mut late_seen = 0;
    for b in 0..400u32 {
        let key = 40 + (b % 24) as u8;
        let events = [
            note(3, key),
            Event::new(300, EventKind::NoteOff { key: key - 5 }),
        ];
        let n = [512usize, 64, 7, 200][b as usize % 4];
        assert_no_alloc(|| e.process_events(&events, &mut l[..n], &mut r[..n]));
        let worst = l[..n]
            .iter()
            .chain(&r[..n])
            .fold(0.0f32, |m, x| m.max(x.abs()));
        assert!(
            worst.is_finite() && worst < 1e4,
            "block {b}: output {worst}"
        );
        late_seen = e.late_jobs();
    }
    e.set_job_wait(Some(Duration::from_secs(10)));
    e.process_events(&[Event::new(0, EventKind::AllSoundOff)], &mut l, &mut r);
    for _ in 0..4 {
        e.process(&mut l, &mut r);
    }
    println!(
        "late jobs {late_seen}, worker jobs {}, events lost {}",
        e.worker_jobs(),
        e.deferred_events_lost()
    );
    assert!(
        late_seen > 0,
        "no job was late: the late path was not exercised"
    );
    assert_eq!(e.deferred_events_lost(), 0);
    assert_ne!(e.bank_id(), 0);
    assert_eq!(e.polyphony(), 8);
    assert_eq!(
        e.active_voices(),
        0,
        "all-sound-off did not reach the voices"
    );
}

/// Deactivate / re-activate at other rates and dropping the engine join the workers (a
/// worker in the middle of a voice finishes it first) within 60 s: the sequence runs on a
/// helper thread and the test fails if it does not report back. Each activation plays notes
/// with every core, and between deactivate and activate the engine still processes, on the
/// audio thread alone.
#[test]
fn lifecycle_joins_workers_without_hanging() {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let (mut e, _p) = gong(4.0);
        let (mut l, mut r) = (vec![0.0f32; 512], vec![0.0f32; 512]);
        for (i, rate) in [44_100.0, 96_000.0, 48_000.0, 22_050.0]
            .into_iter()
            .enumerate()
        {
            for k in 0..4 {
                e.note_on(50 + 7 * k, 1.0);
            }
            for _ in 0..20 {
                e.process(&mut l, &mut r);
            }
            e.deactivate();
            e.process(&mut l, &mut r);
            assert_eq!(
                e.threads_used(),
                1,
                "activation {i}: no pool after deactivate"
            );
            e.activate(rate, 512).unwrap();
            for _ in 0..5 {
                e.process(&mut l, &mut r);
            }
        }
        // Drop in the middle of playing (workers parked or spinning).
        e.note_on(60, 1.0);
        e.process(&mut l, &mut r);
        let jobs = e.worker_jobs();
        drop(e);
        tx.send(jobs).unwrap();
    });
    let jobs = rx
        .recv_timeout(Duration::from_secs(60))
        .expect("the lifecycle hung (or panicked) within 60 s");
    println!("{jobs} jobs on workers over the lifecycle");
}
