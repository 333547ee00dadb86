//! The table and figure of `docs/models.md` ("Curved plates: the backbone"), from the
//! helpers of `plate_shell_backbone.rs`: ignored tests that print (and draw) what the
//! documentation quotes.

use super::*;
use noether::plot::{write_png, Mark, Panel, Series};

/// The table of `docs/models.md` ("Curved plates: the backbone"): for each `κ`, `ω`,
/// `|α̃| = |α| TH`, `Γ̃ = Γ TH²`, `T̃ = T TH²` single-mode, normal form and measured (started
/// on the manifold, and plainly), and the sign changes by bisection.
/// `cargo test --test plates plate_shell_backbone::table -- --ignored --nocapture`.
#[test]
#[ignore = "prints the table of docs/models.md (about 15 s)"]
fn table() {
    let modes = basis(160, 80);
    println!("| κ | ω | ω_m/ω nearest 2 | α̃ | Γ̃ | T̃ single mode | T̃ normal form | T̃ model | T̃ model, plain start | type |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for kappa in [0.0, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0, 50.0] {
        let axi = Axi::new(&modes, kappa);
        let (w, alpha, gamma) = axi.single_mode();
        let t1 = t_single(w, alpha, gamma) * TH * TH;
        let tn = axi.t_normal_form() * TH * TH;
        let a1 = (2e-4 / tn.abs()).sqrt().clamp(0.002, 0.3);
        let tm = measured_t(&axi, a1, 60.0, 400.0, Start::Manifold);
        let tp = measured_t(&axi, a1, 60.0, 400.0, Start::Plain);
        let near = axi.omega_shell[1..]
            .iter()
            .map(|&wm| wm / w)
            .min_by(|x, y| (x - 2.0).abs().total_cmp(&(y - 2.0).abs()))
            .unwrap();
        let kind = if tm > 0.0 { "hardening" } else { "softening" };
        println!(
            "| {kappa} | {w:.3} | {near:.3} | {:.1} | {:.2} | {t1:.4} | {tn:.4} | {tm:.4} | {tp:.4} | {kind} |",
            (alpha * TH).abs(),
            gamma * TH * TH
        );
    }
    let single = |k: f64| {
        let (w, a, g) = Axi::new(&modes, k).single_mode();
        t_single(w, a, g)
    };
    let k1 = sign_change(0.5, 3.0, 1e-4, single);
    let kn = sign_change(0.5, 3.0, 1e-4, |k| Axi::new(&modes, k).t_normal_form());
    let km = sign_change(0.5, 3.0, 2e-3, |k| {
        measured_t(&Axi::new(&modes, k), 0.2, 60.0, 400.0, Start::Manifold)
    });
    println!("sign change: single mode κ = {k1:.4}, normal form {kn:.4}, model {km:.4}");
    let fine = basis(320, 160);
    let kn2 = sign_change(0.5, 3.0, 1e-4, |k| Axi::new(&fine, k).t_normal_form());
    let (r2, e2) = resonance_window(&fine, 1, 5.0, 7.0);
    let t50 = Axi::new(&fine, 50.0).t_normal_form() * TH * TH;
    println!("basis 320 × 160: normal form κ = {kn2:.4}, (0,2) window {r2:.5} to {e2:.5}, T̃(50) {t50:.5}");
    for (m, lo, hi) in [
        (1, 5.0, 7.0),
        (2, 10.0, 20.0),
        (3, 20.0, 35.0),
        (4, 35.0, 50.0),
    ] {
        let (k_res, k_end) = resonance_window(&modes, m, lo, hi);
        let t = |k: f64| measured_t(&Axi::new(&modes, k), 0.002, 60.0, 400.0, Start::Manifold);
        let start = k_res + 0.1 * (k_end - k_res);
        let km = if t(start) > 0.0 {
            format!("{:.5}", sign_change(start, hi, 1e-6, t))
        } else {
            format!("not resolved (T̃ {:.4} at {start:.5})", t(start))
        };
        println!(
            "(0,{}) 2:1 resonance κ = {k_res:.5}; hardening up to {k_end:.5} (normal form), \
             {km} (model)",
            m + 1
        );
    }
}

/// The figure `docs/figures/shell-backbone.png`: `T̃` against `κ`, single mode and normal
/// form (every 0.01 in κ; the normal form's poles at the 2:1 internal resonances are clipped
/// to ±0.6), and the simulated model at the table's `κ`. Written where
/// `SHELL_BACKBONE_PNG` points: `SHELL_BACKBONE_PNG=docs/figures/shell-backbone.png cargo
/// test --test plates plate_shell_backbone::table::figure -- --ignored`.
#[test]
#[ignore = "draws the figure of docs/models.md"]
fn figure() {
    let Ok(path) = std::env::var("SHELL_BACKBONE_PNG") else {
        return;
    };
    let modes = basis(160, 80);
    let clip = |t: f64| (t * TH * TH).clamp(-0.6, 0.6);
    let curves = |lo: f64, hi: f64, step: f64| {
        let ks: Vec<f64> = (0..=((hi - lo) / step).round() as usize)
            .map(|i| lo + step * i as f64)
            .collect();
        let (mut t1, mut tn) = (vec![], vec![]);
        for &k in &ks {
            let axi = Axi::new(&modes, k);
            let (w, a, g) = axi.single_mode();
            t1.push(clip(t_single(w, a, g)));
            tn.push(clip(axi.t_normal_form()));
        }
        (ks, t1, tn)
    };
    let mut panels = vec![];
    for (lo, hi, step, title) in [
        (0.0, 50.0, 0.01, "κ from 0 to 50"),
        (
            0.0,
            8.0,
            0.002,
            "κ from 0 to 8: the main transition and the (0,2) window",
        ),
    ] {
        let (ks, t1, tn) = curves(lo, hi, step);
        let pts: Vec<f64> = [0.0, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0, 50.0]
            .into_iter()
            .filter(|&k| k <= hi)
            .collect();
        let tm: Vec<f64> = pts
            .iter()
            .map(|&k| {
                let axi = Axi::new(&modes, k);
                let a1 = (2e-4 / (axi.t_normal_form() * TH * TH).abs())
                    .sqrt()
                    .clamp(0.002, 0.3);
                measured_t(&axi, a1, 60.0, 400.0, Start::Manifold)
            })
            .collect();
        panels.push(
            Panel::new(title, "κ = a²/(Rh)", "T (per thickness²)")
                .push(Series::line("single mode", ks.clone(), t1))
                .push(Series::line("normal form, all quadratic couplings", ks, tn))
                .push(Series::line("simulated model", pts, tm).with_mark(Mark::Points)),
        );
    }
    write_png(
        std::path::Path::new(&path),
        "Fundamental axisymmetric mode of a free spherical cap: backbone ω(A) = ω(1 + T A²)",
        &panels,
        1,
        (1000, 420),
    )
    .unwrap();
}
