//! Sweep of the stiff string against an obstacle (SEED.md 3.2) over every obstacle kind
//! (curved sitar bridge, point bridge, fretboard, point list, arbitrary profile) touching, far
//! from and penetrating the string at rest; contact stiffness K (1e3 to 1e16) and exponent α
//! (1 to 4); strike force (1e-6 to 1e5 N) or pluck; damping none, Issanchou/Valette, critical
//! and ten times critical; rates 8 kHz to 4 MHz; one mode to thousands.
//!
//! Every case runs under both contact schemes ([`ContactScheme`]: Newton discrete gradient and
//! energy quadratisation); the quadratised scheme is checked on the balance of its own
//! conserved energy.
//!
//! Base case: the lecture's string (L = 1 m, T = 180.5 N, μ = 1.17e-3 kg/m, B = 2e-5), N = 100
//! intervals, 48 kHz, K = 1e13, α = 1.5, Valette losses, a 1 N, 2 ms strike at 0.37 m towards
//! the obstacle; each axis varied alone, plus corners.

use super::{check_finite_outputs, BalanceMeter, Case, Density, RunResult};
use crate::models::string::{
    ContactLaw, ContactScheme, Losses, Obstacle, OutputChannel, Quantity, Readout, SitarBridge,
    StiffString, StrikeForce, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use crate::render::source::RenderSource;
use crate::ParamError;

/// Steps per call to `process`: one, so the energy is sampled every step (see `plate`).
const BLOCK: usize = 1;

/// Damping of a case.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Loss {
    None,
    Valette,
    /// `σ_j = ξ ω_j` for every mode.
    Ratio(f64),
}

/// Excitation of a case.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Excite {
    /// Raised-cosine force of this peak (N), 2 ms at 0.37 m; negative pushes towards `-u`.
    Strike(f64),
    /// Triangular pluck of this amplitude (m) at 0.3 m.
    Pluck(f64),
}

/// Obstacle kinds and placements (relative to the rest line `u = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Place {
    None,
    SitarTouching,
    SitarPenetrating,
    PointTouching,
    PointFar,
    PointPenetrating,
    FretboardTouching,
    FretboardFar,
    PointsMixed,
    ProfilePenetrating,
}

impl Place {
    fn name(self) -> &'static str {
        match self {
            Place::None => "no obstacle",
            Place::SitarTouching => "sitar touching",
            Place::SitarPenetrating => "sitar penetrating",
            Place::PointTouching => "point touching",
            Place::PointFar => "point far",
            Place::PointPenetrating => "point penetrating",
            Place::FretboardTouching => "fretboard touching",
            Place::FretboardFar => "fretboard far",
            Place::PointsMixed => "points touching/far/penetrating",
            Place::ProfilePenetrating => "profile penetrating",
        }
    }

    fn obstacle(self, p: &StringParams) -> Obstacle {
        // The curved bridge covers 2 cm, or one grid spacing on coarse grids.
        let extent = (0.02f64).max(1.01 * p.dx()).min(0.99 * p.length);
        let sitar = |height| {
            Obstacle::Sitar(SitarBridge {
                height,
                extent,
                ..SitarBridge::seed()
            })
        };
        let point = |height| Obstacle::Point {
            position: 6e-3,
            height,
            width: 0.0,
        };
        match self {
            Place::None => Obstacle::None,
            Place::SitarTouching => sitar(0.0),
            Place::SitarPenetrating => sitar(1e-4),
            Place::PointTouching => point(0.0),
            Place::PointFar => point(-1e-2),
            Place::PointPenetrating => point(1e-4),
            Place::FretboardTouching => Obstacle::Fretboard { distance: 0.0 },
            Place::FretboardFar => Obstacle::Fretboard { distance: 5e-3 },
            Place::PointsMixed => Obstacle::Points(vec![(0.25, 0.0), (0.5, -1e-3), (0.75, 1e-5)]),
            Place::ProfilePenetrating => Obstacle::Profile(
                (1..p.intervals)
                    .map(|i| (i % 3 != 0).then(|| 1e-4 * (i as f64 * 0.1).sin()))
                    .collect(),
            ),
        }
    }
}

/// The varied parameters of one string case.
#[derive(Debug, Clone, Copy)]
struct StringCase {
    place: Place,
    intervals: usize,
    fs: f64,
    stiffness: f64,
    alpha: f64,
    loss: Loss,
    excite: Excite,
    scheme: ContactScheme,
}

impl StringCase {
    fn label(&self) -> String {
        format!(
            "{} N={} fs={} K={:e} alpha={} {:?} {:?}",
            self.place.name(),
            self.intervals,
            self.fs,
            self.stiffness,
            self.alpha,
            self.loss,
            self.excite
        )
    }
}

fn run_case(c: StringCase, steps: usize) -> Result<RunResult, ParamError> {
    let params = StringParams::lecture_guitar(c.intervals, c.fs);
    params.validate()?;
    let losses = match c.loss {
        Loss::None => Losses::None,
        Loss::Valette => Losses::Valette(ValetteLosses::default()),
        Loss::Ratio(xi) => {
            Losses::PerMode((1..c.intervals).map(|j| xi * params.omega(j)).collect())
        }
    };
    let config = StringConfig {
        obstacle: c.place.obstacle(&params),
        params,
        losses,
        contact: ContactLaw {
            stiffness: c.stiffness,
            exponent: c.alpha,
        },
        outputs: vec![
            OutputChannel::Pickup {
                position: 0.37,
                quantity: Quantity::Velocity,
                readout: Readout::Grid,
            },
            OutputChannel::Pickup {
                position: 0.71,
                quantity: Quantity::Displacement,
                readout: Readout::Modal,
            },
            OutputChannel::ObstacleForce,
        ],
    };
    let mut s = StiffString::new(&config)?;
    s.set_contact_scheme(c.scheme);
    match c.excite {
        Excite::Strike(peak) => s.strike(&StrikeForce {
            position: 0.37,
            duration: 2e-3,
            peak,
        })?,
        Excite::Pluck(amplitude) => s.pluck(&TrianglePluck {
            position: 0.3,
            amplitude,
        })?,
    }
    let mut out = vec![vec![0.0; BLOCK]; s.channels()];
    let mut meter = BalanceMeter::default();
    meter.record(&s.energy());
    let mut done = 0usize;
    while done < steps {
        let n = BLOCK.min(steps - done);
        s.process(&mut out, n);
        done += n;
        let bad = out
            .iter()
            .find_map(|ch| check_finite_outputs("output", done as u64, &ch[..n]))
            .or_else(|| check_finite_outputs("q", done as u64, s.modal_displacement()));
        if let Some(f) = bad {
            return Ok(RunResult {
                energy_error: None,
                steps: done as u64,
                failure: Some(f),
                ..RunResult::default()
            });
        }
        meter.record(&s.energy());
    }
    let failure = if meter.non_finite() {
        Some("non-finite energy term".to_string())
    } else if s.contact_stats().cap_hits > 0 {
        Some(format!(
            "Newton cap hit {} times",
            s.contact_stats().cap_hits
        ))
    } else {
        None
    };
    Ok(RunResult {
        energy_error: Some(meter.relative_error()),
        steps: done as u64,
        failure,
        ..RunResult::default()
    })
}

/// All string cases.
pub fn cases(density: Density) -> Vec<Case> {
    let full = density == Density::Full;
    let (seconds, budget) = if full { (0.2, 2e9) } else { (0.02, 1e7) };
    let ks: &[f64] = if full {
        &[1e3, 1e6, 1e9, 1e13, 1e16]
    } else {
        &[1e3, 1e16]
    };
    let alphas: &[f64] = if full {
        &[1.0, 2.0, 3.0, 4.0]
    } else {
        &[1.0, 4.0]
    };
    let rates: &[f64] = if full {
        &[8e3, 22.05e3, 192e3, 2e6, 4e6]
    } else {
        &[8e3, 2e6, 4e6]
    };
    let grids: &[usize] = if full {
        &[2, 3, 50, 1000, 4000]
    } else {
        &[2, 1000]
    };
    let forces: &[f64] = if full {
        &[-1e-6, -1e-2, 1e2, -1e5]
    } else {
        &[-1e-6, -1e5]
    };
    let places = [
        Place::None,
        Place::SitarTouching,
        Place::SitarPenetrating,
        Place::PointTouching,
        Place::PointFar,
        Place::PointPenetrating,
        Place::FretboardTouching,
        Place::FretboardFar,
        Place::PointsMixed,
        Place::ProfilePenetrating,
    ];
    let mut out = Vec::new();
    for place in places {
        let base = StringCase {
            place,
            intervals: 100,
            fs: 48e3,
            stiffness: 1e13,
            alpha: 1.5,
            loss: Loss::Valette,
            excite: Excite::Strike(-1.0),
            scheme: ContactScheme::NewtonDiscreteGradient,
        };
        let mut list = vec![base];
        list.extend(ks.iter().map(|&stiffness| StringCase { stiffness, ..base }));
        list.extend(alphas.iter().map(|&alpha| StringCase { alpha, ..base }));
        list.extend(rates.iter().map(|&fs| StringCase { fs, ..base }));
        list.extend(
            grids
                .iter()
                .map(|&intervals| StringCase { intervals, ..base }),
        );
        list.extend(
            [Loss::None, Loss::Ratio(1.0), Loss::Ratio(10.0)]
                .iter()
                .map(|&loss| StringCase { loss, ..base }),
        );
        list.extend(forces.iter().map(|&f| StringCase {
            excite: Excite::Strike(f),
            ..base
        }));
        list.push(StringCase {
            excite: Excite::Pluck(-1e-3),
            loss: Loss::None,
            ..base
        });
        // Corners: the stiffest, most nonlinear contact hit hardest at the lowest rate,
        // lossless; the softest contact touched gently at the highest rate, over-damped.
        list.push(StringCase {
            stiffness: 1e16,
            alpha: 4.0,
            fs: 8e3,
            loss: Loss::None,
            excite: Excite::Strike(-1e5),
            ..base
        });
        list.push(StringCase {
            stiffness: 1e3,
            alpha: 1.0,
            fs: 4e6,
            loss: Loss::Ratio(10.0),
            excite: Excite::Strike(-1e-6),
            ..base
        });
        for scheme in ContactScheme::ALL {
            for &c in &list {
                let c = StringCase { scheme, ..c };
                let steps = ((seconds * c.fs).min(budget / c.intervals as f64).max(64.0)) as usize;
                out.push(Case::new(
                    format!("string {} {}", c.place.name(), scheme.name()),
                    c.label(),
                    false,
                    move || run_case(c, steps),
                ));
            }
        }
    }
    out
}
