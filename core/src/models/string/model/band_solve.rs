//! The band-limited string's step: its limit set and followed, its point contact and seat
//! solved against the stepped modes' compliance (the scheme is in the module doc of
//! [`crate::models::string::band_limit`]).
//!
//! The first [`StiffString::set_band_limit`] allocates the compliance columns (the
//! network's build, control thread); later calls and the solve allocate nothing, and the solve
//! is O(stored rows).

use super::{GridSynthesis, StiffString};
use crate::error::ParamError;
use crate::models::string::band_limit::BandLimit;
use crate::models::string::contact::solve_point;
use crate::models::string::contact_sav::ContactScheme;

/// The band-limited step's two forces and the string's response (module doc).
#[derive(Debug, Clone, Copy)]
struct PointForces {
    /// Obstacle force density `f_a` (N/m).
    contact: f64,
    /// Seat force density `f_t` (N/m).
    seat: f64,
    /// `dF/dλ` (N/m).
    slope: f64,
    /// The contact solve's iterations and whether it hit its cap.
    iterations: usize,
    capped: bool,
}

impl StiffString {
    /// Steps only the modes below `hz` (Hz; `f64::INFINITY` steps them all, as built) and
    /// solves the point contact and the seat against their compliance (module doc). Modes
    /// dropped lose their motion, the change of the discrete energy booked as work. Errors
    /// (nothing changes): `band_limit` not positive or NaN; a string with more than one obstacle
    /// node, with its grid computed by the sine transform, or on the quadratised contact
    /// scheme. The first call allocates two columns of the stored rows' length (control
    /// thread); a later one allocates nothing (audio thread), O(stored rows · N).
    pub fn set_band_limit(&mut self, hz: f64) -> Result<(), ParamError> {
        if hz.is_nan() || hz <= 0.0 {
            return Err(ParamError::new("band_limit", hz, "a frequency > 0 Hz"));
        }
        if self.contact_nodes.len() > 1 {
            return Err(ParamError::new(
                "band_limit",
                hz,
                "a string with at most one obstacle node (a point contact)",
            ));
        }
        let Some(rows) = self
            .rows
            .as_ref()
            .filter(|_| self.synthesis == GridSynthesis::Rows)
        else {
            return Err(ParamError::new(
                "band_limit",
                hz,
                "a string whose grid values come from stored rows",
            ));
        };
        if self.scheme != ContactScheme::NewtonDiscreteGradient {
            return Err(ParamError::new(
                "band_limit",
                hz,
                "a string on the Newton contact scheme",
            ));
        }
        let stored = rows.len();
        let band = self.band.get_or_insert_with(|| BandLimit {
            hz,
            stepped: 0,
            applied: false,
            contact_col: Vec::new(),
            seat_col: Vec::new(),
        });
        band.hz = hz;
        // Sized once (the stored rows never change).
        band.contact_col.resize(stored, 0.0);
        band.seat_col.resize(stored, 0.0);
        let before = self.energy_terms().total();
        self.apply_band_limit();
        self.work += self.energy_terms().total() - before;
        Ok(())
    }

    /// The band limit (Hz; infinite when every mode is stepped).
    pub fn band_limit(&self) -> f64 {
        self.band.as_ref().map_or(f64::INFINITY, |b| b.hz)
    }

    /// The number of modes stepped (all `N - 1` without a band limit).
    pub fn stepped_modes(&self) -> usize {
        self.band.as_ref().map_or(self.q.len(), |b| b.stepped)
    }

    /// Counts the modes below the limit at the current tension, drops the others' motion and
    /// computes the compliances; nothing when the count is the one already applied (the
    /// compliances depend on it alone, and the modes above it are already at rest). No
    /// allocation; after a build, a limit or a retune.
    pub(super) fn apply_band_limit(&mut self) {
        let Some(band) = &mut self.band else {
            return;
        };
        let m = self.params.modes_below(band.hz);
        if m == band.stepped && band.applied {
            return;
        }
        band.stepped = m;
        band.applied = true;
        for v in [
            &mut self.q,
            &mut self.dq,
            &mut self.dq_next,
            &mut self.w_buf,
            &mut self.strike_shape,
        ] {
            v[m..].fill(0.0);
        }
        self.hand.shape[m..].fill(0.0);
        self.hand.shape_sq = self.hand.shape.iter().map(|s| s * s).sum();
        let Some(rows) = &self.rows else {
            return;
        };
        let p = &self.params;
        let dx = p.dx();
        let x_of = |node: usize| (node + 1) as f64 * dx;
        let compliance = |a: f64, b: f64| {
            let s: f64 = (1..=m)
                .map(|j| p.mode_shape(j, a) * p.mode_shape(j, b))
                .sum();
            self.k * dx * s
        };
        let contact = self.contact_nodes.first().map(|&i| x_of(i));
        let seat = self.seat.map(|s| x_of(s.node));
        for (r, &node) in rows.nodes().iter().enumerate() {
            let x = x_of(node);
            band.contact_col[r] = contact.map_or(0.0, |a| compliance(x, a));
            band.seat_col[r] = seat.map_or(0.0, |t| compliance(x, t));
        }
        // The grid values at the stored nodes from the truncated modes.
        if let Some(rows) = &mut self.rows {
            let mut prev = std::mem::take(&mut self.grid_buf);
            for ((w, q), d) in prev.iter_mut().zip(&self.q).zip(&self.dq) {
                *w = q - d;
            }
            rows.synthesize(&prev, &mut self.u_prev);
            rows.synthesize(&self.q, &mut self.u_now);
            self.grid_buf = prev;
        }
    }

    /// The modes stepped when a band limit is set (`None`: all, as built).
    pub(super) fn band_stepped(&self) -> Option<usize> {
        self.band.as_ref().map(|b| b.stepped)
    }

    /// The band-limited step's forces for the bridge at `lift_next` (module doc), from the
    /// free displacements in `u_next`. Changes nothing.
    fn point_forces(&self, band: &BandLimit, lift_next: f64) -> PointForces {
        let dx = self.params.dx();
        // The seat's row follows the obstacle's (`Seat::row`); the obstacle node is row 0.
        let (mut s0, mut sigma, mut c_at) = (0.0, 0.0, 0.0);
        if let Some(seat) = &self.seat {
            let t = seat.node;
            let kappa = 0.5 * seat.stiffness / dx;
            sigma = kappa / (1.0 + kappa * band.seat_col[seat.row]);
            let w_prev = self.u_prev[t] - self.lift_prev;
            s0 = -sigma * (self.u_next[t] - lift_next + w_prev);
            if !self.contact_nodes.is_empty() {
                c_at = band.seat_col[0];
            }
        }
        let mut out = PointForces {
            contact: 0.0,
            seat: s0,
            slope: dx * sigma,
            iterations: 0,
            capped: false,
        };
        if let Some(&i) = self.contact_nodes.first() {
            let g = self.contact_g[0];
            let k_e = band.contact_col[0] - sigma * c_at * c_at;
            let eta_prev = (g + self.lift_prev) - self.u_prev[i];
            let b = ((g + lift_next) - (self.u_next[i] + c_at * s0)) - eta_prev;
            let sol = solve_point(&self.law, eta_prev, b, k_e);
            out.iterations = sol.iterations;
            out.capped = sol.capped;
            if sol.force != 0.0 {
                let phi = self
                    .law
                    .divided_difference_slope(eta_prev, sol.r, sol.force);
                let lever = 1.0 - sigma * c_at;
                out.contact = sol.force;
                out.seat = s0 - sigma * c_at * sol.force;
                out.slope += dx * phi * lever * lever / (1.0 + k_e * phi);
            }
        }
        out
    }

    /// [`Self::coupling_response`] of a band-limited string: `(F, dF/dλ)`.
    pub(super) fn band_limited_response(&self, lift_next: f64) -> Option<(f64, f64)> {
        let band = self.band.as_ref()?;
        let f = self.point_forces(band, lift_next);
        Some((self.params.dx() * (f.contact + f.seat), f.slope))
    }

    /// [`Self::solve_contacts`] of a band-limited string: commits the forces, moves every
    /// stored node by them; returns the sum of the force densities (N/m) and the number of
    /// obstacle nodes pressed.
    pub(super) fn solve_band_limited(&mut self, lift_next: f64) -> Option<(f64, usize)> {
        let band = self.band.take()?;
        let f = self.point_forces(&band, lift_next);
        if let Some(rows) = &self.rows {
            for (r, &node) in rows.nodes().iter().enumerate() {
                self.u_next[node] += band.contact_col[r] * f.contact + band.seat_col[r] * f.seat;
            }
        }
        let mut active = 0;
        if let Some(&i) = self.contact_nodes.first() {
            self.stats.histogram[f.iterations] += 1;
            self.stats.cap_hits += u64::from(f.capped);
            self.contact_f[0] = f.contact;
            if f.contact != 0.0 {
                active = 1;
                let pen = (self.contact_g[0] + lift_next) - self.u_next[i];
                self.stats.max_penetration = self.stats.max_penetration.max(pen);
            }
        }
        if let Some(seat) = &mut self.seat {
            seat.force = f.seat;
        }
        self.band = Some(band);
        Some((f.contact + f.seat, active))
    }
}
