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

impl StiffString {
    /// The stored rows (obstacle nodes first, in order, then the other nodes grid pickups read)
    /// and the default synthesis path: rows when at most [`ROW_LIMIT`] nodes are needed.
    pub(super) fn stored_rows(
        p: &StringParams,
        samples: &[(usize, f64)],
        outputs: &[ResolvedOutput],
    ) -> (Option<NodeRows>, GridSynthesis) {
        let mut nodes: Vec<usize> = samples.iter().map(|s| s.0).collect();
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
    /// stored rows (at most [`ROW_LIMIT`] needed nodes), otherwise the model stays on `Dst`.
    /// Switching to `Dst` recomputes the whole grid `u^{n+1} = S q^{n+1}`,
    /// `u^n = S(q^{n+1} - Δ^{n+1})` (one round-off-level change at the needed nodes). O(N log N),
    /// no allocation.
    pub fn set_grid_synthesis(&mut self, path: GridSynthesis) -> GridSynthesis {
        let path = match (path, &self.rows) {
            (GridSynthesis::Rows, None) => GridSynthesis::Dst,
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

    /// Advances one step `n → n+1` (see the module doc for the algorithm).
    pub fn step(&mut self) {
        let k = self.k;
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
        let w = if rows_path {
            &mut self.w_buf
        } else {
            &mut self.u_next
        };
        let (dn, ct, beta, q, dq, shape) = (
            &mut self.dq_next,
            &self.c_tilde,
            &self.beta,
            &self.q,
            &self.dq,
            &self.strike_shape,
        );
        let kf = k * fe;
        self.arch.dispatch(|| {
            let modes = dn
                .iter_mut()
                .zip(w.iter_mut())
                .zip(ct)
                .zip(beta)
                .zip(q)
                .zip(dq);
            if fe == 0.0 {
                for (((((dn, w), &ct), &b), &q), &d) in modes {
                    let x = ct * d - b * q;
                    *dn = x;
                    *w = q + x;
                }
            } else {
                for ((((((dn, w), &ct), &b), &q), &d), &s) in modes.zip(shape) {
                    let x = ct * d - b * q + kf * s;
                    *dn = x;
                    *w = q + x;
                }
            }
        });
        // 2. Free grid displacement u_free = S (q + Δ_free): at the needed nodes from the
        //    stored rows, or on the whole grid by one DST.
        match (&mut self.rows, rows_path) {
            (Some(rows), true) => rows.synthesize(&self.w_buf, &mut self.u_next),
            _ => self.map.synthesis(&mut self.u_next),
        }
        // 3. Pointwise contact solve: u^{n+1}_i = u_free_i + k f_i (Newton or quadratised).
        let (total, active) = self.solve_contacts();
        self.obstacle_force = total * self.params.dx();
        // 4. Modal correction Δ += k S⁻¹ f = k Δx S f, only when some force acted: a sum over
        //    the stored rows for a few active nodes (obstacle node n is row n), or one DST.
        if active > 0 {
            self.stats.contact_steps += 1;
            match &mut self.rows {
                Some(rows) if active <= ROW_ACTIVE_LIMIT => {
                    rows.add_rows(k * self.params.dx(), &self.contact_f, &mut self.dq_next);
                }
                _ => {
                    self.force_buf.fill(0.0);
                    for (n, &i) in self.contact_nodes.iter().enumerate() {
                        self.force_buf[i] = self.contact_f[n];
                    }
                    self.map.analysis(&mut self.force_buf);
                    for (d, f) in self.dq_next.iter_mut().zip(&self.force_buf) {
                        *d += k * f;
                    }
                }
            }
        }
        // 5. Work of the external force h·F δ_t.q, δ_t.q = (Δ^{n+1}+Δ^n)/(2h).
        if fe != 0.0 {
            let mut w = 0.0;
            for ((s, dn), d) in self.strike_shape.iter().zip(&self.dq_next).zip(&self.dq) {
                w += s * (dn + d);
            }
            self.work += 0.5 * fe * w;
        }
        // 6. Dissipation h·2μs(δ_t.q)², rotation and flush in one pass.
        let (q, dn, dq, wd, lossy) = (
            &mut self.q,
            &mut self.dq_next,
            &self.dq,
            &self.w_diss,
            self.lossy,
        );
        let d = self.arch.dispatch(|| {
            if lossy {
                finish::<true>(q, dn, dq, wd)
            } else {
                finish::<false>(q, dn, dq, wd)
            }
        });
        self.dissipated += d;
        std::mem::swap(&mut self.dq, &mut self.dq_next);
        std::mem::swap(&mut self.u_prev, &mut self.u_now);
        std::mem::swap(&mut self.u_now, &mut self.u_next);
        self.steps += 1;
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

/// Steps 5-6 of [`StiffString::step`] over all modes, in four interleaved lanes (the
/// dissipation sum in four partial sums, so the loop vectorises without reassociation).
/// Returns the energy dissipated in the step (J).
#[inline(always)]
fn finish<const LOSSY: bool>(q: &mut [f64], dn: &mut [f64], d: &[f64], wd: &[f64]) -> f64 {
    let n4 = q.len() - q.len() % 4;
    let (q4, q1) = q.split_at_mut(n4);
    let (dn4, dn1) = dn.split_at_mut(n4);
    let mut acc = [0.0f64; 4];
    let lanes = q4
        .chunks_exact_mut(4)
        .zip(dn4.chunks_exact_mut(4))
        .zip(d[..n4].chunks_exact(4))
        .zip(wd[..n4].chunks_exact(4));
    for (((qc, nc), dc), wc) in lanes {
        for l in 0..4 {
            acc[l] += finish_one::<LOSSY>(&mut qc[l], &mut nc[l], dc[l], wc[l]);
        }
    }
    for (((qv, nv), &dv), &wv) in q1.iter_mut().zip(dn1).zip(&d[n4..]).zip(&wd[n4..]) {
        acc[0] += finish_one::<LOSSY>(qv, nv, dv, wv);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}
