//! Macro controls (GUI thread only): four knobs a player reaches for, each moving several
//! physical parameters together through the host's parameter setter (one begin / set / end
//! gesture per parameter, so automation records the parameters themselves; the macros are
//! not host parameters). A macro's position is read back from its first parameter, so it
//! follows presets and automation.
//!
//! Mappings (`t` the macro position 0..1; "log" interpolates the logarithm):
//! - Hardness: what makes the strike harder for the exciter in use. Plates struck by the force
//!   pulse: its duration log 30 ms → 0.5 ms (shorter is harder); by the mallet with the custom
//!   head: its hardness 0 → 1 (felt to Hertz contact); by a factory head: the head, soft felt →
//!   hard felt → rubber → wood → metal. Strings: pluck position 50 % → 5 % of the length (a
//!   pluck near the end is sharper).
//! - Brightness: plates, strike position 30 % → 95 % of the radius and both pickups 30 % →
//!   95 % (towards the edge more high modes are excited and heard); strings, both pickups
//!   50 % → 3 % of the length. Positions rebuild the voice bank (a short pause in new notes).
//! - Decay: damping scale log 8 → 0.05 and release T60 log 0.2 s → 20 s.
//! - Size: size, log over its whole range (plates: a rescale, strings: a new grid).
//!
//! The tanpura drone has its own four: Buzz (the jivari 12 → 3.5 mm), Pace (the cycle period
//! log 8 → 2 s), Decay (as above) and Looseness (the human variation 0 → 1).

use super::grid::apply_gesture;
use crate::params::NoetherParams;
use egui::Ui;
use nice_plug::prelude::*;
use noether_core::engine::{ModelKind, ParamId};

/// How one parameter follows a macro: from `a` at 0 to `b` at 1, logarithmically if `log`.
#[derive(Debug, Clone, Copy)]
pub struct Target {
    /// The parameter moved.
    pub id: ParamId,
    /// Value at macro position 0 (plain units).
    pub a: f32,
    /// Value at macro position 1 (plain units).
    pub b: f32,
    /// Interpolate the logarithm (both ends positive).
    pub log: bool,
}

impl Target {
    /// The parameter's value at macro position `t` (0..1), inside its range.
    pub fn value(&self, t: f32) -> f32 {
        let t = t.clamp(0.0, 1.0);
        let v = if self.log {
            (self.a.ln() + t * (self.b.ln() - self.a.ln())).exp()
        } else {
            self.a + t * (self.b - self.a)
        };
        let info = self.id.info();
        v.clamp(info.min, info.max)
    }

    /// The macro position at which the parameter has value `v` (clamped to 0..1).
    pub fn position(&self, v: f32) -> f32 {
        let t = if self.log {
            (v.max(1e-30).ln() - self.a.ln()) / (self.b.ln() - self.a.ln())
        } else {
            (v - self.a) / (self.b - self.a)
        };
        if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            0.0
        }
    }
}

const fn lin(id: ParamId, a: f32, b: f32) -> Target {
    Target {
        id,
        a,
        b,
        log: false,
    }
}

const fn log(id: ParamId, a: f32, b: f32) -> Target {
    Target {
        id,
        a,
        b,
        log: true,
    }
}

/// What strikes a plate, which decides what the Hardness macro moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Striker {
    /// The raised-cosine force pulse (`exciter` = pulse): its duration.
    Pulse,
    /// The mallet with the custom head: its hardness.
    CustomMallet,
    /// The mallet with a factory head: the head itself, softest to hardest.
    FactoryMallet,
}

impl Striker {
    /// The striker the `exciter` and `mallet_head` values (enumeration indices) select.
    pub fn from_values(exciter: f32, head: f32) -> Self {
        match (exciter.round() as i32, head.round() as i32) {
            (1, 0) => Self::CustomMallet,
            (1, _) => Self::FactoryMallet,
            _ => Self::Pulse,
        }
    }
}

/// The plate's Hardness macro for `striker`: name, tooltip, targets.
fn plate_hardness(striker: Striker) -> (&'static str, &'static str, Vec<Target>) {
    use ParamId::*;
    match striker {
        Striker::Pulse => (
            "Hardness",
            "strike duration 30 ms → 0.5 ms (log): a shorter strike is a harder mallet",
            vec![log(StrikeDuration, 0.03, 0.0005)],
        ),
        Striker::CustomMallet => (
            "Hardness",
            "mallet hardness 0 → 100 %: soft felt (K = 1e6, α = 2.5) to a hard Hertz contact (K = 1e9, α = 1.5)",
            vec![lin(MalletHardness, 0.0, 1.0)],
        ),
        // The factory heads after `custom`, in the order of MALLET_HEAD_NAMES: soft felt,
        // hard felt, rubber, wood, metal (each harder and brighter than the one before).
        Striker::FactoryMallet => (
            "Hardness",
            "mallet head soft felt → hard felt → rubber → wood → metal",
            vec![lin(MalletHead, 1.0, 5.0)],
        ),
    }
}

/// The macros' names, tooltips and targets for `model` (a plate struck by `striker`).
pub fn macros(
    model: ModelKind,
    striker: Striker,
) -> [(&'static str, &'static str, Vec<Target>); 4] {
    use ParamId::*;
    if model.is_drone() {
        return drone_macros();
    }
    if model.is_sitar_taraf() {
        return sitar_macros();
    }
    let string = model.is_string();
    let size = Size.info();
    [
        if string {
            (
                "Hardness",
                "pluck position 50 % → 5 % of the length: a pluck near the end is sharper",
                vec![lin(PluckPosition, 0.5, 0.05)],
            )
        } else {
            plate_hardness(striker)
        },
        if string {
            (
                "Brightness",
                "both pickups 50 % → 3 % of the length (rebuilds the voices)",
                vec![
                    lin(PickupLeftPos, 0.5, 0.03),
                    lin(PickupRightPos, 0.5, 0.04),
                ],
            )
        } else {
            (
                "Brightness",
                "strike position and both pickups 30 % → 95 % of the radius: towards the edge more high modes sound (rebuilds the voices)",
                vec![
                    lin(StrikeRadius, 0.3, 0.95),
                    lin(PickupLeftPos, 0.3, 0.95),
                    lin(PickupRightPos, 0.25, 0.9),
                ],
            )
        },
        (
            "Decay",
            "damping scale 8 → 0.05 and release T60 0.2 s → 20 s (both log)",
            vec![log(DampingScale, 8.0, 0.05), log(ReleaseT60, 0.2, 20.0)],
        ),
        (
            "Size",
            "size over its whole range (log): plates rescale, strings get a new length",
            vec![log(Size, size.min, size.max)],
        ),
    ]
}

/// The drone's macros: the jivari's buzz, the cycle's pace, the decay and the hand's looseness.
fn drone_macros() -> [(&'static str, &'static str, Vec<Target>); 4] {
    use ParamId::*;
    [
        (
            "Buzz",
            "jivari 12 mm → 3.5 mm from the bridge's edge: the string grazes nearer the edge and buzzes brighter (rebuilds the drone; a new position is tuned by ear once, then kept)",
            vec![lin(Jivari, 12.0, 3.5)],
        ),
        (
            "Pace",
            "cycle period 8 s → 2 s (log), from the next cycle",
            vec![log(DroneCycle, 8.0, 2.0)],
        ),
        (
            "Decay",
            "damping scale 8 → 0.05 and release T60 0.2 s → 20 s (both log)",
            vec![log(DampingScale, 8.0, 0.05), log(ReleaseT60, 0.2, 20.0)],
        ),
        (
            "Looseness",
            "human variation 0 → 1: the player's hand moves the plucks by up to 20 ms and their strength by up to 20 %",
            vec![lin(DroneVariation, 0.0, 1.0)],
        ),
    ]
}

/// The sitar's macros: the mizrab's strength, the chikari stroke, the decay and the taraf's
/// thaat.
fn sitar_macros() -> [(&'static str, &'static str, Vec<Target>); 4] {
    use ParamId::*;
    [
        (
            "Strength",
            "pluck amplitude 0.3 mm → 3 mm (log): a harder mizrab stroke buzzes more on the jawari",
            vec![log(PluckAmplitude, 0.3e-3, 3e-3)],
        ),
        (
            "Chikari",
            "chikari stroke 0 → 100 %: each note strokes the high drone strings too",
            vec![lin(ChikariStroke, 0.0, 1.0)],
        ),
        (
            "Decay",
            "damping scale 8 → 0.05 and release T60 0.2 s → 20 s (both log)",
            vec![log(DampingScale, 8.0, 0.05), log(ReleaseT60, 0.2, 20.0)],
        ),
        (
            "Thaat",
            "the taraf's thaat, Bilawal → Todi (rebuilds the sitar; each thaat is tuned by ear once, then kept)",
            vec![lin(SitarThaat, 0.0, 9.0)],
        ),
    ]
}

/// Draws the macro sliders in a row, `width` points for each.
pub fn macro_row(ui: &mut Ui, params: &NoetherParams, setter: &ParamSetter, width: f32) {
    let model = ModelKind::from_index(params.slot(ParamId::Model).value() as usize);
    let striker = Striker::from_values(
        params.slot(ParamId::Exciter).value(),
        params.slot(ParamId::MalletHead).value(),
    );
    ui.spacing_mut().slider_width = width;
    for (name, help, targets) in macros(model, striker) {
        let first = targets[0];
        let mut t = first.position(params.slot(first.id).value());
        ui.label(egui::RichText::new(name).strong())
            .on_hover_text(help);
        let r = ui
            .add(egui::Slider::new(&mut t, 0.0..=1.0).show_value(false))
            .on_hover_text(format!("{name}: {help}"));
        let values: Vec<(&crate::params::Slot, f32)> = targets
            .iter()
            .map(|g| (params.slot(g.id), g.value(t)))
            .collect();
        apply_gesture(ui, &r, setter, &values);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every target stays inside its parameter's range at both ends and reads back its
    /// position (within 1e-4: f32 logarithms).
    const STRIKERS: [Striker; 3] = [
        Striker::Pulse,
        Striker::CustomMallet,
        Striker::FactoryMallet,
    ];

    /// Every target stays inside its parameter's range at both ends and reads back its
    /// position (within 1e-4: f32 logarithms; the head, an integer, at its own positions).
    #[test]
    fn targets_round_trip_inside_the_ranges() {
        for model in ModelKind::ALL {
            for striker in STRIKERS {
                for (name, _, targets) in macros(model, striker) {
                    for g in targets {
                        let info = g.id.info();
                        for t in [0.0, 0.25, 1.0] {
                            let v = g.value(t);
                            assert!(v >= info.min && v <= info.max, "{name} {}", info.key);
                            assert!((g.position(v) - t).abs() < 1e-4, "{name} {}: {t}", info.key);
                        }
                    }
                }
            }
        }
        // Harder is shorter: the pulse's hardness macro at 1 gives 0.5 ms.
        let hard = &macros(ModelKind::Gong, Striker::Pulse)[0].2[0];
        assert!((hard.value(1.0) - 5e-4).abs() < 1e-7);
    }

    /// The Hardness macro moves the one parameter the exciter in use reads (the engine's
    /// pulse reads the strike duration, the custom mallet its hardness, a factory mallet its
    /// head), over that parameter's soft-to-hard direction.
    #[test]
    fn hardness_moves_what_the_exciter_reads() {
        use ParamId::*;
        let cases = [
            (0.0, 0.0, Striker::Pulse, StrikeDuration),
            (0.0, 3.0, Striker::Pulse, StrikeDuration),
            (1.0, 0.0, Striker::CustomMallet, MalletHardness),
            (1.0, 4.0, Striker::FactoryMallet, MalletHead),
        ];
        for (exciter, head, striker, id) in cases {
            assert_eq!(Striker::from_values(exciter, head), striker);
            let (name, _, targets) = &macros(ModelKind::Gong, striker)[0];
            assert_eq!(*name, "Hardness");
            assert_eq!(targets.len(), 1);
            assert_eq!(targets[0].id, id);
        }
        // Soft to hard: a shorter pulse, a harder felt, a later head (metal last).
        let at = |s: Striker, t: f32| macros(ModelKind::Gong, s)[0].2[0].value(t);
        assert!(at(Striker::Pulse, 1.0) < at(Striker::Pulse, 0.0));
        assert_eq!(
            (
                at(Striker::CustomMallet, 0.0),
                at(Striker::CustomMallet, 1.0)
            ),
            (0.0, 1.0)
        );
        let heads = noether_core::engine::MALLET_HEAD_NAMES;
        assert_eq!(heads[at(Striker::FactoryMallet, 0.0) as usize], "soft-felt");
        assert_eq!(heads[at(Striker::FactoryMallet, 1.0) as usize], "metal");
        // The strings' Hardness is the pluck position whatever the plate exciter says.
        for striker in STRIKERS {
            assert_eq!(macros(ModelKind::Sitar, striker)[0].2[0].id, PluckPosition);
        }
    }

    /// Every macro of every instrument (each model with each exciter and mallet head) moves
    /// only parameters that instrument reads (the table's `reads` column, which
    /// tests/engine/param_meta.rs holds to the sound): no macro is silent for an exciter, as
    /// the Hardness macro was for the mallet when it moved the pulse's duration.
    #[test]
    fn every_macro_moves_what_the_instrument_reads() {
        use noether_core::engine::{ModelKind, ParamValues};
        for model in ModelKind::ALL {
            for (exciter, head) in [(0.0, 0.0), (1.0, 0.0), (1.0, 3.0)] {
                let mut v = ParamValues::defaults();
                v.set(ParamId::Model, model as usize as f32).unwrap();
                v.set(ParamId::Exciter, exciter).unwrap();
                v.set(ParamId::MalletHead, head).unwrap();
                let striker = Striker::from_values(exciter, head);
                for (name, _, targets) in macros(model, striker) {
                    for g in targets {
                        assert!(
                            v.reads(g.id),
                            "{name} moves {} on a {} with exciter {exciter}, head {head}, \
                             which does not read it",
                            g.id.info().key,
                            model.key()
                        );
                    }
                }
            }
        }
    }
}
