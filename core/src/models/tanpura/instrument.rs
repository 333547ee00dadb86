//! [`Tanpura`]: the strings on their bridge, tuned by ear, plucked by the cycle.

use super::cycle::{PluckCycle, PluckEvent};
use super::spec::TanpuraSpec;
use super::tune::{pluck_of, tension_scales};
use crate::error::ParamError;
use crate::models::network::{BridgeInstrument, StringNetwork};
use crate::models::string::TrianglePluck;

/// A tanpura playing its drone: the network of its strings, the pluck cycle, and the stereo
/// pickup (each string's force on the bridge, panned across the image as the strings lie
/// across the bridge).
///
/// Built on the control thread ([`Tanpura::build`]: validates, tunes by ear, allocates);
/// [`Tanpura::step`] and `process` run on the stepping thread without allocating.
#[derive(Debug)]
pub struct Tanpura {
    /// The strings on the bridge.
    network: StringNetwork,
    /// The sequencer.
    cycle: PluckCycle,
    /// The next pluck.
    next: PluckEvent,
    /// Steps taken.
    step: u64,
    /// The pluck at full strength.
    pluck: TrianglePluck,
    /// Per string, `[left, right]` gains (constant-power pan).
    pan: Vec<[f64; 2]>,
    /// Per string, the tension after tuning (N).
    tensions: Vec<f64>,
}

impl Tanpura {
    /// Validates `spec`, tunes every string by ear ([`super::tune`]) and builds the drone,
    /// its first pluck at step 0. Control thread.
    pub fn build(spec: &TanpuraSpec) -> Result<Self, ParamError> {
        spec.validate()?;
        let scales = tension_scales(spec)?;
        let network = StringNetwork::new(&spec.network(&scales)?)?;
        let n = spec.strings;
        let h = network.h();
        let mut cycle = PluckCycle::new(
            spec.cycle_seconds,
            h,
            spec.pattern,
            n,
            spec.timing_jitter_ms * 1e-3,
            spec.strength_jitter,
            spec.seed,
        );
        let next = cycle.next_pluck();
        let pan = (0..n)
            .map(|i| pan_gains(0.6 * (2.0 * i as f64 / (n - 1) as f64 - 1.0)))
            .collect();
        let tensions = (0..n)
            .map(|i| spec.nominal_tension(i) * scales[i])
            .collect();
        Ok(Self {
            network,
            cycle,
            next,
            step: 0,
            pluck: pluck_of(spec),
            pan,
            tensions,
        })
    }

    /// Plucks what the cycle asks for at this step, then advances the network one step.
    /// No allocation; bounded (at most one pluck per string per step).
    pub fn step(&mut self) {
        let mut plucked = 0;
        while self.next.step <= self.step && plucked < self.pan.len() {
            let p = TrianglePluck {
                amplitude: self.pluck.amplitude * self.next.strength,
                ..self.pluck
            };
            // Validated at build; the strength keeps the amplitude within range.
            let ok = self.network.pluck(self.next.string, &p).is_ok();
            debug_assert!(ok);
            self.next = self.cycle.next_pluck();
            plucked += 1;
        }
        self.network.step();
        self.step += 1;
    }

    /// The network.
    pub fn network(&self) -> &StringNetwork {
        &self.network
    }

    /// Each string's tension after tuning by ear (N).
    pub fn tensions(&self) -> &[f64] {
        &self.tensions
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.step
    }
}

impl BridgeInstrument for Tanpura {
    fn network(&self) -> &StringNetwork {
        &self.network
    }

    fn advance(&mut self) {
        self.step();
    }

    fn gains(&self) -> &[[f64; 2]] {
        &self.pan
    }
}

/// Constant-power `[left, right]` gains at `position` (-1 left to 1 right).
pub fn pan_gains(position: f64) -> [f64; 2] {
    let a = (position + 1.0) * std::f64::consts::FRAC_PI_4;
    [a.cos(), a.sin()]
}
