//! [`StringNetwork`]: strings seated on one moving bridge, stepped together (the scheme and
//! its energy are in the module doc of [`crate::models::network`]).

use super::bridge::{BridgeBody, MAX_BRIDGE_MODES};
use super::config::{NetworkConfig, NetworkOutput};
use super::solve::{BridgeSolve, NetworkStats};
use crate::error::ParamError;
use crate::models::source::EnergyTerms;
use crate::models::string::model::FreeStep;
use crate::models::string::params::Stiffness;
use crate::models::string::{Quantity, StiffString, StrikeForce, TrianglePluck, ValetteLosses};

/// A resolved output channel.
#[derive(Debug, Clone)]
enum ResolvedOutput {
    /// A string's own channel.
    String { string: usize, channel: usize },
    /// The bridge at a point (weights per mode).
    Bridge {
        velocity: bool,
        weights: [f64; MAX_BRIDGE_MODES],
    },
}

/// Strings seated on a bridge with its own modes, coupled both ways through it: every
/// string's seat and jawari forces act on the bridge, and the bridge moves every string's
/// seat and jawari. Conservative: the network's discrete energy (strings, contacts, seats,
/// bridge) is conserved to round-off without losses; with them the power balance closes.
///
/// Lifecycle: [`StringNetwork::new`] (control thread: validates, allocates), then
/// [`StringNetwork::reset`], [`StringNetwork::pluck`], [`StringNetwork::strike`] and
/// [`StringNetwork::step`], which never allocate and do bounded work (the bridge's Newton
/// iterations are capped, each string's contact solve is capped per node), so they may run
/// on the audio thread. Owned by one thread at a time.
#[derive(Debug, Clone)]
pub struct StringNetwork {
    /// The strings, in the order of the config.
    strings: Vec<StiffString>,
    /// The bridge's modes.
    bridge: BridgeBody,
    /// The bridge's coupled solve and its scratch.
    solve: BridgeSolve,
    /// Per string, what its free step handed over (scratch, one per string).
    starts: Vec<FreeStep>,
    /// Output channels.
    outputs: Vec<ResolvedOutput>,
    /// Time step in s.
    h: f64,
}

impl StringNetwork {
    /// Validates `config` (the error names the string, the mode or the output) and builds
    /// every string seated on the bridge. Control thread.
    pub fn new(config: &NetworkConfig) -> Result<Self, ParamError> {
        if config.strings.is_empty() {
            return Err(ParamError::new("network.strings", 0, "at least one string"));
        }
        let rate = config.strings[0].config.params.sample_rate;
        let h = 1.0 / rate;
        let bridge = BridgeBody::new(&config.bridge, h)?;
        let b = bridge.modes();
        let mut strings = Vec::with_capacity(config.strings.len());
        let mut shape = Vec::with_capacity(config.strings.len() * b);
        for (i, s) in config.strings.iter().enumerate() {
            let r = s.config.params.sample_rate;
            if r != rate {
                return Err(ParamError::new(
                    format!("network.strings[{i}].sample_rate"),
                    r,
                    format!("{rate} Hz, the rate of the first string"),
                ));
            }
            if s.bridge_shape.len() != b || s.bridge_shape.iter().any(|x| !x.is_finite()) {
                return Err(ParamError::new(
                    format!("network.strings[{i}].bridge_shape"),
                    format!("{:?}", s.bridge_shape),
                    format!("{b} finite values, one per bridge mode"),
                ));
            }
            let mut string = StiffString::new_seated(&s.config, &s.seat)
                .map_err(|e| e.within(&format!("network.strings[{i}]")))?;
            if s.band_limit != f64::INFINITY {
                string
                    .set_band_limit(s.band_limit)
                    .map_err(|e| e.within(&format!("network.strings[{i}]")))?;
            }
            strings.push(string);
            shape.extend_from_slice(&s.bridge_shape);
        }
        let outputs = config
            .outputs
            .iter()
            .enumerate()
            .map(|(c, o)| Self::resolve(o, c, &strings, b))
            .collect::<Result<Vec<_>, _>>()?;
        let n = strings.len();
        Ok(Self {
            solve: BridgeSolve::new(shape, n, b),
            starts: vec![FreeStep::default(); n],
            strings,
            bridge,
            outputs,
            h,
        })
    }

    /// One output channel checked against the strings and the bridge.
    fn resolve(
        o: &NetworkOutput,
        c: usize,
        strings: &[StiffString],
        b: usize,
    ) -> Result<ResolvedOutput, ParamError> {
        match o {
            NetworkOutput::String { string, channel } => {
                let Some(s) = strings.get(*string) else {
                    return Err(ParamError::new(
                        format!("network.outputs[{c}].string"),
                        string,
                        format!("a string index below {}", strings.len()),
                    ));
                };
                if *channel >= s.output_count() {
                    return Err(ParamError::new(
                        format!("network.outputs[{c}].channel"),
                        channel,
                        format!("a channel of string {string}, below {}", s.output_count()),
                    ));
                }
                Ok(ResolvedOutput::String {
                    string: *string,
                    channel: *channel,
                })
            }
            NetworkOutput::Bridge { quantity, weights } => {
                if weights.len() != b || weights.iter().any(|w| !w.is_finite()) {
                    return Err(ParamError::new(
                        format!("network.outputs[{c}].weights"),
                        format!("{weights:?}"),
                        format!("{b} finite values, one per bridge mode"),
                    ));
                }
                let mut w = [0.0; MAX_BRIDGE_MODES];
                w[..b].copy_from_slice(weights);
                Ok(ResolvedOutput::Bridge {
                    velocity: *quantity == Quantity::Velocity,
                    weights: w,
                })
            }
        }
    }

    /// Every string and the bridge at rest, the accounts and counters cleared. No allocation.
    pub fn reset(&mut self) {
        for s in &mut self.strings {
            s.reset();
        }
        self.bridge.reset();
        self.solve.stats = NetworkStats::default();
    }

    /// Plucks string `string` on top of its motion ([`StiffString::add_pluck`]: the energy it
    /// brings is counted as work). O(N), no allocation.
    pub fn pluck(&mut self, string: usize, pluck: &TrianglePluck) -> Result<(), ParamError> {
        self.string_index(string)?;
        self.strings[string].add_pluck(pluck)
    }

    /// Starts a force pulse on string `string` ([`StiffString::strike`]). No allocation.
    pub fn strike(&mut self, string: usize, force: &StrikeForce) -> Result<(), ParamError> {
        self.string_index(string)?;
        self.strings[string].strike(force)
    }

    /// Checks a string index.
    fn string_index(&self, string: usize) -> Result<(), ParamError> {
        if string < self.strings.len() {
            Ok(())
        } else {
            Err(ParamError::new(
                "network.string",
                string,
                format!("a string index below {}", self.strings.len()),
            ))
        }
    }

    /// Advances the whole network one step (module doc of [`crate::models::network`]).
    /// Bounded work, no allocation.
    pub fn step(&mut self) {
        for (s, start) in self.strings.iter_mut().zip(&mut self.starts) {
            *start = s.free_step();
        }
        self.bridge.free();
        let y = self.solve.solve(&self.strings, &self.bridge);
        let forces = self.solve.commit(&mut self.strings, &y);
        self.bridge.finish(&forces);
        for ((s, start), &(total, active)) in self
            .strings
            .iter_mut()
            .zip(&self.starts)
            .zip(&self.solve.committed)
        {
            s.finish_step(*start, total, active);
        }
    }

    /// The network's energy terms (J): the strings' (with their contacts and seats) plus the
    /// bridge's kinetic and potential energy and its dissipation. O(total modes).
    pub fn energy_terms(&self) -> EnergyTerms {
        let mut e = EnergyTerms::default();
        for s in &self.strings {
            let t = s.energy_terms();
            e.kinetic += t.kinetic;
            e.linear += t.linear;
            e.nonlinear += t.nonlinear;
            e.dissipated += t.dissipated;
            e.work += t.work;
        }
        let (kin, pot) = self.bridge.energy();
        e.kinetic += kin;
        e.linear += pot;
        e.dissipated += self.bridge.dissipated();
        e
    }

    /// String `string`'s own energy (J, its seat's spring and its contact included; its
    /// dissipation and work as accounts).
    pub fn string_energy(&self, string: usize) -> EnergyTerms {
        self.strings[string].energy_terms()
    }

    /// The bridge's `(kinetic, potential)` energy (J).
    pub fn bridge_energy(&self) -> (f64, f64) {
        self.bridge.energy()
    }

    /// The strings (read-only).
    pub fn strings(&self) -> &[StiffString] {
        &self.strings
    }

    /// String `string`, mutable (control or the stepping thread; for initial conditions
    /// before the first step and for controls such as the hand).
    pub fn string_mut(&mut self, string: usize) -> &mut StiffString {
        &mut self.strings[string]
    }

    /// Retunes string `string` to `tension` (N), its bending stiffness kept, its Valette
    /// losses (the default law) times `damping` and at least the decay rate `floor` (1/s)
    /// ([`StiffString::retune`], which books the change of energy as work). The caller checks
    /// the inputs (an index in range, a finite positive tension, a finite damping and floor
    /// ≥ 0); `false` if the string refused them anyway. Stepping thread; no allocation,
    /// O(modes).
    pub fn retune_string(&mut self, string: usize, tension: f64, damping: f64, floor: f64) -> bool {
        let Some(s) = self.strings.get_mut(string) else {
            return false;
        };
        let ei = s.params().bending_stiffness();
        s.retune(
            tension,
            Stiffness::BendingStiffness(ei),
            Some(&ValetteLosses::default()),
            damping,
            floor,
        )
        .is_ok()
    }

    /// The bridge.
    pub fn bridge(&self) -> &BridgeBody {
        &self.bridge
    }

    /// The bridge solve's counters.
    pub fn stats(&self) -> NetworkStats {
        self.solve.stats
    }

    /// Time step in s.
    pub fn h(&self) -> f64 {
        self.h
    }

    /// Number of output channels.
    pub fn output_count(&self) -> usize {
        self.outputs.len()
    }

    /// A stereo mix of the strings' forces on the bridge (N): `Σ_s gains[s] · (-F_s)`, `F_s`
    /// the jawari and seat force of the last step on string `s` (`gains` one `[left, right]`
    /// pair per string). The body's drive, as a bridge-force pickup. O(strings).
    pub fn bridge_force_mix(&self, gains: &[[f64; 2]]) -> [f64; 2] {
        let mut out = [0.0; 2];
        for (s, g) in self.strings.iter().zip(gains) {
            let f = -s.obstacle_force();
            out[0] += g[0] * f;
            out[1] += g[1] * f;
        }
        out
    }

    /// Value of output channel `c` at the current state.
    pub fn output(&self, c: usize) -> f64 {
        match &self.outputs[c] {
            ResolvedOutput::String { string, channel } => {
                let mut v = 0.0;
                self.strings[*string].read_outputs(|i, x| {
                    if i == *channel {
                        v = x;
                    }
                });
                v
            }
            ResolvedOutput::Bridge { velocity, weights } => {
                let state = if *velocity {
                    self.bridge.increment()
                } else {
                    self.bridge.displacement()
                };
                let v: f64 = state.iter().zip(weights).map(|(a, w)| a * w).sum();
                if *velocity {
                    v / self.h
                } else {
                    v
                }
            }
        }
    }
}
