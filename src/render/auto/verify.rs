//! Verification of `quality = "auto"`: render an excerpt of the full model, then the
//! candidates of [`super::plan`] from the cheapest (estimated) upward, and keep the first whose
//! log-spectral distance (and, when set, relative L2 error over the first 50 ms) against the
//! full model is within the scene's tolerance on every pickup. If none is, the full model is
//! kept and the report says so. Every candidate tried is reported with its measured errors and
//! wall time.
//!
//! Runs on the CLI thread, its renders on rayon's threads (allocates, renders).

use super::plan::plan;
use super::report::{AutoReport, CandidateResult};
use super::size::ModelSize;
use crate::error::Error;
use crate::render::metrics::{log_spectral_distance, relative_l2, L2_SECONDS};
use crate::render::offline::Rendered;
use crate::render::scene::render_scene;
use crate::scene::{Quality, QualityMode, Scene};
use rayon::prelude::*;
use std::time::Instant;

/// Worst-pickup (log-spectral distance in dB, relative L2 over the first 50 ms) of `r` against
/// `reference`, both at the output rate `rate`.
pub fn distance(r: &Rendered, reference: &Rendered, rate: u32) -> (f64, f64) {
    let n = (L2_SECONDS * rate as f64).round() as usize;
    let (mut lsd, mut l2) = (0.0f64, 0.0f64);
    for (y, x) in r.out.iter().zip(&reference.out) {
        let d = log_spectral_distance(y, x);
        let e = relative_l2(y, x, n);
        // NaN compares false: make it the worst value so it can never pass.
        lsd = if d.is_nan() {
            f64::INFINITY
        } else {
            lsd.max(d)
        };
        l2 = if e.is_nan() { f64::INFINITY } else { l2.max(e) };
    }
    (lsd, l2)
}

fn build_seconds(report: &crate::render::report::RenderReport) -> f64 {
    report
        .details
        .get("modal_seconds")
        .and_then(|v| v.as_f64())
        .unwrap_or(0.0)
}

/// Selects the model of `scene` (a plate or string scene; its `[quality]` table gives the tolerance, the
/// default table with `mode = "auto"` when it has none): returns the report and the reduced
/// scene (full duration, no `[quality]` table) to render. The excerpts render in parallel
/// windows (one render per rayon thread; each render's wall time is measured beside the
/// others); the choice is the sequential search's. `log` receives one line per render read.
pub fn select(scene: &Scene, mut log: impl FnMut(&str)) -> Result<(AutoReport, Scene), Error> {
    let start = Instant::now();
    let q = scene.quality.unwrap_or(Quality {
        mode: QualityMode::Auto,
        ..Quality::default()
    });
    q.validate()?;
    let plan = plan(scene)?;
    let excerpt = q.excerpt_seconds.min(scene.output.seconds);
    let rate = scene.output.sample_rate;
    let short = |size: &ModelSize| -> Result<Scene, Error> {
        let mut s = size.apply(scene)?;
        s.output.seconds = excerpt;
        Ok(s)
    };
    // Renders in windows as wide as rayon's thread count, in parallel, kept in ladder order:
    // the first window holds the full model and the cheapest candidates; the first candidate
    // within tolerance ends the search (the candidates after it in its window are dropped
    // unread, so the result is the sequential search's).
    let width = rayon::current_num_threads().max(2);
    let sizes: Vec<&ModelSize> = std::iter::once(&plan.full)
        .chain(plan.candidates.iter().map(|c| &c.size))
        .collect();
    let mut renders = sizes.chunks(width).flat_map(|window| {
        window
            .par_iter()
            .map(|size| render_scene(&short(size)?, |_| {}))
            .collect::<Vec<Result<_, Error>>>()
    });
    let (full_r, full_rep) = renders.next().expect("the full model's render")?;
    if full_rep.nan_count > 0 {
        return Err(Error::AutoDiverged {
            excerpt_seconds: excerpt,
            non_finite: full_rep.nan_count,
        });
    }
    log(&format!(
        "full model {}: {:.3} s wall for the {excerpt} s excerpt",
        plan.full.label(),
        full_rep.wall_seconds
    ));
    let mut tried = Vec::new();
    let mut chosen: Option<usize> = None;
    for (c, render) in plan.candidates.iter().zip(renders) {
        let (r, rep) = render?;
        let (lsd, l2) = distance(&r, &full_r, rate);
        let passed =
            rep.nan_count == 0 && lsd <= q.tolerance_db && q.l2_tolerance.is_none_or(|t| l2 <= t);
        log(&format!(
            "{}: {:.3} s wall, LSD {lsd:.4} dB, L2(50 ms) {l2:.3e}{}",
            c.size.label(),
            rep.wall_seconds,
            if passed { "  <- within tolerance" } else { "" }
        ));
        tried.push(CandidateResult {
            candidate: c.clone(),
            wall_seconds: rep.wall_seconds,
            build_seconds: build_seconds(&rep),
            lsd_db: lsd,
            l2_50ms: l2,
            passed,
        });
        if passed {
            chosen = Some(tried.len() - 1);
            break;
        }
    }
    let mut reasons = plan.reasons.clone();
    let (size, lsd, l2, wall) = match chosen {
        Some(i) => {
            let t = &tried[i];
            reasons.push(format!(
                "chosen: {} (the cheapest of {} tried within {} dB{}): LSD {:.4} dB, L2(50 ms) \
                 {:.3e} against the full model over {excerpt} s",
                t.candidate.size.label(),
                tried.len(),
                q.tolerance_db,
                q.l2_tolerance
                    .map_or(String::new(), |l| format!(" and L2 {l}")),
                t.lsd_db,
                t.l2_50ms
            ));
            (t.candidate.size, t.lsd_db, t.l2_50ms, t.wall_seconds)
        }
        None => {
            reasons.push(format!(
                "chosen: the full model: none of the {} candidates is within {} dB{}",
                tried.len(),
                q.tolerance_db,
                q.l2_tolerance
                    .map_or(String::new(), |l| format!(" and L2 {l}"))
            ));
            (plan.full, 0.0, 0.0, full_rep.wall_seconds)
        }
    };
    let reduced = size.apply(scene)?;
    let report = AutoReport {
        tolerance_db: q.tolerance_db,
        l2_tolerance: q.l2_tolerance,
        excerpt_seconds: excerpt,
        full: plan.full,
        chosen: size,
        chosen_is_full: chosen.is_none(),
        lsd_db: lsd,
        l2_50ms: l2,
        full_wall_seconds: full_rep.wall_seconds,
        chosen_wall_seconds: wall,
        speedup: if wall > 0.0 {
            full_rep.wall_seconds / wall
        } else {
            f64::INFINITY
        },
        reasons,
        untried: plan.candidates.len() - tried.len(),
        candidates: tried,
        selection_wall_seconds: start.elapsed().as_secs_f64(),
    };
    Ok((report, reduced))
}
