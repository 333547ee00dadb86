//! Assembly of the coupling tensor `H^l_{ij} = ∫_S Ψ_l L(Φ_i, Φ_j) dS` of the circular plate.
//!
//! Polar form of the von Kármán operator (Touzé, Thomas & Chaigne, JSV 258(4), 2002, eq. 3;
//! Ducceschi & Touzé, JSV 344, 2015, eq. 2):
//! `L(f, g) = f_rr (g_r/r + g_θθ/r²) + g_rr (f_r/r + f_θθ/r²)
//!           - 2 (f_rθ/r - f_θ/r²)(g_rθ/r - g_θ/r²)`.
//! For `f = R_i(r) a_i(θ)`, `g = R_j(r) a_j(θ)` with `a = cos nθ` or `sin nθ`:
//! `L = (A_i B_j + A_j B_i) a_i a_j - 2 C_i C_j a_i' a_j'`, where `A = R''`,
//! `B = R'/r - n² R/r²`, `C = R'/r - R/r²`. Hence
//! `H^l_{ij} = T1 ∫_0^1 R_l (A_i B_j + A_j B_i) r dr - 2 T2 ∫_0^1 R_l C_i C_j r dr`,
//! with the exact angular factors `T1 = ∫ a_l a_i a_j dθ`, `T2 = ∫ a_l a_i' a_j' dθ`
//! ([`super::angular::factors`]). Both vanish unless `n_l = n_i + n_j` or
//! `n_l = |n_i - n_j|` and the number of sine factors is even: those entries are never
//! computed. The radial integrals use one Gauss-Legendre rule; each radial function (one per
//! `(n, k)`, shared by its cos and sin modes) is sampled once on that grid, and each radial
//! integral is computed once per triple of radial functions and reused for the up to eight
//! parity combinations.
//!
//! Runs on the calling worker thread plus scoped helper threads (`std::thread::scope`,
//! one per available core); allocates.

use super::angular::{factors, Parity};
use super::modes::Mode;
use crate::error::ParamError;
use crate::modal::quadrature::GaussLegendre;
use crate::modal::tensor::CouplingTensor;
use std::sync::atomic::{AtomicUsize, Ordering};

/// One stored entry `(i, j, H^l_ij)` with `j ≤ i`.
type Entry = (u32, u32, f64);
/// The entries of the row of in-plane mode `l` (first field).
type Row = (usize, Vec<Entry>);

/// Radial functions with their modes: `(index of first mode, modes (index, parity))`.
struct Class {
    n: u32,
    modes: Vec<(u32, Parity)>,
}

/// Groups modes by radial function `(n, k)`, in order of first appearance.
fn classes(modes: &[Mode]) -> Vec<Class> {
    let mut out: Vec<Class> = Vec::new();
    let mut key: Vec<(u32, u32)> = Vec::new();
    for (idx, m) in modes.iter().enumerate() {
        match key.iter().position(|&k| k == (m.n, m.k)) {
            Some(c) => out[c].modes.push((idx as u32, m.parity)),
            None => {
                key.push((m.n, m.k));
                out.push(Class {
                    n: m.n,
                    modes: vec![(idx as u32, m.parity)],
                });
            }
        }
    }
    out
}

/// First radial representative of each class.
fn representative<'a>(modes: &'a [Mode], cls: &[Class]) -> Vec<&'a Mode> {
    cls.iter().map(|c| &modes[c.modes[0].0 as usize]).collect()
}

/// Assembles `H` for the given transverse modes `phi`, in-plane modes `psi` and a
/// Gauss-Legendre rule with `quad_points` points on `[0, 1]`.
pub fn assemble(
    phi: &[Mode],
    psi: &[Mode],
    quad_points: usize,
) -> Result<CouplingTensor, ParamError> {
    let gl = GaussLegendre::new(quad_points)?;
    let q = gl.len();
    let pc = classes(phi);
    let sc = classes(psi);
    // Sample A, B, C of each Φ radial function, and W = w r R of each Ψ radial function.
    let mut a = vec![0.0; pc.len() * q];
    let mut b = vec![0.0; pc.len() * q];
    let mut c = vec![0.0; pc.len() * q];
    for (ci, m) in representative(phi, &pc).into_iter().enumerate() {
        let n2 = (m.n as f64).powi(2);
        for (k, &r) in gl.nodes.iter().enumerate() {
            let [r0, r1, r2] = m.radial.eval(r);
            a[ci * q + k] = r2;
            b[ci * q + k] = r1 / r - n2 * r0 / (r * r);
            c[ci * q + k] = r1 / r - r0 / (r * r);
        }
    }
    let mut w = vec![0.0; sc.len() * q];
    for (li, m) in representative(psi, &sc).into_iter().enumerate() {
        for (k, (&r, &wt)) in gl.nodes.iter().zip(&gl.weights).enumerate() {
            w[li * q + k] = wt * r * m.radial.eval(r)[0];
        }
    }
    let max_n = pc.iter().map(|c| c.n).max().unwrap_or(0);
    let mut by_n: Vec<Vec<usize>> = vec![Vec::new(); max_n as usize + 1];
    for (ci, cl) in pc.iter().enumerate() {
        by_n[cl.n as usize].push(ci);
    }

    // One task per Ψ class; rows of its (one or two) modes.
    let next = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
        .min(sc.len().max(1));
    let mut rows: Vec<Vec<Entry>> = vec![Vec::new(); psi.len()];
    let results: Vec<Vec<Row>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                s.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let li = next.fetch_add(1, Ordering::Relaxed);
                        if li >= sc.len() {
                            break;
                        }
                        let wl = &w[li * q..(li + 1) * q];
                        for (mode, entries) in
                            psi_class_rows(&sc[li], wl, &pc, &by_n, &a, &b, &c, q)
                        {
                            done.push((mode, entries));
                        }
                    }
                    done
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("assembly thread panicked"))
            .collect()
    });
    for (mode, entries) in results.into_iter().flatten() {
        rows[mode] = entries;
    }
    let nnz: usize = rows.iter().map(Vec::len).sum();
    let mut row_start = Vec::with_capacity(psi.len() + 1);
    let (mut vi, mut vj, mut vv) = (
        Vec::with_capacity(nnz),
        Vec::with_capacity(nnz),
        Vec::with_capacity(nnz),
    );
    row_start.push(0u32);
    for mut r in rows {
        r.sort_by_key(|e| (e.0, e.1));
        for (i, j, v) in r {
            vi.push(i);
            vj.push(j);
            vv.push(v);
        }
        row_start.push(vi.len() as u32);
    }
    CouplingTensor::from_parts(phi.len(), psi.len(), row_start, vi, vj, vv)
}

/// Entries of the rows of the modes of one Ψ class `l` (weights `wl = w r R_l` on the grid).
#[allow(clippy::too_many_arguments)]
fn psi_class_rows(
    l: &Class,
    wl: &[f64],
    pc: &[Class],
    by_n: &[Vec<usize>],
    a: &[f64],
    b: &[f64],
    c: &[f64],
    q: usize,
) -> Vec<Row> {
    let mut rows: Vec<Row> = l
        .modes
        .iter()
        .map(|&(m, _)| (m as usize, Vec::new()))
        .collect();
    let nl = l.n as i64;
    for (ni, ci_list) in by_n.iter().enumerate() {
        let ni = ni as i64;
        let mut cands = [nl - ni, ni - nl, ni + nl];
        cands.sort_unstable();
        for (k, &nj) in cands.iter().enumerate() {
            if nj < 0 || nj as usize >= by_n.len() || (k > 0 && cands[k - 1] == nj) {
                continue;
            }
            for &ci in ci_list {
                for &cj in &by_n[nj as usize] {
                    if cj > ci {
                        continue; // each unordered class pair once
                    }
                    radial_block(l, wl, &pc[ci], &pc[cj], ci, cj, a, b, c, q, &mut rows);
                }
            }
        }
    }
    rows
}

/// Radial integrals of the class triple (l; ci, cj) and the entries of every parity combination.
#[allow(clippy::too_many_arguments)]
fn radial_block(
    l: &Class,
    wl: &[f64],
    pi: &Class,
    pj: &Class,
    ci: usize,
    cj: usize,
    a: &[f64],
    b: &[f64],
    c: &[f64],
    q: usize,
    rows: &mut [Row],
) {
    // Angular factors first: skip the radial work when every combination vanishes.
    let mut any = false;
    for &(_, pl) in &l.modes {
        for &(_, p1) in &pi.modes {
            for &(_, p2) in &pj.modes {
                let (t1, t2) = factors((l.n, pl), (pi.n, p1), (pj.n, p2));
                any |= t1 != 0.0 || t2 != 0.0;
            }
        }
    }
    if !any {
        return;
    }
    let (ai, bi, cci) = (&a[ci * q..][..q], &b[ci * q..][..q], &c[ci * q..][..q]);
    let (aj, bj, ccj) = (&a[cj * q..][..q], &b[cj * q..][..q], &c[cj * q..][..q]);
    let (mut s1, mut s2) = (0.0, 0.0);
    for k in 0..q {
        s1 += wl[k] * (ai[k] * bj[k] + aj[k] * bi[k]);
        s2 += wl[k] * cci[k] * ccj[k];
    }
    for (row, &(_, pl)) in rows.iter_mut().zip(&l.modes) {
        for &(mi, p1) in &pi.modes {
            for &(mj, p2) in &pj.modes {
                if ci == cj && mj > mi {
                    continue; // same class: unordered mode pairs once
                }
                let (t1, t2) = factors((l.n, pl), (pi.n, p1), (pj.n, p2));
                if t1 == 0.0 && t2 == 0.0 {
                    continue;
                }
                let v = t1 * s1 - 2.0 * t2 * s2;
                let (hi, lo) = if mi >= mj { (mi, mj) } else { (mj, mi) };
                row.1.push((hi, lo, v));
            }
        }
    }
}
