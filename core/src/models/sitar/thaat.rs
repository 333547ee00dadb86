//! The ten thaats (parent scales) of Hindustani music (Bhatkhande's classification) in just
//! intonation, and the taraf's tuning from them.
//!
//! Degrees: Sa 1, komal Re 16/15, Re 9/8, komal Ga 6/5, Ga 5/4, Ma 4/3, tivra Ma 45/32, Pa 3/2,
//! komal Dha 8/5, Dha 5/3, komal Ni 16/9, Ni 15/8. The taraf strings sound the thaat's seven
//! notes upwards from Sa and go on into the next octave.
//!
//! Plain data, control thread.

use serde::{Deserialize, Serialize};

/// A thaat.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Thaat {
    /// S R G M P D N (the major scale).
    #[default]
    Bilawal,
    /// S R G M# P D N.
    Kalyan,
    /// S R G M P D n.
    Khamaj,
    /// S R g M P D n.
    Kafi,
    /// S R g M P d n.
    Asavari,
    /// S r g M P d n.
    Bhairavi,
    /// S r G M P d N.
    Bhairav,
    /// S r G M# P d N.
    Purvi,
    /// S r G M# P D N.
    Marwa,
    /// S r g M# P d N.
    Todi,
}

/// Komal Re, Re, komal Ga, Ga, Ma, tivra Ma, Pa, komal Dha, Dha, komal Ni, Ni.
const R_K: f64 = 16.0 / 15.0;
const R: f64 = 9.0 / 8.0;
const G_K: f64 = 6.0 / 5.0;
const G: f64 = 5.0 / 4.0;
const M: f64 = 4.0 / 3.0;
const M_T: f64 = 45.0 / 32.0;
const P: f64 = 3.0 / 2.0;
const D_K: f64 = 8.0 / 5.0;
const D: f64 = 5.0 / 3.0;
const N_K: f64 = 16.0 / 9.0;
const N: f64 = 15.0 / 8.0;

impl Thaat {
    /// Every thaat, in the order of their names ([`Self::KEYS`]).
    pub const ALL: [Thaat; 10] = [
        Thaat::Bilawal,
        Thaat::Kalyan,
        Thaat::Khamaj,
        Thaat::Kafi,
        Thaat::Asavari,
        Thaat::Bhairavi,
        Thaat::Bhairav,
        Thaat::Purvi,
        Thaat::Marwa,
        Thaat::Todi,
    ];

    /// The thaats' names as scenes write them, in [`Self::ALL`]'s order.
    pub const KEYS: [&'static str; 10] = [
        "bilawal", "kalyan", "khamaj", "kafi", "asavari", "bhairavi", "bhairav", "purvi", "marwa",
        "todi",
    ];

    /// The seven degrees over Sa, ascending.
    pub fn degrees(self) -> [f64; 7] {
        match self {
            Thaat::Bilawal => [1.0, R, G, M, P, D, N],
            Thaat::Kalyan => [1.0, R, G, M_T, P, D, N],
            Thaat::Khamaj => [1.0, R, G, M, P, D, N_K],
            Thaat::Kafi => [1.0, R, G_K, M, P, D, N_K],
            Thaat::Asavari => [1.0, R, G_K, M, P, D_K, N_K],
            Thaat::Bhairavi => [1.0, R_K, G_K, M, P, D_K, N_K],
            Thaat::Bhairav => [1.0, R_K, G, M, P, D_K, N],
            Thaat::Purvi => [1.0, R_K, G, M_T, P, D_K, N],
            Thaat::Marwa => [1.0, R_K, G, M_T, P, D, N],
            Thaat::Todi => [1.0, R_K, G_K, M_T, P, D_K, N],
        }
    }

    /// The ratios over Sa of `count` taraf strings: the degrees upwards from Sa, then an
    /// octave up.
    pub fn taraf(self, count: usize) -> Vec<f64> {
        let d = self.degrees();
        (0..count)
            .map(|i| d[i % 7] * 2f64.powi((i / 7) as i32))
            .collect()
    }
}
