//! The band above the simulation: linear modes of the same plate above its truncation, fed
//! with exactly the energy the truncation closure takes from the top of the simulated band.
//!
//! # Why this form
//!
//! The closure ([`super::closure`]) removes the energy a loud strike's cascade carries past the
//! cutoff, as the modes left out would take it. In the resolved plate that energy does not
//! vanish: it lives on in those modes (whose damping at 7-20 kHz leaves them ringing for
//! seconds on a bronze cymbal) and is what makes a crash shimmer above its truncated band. The
//! extension is those modes, linear (the cascade's energy there is spread over so many modes
//! that each one's amplitude is small), with the plate's own frequencies, pickups and damping
//! law, and a source: every step the energy the closure absorbed is given to them, so the
//! energy that leaves the simulated band is the energy that arrives above it, exactly.
//!
//! **Injection.** Mode `e` advances by the exact scheme of the plate's linear part
//! (`(1 + c̃h/2) q⁺ - (2 - h²ω̃²) q + (1 - c̃h/2) q⁻ = h² p`, [`super::params`]), whose discrete
//! energy `𝔢 = (ρh/2)[(δ_{t-}q)² + ω̃² q(n) q(n-1)]` changes by the work
//! `ρh p (q⁺ - q⁻)/2` of the modal force `p` (per unit mass) less the damping's
//! `h ρh c̃ (δ_{t.}q)²`. With `q⁺ = q_f + h² p / a` (`q_f` the free update) the work is the
//! quadratic `(ρh h²/2a) p² + (ρh (q_f - q⁻)/2) p`; setting it to the mode's share `W_e` gives
//! two real roots for any `W_e ≥ 0`, and the smaller one, taken without cancellation as
//! `p = 2W_e / (β + sgn β √(β² + 4αW_e))`, pushes along the mode's motion (a mode at rest gets
//! the sign of its index's parity, so the modes start with no common phase). The energy put in is then
//! `W_e` to round-off, whatever the state.
//!
//! **The strike.** The modes above the band are struck too. The mallet's contact sees them as
//! the residual of the modes left out ([`super::contact_residual`]): a spring and a dashpot
//! in series with the simulated plate, the dashpot being the plate's resistance to a point
//! force above its top mode. What that dashpot takes from the contact is what those modes take
//! from the stick: it is given to them here, exactly, as a second budget beside the closure's.
//! A hard stick's contact has its spectrum up to 10-20 kHz, so a ride struck softly (linear,
//! no cascade) still sounds above its simulated band. Mode `e` receives the share
//! `s'_e ∝ Φ_e(x₀)² (ω_e / ω_0)^{-α}` of it: an impulse gives every mode the energy
//! `J² Φ_e(x₀)² / 2ρh` (a mode with a node at the strike point gets none), and the contact's
//! spectrum falls above its inverse duration as the cascade's does (the same `α`). The energy
//! flows from the mallet through the dashpot into the modes, so the balance of plate, mallet
//! and band closes with nothing counted twice.
//!
//! **Spectrum.** Mode `e` receives the share `s_e ∝ (ω_e / ω_0)^{-α}` ([`SPECTRAL_SLOPE`])
//! of the absorbed energy (`ω_0` the lowest extension mode): the cascade front reaches the
//! lower modes first and most. `α` is calibrated against the crash cymbal with its band
//! resolved to 20 kHz (docs/ACCURACY.md).
//!
//! **Cost.** `O(N_e)` per step and no coupling: the modes are split into [`STRIDE`]
//! contiguous blocks and one block is fed per step, in turn (each mode every `STRIDE` steps
//! with what its share accumulated), so the injection's square root and division are taken
//! for `N_e / STRIDE` modes per step and the bank costs a few multiply-adds per mode and step
//! (one sweep, compiled at the CPU's SIMD level with `pulp`, the same bits at every level).
//!
//! Lifecycle: [`BandExtension::new`] allocates (worker thread); [`BandExtension::retune`],
//! [`BandExtension::run`] and [`BandExtension::reset`] run on the audio thread (or a voice
//! job) without allocation.

use super::params::linear_coefficients;
use crate::models::source::EnergyTerms;

/// The exponent `α` of the shares `s_e ∝ (ω_e/ω_0)^{-α}` (see the module doc), calibrated on
/// the crash cymbal against its 20 kHz reference (docs/ACCURACY.md).
pub const SPECTRAL_SLOPE: f64 = 1.0;

/// The top of the band above (Hz): the limit of hearing.
pub const CEILING_HZ: f64 = 20_000.0;

/// The most modes a band above lists (a plate whose basis tops out low would otherwise need
/// thousands to reach [`CEILING_HZ`]: it stops here).
pub const MAX_MODES: usize = 2048;

/// The highest frequency a band above at rate `fs` (Hz) sounds: [`CEILING_HZ`], or 0.45 `fs`
/// below 44.4 kHz (under Nyquist with the margin the voices' pickups keep).
pub fn ceiling_hz(fs: f64) -> f64 {
    CEILING_HZ.min(0.45 * fs)
}

/// How many modes of a plate reach [`CEILING_HZ`] when its first `n` modes reach `top_hz`:
/// a plate's modal density is constant in frequency (Weyl's law), so the count scales with
/// the frequency (5 % margin); at least `n`, at most [`MAX_MODES`].
pub fn mode_count(n: usize, top_hz: f64) -> usize {
    let wanted = if top_hz > 0.0 {
        (n as f64 * CEILING_HZ / top_hz * 1.05).ceil()
    } else {
        0.0
    };
    (wanted.min(MAX_MODES as f64) as usize).max(n)
}

/// Modes are fed in turn: `STRIDE` contiguous blocks, one per step (see the module doc).
pub const STRIDE: usize = 8;

/// Energy terms of the extension (J), copied out by value ([`BandExtension::energy`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ExtensionEnergy {
    /// Stored energy `Σ_e 𝔢_e` at the current step (J).
    pub stored: f64,
    /// Cumulative energy received from the closure since the last reset (J).
    pub received: f64,
    /// Cumulative energy received from the strike (the contact residual's dashpot) since the
    /// last reset (J; module doc, "The strike").
    pub struck: f64,
    /// The part of [`Self::received`] and [`Self::struck`] not yet given to the modes (J, ≥ 0).
    pub pending: f64,
    /// Cumulative energy the modes' damping removed (J, ≥ 0).
    pub dissipated: f64,
}

impl ExtensionEnergy {
    /// Adds the band to a model's energy terms (those of the plate that feeds it): its stored
    /// and pending energy as [`EnergyTerms::above`], and its own losses in place of the
    /// closure's and the contact residual's shares of the plate's dissipation (what it
    /// received and was struck with), so the terms' balance closes over plate and band.
    pub fn fold_into(&self, e: &mut EnergyTerms) {
        e.above = self.stored + self.pending;
        e.dissipated += self.dissipated - self.received - self.struck;
    }

    /// `stored + pending + dissipated - received - struck`: zero to round-off from a reset on.
    pub fn balance(&self) -> f64 {
        self.stored + self.pending + self.dissipated - self.received - self.struck
    }
}

/// A bank of linear plate modes above the simulated band, fed by the closure (module doc).
///
/// Struct-of-arrays state and coefficients, sized for `capacity` modes at [`Self::new`];
/// [`Self::retune`] uses the first `n ≤ capacity`. Owned by one voice (audio thread or the
/// voice job that runs it).
#[derive(Debug, Clone)]
pub struct BandExtension {
    /// Modes in use.
    n: usize,
    /// Time step (s) and surface density (kg/m²) of the last retune.
    h: f64,
    rho_h: f64,
    /// `1/a_e`, `b_e = 2 - h²ω̃_e²`, `d_e = 1 - c̃_e h/2`, `ω̃_e²`, `c̃_e`.
    inv_a: Vec<f64>,
    b: Vec<f64>,
    d: Vec<f64>,
    omega_sq: Vec<f64>,
    c_eff: Vec<f64>,
    /// `STRIDE s_e / Σ s`: what mode `e` receives, per joule of budget, when its turn comes
    /// (every [`STRIDE`] steps).
    share: Vec<f64>,
    /// `Σ share` over the modes of each turn.
    demand: [f64; STRIDE],
    /// The strike's shares (`STRIDE s'_e / Σ s'`, module doc) and their sums per turn.
    strike_share: Vec<f64>,
    strike_demand: [f64; STRIDE],
    /// The strike's part of the pending energy (J, ≥ 0).
    strike_pending: f64,
    /// Pickup weights `Φ_e(x_p)` (1/m) of the two pickups, `capacity` each.
    weights: [Vec<f64>; 2],
    /// `h² p_e / a_e` of the modes fed this step (zero otherwise).
    kick: Vec<f64>,
    q: Vec<f64>,
    q_prev: Vec<f64>,
    /// The pickups' velocities (backward difference, m/s) after the last step.
    outputs: [f64; 2],
    /// Which turn the next step feeds.
    turn: usize,
    /// The running CPU's SIMD level: the sweep is compiled for it (`pulp`, as the string's
    /// loops), with the same bits at every level.
    arch: pulp::Arch,
    energy: ExtensionEnergy,
}

impl BandExtension {
    /// An empty extension with room for `capacity` modes and two pickups (left and right).
    /// Worker thread: allocates.
    pub fn new(capacity: usize) -> Self {
        let z = || vec![0.0; capacity];
        Self {
            n: 0,
            h: 1.0,
            rho_h: 1.0,
            inv_a: z(),
            b: z(),
            d: z(),
            omega_sq: z(),
            c_eff: z(),
            share: z(),
            demand: [0.0; STRIDE],
            strike_share: z(),
            strike_demand: [0.0; STRIDE],
            strike_pending: 0.0,
            weights: [z(), z()],
            kick: z(),
            q: z(),
            q_prev: z(),
            outputs: [0.0; 2],
            turn: 0,
            arch: pulp::Arch::new(),
            energy: ExtensionEnergy::default(),
        }
    }

    /// Modes the extension can hold.
    pub fn capacity(&self) -> usize {
        self.q.len()
    }

    /// Modes in use.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether no mode is in use.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Sets the modes: physical angular frequencies `omega` (rad/s, increasing, each with
    /// `ω h < π`: the caller keeps them under Nyquist), damping `damping` (1/s, ≥ 0), surface
    /// density `rho_h` (kg/m²), step `h` (s). Uses the first `omega.len()` slots (at most
    /// the capacity; extra modes are ignored). The state is kept (a pitch bend retunes a
    /// ringing extension); the pickups keep their weights. Audio thread: no allocation,
    /// `O(N_e)` transcendental evaluations.
    pub fn retune(&mut self, omega: &[f64], damping: &[f64], rho_h: f64, h: f64) {
        let n = omega.len().min(damping.len()).min(self.capacity());
        let lowest = omega.first().copied().unwrap_or(1.0).max(f64::MIN_POSITIVE);
        let mut total = 0.0;
        for e in 0..n {
            let k = linear_coefficients(omega[e], damping[e], h, true);
            let a = 1.0 + 0.5 * k.damping * h;
            self.inv_a[e] = 1.0 / a;
            self.b[e] = 2.0 - h * h * k.omega_sq;
            self.d[e] = 1.0 - 0.5 * k.damping * h;
            self.omega_sq[e] = k.omega_sq;
            self.c_eff[e] = k.damping;
            self.share[e] = (omega[e] / lowest).powf(-SPECTRAL_SLOPE);
            total += self.share[e];
        }
        normalise(&mut self.share[..n], total, &mut self.demand);
        // Until `set_strike` says where the strike is, it shares as the closure does.
        self.strike_share[..n].copy_from_slice(&self.share[..n]);
        self.strike_demand = self.demand;
        // Slots left behind keep no motion (a retune to fewer modes drops their energy from
        // the stored sum; callers retune before a note's first step, or keep the count).
        for e in n..self.n {
            self.q[e] = 0.0;
            self.q_prev[e] = 0.0;
            self.kick[e] = 0.0;
        }
        self.n = n;
        self.h = h;
        self.rho_h = rho_h;
    }

    /// The weights of pickup `c` (0 left, 1 right; 1/m) over the modes in use, to be written
    /// by the caller.
    pub fn pickup_weights_mut(&mut self, c: usize) -> &mut [f64] {
        &mut self.weights[c][..self.n]
    }

    /// Sets where the modes are struck: `phi[e]`, their values at the excitation point over
    /// the modes in use (any common scale), give the strike's shares (module doc, "The
    /// strike"); a point on every mode's node keeps the closure's shares. Call after
    /// [`Self::retune`]. Audio thread: no allocation, `O(N_e)`.
    pub fn set_strike(&mut self, phi: &[f64]) {
        let n = self.n;
        let lowest = self.omega_sq[..n]
            .first()
            .copied()
            .unwrap_or(1.0)
            .max(f64::MIN_POSITIVE);
        let mut total = 0.0;
        for (e, (s, &w2)) in self.strike_share[..n]
            .iter_mut()
            .zip(&self.omega_sq[..n])
            .enumerate()
        {
            // Modes past the end of `phi` are not reached.
            let x = phi.get(e).copied().unwrap_or(0.0);
            *s = x * x * (w2 / lowest).powf(-0.5 * SPECTRAL_SLOPE);
            total += *s;
        }
        if !(total > 0.0 && total.is_finite()) {
            self.strike_share[..n].copy_from_slice(&self.share[..n]);
            self.strike_demand = self.demand;
            return;
        }
        normalise(&mut self.strike_share[..n], total, &mut self.strike_demand);
    }

    /// Puts the modes at rest and clears the energy terms. No allocation.
    pub fn reset(&mut self) {
        for v in [&mut self.q, &mut self.q_prev, &mut self.kick] {
            v.fill(0.0);
        }
        self.outputs = [0.0; 2];
        self.turn = 0;
        self.strike_pending = 0.0;
        self.energy = ExtensionEnergy::default();
    }

    /// Receives `energy` (J, ≥ 0; other values are ignored) from the closure and `struck`
    /// (J, ≥ 0; likewise) from the strike, and runs `frames` steps, giving the pending energy
    /// to the modes evenly over them; after each step calls `out(k, [left, right])` with the
    /// pickups' velocities (m/s). Audio thread: no allocation, `O(N_e)` per step.
    pub fn run(
        &mut self,
        energy: f64,
        struck: f64,
        frames: usize,
        mut out: impl FnMut(usize, [f64; 2]),
    ) {
        if energy > 0.0 && energy.is_finite() {
            self.energy.received += energy;
            self.energy.pending += energy;
        }
        if struck > 0.0 && struck.is_finite() {
            self.energy.struck += struck;
            self.energy.pending += struck;
            self.strike_pending += struck;
        }
        for k in 0..frames {
            let left = (frames - k) as f64;
            let closure = (self.energy.pending - self.strike_pending).max(0.0);
            self.step(closure / left, self.strike_pending / left);
            out(k, self.outputs);
        }
    }

    /// One step, giving `budget` (J) of the closure's and `strike` (J) of the strike's
    /// energy to the modes of this step's turn.
    #[inline]
    fn step(&mut self, budget: f64, strike: f64) {
        let n = self.n;
        let (h, rho_h) = (self.h, self.rho_h);
        let turn = self.turn;
        self.turn = (turn + 1) % STRIDE;
        let (lo, hi) = turn_range(turn, n);
        let fed = (budget > 0.0 || strike > 0.0) && lo < hi;
        if fed {
            // Each turn's demand, scaled down if the pending energy cannot cover it.
            let closure_pending = (self.energy.pending - self.strike_pending).max(0.0);
            let demand = self.demand[turn];
            let per_share = budget.min(closure_pending / demand.max(f64::MIN_POSITIVE));
            let strike_demand = self.strike_demand[turn];
            let per_strike = strike.min(self.strike_pending / strike_demand.max(f64::MIN_POSITIVE));
            let (gain, half) = (h * h, 0.5 * rho_h);
            let rows = self.q[lo..hi]
                .iter()
                .zip(&self.q_prev[lo..hi])
                .zip(self.b[lo..hi].iter().zip(&self.d[lo..hi]))
                .zip(self.inv_a[lo..hi].iter().zip(&self.share[lo..hi]))
                .zip(
                    self.kick[lo..hi]
                        .iter_mut()
                        .zip(&self.strike_share[lo..hi])
                        .enumerate(),
                );
            for ((((&x, &xp), (&b, &d)), (&inv_a, &share)), (k, (kick, &struck))) in rows {
                let w = per_share * share + per_strike * struck;
                let free = (b * x - d * xp) * inv_a;
                let alpha = half * gain * inv_a;
                let beta = half * (free - xp);
                let root = (beta * beta + 4.0 * alpha * w).sqrt();
                // Along the motion; a mode at rest takes the sign of its index's parity, so
                // the modes start with no common phase.
                let sign = if beta > 0.0 {
                    1.0
                } else if beta < 0.0 {
                    -1.0
                } else {
                    1.0 - 2.0 * ((lo + k) & 1) as f64
                };
                let p = 2.0 * w / (beta + sign * root);
                *kick = if p.is_finite() { gain * p * inv_a } else { 0.0 };
            }
            let given_strike = per_strike * strike_demand;
            let given = per_share * demand + given_strike;
            self.energy.pending = (self.energy.pending - given).max(0.0);
            self.strike_pending = (self.strike_pending - given_strike).max(0.0);
        }
        let inv_h = 1.0 / h;
        let arch = self.arch;
        let (o0, o1, lost) = arch.dispatch(self.sweep_args(n));
        self.outputs = [o0 * inv_h, o1 * inv_h];
        let lost = 0.25 * inv_h * inv_h * lost;
        if fed {
            self.kick[lo..hi].fill(0.0);
        }
        self.energy.dissipated += h * rho_h * lost;
    }

    /// The state and coefficients of the modes in use, for [`sweep`].
    fn sweep_args(&mut self, n: usize) -> Sweep<'_> {
        let [w0, w1] = &self.weights;
        Sweep {
            q: &mut self.q[..n],
            qp: &mut self.q_prev[..n],
            b: &self.b[..n],
            d: &self.d[..n],
            inv_a: &self.inv_a[..n],
            kick: &self.kick[..n],
            c: &self.c_eff[..n],
            w: [&w0[..n], &w1[..n]],
        }
    }

    /// The energy terms (J); the stored energy is summed now (`O(N_e)`). Any thread that owns
    /// the extension.
    pub fn energy(&self) -> ExtensionEnergy {
        let inv_h = 1.0 / self.h;
        let stored: f64 = (0..self.n)
            .map(|e| {
                let v = (self.q[e] - self.q_prev[e]) * inv_h;
                0.5 * self.rho_h * (v * v + self.omega_sq[e] * self.q[e] * self.q_prev[e])
            })
            .sum();
        ExtensionEnergy {
            stored,
            ..self.energy
        }
    }

    /// The modal displacements `q_e(n)` of the modes in use.
    pub fn q(&self) -> &[f64] {
        &self.q[..self.n]
    }
}

/// The modes `[lo, hi)` fed at turn `k` of `n` modes: the `k`-th of [`STRIDE`] contiguous
/// blocks (so the feed runs over contiguous memory).
fn turn_range(k: usize, n: usize) -> (usize, usize) {
    (k * n / STRIDE, (k + 1) * n / STRIDE)
}

/// Scales raw `shares` (summing to `total`) to `STRIDE s_e / Σ s` (all zero unless `total`
/// is positive) and writes each turn's sum into `demand`.
fn normalise(shares: &mut [f64], total: f64, demand: &mut [f64; STRIDE]) {
    let n = shares.len();
    let scale = if total > 0.0 {
        STRIDE as f64 / total
    } else {
        0.0
    };
    *demand = [0.0; STRIDE];
    for (e, s) in shares.iter_mut().enumerate() {
        *s *= scale;
        demand[turn_of(e, n)] += *s;
    }
}

/// The turn whose block holds mode `e` of `n` (the inverse of [`turn_range`]).
fn turn_of(e: usize, n: usize) -> usize {
    (0..STRIDE)
        .find(|&k| {
            let (lo, hi) = turn_range(k, n);
            (lo..hi).contains(&e)
        })
        .unwrap_or(0)
}

/// What one sweep over the modes reads and writes (equal lengths).
struct Sweep<'a> {
    q: &'a mut [f64],
    qp: &'a mut [f64],
    b: &'a [f64],
    d: &'a [f64],
    inv_a: &'a [f64],
    kick: &'a [f64],
    c: &'a [f64],
    w: [&'a [f64]; 2],
}

/// One step of every mode: `q⁺ = (b q - d q⁻)/a + kick`, the state shifted, and the sums of
/// the two pickups' `w (q⁺ - q)` and of the damping's `c (q⁺ - q⁻)²`, each over four
/// independent partial sums (kept in SIMD registers) added in a fixed order: the same bits on
/// every run and at every SIMD level (no fused multiply-add). Audio thread; no allocation.
#[inline(always)]
fn sweep(s: Sweep<'_>) -> (f64, f64, f64) {
    let (mut o0, mut o1, mut lost) = ([0.0f64; 4], [0.0f64; 4], [0.0f64; 4]);
    let n = s.q.len();
    let full = n - n % 4;
    let quads = s.q[..full]
        .chunks_exact_mut(4)
        .zip(s.qp[..full].chunks_exact_mut(4))
        .zip(s.b[..full].chunks_exact(4).zip(s.d[..full].chunks_exact(4)))
        .zip(
            s.inv_a[..full]
                .chunks_exact(4)
                .zip(s.kick[..full].chunks_exact(4)),
        )
        .zip(s.c[..full].chunks_exact(4))
        .zip(
            s.w[0][..full]
                .chunks_exact(4)
                .zip(s.w[1][..full].chunks_exact(4)),
        );
    for (((((q, qp), (b, d)), (inv_a, kick)), c), (w0, w1)) in quads {
        for j in 0..4 {
            let (x, xp) = (q[j], qp[j]);
            let next = (b[j] * x - d[j] * xp) * inv_a[j] + kick[j];
            let (v, vc) = (next - x, next - xp);
            qp[j] = x;
            q[j] = next;
            o0[j] += w0[j] * v;
            o1[j] += w1[j] * v;
            lost[j] += c[j] * vc * vc;
        }
    }
    for e in full..n {
        let (x, xp) = (s.q[e], s.qp[e]);
        let next = (s.b[e] * x - s.d[e] * xp) * s.inv_a[e] + s.kick[e];
        let (v, vc) = (next - x, next - xp);
        s.qp[e] = x;
        s.q[e] = next;
        o0[0] += s.w[0][e] * v;
        o1[0] += s.w[1][e] * v;
        lost[0] += s.c[e] * vc * vc;
    }
    let total = |a: [f64; 4]| (a[0] + a[2]) + (a[1] + a[3]);
    (total(o0), total(o1), total(lost))
}

impl pulp::WithSimd for Sweep<'_> {
    type Output = (f64, f64, f64);

    /// [`sweep`], compiled at the SIMD level `pulp` detected.
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) -> Self::Output {
        sweep(self)
    }
}

#[cfg(test)]
#[path = "extension_tests.rs"]
mod tests;
