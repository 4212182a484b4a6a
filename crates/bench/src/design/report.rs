//! The outputs of a design search beside its rows: `best.json` (the best distribution and its
//! confirmation), `best_diameters.txt` (its diameters, one a line), the figures and
//! `report.md`. Written from rows only, so `merge` writes the same for joined islands.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use packbench_core::Container;
use packbench_core::format::write_atomic;
use packbench_core::geometry::ball_volume;

use super::family::short;
use super::history::{DesignRow, INVALID, RowKind};
use super::search::{candidate_fitness, search_n};
use super::{BestDistribution, DesignConfig};
use crate::error::BenchError;
use crate::figures::{DesignPoint, design_figures};
use crate::records::mean_std;

/// Totals of a search's rows.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Totals {
    /// Candidates proposed by the optimiser.
    pub candidates: usize,
    /// Candidates skipped by the screen or the ratio bound, or invalid.
    pub screened: usize,
    /// Candidates whose values made no distribution (among `screened`), scored infeasible.
    pub invalid: usize,
    /// Packings made by the search.
    pub packings: usize,
    /// Confirmation packings.
    pub confirmations: usize,
    /// Runtime of every packing (wall seconds of each, as in runs.csv), summed.
    pub packing_s: f64,
    /// Of which the search's packings and the confirmation's: the cost of each fidelity.
    pub search_s: f64,
    pub confirm_s: f64,
}

/// The totals of `rows`.
pub fn totals(rows: &[DesignRow]) -> Totals {
    let mut t = Totals::default();
    let mut seen = std::collections::BTreeSet::new();
    for r in rows {
        match r.kind {
            RowKind::Search => {
                if seen.insert((r.island, r.generation, r.candidate)) {
                    t.candidates += 1;
                    if !r.screened.is_empty() {
                        t.screened += 1;
                    }
                    if r.screened == INVALID {
                        t.invalid += 1;
                    }
                }
                if r.screened.is_empty() {
                    t.packings += 1;
                }
                t.search_s += r.record.runtime_s;
            }
            RowKind::Confirm => {
                t.confirmations += 1;
                t.confirm_s += r.record.runtime_s;
            }
        }
        t.packing_s += r.record.runtime_s;
    }
    t
}

/// The history figure's points: each packed candidate in the order of its island's
/// generations, with the packings its island had used by the end of its generation and the
/// φ_J of the island's best candidate so far.
pub fn history_points(config: &DesignConfig, rows: &[DesignRow]) -> Vec<DesignPoint> {
    let mut groups: BTreeMap<(usize, usize, usize), Vec<&DesignRow>> = BTreeMap::new();
    for r in rows.iter().filter(|r| r.kind == RowKind::Search) {
        groups
            .entry((r.island, r.generation, r.candidate))
            .or_default()
            .push(r);
    }
    let mut used: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    for ((i, g, _), rs) in &groups {
        *used.entry((*i, *g)).or_default() += rs.iter().filter(|r| r.screened.is_empty()).count();
    }
    let mut cumulative: BTreeMap<(usize, usize), usize> = BTreeMap::new();
    let mut acc: BTreeMap<usize, usize> = BTreeMap::new();
    for ((i, g), n) in &used {
        let a = acc.entry(*i).or_default();
        *a += n;
        cumulative.insert((*i, *g), *a);
    }
    let mut best: BTreeMap<usize, (f64, f64)> = BTreeMap::new();
    let mut pts = Vec::new();
    for ((i, g, _), rs) in &groups {
        if !rs[0].screened.is_empty() {
            continue;
        }
        let Some((phi, f)) = candidate_fitness(config, rs) else {
            continue;
        };
        let b = best.entry(*i).or_insert((f, phi));
        if f < b.0 {
            *b = (f, phi);
        }
        pts.push(DesignPoint {
            island: *i,
            packings: cumulative[&(*i, *g)],
            phi,
            best_phi: b.1,
            predicted_dw: rs[0].predicted_dw,
            predicted_fg: rs[0].predicted_fg,
        });
    }
    pts
}

/// Root-mean-square of `predicted − packed` over packed candidates, for each predictor, with
/// the number of candidates: (Desmond–Weeks, Farr–Groot).
pub fn predictor_errors(pts: &[DesignPoint]) -> [(Option<f64>, usize); 2] {
    let rms = |f: &dyn Fn(&DesignPoint) -> Option<f64>| {
        let e: Vec<f64> = pts.iter().filter_map(|p| Some(f(p)? - p.phi)).collect();
        let n = e.len();
        (
            (n > 0).then(|| (e.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt()),
            n,
        )
    };
    [rms(&|p| p.predicted_dw), rms(&|p| p.predicted_fg)]
}

/// Writes `best.json`, `best_diameters.txt`, the figures and `report.md` into `out`.
///
/// Errors: a run error when a file cannot be written or a figure drawn.
pub fn write_outputs(
    out: &Path,
    config: &DesignConfig,
    rows: &[DesignRow],
    best: Option<&BestDistribution>,
    stop: &str,
) -> Result<(), BenchError> {
    let json = serde_json::to_string_pretty(&best).map_err(|e| BenchError::Run(e.to_string()))?;
    write_atomic(&out.join("best.json"), json.as_bytes())?;
    if let Some(b) = best {
        let mut text = String::from("# diameters of the best distribution, one a line\n");
        for d in &b.diameters {
            let _ = writeln!(text, "{d}");
        }
        write_atomic(&out.join("best_diameters.txt"), text.as_bytes())?;
    }
    let pts = history_points(config, rows);
    let density_sample = match best {
        Some(b) => config
            .family
            .diameters(&b.values, 100_000, config.base_seed)?,
        None => Vec::new(),
    };
    let title = format!(
        "{} family: {}",
        config.family.name(),
        config.objective.describe()
    );
    let figs = design_figures(
        out,
        &title,
        config.objective.target(),
        &pts,
        &density_sample,
    )?;
    let md = report_markdown(config, rows, best, stop, &pts, &figs);
    write_atomic(&out.join("report.md"), md.as_bytes())?;
    Ok(())
}

/// `report.md`: the search, the cost of each fidelity, the best distribution, the predictors
/// against packed φ_J and the figures.
fn report_markdown(
    config: &DesignConfig,
    rows: &[DesignRow],
    best: Option<&BestDistribution>,
    stop: &str,
    pts: &[DesignPoint],
    figs: &[(String, String)],
) -> String {
    let mut s = String::new();
    write_question(&mut s, config);
    write_costs(&mut s, config, &totals(rows), stop);
    write_best(&mut s, config, best);
    write_predictors(&mut s, pts);
    let _ = writeln!(s, "\n## Figures\n");
    for (path, caption) in figs {
        let _ = writeln!(s, "![{caption}]({path})\n\n{caption}.\n");
    }
    let _ = writeln!(
        s,
        "Every evaluation: evaluations.csv (one row per packing, the columns of compare's \
         runs.csv after the candidate's)."
    );
    s
}

/// The question: family, objective, bounds, constraints and how candidates are scored.
fn write_question(s: &mut String, config: &DesignConfig) {
    let _ = writeln!(s, "# Design: {} family\n", config.family.name());
    let _ = writeln!(s, "Objective: {}.", config.objective.describe());
    let bounds: Vec<String> = config
        .family
        .params
        .iter()
        .map(|p| {
            if p.is_free() {
                format!("{} in [{}, {}]", p.name, short(p.lo), short(p.hi))
            } else {
                format!("{} = {}", p.name, short(p.lo))
            }
        })
        .collect();
    let _ = writeln!(s, "Parameters: {}.", bounds.join(", "));
    if let Some(r) = config.max_ratio {
        let _ = writeln!(s, "Constraint: D_max/D_min ≤ {r} on the packed diameters.");
    }
    let structure = config.constraints.describe();
    if !structure.is_empty() {
        let _ = writeln!(s, "Constraint: {structure} in each candidate's packings.");
    }
    let _ = writeln!(
        s,
        "Scored by {}{} at N = {} in {}D, {} seed(s) per candidate (the same seeds for every \
         candidate), budget {} packings, optimiser {}; screen: {:?} with margin {}.\n",
        config.method,
        config
            .refine
            .as_ref()
            .map_or(String::new(), |r| format!(" refined by {r}")),
        search_n(config),
        config.scene.dim(),
        config.seeds_per_candidate,
        config.budget,
        config.optimizer.name(),
        config.screen,
        config.screen_margin
    );
}

/// What each fidelity cost: the screen (no packing), the search, the confirmation.
fn write_costs(s: &mut String, config: &DesignConfig, t: &Totals, stop: &str) {
    let _ = writeln!(
        s,
        "Search: {} candidates, {} skipped by the screen or the ratio bound ({} of them invalid: \
         values that make no distribution, scored infeasible), {} packings; {} confirmation \
         packings. Stopped: {stop}.\n",
        t.candidates, t.screened, t.invalid, t.packings, t.confirmations
    );
    let _ = writeln!(
        s,
        "| fidelity | N | packings | packing time (s, runtimes summed) |"
    );
    let _ = writeln!(s, "|---|---|---|---|");
    let _ = writeln!(
        s,
        "| screen ({:?}) | — | 0 ({} candidates skipped) | 0 |",
        config.screen,
        t.screened - t.invalid
    );
    let _ = writeln!(
        s,
        "| search | {} | {} | {:.1} |",
        search_n(config),
        t.packings,
        t.search_s
    );
    let _ = writeln!(
        s,
        "| confirmation | {} | {} | {:.1} |\n",
        config.scene.n, t.confirmations, t.confirm_s
    );
}

/// The best distribution and its confirmation.
fn write_best(s: &mut String, config: &DesignConfig, best: Option<&BestDistribution>) {
    let Some(b) = best else {
        let _ = writeln!(s, "No candidate made a packing.\n");
        return;
    };
    let _ = writeln!(s, "## Best distribution\n");
    let _ = writeln!(
        s,
        "{} (island {}, generation {}, candidate {}): D_max/D_min = {}, polydispersity {}.\n",
        config.family.describe(&b.values),
        b.island,
        b.generation,
        b.candidate,
        short(b.size_ratio),
        short(b.polydispersity)
    );
    let _ = writeln!(s, "φ_J over the search seeds: {:.5}.", b.search_phi);
    match (b.confirm_mean, b.confirm_std) {
        (Some(m), Some(sd)) => {
            let _ = writeln!(
                s,
                "Confirmation with {} fresh seeds: φ_J = {m:.5} ± {sd:.5} (mean ± sample std).\n",
                b.confirm_phi.len()
            );
        }
        _ => {
            let _ = writeln!(s, "No confirmation reruns.\n");
        }
    }
    let phi = b.confirm_mean.unwrap_or(b.search_phi);
    if let Some(f) = box_fraction(&config.scene.container, &b.diameters, phi) {
        let _ = write!(
            s,
            "Its largest sphere spans {f:.3} of the shortest side of the periodic box at that φ_J."
        );
        if f > 0.5 {
            let _ = write!(
                s,
                " Above 1/2 it touches others through several periodic images, and the box \
                 shapes the packing: a finite-size answer (four spheres of about 0.68 the \
                 side, for one, lock into a strained face-centred cubic cell of the box); a \
                 larger N gives the bulk one."
            );
        }
        let _ = writeln!(s, "\n");
    }
    let _ = writeln!(s, "Diameters: best_diameters.txt; all of it: best.json.\n");
}

/// The largest of `diameters` over the shortest side of a fully periodic `container` scaled
/// to hold them at packing fraction `phi`: Σ v_d(D_i) = φ · V. `None` for other containers.
fn box_fraction(container: &Container, diameters: &[f64], phi: f64) -> Option<f64> {
    if !container.is_fully_periodic() || diameters.is_empty() {
        return None;
    }
    let d = container.dim();
    let volume: f64 = diameters.iter().map(|&x| ball_volume(d, x)).sum();
    let scale = (volume / (phi * container.volume())).powf(1.0 / d as f64);
    let (_, shortest) = container.shortest_periodic_length()?;
    let d_max = diameters.iter().fold(0.0f64, |m, &x| m.max(x));
    Some(d_max / (scale * shortest)).filter(|f| f.is_finite())
}

/// The predictors' RMS error against the packed candidates.
fn write_predictors(s: &mut String, pts: &[DesignPoint]) {
    let errs = predictor_errors(pts);
    let _ = writeln!(s, "## Predictors against packed φ_J\n");
    let _ = writeln!(s, "| predictor | candidates | RMS(predicted − packed) |");
    let _ = writeln!(s, "|---|---|---|");
    for (name, (e, n)) in ["Desmond–Weeks", "Farr–Groot"].iter().zip(errs) {
        let _ = writeln!(
            s,
            "| {name} | {n} | {} |",
            e.map_or("—".into(), |v| format!("{v:.4}"))
        );
    }
    let phis: Vec<f64> = pts.iter().map(|p| p.phi).collect();
    if let Some((m, sd)) = mean_std(&phis) {
        let _ = writeln!(
            s,
            "\nPacked candidates' φ_J: mean {m:.4}, std {sd:.4} over {}.",
            phis.len()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four touching spheres of a face-centred cubic cell: D = L/√2 at φ = π/(3√2), in a
    /// box of any shape given (only its proportions count); walls give no fraction.
    #[test]
    fn box_fraction_of_the_fcc_cell_is_one_over_root_two() {
        let phi = std::f64::consts::PI / (3.0 * 2f64.sqrt());
        let cube = Container::periodic_box(&[3.0, 3.0, 3.0]).unwrap();
        let f = box_fraction(&cube, &[1.0; 4], phi).unwrap();
        assert!((f - 0.5f64.sqrt()).abs() < 1e-12, "{f}");
        let walls = Container::with_flags(&[1.0, 1.0, 1.0], &[true, true, true]).unwrap();
        assert_eq!(box_fraction(&walls, &[1.0; 4], phi), None);
    }
}
