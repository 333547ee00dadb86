//! Coupling tensor `H^l_{ij} = ∫_S Ψ_l L(Φ_i, Φ_j) dS` (Ducceschi & Touzé, JSV 344, 2015,
//! eq. 12), by separation of variables.
//!
//! With `Φ = N sin(κx) sin(μy)`, `N = 2/sqrt(aspect)`, `κ = mπ`, `μ = nπ/aspect`:
//! `L(Φ_i, Φ_j) = N² [(κ_i²μ_j² + μ_i²κ_j²) s_i s_j S_i S_j - 2 κ_iμ_iκ_jμ_j c_i c_j C_i C_j]`
//! (`s, c` = sin, cos in x; `S, C` in y). Products of sines/cosines become `cos((m_i ∓ m_j)πx)`,
//! so with `T_l(a, b) = ∫ Ψ_l cos(aπx) cos(bπy/aspect) dS`:
//! `H^l_ij = (N²/4) [A (T_dd - T_ds - T_sd + T_ss) - B (T_dd + T_ds + T_sd + T_ss)]`,
//! `A = κ_i²μ_j² + μ_i²κ_j²`, `B = 2κ_iμ_iκ_jμ_j`, first index `d = |m_i - m_j|` or
//! `s = m_i + m_j`, second likewise with `n`. `T_l = Gxᵀ c_l Gy` where
//! `Gx[p][a] = ∫_0^1 X_p(x) cos(aπx) dx` (Gauss-Legendre) and `c_l` the Ritz coefficients.
//!
//! Selection rule: about the centre, `sin(mπx)` has parity `(-1)^(m+1)`, so `Φ_iΦ_j` and
//! `L(Φ_i, Φ_j)` are even in x iff `m_i + m_j` is even; `H^l_ij` vanishes unless that parity
//! equals Ψ_l's x-parity, likewise in y. Those entries are never computed nor stored.
//!
//! Built on a worker thread (parallel over `l` with rayon), never on the audio thread.

use super::airy::AiryModes;
use super::beam::ClampedBasis1d;
use super::legendre::gauss_legendre;
use crate::error::ParamError;
use crate::modal::CouplingTensor;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Nonzero entries `H^l_{ij}` with `j ≤ i` as a struct of arrays, sorted by `l`, then `i`,
/// then `j`. Dimensionless (plate `[0,1] × [0,aspect]`); the physical tensor is
/// `H_phys = value / Lx⁵` (see the module docs of [`crate::modal::rect`]).
///
/// Built on a worker thread; read-only afterwards, so an audio thread may read it once the
/// stepper owns it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CouplingTriplets {
    /// Number of transverse modes `N_Φ` (range of `i`, `j`).
    pub n_phi: usize,
    /// Number of Airy modes `N_Ψ` (range of `l`).
    pub n_psi: usize,
    /// Airy mode index `l` of each entry (0-based).
    pub l: Vec<u32>,
    /// Transverse mode index `i` (0-based), `i ≥ j`.
    pub i: Vec<u32>,
    /// Transverse mode index `j` (0-based), `j ≤ i`.
    pub j: Vec<u32>,
    /// `H^l_{ij}` (dimensionless). The full tensor is symmetric: `H^l_{ji} = H^l_{ij}`.
    pub value: Vec<f64>,
}

impl CouplingTriplets {
    /// The entries of `t` listed with their row `l` (the tensor's order: by `l`, then `i`, then
    /// `j ≤ i`). Worker thread or tests; allocates.
    pub fn from_tensor(t: &CouplingTensor) -> Self {
        let (row_start, i, j, value) = t.parts();
        let mut l = Vec::with_capacity(value.len());
        for (row, w) in row_start.windows(2).enumerate() {
            l.extend(std::iter::repeat_n(row as u32, (w[1] - w[0]) as usize));
        }
        Self {
            n_phi: t.n_phi(),
            n_psi: t.n_psi(),
            l,
            i: i.to_vec(),
            j: j.to_vec(),
            value: value.to_vec(),
        }
    }

    /// Number of stored entries.
    pub fn len(&self) -> usize {
        self.value.len()
    }

    /// True if no entry is stored.
    pub fn is_empty(&self) -> bool {
        self.value.is_empty()
    }

    /// `H^l_{ij}` for any order of `i, j` (binary search; 0 for entries not stored, i.e.
    /// zero by the parity rule). Worker thread or tests, not meant for per-sample use.
    pub fn get(&self, l: usize, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        let key = (l as u32, i as u32, j as u32);
        let mut lo = 0;
        let mut hi = self.len();
        while lo < hi {
            let mid = (lo + hi) / 2;
            let k = (self.l[mid], self.i[mid], self.j[mid]);
            match k.cmp(&key) {
                std::cmp::Ordering::Less => lo = mid + 1,
                std::cmp::Ordering::Greater => hi = mid,
                std::cmp::Ordering::Equal => return self.value[mid],
            }
        }
        0.0
    }
}

/// `G[p][k] = ∫_0^len X_p(x) cos(kπx/len) dx`, for `k ≤ k_max` of the basis parity (other
/// entries are exact zeros by parity and left at 0). Row-major `n × (k_max + 1)`.
fn cosine_table(b: &ClampedBasis1d, len: f64, parity: usize, k_max: usize, nq: usize) -> Vec<f64> {
    let n = b.len_basis();
    let nk = k_max + 1;
    let mut g = vec![0.0; n * nk];
    let (t, w) = gauss_legendre(nq);
    let mut s = b.scratch();
    let (mut f, mut df, mut ddf) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for (tq, wq) in t.iter().zip(&w) {
        let x = 0.5 * len * (tq + 1.0);
        let wx = 0.5 * len * wq;
        b.eval(x, &mut s, &mut f, &mut df, &mut ddf);
        for k in (parity..nk).step_by(2) {
            let c = wx * (k as f64 * PI * x / len).cos();
            for p in 0..n {
                g[p * nk + k] += f[p] * c;
            }
        }
    }
    g
}

/// One pair `(i, j)`, `j ≤ i`, allowed in a parity class, with its precomputed factors.
struct Pair {
    i: u32,
    j: u32,
    a: f64,
    b: f64,
    dm: u32,
    sm: u32,
    dn: u32,
    sn: u32,
}

/// Builds the coupling tensor for the given transverse labels and Airy modes, integrating
/// the 1D cosine tables with `nq` Gauss-Legendre points per direction (rows by `l`, entries
/// sorted by `i`, then `j ≤ i`: the layout of [`CouplingTensor`]).
pub(crate) fn build(
    aspect: f64,
    labels: &[(u32, u32)],
    airy: &AiryModes,
    nq: usize,
) -> Result<(CouplingTensor, CosineTables), ParamError> {
    let m_max = labels.iter().map(|l| l.0).max().unwrap_or(1) as usize;
    let n_max = labels.iter().map(|l| l.1).max().unwrap_or(1) as usize;
    let (ka, kb) = (2 * m_max, 2 * n_max);
    let (na, nb) = (ka + 1, kb + 1);
    let gx: Vec<Vec<f64>> = (0..2)
        .map(|p| cosine_table(&airy.bx[p], 1.0, p, ka, nq))
        .collect();
    let gy: Vec<Vec<f64>> = (0..2)
        .map(|p| cosine_table(&airy.by[p], aspect, p, kb, nq))
        .collect();

    // Allowed pairs of each parity class, with A, B and the cosine indices.
    let mut pairs: [Vec<Pair>; 4] = Default::default();
    for (i, &li) in labels.iter().enumerate() {
        for (j, &lj) in labels[..=i].iter().enumerate() {
            let (a, b) = factors(aspect, li, lj);
            pairs[pair_class(li, lj)].push(Pair {
                i: i as u32,
                j: j as u32,
                a,
                b,
                dm: li.0.abs_diff(lj.0),
                sm: li.0 + lj.0,
                dn: li.1.abs_diff(lj.1),
                sn: li.1 + lj.1,
            });
        }
    }

    let n_psi = airy.modes.len();
    let counts: Vec<usize> = airy.modes.iter().map(|m| pairs[m.class].len()).collect();
    let total: usize = counts.iter().sum();
    let mut row_start = vec![0u32; n_psi + 1];
    for (l, &c) in counts.iter().enumerate() {
        row_start[l + 1] = row_start[l] + c as u32;
    }
    let (mut out_i, mut out_j, mut out_v) =
        (vec![0u32; total], vec![0u32; total], vec![0.0; total]);
    // Disjoint output chunks, one per l, filled in parallel.
    let mut chunks = Vec::with_capacity(n_psi);
    let (mut ri, mut rj, mut rv) = (&mut out_i[..], &mut out_j[..], &mut out_v[..]);
    for &c in &counts {
        let (ci, ti) = ri.split_at_mut(c);
        let (cj, tj) = rj.split_at_mut(c);
        let (cv, tv) = rv.split_at_mut(c);
        chunks.push((ci, cj, cv));
        (ri, rj, rv) = (ti, tj, tv);
    }
    let transforms: Vec<Vec<f64>> = (0..n_psi)
        .into_par_iter()
        .map(|l| {
            let class = airy.modes[l].class;
            cosine_transform(airy, l, &gx[class / 2], &gy[class % 2], na, nb)
        })
        .collect();
    chunks
        .into_par_iter()
        .enumerate()
        .for_each(|(l, (ci, cj, cv))| {
            let mode = &airy.modes[l];
            let t = &transforms[l];
            let tt = |a: u32, b: u32| t[a as usize * nb + b as usize];
            for (k, pr) in pairs[mode.class].iter().enumerate() {
                ci[k] = pr.i;
                cj[k] = pr.j;
                cv[k] = combine(
                    aspect,
                    pr.a,
                    pr.b,
                    [
                        tt(pr.dm, pr.dn),
                        tt(pr.dm, pr.sn),
                        tt(pr.sm, pr.dn),
                        tt(pr.sm, pr.sn),
                    ],
                );
            }
        });
    let tensor = CouplingTensor::from_parts(labels.len(), n_psi, row_start, out_i, out_j, out_v)?;
    Ok((tensor, CosineTables { na, nb, transforms }))
}

/// Parity class `2 px + py` of the product `Φ_i Φ_j` (and of `L(Φ_i, Φ_j)`) about the centre
/// lines: `px = (m_i + m_j) mod 2`, `py = (n_i + n_j) mod 2`, 0 = even.
pub(crate) fn pair_class(li: (u32, u32), lj: (u32, u32)) -> usize {
    (((li.0 + lj.0) % 2) * 2 + (li.1 + lj.1) % 2) as usize
}

/// `A = κ_i²μ_j² + μ_i²κ_j²` and `B = 2κ_iμ_iκ_jμ_j`, written as products of squares and of
/// the pair products so that swapping `i` and `j` gives bitwise the same values (IEEE `+`, `×`
/// are commutative): the symmetry `H^l_ij = H^l_ji` is exact.
fn factors(aspect: f64, li: (u32, u32), lj: (u32, u32)) -> (f64, f64) {
    let (ki, ui) = (f64::from(li.0) * PI, f64::from(li.1) * PI / aspect);
    let (kj, uj) = (f64::from(lj.0) * PI, f64::from(lj.1) * PI / aspect);
    let a = (ki * ki) * (uj * uj) + (ui * ui) * (kj * kj);
    let b = 2.0 * ((ki * ui) * (kj * uj));
    (a, b)
}

/// `H = (N²/4)[A (T_dd - T_ds - T_sd + T_ss) - B (T_dd + T_ds + T_sd + T_ss)]`, `N²/4 = 1/aspect`.
fn combine(aspect: f64, a: f64, b: f64, [dd, ds, sd, ss]: [f64; 4]) -> f64 {
    (a * (dd - ds - sd + ss) - b * (dd + ds + sd + ss)) / aspect
}

/// `T_l[a nb + b] = ∫ Ψ_l cos(aπx) cos(bπy/aspect) dS` for `a < na`, `b < nb` of Ψ_l's parities
/// (other entries 0): `W = c_l Gy`, `T = Gxᵀ W`.
fn cosine_transform(
    airy: &AiryModes,
    l: usize,
    gxp: &[f64],
    gyp: &[f64],
    na: usize,
    nb: usize,
) -> Vec<f64> {
    let mode = &airy.modes[l];
    let (px, py) = (mode.class / 2, mode.class % 2);
    let (nx, ny) = (airy.bx[px].len_basis(), airy.by[py].len_basis());
    let mut wpb = vec![0.0; nx * nb];
    for p in 0..nx {
        for q in 0..ny {
            let c = mode.coef[p * ny + q];
            for b in (py..nb).step_by(2) {
                wpb[p * nb + b] += c * gyp[q * nb + b];
            }
        }
    }
    let mut t = vec![0.0; na * nb];
    for p in 0..nx {
        for a in (px..na).step_by(2) {
            let g = gxp[p * na + a];
            for b in (py..nb).step_by(2) {
                t[a * nb + b] += g * wpb[p * nb + b];
            }
        }
    }
    t
}

/// The cosine transforms `T_l` (`na × nb` each), kept to evaluate single entries on demand
/// (`8 na nb N_Ψ` bytes: 6.8 MB for the lecture's 800-mode plate).
#[derive(Debug, Clone)]
pub(crate) struct CosineTables {
    na: usize,
    nb: usize,
    transforms: Vec<Vec<f64>>,
}

impl CosineTables {
    /// `H^l_ij` for any order of `i, j` by the same arithmetic as [`build`] (0 exactly when
    /// the parity rule forbids it); `None` if `2 max(m)`/`2 max(n)` exceed the tables.
    pub fn entry(
        &self,
        aspect: f64,
        airy: &AiryModes,
        l: usize,
        li: (u32, u32),
        lj: (u32, u32),
    ) -> Option<f64> {
        let mode = &airy.modes[l];
        if pair_class(li, lj) != mode.class {
            return Some(0.0);
        }
        let (sm, sn) = ((li.0 + lj.0) as usize, (li.1 + lj.1) as usize);
        if sm >= self.na || sn >= self.nb {
            return None;
        }
        let t = &self.transforms[l];
        let tt = |a: u32, b: u32| t[a as usize * self.nb + b as usize];
        let (dm, dn) = (li.0.abs_diff(lj.0), li.1.abs_diff(lj.1));
        let (sm, sn) = (sm as u32, sn as u32);
        let (a, b) = factors(aspect, li, lj);
        Some(combine(
            aspect,
            a,
            b,
            [tt(dm, dn), tt(dm, sn), tt(sm, dn), tt(sm, sn)],
        ))
    }
}
