//! The player's hand on [`StiffString`]: placement and the closed-form solve with the step
//! (equations in [`crate::models::string::hand_damper`]).

use super::StiffString;
use crate::error::{check_non_negative, ParamError};

impl StiffString {
    /// Puts the hand at the grid node nearest to `position` (m from the `x = 0` end) with
    /// damper coefficient `c` (N·s/m, finite, ≥ 0; 0 lifts the hand). Errors (nothing changes):
    /// `hand_position` when the nearest node is an end or an obstacle node (the hand must sit
    /// off the bridge), or not finite; `hand_damping` for `c`. O(N), no allocation: callable
    /// from the audio thread.
    pub fn set_hand(&mut self, position: f64, c: f64) -> Result<(), ParamError> {
        let (l, n) = (self.params.length, self.params.intervals);
        let node = (position / self.params.dx()).round();
        let allowed =
            || format!("a position in (0, {l}) m whose nearest grid node is off the obstacle");
        if !(node >= 1.0 && node <= (n - 1) as f64) {
            return Err(ParamError::new("hand_position", position, allowed()));
        }
        let node = node as usize;
        if self.contact_nodes.contains(&(node - 1)) {
            return Err(ParamError::new("hand_position", position, allowed()));
        }
        check_non_negative("hand_damping", c)?;
        let x = node as f64 * self.params.dx();
        let mut sq = 0.0;
        for (j, s) in self.hand.shape.iter_mut().enumerate() {
            *s = self.params.mode_shape(j + 1, x);
            sq += *s * *s;
        }
        self.hand.shape_sq = sq;
        if let Some(m) = self.band_stepped() {
            self.hand.shape[m..].fill(0.0);
            self.hand.shape_sq = self.hand.shape.iter().map(|s| s * s).sum();
        }
        self.hand.node = node;
        self.set_hand_damping(c)
    }

    /// Sets the hand's damper coefficient `c` (N·s/m, finite, ≥ 0; 0 lifts the hand) at the
    /// current hand node (a hand never placed with [`Self::set_hand`] has no shape and does
    /// nothing). Errors name `hand_damping`. O(1), no allocation; audio thread.
    pub fn set_hand_damping(&mut self, c: f64) -> Result<(), ParamError> {
        self.hand.c = check_non_negative("hand_damping", c)?;
        if c == 0.0 {
            self.hand.force = 0.0;
        }
        Ok(())
    }

    /// The hand's position (m, its grid node; 0 before [`Self::set_hand`]).
    pub fn hand_position(&self) -> f64 {
        self.hand.node as f64 * self.params.dx()
    }

    /// The hand's damper coefficient `c` (N·s/m).
    pub fn hand_damping(&self) -> f64 {
        self.hand.c
    }

    /// The hand force `F_h` of the last step (N).
    pub fn hand_force(&self) -> f64 {
        self.hand.force
    }

    /// Energy taken by the hand since the initial condition (J, ≥ 0; included in
    /// [`crate::models::source::EnergyTerms::dissipated`]).
    pub fn hand_dissipated(&self) -> f64 {
        self.hand.dissipated
    }

    /// Step 1b (hand on): `F_h` in closed form from the free increment in `dq_next`, added to
    /// `dq_next` and to the synthesis input `w` (module docs). O(N), no allocation.
    pub(super) fn apply_hand(&mut self, rows_path: bool) {
        let w = if rows_path {
            &mut self.w_buf
        } else {
            &mut self.u_next
        };
        let (mut w_star, mut w_prev) = (0.0, 0.0);
        for (((&s, &q), &d), &dn) in self
            .hand
            .shape
            .iter()
            .zip(&self.q)
            .zip(&self.dq)
            .zip(&self.dq_next)
        {
            w_star += s * (q + dn);
            w_prev += s * (q - d);
        }
        let gamma = self.hand.c / (2.0 * self.h);
        let force = -gamma * (w_star - w_prev) / (1.0 + gamma * self.k * self.hand.shape_sq);
        let kf = self.k * force;
        for ((dn, w), &s) in self
            .dq_next
            .iter_mut()
            .zip(w.iter_mut())
            .zip(&self.hand.shape)
        {
            *dn += kf * s;
            *w += kf * s;
        }
        self.hand.force = force;
    }

    /// The hand's share of the step's power (hand on, before the rotation): adds
    /// `-h F_h δ_{t.}w_h = -F_h Σ_j φ_j (Δ_j^{n+1} + Δ_j^n)/2` (J) to the dissipated energy.
    pub(super) fn hand_power(&mut self) {
        let v: f64 = self
            .hand
            .shape
            .iter()
            .zip(&self.dq_next)
            .zip(&self.dq)
            .map(|((s, dn), d)| s * (dn + d))
            .sum();
        let e = -0.5 * self.hand.force * v;
        self.dissipated += e;
        self.hand.dissipated += e;
    }
}
