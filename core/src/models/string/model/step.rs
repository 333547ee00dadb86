//! The time step of [`StiffString`] and the choice of how it computes grid values
//! ([`GridSynthesis`]); the algorithm is in the module doc of [`crate::models::string`].
//!
//! The O(N) modal work is done in two fused passes: the free update also writes the synthesis
//! input `q + Δ_free`, and one pass after the contact solve accumulates the dissipated energy,
//! rotates `q ← q + Δ` and flushes decayed modes to zero (branch-free, four lanes).

use super::{GridSynthesis, StiffString, ROW_ACTIVE_LIMIT, ROW_LIMIT};
use crate::models::string::output::ResolvedOutput;
use crate::models::string::params::StringParams;
use crate::models::string::rows::NodeRows;
use crate::models::FLUSH_TO_ZERO_BELOW;
use pulp::{Simd, WithSimd};

impl StiffString {
    /// The stored rows (obstacle nodes first, in order, then the seat's node, then the other
    /// nodes grid pickups read)
    /// and the default synthesis path: rows when at most [`ROW_LIMIT`] nodes are needed.
    pub(super) fn stored_rows(
        p: &StringParams,
        samples: &[(usize, f64)],
        seat: Option<usize>,
        outputs: &[ResolvedOutput],
    ) -> (Option<NodeRows>, GridSynthesis) {
        let mut nodes: Vec<usize> = samples.iter().map(|s| s.0).collect();
        // The seat's row follows the obstacle's (`Seat::row`).
        nodes.extend(seat);
        for i in outputs.iter().flat_map(|o| o.grid_nodes(p.intervals)) {
            if !nodes.contains(&i) {
                nodes.push(i);
            }
        }
        if nodes.len() <= ROW_LIMIT {
            let rows = NodeRows::new(p.length, p.intervals, nodes);
            (Some(rows), GridSynthesis::Rows)
        } else {
            (None, GridSynthesis::Dst)
        }
    }

    /// Selects how a step computes grid values and returns the path in use: `Rows` needs the
    /// stored rows (at most [`ROW_LIMIT`] needed nodes), otherwise the model stays on `Dst`;
    /// a band-limited string ([`Self::set_band_limit`]) stays on `Rows`.
    /// Switching to `Dst` recomputes the whole grid `u^{n+1} = S q^{n+1}`,
    /// `u^n = S(q^{n+1} - Δ^{n+1})` (one round-off-level change at the needed nodes). O(N log N),
    /// no allocation.
    pub fn set_grid_synthesis(&mut self, path: GridSynthesis) -> GridSynthesis {
        let path = match (path, &self.rows) {
            (GridSynthesis::Rows, None) => GridSynthesis::Dst,
            // A band-limited string's solve moves the stored nodes only.
            (GridSynthesis::Dst, Some(_)) if self.band.is_some() => GridSynthesis::Rows,
            (p, _) => p,
        };
        if path == GridSynthesis::Dst && self.synthesis == GridSynthesis::Rows {
            self.u_now.copy_from_slice(&self.q);
            self.map.synthesis(&mut self.u_now);
            for ((u, q), d) in self.u_prev.iter_mut().zip(&self.q).zip(&self.dq) {
                *u = q - d;
            }
            self.map.synthesis(&mut self.u_prev);
        }
        self.synthesis = path;
        path
    }

    /// How a step computes grid values.
    pub fn grid_synthesis(&self) -> GridSynthesis {
        self.synthesis
    }

    /// Advances one step `n → n+1` (see the module doc for the algorithm). A string seated
    /// on a bridge ([`StiffString::new_seated`]) stepped alone keeps the bridge where it is.
    pub fn step(&mut self) {
        let start = self.free_step();
        let (total, active) = self.solve_contacts(self.lift_now);
        self.finish_step(start, total, active);
    }

    /// Steps 1-2 of [`Self::step`]: the free modal update (with the strike and the hand) and
    /// the free grid displacement at the needed nodes, in `u_next`. Returns what
    /// [`Self::finish_step`] needs. Audio thread, no allocation.
    pub(crate) fn free_step(&mut self) -> FreeStep {
        let k = self.k;
        let dissipated_before = self.dissipated;
        let relaxed_before = self.relaxed;
        // 1. Free update (difference form of the exact scheme) plus the external modal force,
        //    fused with the synthesis input w = q + Δ_free.
        let fe = match self.strike {
            Some(s) => {
                let f = s.force(self.strike_time);
                self.strike_time += self.h;
                if self.strike_time > s.duration {
                    self.strike = None;
                }
                f
            }
            None => 0.0,
        };
        let rows_path = self.synthesis == GridSynthesis::Rows;
        // A band-limited string steps its lowest `m` modes; the others stay at zero.
        let m = self.stepped_modes();
        let w = if rows_path {
            &mut self.w_buf
        } else {
            &mut self.u_next
        };
        self.arch.dispatch(FreeUpdate {
            dn: &mut self.dq_next[..m],
            w: &mut w[..m],
            ct: &self.c_tilde[..m],
            beta: &self.beta[..m],
            q: &self.q[..m],
            dq: &self.dq[..m],
            shape: &self.strike_shape[..m],
            kf: k * fe,
        });
        // 1b. The player's hand, in closed form (it moves no obstacle node, see `hand`).
        if self.hand.c > 0.0 {
            self.apply_hand(rows_path);
        }
        // 2. Free grid displacement u_free = S (q + Δ_free): at the needed nodes from the
        //    stored rows, or on the whole grid by one DST.
        match (&mut self.rows, rows_path) {
            (Some(rows), true) => rows.synthesize(&self.w_buf, &mut self.u_next),
            _ => self.map.synthesis(&mut self.u_next),
        }
        FreeStep {
            fe,
            dissipated_before,
            relaxed_before,
        }
    }

    /// Steps 4-6 of [`Self::step`], after the contact solve (step 3,
    /// [`Self::solve_contacts`], which returned `total` and `active`): the modal correction
    /// of the contact and seat forces, the strike's work, the dissipation and the rotation.
    /// Audio thread, no allocation.
    pub(crate) fn finish_step(&mut self, start: FreeStep, total: f64, active: usize) {
        let FreeStep {
            fe,
            dissipated_before,
            relaxed_before,
        } = start;
        let k = self.k;
        self.obstacle_force = total * self.params.dx();
        // 4. Modal correction Δ += k S⁻¹ f = k Δx S f, only when some force acted: a sum over
        //    the stored rows for a few active nodes (obstacle node n is row n), or one DST.
        let seated = self.seat.is_some_and(|s| s.force != 0.0);
        if active > 0 || seated {
            self.stats.contact_steps += u64::from(active > 0);
            match &mut self.rows {
                Some(rows) if active <= ROW_ACTIVE_LIMIT => {
                    rows.add_rows(k * self.params.dx(), &self.contact_f, &mut self.dq_next);
                    if let Some(seat) = &self.seat {
                        if seat.force != 0.0 {
                            rows.add_row(
                                seat.row,
                                k * self.params.dx() * seat.force,
                                &mut self.dq_next,
                            );
                        }
                    }
                }
                _ => {
                    self.force_buf.fill(0.0);
                    for (n, &i) in self.contact_nodes.iter().enumerate() {
                        self.force_buf[i] = self.contact_f[n];
                    }
                    if let Some(seat) = &self.seat {
                        self.force_buf[seat.node] += seat.force;
                    }
                    self.map.analysis(&mut self.force_buf);
                    for (d, f) in self.dq_next.iter_mut().zip(&self.force_buf) {
                        *d += k * f;
                    }
                }
            }
        }
        let m = self.stepped_modes();
        self.dq_next[m..].fill(0.0);
        // 5. Work of the external force h·F δ_t.q, δ_t.q = (Δ^{n+1}+Δ^n)/(2h).
        if fe != 0.0 {
            let mut w = 0.0;
            for ((s, dn), d) in self.strike_shape.iter().zip(&self.dq_next).zip(&self.dq) {
                w += s * (dn + d);
            }
            self.work += 0.5 * fe * w;
        }
        if self.hand.c > 0.0 {
            self.hand_power();
        }
        // 6. Dissipation h·2μs(δ_t.q)², rotation and flush in one pass.
        let d = self.arch.dispatch(Finish {
            q: &mut self.q[..m],
            dn: &mut self.dq_next[..m],
            d: &self.dq[..m],
            wd: &self.w_diss[..m],
            lossy: self.lossy,
        });
        self.dissipated += d;
        // The physical losses of this step (damping and hand, not the relaxation): the next
        // step's relaxation budget.
        self.step_dissipated =
            (self.dissipated - dissipated_before) - (self.relaxed - relaxed_before);
        std::mem::swap(&mut self.dq, &mut self.dq_next);
        std::mem::swap(&mut self.u_prev, &mut self.u_now);
        std::mem::swap(&mut self.u_now, &mut self.u_next);
        self.lift_prev = self.lift_now;
        self.lift_now = self.lift_next;
        self.steps += 1;
    }
}

/// What [`StiffString::free_step`] hands to [`StiffString::finish_step`] (audio thread).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct FreeStep {
    /// The strike's force this step (N; 0 without strike).
    fe: f64,
    /// `dissipated` before the step (J).
    dissipated_before: f64,
    /// `relaxed` before the step (J).
    relaxed_before: f64,
}

/// Step 1's loop: `Δ_free = c̃ Δ - β q + k f_e φ(x_e)` and `w = q + Δ_free` (the strike term
/// only when `kf ≠ 0`), compiled at the detected SIMD width.
struct FreeUpdate<'a> {
    /// `Δ_free` (written).
    dn: &'a mut [f64],
    /// `q + Δ_free` (written).
    w: &'a mut [f64],
    /// `c̃_j`.
    ct: &'a [f64],
    /// `β_j`.
    beta: &'a [f64],
    /// The current `q`.
    q: &'a [f64],
    /// The current `Δ`.
    dq: &'a [f64],
    /// Strike shape `φ_j(x_e)`.
    shape: &'a [f64],
    /// `k f_e` (0 without strike).
    kf: f64,
}

impl WithSimd for FreeUpdate<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        let kf = self.kf;
        let modes = self
            .dn
            .iter_mut()
            .zip(self.w.iter_mut())
            .zip(self.ct)
            .zip(self.beta)
            .zip(self.q)
            .zip(self.dq);
        if kf == 0.0 {
            for (((((dn, w), &ct), &b), &q), &d) in modes {
                let x = ct * d - b * q;
                *dn = x;
                *w = q + x;
            }
        } else {
            for ((((((dn, w), &ct), &b), &q), &d), &s) in modes.zip(self.shape) {
                let x = ct * d - b * q + kf * s;
                *dn = x;
                *w = q + x;
            }
        }
    }
}

/// Step 6's loop ([`finish`]) compiled at the detected SIMD width; returns the dissipated
/// energy of the step (J).
struct Finish<'a> {
    /// `q` (rotated in place).
    q: &'a mut [f64],
    /// `Δ^{n+1}` (flushed in place).
    dn: &'a mut [f64],
    /// `Δ^n`.
    d: &'a [f64],
    /// Dissipation weights.
    wd: &'a [f64],
    /// Whether any mode is damped.
    lossy: bool,
}

impl WithSimd for Finish<'_> {
    type Output = f64;

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) -> f64 {
        if self.lossy {
            finish::<S, true>(simd, self.q, self.dn, self.d, self.wd)
        } else {
            finish::<S, false>(simd, self.q, self.dn, self.d, self.wd)
        }
    }
}

/// One mode of [`finish`]: returns the dissipation term `w_d (Δ^{n+1} + Δ^n)²` (0 unless
/// `LOSSY`) and rotates `q ← q + Δ^{n+1}`. Decayed modes go to exactly zero instead of through
/// the subnormal range (see `FLUSH_TO_ZERO_BELOW`; grid values are sums of these, so they
/// follow); a mode is flushed only when both the new `q` and `Δ` are tiny (flushing `Δ` alone
/// would freeze a slowly decaying `q`, flushing `q` alone would leave `Δ` decaying into
/// subnormals). Branch-free, and a NaN is never flushed (the comparisons are false).
#[inline(always)]
fn finish_one<const LOSSY: bool>(q: &mut f64, dn: &mut f64, d: f64, wd: f64) -> f64 {
    let x = *dn;
    let diss = if LOSSY {
        let v = x + d;
        wd * v * v
    } else {
        0.0
    };
    let qn = *q + x;
    let t = FLUSH_TO_ZERO_BELOW;
    let flush = (qn.abs() < t) & (x.abs() < t);
    *q = if flush { 0.0 } else { qn };
    *dn = if flush { 0.0 } else { x };
    diss
}

/// Step 6 of [`StiffString::step`] over all modes in explicit SIMD lanes (the dissipation
/// in one partial sum per lane, the flush as a mask select), the tail by [`finish_one`].
/// Returns the energy dissipated in the step (J).
#[inline(always)]
fn finish<S: Simd, const LOSSY: bool>(
    simd: S,
    q: &mut [f64],
    dn: &mut [f64],
    d: &[f64],
    wd: &[f64],
) -> f64 {
    let (qh, qt) = S::as_mut_simd_f64s(q);
    let (nh, nt) = S::as_mut_simd_f64s(dn);
    let (dh, dt) = S::as_simd_f64s(d);
    let (wh, wt) = S::as_simd_f64s(wd);
    let t = simd.splat_f64s(FLUSH_TO_ZERO_BELOW);
    let zero = simd.splat_f64s(0.0);
    let mut acc = zero;
    for (((q, n), &d), &w) in qh.iter_mut().zip(nh.iter_mut()).zip(dh).zip(wh) {
        let x = *n;
        if LOSSY {
            let v = simd.add_f64s(x, d);
            acc = simd.mul_add_e_f64s(simd.mul_f64s(w, v), v, acc);
        }
        let qn = simd.add_f64s(*q, x);
        let small_q = simd.less_than_f64s(simd.abs_f64s(qn), t);
        let small_x = simd.less_than_f64s(simd.abs_f64s(x), t);
        let flush = simd.and_m64s(small_q, small_x);
        *q = simd.select_f64s(flush, zero, qn);
        *n = simd.select_f64s(flush, zero, x);
    }
    let mut sum = simd.reduce_sum_f64s(acc);
    for (((q, n), &d), &w) in qt.iter_mut().zip(nt.iter_mut()).zip(dt).zip(wt) {
        sum += finish_one::<LOSSY>(q, n, d, w);
    }
    sum
}
