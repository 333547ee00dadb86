//! The per-node contact solve of [`StiffString::step`] under either [`ContactScheme`], the
//! quadratised scheme's auxiliary variable and its energy.
//!
//! Both schemes share everything but the scalar solve at each obstacle node (module docs of
//! [`crate::models::string`], [`crate::models::string::contact`] and
//! [`crate::models::string::contact_sav`]).

use super::StiffString;
use crate::models::sav_relaxation::{relax, SavRelaxation};
use crate::models::string::contact::solve_point;
use crate::models::string::contact_sav::{solve_point_quadratised, ContactScheme};

impl StiffString {
    /// Selects the contact scheme. The quadratised auxiliary variable is re-initialised from
    /// the current state (`z = √(ψ(η^{n+1}) + ψ(η^n))`), so both schemes' energies agree at the
    /// switch. O(obstacle nodes), no allocation: callable from the audio thread.
    ///
    /// Returns the scheme in use: a band-limited string ([`Self::set_band_limit`]) stays on
    /// the Newton scheme, which its coupled point solve uses.
    pub fn set_contact_scheme(&mut self, scheme: ContactScheme) -> ContactScheme {
        if self.band.is_none() {
            self.scheme = scheme;
            self.init_quadratised();
        }
        self.scheme
    }

    /// Sets how the quadratised scheme's `z_i` of nodes off the obstacle (at both `n` and
    /// `n-1`) are relaxed toward `√(2ψ(η_i)) = 0` before each step
    /// ([`crate::models::sav_relaxation`]; [`SavRelaxation::OFF`]: the plain scheme). No
    /// effect on the Newton scheme. O(1), no allocation.
    pub fn set_sav_relaxation(&mut self, relaxation: SavRelaxation) {
        self.relaxation = relaxation;
    }

    /// The relaxation of the quadratised scheme's `z_i`.
    pub fn sav_relaxation(&self) -> SavRelaxation {
        self.relaxation
    }

    /// Energy removed by the quadratised scheme's relaxation since the initial condition (J;
    /// part of [`crate::models::source::EnergyTerms::dissipated`]; negative where its budget
    /// returned some of the losses; 0 for the Newton scheme).
    pub fn relaxed(&self) -> f64 {
        self.relaxed
    }

    /// `Δx Σ z_i²/2` over the obstacle nodes off the obstacle at `n` and `n-1` (J): the
    /// energy the quadratised scheme still holds at nodes whose contact has ended (0 for the
    /// Newton scheme). Without the relaxation it stays there until the node's next contact.
    /// O(obstacle nodes).
    pub fn released_contact_energy(&self) -> f64 {
        if self.scheme != ContactScheme::Quadratised {
            return 0.0;
        }
        let mut e = 0.0;
        for (n, &i) in self.contact_nodes.iter().enumerate() {
            let g = self.contact_g[n];
            if (g + self.lift_now) - self.u_now[i] <= 0.0
                && (g + self.lift_prev) - self.u_prev[i] <= 0.0
            {
                e += self.contact_z[n] * self.contact_z[n];
            }
        }
        0.5 * self.params.dx() * e
    }

    /// The contact scheme in use.
    pub fn contact_scheme(&self) -> ContactScheme {
        self.scheme
    }

    /// `z_i = √(ψ(η_i^{n+1}) + ψ(η_i^n))` at every obstacle node (see
    /// [`crate::models::string::contact_sav`], "Initial value").
    pub(super) fn init_quadratised(&mut self) {
        for (n, &i) in self.contact_nodes.iter().enumerate() {
            let g = self.contact_g[n];
            let two_psi = self.law.psi((g + self.lift_now) - self.u_now[i])
                + self.law.psi((g + self.lift_prev) - self.u_prev[i]);
            self.contact_z[n] = two_psi.sqrt();
        }
    }

    /// Newton scheme's contact energy `Δx Σ_i (ψ(η_i^{n+1}) + ψ(η_i^n))/2` in J.
    pub(super) fn contact_potential(&self) -> f64 {
        let mut psi = 0.0;
        for (n, &i) in self.contact_nodes.iter().enumerate() {
            let g = self.contact_g[n];
            psi += self.law.psi((g + self.lift_now) - self.u_now[i])
                + self.law.psi((g + self.lift_prev) - self.u_prev[i]);
        }
        0.5 * psi * self.params.dx()
    }

    /// Quadratised scheme's contact energy `Δx Σ_i z_i²/2` in J.
    pub(super) fn quadratised_energy(&self) -> f64 {
        0.5 * self.params.dx() * self.contact_z.iter().map(|z| z * z).sum::<f64>()
    }

    /// `Δx Σ_i (z_i²/2 - (ψ(η_i^{n+1}) + ψ(η_i^n))/2)` in J: how far the quadratised
    /// scheme's contact energy is from the physical potential at the current state (0 for
    /// the Newton scheme, whose `z` is not advanced). Includes the energy left in `z` at nodes
    /// that have left the obstacle (module doc of `contact_sav`). O(obstacle nodes).
    pub fn quadratisation_gap(&self) -> f64 {
        match self.scheme {
            ContactScheme::NewtonDiscreteGradient => 0.0,
            ContactScheme::Quadratised => self.quadratised_energy() - self.contact_potential(),
        }
    }

    /// Step 3 of [`StiffString::step`] with the bridge under the string at `lift_next` (m;
    /// the current lift for a fixed bridge): solves every obstacle node with `u_free` in
    /// `u_next` and `u^{n}`, `u^{n-1}` in `u_now`, `u_prev`, then the seat
    /// ([`super::seat`]); adds `k f_i` to `u_next`, stores `f_i`, updates the counters.
    /// Returns the sum of the force densities (N/m, the seat's included) and the number of
    /// obstacle nodes with a non-zero force. Bounded work: at most `NEWTON_CAP` iterations per node
    /// (Newton) or one division (quadratised).
    pub(crate) fn solve_contacts(&mut self, lift_next: f64) -> (f64, usize) {
        self.lift_next = lift_next;
        if let Some(solved) = self.solve_band_limited(lift_next) {
            return solved;
        }
        let k = self.k;
        let mut total = 0.0;
        let mut active = 0usize;
        // The relaxation's allowance (J), spent node by node in order (module doc of
        // `sav_relaxation`); `dx` the energy scale of `z_i²/2`.
        let relaxing = self.scheme == ContactScheme::Quadratised && self.relaxation.is_on();
        if relaxing {
            self.ledger
                .begin_step(&self.relaxation, self.step_dissipated);
        }
        let dx = self.params.dx();
        for (n, &i) in self.contact_nodes.iter().enumerate() {
            let g = self.contact_g[n];
            let eta_prev = (g + self.lift_prev) - self.u_prev[i];
            let g_next = g + lift_next;
            let b = (g_next - self.u_next[i]) - eta_prev;
            let force = match self.scheme {
                ContactScheme::NewtonDiscreteGradient => {
                    let sol = solve_point(&self.law, eta_prev, b, k);
                    self.stats.histogram[sol.iterations] += 1;
                    self.stats.cap_hits += u64::from(sol.capped);
                    sol.force
                }
                ContactScheme::Quadratised => {
                    let eta_now = (g + self.lift_now) - self.u_now[i];
                    if relaxing && eta_now <= 0.0 && eta_prev <= 0.0 && self.contact_z[n] != 0.0 {
                        // Off the obstacle at n and n-1, `√(2ψ)` is exactly 0 there: `z`
                        // decays to it (in contact it is left to the scheme, whose own `z`
                        // tracks `√(2ψ)` to its consistency error; only the `z` a release
                        // leaves behind is drift).
                        let (z, removed) = relax(
                            &self.relaxation,
                            self.contact_z[n],
                            0.0,
                            dx,
                            &mut self.ledger,
                        );
                        self.contact_z[n] = z;
                        self.relaxed += removed;
                        self.dissipated += removed;
                    }
                    let slope = self.law.quadratised_slope(eta_now);
                    let sol = solve_point_quadratised(slope, self.contact_z[n], b, k);
                    self.contact_z[n] = sol.z;
                    sol.force
                }
            };
            self.contact_f[n] = force;
            if force != 0.0 {
                self.u_next[i] += k * force;
                total += force;
                active += 1;
                let pen = g_next - self.u_next[i];
                if pen > self.stats.max_penetration {
                    self.stats.max_penetration = pen;
                }
            }
        }
        total += self.solve_seat(lift_next);
        (total, active)
    }
}
