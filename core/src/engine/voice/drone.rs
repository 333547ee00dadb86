//! A drone voice: the tanpura's strings on their moving bridge, plucked in the drone's cycle
//! ([`Tanpura`]). The key held is Sa: a note retunes every string by its tension (with the
//! corrections the worker measured by ear at anchor keys), its velocity sets the plucks'
//! strength, and its release stops the cycle and lets the strings ring out at the release
//! rate; with the latch on, a released drone keeps plucking until the latch is turned off or
//! another note takes the voice.
//!
//! The output is each string's force on the bridge (N), panned as the strings lie across the
//! bridge (`models::network::StringNetwork::bridge_force_mix`), over [`DRONE_FORCE_REF`].
//!
//! Threads: built on the worker thread (inside a bank); everything else runs on the audio
//! thread without allocating.

use super::mapping::{pitch_ratio, release_sigma, Physics};
use super::network_voice::{network_model_info, run_bridge_mix, CapHitsSeen};
use super::strike::PendingStrike;
use super::string_view::{mode_spectrum, sample_grid, snapshot_fraction};
use crate::engine::model_spec::{drone_jitter, drone_pattern, root_hz};
use crate::engine::params::{ParamId, ParamValues};
use crate::engine::telemetry::{
    DroneView, VoiceModelInfo, DRONE_VIEW_POINTS, MAX_DRONE_STRINGS, SNAPSHOT_POINTS,
    SPECTRUM_MODES,
};
use crate::models::source::EnergyTerms;
use crate::models::tanpura::instrument::MAX_STRENGTH;
use crate::models::tanpura::{Pattern, Tanpura};

/// Output normalisation of the drone (N of bridge force at full scale, before the gain): the
/// factory drone (alias-free) at velocity 100 peaks at -7.5 dBFS over a 30 s drone with a
/// gain of 0 dB (its preset adds 2 dB; `tests/engine/preset_levels.rs` holds the levels).
/// The drone that stepped every mode needed 0.25: its aliased modes weakened its bridge
/// forces by 10 dB (docs/models.md, "The drone's grid and rate").
pub const DRONE_FORCE_REF: f64 = 1.0;

/// The drone's cycle period (s) for the values `v` and the host's tempo `tempo` (bpm): the
/// `drone_cycle` parameter, or with `drone_sync` on and a tempo, `drone_beats` beats of it
/// within the cycle's range (0.5 to 30 s). Any thread.
pub fn drone_cycle_seconds(v: &ParamValues, tempo: Option<f64>) -> f64 {
    match tempo {
        Some(bpm) if v.index_of(ParamId::DroneSync) == 1 => {
            let range = ParamId::DroneCycle.info();
            (f64::from(v.get(ParamId::DroneBeats)) * 60.0 / bpm)
                .clamp(f64::from(range.min), f64::from(range.max))
        }
        _ => f64::from(v.get(ParamId::DroneCycle)),
    }
}

/// The index of the string the editor's displacement view shows: the first middle Sa.
const WATCHED_STRING: usize = 1;

/// A drone voice's model.
pub(crate) struct DroneVoice {
    /// The strings, the bridge and the cycle.
    pub model: Tanpura,
    /// Whether the cycle plucks: the note is held, sustained or latched.
    plucking: bool,
    /// Newton cap hits of the bridge solve already counted into the engine's total.
    cap_hits: CapHitsSeen,
    /// The cycle's parameters last applied (period s, pattern index, variation), to retime
    /// the cycle only when they change.
    cycle: (f32, Pattern, f32),
    /// The CPU governor's price of one step (s): measured by the worker's cost trial under
    /// the governor, else the prior estimate (`engine/governor.rs`). Set on the worker.
    pub price: f64,
}

impl DroneVoice {
    /// Wraps a built drone (worker thread), at rest, priced at `price` s per step.
    pub fn new(mut model: Tanpura, price: f64) -> Self {
        model.reset();
        model.set_plucking(false);
        Self {
            model,
            plucking: false,
            cap_hits: CapHitsSeen::default(),
            cycle: (f32::NAN, Pattern::Classic, f32::NAN),
            price,
        }
    }

    /// Retunes to `key` (Sa) with the note's tuning `note`, the damping scale and, when
    /// `released` and not latched, the release: plucking stops and every mode decays at
    /// least at the release rate. A changed cycle period, pattern or variation takes over at
    /// the next cycle (`Tanpura::set_cycle`). `false`: refused. Audio thread.
    pub fn retune(&mut self, p: &Physics, key: u8, note: f32, released: bool) -> bool {
        let v = &p.values;
        let latched = v.index_of(ParamId::DroneLatch) == 1;
        let release = released && !latched;
        let floor = if release { release_sigma(v) } else { 0.0 };
        let damping = v.get(ParamId::DampingScale) as f64;
        self.plucking = !release;
        self.model.set_plucking(self.plucking);
        let cycle = (
            drone_cycle_seconds(v, p.tempo) as f32,
            drone_pattern(v),
            v.get(ParamId::DroneVariation),
        );
        if cycle != self.cycle {
            // Within `set_cycle`'s ranges by the parameters' (its refusal would allocate).
            let period = ParamId::DroneCycle.info();
            if !((period.min..=period.max).contains(&cycle.0) && (0.0..=1.0).contains(&cycle.2)) {
                return false;
            }
            let (timing_jitter_ms, strength_jitter) = drone_jitter(f64::from(cycle.2));
            let ok = self
                .model
                .set_cycle(
                    f64::from(cycle.0),
                    cycle.1,
                    timing_jitter_ms,
                    strength_jitter,
                )
                .is_ok();
            if !ok {
                return false;
            }
            self.cycle = cycle;
        }
        // The key's pitch over the built Sa: `pitch_ratio` is relative to the root key, whose
        // pitch `440 · 2^((root - 69)/12)` the drone was built at unless that lies outside
        // its range.
        let ratio = pitch_ratio(p, key, note) * root_hz(v) / self.model.sa();
        // `try_retune` refuses without allocating (an unmapped key of a key table is NaN).
        self.model.try_retune(ratio, damping, floor).is_ok()
    }

    /// Commits a note-on: a fresh note starts the cycle from its first pluck (the voice was
    /// reset), a repeated one keeps the cycle where it is; either way the plucks' amplitude
    /// becomes the `pluck_amplitude` parameter times the note's velocity after the curve and
    /// the wheel (`s.amount`): a strength of that over the drone's own amplitude (at most
    /// [`MAX_STRENGTH`]). Audio thread.
    pub fn strike(&mut self, s: &PendingStrike, v: ParamValues) -> bool {
        let amplitude = f64::from(v.get(ParamId::PluckAmplitude));
        // At most 2 (velocity 1, the wheel's full factor) times 5 mm over 1 mm, within the
        // drone's largest strength; checked here, as `set_strength`'s refusal would allocate.
        let strength = s.amount * amplitude / self.model.pluck_amplitude();
        if !(0.0..=MAX_STRENGTH).contains(&strength) {
            return false;
        }
        self.model.set_strength(strength).is_ok()
    }

    /// Advances `left.len()` steps, adding `gain ·` the bridge-force mix (N; the bank's gain
    /// carries `1 /` [`DRONE_FORCE_REF`]). Audio thread.
    pub fn run(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        run_bridge_mix(&mut self.model, left, right, gain)
    }

    /// Puts every string and the bridge at rest, the cycle at its first pluck, plucking off.
    pub fn reset(&mut self) {
        self.model.reset();
        self.cap_hits = CapHitsSeen::default();
        self.plucking = false;
        self.model.set_plucking(false);
    }

    /// Whether the cycle still plucks (the voice must not end between plucks).
    pub fn plucking(&self) -> bool {
        self.plucking
    }

    /// The network's energy terms (J).
    pub fn energy_terms(&self) -> EnergyTerms {
        self.model.network().energy_terms()
    }

    /// Newton cap hits of the bridge solve since the last call.
    pub fn take_cap_hits(&mut self) -> u64 {
        self.cap_hits.take(self.model.network())
    }

    /// Per string the modes, the highest mode of the highest string, the simulation rate.
    pub fn model_info(&self) -> VoiceModelInfo {
        network_model_info(self.model.network())
    }

    /// The watched string's displacement (m, from its grid: one inverse transform) and its
    /// lowest modes (Hz, `|q_j|`).
    pub fn snapshot(
        &mut self,
        disp: &mut [f32; SNAPSHOT_POINTS],
        freq: &mut [f32; SPECTRUM_MODES],
        amp: &mut [f32; SPECTRUM_MODES],
    ) {
        let n = self.model.network().strings().len();
        if n == 0 {
            return;
        }
        let i = WATCHED_STRING.min(n - 1);
        sample_grid(
            self.model.string_grid_displacement(i),
            disp,
            snapshot_fraction,
        );
        mode_spectrum(&self.model.network().strings()[i], freq, amp);
    }

    /// Fills `view`: every string's note, energy and displacement (the grid's, sampled at
    /// [`DRONE_VIEW_POINTS`] points), Sa, and where the cycle is. Audio thread, no
    /// allocation: one inverse transform per string (`O(N log N)`).
    pub fn drone_view(&mut self, view: &mut DroneView) {
        let n = self.model.network().strings().len().min(MAX_DRONE_STRINGS);
        view.strings = n as u8;
        view.sa_hz = (self.model.sa() * self.model.ratio()) as f32;
        view.cycle_seconds = self.model.cycle_seconds() as f32;
        view.cycle_phase = self.model.cycle_phase() as f32;
        view.plucking = self.plucking;
        for i in 0..n {
            view.ratio[i] = self.model.ratios()[i] as f32;
            view.onsets[i] = self.model.onset(i) as f32;
            view.energy[i] = self.model.network().string_energy(i).total() as f32;
            // The whole string, both ends included.
            sample_grid(
                self.model.string_grid_displacement(i),
                &mut view.displacement[i],
                |p| p as f64 / (DRONE_VIEW_POINTS - 1) as f64,
            );
        }
    }
}
