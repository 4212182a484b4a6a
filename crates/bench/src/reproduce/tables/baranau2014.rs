//! Baranau & Tallarek, Soft Matter 10, 3826 (2014), Baranau & Tallarek 2014: closest-jamming densities of
//! log-normal hard spheres after fast compressions, Tables 3 and 4.
//!
//! Protocol (Baranau & Tallarek 2014 §III–IV): LS compressions of Poisson configurations at a fast rate
//! (γ⁻¹ < 5; packbench's `ls` default γ = 1), each followed by the MLS search (γ from 10 halved
//! at every reduced pressure of 1e12, with equilibration, down to 1e-4: `mls`'s defaults). The
//! closest-jamming densities φ_J of fast compressions fill a narrow band whose lower edge is
//! φ_fast_min = φ_LT and upper edge φ_fast_max = φ_RCP (their Fig. 4); from K seeds packbench
//! estimates the edges by the lowest and highest φ_J (which lie inside the band of many
//! packings, and spread wider at smaller N: φ_LT rises and φ_RCP falls slightly with N, §IV.D).

use packbench_core::SizeDistribution;
use packbench_core::scene::Placement;

use super::super::published::{BARANAU2014_TABLE3, BARANAU2014_TABLE4, Row, rows};
use super::super::{Case, CaseRun, Cell, Field, Recompute, Statistic, Table};
use super::periodic_scene;
use crate::error::BenchError;

const SOURCE3: &str = "V. Baranau and U. Tallarek, Soft Matter 10, 3826 (2014), Table 3";
const SOURCE4: &str = "V. Baranau and U. Tallarek, Soft Matter 10, 3826 (2014), Table 4";
const PROTOCOL: &str = "fast LS compression (γ = 1) of a Poisson configuration, then the MLS \
    closest-jamming search (γ 10 → 1e-4, halved at reduced pressure 1e12), 3D periodic box, \
    log-normal diameters of mean 1; φ_fast_min / φ_LT and φ_fast_max / φ_RCP are the lowest and \
    highest closest-jamming density over the seeds";

/// Table 3: φ_fast_min and φ_fast_max after LS and FB compressions.
pub const TABLE3: Table = Table {
    name: "baranau2014-table3",
    source: SOURCE3,
    protocol: PROTOCOL,
    published_n: Some(10_000),
    default_n: Some(10_000),
    min_n: MIN_N,
    axis: "σ (log-normal diameters, mean 1)",
    cases: table3,
};

/// Table 4: φ_LT, φ_RCP and φ_GCP.
pub const TABLE4: Table = Table {
    name: "baranau2014-table4",
    source: SOURCE4,
    protocol: PROTOCOL,
    published_n: Some(10_000),
    default_n: Some(10_000),
    min_n: MIN_N,
    axis: "σ (log-normal diameters, mean 1)",
    cases: table4,
};

/// Below 100 spheres the σ = 0.3 LS run ends at `box_limit` (its largest sphere outgrows the
/// periodic box: N = 64, seed 1).
const MIN_N: usize = 100;

const NO_FB: &str = "packbench has no force-biased (FB) algorithm";

const NO_GCP: &str = "φ_GCP extrapolates the closest-jamming densities of slow compressions \
    (γ⁻¹ > 60, ~80 packings per σ) to γ → 0 (Baranau & Tallarek 2014 §IV.C, Table 2): days of MLS on this \
    machine, so it is not run";

/// The fast-compression case of log-normal width `sigma` at `n` spheres.
fn case(n: usize, sigma: f64, cells: Vec<Cell>) -> Result<Case, BenchError> {
    Ok(Case {
        label: format!("σ = {sigma:.2}"),
        run: Some(CaseRun {
            scene: periodic_scene(
                n,
                3,
                SizeDistribution::LognormalMean1 { sigma },
                Placement::Poisson,
            )?,
            method: "ls",
            refine: Some("mls"),
            overrides: Vec::new(),
        }),
        cells,
    })
}

/// The cell of column `col`, recomputed by statistic `s` of the closest-jamming densities.
fn run_cell(quantity: &'static str, r: &Row, col: &str, n: usize, s: Statistic) -> Cell {
    Cell::of_row(
        quantity,
        r,
        col,
        Some(n),
        Recompute::Runs(s, Field::RefinedPhi),
    )
}

fn not_run(quantity: &'static str, r: &Row, col: &str, n: usize, why: &'static str) -> Cell {
    Cell::of_row(quantity, r, col, Some(n), Recompute::NotRun(why))
}

/// One fast-compression case per row of a published table, with the cells `cells` makes of
/// the row at `n` spheres.
fn cases_of(
    n: usize,
    published: &str,
    cells: fn(&Row, usize) -> Vec<Cell>,
) -> Result<Vec<Case>, BenchError> {
    rows(published)
        .iter()
        .map(|r| case(n, r.num("sigma").unwrap_or_default(), cells(r, n)))
        .collect()
}

fn table3(n: usize) -> Result<Vec<Case>, BenchError> {
    cases_of(n, BARANAU2014_TABLE3, |r, n| {
        vec![
            run_cell("φ_fast_min LS", r, "phi_fast_min_ls", n, Statistic::Lowest),
            not_run("φ_fast_min FB", r, "phi_fast_min_fb", n, NO_FB),
            run_cell("φ_fast_max LS", r, "phi_fast_max_ls", n, Statistic::Highest),
            not_run("φ_fast_max FB", r, "phi_fast_max_fb", n, NO_FB),
        ]
    })
}

fn table4(n: usize) -> Result<Vec<Case>, BenchError> {
    cases_of(n, BARANAU2014_TABLE4, |r, n| {
        vec![
            run_cell("φ_LT", r, "phi_lt", n, Statistic::Lowest),
            run_cell("φ_RCP", r, "phi_rcp", n, Statistic::Highest),
            Cell::unbanded(
                "φ_J (mean)",
                None,
                Recompute::Runs(Statistic::Mean, Field::RefinedPhi),
            ),
            not_run("φ_GCP", r, "phi_gcp", n, NO_GCP),
        ]
    })
}
