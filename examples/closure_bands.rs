//! The band table of a plate preset against its resolved reference (a sound designer's and a
//! researcher's tool): plays the preset's root key (one voice, 1.5 s held) as the preset, with
//! its closure off (the plain truncation; the band above then gets only the strike), and
//! resolved (the band raised to `BAND` Hz with up to 1400 modes, the conservative-exact scheme
//! at `RATE` Hz, no closure, no band above), at velocities 127 and 64, and prints each third-octave's level relative to
//! the window's total over 0-0.3 s and 0.3-1.5 s: the reference's, and the preset's and the
//! plain truncation's differences from it (dB), then the worst from 99 Hz to 12.5 kHz.
//! docs/ACCURACY.md ("The closure's gate; the crash at twice its rate") shows the crash's.
//! `CLOSURE`, when given and not `-`, sets the preset column's closure strength (to try the
//! closure on a preset that does not set it). Each `KEY=VALUE` after it (a preset file's
//! parameter keys, e.g. `in_plane_modes=60`) is set on the reference only: the in-plane modes
//! it needs to converge, for one. A note takes the tier of its band, whose in-plane modes are
//! `in_plane_modes` scaled by its share of `modes`. `preset:KEY=VALUE` sets it on the preset
//! and the plain columns instead (another choice of the preset, against the same reference).
//! The word `floor` among them adds the reference's chaotic floor: the reference against
//! itself struck 1e-4 softer, per band and as its worst band (one more reference render).
//!
//! ```text
//! cargo run --release --example closure_bands [-- STEM [BAND [RATE [CLOSURE [KEY=VALUE ...] [floor]]]]]
//! (defaults: crash 14000 62400, the preset's own closure)
//! ```

use noether::engine::ParamId;
use noether_testkit::performance::{engine, relative_band_levels, resolved_reference, strike};
use noether_testkit::presets::preset_params;

const HOST_RATE: f64 = 48_000.0;
/// The windows (s) after the strike.
const WINDOWS: [(f64, f64); 2] = [(0.0, 0.3), (0.3, 1.5)];

/// The left output of `stem`'s root key at `velocity` (0..1), one voice, with `sets`.
fn render(stem: &str, sets: &[(ParamId, f32)], velocity: f32) -> Vec<f32> {
    let mut all = vec![(ParamId::Polyphony, 1.0)];
    all.extend_from_slice(sets);
    let params = preset_params(stem, &all);
    let key = params.get(ParamId::RootKey) as u8;
    let mut e = engine(params);
    strike(&mut e, key, velocity, 1.5, 1.5)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let stem = args.first().map_or("crash", String::as_str);
    let band: f32 = args
        .get(1)
        .map_or(14_000.0, |s| s.parse().expect("BAND in Hz"));
    let rate: f32 = args
        .get(2)
        .map_or(62_400.0, |s| s.parse().expect("RATE in Hz"));
    let preset_sets: Vec<(ParamId, f32)> = args
        .get(3)
        .filter(|s| *s != "-")
        .map(|s| (ParamId::Closure, s.parse().expect("CLOSURE, 0 to 4")))
        .into_iter()
        .collect();
    // The plain resolved truncation: no closure, no band above (nor its contact residual).
    let mut resolved = resolved_reference(band, rate).to_vec();
    let mut preset_sets = preset_sets;
    let mut plain_sets = vec![(ParamId::Closure, 0.0)];
    let with_floor = args.iter().skip(4).any(|a| a == "floor");
    for set in args.iter().skip(4).filter(|a| *a != "floor") {
        let (target, set) = match set.strip_prefix("preset:") {
            Some(rest) => (None, rest),
            None => (Some(&mut resolved), set.as_str()),
        };
        let (key, value) = set.split_once('=').expect("KEY=VALUE");
        let id = ParamId::from_key(key).unwrap_or_else(|| panic!("no parameter named {key}"));
        let value: f32 = value.parse().expect("a number");
        match target {
            Some(r) => r.push((id, value)),
            None => {
                preset_sets.push((id, value));
                plain_sets.push((id, value));
            }
        }
    }
    for velocity in [127u8, 64] {
        let v = f32::from(velocity) / 127.0;
        let preset = render(stem, &preset_sets, v);
        let plain = render(stem, &plain_sets, v);
        let reference = render(stem, &resolved, v);
        // The chaotic floor's twin: the same reference struck 1e-4 softer.
        let twin = with_floor.then(|| render(stem, &resolved, v * (1.0 - 1e-4)));
        for window in WINDOWS {
            let (p, c, r) = (
                relative_band_levels(&preset, HOST_RATE, window),
                relative_band_levels(&plain, HOST_RATE, window),
                relative_band_levels(&reference, HOST_RATE, window),
            );
            let f = twin
                .as_ref()
                .map(|t| relative_band_levels(t, HOST_RATE, window));
            println!(
                "{stem}, velocity {velocity}, {}-{} s: band (Hz), reference (dB of the total), \
                 preset - reference, plain - reference{}",
                window.0,
                window.1,
                if f.is_some() { ", floor" } else { "" }
            );
            let (mut worst_preset, mut worst_plain, mut worst_floor) = (0.0f64, 0.0f64, 0.0f64);
            // The target's measure: bands within 60 dB of the total, each against the larger
            // of 3 dB and its own floor; (excess over that, band, difference).
            let mut worst_heard = (f64::NEG_INFINITY, 0.0f64, 0.0f64);
            for (i, ((&(hz, pl), &(_, cl)), &(_, rl))) in p.iter().zip(&c).zip(&r).enumerate() {
                let floor = f.as_ref().map(|f| (f[i].1 - rl).abs());
                if (90.0..17_000.0).contains(&hz) {
                    let shown = floor.map_or(String::new(), |d| format!(" {d:7.1}"));
                    println!("{hz:8.0} {rl:8.1} {:+7.1} {:+7.1}{shown}", pl - rl, cl - rl);
                }
                if (90.0..13_000.0).contains(&hz) {
                    worst_preset = worst_preset.max((pl - rl).abs());
                    worst_plain = worst_plain.max((cl - rl).abs());
                    worst_floor = worst_floor.max(floor.unwrap_or(0.0));
                    let excess = (pl - rl).abs() - floor.unwrap_or(0.0).max(3.0);
                    if rl >= -60.0 && excess > worst_heard.0 {
                        worst_heard = (excess, hz, pl - rl);
                    }
                }
            }
            let floor = if f.is_some() {
                format!(", floor {worst_floor:.1} dB")
            } else {
                String::new()
            };
            println!(
                "worst, 99 Hz-12.5 kHz: preset {worst_preset:.1} dB, plain {worst_plain:.1} dB{floor}"
            );
            println!(
                "worst within 60 dB of the total: preset {:+.1} dB at {:.0} Hz, {:+.1} dB over \
                 the larger of 3 dB and its floor",
                worst_heard.2, worst_heard.1, worst_heard.0
            );
        }
    }
}
