//! [`Tanpura`]: the strings on their bridge, tuned by ear, plucked by the cycle.

use super::cycle::{Pattern, PluckCycle, PluckEvent};
use super::key_map::SaMap;
use super::spec::TanpuraSpec;
use super::tune::pluck_of;
use super::tuning_cache::{tune_cached, TunedStrings, TuningSource};
use crate::error::{check_closed, ParamError};
use crate::models::network::{BridgeInstrument, StringNetwork};
use crate::models::string::TrianglePluck;
use std::path::Path;

/// Why [`Tanpura::try_retune`] refused (plain data: no allocation on the stepping thread).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RetuneRefusal {
    /// The damping scale is not finite and ≥ 0.
    Damping,
    /// The pitch ratio is not finite and > 0.
    Ratio,
    /// The release floor is not finite and ≥ 0.
    Floor,
    /// A string's tension at that ratio would not be finite and > 0.
    Tension,
}

impl RetuneRefusal {
    /// The allowed values, for the error message.
    pub fn allowed(self) -> &'static str {
        match self {
            RetuneRefusal::Damping => "finite and >= 0",
            RetuneRefusal::Ratio => "finite and > 0",
            RetuneRefusal::Floor => "finite and >= 0 1/s",
            RetuneRefusal::Tension => "a ratio giving every string a finite, positive tension",
        }
    }
}

/// Largest pluck strength ([`Tanpura::set_strength`]): ten times the spec's amplitude.
pub const MAX_STRENGTH: f64 = 10.0;

/// A tanpura playing its drone: the network of its strings, the pluck cycle, and the stereo
/// pickup (each string's force on the bridge, panned across the image as the strings lie
/// across the bridge).
///
/// Built on the control thread ([`Tanpura::build`]: validates, tunes by ear, allocates);
/// [`Tanpura::step`] and `process` run on the stepping thread without allocating.
#[derive(Debug, Clone)]
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
    /// Sa of the tuning the drone was built with (Hz).
    sa: f64,
    /// Each string's note over Sa.
    ratios: Vec<f64>,
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
        Ok(Self::build_cached(spec, anchors, None)?.0)
    }

    /// [`Self::build_for_keys`], the tuning read from the cache in `dir` if an earlier build
    /// saved it there, else tuned and saved ([`super::tuning_cache`]); also says which.
    /// Worker thread (file I/O).
    pub fn build_cached(
        spec: &TanpuraSpec,
        anchors: &[f64],
        dir: Option<&Path>,
    ) -> Result<(Self, TuningSource), ParamError> {
        let (tuned, source) = tune_cached(spec, anchors, dir)?;
        Ok((Self::from_tuned(spec, tuned)?, source))
    }

    /// The drone of `spec` with its strings tuned as `tuned` says (validated). Control
    /// thread.
    pub fn from_tuned(spec: &TanpuraSpec, tuned: TunedStrings) -> Result<Self, ParamError> {
        spec.validate()?;
        let TunedStrings { scales, sa_map } = tuned;
        if scales.len() != spec.strings {
            return Err(ParamError::new(
                "tanpura.scales",
                scales.len(),
                format!("one per string ({})", spec.strings),
            ));
        }
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
            sa: spec.sa,
            ratios: spec.string_table().iter().map(|s| s.ratio).collect(),
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
        self.retune_damped(ratio, 1.0, floor)
    }

    /// [`Self::retune`] with every string's Valette losses multiplied by `damping` (finite,
    /// ≥ 0; 0 is lossless, 1 the strings as built). Control thread (the error allocates;
    /// the stepping thread calls [`Self::try_retune`]).
    pub fn retune_damped(
        &mut self,
        ratio: f64,
        damping: f64,
        floor: f64,
    ) -> Result<(), ParamError> {
        self.try_retune(ratio, damping, floor).map_err(|why| {
            let (field, value) = match why {
                RetuneRefusal::Damping => ("tanpura.damping", damping),
                RetuneRefusal::Floor => ("tanpura.release_floor", floor),
                _ => ("tanpura.ratio", ratio),
            };
            ParamError::new(field, value, why.allowed())
        })
    }

    /// [`Self::retune_damped`] on the stepping thread: no allocation, also when it refuses
    /// (nothing changes then). Every string's new tension is checked before any is applied.
    pub fn try_retune(
        &mut self,
        ratio: f64,
        damping: f64,
        floor: f64,
    ) -> Result<(), RetuneRefusal> {
        if !(damping.is_finite() && damping >= 0.0) {
            return Err(RetuneRefusal::Damping);
        }
        if !(ratio.is_finite() && ratio > 0.0) {
            return Err(RetuneRefusal::Ratio);
        }
        if !(floor.is_finite() && floor >= 0.0) {
            return Err(RetuneRefusal::Floor);
        }
        let semitones = 12.0 * ratio.log2();
        let tension = |i: usize, t: f64| t * ratio * ratio * self.sa_map.correction(i, semitones);
        if !self
            .tensions
            .iter()
            .enumerate()
            .all(|(i, &t)| tension(i, t).is_finite() && tension(i, t) > 0.0)
        {
            return Err(RetuneRefusal::Tension);
        }
        for i in 0..self.tensions.len() {
            let t = tension(i, self.tensions[i]);
            // The inputs are checked above: the string cannot refuse them.
            let ok = self.network.retune_string(i, t, damping, floor);
            debug_assert!(ok);
        }
        self.ratio = ratio;
        Ok(())
    }

    /// The pluck amplitude at strength 1 (m; the spec's).
    pub fn pluck_amplitude(&self) -> f64 {
        self.pluck.amplitude
    }

    /// Sa (Hz) of the tuning the drone was built with (ratio 1).
    pub fn sa(&self) -> f64 {
        self.sa
    }

    /// The pitch ratio from the tuning the drone was built with.
    pub fn ratio(&self) -> f64 {
        self.ratio
    }

    /// Scales every later pluck's amplitude by `strength` (0 to [`MAX_STRENGTH`], the
    /// player's velocity, times the mod wheel's factor in the engine). Refused (nothing
    /// changes) outside that range. Stepping thread.
    pub fn set_strength(&mut self, strength: f64) -> Result<(), ParamError> {
        if !(0.0..=MAX_STRENGTH).contains(&strength) {
            return Err(ParamError::new(
                "tanpura.strength",
                strength,
                format!("0 to {MAX_STRENGTH}"),
            ));
        }
        self.strength = strength;
        Ok(())
    }

    /// Changes the cycle's period (s, 0.5 to 30), pattern and variation (onset shift up to
    /// `timing_jitter_ms` ms, 0 to 50; strength up to `strength_jitter`, 0 to 0.5) while the
    /// drone plays: a drone that has not stepped yet takes them from its first pluck, a
    /// sounding one from its next cycle ([`PluckCycle::retime`]); a [`Self::reset`] starts with
    /// them. Refused (nothing changes) out of range. Stepping thread; O(1), no allocation.
    pub fn set_cycle(
        &mut self,
        period: f64,
        pattern: Pattern,
        timing_jitter_ms: f64,
        strength_jitter: f64,
    ) -> Result<(), ParamError> {
        check_closed("tanpura.cycle_seconds", period, 0.5, 30.0)?;
        check_closed("tanpura.timing_jitter_ms", timing_jitter_ms, 0.0, 50.0)?;
        check_closed("tanpura.strength_jitter", strength_jitter, 0.0, 0.5)?;
        let h = self.network.h();
        let jitter = timing_jitter_ms * 1e-3;
        self.first_cycle
            .retime(period, h, pattern, jitter, strength_jitter);
        if self.step == 0 {
            self.cycle = self.first_cycle.clone();
            self.next = self.cycle.next_pluck();
        } else {
            self.cycle
                .retime(period, h, pattern, jitter, strength_jitter);
        }
        Ok(())
    }

    /// The cycle's period in s (the one coming, after a [`Self::set_cycle`]).
    pub fn cycle_seconds(&self) -> f64 {
        self.cycle.period_seconds(self.network.h())
    }

    /// Where the cycle is: the time since the present cycle's start over its period (0 to 1).
    pub fn cycle_phase(&self) -> f64 {
        self.cycle.phase_at(self.step)
    }

    /// String `i`'s pluck in the cycle, as a fraction of the period.
    pub fn onset(&self, i: usize) -> f64 {
        self.cycle.onset(i)
    }

    /// String `i`'s displacement at the grid's interior nodes (m, from the bridge's end;
    /// [`crate::models::string::StiffString::grid_displacement`]: one inverse transform).
    /// For views; the motion is not changed. Stepping thread, no allocation.
    pub fn string_grid_displacement(&mut self, i: usize) -> &[f64] {
        self.network.string_mut(i).grid_displacement()
    }

    /// Each string's note over Sa, in plucking order.
    pub fn ratios(&self) -> &[f64] {
        &self.ratios
    }

    /// Whether the cycle plucks ([`Self::set_plucking`]).
    pub fn plucking(&self) -> bool {
        self.plucking
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
