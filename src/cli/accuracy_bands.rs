//! The band-by-band output of `noether accuracy`: for every row (and the floor of a preset
//! study) the distances per third-octave band ([`noether::render::metrics::band_breakdown`]), as
//! a long CSV, a PNG of the distances and the reference's level against frequency, and (with
//! `--per-band`) a table on stderr.

use noether::plot::{write_png, Mark, Panel, Scale, Series};
use noether::render::accuracy::AccuracyStudy;
use noether::render::metrics::BandComparison;
use noether::Error;
use std::path::{Path, PathBuf};

/// One line of the band CSV: a row's setting (or the floor) and one band's figures (the
/// fields of [`BandComparison`]; the CSV writer does not flatten nested structs).
#[derive(serde::Serialize)]
struct BandLine<'a> {
    setting: &'a str,
    centre_hz: f64,
    bins: usize,
    reference_level_db: f64,
    band_db: f64,
    bins_db: f64,
    mean_diff_db: f64,
}

/// The study's band breakdowns, labelled: each row's setting, then the floor's when there is
/// one.
fn labelled(study: &AccuracyStudy) -> Vec<(String, &[BandComparison])> {
    let mut out: Vec<(String, &[BandComparison])> = study
        .rows
        .iter()
        .zip(&study.row_bands)
        .map(|(r, b)| (format!("{} = {}", study.vary, r.setting), b.as_slice()))
        .collect();
    if let Some(f) = &study.sensitivity {
        out.push((f.label(), f.bands.as_slice()));
    }
    out
}

/// Writes `<stem>-bands.csv` and `<stem>-bands.png` and, when `print`, the table; returns the
/// two paths.
pub(super) fn write_band_outputs(
    stem: &Path,
    study: &AccuracyStudy,
    print: bool,
) -> Result<[PathBuf; 2], Error> {
    let name = stem
        .file_name()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
    let csv_path = stem.with_file_name(format!("{name}-bands.csv"));
    let png_path = stem.with_file_name(format!("{name}-bands.png"));
    let sets = labelled(study);
    let lines = sets.iter().flat_map(|(label, bands)| {
        bands.iter().map(move |band| BandLine {
            setting: label,
            centre_hz: band.centre_hz,
            bins: band.bins,
            reference_level_db: band.reference_level_db,
            band_db: band.band_db,
            bins_db: band.bins_db,
            mean_diff_db: band.mean_diff_db,
        })
    });
    super::files::write_csv(&csv_path, lines)?;
    let panel = |title: &str, ylabel: &str, pick: fn(&BandComparison) -> f64| {
        let mut p =
            Panel::new(title, "band centre (Hz)", ylabel).scales(Scale::Log10, Scale::Linear);
        for (label, bands) in &sets {
            p = p.push(
                Series::line(
                    label.clone(),
                    bands.iter().map(|b| b.centre_hz).collect(),
                    bands.iter().map(pick).collect(),
                )
                .with_mark(Mark::LinePoints),
            );
        }
        p
    };
    let mut panels = vec![
        panel(
            "band-level distance per band",
            "RMS over frames (dB)",
            |b| b.band_db,
        ),
        panel(
            "bin-level distance per band",
            "RMS over frames and bins (dB)",
            |b| b.bins_db,
        ),
        panel(
            "mean level against the reference",
            "render - reference, mean over frames (dB)",
            |b| b.mean_diff_db,
        ),
    ];
    if let Some((_, bands)) = sets.first() {
        panels.push(
            Panel::new(
                "the reference's level",
                "band centre (Hz)",
                "dB re its loudest band",
            )
            .scales(Scale::Log10, Scale::Linear)
            .push(
                Series::line(
                    "reference",
                    bands.iter().map(|b| b.centre_hz).collect(),
                    bands.iter().map(|b| b.reference_level_db).collect(),
                )
                .with_mark(Mark::LinePoints),
            ),
        );
    }
    let columns = 2;
    write_png(
        &png_path,
        &format!(
            "{}: distance per third-octave band ({})",
            study.scene, study.reference
        ),
        &panels,
        columns,
        (560, 420),
    )?;
    if print {
        for (label, bands) in &sets {
            eprintln!("{label}:");
            eprintln!(
                "{:>10} {:>6} {:>12} {:>11} {:>11} {:>11}",
                "centre Hz", "bins", "ref level", "bands (dB)", "bins (dB)", "mean (dB)"
            );
            for b in *bands {
                eprintln!(
                    "{:>10.0} {:>6} {:>12.1} {:>11.3} {:>11.3} {:>+11.2}",
                    b.centre_hz, b.bins, b.reference_level_db, b.band_db, b.bins_db, b.mean_diff_db
                );
            }
        }
    }
    Ok([csv_path, png_path])
}
