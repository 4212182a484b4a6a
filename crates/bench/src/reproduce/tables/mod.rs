//! Every published table packbench recomputes, one file per publication.

mod baranau2014;
mod black_cheviakov2022;
mod desmond_weeks2014;
mod dimensions;
mod ohern2003;

use packbench_core::scene::Placement;
use packbench_core::{Container, Scene, SizeDistribution};

use super::Table;
use crate::error::BenchError;

/// The tables, in the order `--list` shows them.
pub static TABLES: &[Table] = &[
    baranau2014::TABLE3,
    baranau2014::TABLE4,
    desmond_weeks2014::TABLE,
    dimensions::TABLE,
    dimensions::TABLE_ADAM,
    ohern2003::TABLE,
    black_cheviakov2022::TABLE,
];

/// `n` spheres of `distribution` in a periodic unit box of dimension `dim`, placed by
/// `placement` at φ = 0.05 (the box is rescaled to the diameters by the initial packing).
fn periodic_scene(
    n: usize,
    dim: usize,
    distribution: SizeDistribution,
    placement: Placement,
) -> Result<Scene, BenchError> {
    let scene = Scene {
        n,
        distribution,
        container: Container::periodic_box(&vec![1.0; dim])?,
        phi: 0.05,
        seed: None,
        placement,
    };
    scene.validate()?;
    Ok(scene)
}

/// The 2D disks of the jamming literature: diameters 1 and 1.4 at equal numbers.
fn bidisperse_disks() -> SizeDistribution {
    SizeDistribution::Bidisperse {
        d1: 1.0,
        d2: 1.4,
        p: 0.5,
    }
}
