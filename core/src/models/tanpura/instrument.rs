//! [`Tanpura`]: the strings on their bridge, tuned by ear, plucked by the cycle.

use super::cycle::{PluckCycle, PluckEvent};
use super::key_map::SaMap;
use super::spec::TanpuraSpec;
use super::tune::{pluck_of, tension_scales};
use crate::error::ParamError;
use crate::models::network::{BridgeInstrument, StringNetwork};
use crate::models::string::params::Stiffness;
use crate::models::string::{TrianglePluck, ValetteLosses};

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
    /// The sequencer as built, to start the drone again ([`Tanpura::reset`]).
    first_cycle: PluckCycle,
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
    /// Per string, the tension corrections of the keys tuned by ear ([`SaMap`]).
    sa_map: SaMap,
    /// The pitch ratio the strings are at (1: the tuning the drone was built with).
    ratio: f64,
    /// Strength of every pluck (1: the spec's amplitude).
    strength: f64,
    /// Whether the cycle plucks (off: the strings ring on and decay).
    plucking: bool,
}

impl Tanpura {
    /// Validates `spec`, tunes every string by ear ([`super::tune`]) and builds the drone,
    /// its first pluck at step 0. Control thread.
    pub fn build(spec: &TanpuraSpec) -> Result<Self, ParamError> {
        Self::build_for_keys(spec, &[])
    }

    /// [`Self::build`], and tuned by ear at Sa moved by each of `anchors` too (semitones;
    /// [`SaMap::tune`]) so that [`Self::retune`] keeps the pitch at other keys (none: the
    /// tensions follow `ratio²` alone). Worker thread; each anchor costs one tuning.
    pub fn build_for_keys(spec: &TanpuraSpec, anchors: &[f64]) -> Result<Self, ParamError> {
        spec.validate()?;
        let scales = tension_scales(spec)?;
        let sa_map = if spec.tune_by_ear && !anchors.is_empty() {
            SaMap::tune(spec, &scales, anchors)?
        } else {
            SaMap::none(spec.strings)
        };
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
        let first_cycle = cycle.clone();
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
            first_cycle,
            next,
            step: 0,
            pluck: pluck_of(spec),
            pan,
            tensions,
            sa_map,
            ratio: 1.0,
            strength: 1.0,
            plucking: true,
        })
    }

    /// Puts every string and the bridge at rest and starts the cycle again from its first
    /// pluck, at the next step (the variation repeats too). Keeps the pitch, the strength and
    /// the plucking switch. Stepping thread; no allocation.
    pub fn reset(&mut self) {
        self.network.reset();
        self.cycle = self.first_cycle.clone();
        self.next = self.cycle.next_pluck();
        self.step = 0;
    }

    /// Moves every string's pitch by `ratio` from the tuning the drone was built with (Sa
    /// becomes `ratio · sa`), by its tension (`T = ratio² c T_tuned`, the bending stiffness
    /// kept, `c` the string's correction at that key from the keys tuned by ear, [`SaMap`]),
    /// and sets the floor `floor` (1/s, ≥ 0) under every mode's decay rate (a release).
    /// Refused (nothing changes) for a ratio that is not finite and positive or a floor that
    /// is not finite and ≥ 0. Stepping thread; no allocation, O(strings · modes).
    pub fn retune(&mut self, ratio: f64, floor: f64) -> Result<(), ParamError> {
        if !(ratio.is_finite() && ratio > 0.0) {
            return Err(ParamError::new("tanpura.ratio", ratio, "finite and > 0"));
        }
        if !(floor.is_finite() && floor >= 0.0) {
            return Err(ParamError::new(
                "tanpura.release_floor",
                floor,
                "finite and >= 0 1/s",
            ));
        }
        let losses = ValetteLosses::default();
        let semitones = 12.0 * ratio.log2();
        for (i, &t) in self.tensions.iter().enumerate() {
            let c = self.sa_map.correction(i, semitones);
            // Kept through the retune (the strings are built, and retuned, with it).
            let ei = self.network.strings()[i].params().bending_stiffness();
            self.network
                .string_mut(i)
                .retune(
                    t * ratio * ratio * c,
                    Stiffness::BendingStiffness(ei),
                    Some(&losses),
                    1.0,
                    floor,
                )
                .map_err(|why| ParamError::new("tanpura.ratio", ratio, why))?;
        }
        self.ratio = ratio;
        Ok(())
    }

    /// The pitch ratio from the tuning the drone was built with.
    pub fn ratio(&self) -> f64 {
        self.ratio
    }

    /// Scales every later pluck's amplitude by `strength` (0 to 1, the player's velocity).
    /// Refused (nothing changes) outside that range. Stepping thread.
    pub fn set_strength(&mut self, strength: f64) -> Result<(), ParamError> {
        if !(0.0..=1.0).contains(&strength) {
            return Err(ParamError::new("tanpura.strength", strength, "0 to 1"));
        }
        self.strength = strength;
        Ok(())
    }

    /// Turns the cycle's plucking on or off (off: the strings ring on and decay; on again: the
    /// cycle resumes at its next pluck due). Stepping thread.
    pub fn set_plucking(&mut self, on: bool) {
        self.plucking = on;
    }

    /// Plucks what the cycle asks for at this step, then advances the network one step.
    /// No allocation; bounded (at most one pluck per string per step).
    pub fn step(&mut self) {
        let mut plucked = 0;
        while self.next.step <= self.step && plucked < self.pan.len() {
            if self.plucking && self.strength > 0.0 {
                let p = TrianglePluck {
                    amplitude: self.pluck.amplitude * self.next.strength * self.strength,
                    ..self.pluck
                };
                // Validated at build; the strength keeps the amplitude within range.
                let ok = self.network.pluck(self.next.string, &p).is_ok();
                debug_assert!(ok);
            }
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
