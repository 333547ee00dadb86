//! The band above a plate voice's simulation, its data: the plate's modes continued past the
//! bank's basis (per bank) and each voice's extension bank with its scratch. The per-note
//! retune and the run are the plate voice's (`plate/above.rs`); the physics is
//! [`crate::models::plate::extension`].
//!
//! Threads: built on the worker with the bank; [`Above::reset`] on the audio thread without
//! allocation.

use crate::models::plate::mode_list::ModeList;
use crate::models::plate::spec::Position;
use crate::models::plate::BandExtension;

/// The modes of a bank's plate continued past its basis (per bank, read-only).
#[derive(Debug, Clone)]
pub(crate) struct AboveModes {
    /// The plate's modes from the first on (the basis's are its first `N_Φ`).
    pub list: ModeList,
    /// `Φ̂_e` of every listed mode at the left and right pickups, in the frame's convention
    /// (mirror: at `(r_p, 0)`, rotated per note; fixed: at the pickup points).
    pub pickups: [Vec<f64>; 2],
    /// `Φ̂_e` of every listed mode at the bank's strike point (mirror: `(r_s, 0)`; fixed: the
    /// point of the bank's strike radius and angle).
    pub strike: Vec<f64>,
}

impl AboveModes {
    /// Takes the plate's mode `list` (at least the basis's modes;
    /// [`crate::models::plate::blueprint::PlateBlueprint::modes_above`]) and evaluates it at the
    /// left and right pickup positions `at` and the strike point `struck_at` of the voices'
    /// frame (mirror: `(r, 0)`; fixed: the points). Worker thread; allocates.
    pub fn new(list: ModeList, at: [Position; 2], struck_at: Position) -> Self {
        let values = |p: &Position| (0..list.len()).map(|e| list.phi_at(e, p)).collect();
        let pickups = at.map(|p| values(&p));
        let strike = values(&struck_at);
        Self {
            list,
            pickups,
            strike,
        }
    }
}

/// A voice's band above: the extension bank and its per-note scratch.
pub(crate) struct Above {
    /// The modes above the tier, fed by the closure.
    pub bank: BandExtension,
    /// `ω_e` (rad/s) and `c_e` (1/s) of the note's modes above (scratch, the list's length).
    pub omega: Vec<f64>,
    pub damping: Vec<f64>,
    /// Whether the `band_above` parameter is on.
    pub on: bool,
    /// Whether the `strike_above` parameter is on: the mallet's contact feels the modes above
    /// (with the band above on; [`crate::models::plate::contact_residual`]).
    pub contact: bool,
    /// At rest since the last reset (nothing received yet): the run is skipped.
    pub idle: bool,
    /// The rate the band above runs at (Hz): the host rate up to 48 kHz
    /// ([`crate::engine::above_mix::above_rate`]).
    pub rate: f64,
}

impl Above {
    /// Room for every listed mode, running at `rate` (Hz). Worker thread; allocates.
    pub fn new(modes: &AboveModes, rate: f64) -> Self {
        let n = modes.list.len();
        Self {
            bank: BandExtension::new(n),
            omega: vec![0.0; n],
            damping: vec![0.0; n],
            on: true,
            contact: false,
            idle: true,
            rate,
        }
    }

    /// Puts the band above at rest. No allocation.
    pub fn reset(&mut self) {
        self.bank.reset();
        self.idle = true;
    }
}
