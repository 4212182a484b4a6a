//! The outputs of a comparison: `runs.csv`, `runs.json`, `report.md` and `figures/`.

use std::fmt::Write as _;
use std::path::Path;

use packbench_core::format::write_atomic;

use crate::error::BenchError;
use crate::figures;
use crate::outputs::load_packing;
use crate::records::{NOT_RUN, RunRecord, RunsFile, mean_std};
use crate::runs::OVERLAP_AT_BUDGET;

/// Mean ± std with `digits` decimals, or a dash when there are no values.
pub fn fmt_ms(v: &[f64], digits: usize) -> String {
    match mean_std(v) {
        Some((m, s)) => format!("{m:.digits$} ± {s:.digits$}"),
        None => "—".into(),
    }
}

/// Mean ± std in scientific notation (Δφ spans 1e-13 to 1e-2 across methods).
fn fmt_ms_sci(v: &[f64]) -> String {
    match mean_std(v) {
        Some((m, s)) => format!("{m:.2e} ± {s:.1e}"),
        None => "—".into(),
    }
}

/// The largest |value|, or a dash when there is none.
fn fmt_max_abs(v: impl Iterator<Item = f64>) -> String {
    v.map(f64::abs)
        .reduce(f64::max)
        .map_or("—".into(), |x| format!("{x:.1e}"))
}

/// How many refined packings are exactly jammed by the core's analysis (isostatic over
/// non-rattlers and force-balanced to `JAMMED_FORCE_BALANCE`), "k / n", or a dash for outputs
/// that did not record it.
fn refined_jammed(rows: &[&RunRecord]) -> String {
    let known: Vec<_> = rows
        .iter()
        .filter(|r| r.refined_termination.is_some())
        .collect();
    if known.is_empty() {
        return "—".into();
    }
    let jammed = known
        .iter()
        .filter(|r| {
            r.refined_iso_gap == Some(0)
                && r.refined_force_balance
                    .is_some_and(|f| f <= JAMMED_FORCE_BALANCE)
        })
        .count();
    format!("{jammed} / {}", known.len())
}

/// Force-balance residual below which an isostatic packing counts as jammed (1e-8).
const JAMMED_FORCE_BALANCE: f64 = 1e-8;

/// Writes `runs.csv` (the documented columns first) from rows.
pub fn runs_csv(runs: &[RunRecord]) -> Result<String, BenchError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in runs {
        w.serialize(r)
            .map_err(|e| BenchError::Run(format!("writing runs.csv: {e}")))?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| BenchError::Run(format!("writing runs.csv: {e}")))?;
    Ok(String::from_utf8(bytes).expect("csv is UTF-8"))
}

/// Writes every output of a comparison into `out`.
pub fn write_all(out: &Path, file: &RunsFile) -> Result<(), BenchError> {
    write_atomic(&out.join("runs.csv"), runs_csv(&file.runs)?.as_bytes())?;
    let json = serde_json::to_string_pretty(file).map_err(|e| BenchError::Run(e.to_string()))?;
    write_atomic(&out.join("runs.json"), json.as_bytes())?;
    let figs = figures::comparison(out, file, |m, s| load_packing(out, m, s))?;
    write_atomic(&out.join("report.md"), markdown(file, &figs).as_bytes())?;
    Ok(())
}

/// The Markdown report: the table of mean ± std per method and the comparison in words.
pub fn markdown(file: &RunsFile, figures: &[(String, String)]) -> String {
    let c = &file.config;
    let s = &c.scene;
    let mut md = String::new();
    let _ = writeln!(md, "# packbench comparison\n");
    let _ = writeln!(
        md,
        "Scene: d = {}, N = {}, {} (polydispersity set by `{:?}`), container {}, initial φ = {}; {} starting packings (seeds {}–{}){}.\n",
        s.dim(),
        s.n,
        s.distribution.name(),
        s.distribution,
        s.container.describe(),
        s.phi,
        c.seeds,
        c.base_seed,
        c.base_seed + c.seeds - 1,
        if file.shard.1 > 1 {
            format!("; this is shard {}/{}", file.shard.0, file.shard.1)
        } else {
            String::new()
        }
    );
    let _ = writeln!(
        md,
        "All metrics come from the core's analysis (contact tolerance 1e-6), the same for every method.\n"
    );
    if file.runs.iter().any(|r| r.phi.is_some()) {
        let _ = writeln!(
            md,
            "Every packing, side by side with its contacts and metrics, in an interactive page: [viewer.html](viewer.html) (opens from disk in a browser).\n"
        );
    }
    let _ = writeln!(
        md,
        "| method | runs | failed | φ | z (non-rattlers) | rattlers | iso_gap | isostatic | max overlap | force balance | runtime (s) |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|");
    let mut summary = Vec::new();
    for m in &c.methods {
        let rows: Vec<&RunRecord> = file.runs.iter().filter(|r| &r.method == m).collect();
        let ok: Vec<&&RunRecord> = rows.iter().filter(|r| r.made_packing()).collect();
        let phi: Vec<f64> = ok.iter().filter_map(|r| r.phi).collect();
        let z: Vec<f64> = ok.iter().filter_map(|r| r.z_nonrattler).collect();
        let ratt: Vec<f64> = ok
            .iter()
            .filter_map(|r| r.rattlers.map(|x| x as f64))
            .collect();
        let gap: Vec<f64> = ok
            .iter()
            .filter_map(|r| r.iso_gap.map(|x| x as f64))
            .collect();
        let iso = ok.iter().filter(|r| r.isostatic == Some(true)).count();
        let ov = fmt_max_abs(ok.iter().filter_map(|r| r.max_overlap));
        let fb: Vec<f64> = ok.iter().filter_map(|r| r.force_balance).collect();
        let rt: Vec<f64> = rows.iter().map(|r| r.runtime_s).collect();
        let _ = writeln!(
            md,
            "| {m} | {} | {} | {} | {} | {} | {} | {iso}/{} | {ov} | {} | {} |",
            rows.len(),
            rows.len() - ok.len(),
            fmt_ms(&phi, 4),
            fmt_ms(&z, 3),
            fmt_ms(&ratt, 1),
            fmt_ms(&gap, 1),
            ok.len(),
            if fb.is_empty() {
                "—".into()
            } else {
                format!("≤ {:.1e}", fb.iter().cloned().fold(0.0, f64::max))
            },
            fmt_ms(&rt, 2),
        );
        summary.push((
            m.clone(),
            mean_std(&phi),
            mean_std(&rt),
            iso,
            ok.len(),
            ov,
            rows.len() - ok.len(),
        ));
    }
    if let Some(refine) = &c.refine {
        let _ = writeln!(md, "\n## Refinement with `{refine}`\n");
        if refine == crate::refinement::EXACT {
            let _ = writeln!(md, "{}\n", crate::methods::exact_chain::description());
        }
        let _ = writeln!(
            md,
            "| method | refined by | φ | φ refined | Δφ = φ_refined − φ | max \\|Δφ\\| | refined jammed | refinement s |"
        );
        let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
        for m in &c.methods {
            let rows: Vec<&RunRecord> = file
                .runs
                .iter()
                .filter(|r| &r.method == m && r.delta_phi.is_some())
                .collect();
            let phi: Vec<f64> = rows.iter().filter_map(|r| r.phi).collect();
            let rp: Vec<f64> = rows.iter().filter_map(|r| r.refined_phi).collect();
            let dp: Vec<f64> = rows.iter().filter_map(|r| r.delta_phi).collect();
            let seconds: Vec<f64> = rows.iter().filter_map(|r| r.refined_runtime_s).collect();
            let mut chains: Vec<&str> = rows
                .iter()
                .filter_map(|r| r.refined_by.as_deref())
                .collect();
            chains.sort_unstable();
            chains.dedup();
            let _ = writeln!(
                md,
                "| {m} | {} | {} | {} | {} | {} | {} | {} |",
                if chains.is_empty() {
                    refine.clone()
                } else {
                    chains.join(", ")
                },
                fmt_ms(&phi, 5),
                fmt_ms(&rp, 5),
                fmt_ms_sci(&dp),
                fmt_max_abs(dp.iter().copied()),
                refined_jammed(&rows),
                fmt_ms(&seconds, 2)
            );
        }
    }
    let _ = writeln!(md, "\n## In words\n");
    let done: Vec<_> = summary.iter().filter(|s| s.1.is_some()).collect();
    if let Some(best) = done
        .iter()
        .max_by(|a, b| a.1.unwrap().0.total_cmp(&b.1.unwrap().0))
    {
        let worst = done
            .iter()
            .min_by(|a, b| a.1.unwrap().0.total_cmp(&b.1.unwrap().0))
            .unwrap();
        let _ = writeln!(
            md,
            "- Densest: **{}** with φ = {:.4}; loosest: **{}** with φ = {:.4} (a spread of {:.4}).",
            best.0,
            best.1.unwrap().0,
            worst.0,
            worst.1.unwrap().0,
            best.1.unwrap().0 - worst.1.unwrap().0
        );
    }
    if let Some(fast) = done
        .iter()
        .min_by(|a, b| a.2.unwrap().0.total_cmp(&b.2.unwrap().0))
    {
        let _ = writeln!(
            md,
            "- Fastest: **{}**, {:.3} s per packing on average.",
            fast.0,
            fast.2.unwrap().0
        );
    }
    for s in &done {
        let verdict = if s.3 == s.4 {
            "every packing is isostatic over its non-rattlers"
        } else if s.3 == 0 {
            "no packing is isostatic at contact tolerance 1e-6: its gaps or overlaps exceed the tolerance (soft-sphere overlaps, LS gaps, seq-fill's ε-contacts); `--refine` with an exact method closes them"
        } else {
            "some packings are isostatic"
        };
        let _ = writeln!(md, "- **{}**: {verdict}; largest overlap {}.", s.0, s.5);
    }
    for s in summary.iter().filter(|s| s.6 > 0) {
        let not_run = file
            .runs
            .iter()
            .filter(|r| r.method == s.0 && r.termination == NOT_RUN)
            .count();
        let failed = s.6 - not_run;
        if failed > 0 {
            let _ = writeln!(
                md,
                "- **{}**: {failed} run(s) failed (no packing, overlaps above {OVERLAP_AT_BUDGET:e} at the step budget, or a jammed packing the analysis contradicts: `not_jammed`); see the `error` and `termination` columns of runs.csv.",
                s.0
            );
        }
        if not_run > 0 {
            let _ = writeln!(
                md,
                "- **{}**: {not_run} run(s) not run: the command was interrupted before they started.",
                s.0
            );
        }
    }
    if !figures.is_empty() {
        let _ = writeln!(md, "\n## Figures\n");
        for (path, caption) in figures {
            let _ = writeln!(md, "![{caption}]({path})\n\n*{caption}*\n");
        }
    }
    md
}
