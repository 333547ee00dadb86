//! The rest shape's per-model state and scratch (the model in `rest_shape.rs`): plain buffers,
//! allocated with the model, used on the audio thread.

/// The rest shape's state and scratch (all allocated with the model; audio thread).
#[derive(Debug, Clone)]
pub(crate) struct RestShape {
    /// Whether a nonzero rest shape is set (a flat plate runs the flat code, bit for bit).
    pub on: bool,
    /// `a_k` (units of `q`, m²), length `N_Φ`.
    pub a: Vec<f64>,
    /// `c_l = Ĥ(a, a)_l`, length `N_Ψ`.
    pub c: Vec<f64>,
    /// `σ_l = (Gᵀ a)_l - c_l` for the current step's `G`, length `N_Ψ`.
    pub shift: Vec<f64>,
    /// `r = q(n) + a`, length `N_Φ`.
    pub r: Vec<f64>,
    /// `G(a)_{s,l} = Σ_k Ĥ^l_{s,k} a_k`, row-major `N_Φ × N_Ψ`: the curvature's linear part of
    /// the in-plane stress, `2 Ĥ(a, q)_l = 2 Σ_s G(a)_{s,l} q_s` (set with `a`).
    pub g_a: Vec<f64>,
    /// Scratch, length `N_Ψ`: the linear part of the stress of a step.
    pub linear_stress: Vec<f64>,
}

impl RestShape {
    /// A flat plate's (zero) rest shape, sized for `n_phi` and `n_psi` modes (worker thread).
    pub fn flat(n_phi: usize, n_psi: usize) -> Self {
        Self {
            on: false,
            a: vec![0.0; n_phi],
            c: vec![0.0; n_psi],
            shift: vec![0.0; n_psi],
            r: vec![0.0; n_phi],
            g_a: vec![0.0; n_phi * n_psi],
            linear_stress: vec![0.0; n_psi],
        }
    }

    /// `r = q + a`.
    #[inline]
    pub fn fill_r(&mut self, q: &[f64]) {
        for ((r, &q), &a) in self.r.iter_mut().zip(q).zip(&self.a) {
            *r = q + a;
        }
    }

    /// `σ = Gᵀ a - c` from the row-major `N_Φ × N_Ψ` matrix `g`.
    #[inline]
    pub fn update_shift(&mut self, g: &[f64]) {
        let np = self.shift.len();
        self.shift.copy_from_slice(&self.c);
        for s in &mut self.shift {
            *s = -*s;
        }
        for (grow, &a) in g.chunks_exact(np.max(1)).zip(&self.a) {
            if a != 0.0 {
                for (sl, &gv) in self.shift.iter_mut().zip(grow) {
                    *sl += gv * a;
                }
            }
        }
    }
}
