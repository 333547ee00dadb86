//! In-place retuning of a built [`StiffString`]: new tension, bending stiffness and losses on
//! the same grid (length, density, obstacle and outputs unchanged), without allocating, so the
//! engine can tune a voice to a note on the audio thread.
//!
//! The coefficients are those of [`StiffString::new`] (same formulas, [`super::super::exact`]).

use super::StiffString;
use crate::models::string::exact::ModeCoefficients;
use crate::models::string::losses::ValetteLosses;
use crate::models::string::params::Stiffness;

impl StiffString {
    /// Sets tension `T` (N) and stiffness, and the losses `σ_j = max(scale · σ_Valette(f_j),
    /// min(floor, ω_j))` (`losses = None`: `σ_j = floor`), then recomputes every per-mode coefficient.
    /// `scale ≥ 0` multiplies the Issanchou/Valette model; `floor` (1/s, ≥ 0) is a minimum
    /// decay rate (the engine's release).
    ///
    /// Checks run first: on `Err` (a non-finite or out-of-range value, message naming it) the
    /// model is unchanged. The state is kept; the discrete energy changes with the
    /// coefficients, and the change is booked as work (the peg's, or the player's pull on the
    /// string), so the power balance closes across a retune. Audio thread: no allocation on
    /// success, O(N) transcendental evaluations.
    pub fn retune(
        &mut self,
        tension: f64,
        stiffness: Stiffness,
        losses: Option<&ValetteLosses>,
        scale: f64,
        floor: f64,
    ) -> Result<(), &'static str> {
        if !(tension.is_finite() && tension > 0.0) {
            return Err("tension must be finite and > 0");
        }
        let s = match stiffness {
            Stiffness::BendingStiffness(x) | Stiffness::Inharmonicity(x) => x,
        };
        if !(s.is_finite() && s >= 0.0) {
            return Err("stiffness must be finite and >= 0");
        }
        if !(scale.is_finite() && scale >= 0.0 && floor.is_finite() && floor >= 0.0) {
            return Err("loss scale and floor must be finite and >= 0");
        }
        if let Some(v) = losses {
            if v.validate().is_err() {
                return Err("loss coefficients must be finite and >= 0");
            }
        }
        let before = self.energy_terms().total();
        self.params.tension = tension;
        self.params.stiffness = stiffness;
        let (h, mu) = (self.h, self.params.linear_density);
        let h2 = h * h;
        let mut lossy = false;
        for j in 0..self.q.len() {
            let omega = self.params.omega(j + 1);
            let base = match losses {
                Some(v) => scale * v.sigma(&self.params, omega / std::f64::consts::TAU),
                None => 0.0,
            };
            // The floor is capped at critical damping (σ = ω), the fastest decay of a mode.
            let sigma = base.max(floor.min(omega));
            lossy |= sigma > 0.0;
            let c = ModeCoefficients::new(omega, sigma, h);
            self.sigma[j] = sigma;
            self.w_kin[j] = mu * (2.0 + 2.0 * c.c_tilde - c.beta) / (8.0 * h2);
            self.w_pot[j] = mu * c.beta / (8.0 * h2);
            self.w_diss[j] = mu * c.s / (2.0 * h);
            self.c_tilde[j] = c.c_tilde;
            self.beta[j] = c.beta;
            self.coeffs[j] = c;
        }
        self.lossy = lossy;
        // The stepped modes follow the band limit at the new tension.
        self.apply_band_limit();
        self.work += self.energy_terms().total() - before;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::models::string::params::Stiffness;
    use crate::models::string::{
        ContactLaw, Losses, Obstacle, OutputChannel, Quantity, Readout, StiffString, StringConfig,
        StringParams, TrianglePluck, ValetteLosses,
    };

    fn config(tension: f64, b: f64) -> StringConfig {
        let mut params = StringParams::lecture_guitar(64, 96_000.0);
        params.tension = tension;
        params.stiffness = Stiffness::Inharmonicity(b);
        StringConfig {
            params,
            losses: Losses::Valette(ValetteLosses::default()),
            obstacle: Obstacle::tanpura(),
            contact: ContactLaw::lecture(),
            outputs: vec![OutputChannel::Pickup {
                position: 0.3,
                quantity: Quantity::Velocity,
                readout: Readout::Grid,
            }],
        }
    }

    /// A string retuned to (T, B) steps exactly like one built with (T, B).
    #[test]
    fn retune_equals_rebuild() {
        let mut built = StiffString::new(&config(300.0, 1e-5)).unwrap();
        let mut tuned = StiffString::new(&config(180.5, 2e-5)).unwrap();
        tuned
            .retune(
                300.0,
                Stiffness::Inharmonicity(1e-5),
                Some(&ValetteLosses::default()),
                1.0,
                0.0,
            )
            .unwrap();
        let pluck = TrianglePluck {
            position: 0.2,
            amplitude: 1e-3,
        };
        built.pluck(&pluck).unwrap();
        tuned.pluck(&pluck).unwrap();
        for _ in 0..500 {
            built.step();
            tuned.step();
        }
        assert_eq!(built.modal_displacement(), tuned.modal_displacement());
        assert_eq!(built.sigmas(), tuned.sigmas());
    }

    /// A string retuned while it rings books the change of its discrete energy as work: the
    /// power balance closes across the retune to round-off (1e-12 of the energy; the tension
    /// rises by 39 % in steps and the energy with it, so an unbooked retune fails by far).
    #[test]
    fn retune_keeps_the_power_balance() {
        let mut s = StiffString::new(&config(180.5, 2e-5)).unwrap();
        s.pluck(&TrianglePluck {
            position: 0.2,
            amplitude: 1e-3,
        })
        .unwrap();
        let b0 = s.energy_terms().balance();
        let mut e_max = 0.0f64;
        for k in 0..40 {
            for _ in 0..100 {
                s.step();
                e_max = e_max.max(s.energy_terms().total());
            }
            let t = 180.5 * (1.0 + 0.01 * k as f64);
            s.retune(
                t,
                Stiffness::Inharmonicity(2e-5),
                Some(&ValetteLosses::default()),
                1.0,
                0.0,
            )
            .unwrap();
        }
        let e = s.energy_terms();
        assert!(e.work.abs() > 0.05 * e_max, "work {:e}", e.work);
        assert!(
            (e.balance() - b0).abs() < 1e-12 * e_max,
            "balance {:e} of {e_max:e}",
            (e.balance() - b0).abs()
        );
    }

    #[test]
    fn retune_refuses_bad_values() {
        let mut s = StiffString::new(&config(180.5, 2e-5)).unwrap();
        assert!(s
            .retune(-1.0, Stiffness::Inharmonicity(0.0), None, 1.0, 0.0)
            .is_err());
        assert_eq!(s.params().tension, 180.5);
    }
}
