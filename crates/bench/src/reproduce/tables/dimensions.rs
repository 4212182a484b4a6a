//! Jamming densities by dimension, d = 2 … 6: Skoge, Donev, Stillinger & Torquato, Phys. Rev.
//! E 74, 041127 (2006) for equal hyperspheres in d = 3 … 6, and O'Hern et al. 2003 for the
//! bidisperse disks of d = 2 (equal disks crystallise).
//!
//! Skoge et al. grew hard spheres by Lubachevsky–Stillinger (collision-driven molecular
//! dynamics) until the reduced pressure diverged; `dimensions` runs packbench's `ls` so, from a
//! Poisson start up to a reduced pressure of 10¹² at one growth rate for every dimension
//! ([`LS_RATE`]). `dimensions-adam` keeps the second protocol, adam's soft-sphere inflation,
//! beside it.

use packbench_core::SizeDistribution;
use packbench_core::scene::Placement;
use serde_json::{Value, json};

use super::super::published::{DIMENSIONS, Row, rows};
use super::super::{Case, CaseRun, Cell, Field, Recompute, Statistic, Table};
use super::{bidisperse_disks, periodic_scene};
use crate::error::BenchError;

/// φ_J and z for d = 2 … 6 by the publication's protocol.
pub const TABLE: Table = Table {
    name: "dimensions",
    source: SOURCE,
    protocol: "Lubachevsky–Stillinger growth of hard spheres (`ls`) from a Poisson start in a \
        periodic box, growth rate γ = 0.01 (mean diameter per unit time, in units of the \
        mean diameter at φ = 1, at temperature 0.2) until the reduced pressure reaches \
        10¹², as Skoge et al. grew theirs until the pressure diverged; equal spheres for \
        d ≥ 3, disks 1 : 1.4 at equal numbers for d = 2; z over non-rattlers",
    published_n: None,
    default_n: Some(1000),
    min_n: MIN_N,
    axis: "dimension d",
    cases: ls_cases,
};

/// The same rows by a second protocol, not the publication's.
pub const TABLE_ADAM: Table = Table {
    name: "dimensions-adam",
    source: SOURCE,
    protocol: "a second protocol, not the publication's: adam (fast compression of soft \
        spheres, RCPGenerator's schedule) from random sequential addition at φ = 0.05, periodic \
        box; equal spheres for d ≥ 3, disks 1 : 1.4 at equal numbers for d = 2; z over \
        non-rattlers",
    published_n: None,
    default_n: Some(1000),
    min_n: MIN_N,
    axis: "dimension d",
    cases: adam_cases,
};

const SOURCE: &str = "M. Skoge, A. Donev, F. H. Stillinger and S. Torquato, Phys. Rev. E 74, \
    041127 (2006), φ_MRJ for d = 3–6 (abstract) and isostaticity; d = 2: C. S. O'Hern, L. E. \
    Silbert, A. J. Liu and S. R. Nagel, Phys. Rev. E 68, 011306 (2003)";

/// The growth rate of the LS protocol. Skoge et al.'s own rates could not be read here (the
/// body of the paper was not at hand); 0.01 is the rate at which packbench's 3D LS lands on
/// the established MRJ density of equal spheres (0.639 at N = 250, where 0.1 gives 0.620 and
/// 0.001 orders towards 0.648), held for every dimension (docs/notes/published-values.md).
pub const LS_RATE: f64 = 0.01;

/// The reduced pressure at which LS stops: "diverging", as Skoge et al. 2006 ran it.
const LS_PRESSURE_CAP: f64 = 1e12;

/// The 6D periodic box holds two diameters only above N = 64 φ_J / v₆(½) ≈ 150 at φ_J ≈ 0.19;
/// below, spheres touch through several images, a finite-size effect a published infinite-
/// system value should not carry (adam refused such diameters once: 3 of 5 seeds at N = 150
/// did). 250 leaves a margin (5 of 5 seeds).
const MIN_N: usize = 250;

fn ls_cases(n: usize) -> Result<Vec<Case>, BenchError> {
    jamming_cases(n, DIMENSIONS, Protocol::Ls, "phi_j", |d| format!("d = {d}"))
}

fn adam_cases(n: usize) -> Result<Vec<Case>, BenchError> {
    jamming_cases(n, DIMENSIONS, Protocol::Adam, "phi_j_adam", |d| {
        format!("d = {d}")
    })
}

/// How the jamming points are packed.
#[derive(Clone, Copy)]
pub(super) enum Protocol {
    /// Lubachevsky–Stillinger (`ls`) from a Poisson start at [`LS_RATE`] to a reduced pressure
    /// of 10¹².
    Ls,
    /// adam's soft-sphere inflation and minimisation from random sequential addition at
    /// φ = 0.05 (RCPGenerator's schedule).
    Adam,
    /// O'Hern et al. 2003's quench: soft harmonic spheres at random positions (an infinite
    /// temperature state), minimised (FIRE), inflated while the minimised energy is zero and
    /// deflated when not, the step halved at every reversal (`fire` with the `threshold`
    /// protocol).
    Quench,
}

impl Protocol {
    fn run(self, n: usize, d: usize, dist: SizeDistribution) -> Result<CaseRun, BenchError> {
        let set = |m: &str, k: &str, v: Value| (m.to_string(), k.to_string(), v);
        Ok(match self {
            Protocol::Ls => CaseRun {
                scene: periodic_scene(n, d, dist, Placement::Poisson)?,
                method: "ls",
                refine: None,
                overrides: vec![
                    set("ls", "rate", json!(LS_RATE)),
                    set("ls", "pressure_cap", json!(LS_PRESSURE_CAP)),
                ],
            },
            Protocol::Quench => CaseRun {
                scene: periodic_scene(n, d, dist, Placement::Random)?,
                method: "fire",
                refine: None,
                overrides: vec![set("fire", "protocol", json!("threshold"))],
            },
            Protocol::Adam => CaseRun {
                scene: periodic_scene(n, d, dist, Placement::Rsa)?,
                method: "adam",
                refine: None,
                overrides: Vec::new(),
            },
        })
    }
}

/// The cases of a published file of jamming points (columns d, phi_j, z): disks 1 : 1.4 for
/// d = 2, equal spheres otherwise, each packed by `protocol`, labelled by `label(d)`. A row's
/// known disagreement is read from the column `<disagrees>_disagrees`: the publication's own
/// protocol reads `phi_j`'s, a second protocol its own.
pub(super) fn jamming_cases(
    n: usize,
    published: &str,
    protocol: Protocol,
    disagrees: &str,
    label: fn(usize) -> String,
) -> Result<Vec<Case>, BenchError> {
    rows(published)
        .iter()
        .map(|r| {
            let d = r.num("d").unwrap_or_default() as usize;
            let dist = if d == 2 {
                bidisperse_disks()
            } else {
                SizeDistribution::Mono { d: 1.0 }
            };
            Ok(Case {
                label: label(d),
                run: Some(protocol.run(n, d, dist)?),
                cells: phi_and_z(r, n, disagrees),
            })
        })
        .collect()
}

/// The cells φ_J (with its band at `n` spheres) and z of a jamming point, recomputed as means
/// over the seeds.
fn phi_and_z(r: &Row, n: usize, disagrees: &str) -> Vec<Cell> {
    let mut z = Cell::unbanded(
        "z",
        r.num("z"),
        Recompute::Runs(Statistic::Mean, Field::ZNonrattler),
    );
    z.note = Some("isostatic 2d, over non-rattlers; no band (exact at jamming only)");
    let mut phi = Cell::of_row(
        "φ_J",
        r,
        "phi_j",
        Some(n),
        Recompute::Runs(Statistic::Mean, Field::Phi),
    );
    phi.disagrees = r.disagreement(disagrees);
    vec![phi, z]
}
