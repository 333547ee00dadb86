//! The stiff string model: build, initial conditions, the time step, energy and outputs.
//! See the module doc of [`crate::models::string`] for the scheme and its energy proof.

use super::band_limit::BandLimit;
use super::contact::{ContactLaw, ContactStats, NEWTON_CAP, NEWTON_TOL};
use super::contact_sav::ContactScheme;
use super::exact::ModeCoefficients;
use super::excitation::{StrikeForce, TrianglePluck};
use super::hand_damper::StringHand;
use super::losses::Losses;
use super::obstacle::Obstacle;
use super::output::{FieldView, OutputChannel, ResolvedOutput};
use super::params::StringParams;
use super::rows::NodeRows;
use super::seat::{Seat, SeatSpec};
use super::transform::ModalMap;
use crate::error::ParamError;
use crate::models::sav_relaxation::{RelaxationLedger, SavRelaxation};
use crate::models::source::{
    ContactSummary, EnergyTerms, ModelDetails, RenderSource, ShapeSnapshot, StringDetails,
};
use crate::schemes::two_step::first_increment;

/// Largest number of stored grid rows (obstacle nodes plus the nodes grid pickups read) for
/// which rows of `S` are kept (memory `ROW_LIMIT · N_m` values, [`NodeRows`]): a step then
/// computes the grid values at those nodes only ([`GridSynthesis::Rows`]) and the modal
/// contact force of a few active nodes from the same rows. With more nodes both directions go
/// through a DST of the whole grid.
pub const ROW_LIMIT: usize = 64;

/// Largest number of simultaneously active contact nodes for which the stored rows give the
/// modal force (`active · N/2 + N` multiply-adds, [`NodeRows::add_rows`]); beyond it one DST
/// (about `8 N log₂N` flops) is used.
pub const ROW_ACTIVE_LIMIT: usize = 8;

/// How a step obtains the grid displacement it needs (obstacle nodes, grid pickups).
///
/// Chosen at build ([`StiffString::new`]: `Rows` when at most [`ROW_LIMIT`] nodes are needed);
/// switchable with [`StiffString::set_grid_synthesis`]. Both give the same trajectory to
/// round-off (`tests/strings/string_rows.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridSynthesis {
    /// One DST of the whole grid every step (`O(N log N)`); every grid value is current.
    Dst,
    /// Dot products with stored rows of `S` at the needed nodes only (`T · N_m` multiply-adds
    /// for `T` nodes); other grid values are computed on demand
    /// ([`StiffString::grid_displacement`], snapshots).
    Rows,
}

/// Everything needed to build a [`StiffString`].
///
/// Built on the control thread.
#[derive(Debug, Clone, PartialEq)]
pub struct StringConfig {
    /// String and grid parameters.
    pub params: StringParams,
    /// Modal damping.
    pub losses: Losses,
    /// Obstacle profile (sampled on the grid at build).
    pub obstacle: Obstacle,
    /// Penalty contact law (ignored without obstacle, validated always).
    pub contact: ContactLaw,
    /// Output channels, in order.
    pub outputs: Vec<OutputChannel>,
}

/// Stiff string against a unilateral obstacle, modal exact scheme with pointwise
/// discrete-gradient contact (Issanchou et al., JSV 2017; SEED.md 3.2).
///
/// Lifecycle: [`StiffString::new`] (control thread: validates, allocates every buffer, plans
/// the DST), then [`StiffString::reset`], [`StiffString::pluck`], [`StiffString::strike`] and
/// [`StiffString::step`] / `process`, which never allocate and do bounded work (one or two
/// DSTs, at most `NEWTON_CAP` iterations per obstacle node), so they may run on the audio
/// thread. Owned by one thread at a time.
#[derive(Debug, Clone)]
pub struct StiffString {
    /// Validated parameters (read-only after build).
    params: StringParams,
    /// Time step `h` in s.
    h: f64,
    /// `k = h²/μ` in m·s²/kg (maps a force density in N/m to a displacement in m).
    k: f64,
    /// Per-mode scheme coefficients.
    coeffs: Vec<ModeCoefficients>,
    /// `c̃_j` of `coeffs`, contiguous for the vectorised free update (dimensionless).
    c_tilde: Vec<f64>,
    /// `β_j` of `coeffs`, contiguous for the vectorised free update (dimensionless).
    beta: Vec<f64>,
    /// Damping `σ_j` in s⁻¹.
    sigma: Vec<f64>,
    /// Energy weight of `(Δ^{n+1})²`: `μ(1 + c̃ + c)/(8h²)` in J/m³ (modal coordinates are in
    /// m^3/2, so a squared one is in m³).
    w_kin: Vec<f64>,
    /// Energy weight of `(q^{n+1} + q^n)²`: `μβ/(8h²)` in J/m³.
    w_pot: Vec<f64>,
    /// Dissipation weight of `(Δ^{n+1} + Δ^n)²` per step: `μ s/(2h)` in J/m³.
    w_diss: Vec<f64>,
    /// Whether any mode is damped.
    lossy: bool,
    /// The DST-based map `u = S q`.
    map: ModalMap,
    /// `q^{n+1}` (m^3/2).
    q: Vec<f64>,
    /// `Δ^{n+1} = q^{n+1} - q^n` (m^3/2).
    dq: Vec<f64>,
    /// Scratch: the new increment during a step.
    dq_next: Vec<f64>,
    /// `u^{n+1}` at interior nodes (m).
    u_now: Vec<f64>,
    /// `u^n` at interior nodes (m).
    u_prev: Vec<f64>,
    /// Scratch: `u^{n+2}` during a step (m).
    u_next: Vec<f64>,
    /// Scratch: nodal contact forces transformed to modal forces.
    force_buf: Vec<f64>,
    /// Scratch: the synthesis input `q^{n+1} + Δ_free` (m^3/2) on the rows path.
    w_buf: Vec<f64>,
    /// The whole grid `u^{n+1}` computed on demand on the rows path (m; control or audio
    /// thread, [`StiffString::grid_displacement`]).
    grid_buf: Vec<f64>,
    /// How a step computes grid values.
    synthesis: GridSynthesis,
    /// SIMD level detected at build ([`pulp`]); the step's O(N) loops run at its width.
    arch: pulp::Arch,
    /// Obstacle nodes (0-based interior index `i - 1`).
    contact_nodes: Vec<usize>,
    /// Obstacle heights `g_i` at those nodes (m).
    contact_g: Vec<f64>,
    /// Contact force densities `f_i` of the last step at those nodes (N/m).
    contact_f: Vec<f64>,
    /// Rows of `S` at the obstacle nodes (row `n` = obstacle node `n`) followed by the other
    /// nodes grid pickups read, kept when there are at most [`ROW_LIMIT`] such nodes (empty
    /// otherwise). They give the grid values on the [`GridSynthesis::Rows`] path, and (times
    /// `Δx`, the row of `S⁻¹`) the modal force of a few active nodes, cheaper than a DST.
    rows: Option<NodeRows>,
    /// Contact law.
    law: ContactLaw,
    /// Contact scheme (Newton by default; [`StiffString::set_contact_scheme`]).
    scheme: ContactScheme,
    /// Quadratised scheme's auxiliary `z_i^{n+1/2}` at the obstacle nodes, √(J/m): advanced
    /// only by that scheme, re-initialised from the state on reset, initial conditions and
    /// scheme switches.
    contact_z: Vec<f64>,
    /// How the quadratised scheme's `z_i` of nodes off the obstacle are pulled back to
    /// `√(2ψ(η_i)) = 0` before each step ([`crate::models::sav_relaxation`]; default
    /// [`SavRelaxation::contact_default_at`] the step).
    relaxation: SavRelaxation,
    /// Physical energy dissipated in the last step (J): the relaxation's budget.
    step_dissipated: f64,
    /// Energy removed by the relaxation since the initial condition (J; part of
    /// `dissipated`, negative where its budget returned some).
    relaxed: f64,
    /// What the relaxation may give back ([`crate::models::sav_relaxation`]).
    ledger: RelaxationLedger,
    /// Solver counters.
    stats: ContactStats,
    /// Energy dissipated since the initial condition (J).
    dissipated: f64,
    /// Work of the external force since the initial condition (J).
    work: f64,
    /// Active force excitation, if any.
    strike: Option<StrikeForce>,
    /// Time since the strike's onset at the next step, in s.
    strike_time: f64,
    /// `φ_j(x_e)` of the active strike (m^-1/2).
    strike_shape: Vec<f64>,
    /// Resolved output channels.
    outputs: Vec<ResolvedOutput>,
    /// Time index of `u^{n+1}` when the motion started: 1 after an initial condition (the
    /// state is then `(u^1, u^0)`), 0 after a reset (at rest, a strike's force acts from the
    /// next step). Gives the time of each output sample.
    start_index: u64,
    /// Total obstacle force of the last step (N).
    obstacle_force: f64,
    /// Steps since the last initial condition.
    steps: u64,
    /// The player's hand (a point damper, [`super::hand_damper`]); `c = 0` without one.
    hand: StringHand,
    /// How far the bridge under the string has moved the obstacle and the seat at `n` (m,
    /// along `u`; 0 for a string on a fixed bridge). Written by the network's step.
    lift_prev: f64,
    /// The same at `n+1` (m).
    lift_now: f64,
    /// The same at the step being computed (m; set by [`Self::solve_contacts`]).
    lift_next: f64,
    /// The spring that seats the string on a moving bridge ([`seat`]); `None` on a fixed one.
    seat: Option<Seat>,
    /// The modes stepped below a frequency and their compliances (`band_limit`); `None`:
    /// every mode, as built.
    band: Option<BandLimit>,
}

impl StiffString {
    /// Validates `config`, computes the modal coefficients and allocates every buffer.
    pub fn new(config: &StringConfig) -> Result<Self, ParamError> {
        Self::build(config, None)
    }

    /// As [`Self::new`], for a string seated on a moving bridge
    /// ([`crate::models::network`]): a linear spring of `seat.stiffness` ties the node nearest
    /// to `seat.position` to the bridge, and the obstacle moves with the bridge. The seat's
    /// node must not be an obstacle node (the error names it). Control thread.
    pub fn new_seated(config: &StringConfig, seat: &SeatSpec) -> Result<Self, ParamError> {
        Self::build(config, Some(seat))
    }

    /// [`Self::new`] and [`Self::new_seated`].
    fn build(config: &StringConfig, seat: Option<&SeatSpec>) -> Result<Self, ParamError> {
        let p = &config.params;
        p.validate()?;
        config.contact.validate()?;
        let m = p.modes();
        let (h, mu) = (p.h(), p.linear_density);
        let mut sigma = vec![0.0; m];
        config.losses.sigmas(p, &mut sigma)?;
        let coeffs: Vec<ModeCoefficients> = (0..m)
            .map(|j| ModeCoefficients::new(p.omega(j + 1), sigma[j], h))
            .collect();
        let samples = config.obstacle.sample(p)?;
        let outputs = config
            .outputs
            .iter()
            .enumerate()
            .map(|(i, o)| o.resolve(p, i))
            .collect::<Result<Vec<_>, _>>()?;
        let h2 = h * h;
        let seat_node = match seat {
            Some(spec) => Some(spec.node(p, &samples)?),
            None => None,
        };
        let (rows, synthesis) = Self::stored_rows(p, &samples, seat_node, &outputs);
        Ok(Self {
            params: p.clone(),
            h,
            k: h2 / mu,
            w_kin: coeffs
                .iter()
                .map(|c| mu * (2.0 + 2.0 * c.c_tilde - c.beta) / (8.0 * h2))
                .collect(),
            w_pot: coeffs.iter().map(|c| mu * c.beta / (8.0 * h2)).collect(),
            w_diss: coeffs.iter().map(|c| mu * c.s / (2.0 * h)).collect(),
            lossy: sigma.iter().any(|&s| s > 0.0),
            sigma,
            c_tilde: coeffs.iter().map(|c| c.c_tilde).collect(),
            beta: coeffs.iter().map(|c| c.beta).collect(),
            coeffs,
            map: ModalMap::new(p.length, p.intervals),
            q: vec![0.0; m],
            dq: vec![0.0; m],
            dq_next: vec![0.0; m],
            u_now: vec![0.0; m],
            u_prev: vec![0.0; m],
            u_next: vec![0.0; m],
            force_buf: vec![0.0; m],
            w_buf: vec![0.0; m],
            grid_buf: vec![0.0; m],
            synthesis,
            arch: pulp::Arch::new(),
            contact_nodes: samples.iter().map(|s| s.0).collect(),
            contact_g: samples.iter().map(|s| s.1).collect(),
            contact_f: vec![0.0; samples.len()],
            rows,
            law: config.contact,
            scheme: ContactScheme::default(),
            contact_z: vec![0.0; samples.len()],
            relaxation: SavRelaxation::contact_default_at(h),
            step_dissipated: 0.0,
            relaxed: 0.0,
            ledger: RelaxationLedger::default(),
            stats: ContactStats::default(),
            dissipated: 0.0,
            work: 0.0,
            strike: None,
            strike_time: 0.0,
            strike_shape: vec![0.0; m],
            outputs,
            obstacle_force: 0.0,
            steps: 0,
            start_index: 0,
            hand: StringHand::new(m),
            lift_prev: 0.0,
            lift_now: 0.0,
            lift_next: 0.0,
            seat: match (seat, seat_node) {
                (Some(spec), Some(node)) => Some(Seat::new(spec, node, samples.len())),
                _ => None,
            },
            band: None,
        })
    }

    /// Puts the string at rest (`q = Δ = 0`), clears the counters, the energy accounts and any
    /// active strike. No allocation.
    pub fn reset(&mut self) {
        for v in [&mut self.q, &mut self.dq, &mut self.u_now, &mut self.u_prev] {
            v.fill(0.0);
        }
        self.contact_f.fill(0.0);
        self.stats = ContactStats::default();
        self.dissipated = 0.0;
        self.step_dissipated = 0.0;
        self.relaxed = 0.0;
        self.ledger = RelaxationLedger::default();
        self.hand.dissipated = 0.0;
        self.hand.force = 0.0;
        self.work = 0.0;
        self.strike = None;
        self.strike_time = 0.0;
        self.obstacle_force = 0.0;
        self.steps = 0;
        self.start_index = 0;
        self.lift_prev = 0.0;
        self.lift_now = 0.0;
        self.lift_next = 0.0;
        if let Some(seat) = &mut self.seat {
            seat.force = 0.0;
        }
        self.init_quadratised();
    }

    /// Resets, then sets the initial modal displacement `q(0) = q0` and velocity `q̇(0) = v0`
    /// (`len = N - 1` each) and takes the exact free first step, so the stored state is
    /// `(q^1, q^0)`: without contact and damping the samples are exactly
    /// `q_j^n = q0_j cos(ω_j nh) + v0_j sin(ω_j nh)/ω_j`. No allocation.
    ///
    /// # Panics
    /// If the slices do not have length `N - 1`.
    pub fn set_modal_state(&mut self, q0: &[f64], v0: &[f64]) {
        assert!(q0.len() == self.q.len() && v0.len() == self.q.len());
        self.reset();
        let h = self.h;
        for j in 0..self.q.len() {
            let om = self.params.omega(j + 1);
            let sg = self.sigma[j];
            let d = first_increment(om, sg, h, q0[j], v0[j]);
            self.dq[j] = d;
            self.q[j] = q0[j] + d;
        }
        self.u_prev.copy_from_slice(q0);
        if let Some(m) = self.band_stepped() {
            self.q[m..].fill(0.0);
            self.dq[m..].fill(0.0);
            for ((u, q), d) in self.u_prev.iter_mut().zip(&self.q).zip(&self.dq) {
                *u = q - d;
            }
        }
        self.map.synthesis(&mut self.u_prev);
        self.u_now.copy_from_slice(&self.q);
        self.map.synthesis(&mut self.u_now);
        self.start_index = 1;
        self.init_quadratised();
    }

    /// Resets and sets the lecture's triangular pluck (zero velocity): `q(0) = S⁻¹ u0` of the
    /// sampled triangle. No allocation (uses the model's scratch).
    pub fn pluck(&mut self, pluck: &TrianglePluck) -> Result<(), ParamError> {
        pluck.validate(&self.params)?;
        let dx = self.params.dx();
        let mut q0 = std::mem::take(&mut self.u_next);
        let mut v0 = std::mem::take(&mut self.force_buf);
        for (i, x) in q0.iter_mut().enumerate() {
            *x = pluck.displacement(self.params.length, (i + 1) as f64 * dx);
        }
        self.map.analysis(&mut q0);
        v0.fill(0.0);
        self.set_modal_state(&q0, &v0);
        self.u_next = q0;
        self.force_buf = v0;
        Ok(())
    }

    /// Adds the triangular pluck's displacement to the current motion: a re-pluck of a
    /// sounding string, without the reset of [`Self::pluck`] (which silences the motion first:
    /// an audible click). The shape (sampled, through the grid map as in `pluck`) is added to
    /// both stored levels `u^n` and `u^{n+1}`, so the discrete velocity `δ_{t-}u` is unchanged
    /// and a velocity pickup continues without a jump. The energy the new shape brings
    /// (strain and, against an obstacle, contact) is counted as work, so the power balance
    /// stays closed across it; the quadratised contact state is re-initialised from the new
    /// displacement. O(N), no allocation: callable from the audio thread.
    pub fn add_pluck(&mut self, pluck: &TrianglePluck) -> Result<(), ParamError> {
        pluck.validate(&self.params)?;
        let before = self.energy_terms().total();
        let dx = self.params.dx();
        let mut d = std::mem::take(&mut self.u_next);
        for (i, x) in d.iter_mut().enumerate() {
            *x = pluck.displacement(self.params.length, (i + 1) as f64 * dx);
        }
        self.map.analysis(&mut d);
        if let Some(m) = self.band_stepped() {
            d[m..].fill(0.0);
        }
        for (q, dq) in self.q.iter_mut().zip(&d) {
            *q += dq;
        }
        self.map.synthesis(&mut d);
        for ((a, b), du) in self.u_prev.iter_mut().zip(self.u_now.iter_mut()).zip(&d) {
            *a += du;
            *b += du;
        }
        self.u_next = d;
        self.init_quadratised();
        self.work += self.energy_terms().total() - before;
        Ok(())
    }

    /// Starts a raised-cosine force at the next step (replacing any active one); the string
    /// keeps its current motion. O(N) (evaluates `φ_j(x_e)` into a preallocated buffer), no
    /// allocation: callable from the audio thread.
    pub fn strike(&mut self, force: &StrikeForce) -> Result<(), ParamError> {
        force.validate(&self.params)?;
        for (j, s) in self.strike_shape.iter_mut().enumerate() {
            *s = self.params.mode_shape(j + 1, force.position);
        }
        if let Some(m) = self.band_stepped() {
            self.strike_shape[m..].fill(0.0);
        }
        self.strike = Some(*force);
        self.strike_time = 0.0;
        Ok(())
    }

    /// The discrete energy terms at the current state `(n+1, n)` (O(N), no allocation):
    /// kinetic `Σ μ(1+c̃+c)/(8h²) (Δ^{n+1})²`, linear `Σ μβ/(8h²) (q^{n+1}+q^n)²` (plus the
    /// seat spring's energy on a moving bridge, [`Self::seat_energy`]), nonlinear
    /// (contact) `Δx Σ_i (ψ(η_i^{n+1}) + ψ(η_i^n))/2` (Newton scheme) or `Δx Σ_i z_i²/2`
    /// (quadratised scheme, [`super::contact_sav`]), dissipated and work accumulated so far.
    pub fn energy_terms(&self) -> EnergyTerms {
        let (mut kin, mut pot) = (0.0, 0.0);
        for j in 0..self.q.len() {
            let d = self.dq[j];
            let s = 2.0 * self.q[j] - d;
            kin += self.w_kin[j] * d * d;
            pot += self.w_pot[j] * s * s;
        }
        let contact = match self.scheme {
            ContactScheme::NewtonDiscreteGradient => self.contact_potential(),
            ContactScheme::Quadratised => self.quadratised_energy(),
        };
        EnergyTerms {
            kinetic: kin,
            linear: pot + self.seat_energy(),
            nonlinear: contact,
            above: 0.0,
            dissipated: self.dissipated,
            work: self.work,
        }
    }

    /// Value of every output channel at the current state, written to `out[c]`.
    pub fn read_outputs(&self, mut write: impl FnMut(usize, f64)) {
        let view = FieldView {
            u_now: &self.u_now,
            u_prev: &self.u_prev,
            q: &self.q,
            dq: &self.dq,
            h: self.h,
            obstacle_force: self.obstacle_force,
        };
        for (c, o) in self.outputs.iter().enumerate() {
            write(c, o.read(&view));
        }
    }

    /// Writes channel `c` of the current state to `out[c][n]` (`out.len() >= channels`).
    pub fn write_outputs(&self, out: &mut [Vec<f64>], n: usize) {
        self.read_outputs(|c, v| out[c][n] = v);
    }

    /// Validated parameters.
    pub fn params(&self) -> &StringParams {
        &self.params
    }

    /// Per-mode damping `σ_j` in s⁻¹ (`j - 1` indexed).
    pub fn sigmas(&self) -> &[f64] {
        &self.sigma
    }

    /// Per-mode scheme coefficients (`j - 1` indexed).
    pub fn coefficients(&self) -> &[ModeCoefficients] {
        &self.coeffs
    }

    /// Modal coordinates `q^{n+1}` (m^3/2).
    pub fn modal_displacement(&self) -> &[f64] {
        &self.q
    }

    /// Grid displacement `u^{n+1}` at nodes `1..N-1` (m).
    ///
    /// On the [`GridSynthesis::Rows`] path a step only updates the nodes it needs, so this runs
    /// one DST of `q^{n+1}` into a model-owned buffer (O(N log N), no allocation, does not touch
    /// the state); on the DST path it is the step's own grid.
    pub fn grid_displacement(&mut self) -> &[f64] {
        match self.synthesis {
            GridSynthesis::Dst => &self.u_now,
            GridSynthesis::Rows => {
                self.grid_buf.copy_from_slice(&self.q);
                self.map.synthesis(&mut self.grid_buf);
                &self.grid_buf
            }
        }
    }

    /// Contact solver counters.
    pub fn contact_stats(&self) -> &ContactStats {
        &self.stats
    }

    /// Number of obstacle nodes in the contact solve.
    pub fn contact_node_count(&self) -> usize {
        self.contact_nodes.len()
    }

    /// Total force on the obstacle at the last step (N).
    pub fn obstacle_force(&self) -> f64 {
        self.obstacle_force
    }

    /// Steps since the last initial condition.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Number of output channels.
    pub fn output_count(&self) -> usize {
        self.outputs.len()
    }
}

impl RenderSource for StiffString {
    fn sim_rate(&self) -> f64 {
        self.params.sample_rate
    }

    fn channels(&self) -> usize {
        self.outputs.len()
    }

    fn process(&mut self, out: &mut [Vec<f64>], frames: usize) {
        for n in 0..frames {
            self.step();
            self.write_outputs(out, n);
        }
    }

    fn energy(&self) -> EnergyTerms {
        self.energy_terms()
    }

    fn is_conservative(&self) -> bool {
        true
    }

    /// The exact scheme's recursion `q⁺ - C q + C̃ q⁻` against `√(ω_j² - σ_j²)`: equal to
    /// round-off (the metric shows that, it is not assumed).
    fn linear_partials(&self) -> Vec<crate::analysis::dispersion::LinearPartial> {
        use crate::analysis::dispersion::{damped_frequency, two_step_frequency, LinearPartial};
        let h = self.h;
        self.coeffs
            .iter()
            .enumerate()
            .filter_map(|(j, c)| {
                let exact = damped_frequency(self.params.omega(j + 1), self.sigma[j])?;
                let sim = two_step_frequency(c.c, c.c_tilde, h)?;
                Some(LinearPartial {
                    exact_hz: exact / std::f64::consts::TAU,
                    simulated_hz: sim / std::f64::consts::TAU,
                })
            })
            .collect()
    }

    /// Sample 0 is written after the first step, which computes `u^{s+1}` from `u^s`
    /// (`s = start_index`): a displacement `u^{s+1}` lies at `(s+1)h`, a velocity
    /// `(u^{s+1} - u^s)/h` is centred at `(s+½)h`, a bridge force `f^s` acts at `s h`.
    fn output_delay(&self, channel: usize) -> f64 {
        let s = self.start_index as f64;
        match self.outputs.get(channel) {
            Some(ResolvedOutput::ObstacleForce) => s * self.h,
            Some(ResolvedOutput::Grid { quantity, .. })
            | Some(ResolvedOutput::Modal { quantity, .. }) => match quantity {
                super::output::Quantity::Displacement => (s + 1.0) * self.h,
                super::output::Quantity::Velocity => (s + 0.5) * self.h,
            },
            None => 0.0,
        }
    }

    fn contact(&self) -> Option<ContactSummary> {
        let s = &self.stats;
        let last = s.max_iterations();
        Some(ContactSummary {
            max_penetration: s.max_penetration,
            newton_max_iterations: last,
            newton_failures: s.cap_hits,
            newton_histogram: s.histogram[..=last].to_vec(),
            newton_mean_iterations: s.mean_iterations_in_contact(),
            newton_cap: NEWTON_CAP,
            newton_tolerance: NEWTON_TOL,
            contact_steps: s.contact_steps,
            obstacle_nodes: self.contact_nodes.len(),
        })
    }

    fn shape(&self, time: f64) -> Option<ShapeSnapshot> {
        let (dx, m) = (self.params.dx(), self.u_now.len());
        let x = (0..=m + 1).map(|i| i as f64 * dx).collect();
        let mut u = Vec::with_capacity(m + 2);
        u.push(0.0);
        match self.synthesis {
            GridSynthesis::Dst => u.extend_from_slice(&self.u_now),
            GridSynthesis::Rows => u.extend(self.map.synthesized(&self.q)),
        }
        u.push(0.0);
        let obstacle = self
            .contact_nodes
            .iter()
            .zip(&self.contact_g)
            .map(|(&i, &g)| ((i + 1) as f64 * dx, g))
            .collect();
        Some(ShapeSnapshot {
            time,
            x,
            u,
            obstacle,
        })
    }

    fn details(&self) -> ModelDetails {
        let s = &self.stats;
        let last = s.max_iterations();
        ModelDetails::String(StringDetails {
            modes: self.q.len(),
            contact_scheme: self.scheme.name().into(),
            quadratisation_gap_j: (self.scheme == ContactScheme::Quadratised)
                .then(|| self.quadratisation_gap()),
            obstacle_nodes: self.contact_nodes.len(),
            contact_steps: s.contact_steps,
            newton_max_iterations: last,
            newton_cap_hits: s.cap_hits,
            newton_mean_iterations_in_contact: s.mean_iterations_in_contact(),
            max_penetration_m: s.max_penetration,
            newton_histogram: s.histogram[..=last].to_vec(),
        })
    }
}

mod band_solve;
mod contact_step;
mod hand_solve;
mod retune;
mod seat_solve;
mod step;

pub(crate) use step::FreeStep;
