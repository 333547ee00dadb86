//! The tanpura drone's strings over time: each string's energy (its motion, its jawari contact
//! and its seat) and the bridge's, every 10 ms, over three cycles of
//! `assets/scenes/tanpura-drone.toml` (four strings, Pa-Sa-Sa-Sa on C#3, a pluck every 0.8 s,
//! a 4 s cycle). A plucked string rises by its pluck's energy; the others rise between their own
//! plucks as the bridge hands them energy (the two Sa strings most, sounding the same note).
//!
//! Then the jawari's sweep: string 1 (Pa, 103.9 Hz, 480 modes) plucked alone, its band of
//! harmonics louder than the spectrum's trend followed as a ridge
//! ([`noether::analysis::formant::formant_ridge`]) every 50 ms over the first second: with the
//! jivari at 5 mm and without the thread at 192 kHz (the string's modes under the Nyquist
//! frequency), and with the jivari at the scene's 48 kHz (they alias).
//!
//! Run: `cargo run --release --example tanpura_drone [OUT_DIR]` (default `out`): prints each
//! string's tension after tuning by ear, its share of the energy at the end of each cycle and
//! the formant's track, and writes `OUT_DIR/tanpura-drone-strings.png` and
//! `OUT_DIR/tanpura-jawari-formant.png`.

use noether::analysis::formant::formant_ridge;
use noether::models::network::BridgeInstrument;
use noether::models::tanpura::{Tanpura, TanpuraSpec};
use noether::plot::{write_png, Mark, Panel, Scale, Series};
use noether::scene::Scene;
use std::path::{Path, PathBuf};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "out".into()));
    std::fs::create_dir_all(&out)?;
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/tanpura-drone.toml");
    let scene = Scene::load(&scene_path, &[])?;
    let spec = scene.tanpura.ok_or("the scene has no [tanpura] table")?;
    let mut drone = Tanpura::build(&spec)?;
    let names = [
        "Pa (string 1)",
        "Sa (string 2)",
        "Sa (string 3)",
        "low Sa (string 4)",
    ];
    println!("tensions after tuning by ear (N): {:.3?}", drone.tensions());
    let rate = 1.0 / drone.network().h();
    let every = (0.01 * rate) as u64;
    let cycle = (spec.cycle_seconds * rate) as u64;
    let n = drone.network().strings().len();
    let (mut t, mut strings, mut bridge) = (Vec::new(), vec![Vec::new(); n], Vec::new());
    while drone.steps() < 3 * cycle {
        drone.step();
        if drone.steps() % every == 0 {
            t.push(drone.steps() as f64 / rate);
            for (s, e) in strings.iter_mut().enumerate() {
                e.push(drone.network().string_energy(s).total());
            }
            let (k, p) = drone.network().bridge_energy();
            bridge.push(k + p);
        }
        if drone.steps() % cycle == 0 {
            let total = drone.network().energy_terms().total();
            let shares: Vec<String> = (0..n)
                .map(|s| format!("{:.3}", drone.network().string_energy(s).total() / total))
                .collect();
            println!(
                "end of cycle {}: string shares {}",
                drone.steps() / cycle,
                shares.join(" ")
            );
        }
    }
    let mut panel = Panel::new(
        "Each string's energy and the bridge's (J)",
        "time (s)",
        "energy (J)",
    )
    .scales(Scale::Linear, Scale::Log10);
    for (s, e) in strings.into_iter().enumerate() {
        let label = names
            .get(s)
            .map_or_else(|| format!("string {}", s + 1), |x| x.to_string());
        panel = panel.push(Series::line(label, t.clone(), e));
    }
    panel = panel.push(Series::line("bridge", t, bridge));
    let path = out.join("tanpura-drone-strings.png");
    write_png(
        &path,
        "tanpura-drone: energy of each string",
        &[panel],
        1,
        (1100, 520),
    )?;
    println!("wrote {}", path.display());
    jawari_formant(&spec, &out)
}

/// The formant's track of string 1 plucked alone, with and without the thread (module doc).
fn jawari_formant(spec: &TanpuraSpec, out: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let times: Vec<f64> = (1..=19).map(|k| 0.05 * k as f64).collect();
    let mut panel = Panel::new(
        "The jawari's formant, followed as a ridge: string 1 (Pa, 480 modes) plucked alone",
        "time after the pluck (s)",
        "formant centre (Hz)",
    );
    for (label, jivari, rate) in [
        ("jivari 5 mm, 192 kHz", 5.0, 192_000.0),
        ("no thread, 192 kHz", 0.0, 192_000.0),
        ("jivari 5 mm, 48 kHz (modes aliased)", 5.0, 48_000.0),
    ] {
        let mut s = spec.clone();
        s.cycle_seconds = 30.0;
        s.jivari_mm = vec![jivari];
        s.sim_rate = rate;
        s.tune_by_ear = false;
        let mut drone = Tanpura::build(&s)?;
        let rate = 1.0 / drone.network().h();
        let mut x = Vec::new();
        while drone.steps() < (1.2 * rate) as u64 {
            drone.step();
            let [l, r] = drone.network().bridge_force_mix(drone.gains());
            x.push(l + r);
        }
        let frames = formant_ridge(&x, rate, s.target_hz(0), &times);
        let track: Vec<usize> = frames.iter().map(|f| f.harmonic).collect();
        println!("formant ridge every 50 ms from 0.05 s, {label}: {track:?}");
        panel = panel.push(
            Series::line(
                label,
                frames.iter().map(|f| f.time).collect(),
                frames.iter().map(|f| f.hz).collect(),
            )
            .with_mark(Mark::LinePoints),
        );
    }
    let path = out.join("tanpura-jawari-formant.png");
    write_png(
        &path,
        "tanpura: the jawari's sweep",
        &[panel],
        1,
        (1100, 520),
    )?;
    println!("wrote {}", path.display());
    Ok(())
}
