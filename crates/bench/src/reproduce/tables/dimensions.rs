//! Jamming densities by dimension, d = 2 … 6: Skoge, Donev, Stillinger & Torquato, Phys. Rev.
//! E 74, 041127 (2006) for equal hyperspheres in d = 3 … 6, and O'Hern et al. 2003 for the
//! bidisperse disks of d = 2 (equal disks crystallise).
//!
//! Fast compressions by `adam`: soft spheres inflated and minimised (RCPGenerator's schedule)
//! stop at the jamming point of the random start they come from, as the fast LS compressions
//! of Skoge et al. do; packbench's `ls` alone stops at its pressure cap well below jamming
//! (φ ≈ 0.60 in 3D, docs/BENCHMARKS.md), and `mls` is the slow closest-jamming search, not a
//! fast compression.

use packbench_core::SizeDistribution;
use packbench_core::scene::Placement;

use super::super::published::{DIMENSIONS, Row, rows};
use super::super::{Case, CaseRun, Cell, Field, Recompute, Statistic, Table};
use super::{bidisperse_disks, periodic_scene};
use crate::error::BenchError;

/// φ_J and z for d = 2 … 6.
pub const TABLE: Table = Table {
    name: "dimensions",
    source: "M. Skoge, A. Donev, F. H. Stillinger and S. Torquato, Phys. Rev. E 74, 041127 \
        (2006), φ_MRJ for d = 3–6 (abstract) and isostaticity; d = 2: C. S. O'Hern, L. E. \
        Silbert, A. J. Liu and S. R. Nagel, Phys. Rev. E 68, 011306 (2003)",
    protocol: "a second protocol, not the publication's: adam (fast compression of soft \
        spheres, RCPGenerator's schedule) from random sequential addition at φ = 0.05, periodic \
        box, where Skoge et al. compressed hard spheres by Lubachevsky–Stillinger (not run here); \
        equal spheres for d ≥ 3, disks 1 : 1.4 at equal numbers for d = 2; z over non-rattlers",
    published_n: None,
    default_n: Some(1000),
    min_n: MIN_N,
    axis: "dimension d",
    cases,
};

/// The 6D periodic box holds two diameters only above N = 64 φ_J / v₆(½) ≈ 150 at φ_J ≈ 0.19
/// (adam refuses the largest diameter at half the box: 3 of 5 seeds at N = 150 did); 250
/// leaves a margin (5 of 5 seeds).
const MIN_N: usize = 250;

fn cases(n: usize) -> Result<Vec<Case>, BenchError> {
    jamming_cases(n, DIMENSIONS, |d| format!("d = {d}"))
}

/// The cases of a published file of jamming points (columns d, phi_j, z): disks 1 : 1.4 for
/// d = 2, equal spheres otherwise, each packed by `adam`, labelled by `label(d)`.
pub(super) fn jamming_cases(
    n: usize,
    published: &str,
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
                run: Some(CaseRun {
                    scene: periodic_scene(n, d, dist, Placement::Rsa)?,
                    method: "adam",
                    refine: None,
                    overrides: Vec::new(),
                }),
                cells: phi_and_z(r, n),
            })
        })
        .collect()
}

/// The cells φ_J (with its band at `n` spheres) and z of a jamming point, recomputed as means
/// over the seeds.
fn phi_and_z(r: &Row, n: usize) -> Vec<Cell> {
    let mut z = Cell::unbanded(
        "z",
        r.num("z"),
        Recompute::Runs(Statistic::Mean, Field::ZNonrattler),
    );
    z.note = Some("isostatic 2d, over non-rattlers; no band (exact at jamming only)");
    vec![
        Cell::of_row(
            "φ_J",
            r,
            "phi_j",
            Some(n),
            Recompute::Runs(Statistic::Mean, Field::Phi),
        ),
        z,
    ]
}
