//! `noether play PRESET`: a factory or user preset played through the real-time engine,
//! headless, exactly as the plugin plays it ([`noether::render::play`]); writes a WAV, a JSON
//! report and (with `--plot`) a waveform and a spectrogram.

use super::files::OutputArgs;
use clap::Args;
use noether::engine::ParamId;
use noether::engine::{load_scala, KeyTuning};
use noether::render::midi::load_midi;
use noether::render::play::{
    notes_timeline, parse_note, play, root_key, NoteSpec, PlaySettings, Timeline,
};
use noether::render::preset_engine::find_preset;
use noether::render::report::{write_spectrogram, write_waveform_png};
use noether::render::wav::{write_wav, WavFormat};
use noether::Error;
use std::path::PathBuf;

/// Arguments of `noether play`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub struct PlayArgs {
    /// A factory preset (file stem in assets/presets, e.g. gong-40N) or a preset TOML file.
    pub preset: String,
    /// A note KEY[:VEL[:SECONDS]] (repeatable): KEY a MIDI number or a name (C4 = 60, F#3),
    /// VEL 1-127 [default 127], SECONDS held [default 4]. Default: the preset's root key.
    #[arg(
        long = "note",
        value_name = "KEY[:VEL[:SECONDS]]",
        conflicts_with = "midi"
    )]
    pub notes: Vec<String>,
    /// Seconds between a note's release and the next note's start (0 to 600).
    #[arg(long, default_value_t = 0.0, conflicts_with_all = ["at", "midi"])]
    pub gap: f64,
    /// Start times in s, one per --note, comma separated or repeated (one --note: played at
    /// every time).
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "SECONDS",
        conflicts_with = "midi"
    )]
    pub at: Vec<f64>,
    /// A standard MIDI file (format 0 or 1) to play instead of --note.
    #[arg(long, value_name = "FILE.mid")]
    pub midi: Option<PathBuf>,
    /// Host sample rate in Hz (8000 to 768000).
    #[arg(long, default_value_t = 48_000)]
    pub rate: u32,
    /// Host block size in samples (1 to 8192).
    #[arg(long, default_value_t = 512)]
    pub block: usize,
    /// Seconds rendered after the last note-off (0 to 600).
    #[arg(long, default_value_t = 2.0)]
    pub tail: f64,
    /// Output files and progress.
    #[command(flatten)]
    pub out: OutputArgs,
    /// A Scala scale file: the keys play its pitches instead of 12-tone equal temperament
    /// (degree 0 on key 60 at 261.626 Hz unless --kbm maps the keys).
    #[arg(long, value_name = "FILE.scl")]
    pub scl: Option<PathBuf>,
    /// The host's tempo in beats per minute (20 to 400), as a DAW's transport gives it: a
    /// tanpura drone with `drone_sync` on plays `drone_beats` beats per cycle.
    #[arg(long, value_name = "BPM")]
    pub tempo: Option<f64>,
    /// A Scala keyboard mapping for --scl (reference key and frequency, unmapped keys).
    #[arg(long, value_name = "FILE.kbm", requires = "scl")]
    pub kbm: Option<PathBuf>,
}

/// The performance the arguments describe.
fn timeline(a: &PlayArgs, root: u8) -> Result<Timeline, Error> {
    if let Some(path) = &a.midi {
        return Ok(load_midi(path)?);
    }
    let notes = if a.notes.is_empty() {
        vec![NoteSpec::new(root)]
    } else {
        a.notes
            .iter()
            .map(|n| parse_note(n))
            .collect::<Result<Vec<_>, _>>()?
    };
    Ok(notes_timeline(&notes, &a.at, a.gap)?)
}

/// Runs `noether play`.
pub fn run(a: PlayArgs) -> Result<(), Error> {
    let found = find_preset(&a.preset)?;
    let root = root_key(&found.preset)?;
    let tl = timeline(&a, root)?;
    let tuning = match &a.scl {
        Some(scl) => {
            let t = load_scala(scl, a.kbm.as_deref())?;
            eprintln!(
                "tuning: {} ({} keys mapped)",
                t.description,
                t.table.mapped_keys()
            );
            t.table
        }
        None => KeyTuning::equal(),
    };
    let settings = PlaySettings {
        host_rate: f64::from(a.rate),
        block: a.block,
        tail: a.tail,
        tuning,
        tempo: a.tempo,
    };
    settings.validate()?;
    let (wav, report_path) = a.out.wav_and_report(&format!("play-{}.wav", found.stem))?;
    eprintln!(
        "playing {} ({}): {} events, {:.2} s + {:.2} s tail at {} Hz, blocks of {}",
        found.stem,
        found.preset.name,
        tl.events.len(),
        tl.end,
        a.tail,
        a.rate,
        a.block
    );
    let bar = a.out.progress_bar();
    let played = play(&found, &tl, &settings, |f| {
        bar.set_position((f * 1000.0) as u64)
    })?;
    bar.finish_and_clear();
    let r = &played.report;
    let out: Vec<Vec<f64>> = played
        .out
        .iter()
        .map(|c| c.iter().map(|&x| f64::from(x)).collect())
        .collect();
    write_wav(&wav, &out, a.rate, WavFormat::Float32)?;
    let json = serde_json::to_string_pretty(r)?;
    super::files::write_text(&report_path, &(json + "\n"))?;
    for n in &r.notes {
        match (n.n_phi, n.n_psi, n.sim_rate, n.top_mode_hz) {
            (Some(phi), Some(psi), Some(sim), Some(top)) => eprintln!(
                "  note {} vel {} at {:.3} s: N_phi = {phi}, N_psi = {psi}, sim {sim} Hz, top mode {top:.0} Hz{}",
                n.key,
                n.velocity,
                n.start_s,
                match (n.above_modes, n.above_top_hz) {
                    (Some(m), Some(f)) if m > 0 =>
                        format!("; band above: {m} modes to {f:.0} Hz at the host rate"),
                    _ => String::new(),
                }
            ),
            _ => eprintln!(
                "  note {} vel {} at {:.3} s: no voice sounds it (refused)",
                n.key, n.velocity, n.start_s
            ),
        }
    }
    eprintln!(
        "  {:.2} s, peak {:.4} ({}), nan {}; CPU {:.3} s and wall {:.3} s per audio second, worst block {:.3} of its duration, {} thread(s); bank ready in {:.2} s",
        r.seconds,
        r.peak,
        r.peak_dbfs
            .map_or("silent".to_string(), |d| format!("{d:.1} dBFS")),
        r.nan_count,
        r.cpu_seconds_per_audio_second,
        r.wall_seconds_per_audio_second,
        r.max_block_cpu_fraction,
        r.threads,
        r.bank_seconds
    );
    if let Some(reduced) = &r.reduced {
        eprintln!(
            "  the model was built with {reduced}; tensors {:.1} MB",
            r.tensor_megabytes
        );
    }
    if let Some(tuning) = &r.drone_tuning {
        eprintln!("  the strings were {tuning}");
    }
    eprintln!("  wrote {} and {}", wav.display(), report_path.display());
    if let Some(dir) = &a.out.plot {
        super::files::create_dir(dir)?;
        let stem = wav
            .file_stem()
            .map_or("play".into(), |s| s.to_string_lossy().into_owned());
        // The band the notes simulate: up to 1.25x their highest mode (log axis); to Nyquist
        // when a plate's band above the simulation may sound (closure and band above on).
        let above = found.preset.values().is_ok_and(|v| {
            v.model().is_plate()
                && v.get(ParamId::Closure) > 0.0
                && v.index_of(ParamId::BandAbove) == 1
        });
        let top = r
            .notes
            .iter()
            .filter_map(|n| n.top_mode_hz)
            .fold(0.0f32, f32::max);
        let max_freq = if top > 0.0 && !above {
            1.25 * f64::from(top)
        } else {
            f64::INFINITY
        };
        for p in [
            write_waveform_png(dir, &stem, &out[0], a.rate)?,
            write_spectrogram(dir, &stem, &out[0], a.rate, max_freq)?,
        ] {
            eprintln!("  wrote {}", p.display());
        }
    }
    if r.nan_count > 0 {
        return Err(Error::Diverged {
            non_finite: r.nan_count,
        });
    }
    Ok(())
}
