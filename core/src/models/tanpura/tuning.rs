//! The tanpura's tunings and its strings: which note each string sounds, relative to Sa, and
//! what it is made of.
//!
//! The four-string tanpura is tuned, from the player's side, to the tuning note of the lower
//! octave, two Sa of the middle octave, and Sa of the lower octave (the kharaj). The tuning
//! note is Pa (3/2 below the octave: 3/4 of Sa), Ma (4/3: 2/3 of Sa), Ni (15/8: 15/16 of Sa) or
//! Sa (1/2), in just intonation. Five strings add a third middle Sa, six also a second
//! kharaj. The low strings (the tuning note when it is Pa or Ma, and the kharaj) are bronze,
//! the others steel (Deva, *Indian Music*, 1974; van Walstijn et al., DAFx-16, for the
//! dimensions' order of magnitude).
//!
//! Plain data, control thread.

use serde::{Deserialize, Serialize};

/// The first string's note.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Tuning {
    /// Pa-Sa-Sa-Sa: the fifth (3/4 of Sa, the lower octave's Pa).
    #[default]
    Pa,
    /// Ma-Sa-Sa-Sa: the fourth (2/3 of Sa).
    Ma,
    /// Ni-Sa-Sa-Sa: the major seventh (15/16 of Sa).
    Ni,
    /// Sa-Sa-Sa-Sa: the lower octave's Sa (1/2).
    Sa,
}

impl Tuning {
    /// The first string's frequency over Sa's (just intonation).
    pub fn ratio(self) -> f64 {
        match self {
            Tuning::Pa => 3.0 / 4.0,
            Tuning::Ma => 2.0 / 3.0,
            Tuning::Ni => 15.0 / 16.0,
            Tuning::Sa => 0.5,
        }
    }

    /// Every tuning, for tables and tests.
    pub const ALL: [Tuning; 4] = [Tuning::Pa, Tuning::Ma, Tuning::Ni, Tuning::Sa];
}

/// A string's material.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Metal {
    /// Steel: density 7850 kg/m³, Young's modulus 200 GPa, 0.30 mm.
    Steel,
    /// Phosphor bronze: density 8800 kg/m³, Young's modulus 110 GPa, 0.40 mm (0.50 mm for a
    /// kharaj).
    Bronze,
}

impl Metal {
    /// Density in kg/m³.
    pub fn density(self) -> f64 {
        match self {
            Metal::Steel => 7850.0,
            Metal::Bronze => 8800.0,
        }
    }

    /// Young's modulus in Pa.
    pub fn young(self) -> f64 {
        match self {
            Metal::Steel => 200e9,
            Metal::Bronze => 110e9,
        }
    }

    /// Linear density `ρπd²/4` (kg/m) of a round wire of diameter `d` (m).
    pub fn linear_density(self, d: f64) -> f64 {
        self.density() * std::f64::consts::PI * d * d / 4.0
    }

    /// Bending stiffness `E π d⁴/64` (N·m²) of a round wire of diameter `d` (m).
    pub fn bending_stiffness(self, d: f64) -> f64 {
        self.young() * std::f64::consts::PI * d.powi(4) / 64.0
    }
}

/// One string of the tanpura: its note and its metal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TanpuraString {
    /// Frequency over Sa's.
    pub ratio: f64,
    /// Material.
    pub metal: Metal,
    /// Diameter in m.
    pub diameter: f64,
}

impl TanpuraString {
    /// The string sounding `ratio` times Sa: bronze at or below 3/4, steel above.
    fn new(ratio: f64) -> Self {
        let (metal, diameter) = if ratio > 0.75 {
            (Metal::Steel, 0.30e-3)
        } else if ratio > 0.5 {
            (Metal::Bronze, 0.40e-3)
        } else {
            (Metal::Bronze, 0.50e-3)
        };
        Self {
            ratio,
            metal,
            diameter,
        }
    }

    /// Density in kg/m³.
    pub fn density(&self) -> f64 {
        self.metal.density()
    }

    /// Young's modulus in Pa.
    pub fn young(&self) -> f64 {
        self.metal.young()
    }

    /// Linear density `ρπd²/4` in kg/m.
    pub fn linear_density(&self) -> f64 {
        self.metal.linear_density(self.diameter)
    }

    /// Bending stiffness `E π d⁴/64` in N·m².
    pub fn bending_stiffness(&self) -> f64 {
        self.metal.bending_stiffness(self.diameter)
    }
}

/// The strings of a tanpura of `count` strings (4 to 6) in `tuning`, in plucking order.
pub fn strings(tuning: Tuning, count: usize) -> Vec<TanpuraString> {
    let mut ratios = vec![tuning.ratio(), 1.0, 1.0];
    if count >= 5 {
        ratios.push(1.0);
    }
    ratios.push(0.5);
    if count >= 6 {
        ratios.push(0.5);
    }
    ratios.into_iter().map(TanpuraString::new).collect()
}
