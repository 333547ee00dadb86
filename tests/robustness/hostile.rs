//! Hostile input: a proptest fuzz of the scene parser and of model construction.
//!
//! Scene fuzz: a shipped scene is mutated by random `--set` overrides (the CLI's own route:
//! unknown fields, wrong types, NaN/Inf, negative and zero sizes, absurd mode counts, valid
//! values that reach deeper validation), line deletions and truncation, then parsed. Never a
//! panic; every error is either a parse error with a location (`line N, column M`, or the
//! dotted path of the field in backticks) or a range error naming field, value and allowed
//! range. A scene that parses and is small enough to build quickly is built (a plate voice or a
//! string) and run for a few steps: its outputs must be finite, and a string's power balance
//! must hold (see [`check_string_run`]). The bases are plate scenes and the sitar string scene.
//!
//! Model fuzz: the stiff string built from arbitrary floats (NaN, infinities, negatives,
//! zeros, huge) and grid sizes: a clear `ParamError` or a model that steps with finite outputs,
//! a conserved energy (lossless) and an energy that never exceeds the initial one. Those
//! arbitrary floats rarely make a buildable string, so a third fuzz draws valid but extreme
//! strings (sizes, rates and contact laws over decades) and runs each through the same checks.
//!
//! Bounded: `PROPTEST_CASES` (default 256 scene cases, 256 string cases) keeps it to a few
//! seconds at opt-level 3.

use noether::models::plate::voice::PlateVoice;
use noether::models::string::{
    ContactLaw, ContactScheme, Losses, Obstacle, OutputChannel, Quantity, Readout, SitarBridge,
    StiffString, Stiffness, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use noether::render::source::RenderSource;
use noether::scene::{Scene, SceneError};
use proptest::prelude::*;

const BASES: &[&str] = &[
    include_str!("../../assets/scenes/gong.toml"),
    include_str!("../../assets/scenes/seed-rect-energy.toml"),
    include_str!("../../assets/scenes/seed-gong-40N.toml"),
    include_str!("../../assets/scenes/seed-sitar.toml"),
];

/// Small-size overrides applied first to each base (the random overrides may replace them), so
/// that scenes surviving the mutations build and step quickly: a plate with 12/6 modes, or the
/// sitar with 63 modes at 96 kHz (top partial 6.4 kHz, below Nyquist).
fn small(base: usize) -> [String; 2] {
    if BASES[base].contains("[string]") {
        ["string.modes=63".into(), "string.sim_rate=96000".into()]
    } else {
        ["plate.n_phi=12".into(), "plate.n_psi=6".into()]
    }
}

/// Field paths the overrides aim at: every scene field, plus unknown ones.
const PATHS: &[&str] = &[
    "name",
    "description",
    "output.sample_rate",
    "output.seconds",
    "output.gain_db",
    "plate.shape",
    "plate.radius",
    "plate.lx",
    "plate.ly",
    "plate.thickness",
    "plate.material.youngs_modulus",
    "plate.material.density",
    "plate.material.poisson",
    "plate.n_phi",
    "plate.n_psi",
    "plate.sim_rate",
    "plate.scheme",
    "plate.damping",
    "plate.damping.law",
    "plate.damping.a",
    "plate.damping.b",
    "plate.damping.c0",
    "plate.damping.q",
    "plate.damping.seconds",
    "plate.excitation",
    "plate.excitation.kind",
    "plate.excitation.at",
    "plate.excitation.at.r",
    "plate.excitation.at.angle",
    "plate.excitation.at.x",
    "plate.excitation.at.y",
    "plate.excitation.duration",
    "plate.excitation.peak_force",
    "plate.excitation.impulse",
    "plate.excitation.mode",
    "plate.excitation.displacement",
    "plate.excitation.velocity",
    "plate.pickups",
    "plate",
    "output",
    "bogus",
    "plate.bogus",
    "output.bogus",
    "plate.material.bogus",
    "plate.excitation.at.bogus",
    "string",
    "string.length",
    "string.diameter",
    "string.tension",
    "string.linear_density",
    "string.inharmonicity",
    "string.bending_stiffness",
    "string.modes",
    "string.sim_rate",
    "string.losses",
    "string.losses.law",
    "string.obstacle",
    "string.obstacle.kind",
    "string.obstacle.position",
    "string.obstacle.curvature",
    "string.obstacle.height",
    "string.obstacle.extent",
    "string.contact",
    "string.contact.stiffness",
    "string.contact.exponent",
    "string.contact_scheme",
    "string.excitation",
    "string.excitation.kind",
    "string.excitation.position",
    "string.excitation.amplitude",
    "string.outputs",
    "string.snapshots",
    "string.bogus",
];

/// Values, raw as on the command line: hostile ones and valid ones that get deeper.
const VALUES: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "-1.0",
    "0",
    "0.0",
    "-0.0",
    "1e308",
    "-1e308",
    "1e-320",
    "9223372036854775807",
    "-9223372036854775808",
    "4001",
    "1000000000",
    "\"text\"",
    "true",
    "[1, 2]",
    "{ a = 1 }",
    "{}",
    "[]",
    "",
    "=",
    "0.3",
    "0.001",
    "1",
    "2",
    "3",
    "8000",
    "4000000",
    "rect-ss",
    "circular-clamped",
    "circular-free",
    "stormer-verlet",
    "conservative",
    "conservative-exact",
    "impulse",
    "initial",
    "strike",
    "power",
    "q",
    "t60",
    "none",
    "{ r = 0.5, angle = 1e300 }",
    "{ x = 0.5, y = 0.5 }",
    "[{ at = { r = 0.5 } }]",
    "[{ at = { x = 2.0, y = 0.5 }, quantity = \"velocity\" }]",
    "{ law = \"power\", a = 1e300, b = 2.0 }",
    "{ law = \"q\", q = 1 }",
    "{ kind = \"initial\", mode = 1, displacement = 1.0, velocity = 1e4 }",
    "{ kind = \"impulse\", at = { r = 0.0 }, impulse = 1000.0 }",
    "{ kind = \"strike\", at = { r = 1.0 }, duration = 1e-5, peak_force = 1e6 }",
    "valette",
    "quadratised",
    "newton",
    "pluck",
    "sitar",
    "fretboard",
    "1e13",
    "1e18",
    "1.5",
    "{ law = \"none\" }",
    "{ kind = \"point\", position = 0.5, height = 1e-4, width = 0.0 }",
    "{ kind = \"fretboard\", distance = 1e-4 }",
    "{ stiffness = 1e16, exponent = 10 }",
    "{ kind = \"pluck\", position = 0.5, amplitude = 1e-2 }",
    "[{ kind = \"pickup\", position = 0.5, quantity = \"displacement\" }]",
];

/// Power-balance tolerance of the fuzzed strings, relative to the largest energy of the run: the
/// stress sweep's bound (`noether::stress::ENERGY_TOLERANCE`, whose measured worst case is a
/// penetrating bridge at K = 1e16; the fuzz's contact laws stay within that range). A broken
/// balance (a wrong contact force term, a missing loss) shows at 1e-6 or above.
const BALANCE_TOLERANCE: f64 = noether::stress::ENERGY_TOLERANCE;

/// Runs a built string `steps` steps, one per `process` call: every output finite; the power
/// balance `H + dissipated - work` constant to [`BALANCE_TOLERANCE`] of the largest `H`; and,
/// when no external force works on it (`work = 0`: a pluck, no strike), the energy bounded by its
/// initial value, `H_n <= H_0 (1 + tol)` (the schemes never create energy).
fn check_string_run(s: &mut StiffString, steps: usize) -> Result<(), TestCaseError> {
    let mut out = vec![vec![0.0; 1]; s.channels()];
    let first = s.energy();
    let mut max = first.total();
    let mut drift = 0.0f64;
    for _ in 0..steps {
        s.process(&mut out, 1);
        prop_assert!(
            out.iter().all(|c| c[0].is_finite()),
            "non-finite output {out:?}"
        );
        let e = s.energy();
        prop_assert!(e.total().is_finite() && e.balance().is_finite(), "{e:?}");
        max = max.max(e.total());
        drift = drift.max((e.balance() - first.balance()).abs());
        if e.work == 0.0 {
            prop_assert!(
                e.total() <= first.total() * (1.0 + BALANCE_TOLERANCE),
                "energy grew: {} > {}",
                e.total(),
                first.total()
            );
        }
    }
    prop_assert!(
        drift <= BALANCE_TOLERANCE * max,
        "power balance drift {drift:e} of max energy {max:e}"
    );
    Ok(())
}

/// Whether a scene error says where or what: a TOML location, a field path in backticks, or a
/// range error with field, value and allowed range.
fn error_is_clear(e: &SceneError) -> bool {
    match e {
        SceneError::Invalid(p) => {
            !p.field.is_empty() && !p.value.is_empty() && !p.allowed.is_empty()
        }
        SceneError::Parse(m) => m.contains("line ") || m.contains('`'),
        // Names the file.
        SceneError::Io { path, .. } => !path.as_os_str().is_empty(),
        // Quotes the override (`invalid --set `...``).
        SceneError::Set(_) => true,
    }
}

/// Builds and runs a parsed scene when it is cheap enough (small mode counts): a clear error or
/// finite outputs.
fn build_and_step(scene: &Scene) -> Result<(), TestCaseError> {
    if let Some(string) = scene.string.as_ref() {
        if string.modes > 200 {
            return Ok(());
        }
        match noether::render::scene::build_string(string) {
            Err(e) => prop_assert!(
                !e.field.is_empty() && !e.value.is_empty() && !e.allowed.is_empty(),
                "unclear build error: {e:?}"
            ),
            Ok(mut s) => check_string_run(&mut s, 64)?,
        }
    }
    let Some(plate) = scene.plate.as_ref() else {
        return Ok(());
    };
    if plate.n_phi > 40 || plate.n_psi > 20 {
        return Ok(());
    }
    match PlateVoice::build(plate) {
        Err(e) => prop_assert!(
            !e.field.is_empty() && !e.value.is_empty() && !e.allowed.is_empty(),
            "unclear build error: {e:?}"
        ),
        Ok(mut v) => {
            let mut out = vec![vec![0.0; 64]; v.channels()];
            v.process(&mut out, 64);
            for c in &out {
                prop_assert!(c.iter().all(|x| x.is_finite()), "non-finite output");
            }
        }
    }
    Ok(())
}

/// The unmutated bases with the fuzz's small mode counts parse and build, so the fuzz reaches
/// the voice build whenever its mutations leave a valid scene.
#[test]
fn small_base_scenes_build() {
    noether_testkit::env::test_cache_dir();
    for (i, base) in BASES.iter().enumerate() {
        let scene = Scene::from_toml(base, "base.toml", &small(i)).unwrap();
        build_and_step(&scene).unwrap();
        match (&scene.plate, &scene.string) {
            (Some(p), _) => assert!(PlateVoice::build(p).is_ok()),
            (None, Some(s)) => assert!(noether::render::scene::build_string(s).is_ok()),
            (None, None) => panic!("base {i} has no model"),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_never_panic_and_errors_are_clear(
        base in 0..BASES.len(),
        sets in prop::collection::vec((0..PATHS.len(), 0..VALUES.len()), 0..4),
        delete_line in prop::option::of(0usize..40),
        truncate in prop::option::of(0.0f64..1.0),
        garbage in prop::option::of((0.0f64..1.0, any::<u8>())),
    ) {
        noether_testkit::env::test_cache_dir();
        let mut text: String = BASES[base]
            .lines()
            .enumerate()
            .filter(|(i, _)| Some(*i) != delete_line)
            .map(|(_, l)| format!("{l}\n"))
            .collect();
        if let Some(f) = truncate {
            let mut cut = (text.len() as f64 * f) as usize;
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            text.truncate(cut);
        }
        if let Some((f, b)) = garbage {
            let mut bytes = text.into_bytes();
            let at = ((bytes.len() as f64) * f) as usize;
            bytes.insert(at.min(bytes.len()), b);
            text = String::from_utf8_lossy(&bytes).into_owned();
        }
        // Small mode counts first (the random overrides may replace them), so that scenes
        // which survive the mutations are cheap enough to build and step.
        let overrides: Vec<String> = small(base)
            .into_iter()
            .chain(sets.iter().map(|&(p, v)| format!("{}={}", PATHS[p], VALUES[v])))
            .collect();
        match Scene::from_toml(&text, "fuzz.toml", &overrides) {
            Err(e) => prop_assert!(error_is_clear(&e), "unclear error: {e}"),
            Ok(scene) => build_and_step(&scene)?,
        }
    }

    #[test]
    fn arbitrary_strings_are_refused_clearly_or_step(
        floats in prop::collection::vec(
            prop_oneof![
                Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY), Just(0.0),
                Just(-1.0), Just(1e308), Just(1e-310), -1e3f64..1e3, 1e-6f64..1e4,
            ],
            10,
        ),
        intervals in prop_oneof![0usize..8, 8usize..600, Just(1usize << 21)],
        obstacle_kind in 0..4usize,
    ) {
        let f = &floats;
        let params = StringParams {
            length: f[0],
            tension: f[1],
            linear_density: f[2] * 1e-3,
            stiffness: if f[3] > 0.0 { Stiffness::Inharmonicity(f[3] * 1e-5) }
                       else { Stiffness::BendingStiffness(f[3]) },
            diameter: f[4] * 1e-4,
            intervals,
            sample_rate: f[5] * 1e3,
        };
        let obstacle = match obstacle_kind {
            0 => Obstacle::None,
            1 => Obstacle::Sitar(SitarBridge { position: 0.0, curvature: f[6], height: f[7] * 1e-4, extent: f[8] * 1e-3 }),
            2 => Obstacle::Point { position: f[8] * 1e-3, height: f[7] * 1e-4, width: f[6] * 1e-3 },
            _ => Obstacle::Fretboard { distance: f[7] * 1e-4 },
        };
        let config = StringConfig {
            params,
            losses: Losses::None,
            obstacle,
            contact: ContactLaw { stiffness: f[9].abs() * 1e10, exponent: 1.0 + f[6].abs() % 4.0 },
            outputs: vec![
                OutputChannel::Pickup { position: f[8] * 1e-3, quantity: Quantity::Velocity, readout: Readout::Grid },
                OutputChannel::ObstacleForce,
            ],
        };
        match StiffString::new(&config) {
            Err(e) => prop_assert!(
                !e.field.is_empty() && !e.value.is_empty() && !e.allowed.is_empty(),
                "unclear error: {e:?}"
            ),
            Ok(mut s) => {
                // Built: a pluck is validated the same way, then a few steps run.
                let pluck = TrianglePluck { position: f[0] * 0.3, amplitude: f[7] * 1e-6 };
                match s.pluck(&pluck) {
                    Err(e) => prop_assert!(!e.field.is_empty() && !e.allowed.is_empty()),
                    Ok(()) => check_string_run(&mut s, 16)?,
                }
            }
        }
    }

    /// Valid but extreme strings (the arbitrary floats above almost never make a buildable
    /// string): sizes, tensions and rates over decades, every obstacle kind, contact laws up to
    /// K = 1e14 and α = 5, both contact schemes, lossless or damped, plucks from 1 nm to 1 cm.
    /// Each is built and run 256 steps through [`check_string_run`].
    #[test]
    fn extreme_valid_strings_step_finitely_and_conservatively(
        length in 0.05f64..5.0,
        tension in 1.0f64..1e4,
        density in 1e-5f64..1e-1,
        inharmonicity in prop_oneof![Just(0.0), 1e-6f64..1e-2],
        intervals in 2usize..300,
        fs in prop_oneof![Just(8e3), Just(48e3), Just(1e6), 8e3f64..4e6],
        obstacle_kind in 0..5usize,
        height in -1e-3f64..1e-3,
        stiffness_exp in 0.0f64..14.0,
        exponent in 1.0f64..5.0,
        quadratised in any::<bool>(),
        damped in any::<bool>(),
        at in 0.05f64..0.95,
        amplitude_exp in -9.0f64..-2.0,
    ) {
        let params = StringParams {
            length,
            tension,
            linear_density: density,
            stiffness: Stiffness::Inharmonicity(inharmonicity),
            diameter: 0.43e-3,
            intervals,
            sample_rate: fs,
        };
        let obstacle = match obstacle_kind {
            0 => Obstacle::None,
            1 => Obstacle::Sitar(SitarBridge {
                height,
                // At least one grid node, inside the string.
                extent: (0.3 * length).max(1.5 * length / intervals as f64).min(0.9 * length),
                ..SitarBridge::seed()
            }),
            2 => Obstacle::Point { position: at * length, height, width: 0.0 },
            3 => Obstacle::Fretboard { distance: height.abs() },
            _ => Obstacle::Points(vec![(0.25 * length, height), (0.75 * length, -height)]),
        };
        let config = StringConfig {
            params,
            losses: if damped { Losses::Valette(ValetteLosses::default()) } else { Losses::None },
            obstacle,
            contact: ContactLaw { stiffness: 10f64.powf(stiffness_exp), exponent },
            outputs: vec![
                OutputChannel::Pickup {
                    position: 0.37 * length,
                    quantity: Quantity::Velocity,
                    readout: Readout::Modal,
                },
                OutputChannel::ObstacleForce,
            ],
        };
        let mut s = StiffString::new(&config).map_err(|e| TestCaseError::fail(format!("{e}")))?;
        if quadratised {
            s.set_contact_scheme(ContactScheme::Quadratised);
        }
        s.pluck(&TrianglePluck { position: at * length, amplitude: 10f64.powf(amplitude_exp) })
            .map_err(|e| TestCaseError::fail(format!("{e}")))?;
        check_string_run(&mut s, 256)?;
    }
}

/// The case the string fuzz found (a 1e308 m string at 1e-310 N, 1e305 kg/m and a rate of
/// 1e-307 Hz): every derived quantity was finite, the build passed and the first step gave
/// NaN. The string's parameters now have the scenes' ranges at the core too (the rate a wider
/// one, for convergence studies), so it is refused naming the length.
#[test]
fn the_fuzzed_overflowing_string_is_refused() {
    let params = StringParams {
        length: 1e308,
        tension: 1e-310,
        linear_density: 1e305,
        stiffness: Stiffness::Inharmonicity(1e303),
        diameter: 1e304,
        intervals: 2,
        sample_rate: 1e-307,
    };
    let config = StringConfig {
        params,
        losses: Losses::None,
        obstacle: Obstacle::None,
        contact: ContactLaw {
            stiffness: 1e-300,
            exponent: 1.0,
        },
        outputs: vec![OutputChannel::Pickup {
            position: 1e305,
            quantity: Quantity::Velocity,
            readout: Readout::Grid,
        }],
    };
    let Err(e) = StiffString::new(&config) else {
        panic!("the overflowing string was built")
    };
    assert_eq!(e.field, "length");
    assert!(e.allowed.contains("[0.01, 100]"), "{e:?}");
}
