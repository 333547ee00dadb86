//! A string voice: the stiff string with its bridge, retuned per note by its tension.
//!
//! Threads: built on the worker thread (inside a bank); everything else runs on the audio
//! thread without allocating.

use super::hand_placement::{HAND_STRING_POSITION, HAND_T60};
use super::mapping::{pitch_ratio, release_sigma, Physics};
use crate::engine::governor::PRIOR_SECONDS_PER_UNIT;
use crate::engine::params::ParamId;
use crate::models::plate::hand_damping_for_t60;
use crate::models::string::params::Stiffness;
use crate::models::string::{StiffString, ValetteLosses};

/// A string voice's model and the root-key constants.
pub(crate) struct StringVoice {
    pub model: StiffString,
    losses: ValetteLosses,
    /// Newton cap hits already counted into the engine's total.
    pub cap_hits_seen: u64,
    /// The hand's damper coefficient at full pressure (N·s/m): the fundamental's 60 dB decay
    /// in [`HAND_T60`] by `σ = c φ₁(x_h)² / 2μ` ([`hand_damping_for_t60`] with `μ` for
    /// `ρh`); 0 if the hand point is refused (on the obstacle).
    hand_c_max: f64,
    /// The hand pressure applied to the model (0 to 1).
    pressure: f64,
    /// The CPU governor's price of one step (s): measured by the worker's cost trial under
    /// the governor, else the prior estimate (`engine/governor.rs`). Set on the worker.
    pub price: f64,
}

impl StringVoice {
    /// Wraps a built model and puts the hand (lifted) at [`HAND_STRING_POSITION`] (worker
    /// thread).
    pub fn new(mut model: StiffString, losses: ValetteLosses) -> Self {
        let p = model.params().clone();
        let modes = model.modal_displacement().len();
        let x = HAND_STRING_POSITION * p.length;
        let hand_c_max = match model.set_hand(x, 0.0) {
            Ok(()) => {
                let phi = p.mode_shape(1, model.hand_position());
                hand_damping_for_t60(p.linear_density, phi, HAND_T60)
            }
            Err(_) => 0.0,
        };
        Self {
            model,
            losses,
            cap_hits_seen: 0,
            hand_c_max: if hand_c_max.is_finite() {
                hand_c_max
            } else {
                0.0
            },
            pressure: 0.0,
            price: PRIOR_SECONDS_PER_UNIT * (modes * modes) as f64,
        }
    }

    /// Sets the player's hand pressure (0 to 1, clamped; 0 lifts the hand): the hand's damper
    /// coefficient becomes `pressure · c_max`. O(1), no allocation; audio thread.
    pub fn set_pressure(&mut self, pressure: f64) {
        let p = pressure.clamp(0.0, 1.0);
        if p != self.pressure {
            self.pressure = p;
            // Finite and ≥ 0 by construction: cannot refuse.
            let _ = self.model.set_hand_damping(p * self.hand_c_max);
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
