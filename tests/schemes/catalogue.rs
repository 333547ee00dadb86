//! The model × scheme catalogue through the shared harness (`noether_testkit::harness`): every
//! case runs its steps checking finiteness of every output and energy term and the absence of
//! allocation in the step, then its power balance against the case's stated tolerance and what
//! the run must exercise (module doc of the harness). One test per family, so the families run
//! in parallel; each prints its cases' figures (`--nocapture`). The negative controls at the end
//! show each check fails when it should.

use noether::models::plate::spec::{Damping, Excitation, PlateShape, Position};
use noether::models::plate::voice::PlateVoice;
use noether::models::plate::LinearSolve;
use noether::models::source::{EnergyTerms, RenderSource};
use noether_testkit::harness::{
    self, catalogue, check, check_family, plate_spec, Case, Exercise, Expect, Family, PLATE_SCHEMES,
};

#[test]
fn circular_free_plates() {
    assert_eq!(check_family(Family::CircularFree).len(), 12);
}

#[test]
fn circular_clamped_plates() {
    assert_eq!(check_family(Family::CircularClamped).len(), 12);
}

#[test]
fn rectangular_plates() {
    assert_eq!(check_family(Family::Rectangle).len(), 12);
}

#[test]
fn strings() {
    assert_eq!(check_family(Family::String).len(), 14);
}

#[test]
fn oscillators() {
    assert_eq!(check_family(Family::Oscillator).len(), 6);
}

/// The catalogue's names are unique, and its plates cover both linear-solve routes of the
/// conservative schemes (Woodbury when `N_Ψ < N_Φ`, direct otherwise) and every scheme, flat
/// and curved (three shapes × three cases per scheme).
#[test]
fn catalogue_covers_routes_and_schemes() {
    let cases = catalogue();
    let mut names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
    names.sort_unstable();
    let n = names.len();
    names.dedup();
    assert_eq!(names.len(), n, "duplicate case names");
    for scheme in PLATE_SCHEMES {
        let name = format!("/{}/", scheme.name());
        assert_eq!(
            cases.iter().filter(|c| c.name.contains(&name)).count(),
            9,
            "{name}"
        );
    }
    let impulse = |shape| Excitation::Impulse {
        at: if shape == PlateShape::RectSs {
            Position {
                x: Some(0.37),
                y: Some(0.41),
                ..Position::default()
            }
        } else {
            Position {
                r: Some(0.5),
                angle: Some(0.3),
                ..Position::default()
            }
        },
        impulse: 4.0,
    };
    let route = |shape| {
        noether_testkit::env::test_cache_dir();
        let spec = plate_spec(shape, PLATE_SCHEMES[0], Damping::None, impulse(shape));
        PlateVoice::build(&spec).unwrap().model().solve_route()
    };
    assert_eq!(route(PlateShape::CircularFree), Some(LinearSolve::Woodbury));
    assert_eq!(
        route(PlateShape::CircularClamped),
        Some(LinearSolve::Direct)
    );
}

// ---------------------------------------------------------------- negative controls

/// A source that allocates in its step, writes `output` and reports `energy(n)`.
struct Fake {
    n: usize,
    allocate: bool,
    output: f64,
    energy: fn(usize) -> f64,
    sink: Vec<Vec<u8>>,
}

impl RenderSource for Fake {
    fn sim_rate(&self) -> f64 {
        1.0
    }
    fn channels(&self) -> usize {
        1
    }
    fn process(&mut self, out: &mut [Vec<f64>], frames: usize) {
        for o in out[0].iter_mut().take(frames) {
            self.n += 1;
            if self.allocate {
                self.sink.push(vec![0; 8]);
            }
            *o = self.output;
        }
    }
    fn energy(&self) -> EnergyTerms {
        EnergyTerms {
            linear: (self.energy)(self.n),
            ..EnergyTerms::default()
        }
    }
    fn is_conservative(&self) -> bool {
        true
    }
}

fn fake(allocate: bool, output: f64, energy: fn(usize) -> f64) -> Case {
    Case::new(
        "fake",
        Family::Oscillator,
        10,
        Expect::Conserves { tol: 1e-12 },
        Exercise::default(),
        move || {
            Box::new(Fake {
                n: 0,
                allocate,
                output,
                energy,
                sink: Vec::new(),
            })
        },
    )
}

#[test]
fn a_conserving_fake_passes() {
    let o = check(&fake(false, 0.5, |_| 1.0));
    assert_eq!(o.balance_error, 0.0);
}

#[test]
#[should_panic(expected = "allocated")]
fn an_allocating_step_fails() {
    check(&fake(true, 0.5, |_| 1.0));
}

#[test]
#[should_panic(expected = "output 0 = NaN")]
fn a_non_finite_output_fails() {
    check(&fake(false, f64::NAN, |_| 1.0));
}

#[test]
#[should_panic(expected = "energy")]
fn a_non_finite_energy_fails() {
    check(&fake(
        false,
        0.0,
        |n| if n == 5 { f64::INFINITY } else { 1.0 },
    ));
}

/// A drift of 1e-11 of the energy over the run breaks a 1e-12 tolerance.
#[test]
#[should_panic(expected = "balance error")]
fn an_energy_drift_fails() {
    check(&fake(false, 0.0, |n| 1.0 + 1e-12 * n as f64));
}

/// `Expect::Drifts` fails a run that conserves (the negative control of the Störmer-Verlet
/// cases must see their drift).
#[test]
#[should_panic(expected = "outside")]
fn a_drift_band_fails_a_conserving_run() {
    let mut c = fake(false, 0.0, |_| 1.0);
    c.expect = Expect::Drifts {
        min: 1e-9,
        max: 1.0,
    };
    harness::check(&c);
}

/// An exercise requirement the run does not meet fails.
#[test]
#[should_panic(expected = "dissipated share")]
fn an_unexercised_case_fails() {
    let mut c = fake(false, 0.0, |_| 1.0);
    c.exercise.dissipated_share = 0.1;
    check(&c);
}
