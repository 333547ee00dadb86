//! The CPU governor (`engine/governor.rs`): off, every note keeps the band it asks for; on
//! with a budget it cannot meet, a note starts on a smaller tier (a narrower band) and the
//! other voices end to make room, each reduction counted; on with a budget it meets, nothing
//! changes. No allocation in any of it. Bounded: a few notes of the factory gong, 0.2 s each.
//! The block-time watch is tested in `core/src/engine/governor.rs` (it depends on the
//! machine's load, so it is driven there with given block times).

use assert_no_alloc::assert_no_alloc;
use noether::engine::{Engine, Event, EventKind, ParamId};
use noether_testkit::presets::preset_params;
use std::time::Duration;

const BLOCK: usize = 256;

/// The factory gong-40N (510 modes, 15 in-plane), four voices, `cpu_budget` = `cores`.
fn gong(cores: f32) -> Engine {
    gong_with(&[(ParamId::CpuBudget, cores)], false)
}

/// The factory gong-40N, four voices, with `changes`, activated with the governor on (the
/// bank priced by trials, `engine/cost_trial.rs`) or off.
fn gong_with(changes: &[(ParamId, f32)], governed: bool) -> Engine {
    let mut all = vec![(ParamId::Polyphony, 4.0)];
    all.extend_from_slice(changes);
    let params = preset_params("gong-40N", &all);
    let (mut e, _h) = Engine::new(params);
    e.set_governor(governed);
    e.activate(48_000.0, BLOCK).unwrap();
    // No late voice jobs on a loaded machine (a late job holds the bank, and the voices'
    // read-outs wait for it): the bounce's wait.
    e.set_job_wait(Some(Duration::from_secs(10)));
    e
}

/// Plays `key` (velocity 1) for `blocks` blocks, without allocating.
fn play_for(e: &mut Engine, key: u8, blocks: usize) {
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let on = [Event::new(0, EventKind::NoteOn { key, velocity: 1.0 })];
    for i in 0..blocks {
        let events: &[Event] = if i == 0 { &on } else { &[] };
        assert_no_alloc(|| e.process_events(events, &mut l, &mut r));
        assert!(l.iter().chain(&r).all(|x| x.is_finite() && x.abs() <= 1.0));
    }
}

/// Plays `key` for 0.2 s.
fn play(e: &mut Engine, key: u8) {
    play_for(e, key, (0.2 * 48_000.0 / BLOCK as f64) as usize);
}

/// The transverse modes of the voice playing `key`.
fn modes_of(e: &Engine, key: u8) -> u32 {
    (0..e.polyphony())
        .find(|&s| e.voice_key(s) == Some(key))
        .and_then(|s| e.voice_model(s))
        .map(|m| m.n_phi)
        .expect("a voice plays the key")
}

#[test]
fn off_every_note_keeps_its_band() {
    let mut e = gong(0.001);
    play(&mut e, 60);
    play(&mut e, 62);
    assert_eq!(e.governor_counts(), (0, 0), "off by default");
    assert_eq!(e.active_voices(), 2);
    assert!(modes_of(&e, 60) > 100, "the root key's full band");
}

#[test]
fn on_with_a_budget_too_small_notes_narrow_and_voices_end() {
    let mut full = gong(0.001);
    play(&mut full, 60);
    let natural = modes_of(&full, 60);

    let mut e = gong(0.001);
    e.set_governor(true);
    play(&mut e, 60);
    let narrowed = modes_of(&e, 60);
    assert!(
        narrowed < natural,
        "a thousandth of a core: {narrowed} modes, not the band's {natural}"
    );
    assert_eq!(e.governor_counts().0, 1, "one note narrowed");
    // A second note does not fit beside the first: the first ends (a fade of 8 chunks,
    // long over after 0.2 s), the second plays.
    play(&mut e, 64);
    let (reduced, shed) = e.governor_counts();
    assert_eq!(reduced, 2);
    assert!(shed >= 1, "the first voice ended to make room");
    assert_eq!(e.active_voices(), 1);
    assert!(modes_of(&e, 64) < natural);
}

#[test]
fn on_with_room_nothing_changes() {
    // One block per note: the note-on's admission alone (the block-time watch averages over
    // 0.1 s, so it cannot act within these three blocks whatever the machine's load). The
    // gong at 128 modes: one voice costs a few hundredths of a core here (the full 510
    // modes 0.39, docs/performance.md), well within one voice's share on a machine several
    // times slower.
    let few = [(ParamId::CpuBudget, 64.0), (ParamId::Modes, 128.0)];
    let mut e = gong_with(&few, true);
    let mut full = gong_with(&few, false);
    for key in [60, 64, 67] {
        play_for(&mut e, key, 1);
        play_for(&mut full, key, 1);
        assert_eq!(modes_of(&e, key), modes_of(&full, key));
    }
    assert_eq!(e.governor_counts(), (0, 0));
    assert_eq!(e.active_voices(), 3);
}

/// The factory tanpura with `modes` modes and `cpu_budget` = `cores`, activated with the
/// governor on or off.
fn tanpura(modes: f32, cores: f32, governed: bool) -> Engine {
    let params = preset_params(
        "tanpura",
        &[
            (ParamId::Modes, modes),
            (ParamId::Polyphony, 2.0),
            (ParamId::CpuBudget, cores),
        ],
    );
    let (mut e, _h) = Engine::new(params);
    e.set_governor(governed);
    e.activate(48_000.0, BLOCK).unwrap();
    e.set_job_wait(Some(Duration::from_secs(10)));
    e
}

/// A string voice is one model, so the worker fits its mode count to one voice's share of the
/// budget when it builds the bank (`engine/string_bank.rs`, timed in thread CPU time). A
/// thousandth of a core holds no tanpura of 2000 modes (one costs about 3.6 cores here, and
/// the smallest trial string is far above a thousandth): the bank comes down to the fewest
/// modes, is reported, and plays a note without allocating. Offline (governor off) the
/// string keeps every mode; a bank kept across an activation is rebuilt when the governor
/// switches.
#[test]
fn a_string_too_costly_for_the_budget_is_built_with_fewer_modes() {
    let mut e = tanpura(2000.0, 0.001, true);
    let fitted = e.modes_fitted().expect("fitted to a thousandth of a core");
    assert_eq!(fitted.wanted, 2000);
    assert!(fitted.built < 100, "{fitted:?}");
    play(&mut e, 60);
    assert_eq!(e.active_voices(), 1);

    let mut off = tanpura(2000.0, 0.001, false);
    assert_eq!(off.modes_fitted(), None, "offline: every mode");
    off.set_governor(true);
    off.activate(48_000.0, BLOCK).unwrap();
    assert!(
        off.modes_fitted().is_some(),
        "rebuilt when the governor switched on"
    );
}

/// A cheap string keeps its modes under the default budget: the factory tanpura (166 modes at
/// 192 kHz) costs about 0.16 of a core (worst block 0.2-0.3 alone), below one voice's 70 % of a
/// core. On a loaded machine (this binary's other tests beside it, on a two-core VM) its trial
/// has measured up to about twice that, and the fresh-clone CI then fitted it to 109-124 modes;
/// so the test asks that it keeps at least half its modes. Alone, a string about eight times
/// as costly would be fitted below that (its worst window past 1.7 times the limit); the
/// 2000-mode string of the test above drops below 100.
#[test]
fn a_string_within_the_budget_keeps_its_modes() {
    let e = tanpura(166.0, 0.0, true);
    if let Some(fitted) = e.modes_fitted() {
        assert!(fitted.built >= 83, "{fitted:?}");
    }
}

/// One voice is held to its share of one core (`governor::voice_share`, 70 %) even where the
/// budget has room: its step runs on one thread, so a voice priced above the share would make
/// every block late however few voices sound. The bank is built offline and the governor
/// switched on without an activation, so its tiers keep their prior prices (2 ns per stored
/// tensor entry and mode) and the first note's admission does not depend on this machine's
/// speed: the gong's full band is priced at several cores, far inside a budget of 64 cores
/// and far above the share. It starts narrowed, and no other voice is ended; offline it keeps
/// its band.
#[test]
fn on_a_voice_is_held_to_its_share_of_a_core() {
    let roomy = [(ParamId::CpuBudget, 64.0)];
    let mut full = gong_with(&roomy, false);
    play_for(&mut full, 60, 2);
    let natural = modes_of(&full, 60);
    let mut e = gong_with(&roomy, false);
    e.set_governor(true);
    play_for(&mut e, 60, 2);
    let narrowed = modes_of(&e, 60);
    assert!(
        narrowed < natural,
        "one voice under 64 cores: {narrowed} modes, not the band's {natural}"
    );
    assert_eq!(e.governor_counts(), (1, 0), "narrowed, nothing ended");
}
