//! The engine's physical mallet ([`crate::models::plate::Mallet`], docs/models.md "The mallet"):
//! the hardness mapping of the `mallet_hardness` parameter, and the per-voice state that
//! launches a mallet at each strike and drops it once it has left the plate.
//!
//! **Hardness.** `mallet_hardness` `x ∈ [0, 1]` interpolates the felt law `K [δ]_+^α` between a
//! soft felt (`K = 1e6 N/m^α`, `α = 2.5`) and a hard head (`K = 1e9 N/m^α`, `α = 1.5`):
//! `log₁₀ K = 6 + 3x`, `α = 2.5 - x`. The felt exponents of struck-bar mallets and piano
//! hammers lie between about 2 and 3.5 and harder heads have larger `K` (Chaigne & Doutaut,
//! J. Acoust. Soc. Am. 101(1), 1997, section II.B); `α = 3/2` is Hertz's law of two elastic
//! solids (a hard rubber or wooden head). For the default 0.2 kg mallet at 2 m/s against a
//! rigid target the ends give contacts of about 30 ms (soft) and 0.35 ms (hard).
//!
//! **Factory heads.** With `mallet_head` other than `custom`, the mallet is that head
//! ([`crate::models::plate::MalletHead`]: its mass, contact law and felt loss); the mass and
//! hardness parameters, and a note's own hardness and brightness, apply to `custom` only.
//!
//! **When the mallet runs.** A strike launches it just short of the (possibly moving) plate
//! ([`crate::models::plate::PlateModel::launch_mallet`]: nothing is reset) and the voice steps
//! with [`crate::models::plate::PlateModel::step_with_mallet`]: it rebounds, and strikes again
//! by itself whenever the plate's motion catches it up, as the physics says (a heavy mallet on
//! a light plate strikes several times). It is dropped (the voice steps force-free again) only
//! once it can never touch the plate again: moving away (no gravity acts on it, so it keeps
//! its speed) and farther from the plate's rest plane than the plate can ever reach at the
//! strike point. That reach follows from the plate's energy `E` (which only decreases once the
//! mallet has left): the discrete energy bounds the step-mean displacement,
//! `E ≥ (ρh/2) Σ_s ω̃_s² q̄_s²`, so by Cauchy-Schwarz
//! `|w̄| ≤ √(2E/ρh · Σ_s Φ_s²/ω̃_s²)` at a point of weights `Φ_s`; the mallet is dropped past
//! twice that bound (the margin covers the half step between `w̄` and `w(n)`), with
//! `ω̃_s ≥ (2/h) sin(ω_s h/2)` (the exact scheme's modified frequency, the lower of the two
//! schemes' values), checked every [`REACH_CHECK_STEPS`] steps. Whatever it does, it is
//! dropped [`MALLET_MAX_FLIGHT`] after its launch: a player's hand withdraws the beater. The
//! mallet's Newton solve is capped at 100 evaluations a step, so the work per step is bounded.
//!
//! Threads: built with the voice on the worker thread (an `Option` of plain data, no heap);
//! launched and stepped on the audio thread without allocating.

use crate::engine::params::{ParamId, ParamValues};
use crate::error::ParamError;
use crate::modal::CouplingTensor;
use crate::models::plate::{Diverged, Mallet, MalletHead, PlateModel};

/// Felt stiffness `K` (N/m^α) at hardness 0 (soft felt).
pub const MALLET_K_SOFT: f64 = 1e6;
/// Felt stiffness `K` (N/m^α) at hardness 1 (hard head).
pub const MALLET_K_HARD: f64 = 1e9;
/// Felt exponent `α` at hardness 0 (soft felt).
pub const MALLET_ALPHA_SOFT: f64 = 2.5;
/// Felt exponent `α` at hardness 1 (Hertz's law).
pub const MALLET_ALPHA_HARD: f64 = 1.5;
/// Felt loss `λ` (s/m) of the engine's mallet (Hunt-Crossley; `λ v = 0.2` at 2 m/s, as the
/// gong-mallet scene): moderately lossy, fixed.
pub const MALLET_LOSS: f64 = 0.1;
/// Steps between two checks of whether the mallet can still reach the plate (module doc).
pub const REACH_CHECK_STEPS: u64 = 16;
/// Longest time (s) a mallet is simulated after its launch.
pub const MALLET_MAX_FLIGHT: f64 = 0.5;

/// Felt stiffness `K` (N/m^α) and exponent `α` of `mallet_hardness` `x` (module docs):
/// `K = 10^(6 + 3x)`, `α = 2.5 - x`, `x` clamped to [0, 1]. Any thread.
pub fn mallet_law(hardness: f64) -> (f64, f64) {
    let x = hardness.clamp(0.0, 1.0);
    let k = MALLET_K_SOFT * (MALLET_K_HARD / MALLET_K_SOFT).powf(x);
    let alpha = MALLET_ALPHA_SOFT + (MALLET_ALPHA_HARD - MALLET_ALPHA_SOFT) * x;
    (k, alpha)
}

/// A voice's mallet while it is in flight or in contact (audio thread).
#[derive(Debug, Default)]
pub(crate) struct VoiceMallet {
    /// The mallet, `None` when dropped or not yet launched.
    mallet: Option<Mallet>,
    /// Steps since the launch.
    steps: u64,
    /// `2 Σ_s Φ_s²/ω̃_s² / ρh` at the strike point (m²/J): the plate can never reach past
    /// `√(reach · E)` there (module doc).
    reach: f64,
    /// Contacts begun (first strikes and the later ones) not yet taken by
    /// [`Self::take_impacts`].
    impacts: u32,
    /// Whether the last step had a contact force.
    touching: bool,
}

impl VoiceMallet {
    /// Whether a mallet is being simulated.
    pub fn live(&self) -> bool {
        self.mallet.is_some()
    }

    /// Drops the mallet.
    pub fn drop_mallet(&mut self) {
        self.mallet = None;
    }

    /// Contacts begun since the last call (every strike and re-strike of the felt).
    pub fn take_impacts(&mut self) -> u32 {
        std::mem::take(&mut self.impacts)
    }

    /// Builds a mallet from `v` (mass and hardness, or the factory head of `mallet_head`) for
    /// `model`'s time step and launches it at
    /// `speed` (m/s, > 0) at `model`'s force point, whose reach coefficient is `reach`
    /// (`2 Σ_s Φ_s²/ω̃_s² / ρh`, m²/J, module doc). No allocation. Errors name the field.
    pub fn launch(
        &mut self,
        v: &ParamValues,
        model: &PlateModel<CouplingTensor>,
        speed: f64,
        reach: f64,
    ) -> Result<(), ParamError> {
        let (mass, k, alpha, loss) = match v.index_of(ParamId::MalletHead) {
            0 => {
                let (k, alpha) = mallet_law(v.get(ParamId::MalletHardness) as f64);
                (v.get(ParamId::MalletMass) as f64, k, alpha, MALLET_LOSS)
            }
            i => {
                let l = MalletHead::ALL[(i - 1).min(MalletHead::ALL.len() - 1)].law();
                (l.mass, l.stiffness, l.exponent, l.loss)
            }
        };
        let mut m = Mallet::new(mass, k, alpha, loss, model.h())?;
        model.launch_mallet(&mut m, speed)?;
        self.mallet = Some(m);
        self.steps = 0;
        self.reach = reach;
        self.touching = false;
        Ok(())
    }

    /// One step of `model` with the mallet (force-free if none); drops the mallet when it is
    /// done (module docs). `Err` on divergence.
    pub fn step(&mut self, model: &mut PlateModel<CouplingTensor>) -> Result<(), Diverged> {
        let Some(m) = self.mallet.as_mut() else {
            return model.step(0.0);
        };
        model.step_with_mallet(m)?;
        self.steps += 1;
        let touching = m.force() > 0.0;
        self.impacts += u32::from(touching && !self.touching);
        self.touching = touching;
        let h = model.h();
        let (y, speed) = m.position_velocity();
        let gone = !touching
            && speed <= 0.0
            && self.steps % REACH_CHECK_STEPS == 0
            && y < -2.0 * (self.reach * model.energy().total().max(0.0)).sqrt();
        if gone || self.steps as f64 * h >= MALLET_MAX_FLIGHT {
            self.mallet = None;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hardness_maps_the_ends_and_log_k() {
        assert_eq!(mallet_law(0.0), (1e6, 2.5));
        let (k, a) = mallet_law(1.0);
        assert!((k / 1e9 - 1.0).abs() < 1e-12 && a == 1.5, "{k} {a}");
        let (k, a) = mallet_law(0.5);
        assert!(
            (k / 10f64.powf(7.5) - 1.0).abs() < 1e-12 && a == 2.0,
            "{k} {a}"
        );
    }
}
