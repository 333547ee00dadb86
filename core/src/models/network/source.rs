//! [`StringNetwork`] as a [`RenderSource`] for the offline renderer and the harness, and the
//! instruments built on a network ([`BridgeInstrument`]: the tanpura, the sitar) as sources
//! with a stereo bridge-force pickup.

use super::StringNetwork;
use crate::models::source::{
    EnergyTerms, ModelDetails, NetworkDetails, NetworkStringDetails, RenderSource,
};

impl StringNetwork {
    /// Each string's grid and where its modes lie against the Nyquist frequency, for reports.
    /// Control thread (allocates).
    pub fn details(&self) -> NetworkDetails {
        let nyquist_hz = 0.5 / self.h();
        let strings = self
            .strings()
            .iter()
            .map(|s| {
                let p = s.params();
                let hz = |j: usize| p.omega(j) / std::f64::consts::TAU;
                let stepped = s.stepped_modes();
                NetworkStringDetails {
                    modes: p.modes(),
                    stepped,
                    top_mode_hz: if stepped > 0 { hz(stepped) } else { 0.0 },
                    modes_above_nyquist: (1..=stepped).filter(|&j| hz(j) > nyquist_hz).count(),
                }
            })
            .collect();
        NetworkDetails {
            nyquist_hz,
            strings,
        }
    }
}

impl RenderSource for StringNetwork {
    fn sim_rate(&self) -> f64 {
        1.0 / self.h()
    }

    fn channels(&self) -> usize {
        self.output_count()
    }

    fn process(&mut self, out: &mut [Vec<f64>], frames: usize) {
        for n in 0..frames {
            self.step();
            for (c, o) in out.iter_mut().enumerate().take(self.output_count()) {
                o[n] = self.output(c);
            }
        }
    }

    fn energy(&self) -> EnergyTerms {
        self.energy_terms()
    }

    fn is_conservative(&self) -> bool {
        true
    }

    fn details(&self) -> ModelDetails {
        ModelDetails::Network(StringNetwork::details(self))
    }
}

/// An instrument whose sound is its strings' forces on the bridge, mixed to stereo
/// ([`StringNetwork::bridge_force_mix`]); every such instrument is a [`RenderSource`] of two
/// channels.
///
/// Stepped by one thread at a time; `advance` must not allocate.
pub trait BridgeInstrument {
    /// The network of strings on the bridge.
    fn network(&self) -> &StringNetwork;
    /// Advances one step (with whatever the instrument plays at that step).
    fn advance(&mut self);
    /// Per string, the `[left, right]` gains of its bridge force.
    fn gains(&self) -> &[[f64; 2]];
}

impl<T: BridgeInstrument> RenderSource for T {
    fn sim_rate(&self) -> f64 {
        1.0 / self.network().h()
    }

    fn channels(&self) -> usize {
        2
    }

    fn process(&mut self, out: &mut [Vec<f64>], frames: usize) {
        let (left, right) = out.split_at_mut(1);
        for (l, r) in left[0].iter_mut().zip(right[0].iter_mut()).take(frames) {
            self.advance();
            [*l, *r] = self.network().bridge_force_mix(self.gains());
        }
    }

    fn energy(&self) -> EnergyTerms {
        self.network().energy_terms()
    }

    fn is_conservative(&self) -> bool {
        true
    }

    fn details(&self) -> ModelDetails {
        ModelDetails::Network(self.network().details())
    }
}
