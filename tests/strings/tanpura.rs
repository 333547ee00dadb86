//! The tanpura drone (`noether::models::tanpura`): its strings sound the tuning table within a
//! cent, the cycle's plucks start on the pattern's instants, the variation moves them and is
//! repeatable, a long drone keeps its level and its power balance (ten minutes of it neither
//! grows nor fades), and bad specs name the field.

use noether::models::tanpura::{Pattern, Tanpura, TanpuraSpec, Tuning};

const FS: f64 = 48_000.0;

/// The frequency of string `s`'s first modal coordinate over steps `[from, to)` of the drone
/// (steps it there), read in the drone with every string sounding.
fn first_partial(t: &mut Tanpura, s: usize, from: u64, to: u64) -> f64 {
    super::crossings::first_partial(t, Tanpura::steps, s, FS, from, to)
}

/// Every string of the four standard tunings (on Sa = C#3) sounds its note within 1 cent,
/// measured in the drone from 0.3 to 0.75 s after its own pluck (before the next string's
/// pluck; the cycle is 4 s, a string every 0.8 s). Measured: within 0.04 cents (docs/models.md
/// table). Without tuning by ear the same strings are up to 3 cents sharp (the kharaj: the
/// seat, the bridge, the jawari and the stiffness all raise the pitch), so the test fails
/// without it.
#[test]
fn every_string_sounds_its_note_within_a_cent() {
    for tuning in Tuning::ALL {
        for by_ear in [true, false] {
            let mut spec = TanpuraSpec::at(138.59);
            spec.tuning = tuning;
            spec.tune_by_ear = by_ear;
            let mut t = Tanpura::build(&spec).unwrap();
            let gap = (0.8 * FS) as u64;
            let mut cents = Vec::new();
            for s in 0..4 {
                let onset = s as u64 * gap;
                let f = first_partial(
                    &mut t,
                    s,
                    onset + (0.3 * FS) as u64,
                    onset + (0.75 * FS) as u64,
                );
                cents.push(1200.0 * (f / spec.target_hz(s)).log2());
            }
            let worst = cents.iter().fold(0.0f64, |w, c| w.max(c.abs()));
            eprintln!("{tuning:?}, by ear {by_ear}: cents {cents:.3?}");
            if by_ear {
                assert!(worst < 1.0, "{tuning:?}: {cents:?}");
            } else {
                assert!(
                    worst > 1.0,
                    "{tuning:?} untuned is already in tune: {cents:?}"
                );
            }
        }
    }
}

/// The step at which each pluck of the first `cycles` cycles started, per string: where the
/// string's work account jumped (a pluck's energy is counted as work).
fn onsets(t: &mut Tanpura, steps: u64) -> Vec<Vec<u64>> {
    let n = t.network().strings().len();
    let mut out = vec![Vec::new(); n];
    let mut work: Vec<f64> = (0..n).map(|s| t.network().string_energy(s).work).collect();
    while t.steps() < steps {
        let at = t.steps();
        t.step();
        for (s, w) in work.iter_mut().enumerate() {
            let now = t.network().string_energy(s).work;
            if now != *w {
                out[s].push(at);
                *w = now;
            }
        }
    }
    out
}

/// The cycle's onsets, read from the strings (their work jumps), lie on the pattern's
/// instants within 1 ms: classic, string `i` of 4 at `(c + i/5) P`; even, at `(c + i/4) P`
/// (three cycles of 2 s). With 20 ms of timing variation the onsets move (some by more than
/// 1 ms), never by more than 20 ms, and the same seed repeats them exactly.
#[test]
fn the_cycle_plucks_on_the_pattern() {
    let period = 2.0;
    for (pattern, denom) in [(Pattern::Classic, 5.0), (Pattern::Even, 4.0)] {
        let mut spec = TanpuraSpec::at(138.59);
        spec.cycle_seconds = period;
        spec.pattern = pattern;
        spec.tune_by_ear = false;
        let got = onsets(
            &mut Tanpura::build(&spec).unwrap(),
            (3.0 * period * FS) as u64,
        );
        for (s, list) in got.iter().enumerate() {
            assert_eq!(list.len(), 3, "{pattern:?} string {s}: {list:?}");
            for (c, &step) in list.iter().enumerate() {
                let want = (c as f64 + s as f64 / denom) * period;
                let err = (step as f64 / FS - want).abs();
                assert!(err < 1e-3, "{pattern:?} string {s} cycle {c}: {err} s");
            }
        }
        spec.timing_jitter_ms = 20.0;
        spec.strength_jitter = 0.2;
        let a = onsets(
            &mut Tanpura::build(&spec).unwrap(),
            (3.0 * period * FS) as u64,
        );
        let b = onsets(
            &mut Tanpura::build(&spec).unwrap(),
            (3.0 * period * FS) as u64,
        );
        assert_eq!(a, b, "the seed does not repeat the variation");
        let moved: Vec<f64> = a
            .iter()
            .zip(&got)
            .flat_map(|(x, y)| {
                x.iter()
                    .zip(y)
                    .map(|(p, q)| (*p as f64 - *q as f64).abs() / FS)
            })
            .collect();
        assert!(moved.iter().all(|&d| d <= 0.020 + 1.0 / FS), "{moved:?}");
        assert!(moved.iter().any(|&d| d > 1e-3), "no variation: {moved:?}");
    }
}

/// Plays `cycles` cycles of `cycle` steps of the drone: the largest energy (J) of each cycle,
/// and the largest drift of the power balance over the largest energy.
fn cycle_peaks(t: &mut Tanpura, cycle: u64, cycles: u64) -> (Vec<f64>, f64) {
    let b0 = t.network().energy_terms().balance();
    let (mut peaks, mut peak, mut worst, mut e_max) = (Vec::new(), 0.0f64, 0.0f64, 0.0f64);
    while t.steps() < cycles * cycle {
        t.step();
        let e = t.network().energy_terms();
        peak = peak.max(e.total());
        e_max = e_max.max(e.total());
        worst = worst.max((e.balance() - b0).abs());
        if t.steps() % cycle == 0 {
            peaks.push(peak);
            peak = 0.0;
        }
    }
    (peaks, worst / e_max)
}

/// A 40 s drone (ten cycles of 4 s) keeps its level: the largest energy in each of the last
/// five cycles is within 10 % of the second cycle's (the first has no ringing strings yet), and
/// the power balance closes to 1e-11 of the largest energy (measured in docs/models.md).
#[test]
fn a_long_drone_keeps_its_level_and_its_balance() {
    let spec = TanpuraSpec::at(138.59);
    let mut t = Tanpura::build(&spec).unwrap();
    let cycle = (spec.cycle_seconds * spec.sim_rate) as u64;
    let (peaks, balance) = cycle_peaks(&mut t, cycle, 10);
    let rel: Vec<f64> = peaks.iter().map(|p| p / peaks[1]).collect();
    eprintln!(
        "cycle peaks / second cycle's: {rel:.4?}; balance {:.2e}",
        balance
    );
    assert!(rel[5..].iter().all(|r| (r - 1.0).abs() < 0.1), "{rel:?}");
    assert!(balance < 1e-11, "balance {:.2e}", balance);
}

/// Bad specs are refused with the field named.
#[test]
fn bad_tanpura_specs_name_the_field() {
    let field = |f: &dyn Fn(&mut TanpuraSpec)| {
        let mut spec = TanpuraSpec::at(138.59);
        f(&mut spec);
        spec.validate().unwrap_err().field
    };
    assert_eq!(field(&|s| s.sa = 5.0), "tanpura.sa");
    assert_eq!(field(&|s| s.strings = 7), "tanpura.strings");
    assert_eq!(field(&|s| s.jivari_mm = vec![1.0]), "tanpura.jivari_mm[0]");
    assert_eq!(
        field(&|s| s.jivari_mm = vec![5.0, 5.0]),
        "tanpura.jivari_mm"
    );
    assert_eq!(
        field(&|s| s.fine_cents = vec![0.0, 0.0, 0.0, 300.0]),
        "tanpura.fine_cents[3]"
    );
    assert_eq!(field(&|s| s.cycle_seconds = 0.0), "tanpura.cycle_seconds");
}

/// The jivari makes the buzz: string 1 plucked alone (a 30 s cycle: the first pluck only), the
/// share of the output's power above 3 kHz from 1.5 to 2.5 s after the pluck is at least 100
/// times larger with the thread (jivari 5 mm) than without it (measured in docs/models.md:
/// the jawari keeps feeding the upper partials while the losses empty them on a free string).
/// Fails when the jivari is ignored (both runs alike).
#[test]
fn the_jivari_keeps_the_upper_partials_sounding() {
    use noether::render::metrics::{power_frames, LSD_HOP, LSD_WINDOW};
    use noether::render::source::RenderSource;
    let high_share = |jivari: f64| {
        let mut spec = TanpuraSpec::at(138.59);
        spec.cycle_seconds = 30.0;
        spec.jivari_mm = vec![jivari];
        spec.tune_by_ear = false;
        let mut t = Tanpura::build(&spec).unwrap();
        let n = (2.5 * FS) as usize;
        let mut out = vec![vec![0.0; n]; 2];
        t.process(&mut out, n);
        let frames = power_frames(&out[0]);
        let first = (1.5 * FS) as usize / LSD_HOP;
        let cut = 3000 * LSD_WINDOW / FS as usize;
        let (mut high, mut all) = (0.0, 0.0);
        for f in &frames[first..] {
            high += f[cut..].iter().sum::<f64>();
            all += f.iter().sum::<f64>();
        }
        high / all
    };
    let (with, without) = (high_share(5.0), high_share(0.0));
    eprintln!("power above 3 kHz, 1.5-2.5 s: {with:.2e} with the jivari, {without:.2e} without");
    assert!(with > 100.0 * without, "with {with:e}, without {without:e}");
}

/// The long-performance test: a 10-minute drone (150 cycles of 4 s) neither grows nor fades.
/// The strings here are coarser than the factory drone's (120 modes at 32 kHz, the jivari at
/// 15 mm, the second node beyond the seat: the same network, scheme and cycle at about a third
/// of the per-step work), so ten minutes take under two minutes of CPU. The mean of the
/// largest energies of the last ten cycles is within 0.5 % of that of cycles 5 to 14 (the
/// ringing has built up by the fifth): a drift of 1e-4 per cycle would move it by 1.4 %.
/// Single cycles differ from that mean by up to 3 % (2.6 % measured) as the strings' phases
/// meet differently. The power balance closes to 1e-9 of the largest energy (the accounts' round-off summed over 19 million steps).
#[test]
fn a_ten_minute_drone_neither_grows_nor_fades() {
    let mut spec = TanpuraSpec::at(138.59);
    spec.modes = 120;
    spec.sim_rate = 32_000.0;
    spec.jivari_mm = vec![15.0];
    let mut t = Tanpura::build(&spec).unwrap();
    let cycle = (spec.cycle_seconds * spec.sim_rate) as u64;
    let (peaks, balance) = cycle_peaks(&mut t, cycle, 150);
    let mean = |c: &[f64]| c.iter().sum::<f64>() / c.len() as f64;
    let early = mean(&peaks[4..14]);
    let last = mean(&peaks[140..]) / early - 1.0;
    let far = peaks[4..]
        .iter()
        .fold(0.0f64, |m, p| m.max((p / early - 1.0).abs()));
    eprintln!(
        "10 min drone: last ten cycles {last:+.2e} of cycles 5-14 (single cycles within \
         {far:.2e}); balance {:.2e}",
        balance
    );
    assert!(last.abs() < 5e-3, "the drone moved by {last:+.3e}");
    assert!(balance < 1e-9, "balance {:.2e}", balance);
}

/// Sa moved by the held key: the drone tuned by ear on C#3 and at four anchor keys (an octave
/// and a tritone down and up, [`Tanpura::build_for_keys`]) and retuned by its tensions
/// ([`Tanpura::retune`]) to keys on and between the anchors. Every string sounds its note
/// within 1 cent (the tuning's own target), over the same window as the tuning test. Without
/// the anchors the tensions alone leave it 3 to 4 cents sharp an octave down (measured in
/// docs/models.md), so that case fails. The strength scales the plucks and a released drone
/// (plucking off, a floor under the decay) falls silent; a reset starts the cycle again.
#[test]
fn a_retuned_drone_sounds_the_held_key() {
    let spec = TanpuraSpec::at(138.59);
    let gap = (0.8 * FS) as u64;
    let cents_at = |t: &mut Tanpura, semitones: f64| {
        let ratio = 2f64.powf(semitones / 12.0);
        t.reset();
        t.retune(ratio, 0.0).unwrap();
        (0..4)
            .map(|s| {
                let onset = s as u64 * gap;
                let from = onset + (0.3 * FS) as u64;
                let f = first_partial(t, s, from, onset + (0.75 * FS) as u64);
                1200.0 * (f / (ratio * spec.target_hz(s))).log2()
            })
            .collect::<Vec<f64>>()
    };
    let worst = |c: &[f64]| c.iter().fold(0.0f64, |w, c| w.max(c.abs()));
    let mut alone = Tanpura::build(&spec).unwrap();
    let off = cents_at(&mut alone, -12.0);
    assert!(worst(&off) > 1.0, "in tune without anchors: {off:?}");
    let mut t = Tanpura::build_for_keys(&spec, &[-12.0, -6.0, 6.0, 12.0]).unwrap();
    let mut report = Vec::new();
    for semitones in [-12.0f64, -9.0, -2.0, 3.0, 7.0, 12.0] {
        let cents = cents_at(&mut t, semitones);
        report.push((semitones, cents.clone()));
        assert!(
            worst(&cents) < 1.0,
            "{semitones} semitones: cents {cents:?}"
        );
    }
    eprintln!("retuned drone, cents per string: {report:.3?}; without anchors at -12: {off:.3?}");
    assert!(t.retune(f64::NAN, 0.0).is_err() && t.retune(1.0, -1.0).is_err());
    assert!(t.set_strength(10.5).is_err() && t.set_strength(-0.1).is_err());

    // Half strength: the first pluck brings a quarter of the energy (the pluck's energy is
    // quadratic in its amplitude), to round-off.
    let first_work = |t: &mut Tanpura| {
        t.reset();
        t.step();
        t.network().energy_terms().total()
    };
    t.retune(1.0, 0.0).unwrap();
    let full = first_work(&mut t);
    t.set_strength(0.5).unwrap();
    let half = first_work(&mut t);
    assert!((half / full - 0.25).abs() < 1e-9, "{}", half / full);

    // Released: no more plucks, every mode decays at least at 60 dB in 0.5 s.
    t.set_strength(1.0).unwrap();
    t.reset();
    while t.steps() < 3 * gap {
        t.step();
    }
    let held = t.network().energy_terms().total();
    t.set_plucking(false);
    t.retune(1.0, 3.0 * 10f64.ln() / 0.5).unwrap();
    while t.steps() < 3 * gap + (1.0 * FS) as u64 {
        t.step();
    }
    let released = t.network().energy_terms().total();
    assert!(released < 1e-9 * held, "{released:e} of {held:e}");
}

/// The drone's stepping-thread methods (step, retune, strength, plucking, reset) do not
/// allocate (the binary's counting allocator); the retune interpolates the anchors' table in
/// place.
#[test]
fn the_drone_plays_and_retunes_without_allocating() {
    let mut spec = TanpuraSpec::at(138.59);
    spec.modes = 120;
    spec.jivari_mm = vec![15.0];
    let mut t = Tanpura::build_for_keys(&spec, &[-12.0, 12.0]).unwrap();
    let n = noether_testkit::alloc::count_allocations(|| {
        for k in 0..4 {
            t.retune(2f64.powf((k as f64 - 2.0) / 5.0), 0.0).unwrap();
            t.set_strength(0.25 * k as f64).unwrap();
            for _ in 0..2000 {
                t.step();
            }
        }
        t.set_plucking(false);
        t.retune(1.0, 20.0).unwrap();
        for _ in 0..2000 {
            t.step();
        }
        t.reset();
        t.set_plucking(true);
        t.step();
        // The stepping thread's retune refuses without allocating, and leaves the pitch.
        assert!(t.try_retune(f64::NAN, 1.0, 0.0).is_err());
        assert!(t.try_retune(1.0, -1.0, 0.0).is_err());
        assert_eq!(t.ratio(), 1.0);
        // A new cycle timing, from the next cycle.
        t.set_cycle(2.0, noether::models::tanpura::Pattern::Even, 5.0, 0.1)
            .unwrap();
        t.step();
    })
    .1;
    assert_eq!(n, 0, "allocations in the drone's real-time methods");
}

/// The jawari's sweep: string 1 of the drone (Pa, 103.9 Hz, 480 modes) plucked alone, at
/// 192 kHz, where only its top 85 modes (to 137 kHz through its stiffness) lie above the
/// Nyquist frequency (at 48 kHz 310 do: docs/models.md, "The drone's grid and rate"). The band of harmonics louder than the
/// spectrum's trend is followed as a ridge ([`noether::analysis::formant::formant_ridge`])
/// every 50 ms from 0.05 to 0.95 s. With the jivari at 5 mm it moves down: it ends at most two
/// thirds of where it began and steps down in at least five of the eighteen intervals (a
/// moving band; measured: from harmonic 35 to 11, down in nine). Without the thread the bands
/// stand: the ridge holds harmonic 36 for half a second and then jumps to the next standing
/// band (measured: down in two intervals), so the test fails when the jivari is ignored.
/// Tuning by ear is off (the pitch does not matter here; the harmonics are looked for within
/// 1.5 % of the nominal ones).
#[test]
fn the_jivari_sweeps_a_formant_down() {
    use noether::analysis::formant::formant_ridge;
    use noether::models::network::BridgeInstrument;
    let rate = 192_000.0;
    let track = |jivari: f64| {
        let mut spec = TanpuraSpec::at(138.59);
        spec.cycle_seconds = 30.0;
        spec.sim_rate = rate;
        spec.tune_by_ear = false;
        spec.jivari_mm = vec![jivari];
        let mut t = Tanpura::build(&spec).unwrap();
        let mut x = Vec::new();
        while t.steps() < (1.2 * rate) as u64 {
            t.step();
            let [l, r] = t.network().bridge_force_mix(t.gains());
            x.push(l + r);
        }
        let times: Vec<f64> = (1..=19).map(|k| 0.05 * k as f64).collect();
        let frames = formant_ridge(&x, rate, spec.target_hz(0), &times);
        assert_eq!(frames.len(), times.len());
        frames.iter().map(|f| f.harmonic).collect::<Vec<usize>>()
    };
    let sweeps = |h: &[usize]| {
        let downs = h.windows(2).filter(|w| w[1] < w[0]).count();
        3 * h[h.len() - 1] <= 2 * h[0] && downs >= 5
    };
    let with = track(5.0);
    let without = track(0.0);
    eprintln!("formant ridge every 50 ms: jivari {with:?}, no thread {without:?}");
    assert!(sweeps(&with), "no sweep with the jivari: {with:?}");
    assert!(!sweeps(&without), "a sweep without the thread: {without:?}");
}
