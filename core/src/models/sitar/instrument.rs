//! [`Sitar`]: the played string and its taraf on the bridges, tuned by ear, one note plucked.

use super::spec::SitarSpec;
use crate::error::ParamError;
use crate::models::network::{BridgeInstrument, StringNetwork};
use crate::models::string::TrianglePluck;
use crate::models::tanpura::instrument::pan_gains;
use crate::models::tanpura::tune::tune_by_ear;

/// Amplitude of the pluck that tunes a taraf string by ear, m.
const TARAF_TUNING_PLUCK: f64 = 3e-4;

/// A sitar: the played string (string 0, with the curved jawari of the main bridge) and its
/// taraf (strings 1 and up) on the bridges' shared modes. The played string is plucked at the
/// first step; the taraf answers through the bridges. The output is the strings' forces on the
/// bridges, the played string in the centre and the taraf spread across the image.
///
/// Built on the control thread ([`Sitar::build`]); stepped without allocating.
#[derive(Debug)]
pub struct Sitar {
    /// The strings on the bridges.
    network: StringNetwork,
    /// Per string, `[left, right]` gains.
    pan: Vec<[f64; 2]>,
    /// Per string, its tension after tuning (N).
    tensions: Vec<f64>,
}

impl Sitar {
    /// Validates `spec`, tunes every string by ear, builds the network and plucks the played
    /// string. Control thread.
    pub fn build(spec: &SitarSpec) -> Result<Self, ParamError> {
        spec.validate()?;
        let n = spec.taraf + 1;
        let targets = spec.targets();
        let plucks: Vec<TrianglePluck> = (0..n)
            .map(|i| {
                let (length, _, _) = spec.geometry(i);
                if i == 0 {
                    TrianglePluck {
                        position: spec.pluck_position * length,
                        amplitude: spec.pluck_amplitude,
                    }
                } else {
                    TrianglePluck {
                        position: 0.3 * length,
                        amplitude: TARAF_TUNING_PLUCK,
                    }
                }
            })
            .collect();
        let scales = if spec.tune_by_ear {
            tune_by_ear(|s| spec.network(s), &targets, &plucks)?
        } else {
            vec![1.0; n]
        };
        let mut network = StringNetwork::new(&spec.network(&scales)?)?;
        network.pluck(0, &plucks[0])?;
        let pan = (0..n)
            .map(|i| {
                if i == 0 || n == 1 {
                    pan_gains(0.0)
                } else {
                    pan_gains(0.8 * (2.0 * (i - 1) as f64 / (n - 2).max(1) as f64 - 1.0))
                }
            })
            .collect();
        let tensions = (0..n)
            .map(|i| spec.nominal_tension(i) * scales[i])
            .collect();
        Ok(Self {
            network,
            pan,
            tensions,
        })
    }

    /// The network (string 0 the played string, then the taraf).
    pub fn network(&self) -> &StringNetwork {
        &self.network
    }

    /// Each string's tension after tuning by ear (N).
    pub fn tensions(&self) -> &[f64] {
        &self.tensions
    }

    /// Advances one step. No allocation.
    pub fn step(&mut self) {
        self.network.step();
    }
}

impl BridgeInstrument for Sitar {
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
