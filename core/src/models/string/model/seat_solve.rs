//! The seat of a string on a moving bridge, and the string's side of the network's coupled
//! solve ([`crate::models::network`]).
//!
//! A seated string is tied at one grid node `t` to the bridge under it by a linear spring
//! `V = (K/2) w²`, `w = u_t - y` (`y` the bridge's displacement there, the *lift*), and its
//! obstacle moves with the bridge: `η_i = g_i + y - u_i`. Both forces are discrete gradients
//! between `n+1` and `n-1`:
//! - seat: `P^n = -(K/2)(w^{n+1} + w^{n-1})` (N, on the string; `-P` on the bridge), so
//!   `P δ_t. w = -δ_{t-}[(K/4)(w^{n+1}² + w^n²)]` exactly;
//! - obstacle: `f_i^n = (ψ(η_i^{n+1}) - ψ(η_i^{n-1}))/(η_i^{n+1} - η_i^{n-1})` as on a fixed
//!   bridge, with `δ_t. η_i = δ_t. y - δ_t. u_i`, so `Δx Σ f_i (δ_t. u_i - δ_t. y) = -δ_t. Σ ψ`.
//!
//! Given the bridge's `y^{n+1}` every node's force still follows from one scalar equation
//! (`u_t^{n+1} = u_free_t + (k/Δx) P`, the grid identity of the module doc of
//! [`crate::models::string`]): the seat's in closed form,
//! `P = -(K/2)(u_free_t - y^{n+1} + w^{n-1}) / (1 + K k/(2Δx))`, the obstacle's by the same
//! safeguarded Newton solve. [`StiffString::coupling_response`] returns the string's total
//! force and its derivative in `y^{n+1}` (both ≥ 0 in the derivative: the string pushes
//! harder on a bridge that comes up), which the network's Newton iteration on `y^{n+1}` needs.
//!
//! Audio thread: no allocation, bounded work (the contact solve's cap per node).

use super::StiffString;
use crate::models::string::contact::solve_point;
use crate::models::string::seat::Seat;

impl StiffString {
    /// The seat's point force `P` (N, on the string) for a bridge at `lift_next` (m), and
    /// `dP/dlift_next` (N/m, ≥ 0); during a step, after [`Self::free_step`].
    fn seat_force(&self, seat: &Seat, lift_next: f64) -> (f64, f64) {
        let t = seat.node;
        let w_prev = self.u_prev[t] - self.lift_prev;
        let half_k = 0.5 * seat.stiffness;
        let denom = 1.0 + half_k * self.k / self.params.dx();
        let p = -half_k * (self.u_next[t] - lift_next + w_prev) / denom;
        (p, half_k / denom)
    }

    /// The string's total force on itself from the bridge, `F = Δx Σ_i f_i + P` (N; the
    /// bridge receives `-F`), for a bridge at `lift_next` (m) in the step under way, and
    /// `dF/dlift_next` (N/m, ≥ 0). Changes nothing: the network evaluates it for each trial
    /// bridge position, then commits with [`Self::solve_contacts`]. Audio thread, bounded
    /// work (the Newton cap per obstacle node).
    pub(crate) fn coupling_response(&self, lift_next: f64) -> (f64, f64) {
        if let Some(response) = self.band_limited_response(lift_next) {
            return response;
        }
        let (k, dx) = (self.k, self.params.dx());
        let (mut force, mut slope) = (0.0, 0.0);
        for (n, &i) in self.contact_nodes.iter().enumerate() {
            let g = self.contact_g[n];
            let eta_prev = (g + self.lift_prev) - self.u_prev[i];
            let b = ((g + lift_next) - self.u_next[i]) - eta_prev;
            let sol = solve_point(&self.law, eta_prev, b, k);
            if sol.force != 0.0 {
                force += dx * sol.force;
                let s = self
                    .law
                    .divided_difference_slope(eta_prev, sol.r, sol.force);
                slope += dx * s / (1.0 + k * s);
            }
        }
        if let Some(seat) = &self.seat {
            let (p, dp) = self.seat_force(seat, lift_next);
            force += p;
            slope += dp;
        }
        (force, slope)
    }

    /// The seat's part of step 3 for a bridge at `lift_next`: its force into `u_next` and
    /// the seat. Returns the force density `P/Δx` (N/m), 0 without a seat.
    pub(super) fn solve_seat(&mut self, lift_next: f64) -> f64 {
        let Some(seat) = self.seat else {
            return 0.0;
        };
        let (p, _) = self.seat_force(&seat, lift_next);
        let f = p / self.params.dx();
        self.u_next[seat.node] += self.k * f;
        if let Some(s) = &mut self.seat {
            s.force = f;
        }
        f
    }

    /// The seat spring's energy `(K/4)(w^{n+1}² + w^n²)` at the current state (J; 0 without
    /// a seat). O(1).
    pub fn seat_energy(&self) -> f64 {
        match &self.seat {
            Some(seat) => {
                let t = seat.node;
                let w_now = self.u_now[t] - self.lift_now;
                let w_prev = self.u_prev[t] - self.lift_prev;
                0.25 * seat.stiffness * (w_now * w_now + w_prev * w_prev)
            }
            None => 0.0,
        }
    }

    /// The bridge's displacement under the string at `n+1` (m; 0 on a fixed bridge).
    pub fn lift(&self) -> f64 {
        self.lift_now
    }

    /// The seat's point force on the string at the last step (N; 0 without a seat).
    pub fn seat_force_last(&self) -> f64 {
        self.seat.map_or(0.0, |s| s.force * self.params.dx())
    }
}
