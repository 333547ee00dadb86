//! Sweep of the modal von Kármán plate (SEED.md 3.1): circular free and clamped, rectangular
//! simply supported, each scheme, over strike force (1e-6 to 1e5 N), thickness (0.1 to 10 mm),
//! radius or sides (0.05 to 3 m), damping (none, the lecture's law, critical, ten times
//! critical), simulation rate (8 kHz to 4 MHz) and mode counts (N_Φ from 1 to 2000).
//!
//! Cases are built through the scene route ([`PlateSpec`] → [`PlateVoice`]), so they cover the
//! scaling and validation a user's scene goes through. Design: each axis is varied alone around
//! a base case (the default gong's material, a = 0.3 m or 0.4 × 0.6 m, h = 1 mm, 60 N, 48 kHz),
//! plus corner cases combining the extremes.

use super::{check_finite_outputs, BalanceMeter, Case, Density, RunResult};
use crate::models::plate::voice::PlateVoice;
use crate::render::source::RenderSource;
use crate::scene::plate::{
    Damping, Excitation, Material, PlateScheme, PlateShape, PlateSpec, Position, ShapePart,
};
use crate::ParamError;

/// Steps per call to `process`: one, so the energy is sampled every step (a struck
/// model's energy can peak and fall back within a few hundred steps, and the balance error is
/// measured relative to that peak).
const BLOCK: usize = 1;

/// The varied parameters of one plate case.
#[derive(Debug, Clone, Copy)]
struct PlateCase {
    shape: PlateShape,
    scheme: PlateScheme,
    size: f64,
    thickness: f64,
    force: f64,
    damping: Damping,
    fs: f64,
    n_phi: usize,
    n_psi: usize,
    /// Rest shape's rise in thicknesses (0: flat): a spherical cap plus a centre boss of half
    /// that height on circles, a dome on rectangles.
    rise: f64,
}

impl PlateCase {
    fn label(&self) -> String {
        let d = match self.damping {
            Damping::None => "lossless".to_string(),
            Damping::Power { a, b, .. } => format!("c=({a})w^{b}"),
            Damping::Q { q } => format!("Q={q}"),
            Damping::T60 { seconds } => format!("T60={seconds}s"),
        };
        let rise = if self.rise > 0.0 {
            format!(" rise={}h", self.rise)
        } else {
            String::new()
        };
        format!(
            "size={} m h={} mm F={:e} N {d} fs={} N_phi={} N_psi={}{rise}",
            self.size,
            self.thickness * 1e3,
            self.force,
            self.fs,
            self.n_phi,
            self.n_psi
        )
    }

    fn scene(&self) -> PlateSpec {
        let circular = self.shape.is_circular();
        let at = if circular {
            Position {
                r: Some(0.83),
                angle: Some(0.3),
                ..Position::default()
            }
        } else {
            Position {
                x: Some(0.37),
                y: Some(0.41),
                ..Position::default()
            }
        };
        PlateSpec {
            shape: self.shape,
            radius: circular.then_some(self.size),
            lx: (!circular).then_some(self.size),
            ly: (!circular).then_some(1.5 * self.size),
            thickness: self.thickness,
            material: Material::default(),
            n_phi: self.n_phi,
            n_psi: self.n_psi,
            symmetry: Default::default(),
            sim_rate: self.fs,
            scheme: self.scheme,
            sav_relaxation: crate::models::plate::spec::default_sav_relaxation(),
            closure: 0.0,
            band_above: false,
            strike_above: false,
            tensor_storage: Default::default(),
            damping: self.damping,
            excitation: Excitation::Strike {
                at,
                duration: 1e-3,
                peak_force: self.force,
            },
            pickups: Vec::new(),
            imperfection: self.imperfection(),
        }
    }

    fn imperfection(&self) -> Vec<ShapePart> {
        let rise = self.rise * self.thickness;
        if rise == 0.0 {
            Vec::new()
        } else if self.shape.is_circular() {
            vec![
                ShapePart::Spherical {
                    rise: Some(rise),
                    curvature_radius: None,
                },
                ShapePart::Boss {
                    rise: 0.5 * rise,
                    radius: 0.2,
                },
            ]
        } else {
            vec![ShapePart::Dome { rise }]
        }
    }
}

/// Builds the voice and runs `steps` steps, checking outputs, energies and divergence.
fn run_case(c: PlateCase, steps: usize) -> Result<RunResult, ParamError> {
    let scene = c.scene();
    scene.validate()?;
    let mut voice = PlateVoice::build(&scene)?;
    let conservative = voice.is_conservative();
    let mut out = vec![vec![0.0; BLOCK]; voice.channels()];
    let mut meter = BalanceMeter::default();
    meter.record(&voice.energy());
    let mut done = 0usize;
    while done < steps {
        let n = BLOCK.min(steps - done);
        voice.process(&mut out, n);
        done += n;
        if voice.model().is_diverged() {
            return Ok(RunResult {
                energy_error: None,
                steps: done as u64,
                failure: Some(format!("diverged (non-finite state) by step {done}")),
                diverged: true,
                tolerance: None,
            });
        }
        for ch in &out {
            if let Some(f) = check_finite_outputs("output", done as u64, &ch[..n]) {
                return Ok(RunResult {
                    energy_error: None,
                    steps: done as u64,
                    failure: Some(f),
                    ..RunResult::default()
                });
            }
        }
        if let Some(f) = check_finite_outputs("q", done as u64, voice.model().q()) {
            return Ok(RunResult {
                energy_error: None,
                steps: done as u64,
                failure: Some(f),
                ..RunResult::default()
            });
        }
        meter.record(&voice.energy());
    }
    if meter.non_finite() {
        return Ok(RunResult {
            energy_error: None,
            steps: done as u64,
            failure: Some("non-finite energy term".into()),
            ..RunResult::default()
        });
    }
    // The plate stores the two levels (q(n), q(n-1)); each step rounds q(n+1) at ε|q|, which
    // perturbs δ_{t-}q by ε|q|/h, i.e. the kinetic energy relatively by about 2ε/(ω_min h) at
    // the slowest mode. Accumulated linearly over the run this gives the tolerance below; it
    // only exceeds ENERGY_TOLERANCE at heavy oversampling (fs = 4 MHz: ω_min h ≈ 1e-4, 80 000
    // steps, bound 2e-7, measured 6.5e-8). The string avoids this by storing increments.
    let omega_min_h = std::f64::consts::TAU * voice.info().f_min / c.fs;
    let rounding = 2.0 * f64::EPSILON * done as f64 / omega_min_h;
    Ok(RunResult {
        energy_error: conservative.then(|| meter.relative_error()),
        steps: done as u64,
        failure: None,
        diverged: false,
        tolerance: Some(rounding.max(super::ENERGY_TOLERANCE)),
    })
}

/// All plate cases.
pub fn cases(density: Density) -> Vec<Case> {
    let full = density == Density::Full;
    // Simulated time per case and the work budget (steps × N_Φ × (N_Ψ + 1)) that caps it.
    let (seconds, budget) = if full { (0.2, 4e9) } else { (0.02, 2e7) };
    let forces: &[f64] = if full {
        &[1e-6, 1e-2, 1e3, 1e5]
    } else {
        &[1e-6, 1e5]
    };
    let thick: &[f64] = if full {
        &[1e-4, 3e-4, 3e-3, 1e-2]
    } else {
        &[1e-4, 1e-2]
    };
    let sizes: &[f64] = if full {
        &[0.05, 0.1, 1.0, 3.0]
    } else {
        &[0.05, 3.0]
    };
    let rates: &[f64] = if full {
        &[8e3, 22.05e3, 192e3, 1e6, 4e6]
    } else {
        &[8e3, 4e6]
    };
    let modes: &[(usize, usize)] = if full {
        &[
            (1, 0),
            (1, 1),
            (2, 1),
            (60, 20),
            (200, 60),
            (400, 100),
            (2000, 10),
        ]
    } else {
        &[(1, 0), (1, 1), (60, 20), (2000, 2)]
    };
    // Rest shapes up to the largest accepted rise (500 thicknesses, κ = 1000 for a cap).
    let rises: &[f64] = if full {
        &[1.0, 10.0, 50.0, 500.0]
    } else {
        &[10.0, 500.0]
    };
    let dampings = [
        Damping::None,
        // Critical for every mode: c = 2ω (ξ = 1); then ten times critical.
        Damping::Power {
            a: 2.0,
            b: 1.0,
            c0: 0.0,
        },
        Damping::Power {
            a: 20.0,
            b: 1.0,
            c0: 0.0,
        },
    ];
    let mut out = Vec::new();
    for shape in [
        PlateShape::CircularFree,
        PlateShape::CircularClamped,
        PlateShape::RectSs,
    ] {
        for scheme in [
            PlateScheme::ConservativeTheta1,
            PlateScheme::ConservativeExact,
            PlateScheme::StormerVerletExact,
            PlateScheme::SavExact,
        ] {
            let base = PlateCase {
                shape,
                scheme,
                size: if shape.is_circular() { 0.3 } else { 0.4 },
                thickness: 1e-3,
                force: 60.0,
                damping: Damping::Power {
                    a: 0.005,
                    b: 0.6,
                    c0: 0.0,
                },
                fs: 48e3,
                n_phi: 10,
                n_psi: 5,
                rise: 0.0,
            };
            let mut list = vec![base];
            list.extend(forces.iter().map(|&force| PlateCase { force, ..base }));
            list.extend(
                thick
                    .iter()
                    .map(|&thickness| PlateCase { thickness, ..base }),
            );
            list.extend(sizes.iter().map(|&size| PlateCase { size, ..base }));
            list.extend(rates.iter().map(|&fs| PlateCase { fs, ..base }));
            list.extend(
                dampings
                    .iter()
                    .map(|&damping| PlateCase { damping, ..base }),
            );
            list.extend(modes.iter().map(|&(n_phi, n_psi)| PlateCase {
                n_phi,
                n_psi,
                ..base
            }));
            list.extend(rises.iter().map(|&rise| PlateCase { rise, ..base }));
            // Corners: thin, large and hit hard at the lowest rate, lossless; thick, small
            // and touched at the highest rate, over-damped; thin, small, hit hard, lossless.
            list.push(PlateCase {
                thickness: 1e-4,
                size: 3.0,
                force: 1e5,
                fs: 8e3,
                damping: Damping::None,
                ..base
            });
            list.push(PlateCase {
                thickness: 1e-2,
                size: 0.05,
                force: 1e-6,
                fs: 4e6,
                damping: dampings[2],
                ..base
            });
            list.push(PlateCase {
                thickness: 1e-4,
                size: 0.05,
                force: 1e5,
                damping: Damping::None,
                ..base
            });
            // The most curved plate, hit hard at the lowest rate, lossless.
            list.push(PlateCase {
                rise: 500.0,
                force: 1e5,
                fs: 8e3,
                damping: Damping::None,
                ..base
            });
            for c in list {
                let work = (c.n_phi * (c.n_psi + 1)) as f64;
                let steps = ((seconds * c.fs).min(budget / work).max(64.0)) as usize;
                // θ = 1 is stable only for fs > f_max π: a refusal naming fs is expected
                // where that fails; the other schemes have no linear limit.
                let may_refuse = scheme == PlateScheme::ConservativeTheta1;
                let family = format!(
                    "plate {} {}",
                    shape_name(shape),
                    match scheme {
                        PlateScheme::ConservativeTheta1 => "conservative",
                        PlateScheme::ConservativeExact => "conservative-exact",
                        PlateScheme::StormerVerletExact => "stormer-verlet",
                        PlateScheme::SavExact => "sav",
                    }
                );
                let case = Case::new(family, c.label(), may_refuse, move || run_case(c, steps));
                // Störmer-Verlet's explicit nonlinear term is stable only below an
                // amplitude-dependent limit (SEED 1.3): a divergence is detected and reported.
                out.push(if scheme == PlateScheme::StormerVerletExact {
                    case.may_diverge()
                } else {
                    case
                });
            }
        }
    }
    out
}

fn shape_name(s: PlateShape) -> &'static str {
    match s {
        PlateShape::CircularFree => "circular-free",
        PlateShape::CircularClamped => "circular-clamped",
        PlateShape::RectSs => "rect-ss",
    }
}
