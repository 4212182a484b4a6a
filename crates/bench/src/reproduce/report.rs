//! The outputs of a reproduction besides its rows: `report.md`, each published value beside
//! its recomputation, and `figures/reproduce.png`.

use std::fmt::Write as _;
use std::path::Path;

use packbench_core::format::write_atomic;

use super::published::Band;
use super::rows::ReproduceRow;
use super::{Case, Estimate, Recompute, ReproduceConfig, Table};
use crate::error::BenchError;
use crate::figures::{ReproducePoint, reproduce_figure};
use crate::shards::is_finished;

/// One cell as reported.
pub struct CellResult {
    pub case: usize,
    pub quantity: &'static str,
    pub published: Option<f64>,
    pub recomputed: Option<Estimate>,
    /// Why there is no recomputed value.
    pub not_run: Option<String>,
    pub note: Option<&'static str>,
    /// The band fixed by the published file (see [`super::Cell::band`]).
    pub band: Option<Band>,
    /// Why the value is known to fall outside its band (from the published file).
    pub disagrees: Option<String>,
}

/// Where a recomputed value lies against its band.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Inside, as expected.
    Inside,
    /// Outside, where the published file expects it inside.
    Outside,
    /// Outside, as the published file expects (its reason is in the note).
    KnownOutside,
    /// Inside, where the published file expects it outside: its reason no longer holds.
    UnexpectedlyInside,
}

impl Verdict {
    /// The text of the report's column.
    pub fn text(self) -> &'static str {
        match self {
            Verdict::Inside => "inside",
            Verdict::Outside => "OUTSIDE",
            Verdict::KnownOutside => "outside (known)",
            Verdict::UnexpectedlyInside => "inside (expected outside)",
        }
    }
}

impl CellResult {
    /// The recomputed value against its band, when both are there.
    pub fn verdict(&self) -> Option<Verdict> {
        let inside = self.band?.contains(self.recomputed?.value);
        Some(match (inside, self.disagrees.is_some()) {
            (true, false) => Verdict::Inside,
            (false, false) => Verdict::Outside,
            (false, true) => Verdict::KnownOutside,
            (true, true) => Verdict::UnexpectedlyInside,
        })
    }

    /// (recomputed − published) / standard error, when all three are there and the error is
    /// not zero.
    pub fn deviation(&self) -> Option<f64> {
        let e = self.recomputed?;
        let se = e.std_error.filter(|&s| s > 0.0)?;
        Some((e.value - self.published?) / se)
    }
}

/// Every cell of `cases` recomputed from `rows`.
pub fn results(cases: &[Case], rows: &[ReproduceRow]) -> Vec<CellResult> {
    let mut out = Vec::new();
    for (c, case) in cases.iter().enumerate() {
        let mine: Vec<&ReproduceRow> = rows
            .iter()
            .filter(|r| r.case == case.label && is_finished(&r.record))
            .collect();
        for cell in &case.cells {
            let (recomputed, not_run) = match &cell.recompute {
                Recompute::Value(v) => (
                    Some(Estimate {
                        value: *v,
                        std_error: None,
                        runs: 0,
                    }),
                    None,
                ),
                Recompute::NotRun(why) => (None, Some(format!("not run: {why}"))),
                Recompute::Runs(stat, field) => {
                    let values: Vec<f64> =
                        mine.iter().filter_map(|r| field.of(&r.record)).collect();
                    let e = stat.estimate(&values);
                    let why = e.is_none().then(|| {
                        if mine.is_empty() {
                            "not run: no finished run of this case in this folder".to_string()
                        } else {
                            format!("no packing: all {} runs failed (see runs.csv)", mine.len())
                        }
                    });
                    (e, why)
                }
            };
            out.push(CellResult {
                case: c,
                quantity: cell.quantity,
                published: cell.published,
                recomputed,
                not_run,
                note: cell.note,
                band: cell.band,
                disagrees: cell.disagrees.clone(),
            });
        }
    }
    out
}

fn num(v: f64) -> String {
    if v.abs() >= 100.0 {
        format!("{v:.0}")
    } else {
        format!("{v:.4}")
    }
}

/// The recomputed column: value ± standard error (runs).
fn recomputed_text(e: &Estimate) -> String {
    let v = num(e.value);
    match (e.std_error, e.runs) {
        (_, 0) => v,
        (Some(se), k) if e.value.abs() >= 100.0 => format!("{v} ± {se:.0} ({k})"),
        (Some(se), k) => format!("{v} ± {se:.4} ({k})"),
        (None, k) => format!("{v} ({k})"),
    }
}

/// The report's table line of cell `r` of case `label`.
fn table_line(label: &str, r: &CellResult) -> String {
    let note = [
        r.not_run.clone(),
        r.note.map(str::to_string),
        r.disagrees
            .as_ref()
            .map(|w| format!("known disagreement: {w}")),
    ]
    .into_iter()
    .flatten()
    .collect::<Vec<_>>()
    .join("; ");
    format!(
        "| {label} | {} | {} | {} | {} | {} | {} | {note} |",
        r.quantity,
        r.published.map_or("—".into(), num),
        r.band
            .map_or("—".into(), |b| format!("[{}, {}]", num(b.lo), num(b.hi))),
        r.recomputed
            .as_ref()
            .map_or("not run".into(), recomputed_text),
        r.deviation().map_or("—".into(), |d| format!("{d:+.1}")),
        r.verdict().map_or("—", Verdict::text),
    )
}

/// The Markdown report.
pub fn markdown(
    table: &Table,
    config: &ReproduceConfig,
    shard: (usize, usize),
    cases: &[Case],
    cells: &[CellResult],
    rows: &[ReproduceRow],
    figures: &[(String, String)],
) -> String {
    let mut md = String::new();
    let _ = writeln!(md, "# packbench reproduce {}\n", table.name);
    let _ = writeln!(md, "Source: {}.\n", table.source);
    let _ = writeln!(md, "Protocol: {}.\n", table.protocol);
    let size = match (config.n, table.published_n) {
        (Some(n), Some(p)) => format!("N = {n} (the publication's N = {p})"),
        (Some(n), None) => {
            format!("N = {n} (the publication's values are its own N or large-N limits)")
        }
        (None, _) => "N set by each case's domain, as in the publication".into(),
    };
    let _ = writeln!(
        md,
        "{size}; {} seeds ({}–{}){}.\n",
        config.seeds,
        config.base_seed,
        config.base_seed + config.seeds - 1,
        if shard.1 > 1 {
            format!("; this folder is shard {}/{}", shard.0, shard.1)
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        md,
        "Recomputed: the mean over the seeds ± its standard error (std/√k), or for the edge of a \
         distribution (lowest, highest) the extreme of the seeds ± its exact bootstrap standard \
         error; (k) runs. Δ/SE = (recomputed − published) / standard error. Every metric is the \
         core's analysis, as in `packbench compare`.\n"
    );
    let _ = writeln!(
        md,
        "Band: fixed by the published file before any run (`crates/bench/data/published/`, whose \
         header gives the source of each part): the published value ± (its published uncertainty \
         + a finite-size allowance at this N). A value outside is reported outside, never \
         widened; \"outside (known)\" is a disagreement the file expects, its reason in the note.\n"
    );
    let _ = writeln!(
        md,
        "| case | quantity | published | band | recomputed | Δ/SE | verdict | note |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    for r in cells {
        let _ = writeln!(md, "{}", table_line(&cases[r.case].label, r));
    }
    let failed: Vec<&ReproduceRow> = rows
        .iter()
        .filter(|r| is_finished(&r.record) && !r.record.made_packing())
        .collect();
    let total: f64 = rows.iter().map(|r| r.total_s).sum();
    let _ = writeln!(
        md,
        "\n{} runs, {} failed, {total:.1} s summed over the runs (each run's wall time, a chained \
         method included: runs.csv's `total_s`; every row is there).",
        rows.len(),
        failed.len()
    );
    for r in failed {
        let _ = writeln!(
            md,
            "- {} seed {}: {} ({})",
            r.case,
            r.record.seed,
            r.record.termination,
            r.record.error.as_deref().unwrap_or("no packing")
        );
    }
    for (path, caption) in figures {
        let _ = writeln!(md, "\n![{caption}]({path})\n\n*{caption}*");
    }
    md
}

/// Writes `report.md` and the figure into `out`.
///
/// Errors: a run error when a file cannot be written or the figure drawn.
pub fn write_report(
    out: &Path,
    table: &Table,
    config: &ReproduceConfig,
    shard: (usize, usize),
    cases: &[Case],
    rows: &[ReproduceRow],
) -> Result<Vec<CellResult>, BenchError> {
    let cells = results(cases, rows);
    let mut quantities: Vec<String> = Vec::new();
    for c in &cells {
        if !quantities.iter().any(|q| q == c.quantity) {
            quantities.push(c.quantity.to_string());
        }
    }
    let points: Vec<ReproducePoint> = cells
        .iter()
        .map(|c| ReproducePoint {
            case: c.case,
            quantity: quantities.iter().position(|q| q == c.quantity).unwrap_or(0),
            published: c.published,
            recomputed: c.recomputed.map(|e| (e.value, e.std_error)),
        })
        .collect();
    let labels: Vec<String> = cases.iter().map(|c| c.label.clone()).collect();
    let title = format!("packbench reproduce {}", table.name);
    let figures = reproduce_figure(out, &title, table.axis, &labels, &quantities, &points)?;
    let md = markdown(table, config, shard, cases, &cells, rows, &figures);
    write_atomic(&out.join("report.md"), md.as_bytes())?;
    Ok(cells)
}
