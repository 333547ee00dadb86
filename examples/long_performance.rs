//! The long-performance table of docs/robustness.md: for each factory preset (and, for the
//! plates, each engine scheme asked for), minutes of scripted playing
//! (`noether_testkit::performance`), then a soft strike compared with the same strike on a new
//! instance: worst third-octave band, spectral centroid before and after, bit identity.
//!
//! `cargo run --release --example long_performance -- --seconds 120 gong-80N gong-40N`
//! (`--scheme sav` etc. to force a plate scheme; `--modes N` to lower the mode budget; no
//! preset: every factory preset; `--storm S` plays S seconds of the soak's random note storm,
//! 8 notes a second under `assert_no_alloc`, instead of the scripted performance). Prints one
//! Markdown row per run.

use assert_no_alloc::{assert_no_alloc, AllocDisabler};
use clap::Parser;
use noether::engine::{ParamId, Preset};
use noether_testkit::performance::{after_performance, after_storm, Performance};

#[global_allocator]
static A: AllocDisabler = AllocDisabler;
use noether_testkit::presets::preset_params;

/// Long performances, then a fresh strike compared with a new instance's.
#[derive(Debug, Parser)]
struct Args {
    /// Factory presets (file stems); none: every factory preset.
    presets: Vec<String>,
    /// Seconds of playing (8 s cycles of rolls, chords, pedal, bends, hand, re-strikes).
    #[arg(long, default_value_t = 120.0)]
    seconds: f64,
    /// Velocity of the compared strike (1-127).
    #[arg(long, default_value_t = 40)]
    velocity: u8,
    /// Plate schemes to run (`conservative`, `conservative-exact`, `stormer-verlet`, `sav`);
    /// none: the preset's own.
    #[arg(long)]
    scheme: Vec<String>,
    /// Transverse mode budget (default: the preset's).
    #[arg(long)]
    modes: Option<f32>,
    /// Seconds of the soak's random note storm instead of the scripted performance.
    #[arg(long)]
    storm: Option<f64>,
    /// Seed of the script's random re-strikes.
    #[arg(long, default_value_t = 29)]
    seed: u64,
}

/// The scene names of the engine's plate schemes, in the order of its `scheme` parameter.
const SCHEMES: [&str; 4] = [
    "conservative",
    "conservative-exact",
    "stormer-verlet",
    "sav",
];

/// The engine's scheme index of a scene name.
fn scheme_index(name: &str) -> Option<f32> {
    SCHEMES.iter().position(|s| *s == name).map(|i| i as f32)
}

fn main() {
    let args = Args::parse();
    let stems: Vec<String> = if args.presets.is_empty() {
        Preset::factory()
            .into_iter()
            .map(|(s, _)| s.to_string())
            .collect()
    } else {
        args.presets.clone()
    };
    println!(
        "| preset | scheme | notes | worst band (dB) | at (Hz) | centroid after / fresh (Hz) | change | identical |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    for stem in &stems {
        let preset =
            Preset::factory_named(stem).unwrap_or_else(|| panic!("no factory preset named {stem}"));
        let values = preset.values().expect("factory preset");
        let key = values.get(ParamId::RootKey) as u8;
        let is_plate = values.model().is_plate();
        let schemes: Vec<Option<f32>> = if args.scheme.is_empty() || !is_plate {
            vec![None]
        } else {
            args.scheme
                .iter()
                .map(|s| Some(scheme_index(s).unwrap_or_else(|| panic!("unknown scheme {s}"))))
                .collect()
        };
        for scheme in schemes {
            let mut sets = Vec::new();
            if let Some(s) = scheme {
                sets.push((ParamId::Scheme, s));
            }
            if let Some(m) = args.modes {
                sets.push((ParamId::Modes, m));
            }
            let name = if is_plate {
                let i = scheme.unwrap_or(values.get(ParamId::Scheme)) as usize;
                SCHEMES[i].to_string()
            } else {
                "exact modal, Newton contact".to_string()
            };
            let velocity = args.velocity as f32 / 127.0;
            let c = match args.storm {
                Some(seconds) => after_storm(
                    || preset_params(stem, &sets),
                    seconds,
                    8.0,
                    args.seed,
                    |e, ev, l, r| assert_no_alloc(|| e.process_events(ev, l, r)),
                    key,
                    velocity,
                    4.0,
                    600.0,
                ),
                None => {
                    let perf = Performance::new(args.seconds, key, args.seed);
                    let params = || preset_params(stem, &sets);
                    after_performance(params, &perf, key, velocity, 0.2, 4.0, 600.0)
                }
            };
            println!(
                "| {stem} | {name} | {} | {:+.2} | {:.0} | {:.0} / {:.0} | {:+.1} % | {} |",
                c.notes,
                c.worst_band_db,
                c.worst_band_hz,
                c.centroid_after,
                c.centroid_fresh,
                100.0 * c.centroid_change(),
                if c.identical { "yes" } else { "no" }
            );
        }
    }
}
