//! The shared model harness: one catalogue of model × scheme cases ([`catalogue`]) and one run
//! ([`check`]) that every case goes through, in place of the energy loops once copied across the
//! test files.
//!
//! A case builds a [`RenderSource`] through the public API (plates from a scene's
//! [`PlateSpec`] through [`PlateVoice::build`], strings from a [`StringConfig`], one-oscillator
//! schemes through [`build_oscillator`] behind [`OscillatorSource`]) and states what its run must
//! show. [`run`] steps it one step per `process` call and checks, at every step:
//!
//! - **finiteness**: every output and every energy term (`kinetic`, `linear`, `nonlinear`,
//!   `dissipated`, `work`) is finite;
//! - **no allocation**: `process` and `energy` allocate nothing (counted per thread by
//!   [`crate::alloc::Guard`], which must be the test binary's global allocator; checked first,
//!   so the check cannot pass vacuously);
//!
//! and [`check`] then asserts on the whole run:
//!
//! - **power balance**: `balance() = total + dissipated - work` stays within the case's stated
//!   tolerance of its first value, relative to the peak energy of the run
//!   ([`Expect::Conserves`]); for a scheme that does not conserve its energy (Störmer-Verlet)
//!   the deviation must instead lie in a stated band, clearly above round-off and bounded
//!   ([`Expect::Drifts`]): a negative control showing the measure sees a non-conservative update;
//! - **exercise**: the run did what the case is about (the nonlinear energy reached its share of
//!   the total, the losses dissipated and the force worked their share, the contact was touched
//!   without a Newton failure), so a case cannot pass by doing nothing.
//!
//! Tolerances are a few times the round-off measured on each case (stated with the measured
//! values and the reason in the source of [`catalogue`], per family); [`check_family`] prints
//! every outcome (`--nocapture`), so a change in round-off shows.

use crate::env::test_cache_dir;
use noether_core::models::plate::spec::{
    Damping, Excitation, PlateScheme, PlateShape, PlateSpec, Position, ShapePart, Symmetry,
    TensorStorage,
};
use noether_core::models::plate::voice::PlateVoice;
use noether_core::models::source::{ContactSummary, EnergyTerms, ModelDetails, RenderSource};
use noether_core::models::string::{
    ContactLaw, ContactScheme, Losses, Obstacle, OutputChannel, Quantity, Readout, StiffString,
    StrikeForce, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use noether_core::schemes::{build_oscillator, OscillatorSpec, OscillatorStepper};
use std::fmt;

/// What the balance of a case must do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Expect {
    /// An energy-conserving scheme: `max |balance_n - balance_0| / peak energy < tol`.
    Conserves {
        /// The tolerance (a few times the measured round-off; see [`catalogue`]).
        tol: f64,
    },
    /// A scheme that does not conserve its energy: the same deviation must lie in
    /// `[min, max]` (above round-off, so the measure sees it; bounded, so the run is stable).
    Drifts {
        /// Lower bound of the deviation.
        min: f64,
        /// Upper bound of the deviation.
        max: f64,
    },
}

/// What the run must have exercised, as shares of the peak energy.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Exercise {
    /// Largest `nonlinear / total` seen must reach this.
    pub nonlinear_share: f64,
    /// Final `dissipated / peak` must reach this.
    pub dissipated_share: f64,
    /// Final `|work| / peak` must reach this.
    pub work_share: f64,
    /// The model must report contact steps and no Newton failure.
    pub contact: bool,
}

/// The model families of the catalogue (a test per family runs in parallel with the others).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Circular free-edge plates (gongs).
    CircularFree,
    /// Circular clamped-edge plates.
    CircularClamped,
    /// Simply supported rectangles.
    Rectangle,
    /// Stiff strings against an obstacle.
    String,
    /// One-oscillator schemes.
    Oscillator,
}

type Builder = Box<dyn Fn() -> Box<dyn RenderSource> + Send + Sync>;

/// One model × scheme case.
pub struct Case {
    /// Identifier, `family/model/scheme/situation`.
    pub name: String,
    /// Its family.
    pub family: Family,
    /// Steps to run.
    pub steps: usize,
    /// What the balance must do.
    pub expect: Expect,
    /// What the run must exercise.
    pub exercise: Exercise,
    build: Builder,
}

impl Case {
    /// A case from its parts; `build` makes a fresh model at its initial state.
    pub fn new(
        name: impl Into<String>,
        family: Family,
        steps: usize,
        expect: Expect,
        exercise: Exercise,
        build: impl Fn() -> Box<dyn RenderSource> + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: name.into(),
            family,
            steps,
            expect,
            exercise,
            build: Box::new(build),
        }
    }

    /// A fresh model of the case.
    pub fn build(&self) -> Box<dyn RenderSource> {
        (self.build)()
    }
}

impl fmt::Debug for Case {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Case")
            .field("name", &self.name)
            .field("steps", &self.steps)
            .field("expect", &self.expect)
            .field("exercise", &self.exercise)
            .finish()
    }
}

/// What a run measured.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// The case's name.
    pub name: String,
    /// Steps run.
    pub steps: usize,
    /// `max_n |balance_n - balance_0|` over the peak energy.
    pub balance_error: f64,
    /// Largest total energy seen (J, or the scheme's unit).
    pub peak_energy: f64,
    /// Largest `nonlinear / total` seen.
    pub nonlinear_share: f64,
    /// Final `dissipated` over the peak energy.
    pub dissipated_share: f64,
    /// Final `work` over the peak energy.
    pub work_share: f64,
    /// Contact counters, for models with a contact.
    pub contact: Option<ContactSummary>,
    /// The model's own figures (scheme names and the like).
    pub details: ModelDetails,
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{:<52} {:>6} steps: balance error {:.2e}, nonlinear ≤ {:.3}, dissipated {:.3}, work {:.3}",
            self.name,
            self.steps,
            self.balance_error,
            self.nonlinear_share,
            self.dissipated_share,
            self.work_share
        )?;
        if let Some(c) = &self.contact {
            write!(
                f,
                ", contact steps {}, Newton failures {}",
                c.contact_steps, c.newton_failures
            )?;
        }
        Ok(())
    }
}

fn finite_terms(e: &EnergyTerms) -> bool {
    [e.kinetic, e.linear, e.nonlinear, e.dissipated, e.work]
        .iter()
        .all(|x| x.is_finite())
}

/// Runs `case` (one step per `process` call) and returns what it measured. Panics, naming the
/// case and the step, on a non-finite output or energy term, and on any allocation in
/// `process` or `energy`.
pub fn run(case: &Case) -> Outcome {
    assert!(
        crate::alloc::installed(),
        "noether_testkit::alloc::Guard is not this binary's global allocator: the harness could \
         not see an allocation"
    );
    let mut s = case.build();
    let mut out = vec![vec![0.0f64; 1]; s.channels()];
    let first = s.energy();
    assert!(
        finite_terms(&first),
        "{}: initial energy {first:?}",
        case.name
    );
    let b0 = first.balance();
    let mut peak = first.total();
    let mut dev = 0.0f64;
    let mut share = if first.total() > 0.0 {
        first.nonlinear / first.total()
    } else {
        0.0
    };
    let mut last = first;
    for n in 0..case.steps {
        let ((), allocated) = crate::alloc::count_allocations(|| {
            s.process(&mut out, 1);
            last = s.energy();
        });
        assert_eq!(allocated, 0, "{}: step {n} allocated", case.name);
        for (c, ch) in out.iter().enumerate() {
            assert!(
                ch[0].is_finite(),
                "{}: output {c} = {} at step {n}",
                case.name,
                ch[0]
            );
        }
        let e = last;
        assert!(finite_terms(&e), "{}: energy {e:?} at step {n}", case.name);
        let total = e.total();
        peak = peak.max(total);
        dev = dev.max((e.balance() - b0).abs());
        if total > 0.0 {
            share = share.max(e.nonlinear / total);
        }
    }
    Outcome {
        name: case.name.clone(),
        steps: case.steps,
        balance_error: dev / peak,
        peak_energy: peak,
        nonlinear_share: share,
        dissipated_share: last.dissipated / peak,
        work_share: last.work / peak,
        contact: s.contact(),
        details: s.details(),
    }
}

/// Runs `case` and asserts its balance and exercise (module doc); returns the outcome.
pub fn check(case: &Case) -> Outcome {
    let o = run(case);
    let name = &case.name;
    assert!(o.peak_energy > 0.0, "{name}: the model never held energy");
    match case.expect {
        Expect::Conserves { tol } => assert!(
            o.balance_error < tol,
            "{name}: balance error {:.3e} >= {tol:.1e}",
            o.balance_error
        ),
        Expect::Drifts { min, max } => assert!(
            (min..=max).contains(&o.balance_error),
            "{name}: energy deviation {:.3e} outside [{min:.1e}, {max:.1e}]",
            o.balance_error
        ),
    }
    let x = &case.exercise;
    assert!(
        o.nonlinear_share >= x.nonlinear_share,
        "{name}: nonlinear share {:.3} < {}",
        o.nonlinear_share,
        x.nonlinear_share
    );
    // A SAV relaxation gives back what it removed to the round-off of its auxiliary energy
    // (`models::sav_relaxation`), so a lossless run may end a few ulps below 0.
    assert!(
        o.dissipated_share >= x.dissipated_share - 1e-12,
        "{name}: dissipated share {:.3e} < {}",
        o.dissipated_share,
        x.dissipated_share
    );
    assert!(
        o.work_share.abs() >= x.work_share,
        "{name}: work share {:.3e} < {}",
        o.work_share,
        x.work_share
    );
    if x.contact {
        let c = o
            .contact
            .as_ref()
            .unwrap_or_else(|| panic!("{name}: no contact counters"));
        assert!(c.contact_steps > 0, "{name}: never touched the obstacle");
        assert_eq!(c.newton_failures, 0, "{name}: Newton hit its cap");
    }
    // The quadratised contact has no iteration: it must never have run Newton.
    if let (ModelDetails::String(d), Some(c)) = (&o.details, &o.contact) {
        if d.contact_scheme == ContactScheme::Quadratised.name() {
            assert_eq!(
                c.newton_histogram.iter().skip(1).sum::<u64>(),
                0,
                "{name}: the quadratised scheme ran Newton"
            );
        }
    }
    o
}

// ---------------------------------------------------------------- one-oscillator adapter

/// A one-oscillator scheme as a [`RenderSource`]: one output (the displacement); the energy is
/// the scheme's discrete energy (reported as `linear`: the trait's split into kinetic and
/// potential parts is not available for every scheme) with its dissipated energy; contact
/// counters for the impact scheme.
pub struct OscillatorSource {
    stepper: Box<dyn OscillatorStepper>,
}

impl OscillatorSource {
    /// `spec` at time step `h`, started from `u(0) = u0`, `u̇(0) = v0`.
    pub fn new(spec: &OscillatorSpec, h: f64, u0: f64, v0: f64) -> Self {
        let mut stepper = build_oscillator(spec, h).expect("valid oscillator");
        stepper.reset(u0, v0);
        Self { stepper }
    }
}

impl RenderSource for OscillatorSource {
    fn sim_rate(&self) -> f64 {
        1.0 / self.stepper.step_size()
    }
    fn channels(&self) -> usize {
        1
    }
    fn process(&mut self, out: &mut [Vec<f64>], frames: usize) {
        for y in out[0].iter_mut().take(frames) {
            self.stepper.step();
            *y = self.stepper.displacement();
        }
    }
    fn energy(&self) -> EnergyTerms {
        EnergyTerms {
            linear: self.stepper.discrete_energy(),
            dissipated: self.stepper.dissipated_energy(),
            ..EnergyTerms::default()
        }
    }
    fn is_conservative(&self) -> bool {
        true
    }
    fn contact(&self) -> Option<ContactSummary> {
        let st = self.stepper.stats();
        (self.stepper.name() == "impact").then(|| ContactSummary {
            contact_steps: st.contact_steps,
            newton_failures: st.solver_failures,
            newton_max_iterations: st.max_iterations_per_step as usize,
            ..ContactSummary::default()
        })
    }
}

mod catalogue;
pub use catalogue::*;
