//! Writing a lab run to disk: CSV of the series, JSON summary, PNG figures.
//!
//! Files written into the output folder (created if needed), prefixed with `stem`:
//! - `{stem}.csv`: `t, u, v, energy, dissipated, reference`;
//! - `{stem}.json`: the [`Summary`];
//! - `{stem}-waveform.png`: numerical against reference solution over the first and the last
//!   three periods (short and long times, as on the lecture's slides);
//! - `{stem}-energy.png`: the discrete energy `H(t)` and its relative error `(H - H0)/H0`
//!   (with the dissipated energy added back for damped runs);
//! - `{stem}-phase.png`: phase portrait `(u, v)`.

use super::{Summary, Trace};
use crate::error::Error;
use crate::plot::{write_png, Mark, Panel, Series};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Paths of the files a report wrote.
#[derive(Debug, Clone, Default)]
pub struct Written {
    /// Every file written, in order.
    pub files: Vec<PathBuf>,
}

/// Writes the CSV, JSON and PNG files of a run into `dir`.
pub fn write_report(
    dir: &Path,
    stem: &str,
    trace: &Trace,
    summary: &Summary,
) -> Result<Written, Error> {
    std::fs::create_dir_all(dir).map_err(|source| Error::CreateDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut written = Written::default();
    let csv = dir.join(format!("{stem}.csv"));
    write_csv(&csv, trace).map_err(|source| Error::Write {
        path: csv.clone(),
        source,
    })?;
    written.files.push(csv);
    let json = dir.join(format!("{stem}.json"));
    std::fs::write(&json, serde_json::to_string_pretty(summary)? + "\n").map_err(|source| {
        Error::Write {
            path: json.clone(),
            source,
        }
    })?;
    written.files.push(json);
    let title = format!(
        "{} / {} (h = {})",
        summary.system, summary.scheme, summary.h
    );
    let figures = [
        ("waveform", waveform_panels(trace, summary)),
        ("energy", energy_panels(trace)),
        ("phase", vec![phase_panel(trace)]),
    ];
    for (name, panels) in figures {
        let path = dir.join(format!("{stem}-{name}.png"));
        let cols = if panels.len() > 1 { 2 } else { 1 };
        write_png(&path, &title, &panels, cols, (720, 420))?;
        written.files.push(path);
    }
    Ok(written)
}

fn write_csv(path: &Path, tr: &Trace) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(w, "t,u,v,energy,dissipated,reference")?;
    for i in 0..tr.t.len() {
        let r = tr.reference.as_ref().map_or(f64::NAN, |r| r[i]);
        writeln!(
            w,
            "{:e},{:e},{:e},{:e},{:e},{:e}",
            tr.t[i], tr.u[i], tr.v[i], tr.energy[i], tr.dissipated[i], r
        )?;
    }
    w.flush()
}

/// Number of samples in three periods (or 5 % of the run when there is no period).
fn window(trace: &Trace, summary: &Summary) -> usize {
    let n = trace.t.len();
    let w = match summary.period {
        Some(p) if summary.h > 0.0 => (3.0 * p / summary.h).ceil() as usize,
        _ => n / 20,
    };
    w.clamp(2.min(n), n)
}

fn slice_panel(title: &str, trace: &Trace, range: std::ops::Range<usize>) -> Panel {
    let t = trace.t[range.clone()].to_vec();
    let mut p = Panel::new(title, "t", "u").push(Series::line(
        "numerical",
        t.clone(),
        trace.u[range.clone()].to_vec(),
    ));
    if let Some(r) = &trace.reference {
        p = p.push(Series::line(
            trace.reference_label.clone(),
            t,
            r[range].to_vec(),
        ));
    }
    p
}

fn waveform_panels(trace: &Trace, summary: &Summary) -> Vec<Panel> {
    let n = trace.t.len();
    let w = window(trace, summary);
    vec![
        slice_panel("start of the run", trace, 0..w),
        slice_panel("end of the run", trace, n - w..n),
    ]
}

fn energy_panels(trace: &Trace) -> Vec<Panel> {
    let balance = trace.balance();
    let e0 = balance.first().copied().unwrap_or(0.0);
    let scale = if e0 != 0.0 { e0.abs() } else { 1.0 };
    let rel: Vec<f64> = balance.iter().map(|e| (e - e0) / scale).collect();
    let damped = trace.dissipated.iter().any(|&d| d != 0.0);
    let mut h = Panel::new("discrete energy", "t", "H").push(Series::line(
        "H(t)",
        trace.t.clone(),
        trace.energy.clone(),
    ));
    if damped {
        h = h.push(Series::line(
            "H + dissipated",
            trace.t.clone(),
            balance.clone(),
        ));
    }
    let label = if damped {
        "(H + D - H0)/H0"
    } else {
        "(H - H0)/H0"
    };
    let r = Panel::new("relative energy error", "t", label).push(Series::line(
        label,
        trace.t.clone(),
        rel,
    ));
    vec![h, r]
}

fn phase_panel(trace: &Trace) -> Panel {
    Panel::new("phase portrait", "u", "v")
        .push(Series::line("numerical", trace.u.clone(), trace.v.clone()).with_mark(Mark::Points))
}
