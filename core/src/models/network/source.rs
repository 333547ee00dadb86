//! [`StringNetwork`] as a [`RenderSource`] for the offline renderer and the harness.

use super::StringNetwork;
use crate::models::source::{EnergyTerms, RenderSource};

impl RenderSource for StringNetwork {
    fn sim_rate(&self) -> f64 {
        1.0 / self.h()
    }

    fn channels(&self) -> usize {
        self.output_count()
    }

    fn process(&mut self, out: &mut [Vec<f64>], frames: usize) {
        for n in 0..frames {
            self.step();
            for (c, o) in out.iter_mut().enumerate().take(self.output_count()) {
                o[n] = self.output(c);
            }
        }
    }

    fn energy(&self) -> EnergyTerms {
        self.energy_terms()
    }

    fn is_conservative(&self) -> bool {
        true
    }
}
