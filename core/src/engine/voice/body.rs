//! What a voice's model implements ([`VoiceBody`]): the lifecycle the engine drives and what
//! it reads back, the one interface between the engine's notes and an instrument's physics.
//! The plate ([`PlateVoice`]), the string ([`StringVoice`]), the drone ([`DroneVoice`]) and
//! the sitar (`super::sitar`) implement it; a new instrument
//! implements it and the engine's note handling, mixing, governor and telemetry take it as it
//! is (a voice holds its body as [`super::VoiceModel`] and reaches it through
//! [`super::VoiceModel::body`]).
//!
//! Lifecycle of a note: [`VoiceBody::begin`] (a fresh note) → [`VoiceBody::retune`] (the
//! note's coefficients, again whenever a parameter, bend or expression moves) →
//! [`VoiceBody::strike`] (the excitation, at the voice's first step after the note-on) →
//! [`VoiceBody::run`] / [`VoiceBody::run_above`] (each chunk) → [`VoiceBody::reset`] (at rest,
//! free).
//!
//! Threads: built on the worker thread (inside a bank); every method runs on the audio thread
//! or the voice's job without allocating, in time bounded by the chunk.

use super::drone::DroneVoice;
use super::mapping::{Physics, VOICE_CEILING};
use super::plate::PlateVoice;
use super::strike::{commit_plate, commit_string, PendingStrike};
use super::string::StringVoice;
use super::string_view::{mode_spectrum, sample_grid, snapshot_fraction};
use crate::engine::params::ParamValues;
use crate::engine::telemetry::{DroneView, VoiceModelInfo, SNAPSHOT_POINTS, SPECTRUM_MODES};
use crate::models::source::EnergyTerms;

/// The physics of one voice, as the engine drives it (see the module documentation).
pub(crate) trait VoiceBody {
    /// Prepares a fresh note on `key` (a plate picks its tier and strike frame). Default:
    /// nothing to prepare.
    fn begin(&mut self, _p: &Physics, _key: u8) {}

    /// Applies the note's coefficients for `key` with the note's own tuning `note`
    /// (semitones) and, when `released`, the release's damping floor. `false`: refused
    /// (unstable coefficients; the voice is silenced).
    fn retune(&mut self, p: &Physics, key: u8, note: f32, released: bool) -> bool;

    /// Commits the note-on's excitation `s` with the note's values `v` and brightness
    /// `bright` (0 to 1). `false`: refused.
    fn strike(&mut self, s: &PendingStrike, v: ParamValues, bright: f32) -> bool;

    /// Advances `left.len()` steps, adding `gain ·` the two pickups into `left` and `right`.
    /// `false` if the state became non-finite or an output passed [`VOICE_CEILING`].
    fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool;

    /// Runs the band above the simulation for `left.len()` samples at its own rate (after
    /// [`Self::run`] ran the chunk). Default: no band above.
    fn run_above(&mut self, _left: &mut [f32], _right: &mut [f32], _gain: f64) -> bool {
        true
    }

    /// Puts the model at rest and clears its note state.
    fn reset(&mut self);

    /// Sets the player's hand pressure (0 to 1).
    fn set_pressure(&mut self, pressure: f64);

    /// The CPU governor's price of one step of the current note (s).
    fn price(&self) -> f64;

    /// Whether the current note offers the second half of its steps to the voice pool's
    /// workers. Default: no.
    fn offers_step_halves(&self) -> bool {
        false
    }

    /// Whether an excitation force is still acting (a pulse, a mallet in flight). Default: no
    /// (a pluck is an initial condition).
    fn exciting(&self) -> bool {
        false
    }

    /// The model's energy terms (J).
    fn energy_terms(&self) -> EnergyTerms;

    /// The energy (J) that says how loud the voice still is (its end, voice stealing).
    /// Default: the total energy.
    fn level_energy(&self) -> f64 {
        self.energy_terms().total()
    }

    /// Whether a new key on the sounding voice keeps the model's motion (a sitar's next fret:
    /// its strings ring on and the played string is plucked again at the new pitch). Default:
    /// no (a new key starts the model at rest).
    fn legato(&self) -> bool {
        false
    }

    /// Whether the model plays on by itself after its key is released (a latched drone's
    /// cycle keeps plucking). Default: no.
    fn plays_on(&self) -> bool {
        false
    }

    /// Mallet contacts begun since the last call. Default: none.
    fn take_impacts(&mut self) -> u64 {
        0
    }

    /// Contact Newton solves that hit their cap since the last call. Default: none.
    fn take_cap_hits(&mut self) -> u64 {
        0
    }

    /// What the model simulates for the current note.
    fn model_info(&self) -> VoiceModelInfo;

    /// Writes the displacement snapshot (m), the lowest mode frequencies (Hz) and `|q_s|`
    /// (the caller has zeroed `freq` and `amp`).
    fn snapshot(
        &mut self,
        disp: &mut [f32; SNAPSHOT_POINTS],
        freq: &mut [f32; SPECTRUM_MODES],
        amp: &mut [f32; SPECTRUM_MODES],
    );
    /// Fills `view` with the drone's strings and cycle; `false` (the default) for a model
    /// that is not a drone.
    fn drone_view(&mut self, _view: &mut DroneView) -> bool {
        false
    }
    // End of the interface: the engine reaches a model through nothing else.
}

impl VoiceBody for PlateVoice {
    fn begin(&mut self, p: &Physics, key: u8) {
        PlateVoice::begin(self, p, key);
    }

    fn retune(&mut self, p: &Physics, key: u8, note: f32, released: bool) -> bool {
        PlateVoice::retune(self, p, key, note, released)
    }

    fn strike(&mut self, s: &PendingStrike, v: ParamValues, bright: f32) -> bool {
        commit_plate(self, s, v, bright)
    }

    fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        PlateVoice::run(self, left, right, gain)
    }

    fn run_above(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        PlateVoice::run_above(self, left, right, gain)
    }

    fn reset(&mut self) {
        PlateVoice::reset(self);
    }

    fn set_pressure(&mut self, pressure: f64) {
        PlateVoice::set_pressure(self, pressure);
    }

    fn price(&self) -> f64 {
        PlateVoice::price(self)
    }

    fn offers_step_halves(&self) -> bool {
        self.model().offers_step_halves()
    }

    fn exciting(&self) -> bool {
        self.strike.is_some() || self.mallet.live()
    }

    fn energy_terms(&self) -> EnergyTerms {
        PlateVoice::energy_terms(self)
    }

    /// Kinetic plus linear potential energy: the nonlinear term is left out, because under
    /// the SAV scheme it is the auxiliary `ψ²/2`, which keeps an `O(h²)` residue after the
    /// motion has died away, while the physical quartic energy vanishes faster than the
    /// linear one as `q → 0`.
    fn level_energy(&self) -> f64 {
        let e = PlateVoice::energy_terms(self);
        e.kinetic + e.linear
    }

    fn take_impacts(&mut self) -> u64 {
        u64::from(self.mallet.take_impacts())
    }

    fn model_info(&self) -> VoiceModelInfo {
        PlateVoice::model_info(self)
    }

    fn snapshot(
        &mut self,
        disp: &mut [f32; SNAPSHOT_POINTS],
        freq: &mut [f32; SPECTRUM_MODES],
        amp: &mut [f32; SPECTRUM_MODES],
    ) {
        PlateVoice::snapshot(self, disp, freq, amp);
    }
}

impl VoiceBody for StringVoice {
    fn retune(&mut self, p: &Physics, key: u8, note: f32, released: bool) -> bool {
        StringVoice::retune(self, p, key, note, released)
    }

    fn strike(&mut self, s: &PendingStrike, v: ParamValues, bright: f32) -> bool {
        commit_string(self, s, v, bright)
    }

    fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        for (l, r) in left.iter_mut().zip(right.iter_mut()) {
            self.model.step();
            let (mut a, mut b) = (0.0, 0.0);
            self.model
                .read_outputs(|c, x| if c == 0 { a = x } else { b = x });
            let (a, b) = (gain * a, gain * b);
            if !(a.abs() <= VOICE_CEILING && b.abs() <= VOICE_CEILING) {
                return false;
            }
            *l += a as f32;
            *r += b as f32;
        }
        true
    }

    fn reset(&mut self) {
        self.model.reset();
        self.cap_hits_seen = 0;
    }

    fn set_pressure(&mut self, pressure: f64) {
        StringVoice::set_pressure(self, pressure);
    }

    fn price(&self) -> f64 {
        self.price
    }

    fn energy_terms(&self) -> EnergyTerms {
        self.model.energy_terms()
    }

    fn take_cap_hits(&mut self) -> u64 {
        let total = self.model.contact_stats().cap_hits;
        let d = total.saturating_sub(self.cap_hits_seen);
        self.cap_hits_seen = total;
        d
    }

    fn model_info(&self) -> VoiceModelInfo {
        let params = self.model.params();
        let n = self.model.modal_displacement().len();
        VoiceModelInfo {
            n_phi: n as u32,
            n_psi: 0,
            top_mode_hz: (params.omega(n) / std::f64::consts::TAU) as f32,
            sim_rate: params.sample_rate as f32,
            ..VoiceModelInfo::default()
        }
    }

    fn snapshot(
        &mut self,
        disp: &mut [f32; SNAPSHOT_POINTS],
        freq: &mut [f32; SPECTRUM_MODES],
        amp: &mut [f32; SPECTRUM_MODES],
    ) {
        let u = self.model.grid_displacement();
        sample_grid(u, disp, snapshot_fraction);
        mode_spectrum(&self.model, freq, amp);
    }
}

impl VoiceBody for DroneVoice {
    fn retune(&mut self, p: &Physics, key: u8, note: f32, released: bool) -> bool {
        DroneVoice::retune(self, p, key, note, released)
    }

    fn strike(&mut self, s: &PendingStrike, v: ParamValues, _bright: f32) -> bool {
        DroneVoice::strike(self, s, v)
    }

    fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        DroneVoice::run(self, left, right, gain)
    }

    fn reset(&mut self) {
        DroneVoice::reset(self);
    }

    /// The drone is not touched by the player's hand: pressure is ignored.
    fn set_pressure(&mut self, _pressure: f64) {}

    fn price(&self) -> f64 {
        self.price
    }

    /// The cycle is an excitation still acting while it plucks: the voice does not end in a
    /// quiet moment between two plucks.
    fn exciting(&self) -> bool {
        self.plucking()
    }

    fn energy_terms(&self) -> EnergyTerms {
        DroneVoice::energy_terms(self)
    }

    fn take_cap_hits(&mut self) -> u64 {
        DroneVoice::take_cap_hits(self)
    }

    fn model_info(&self) -> VoiceModelInfo {
        DroneVoice::model_info(self)
    }

    fn snapshot(
        &mut self,
        disp: &mut [f32; SNAPSHOT_POINTS],
        freq: &mut [f32; SPECTRUM_MODES],
        amp: &mut [f32; SPECTRUM_MODES],
    ) {
        DroneVoice::snapshot(self, disp, freq, amp);
    }

    fn drone_view(&mut self, view: &mut DroneView) -> bool {
        DroneVoice::drone_view(self, view);
        true
    }

    fn plays_on(&self) -> bool {
        self.plucking()
    }
}
