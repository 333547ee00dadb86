//! A string voice: the stiff string with its bridge, retuned per note by its tension.
//!
//! Threads: built on the worker thread (inside a bank); everything else runs on the audio
//! thread without allocating.

use super::mapping::{pitch_ratio, release_sigma, Physics};
use crate::engine::params::ParamId;
use crate::models::string::params::Stiffness;
use crate::models::string::{StiffString, ValetteLosses};

/// A string voice's model and the root-key constants.
pub(crate) struct StringVoice {
    pub model: StiffString,
    losses: ValetteLosses,
    /// Newton cap hits already counted into the engine's total.
    pub cap_hits_seen: u64,
}

impl StringVoice {
    /// Wraps a built model (worker thread).
    pub fn new(model: StiffString, losses: ValetteLosses) -> Self {
        Self {
            model,
            losses,
            cap_hits_seen: 0,
        }
    }

    pub fn retune(&mut self, p: &Physics, key: u8, note: f32, released: bool) -> bool {
        let v = &p.values;
        let r = pitch_ratio(p, key, note);
        let t_root = v.get(ParamId::Tension) as f64;
        let l = self.model.params().length;
        let ei = v.get(ParamId::Inharmonicity) as f64 * t_root * l * l
            / (std::f64::consts::PI * std::f64::consts::PI);
        let floor = if released { release_sigma(v) } else { 0.0 };
        self.model
            .retune(
                t_root * r * r,
                Stiffness::BendingStiffness(ei),
                Some(&self.losses),
                v.get(ParamId::DampingScale) as f64,
                floor,
            )
            .is_ok()
    }
}
