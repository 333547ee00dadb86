//! What the voices of the instruments on a string network share (the drone,
//! [`super::drone`], and the sitar, [`super::sitar`]): the run of a block summing the bridge
//! forces, the bridge solve's cap hits handed to the engine once, and the model's facts for
//! the editor.
//!
//! Audio thread, no allocation.

use super::mapping::VOICE_CEILING;
use crate::engine::telemetry::VoiceModelInfo;
use crate::models::network::{BridgeInstrument, StringNetwork};

/// Advances `model` `left.len()` steps, adding `gain ·` its bridge-force mix (N; the bank's
/// gain carries the instrument's force reference) into `left` and `right`. `false` when a
/// sample passes [`VOICE_CEILING`] (the voice is then stopped by its caller). Audio thread.
pub(super) fn run_bridge_mix(
    model: &mut impl BridgeInstrument,
    left: &mut [f32],
    right: &mut [f32],
    gain: f64,
) -> bool {
    for (l, r) in left.iter_mut().zip(right.iter_mut()) {
        model.advance();
        let [a, b] = model.network().bridge_force_mix(model.gains());
        let (a, b) = (gain * a, gain * b);
        if !(a.abs() <= VOICE_CEILING && b.abs() <= VOICE_CEILING) {
            return false;
        }
        *l += a as f32;
        *r += b as f32;
    }
    true
}

/// The bridge solve's Newton cap hits a voice has already handed to the engine.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct CapHitsSeen(u64);

impl CapHitsSeen {
    /// The cap hits of `network` since the last call (its counter only grows between resets).
    pub(super) fn take(&mut self, network: &StringNetwork) -> u64 {
        let total = network.stats().cap_hits;
        let d = total.saturating_sub(self.0);
        self.0 = total;
        d
    }
}

/// The first string's stepped modes, the highest stepped mode of any string (Hz) and the
/// simulation rate of `network`, for the editor's model line.
pub(super) fn network_model_info(network: &StringNetwork) -> VoiceModelInfo {
    let strings = network.strings();
    let top = strings
        .iter()
        .filter(|s| s.stepped_modes() > 0)
        .map(|s| s.params().omega(s.stepped_modes()))
        .fold(0.0, f64::max);
    VoiceModelInfo {
        n_phi: strings.first().map_or(0, |s| s.stepped_modes()) as u32,
        n_psi: 0,
        top_mode_hz: (top / std::f64::consts::TAU) as f32,
        sim_rate: (1.0 / network.h()) as f32,
        ..VoiceModelInfo::default()
    }
}
