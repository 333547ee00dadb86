//! The catalogue of model × scheme cases: plates (circular free and clamped, rectangle) under
//! every scheme, lossless and damped with a strike; strings with Newton and quadratised contact;
//! the one-oscillator schemes. Each case states its tolerance with the round-off measured on it.

use super::*;

/// Runs every case of `family` through [`check`], printing each outcome (`--nocapture`).
pub fn check_family(family: Family) -> Vec<Outcome> {
    catalogue()
        .iter()
        .filter(|c| c.family == family)
        .map(|c| {
            let o = check(c);
            eprintln!("{o}");
            o
        })
        .collect()
}

// ---------------------------------------------------------------- the catalogue

/// Every plate scheme of the scenes, with its scene name.
pub const PLATE_SCHEMES: [PlateScheme; 4] = [
    PlateScheme::ConservativeTheta1,
    PlateScheme::ConservativeExact,
    PlateScheme::SavExact,
    PlateScheme::StormerVerletExact,
];

/// Transverse and in-plane mode counts of the catalogue's plates: 24 and 12 (the conservative
/// schemes then solve through the Woodbury identity, `N_Ψ < N_Φ`), except the clamped disc's 12
/// and 16 (the direct route), so both routes are covered.
pub fn plate_modes(shape: PlateShape) -> (usize, usize) {
    match shape {
        PlateShape::CircularClamped => (12, 16),
        _ => (24, 12),
    }
}

/// A plate scene of the catalogue: 0.3 m disc or 0.4 × 0.6 m rectangle of 1 mm steel,
/// [`plate_modes`] modes at 48 kHz, the default stereo velocity pickups.
pub fn plate_spec(
    shape: PlateShape,
    scheme: PlateScheme,
    damping: Damping,
    excitation: Excitation,
) -> PlateSpec {
    let circular = shape.is_circular();
    let (n_phi, n_psi) = plate_modes(shape);
    PlateSpec {
        shape,
        radius: circular.then_some(0.3),
        lx: (!circular).then_some(0.4),
        ly: (!circular).then_some(0.6),
        thickness: 1e-3,
        material: Default::default(),
        n_phi,
        n_psi,
        symmetry: Symmetry::Full,
        sim_rate: 48_000.0,
        scheme,
        sav_relaxation: noether_core::models::plate::spec::default_sav_relaxation(),
        closure: 0.0,
        band_above: false,
        strike_above: false,
        tensor_storage: Default::default(),
        damping,
        excitation,
        pickups: Vec::new(),
        imperfection: Vec::new(),
    }
}

/// The catalogue's lossless plate case: a 4 N·s impulse at `(r, θ) = (0.5, 0.3)` on the
/// discs, `(0.37, 0.41)` of the sides on the rectangle, no damping ([`plate_spec`]'s modes and
/// rate). Tolerances and measured errors: the catalogue's plate cases.
pub fn lossless_impulse_spec(shape: PlateShape, scheme: PlateScheme) -> PlateSpec {
    let impulse = Excitation::Impulse {
        at: plate_at(shape, (0.5, 0.3), (0.37, 0.41)),
        impulse: 4.0,
    };
    plate_spec(shape, scheme, Damping::None, impulse)
}

/// The catalogue's damped plate case: ten times the lecture's damping law (a = 0.05,
/// b = 0.6) and a 600 N, 1 ms raised-cosine strike at `r = 0.92` on the discs, `(0.13, 0.21)`
/// of the sides on the rectangle.
pub fn damped_strike_spec(shape: PlateShape, scheme: PlateScheme) -> PlateSpec {
    let strike = Excitation::Strike {
        at: plate_at(shape, (0.92, 0.0), (0.13, 0.21)),
        duration: 1e-3,
        peak_force: 600.0,
    };
    let damping = Damping::Power {
        a: 0.05,
        b: 0.6,
        c0: 0.0,
    };
    plate_spec(shape, scheme, damping, strike)
}

fn plate_at(shape: PlateShape, circular: (f64, f64), rect: (f64, f64)) -> Position {
    if shape.is_circular() {
        Position {
            r: Some(circular.0),
            angle: Some(circular.1),
            ..Position::default()
        }
    } else {
        Position {
            x: Some(rect.0),
            y: Some(rect.1),
            ..Position::default()
        }
    }
}

/// The plate cases of the catalogue with the coupling tensor in `storage`: the same scenes,
/// tolerances and exercise for either storage (single storage rounds the tensor once and the
/// model sees that one tensor, so its energy identity holds to the same round-off). Names
/// of single-storage cases end in `-single`.
pub fn plate_catalogue(storage: TensorStorage) -> Vec<Case> {
    let mut cases = Vec::new();
    plate_cases(&mut cases, storage);
    cases
}

fn plate_cases(cases: &mut Vec<Case>, storage: TensorStorage) {
    let suffix = match storage {
        TensorStorage::Double => "",
        TensorStorage::Single => "-single",
    };
    let shapes = [
        (
            PlateShape::CircularFree,
            Family::CircularFree,
            "circular-free",
        ),
        (
            PlateShape::CircularClamped,
            Family::CircularClamped,
            "circular-clamped",
        ),
        (PlateShape::RectSs, Family::Rectangle, "rect-ss"),
    ];
    for (shape, family, shape_name) in shapes {
        for scheme in PLATE_SCHEMES {
            let (conservative, scheme_name) = (scheme.is_conservative(), scheme.name());
            // Lossless, a 4 N·s impulse, 1 s (48 000 steps): the in-plane energy reaches 80 %
            // of the total. Measured balance error (here the energy drift), free / clamped /
            // rect: conservative 3.4e-13 / 5.2e-13 / 1.3e-13, conservative-exact 5.2e-13 /
            // 4.8e-13 / 1.7e-13, sav 7.9e-13 / 9.7e-14 / 7.7e-14. Tolerance 3e-12, about 4×
            // the worst: the discrete identity is exact, so only round-off accumulates, ~ε of
            // the energy a step from the energy's own sums (the in-plane energy is a sum over
            // the coupling tensor whose terms exceed their total) and the linear solve, over
            // 48 000 steps. Störmer-Verlet's deviation on the same runs: 1.8e-3 to 7.3e-3,
            // required in [1e-4, 0.1] (bounded, and eight orders above the tolerance).
            let mut spec = lossless_impulse_spec(shape, scheme);
            spec.tensor_storage = storage;
            cases.push(Case::new(
                format!("plate/{shape_name}/{scheme_name}/lossless-impulse{suffix}"),
                family,
                48_000,
                if conservative {
                    Expect::Conserves { tol: 3e-12 }
                } else {
                    Expect::Drifts {
                        min: 1e-4,
                        max: 0.1,
                    }
                },
                Exercise {
                    nonlinear_share: 0.5,
                    ..Exercise::default()
                },
                move || {
                    test_cache_dir();
                    Box::new(PlateVoice::build(&spec).expect("catalogue plate"))
                },
            ));
            // Ten times the lecture's damping law (a = 0.05, b = 0.6) and a 600 N, 1 ms strike
            // near the rim from rest, 0.5 s (24 000 steps): the losses remove 68 to 86 % of the
            // energy the strike puts in (in-plane share up to 1 % (clamped) to 41 % (free)), so
            // both accumulators of the balance are exercised. Measured balance error, free /
            // clamped / rect: conservative 1.0e-12 / 6.2e-13 / 2.4e-13, conservative-exact
            // 1.6e-12 / 2.6e-13 / 1.3e-13, sav 1.6e-12 / 6.8e-13 / 9.2e-14. Tolerance 5e-12,
            // about 3× the worst, for the same reason as above (the dissipation and the work
            // are summed each step exactly as the identity states them, adding their own
            // rounding). Störmer-Verlet: 1.8e-6 (clamped, nearly linear) to 1.2e-4, required in
            // [1e-7, 0.1].
            let mut spec = damped_strike_spec(shape, scheme);
            spec.tensor_storage = storage;
            // The same strike on the curved plate (a shallow shell, `plate.imperfection`): a
            // spherical cap of 5 mm (κ = 10) with a 2 mm centre boss on the discs, a 5 mm dome
            // on the rectangle. The rest shape enters every scheme through `q + a` and leaves
            // the energy identity as it is (`model/rest_shape.rs`), so the conservative
            // schemes keep the flat case's tolerance, 5e-12. Measured balance error, free /
            // clamped / rect: conservative 9.0e-13 / 8.4e-13 / 5.7e-13, conservative-exact
            // 2.3e-12 / 3.3e-13 / 7.7e-13, sav 1.5e-12 / 7.4e-13 / 5.7e-13 (`cargo test --test
            // schemes catalogue -- --nocapture`). Störmer-Verlet: 4.6e-5 to 1.4e-4, required
            // in [1e-9, 0.1].
            let mut curved = spec.clone();
            curved.imperfection = if shape.is_circular() {
                vec![
                    ShapePart::Spherical {
                        rise: Some(0.005),
                        curvature_radius: None,
                    },
                    ShapePart::Boss {
                        rise: 0.002,
                        radius: 0.2,
                    },
                ]
            } else {
                vec![ShapePart::Dome { rise: 0.005 }]
            };
            // The curved and the flat plate share the run; only Störmer-Verlet's lower drift
            // bound differs.
            for (variant, spec, drift_min) in [
                ("curved-damped-strike", curved, 1e-9),
                ("damped-strike", spec, 1e-7),
            ] {
                cases.push(Case::new(
                    format!("plate/{shape_name}/{scheme_name}/{variant}{suffix}"),
                    family,
                    24_000,
                    if conservative {
                        Expect::Conserves { tol: 5e-12 }
                    } else {
                        Expect::Drifts {
                            min: drift_min,
                            max: 0.1,
                        }
                    },
                    Exercise {
                        nonlinear_share: 0.005,
                        dissipated_share: 0.5,
                        work_share: 0.9,
                        contact: false,
                    },
                    move || {
                        test_cache_dir();
                        Box::new(PlateVoice::build(&spec).expect("catalogue plate"))
                    },
                ));
            }
        }
    }
}

/// The lecture's string (L = 1 m, T = 180.5 N, μ = 1.17e-3 kg/m, B = 2e-5, d = 0.43 mm) with the
/// lecture's contact law and the given grid, rate, losses, obstacle and contact scheme;
/// outputs: grid displacement and modal velocity at 0.37 m, obstacle force.
pub fn lecture_string(
    intervals: usize,
    fs: f64,
    losses: Losses,
    obstacle: Obstacle,
    scheme: ContactScheme,
) -> StiffString {
    lecture_string_with_law(
        intervals,
        fs,
        losses,
        obstacle,
        ContactLaw::lecture(),
        scheme,
    )
}

/// [`lecture_string`] with the contact law `law` instead of the lecture's.
pub fn lecture_string_with_law(
    intervals: usize,
    fs: f64,
    losses: Losses,
    obstacle: Obstacle,
    law: ContactLaw,
    scheme: ContactScheme,
) -> StiffString {
    let mut s = StiffString::new(&StringConfig {
        params: StringParams::lecture_guitar(intervals, fs),
        losses,
        obstacle,
        contact: law,
        outputs: vec![
            OutputChannel::Pickup {
                position: 0.37,
                quantity: Quantity::Displacement,
                readout: Readout::Grid,
            },
            OutputChannel::Pickup {
                position: 0.37,
                quantity: Quantity::Velocity,
                readout: Readout::Modal,
            },
            OutputChannel::ObstacleForce,
        ],
    })
    .expect("lecture string");
    s.set_contact_scheme(scheme);
    s
}

/// The lecture's pluck: triangle of 1 mm at 0.3 m, at rest.
pub const LECTURE_PLUCK: TrianglePluck = TrianglePluck {
    position: 0.3,
    amplitude: 1e-3,
};

fn string_cases(cases: &mut Vec<Case>) {
    // N = 500 (so the tanpura's point at 6 mm is a node), the lecture's 1 mm pluck, 1 s at
    // 48 kHz or 20 ms at 2 MHz. Measured balance error (Newton / quadratised): lossless sitar
    // 48 kHz 7.2e-14 / 3.8e-14, tanpura 48 kHz 1.7e-14 / 2.3e-14, sitar 2 MHz 2.6e-14 /
    // 1.2e-14, tanpura 2 MHz 1.8e-14 / 2.0e-14; lossy tanpura 2 MHz 4.5e-14 / 3.4e-14; the
    // fretboard strike 4.8e-14 / 7.0e-15; lossy sitar 48 kHz 1.0e-12 / 9.8e-13. Tolerance 3e-13
    // (4× the worst), and 4e-12 for the lossy sitar at 48 kHz (4× its own): the identities
    // are exact, so what is left is round-off (a few ulps of H a step, over 2.4e4 to 4.8e4
    // steps; the lossy 48 kHz run, whose losses remove half the energy, accumulates the
    // rounding of each step's dissipation term besides) plus, for Newton, the residual of an
    // iteration stopped at a relative step of 1e-13; the quadratised node update has no
    // iteration.
    for scheme in ContactScheme::ALL {
        let contact = Exercise {
            contact: true,
            ..Exercise::default()
        };
        let lossy = Exercise {
            contact: true,
            dissipated_share: 1e-3,
            ..Exercise::default()
        };
        let plucked = |n: usize, fs: f64, losses: Losses, obstacle: fn() -> Obstacle| {
            move || -> Box<dyn RenderSource> {
                let mut s = lecture_string(n, fs, losses.clone(), obstacle(), scheme);
                s.pluck(&LECTURE_PLUCK).expect("pluck");
                Box::new(s)
            }
        };
        let valette = || Losses::Valette(ValetteLosses::default());
        let name = scheme.name();
        let conserves = Expect::Conserves { tol: 3e-13 };
        for (situation, steps, build, exercise, tol) in [
            (
                "sitar/lossless-48k",
                48_000,
                Box::new(plucked(500, 48e3, Losses::None, Obstacle::seed_sitar)) as Builder,
                contact,
                3e-13,
            ),
            (
                "tanpura/lossless-48k",
                48_000,
                Box::new(plucked(500, 48e3, Losses::None, Obstacle::tanpura)),
                contact,
                3e-13,
            ),
            (
                "sitar/lossless-2M",
                40_000,
                Box::new(plucked(500, 2e6, Losses::None, Obstacle::seed_sitar)),
                contact,
                3e-13,
            ),
            (
                "tanpura/lossless-2M",
                40_000,
                Box::new(plucked(500, 2e6, Losses::None, Obstacle::tanpura)),
                contact,
                3e-13,
            ),
            (
                "sitar/lossy-48k",
                48_000,
                Box::new(plucked(500, 48e3, valette(), Obstacle::seed_sitar)),
                lossy,
                4e-12,
            ),
            (
                "tanpura/lossy-2M",
                40_000,
                Box::new(plucked(500, 2e6, valette(), Obstacle::tanpura)),
                lossy,
                3e-13,
            ),
        ] {
            cases.push(Case {
                name: format!("string/{situation}/{name}"),
                family: Family::String,
                steps,
                expect: Expect::Conserves { tol },
                exercise,
                build,
            });
        }
        // A 2 N raised-cosine strike at rest against a fretboard 0.2 mm below, with losses: the
        // work term of the balance.
        cases.push(Case::new(
            format!("string/fretboard/lossy-strike-48k/{name}"),
            Family::String,
            24_000,
            conserves,
            Exercise {
                work_share: 0.3,
                ..lossy
            },
            move || {
                let mut s = lecture_string(
                    200,
                    48e3,
                    Losses::Valette(ValetteLosses::default()),
                    Obstacle::Fretboard { distance: 2e-4 },
                    scheme,
                );
                s.strike(&StrikeForce {
                    position: 0.2,
                    duration: 2e-3,
                    peak: -2.0,
                })
                .expect("strike");
                Box::new(s)
            },
        ));
    }
}

fn oscillator_cases(cases: &mut Vec<Case>) {
    // 10⁵ steps each. Measured balance error: θ = 0.5 2.7e-14, exact with ξ = 0.01 8.2e-15,
    // conservative Duffing (θ1, θ2) = (0.5, 0.5) 3.0e-14 and (1, 0) 3.5e-14, impact (K = 1e13,
    // α = 1.5, 1787 contact steps) 3.3e-14. Tolerance 2e-13 (about 6× the worst): the state is
    // stored as (u_n, u_n - u_{n-1}), so each step's rounding moves the energy by O(ε)
    // relatively, ~3e-14 over 10⁵ steps as a random walk. Störmer-Verlet's natural-energy error
    // is an O(h²) oscillation without secular growth: measured 6.0e-3, required in
    // [1e-3, 1e-2].
    let w = 2.0 * std::f64::consts::PI * 100.0;
    let list: [(&str, OscillatorSpec, f64, f64, f64, Expect, bool); 6] = [
        (
            "theta-0.5",
            OscillatorSpec::Theta {
                omega0: 1.0,
                theta: 0.5,
            },
            0.125,
            1.0,
            0.0,
            Expect::Conserves { tol: 2e-13 },
            false,
        ),
        (
            "exact-damped",
            OscillatorSpec::Exact {
                omega0: 1.0,
                xi: 0.01,
            },
            0.31,
            1.0,
            0.5,
            Expect::Conserves { tol: 2e-13 },
            false,
        ),
        (
            "duffing-conservative-0.5-0.5",
            OscillatorSpec::DuffingConservative {
                omega0: 1.0,
                gamma: 5.0,
                theta1: 0.5,
                theta2: 0.5,
            },
            0.0628,
            1.0,
            0.0,
            Expect::Conserves { tol: 2e-13 },
            false,
        ),
        (
            "duffing-conservative-1-0",
            OscillatorSpec::DuffingConservative {
                omega0: 1.0,
                gamma: 5.0,
                theta1: 1.0,
                theta2: 0.0,
            },
            0.0628,
            1.0,
            0.0,
            Expect::Conserves { tol: 2e-13 },
            false,
        ),
        (
            "impact-theta-1",
            OscillatorSpec::Impact {
                mass: 1.0,
                stiffness: w * w,
                contact_stiffness: 1e13,
                alpha: 1.5,
                gap: 1e-4,
                theta: 1.0,
            },
            1.0 / 44_100.0,
            -1e-3,
            0.0,
            Expect::Conserves { tol: 2e-13 },
            true,
        ),
        (
            "duffing-verlet",
            OscillatorSpec::DuffingVerlet {
                omega0: 1.0,
                gamma: 5.0,
            },
            0.0628,
            1.0,
            0.0,
            Expect::Drifts {
                min: 1e-3,
                max: 1e-2,
            },
            false,
        ),
    ];
    for (name, spec, h, u0, v0, expect, contact) in list {
        let exercise = Exercise {
            contact,
            dissipated_share: if name == "exact-damped" { 0.5 } else { 0.0 },
            ..Exercise::default()
        };
        cases.push(Case::new(
            format!("oscillator/{name}"),
            Family::Oscillator,
            100_000,
            expect,
            exercise,
            move || Box::new(OscillatorSource::new(&spec, h, u0, v0)),
        ));
    }
}

/// The whole catalogue: plates (circular free and clamped, rectangle) × the four schemes ×
/// {lossless impulse, damped strike}; strings × {Newton, quadratised contact} × {lossless,
/// lossy} on the sitar and tanpura bridges plus a forced lossy run against a fretboard; the
/// one-oscillator schemes (θ, exact with damping, conservative Duffing, impact, and Störmer-Verlet
/// Duffing as the non-conservative control).
pub fn catalogue() -> Vec<Case> {
    let mut cases = Vec::new();
    plate_cases(&mut cases, TensorStorage::Double);
    string_cases(&mut cases);
    oscillator_cases(&mut cases);
    cases
}
