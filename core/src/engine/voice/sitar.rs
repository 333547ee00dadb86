//! A sitar voice: the played string, its taraf and its chikari on the two bridges
//! ([`Sitar`]). The root key is Sa: the taraf and chikari are tuned to it, and the played
//! string sounds it open; a key frets the played string by its tension (with the
//! corrections the worker measured by ear at anchor keys) and plucks it, its velocity the
//! mizrab's strength (and with `chikari_stroke` the chikari's too). A new key on a sounding
//! voice does not stop the strings: the taraf and chikari ring on and the played string is
//! plucked again at its new fret, as a sitar is played ([`VoiceBody::legato`]). The release
//! (the last key let go, without the sustain pedal) damps every string at least at the
//! release rate, the player's hand on the strings; the sustain pedal lets them ring.
//!
//! The output is each string's force on its bridge (N), panned as the strings lie
//! (`models::network::StringNetwork::bridge_force_mix`), over [`SITAR_FORCE_REF`].
//!
//! Threads: built on the worker thread (inside a bank); everything else runs on the audio
//! thread without allocating.

use super::body::VoiceBody;
use super::mapping::{pitch_ratio, release_sigma, Physics};
use super::network_voice::{network_model_info, run_bridge_mix, CapHitsSeen};
use super::strike::PendingStrike;
use super::string_view::{mode_spectrum, sample_grid, snapshot_fraction};
use crate::engine::model_spec::root_hz;
use crate::engine::params::{ParamId, ParamValues};
use crate::engine::telemetry::{VoiceModelInfo, SNAPSHOT_POINTS, SPECTRUM_MODES};
use crate::models::sitar::Sitar;
use crate::models::source::EnergyTerms;

/// Output normalisation of the sitar (N of bridge force at full scale, before the gain): the
/// factory sitar's root key at velocity 127 peaks near -4 dBFS at a gain of 0 dB (the
/// mizrab's pluck near the bridge; `tests/engine/preset_levels.rs` holds the levels).
pub const SITAR_FORCE_REF: f64 = 3.0;

/// A sitar voice's model.
pub(crate) struct SitarVoice {
    /// The strings on the bridges.
    pub model: Sitar,
    /// Newton cap hits of the bridge solve already counted into the engine's total.
    cap_hits: CapHitsSeen,
    /// The CPU governor's price of one step (s): measured by the worker's cost trial under
    /// the governor, else the prior estimate (`engine/governor.rs`). Set on the worker.
    pub price: f64,
}

impl SitarVoice {
    /// Wraps a built sitar (worker thread), at rest, priced at `price` s per step.
    pub fn new(mut model: Sitar, price: f64) -> Self {
        model.reset();
        Self {
            model,
            cap_hits: CapHitsSeen::default(),
            price,
        }
    }
}

impl VoiceBody for SitarVoice {
    /// Frets the played string at `key` with the note's tuning `note`, every string's losses
    /// times the damping scale and, when `released`, the release rate under every string's
    /// decay.
    fn retune(&mut self, p: &Physics, key: u8, note: f32, released: bool) -> bool {
        let v = &p.values;
        let floor = if released { release_sigma(v) } else { 0.0 };
        let damping = f64::from(v.get(ParamId::DampingScale));
        // The key's pitch over the played string's open note, which the sitar was built at
        // (the root key's pitch unless that lies outside the sitar's range).
        let ratio = pitch_ratio(p, key, note) * root_hz(v) / self.model.note();
        self.model.try_fret(ratio, damping, floor).is_ok()
    }

    /// Plucks the played string at the `pluck_amplitude` parameter times the note's velocity
    /// after the curve and the wheel (`s.amount`), and the chikari at `chikari_stroke` times
    /// that.
    fn strike(&mut self, s: &PendingStrike, v: ParamValues, _bright: f32) -> bool {
        let amplitude = f64::from(v.get(ParamId::PluckAmplitude));
        let strength = s.amount * amplitude / self.model.pluck_amplitude();
        let chikari = strength * f64::from(v.get(ParamId::ChikariStroke));
        self.model.try_pluck(strength) && (chikari == 0.0 || self.model.try_pluck_chikari(chikari))
    }

    fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        run_bridge_mix(&mut self.model, left, right, gain)
    }

    fn reset(&mut self) {
        self.model.reset();
        self.cap_hits = CapHitsSeen::default();
    }

    /// The player's hand is not modelled on the sitar: pressure is ignored.
    fn set_pressure(&mut self, _pressure: f64) {}

    fn price(&self) -> f64 {
        self.price
    }

    fn legato(&self) -> bool {
        true
    }

    fn energy_terms(&self) -> EnergyTerms {
        self.model.network().energy_terms()
    }

    fn take_cap_hits(&mut self) -> u64 {
        self.cap_hits.take(self.model.network())
    }

    /// The played string's modes, the highest mode of any string, the simulation rate.
    fn model_info(&self) -> VoiceModelInfo {
        network_model_info(self.model.network())
    }

    /// The played string's displacement and lowest modes.
    fn snapshot(
        &mut self,
        disp: &mut [f32; SNAPSHOT_POINTS],
        freq: &mut [f32; SPECTRUM_MODES],
        amp: &mut [f32; SPECTRUM_MODES],
    ) {
        sample_grid(
            self.model.string_grid_displacement(0),
            disp,
            snapshot_fraction,
        );
        mode_spectrum(&self.model.network().strings()[0], freq, amp);
    }
}
