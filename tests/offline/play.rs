//! `noether play`: presets played through the real-time engine as the plugin plays them
//! (src/render/play.rs, src/render/midi.rs, src/cli/play.rs).

use midly::num::{u15, u24, u28, u4, u7};
use midly::{Format, Header, MetaMessage, MidiMessage, Smf, Timing, TrackEvent, TrackEventKind};
use noether::analysis::fundamental::fundamental_near;
use noether::engine::{KeyTuning, ParamId, Preset};
use noether::render::play::{notes_timeline, play, NoteSpec, PlaySettings};
use noether::render::preset_engine::find_preset;
use std::path::PathBuf;
use std::process::{Command, Output};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("noether-play-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn noether(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_noether"))
        .args(args)
        .env("NOETHER_CACHE", noether_testkit::env::test_cache_dir())
        .output()
        .unwrap()
}

fn read_wav(path: &std::path::Path) -> (u32, u16, Vec<f32>) {
    let mut r = hound::WavReader::open(path).unwrap();
    let spec = r.spec();
    let s = r.samples::<f32>().map(|x| x.unwrap()).collect();
    (spec.sample_rate, spec.channels, s)
}

/// A play of gong-40N writes a stereo float WAV of the announced length with finite samples
/// and a positive peak, and a report with every documented field; the report's peak is the
/// WAV's (both f32, so equal to round-off: 1e-6 relative).
#[test]
fn gong_play_writes_wav_and_report() {
    let dir = scratch("gong");
    let wav = dir.join("g.wav");
    let out = noether(&[
        "play",
        "gong-40N",
        "--note",
        "C4:127:0.3",
        "--tail",
        "0.2",
        "-q",
        "-o",
        wav.to_str().unwrap(),
        "--plot",
        dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let (rate, channels, s) = read_wav(&wav);
    assert_eq!((rate, channels), (48_000, 2));
    assert_eq!(s.len(), 2 * 24_000, "0.3 s + 0.2 s at 48 kHz, stereo");
    assert!(s.iter().all(|x| x.is_finite()));
    let peak = s.iter().fold(0.0f32, |m, x| m.max(x.abs()));
    assert!(peak > 0.0);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("g.json")).unwrap()).unwrap();
    for key in [
        "cpu_seconds_per_audio_second",
        "max_block_cpu_fraction",
        "threads",
        "peak",
        "peak_dbfs",
        "nan_count",
        "seconds",
    ] {
        assert!(report[key].is_number(), "report lacks {key}: {report}");
    }
    assert_eq!(report["nan_count"], 0);
    assert!(report["threads"].as_u64().unwrap() >= 1);
    assert!(report["cpu_seconds_per_audio_second"].as_f64().unwrap() > 0.0);
    let rp = report["peak"].as_f64().unwrap();
    assert!((rp - f64::from(peak)).abs() <= 1e-6 * rp, "{rp} vs {peak}");
    let notes = report["notes"].as_array().unwrap();
    assert_eq!(notes.len(), 1);
    let n = &notes[0];
    assert_eq!(
        (n["key"].as_u64(), n["velocity"].as_u64()),
        (Some(60), Some(127))
    );
    assert_eq!(n["start_s"].as_f64(), Some(0.0));
    // The voice simulates what the preset allows at its root key: at most `modes` transverse
    // modes, the preset's in-plane modes, its top mode under the band limit and below the
    // simulation's Nyquist frequency.
    let v = Preset::factory_named("gong-40N").unwrap().values().unwrap();
    let n_phi = n["n_phi"].as_u64().unwrap();
    assert!((1..=v.get(ParamId::Modes) as u64).contains(&n_phi), "{n}");
    assert_eq!(
        n["n_psi"].as_u64(),
        Some(v.get(ParamId::InPlaneModes) as u64)
    );
    let (sim, top) = (
        n["sim_rate"].as_f64().unwrap(),
        n["top_mode_hz"].as_f64().unwrap(),
    );
    assert!(
        top > 0.0 && top <= f64::from(v.get(ParamId::BandLimit)),
        "{n}"
    );
    assert!(sim > 2.0 * top, "{n}");
    for f in ["g-waveform.png", "g-spectrogram.png"] {
        assert!(std::fs::metadata(dir.join(f)).unwrap().len() > 1000, "{f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad input is refused before anything is rendered, naming the flag, the value and the range.
#[test]
fn bad_values_are_refused_clearly() {
    for (args, fragments) in [
        (
            vec!["--note", "H4"],
            vec!["--note", "H4", "0 to 127", "C-1 to G9"],
        ),
        (vec!["--note", "128"], vec!["--note", "128", "0 to 127"]),
        (
            vec!["--note", "C4:0"],
            vec!["--note", "velocity", "1 to 127"],
        ),
        (vec!["--rate", "4000"], vec!["--rate", "4000", "8000"]),
        (vec!["--block", "0"], vec!["--block", "1 to 8192"]),
        (vec!["--tail", "-1"], vec!["--tail", "-1"]),
    ] {
        let mut all = vec!["play", "gong-40N", "-q"];
        all.extend(args.iter());
        let out = noether(&all);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        for f in &fragments {
            assert!(stderr.contains(f), "{args:?}: `{f}` missing from {stderr}");
        }
    }
    let out = noether(&["play", "no-such-preset", "-q"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("PRESET") && stderr.contains("gong-40N"),
        "{stderr}"
    );
}

/// `--scl` (and `--kbm`) tune the keys: a 19-EDO scale through the ideal sitar string plays
/// key 79 an octave above key 60 (19 keys, not 12: in 12-TET they are 1900 cents apart). The
/// fundamentals of the two renders are an octave apart within 2 cents: the bridge contact of
/// the sitar moves each note's fundamental a little with its amplitude (measured 0.08 cent);
/// the tuning itself is checked to 0.1 cent through the engine on the untouched string
/// (`tests/engine/pitch_from_sound.rs`). A bad scale file or a
/// `--kbm` without `--scl` is refused naming the file or the flag.
#[test]
fn scala_files_tune_the_keys() {
    let dir = scratch("scl");
    let steps: Vec<String> = (1..=19)
        .map(|i| format!(" {:.12}", 1200.0 * f64::from(i) / 19.0))
        .collect();
    let scl = dir.join("19.scl");
    std::fs::write(
        &scl,
        format!("! 19.scl\n19-EDO\n 19\n!\n{}\n", steps.join("\n")),
    )
    .unwrap();
    let f1 = |key: &str| {
        let wav = dir.join(format!("k{key}.wav"));
        let out = noether(&[
            "play",
            "sitar-b0",
            "-q",
            "--scl",
            scl.to_str().unwrap(),
            "--note",
            &format!("{key}:127:1"),
            "--tail",
            "0",
            "-o",
            wav.to_str().unwrap(),
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert!(
            stderr.contains("tuning: 19-EDO") && stderr.contains("128 keys mapped"),
            "{stderr}"
        );
        let (rate, ch, s) = read_wav(&wav);
        let left: Vec<f64> = s
            .iter()
            .step_by(usize::from(ch))
            .map(|&x| f64::from(x))
            .collect();
        // The fundamental isolated within 40 Hz (the sitar's bridge makes its other
        // partials strong), expected near 19-EDO's C4 (262.1 Hz) and C5.
        let expect = if key == "60" { 262.1 } else { 524.3 };
        fundamental_near(&left, f64::from(rate), expect, 40.0).expect("an oscillation")
    };
    let cents = 1200.0 * (f1("79") / f1("60")).log2() - 1200.0;
    println!("19-EDO key 79 over key 60: octave {cents:+.3e} cents");
    assert!(cents.abs() < 2.0, "{cents} cents from an octave");
    std::fs::write(dir.join("bad.scl"), "not a scale").unwrap();
    let out = noether(&[
        "play",
        "sitar-b0",
        "-q",
        "--scl",
        dir.join("bad.scl").to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("bad.scl"),
        "{stderr}"
    );
    let out = noether(&["play", "sitar-b0", "-q", "--kbm", "x.kbm"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("--scl"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A note on or off of `key` at velocity `vel` on MIDI channel 0.
fn midi_note(on: bool, key: u8, vel: u8) -> TrackEventKind<'static> {
    channel_note(0, on, key, vel)
}

/// A note on or off of `key` at velocity `vel` on MIDI channel `ch` (0-based).
fn channel_note(ch: u8, on: bool, key: u8, vel: u8) -> TrackEventKind<'static> {
    let (key, vel) = (u7::new(key), u7::new(vel));
    on_channel(
        ch,
        if on {
            MidiMessage::NoteOn { key, vel }
        } else {
            MidiMessage::NoteOff { key, vel }
        },
    )
}

/// Saves `smf` as `DIR/STEM.mid` and plays it on `preset` with `noether play --midi` (a
/// 0.1 s tail) into `DIR/STEM.wav` (and its report `DIR/STEM.json`); panics with the
/// command's stderr if it fails. Returns the WAV's path.
fn play_midi_file(preset: &str, smf: &Smf, dir: &std::path::Path, stem: &str) -> PathBuf {
    let mid = dir.join(format!("{stem}.mid"));
    smf.save(&mid).unwrap();
    let wav = dir.join(format!("{stem}.wav"));
    let out = noether(&[
        "play",
        preset,
        "--midi",
        mid.to_str().unwrap(),
        "--tail",
        "0.1",
        "-q",
        "-o",
        wav.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    wav
}

/// A MIDI file written with midly (format 1: a tempo track and a note track; 96 ticks per
/// quarter at 150 bpm = 400 000 µs, so 96 ticks = 0.4 s) plays its notes at their times and
/// velocities: the report lists keys 60 and 67, velocities 100 and 50, starts 0.0 and 0.4 s
/// (to 1e-9 s, round-off of the tick-to-second sums), the render ends 0.1 s (the tail) after
/// the last event, and the WAV sounds.
#[test]
fn midi_file_round_trip() {
    let dir = scratch("midi");
    let tempo = vec![
        TrackEvent {
            delta: u28::new(0),
            kind: TrackEventKind::Meta(MetaMessage::Tempo(u24::new(400_000))),
        },
        TrackEvent {
            delta: u28::new(0),
            kind: TrackEventKind::Meta(MetaMessage::EndOfTrack),
        },
    ];
    let ev = |delta: u32, kind| TrackEvent {
        delta: u28::new(delta),
        kind,
    };
    let notes = vec![
        ev(0, midi_note(true, 60, 100)),
        ev(96, midi_note(true, 67, 50)),
        ev(48, midi_note(false, 60, 0)),
        ev(48, midi_note(true, 67, 0)),
        ev(0, TrackEventKind::Meta(MetaMessage::EndOfTrack)),
    ];
    let smf = Smf {
        header: Header::new(Format::Parallel, Timing::Metrical(u15::new(96))),
        tracks: vec![tempo, notes],
    };
    let wav = play_midi_file("gong-40N", &smf, &dir, "two");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("two.json")).unwrap()).unwrap();
    let notes = report["notes"].as_array().unwrap();
    let got: Vec<(u64, u64, f64)> = notes
        .iter()
        .map(|n| {
            (
                n["key"].as_u64().unwrap(),
                n["velocity"].as_u64().unwrap(),
                n["start_s"].as_f64().unwrap(),
            )
        })
        .collect();
    assert_eq!(got.len(), 2, "{got:?}");
    assert_eq!((got[0].0, got[0].1), (60, 100));
    assert_eq!((got[1].0, got[1].1), (67, 50));
    assert!(
        got[0].2.abs() < 1e-9 && (got[1].2 - 0.4).abs() < 1e-9,
        "{got:?}"
    );
    // The last event (key 67 off) is at 0.8 s; plus the 0.1 s tail.
    assert!((report["seconds"].as_f64().unwrap() - 0.9).abs() < 1e-9);
    let (_, _, s) = read_wav(&wav);
    assert!(s.iter().any(|&x| x != 0.0) && s.iter().all(|x| x.is_finite()));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Notes start at their sample, inside a block (as a host's sample-accurate events): a note at
/// 0.1 s (sample 4800, inside the tenth 512-sample block) leaves the output exactly zero before
/// it, and sounds within the engine's reported latency (the resampler's half-width) plus 1 ms
/// (the raised-cosine strike's first samples may round to zero in f32) after it.
#[test]
fn notes_start_at_their_sample() {
    noether_testkit::env::test_cache_dir();
    let preset = find_preset("gong-40N").unwrap();
    let note = NoteSpec {
        seconds: 0.1,
        ..NoteSpec::new(60)
    };
    let tl = notes_timeline(&[note], &[0.1], 0.0).unwrap();
    let settings = PlaySettings {
        tempo: None,
        host_rate: 48_000.0,
        block: 512,
        tail: 0.05,
        tuning: KeyTuning::equal(),
    };
    let p = play(&preset, &tl, &settings, |_| {}).unwrap();
    let left = &p.out[0];
    assert_eq!(left.len(), 12_000);
    assert!(
        left[..4800].iter().all(|&x| x == 0.0),
        "sound before the note"
    );
    // Resampler half-width: 12 zero crossings at 16 kHz = 0.75 ms = 36 host samples; 1 ms more.
    let first = left.iter().position(|&x| x != 0.0).unwrap();
    assert!(
        (4800..4800 + 36 + 48).contains(&first),
        "first sound at {first}"
    );
    assert_eq!(p.report.notes.len(), 1);
    assert!((p.report.notes[0].start_s - 0.1).abs() < 1e-12);
}

/// A channel message on MIDI channel `ch` (0-based).
fn on_channel(ch: u8, message: MidiMessage) -> TrackEventKind<'static> {
    TrackEventKind::Midi {
        channel: u4::new(ch),
        message,
    }
}

/// `noether play --midi` plays MPE (the core's mapping, shared with the plugin): an MPE file
/// (lower zone of 15 member channels, the members' bend range set to 3 semitones by RPN 0)
/// sends a full bend up on channel 2 and a full bend down on channel 3, then a G3 on channel 2
/// (0 to 1.5 s) and a C4 on channel 3 (2 to 3.5 s). Each note sounds at its own channel's
/// bend: A#3 (G3 + 3) and A3 (C4 - 3), measured from the sound's fundamental on the ideal
/// sitar string with its bridge out of reach (f₁ = √(T/μ)/2L = 196.4 Hz at G3, as in
/// tests/engine/pitch_from_sound.rs). Without MPE both bends would be one global bend (the
/// last, down) over the preset's 2 semitones, both notes 2 semitones down: the two readings
/// tell the mappings apart by a semitone or more. Tolerance 3e-5 relative (0.05 cent; measured
/// -6.5e-6 and +1.0e-6 on 2026-11-28: the estimator reads this string to 1e-8 over 2 s in the
/// engine tests, these 1.2 s windows are shorter and the first note's release still rings).
/// Seen failing when the timeline put a note's expressions before its note on (the tuning
/// was lost: 196 Hz, read as 213.8 Hz at the band's edge).
#[test]
fn mpe_file_bends_each_note_by_its_channel() {
    let dir = scratch("mpe");
    let preset = noether::render::preset_accuracy::with_overrides(
        &Preset::factory_named("sitar-b0").unwrap(),
        &[
            "bridge_curvature=1".into(),
            "bridge_fraction=0.01".into(),
            "polyphony=2".into(),
            "threads=1".into(),
        ],
    )
    .unwrap();
    let toml = dir.join("ideal-sitar.toml");
    std::fs::write(&toml, preset.to_toml()).unwrap();
    let ev = |delta: u32, kind| TrackEvent {
        delta: u28::new(delta),
        kind,
    };
    let cc = |ch: u8, controller: u8, value: u8| {
        on_channel(
            ch,
            MidiMessage::Controller {
                controller: u7::new(controller),
                value: u7::new(value),
            },
        )
    };
    let bend = |ch: u8, raw: u16| {
        on_channel(
            ch,
            MidiMessage::PitchBend {
                bend: midly::PitchBend(midly::num::u14::new(raw)),
            },
        )
    };
    let note = |ch: u8, on: bool, key: u8| channel_note(ch, on, key, if on { 100 } else { 0 });
    // 1000 ticks per quarter at the default 120 bpm: 2000 ticks a second.
    let track = vec![
        // MPE Configuration Message: RPN 6 on the master channel, 15 member channels.
        ev(0, cc(0, 101, 0)),
        ev(0, cc(0, 100, 6)),
        ev(0, cc(0, 6, 15)),
        // Members' bend sensitivity: RPN 0 = 3 semitones on a member channel (the whole zone).
        ev(0, cc(1, 101, 0)),
        ev(0, cc(1, 100, 0)),
        ev(0, cc(1, 6, 3)),
        ev(0, bend(1, 16383)),
        ev(0, bend(2, 0)),
        ev(0, note(1, true, 55)),
        ev(3000, note(1, false, 55)),
        ev(1000, note(2, true, 60)),
        ev(3000, note(2, false, 60)),
        ev(0, TrackEventKind::Meta(MetaMessage::EndOfTrack)),
    ];
    let smf = Smf {
        header: Header::new(Format::SingleTrack, Timing::Metrical(u15::new(1000))),
        tracks: vec![track],
    };
    let wav = play_midi_file(toml.to_str().unwrap(), &smf, &dir, "mpe");
    let (rate, channels, s) = read_wav(&wav);
    assert_eq!(channels, 2);
    let left: Vec<f64> = s.iter().step_by(2).map(|&x| f64::from(x)).collect();
    let rate = f64::from(rate);
    let f1 = (180.5f64 / 1.17e-3).sqrt() / 2.0;
    for (start, semitones, what) in [(0.2, 3.0, "G3 bent up 3"), (2.2, 2.0, "C4 bent down 3")] {
        let window = &left[(start * rate) as usize..((start + 1.2) * rate) as usize];
        let want = f1 * (semitones / 12.0f64).exp2();
        // A band of ±6 Hz: the first note still rings (its release) 13 Hz above the second.
        let got = fundamental_near(window, rate, want, 6.0).expect("a pitch");
        println!("{what}: {got:.5} Hz, want {want:.5} Hz");
        assert!(
            (got / want - 1.0).abs() < 3e-5,
            "{what}: {got} Hz, want {want} Hz"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
