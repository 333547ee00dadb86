//! `noether accuracy SCENE --vary rate|modes|psi|scheme --values a,b,c [--reference-set P=V]`:
//! render a scene (a plate, a string, a tanpura drone or a sitar) under several settings and
//! against a reference, write a CSV and JSON table
//! and a PNG of the error against wall time. `noether accuracy --preset STEM ...` does the same
//! for a factory preset played through the engine ([`noether::render::preset_accuracy`]). The metrics are those of
//! [`noether::render::accuracy`] (stated in docs/ACCURACY.md).

use clap::{Args, ValueEnum};
use noether::engine::{ParamId, Preset};
use noether::plot::{write_png, Mark, Panel, Scale, Series};
use noether::render::accuracy::{study, AccuracyStudy, Variant};
use noether::render::preset_accuracy::{preset_study, with_overrides, PresetVariant};
use noether::scene::Scene;
use noether::{Error, ParamError};
use std::path::{Path, PathBuf};

/// The setting a study varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Vary {
    /// The simulation rate (Hz). Default reference: twice the largest value.
    Rate,
    /// Transverse modes N_Φ (plate), string modes, or modes per string (tanpura; the sitar's
    /// played string). Default reference: twice the largest value.
    Modes,
    /// In-plane modes N_Ψ (plate only). Default reference: twice the largest value.
    Psi,
    /// The time scheme (plate: conservative, conservative-exact, stormer-verlet, sav; string:
    /// the contact scheme, newton or quadratised). Default reference: conservative-exact
    /// (plate) or newton (string) at twice the scene's rate.
    Scheme,
}

impl Vary {
    fn name(self) -> &'static str {
        match self {
            Vary::Rate => "rate",
            Vary::Modes => "modes",
            Vary::Psi => "psi",
            Vary::Scheme => "scheme",
        }
    }

    /// The scene field the setting writes for a scene whose model table is `model`
    /// ([`Scene::model_key`]: `plate`, `string`, `tanpura` or `sitar`).
    fn field(self, model: &str) -> Result<&'static str, ParamError> {
        Ok(match (self, model) {
            (Vary::Rate, "plate") => "plate.sim_rate",
            (Vary::Rate, "string") => "string.sim_rate",
            (Vary::Rate, "tanpura") => "tanpura.sim_rate",
            (Vary::Rate, "sitar") => "sitar.sim_rate",
            (Vary::Modes, "plate") => "plate.n_phi",
            (Vary::Modes, "string") => "string.modes",
            (Vary::Modes, "tanpura") => "tanpura.modes",
            (Vary::Modes, "sitar") => "sitar.modes",
            (Vary::Psi, "plate") => "plate.n_psi",
            (Vary::Scheme, "plate") => "plate.scheme",
            (Vary::Scheme, "string") => "string.contact_scheme",
            _ => {
                return Err(ParamError::new(
                    "--vary",
                    format!("`{}`", self.name()),
                    match model {
                        "plate" => "rate, modes, psi, scheme for a plate scene",
                        "string" => "rate, modes, scheme for a string scene",
                        _ => "rate, modes for a tanpura or sitar scene",
                    },
                ))
            }
        })
    }

    fn numeric(self) -> bool {
        self != Vary::Scheme
    }
}

/// Arguments of `noether accuracy`.
#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// Scene file (TOML); or give `--preset`.
    #[arg(required_unless_present = "preset", conflicts_with = "preset")]
    pub scene: Option<PathBuf>,
    /// A factory preset (file stem in assets/presets, e.g. gong-40N), played through the
    /// real-time engine (root key, one voice, 48 kHz); `--set` and `--reference-set` then take
    /// engine parameter keys (modes=100, sim_rate=32000, scheme=sav).
    #[arg(long)]
    pub preset: Option<String>,
    /// Rendered seconds for `--preset` (scenes use their `output.seconds`).
    #[arg(long, default_value_t = 0.3)]
    pub seconds: f64,
    /// Which setting to vary.
    #[arg(long, value_enum)]
    pub vary: Vary,
    /// The values to render, comma separated (rates in Hz, mode counts, or scheme names).
    #[arg(long, value_delimiter = ',', required = true)]
    pub values: Vec<String>,
    /// Simulation rate of the reference render (Hz), for `--vary rate` [default: twice the
    /// largest value].
    #[arg(long)]
    pub reference_rate: Option<f64>,
    /// Override a field of the reference scene only (repeatable), replacing the default
    /// reference of the study, e.g. --reference-set plate.n_phi=400.
    #[arg(long = "reference-set", value_name = "PATH=VALUE")]
    pub reference_set: Vec<String>,
    /// Override a scene field by its dotted path (repeatable, every render), e.g.
    /// --set output.seconds=0.2.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<String>,
    /// Folder for the table and the figure.
    #[arg(long, default_value = "out/accuracy")]
    pub out: PathBuf,
    /// Also print the distances per third-octave band (always written to
    /// `<stem>-bands.{csv,png}`).
    #[arg(long)]
    pub per_band: bool,
}

/// Loads the scene with the common overrides plus `extra`.
fn load_with(a: &AccuracyArgs, extra: &[String]) -> Result<Scene, Error> {
    let mut set = a.set.clone();
    set.extend_from_slice(extra);
    let path = a
        .scene
        .as_ref()
        .ok_or_else(|| ParamError::new("SCENE", "missing", "a scene file (or --preset NAME)"))?;
    Ok(Scene::load(path, &set)?)
}

/// The default reference overrides of a study (see [`Vary`]).
fn default_reference(
    a: &AccuracyArgs,
    base: &Scene,
    field: &str,
) -> Result<Vec<String>, ParamError> {
    let plate = base.plate.is_some();
    let rate_field = Vary::Rate.field(base.model_key())?;
    let base_rate = base.sim_rate();
    let top = || {
        a.values
            .iter()
            .filter_map(|v| v.parse::<f64>().ok())
            .fold(0.0, f64::max)
    };
    Ok(match a.vary {
        Vary::Rate => vec![format!(
            "{rate_field}={}",
            a.reference_rate.unwrap_or(2.0 * top())
        )],
        Vary::Modes | Vary::Psi => vec![format!("{field}={}", (2.0 * top()).round())],
        Vary::Scheme => vec![
            format!(
                "{field}={}",
                if plate {
                    "conservative-exact"
                } else {
                    "newton"
                }
            ),
            format!("{rate_field}={}", 2.0 * base_rate),
        ],
    })
}

/// Runs `noether accuracy`.
pub fn run(a: AccuracyArgs) -> Result<(), Error> {
    let study = match &a.preset {
        Some(stem) => preset_run(&a, stem)?,
        None => scene_run(&a)?,
    };
    write_outputs(&a.out, &study, a.per_band)
}

/// The engine parameter a preset study varies.
fn preset_key(vary: Vary) -> &'static str {
    match vary {
        Vary::Rate => "sim_rate",
        Vary::Modes => "modes",
        Vary::Psi => "in_plane_modes",
        Vary::Scheme => "scheme",
    }
}

/// The study of a factory preset (see [`AccuracyArgs::preset`]).
fn preset_run(a: &AccuracyArgs, stem: &str) -> Result<AccuracyStudy, Error> {
    let names: Vec<&str> = Preset::factory().iter().map(|(s, _)| *s).collect();
    let factory = Preset::factory_named(stem)
        .ok_or_else(|| ParamError::new("--preset", format!("`{stem}`"), names.join(", ")))?;
    let base = with_overrides(&factory, &a.set)?;
    let key = preset_key(a.vary);
    let plate = base.values().map(|v| v.model().is_plate())?;
    if !plate && matches!(a.vary, Vary::Psi | Vary::Scheme) {
        return Err(ParamError::new(
            "--vary",
            format!("`{}`", a.vary.name()),
            "rate, modes for a string preset",
        )
        .into());
    }
    let mut variants = Vec::new();
    for v in &a.values {
        let v = v.trim();
        let value = parse_value(a.vary, v)?;
        variants.push(PresetVariant {
            setting: v.to_string(),
            value,
            preset: with_overrides(&base, &[format!("{key}={v}")])?,
        });
    }
    let reference_set = if a.reference_set.is_empty() {
        let top = variants.iter().filter_map(|v| v.value).fold(0.0, f64::max);
        let rate = f64::from(base.values()?.get(ParamId::SimRate));
        match a.vary {
            Vary::Rate => vec![format!(
                "sim_rate={}",
                a.reference_rate.unwrap_or(2.0 * top)
            )],
            Vary::Modes | Vary::Psi => vec![format!("{key}={}", (2.0 * top).round())],
            Vary::Scheme => vec![
                "scheme=conservative-exact".to_string(),
                format!("sim_rate={}", 2.0 * rate),
            ],
        }
    } else {
        a.reference_set.clone()
    };
    let reference = with_overrides(&base, &reference_set)?;
    let description = format!("the preset with {}", reference_set.join(", "));
    eprintln!(
        "accuracy of preset {stem} against {description} ({} s)",
        a.seconds
    );
    Ok(preset_study(
        stem,
        a.vary.name(),
        &variants,
        &reference,
        description,
        a.seconds,
        |l| eprintln!("  {l}"),
    )?)
}

/// Parses one `--values` entry of a numeric study (`None` for schemes).
fn parse_value(vary: Vary, v: &str) -> Result<Option<f64>, ParamError> {
    if !vary.numeric() {
        return Ok(None);
    }
    match v.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(Some(x)),
        _ => Err(ParamError::new(
            "--values",
            format!("`{v}`"),
            format!("positive finite numbers for --vary {}", vary.name()),
        )),
    }
}

/// The study of a scene file.
fn scene_run(a: &AccuracyArgs) -> Result<AccuracyStudy, Error> {
    let base = load_with(a, &[])?;
    let field = a.vary.field(base.model_key())?;
    if a.values.is_empty() {
        return Err(ParamError::new("--values", "empty", "one or more settings").into());
    }
    let mut variants = Vec::new();
    for v in &a.values {
        let value = parse_value(a.vary, v.trim())?;
        let scene = load_with(a, &[format!("{field}={}", v.trim())])?;
        variants.push(Variant {
            setting: v.trim().to_string(),
            value,
            scene,
        });
    }
    let reference_set = if a.reference_set.is_empty() {
        default_reference(a, &base, field)?
    } else {
        a.reference_set.clone()
    };
    let reference = load_with(a, &reference_set)?;
    let description = format!("the scene with {}", reference_set.join(", "));
    eprintln!(
        "accuracy of {} against {description} ({} s)",
        base.name, base.output.seconds
    );
    study(a.vary.name(), &variants, &reference, description, |l| {
        eprintln!("  {l}")
    })
}

/// Writes the CSV, JSON and PNG of a study into `out` and prints the table.
fn write_outputs(out: &Path, study: &AccuracyStudy, per_band: bool) -> Result<(), Error> {
    super::files::create_dir(out)?;
    let stem = out.join(format!("{}-accuracy-{}", study.scene, study.vary));
    let csv_path = stem.with_extension("csv");
    super::files::write_csv(&csv_path, &study.rows)?;
    let json_path = stem.with_extension("json");
    let json = serde_json::to_string_pretty(study)?;
    super::files::write_text(&json_path, &(json + "\n"))?;
    let png_path = stem.with_extension("png");
    write_figure(&png_path, study)?;
    eprintln!(
        "reference: {} ({:.2} s wall, balance error {:.2e})",
        study.reference, study.reference_wall_seconds, study.reference_energy_balance_error
    );
    if let Some(f) = &study.sensitivity {
        eprintln!(
            "floor: the reference against itself with {} {:+e} relative (inaudible): \
             L2 (50 ms) {:.3e}, LSD {:.3} dB, bands {:.3} dB; distances near or below it are \
             the note's own sensitivity, not a difference between the models",
            f.parameter, f.relative_change, f.l2_50ms, f.lsd_db, f.band_db
        );
    }
    eprintln!(
        "{:>20} {:>10} {:>12} {:>10} {:>11} {:>12} {:>12}",
        study.vary,
        "wall (s)",
        "L2 (50 ms)",
        "LSD (dB)",
        "bands (dB)",
        "partials (¢)",
        "balance err"
    );
    for r in &study.rows {
        eprintln!(
            "{:>20} {:>10.3} {:>12.3e} {:>10.3} {:>11.3} {:>12} {:>12.2e}",
            r.setting,
            r.wall_seconds,
            r.l2_50ms,
            r.lsd_db,
            r.band_db,
            r.partial_cents.map_or("-".into(), |c| format!("{c:.2e}")),
            r.energy_balance_error
        );
    }
    let [bands_csv, bands_png] = super::accuracy_bands::write_band_outputs(&stem, study, per_band)?;
    for p in [&csv_path, &json_path, &png_path, &bands_csv, &bands_png] {
        eprintln!("  wrote {}", p.display());
    }
    Ok(())
}

fn write_figure(path: &Path, study: &AccuracyStudy) -> Result<(), Error> {
    use noether::render::accuracy::{AccuracyRow, SensitivityFloor};
    // The note's floor (preset studies) as a level line across the cost panels' wall range.
    let walls = study.rows.iter().map(|r| r.wall_seconds);
    let (w0, w1) = walls.fold((f64::INFINITY, 0.0f64), |(a, b), w| (a.min(w), b.max(w)));
    // Each setting is its own labelled point on the cost panels (a scheme study has no order).
    let cost_panel = |title: &str,
                      ylabel: &str,
                      pick: fn(&AccuracyRow) -> f64,
                      floor: fn(&SensitivityFloor) -> f64| {
        let mut p = Panel::new(title, "wall time (s)", ylabel).scales(Scale::Log10, Scale::Log10);
        if let Some(f) = study.sensitivity.as_ref().filter(|_| w1 > 0.0) {
            p = p.push(Series::line(
                f.label(),
                vec![0.8 * w0, 1.25 * w1],
                vec![floor(f); 2],
            ));
        }
        if study.rows.iter().all(|r| r.value.is_some()) {
            p = p.push(
                Series::line(
                    ylabel,
                    study.rows.iter().map(|r| r.wall_seconds).collect(),
                    study.rows.iter().map(pick).collect(),
                )
                .with_mark(Mark::LinePoints),
            );
        } else {
            for r in &study.rows {
                p = p.push(
                    Series::line(r.setting.clone(), vec![r.wall_seconds], vec![pick(r)])
                        .with_mark(Mark::Points),
                );
            }
        }
        p
    };
    let mut panels = vec![
        cost_panel(
            "waveform error against cost",
            "relative L2, first 50 ms",
            |r| r.l2_50ms,
            |f| f.l2_50ms,
        ),
        cost_panel(
            "spectral error against cost",
            "log-spectral distance (dB)",
            |r| r.lsd_db,
            |f| f.lsd_db,
        ),
        cost_panel(
            "band-level error against cost",
            "third-octave band distance (dB)",
            |r| r.band_db,
            |f| f.band_db,
        ),
    ];
    if study.rows.iter().all(|r| r.value.is_some()) {
        let value: Vec<f64> = study.rows.iter().filter_map(|r| r.value).collect();
        let unit = if study.vary == "rate" { " (Hz)" } else { "" };
        panels.push(
            Panel::new(
                "errors against the setting",
                format!("{}{unit}", study.vary),
                "error",
            )
            .scales(Scale::Log10, Scale::Log10)
            .push(
                Series::line(
                    "L2 (50 ms)",
                    value.clone(),
                    study.rows.iter().map(|r| r.l2_50ms).collect(),
                )
                .with_mark(Mark::LinePoints),
            )
            .push(
                Series::line(
                    "LSD (dB)",
                    value.clone(),
                    study.rows.iter().map(|r| r.lsd_db).collect(),
                )
                .with_mark(Mark::LinePoints),
            )
            .push(
                Series::line(
                    "bands (dB)",
                    value,
                    study.rows.iter().map(|r| r.band_db).collect(),
                )
                .with_mark(Mark::LinePoints),
            ),
        );
    }
    let columns = panels.len();
    write_png(
        path,
        &if columns > 3 {
            format!(
                "{}: accuracy against {} (reference: {})",
                study.scene, study.vary, study.reference
            )
        } else {
            format!("{}: accuracy against {}", study.scene, study.vary)
        },
        &panels,
        columns,
        (560, 420),
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The path of a scene file of the repository.
    fn scene_path(name: &str) -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("assets/scenes")
            .join(name)
    }

    #[test]
    fn every_scene_model_maps_its_settings_or_names_the_setting_it_lacks() {
        let drone = Scene::load(&scene_path("tanpura-drone.toml"), &[]).unwrap();
        let sitar = Scene::load(&scene_path("sitar-taraf.toml"), &[]).unwrap();
        assert_eq!(
            Vary::Rate.field(drone.model_key()).unwrap(),
            "tanpura.sim_rate"
        );
        assert_eq!(Vary::Modes.field(sitar.model_key()).unwrap(), "sitar.modes");
        let e = Vary::Psi.field(drone.model_key()).unwrap_err();
        assert_eq!(e.field, "--vary");
        assert!(e.to_string().contains("tanpura"), "{e}");
    }

    /// A drone studied over its rate: each row renders at its own rate and the reference at
    /// the one asked for, every power balance closes to 1e-10 (round-off; coarse strings and
    /// 0.3 s, so the test is quick) and each row has a finite, non-zero band distance.
    #[test]
    fn a_drone_is_studied_over_its_rate() {
        let a = AccuracyArgs {
            scene: Some(scene_path("tanpura-drone.toml")),
            preset: None,
            seconds: 0.3,
            vary: Vary::Rate,
            values: vec!["16000".into(), "24000".into()],
            reference_rate: Some(48_000.0),
            reference_set: vec![],
            set: vec![
                "output.seconds=0.3".into(),
                "tanpura.modes=64".into(),
                "tanpura.jivari_mm=[30.0]".into(),
                "tanpura.tune_by_ear=false".into(),
            ],
            out: PathBuf::from("unused"),
            per_band: false,
        };
        let study = scene_run(&a).unwrap();
        let rates: Vec<f64> = study.rows.iter().map(|r| r.sim_rate).collect();
        assert_eq!(rates, [16_000.0, 24_000.0]);
        assert!(
            study.reference.contains("tanpura.sim_rate=48000"),
            "{}",
            study.reference
        );
        for r in &study.rows {
            assert!(
                r.energy_balance_error < 1e-10,
                "{}: {:e}",
                r.setting,
                r.energy_balance_error
            );
            assert!(
                r.band_db.is_finite() && r.band_db > 0.0,
                "{}: {}",
                r.setting,
                r.band_db
            );
        }
        assert!(study.reference_energy_balance_error < 1e-10);
    }
}
