//! Per-note values: polyphonic modulation of the strike, hardness, damping and pickup
//! parameters ([`NoteOverrides`]), and the brightness expression's mapping onto the strike.
//!
//! **Polyphonic modulation.** A host (CLAP's polyphonic modulation) may give one note its own
//! value of a few parameters, [`POLY_PARAMS`]: the note then plays exactly as if the parameter
//! had that value globally, and the other notes keep the global value. What each one moves and
//! when:
//! - `strike_radius` (plates) and `pluck_position` (strings): where the note's strikes and
//!   plucks land, from its next strike on (module doc of [`super`]: a note's excitation is
//!   committed at its first step, so a modulation sent with the note-on shapes its own strike);
//! - `mallet_hardness`: the felt law of the note's next mallet strikes, the same way;
//! - `damping_scale`: the note's damping at once (a retune of that voice);
//! - `pickup_left_pos`, `pickup_right_pos` (plates): where the note is heard, at once. A
//!   string's pickups stay where the bank put them: its output rows are built with the bank.
//!
//! **Brightness.** The brightness expression `b ∈ [0, 1]` (0.5 neutral) moves the next
//! strikes: the mallet's hardness by `b - 0.5` (clamped to [0, 1], so `b = 1` takes a
//! hardness-0.5 mallet to the hard end); a force pulse's duration by `4^{0.5 - b}` (half as
//! long at `b = 1`: a shorter pulse reaches higher partials, its spectrum's first zero is at
//! `1.5 / T`, [`crate::models::plate::RaisedCosine`]); a pluck's distance to the nearer end by
//! `4^{0.5 - b}` (a pluck nearer the end excites the high partials more: the `j`-th partial's
//! amplitude goes as `sin(jπx/L)/j²`), within [0.02, 0.5] of the length.
//!
//! Plain `Copy` data; audio thread.

use crate::engine::params::{ParamId, ParamValues};

/// The parameters a host may modulate per note (their index is the plugin's poly-modulation
/// id).
pub const POLY_PARAMS: [ParamId; 6] = [
    ParamId::StrikeRadius,
    ParamId::PluckPosition,
    ParamId::MalletHardness,
    ParamId::DampingScale,
    ParamId::PickupLeftPos,
    ParamId::PickupRightPos,
];

/// The slot of `id` in [`POLY_PARAMS`], if it is one.
pub fn poly_slot(id: ParamId) -> Option<usize> {
    POLY_PARAMS.iter().position(|&p| p == id)
}

/// A note's own values of [`POLY_PARAMS`] (NaN: the global value). Audio thread.
#[derive(Debug, Clone, Copy)]
pub struct NoteOverrides([f32; POLY_PARAMS.len()]);

impl Default for NoteOverrides {
    fn default() -> Self {
        Self([f32::NAN; POLY_PARAMS.len()])
    }
}

impl NoteOverrides {
    /// Sets the note's value of `id` (clamped into the parameter's range, as a host's
    /// modulated value is). Returns `false`, changing nothing, if `id` is not in
    /// [`POLY_PARAMS`] or `value` is not finite.
    pub fn set(&mut self, id: ParamId, value: f32) -> bool {
        match poly_slot(id) {
            Some(i) if value.is_finite() => {
                let info = id.info();
                self.0[i] = value.clamp(info.min, info.max);
                true
            }
            _ => false,
        }
    }

    /// The note's own value of `id`, if it has one.
    pub fn get(&self, id: ParamId) -> Option<f32> {
        let v = self.0[poly_slot(id)?];
        (!v.is_nan()).then_some(v)
    }

    /// `values` with the note's own values written over the global ones.
    pub fn apply(&self, mut values: ParamValues) -> ParamValues {
        for (&id, &v) in POLY_PARAMS.iter().zip(&self.0) {
            if !v.is_nan() {
                values.0[id.index()] = v;
            }
        }
        values
    }
}

/// Neutral brightness.
pub const NEUTRAL_BRIGHTNESS: f32 = 0.5;

/// The mallet hardness a strike uses at brightness `b` (module doc).
pub fn bright_hardness(hardness: f64, b: f32) -> f64 {
    (hardness + (b as f64 - NEUTRAL_BRIGHTNESS as f64)).clamp(0.0, 1.0)
}

/// The factor `4^{0.5 - b}` on a pulse's duration and a pluck's distance to its end.
pub fn bright_factor(b: f32) -> f64 {
    4f64.powf(NEUTRAL_BRIGHTNESS as f64 - b as f64)
}

/// The pluck position (fraction of the length) at brightness `b`: the distance to the nearer
/// end times [`bright_factor`], kept within [0.02, 0.5] (module doc).
pub fn bright_pluck(position: f64, b: f32) -> f64 {
    if b == NEUTRAL_BRIGHTNESS {
        return position;
    }
    let near = position.min(1.0 - position);
    let d = (near * bright_factor(b)).clamp(0.02, 0.5);
    if position <= 0.5 {
        d
    } else {
        1.0 - d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_replace_only_their_parameter() {
        let mut o = NoteOverrides::default();
        let g = ParamValues::default();
        assert_eq!(o.apply(g).0, g.0);
        assert!(o.set(ParamId::DampingScale, 3.0));
        assert!(!o.set(ParamId::Gain, 3.0), "gain is not per note");
        assert!(!o.set(ParamId::DampingScale, f32::NAN));
        assert_eq!(o.get(ParamId::DampingScale), Some(3.0));
        let v = o.apply(g);
        for p in crate::engine::params::PARAMS {
            let want = if p.id == ParamId::DampingScale {
                3.0
            } else {
                g.get(p.id)
            };
            assert_eq!(v.get(p.id), want, "{}", p.key);
        }
        // A host's value past the range is the range's end, as the host's own control.
        assert!(o.set(ParamId::DampingScale, 1e9));
        assert_eq!(o.get(ParamId::DampingScale), Some(20.0));
    }

    #[test]
    fn brightness_moves_the_strike() {
        assert_eq!(bright_hardness(0.5, 1.0), 1.0);
        assert_eq!(bright_hardness(0.5, 0.5), 0.5);
        assert_eq!(bright_hardness(0.2, 0.0), 0.0);
        assert_eq!(bright_factor(1.0), 0.5);
        assert_eq!(bright_factor(0.0), 2.0);
        assert_eq!(bright_pluck(0.25, 0.5), 0.25);
        assert_eq!(bright_pluck(0.25, 1.0), 0.125);
        assert_eq!(bright_pluck(0.25, 0.0), 0.5);
        assert!((bright_pluck(0.8, 1.0) - 0.9).abs() < 1e-12);
        assert_eq!(bright_pluck(0.03, 1.0), 0.02);
    }
}
