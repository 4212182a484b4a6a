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

/// How many refined packings are jammed, "k / n" over the rows that recorded it, from the
/// row's `refined_jammed` (the column runs.csv has), or a dash when none did.
fn refined_jammed(rows: &[&RunRecord]) -> String {
    count_of(rows.iter().filter_map(|r| r.refined_jammed))
}

/// How many refined packings are isostatic (`refined_iso_gap` 0), "k / n", or a dash.
fn refined_isostatic(rows: &[&RunRecord]) -> String {
    count_of(
        rows.iter()
            .filter_map(|r| r.refined_iso_gap.map(|g| g == 0)),
    )
}

/// "k / n" of the true values among `known`, or a dash when there are none.
fn count_of(known: impl Iterator<Item = bool>) -> String {
    let (yes, all) = known.fold((0, 0), |(y, a), b| (y + usize::from(b), a + 1));
    if all == 0 {
        "—".into()
    } else {
        format!("{yes} / {all}")
    }
}

/// The N of a method's packings: one number, or "min–max" when they differ.
fn n_range(rows: &[&RunRecord]) -> String {
    let ns = rows.iter().filter(|r| r.made_packing()).map(|r| r.n);
    match (ns.clone().min(), ns.max()) {
        (Some(lo), Some(hi)) if lo == hi => lo.to_string(),
        (Some(lo), Some(hi)) => format!("{lo}–{hi}"),
        _ => "—".into(),
    }
}

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

/// The Markdown report: the scene, the table of mean ± std per method, the refinement,
/// the comparison in words and the figures, each a section of its own.
pub fn markdown(file: &RunsFile, figures: &[(String, String)]) -> String {
    let mut md = String::new();
    scene_section(&mut md, file);
    let summary = method_table(&mut md, file);
    if let Some(refine) = &file.config.refine {
        refinement_table(&mut md, file, refine);
    }
    in_words(&mut md, file, &summary);
    if !figures.is_empty() {
        let _ = writeln!(md, "\n## Figures\n");
        for (path, caption) in figures {
            let _ = writeln!(md, "![{caption}]({path})\n\n*{caption}*\n");
        }
    }
    md
}

/// The title and the scene the starts were drawn from.
fn scene_section(md: &mut String, file: &RunsFile) {
    let c = &file.config;
    let s = &c.scene;
    let _ = writeln!(md, "# packbench comparison\n");
    let _ = writeln!(
        md,
        "Scene: d = {}, N = {} per starting packing, {} (polydispersity set by `{:?}`), container {}, initial φ = {}; {} starting packings (seeds {}–{}){}.\n",
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
}

/// One method's line of the summary, for the words under the tables.
struct MethodSummary {
    method: String,
    phi: Option<(f64, f64)>,
    runtime: Option<(f64, f64)>,
    isostatic: usize,
    packings: usize,
    max_overlap: String,
    failed: usize,
    n: String,
}

/// The table of mean ± std per method; returns each method's summary.
fn method_table(md: &mut String, file: &RunsFile) -> Vec<MethodSummary> {
    let _ = writeln!(
        md,
        "| method | N | runs | failed | φ | z (non-rattlers) | rattlers | iso_gap | isostatic | max overlap | force balance | runtime (s) |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut summary = Vec::new();
    for m in &file.config.methods {
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
        let n = n_range(&rows);
        let _ = writeln!(
            md,
            "| {m} | {n} | {} | {} | {} | {} | {} | {} | {iso}/{} | {ov} | {} | {} |",
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
        summary.push(MethodSummary {
            method: m.clone(),
            phi: mean_std(&phi),
            runtime: mean_std(&rt),
            isostatic: iso,
            packings: ok.len(),
            max_overlap: ov,
            failed: rows.len() - ok.len(),
            n,
        });
    }
    let undefined = file
        .runs
        .iter()
        .any(|r| r.made_packing() && r.iso_gap.is_none());
    if undefined {
        let _ = writeln!(
            md,
            "\n— where a packing has no non-rattlers: its z and iso_gap are undefined (empty in runs.csv, null in runs.json), and such packings are left out of those means."
        );
    }
    summary
}

/// The refinement's table: φ before and after, Δφ, and how many refined packings are jammed
/// and isostatic, counted from the rows' columns.
fn refinement_table(md: &mut String, file: &RunsFile, refine: &str) {
    let _ = writeln!(md, "\n## Refinement with `{refine}`\n");
    if refine == crate::refinement::EXACT {
        let _ = writeln!(md, "{}\n", crate::methods::exact_chain::description());
    }
    let _ = writeln!(
        md,
        "| method | refined by | φ | φ refined | Δφ = φ_refined − φ | max \\|Δφ\\| | refined jammed | refined isostatic | refinement s |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
    for m in &file.config.methods {
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
            "| {m} | {} | {} | {} | {} | {} | {} | {} | {} |",
            if chains.is_empty() {
                refine.to_string()
            } else {
                chains.join(", ")
            },
            fmt_ms(&phi, 5),
            fmt_ms(&rp, 5),
            fmt_ms_sci(&dp),
            fmt_max_abs(dp.iter().copied()),
            refined_jammed(&rows),
            refined_isostatic(&rows),
            fmt_ms(&seconds, 2)
        );
    }
    let _ = writeln!(
        md,
        "\nRefined jammed: the refiner claimed a jammed packing and the core's analysis agrees (no overlap above 1e-9, iso_gap ≥ 0, force balance ≤ 1e-8; runs.csv's `refined_jammed`). A jammed packing may hold a contact more than n_dof at the contact tolerance (iso_gap > 0), so isostatic counts are given apart."
    );
}

/// The comparison in words: densest and loosest, fastest, each method's isostaticity and
/// overlap, methods whose N is their own, and failed or unstarted runs.
fn in_words(md: &mut String, file: &RunsFile, summary: &[MethodSummary]) {
    let _ = writeln!(md, "\n## In words\n");
    let done: Vec<_> = summary.iter().filter(|s| s.phi.is_some()).collect();
    let phi = |s: &MethodSummary| s.phi.map_or(f64::NAN, |p| p.0);
    let best = done.iter().max_by(|a, b| phi(a).total_cmp(&phi(b)));
    let worst = done.iter().min_by(|a, b| phi(a).total_cmp(&phi(b)));
    if let (Some(best), Some(worst)) = (best, worst) {
        let _ = writeln!(
            md,
            "- Densest: **{}** with φ = {:.4}; loosest: **{}** with φ = {:.4} (a spread of {:.4}).",
            best.method,
            phi(best),
            worst.method,
            phi(worst),
            phi(best) - phi(worst)
        );
    }
    let seconds = |s: &MethodSummary| s.runtime.map_or(f64::NAN, |t| t.0);
    if let Some(fast) = done.iter().min_by(|a, b| seconds(a).total_cmp(&seconds(b))) {
        let _ = writeln!(
            md,
            "- Fastest: **{}**, {:.3} s per packing on average.",
            fast.method,
            seconds(fast)
        );
    }
    let scene_n = file.config.scene.n.to_string();
    for s in done.iter().filter(|s| s.n != scene_n && s.n != "—") {
        let _ = writeln!(
            md,
            "- **{}** packs its own N = {}, not the scene's N = {scene_n}: it fills the container with the distribution's sizes instead of taking the starting packing, so its rattler count is out of its own N.",
            s.method, s.n
        );
    }
    for s in &done {
        let verdict = if s.isostatic == s.packings {
            "every packing is isostatic over its non-rattlers"
        } else if s.isostatic == 0 {
            "no packing is isostatic at contact tolerance 1e-6: its gaps or overlaps exceed the tolerance (soft-sphere overlaps, LS gaps, seq-fill's ε-contacts); `--refine` with an exact method closes them"
        } else {
            "some packings are isostatic"
        };
        let _ = writeln!(
            md,
            "- **{}**: {verdict}; largest overlap {}.",
            s.method, s.max_overlap
        );
    }
    failures_in_words(md, file, summary);
}

/// The methods with failed or unstarted runs, in words.
fn failures_in_words(md: &mut String, file: &RunsFile, summary: &[MethodSummary]) {
    for s in summary.iter().filter(|s| s.failed > 0) {
        let not_run = file
            .runs
            .iter()
            .filter(|r| r.method == s.method && r.termination == NOT_RUN)
            .count();
        let failed = s.failed - not_run;
        if failed > 0 {
            let _ = writeln!(
                md,
                "- **{}**: {failed} run(s) failed (no packing, overlaps above {OVERLAP_AT_BUDGET:e} at the step budget, or a jammed packing the analysis contradicts: `not_jammed`); see the `error` and `termination` columns of runs.csv.",
                s.method
            );
        }
        if not_run > 0 {
            let _ = writeln!(
                md,
                "- **{}**: {not_run} run(s) not run: the command was interrupted before they started.",
                s.method
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::args::default_compare_scene;
    use crate::records::CompareConfig;

    fn row(method: &str, seed: u64, n: usize) -> RunRecord {
        RunRecord {
            method: method.into(),
            seed,
            d: 2,
            n,
            phi: Some(0.84),
            z_nonrattler: Some(4.0),
            rattlers: Some(2),
            iso_gap: Some(0),
            isostatic: Some(true),
            max_overlap: Some(0.0),
            force_balance: Some(1e-14),
            termination: "jammed".into(),
            ..RunRecord::default()
        }
    }

    fn file(methods: &[&str], refine: Option<&str>, runs: Vec<RunRecord>) -> RunsFile {
        RunsFile {
            config: CompareConfig {
                scene: default_compare_scene(),
                methods: methods.iter().map(|m| m.to_string()).collect(),
                seeds: 2,
                base_seed: 1,
                refine: refine.map(String::from),
                overrides: Vec::new(),
            },
            shard: (1, 1),
            runs,
        }
    }

    /// The table row of `method` (its cells, trimmed).
    fn cells<'a>(md: &'a str, method: &str) -> Vec<&'a str> {
        let line = md
            .lines()
            .find(|l| l.starts_with(&format!("| {method} |")))
            .unwrap_or_else(|| panic!("no row for {method} in\n{md}"));
        line.split('|').map(str::trim).collect()
    }

    /// A method that packs its own N (seq-fill fills the box) says so: its N is in its row
    /// and in words, not hidden under the scene's N.
    #[test]
    fn a_method_with_its_own_n_shows_it() {
        let runs = vec![
            row("adam", 1, 40),
            row("seq-fill", 1, 444),
            row("adam", 2, 40),
            row("seq-fill", 2, 435),
        ];
        let md = markdown(&file(&["adam", "seq-fill"], None, runs), &[]);
        assert_eq!(cells(&md, "adam")[2], "40");
        assert_eq!(cells(&md, "seq-fill")[2], "435–444");
        assert!(
            md.contains("**seq-fill** packs its own N = 435–444, not the scene's N = 40"),
            "{md}"
        );
        assert!(!md.contains("**adam** packs its own"), "{md}");
    }

    /// A packing with no non-rattlers has no iso_gap: a dash and a note, not "0.0 ± 0.0".
    #[test]
    fn an_undefined_iso_gap_is_a_dash_with_a_note() {
        let mut dilute = row("ls", 1, 40);
        (dilute.rattlers, dilute.iso_gap, dilute.z_nonrattler) = (Some(40), None, None);
        dilute.isostatic = Some(false);
        let md = markdown(&file(&["ls"], None, vec![dilute]), &[]);
        let c = cells(&md, "ls");
        assert_eq!((c[6], c[8]), ("—", "—"), "{md}");
        assert!(md.contains("its z and iso_gap are undefined"), "{md}");
    }

    /// report.md counts refined jammed packings from the column runs.csv writes, so the two
    /// agree: two jammed refinements, one of them with a contact over n_dof (iso_gap 1).
    #[test]
    fn the_refinement_counts_agree_with_the_csv() {
        let refined = |seed, gap| RunRecord {
            delta_phi: Some(1e-3),
            refined_phi: Some(0.841),
            refined_termination: Some("jammed".into()),
            refined_iso_gap: Some(gap),
            refined_force_balance: Some(6e-14),
            refined_jammed: Some(true),
            refined_by: Some("closest-jammed".into()),
            ..row("fire", seed, 40)
        };
        let runs = vec![refined(1, 0), refined(2, 1)];
        let f = file(&["fire"], Some("closest-jammed"), runs.clone());
        let md = markdown(&f, &[]);
        let csv = runs_csv(&runs).unwrap();
        let mut reader = csv::Reader::from_reader(csv.as_bytes());
        let col = reader
            .headers()
            .unwrap()
            .iter()
            .position(|h| h == "refined_jammed")
            .expect("a refined_jammed column");
        let jammed_in_csv = reader
            .records()
            .filter(|r| &r.as_ref().unwrap()[col] == "true")
            .count();
        let table = md.split("## Refinement").nth(1).unwrap();
        let c = cells(table, "fire");
        assert_eq!(c[7], format!("{jammed_in_csv} / 2"), "{md}");
        assert_eq!(c[8], "1 / 2", "{md}");
    }
}
