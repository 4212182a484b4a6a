//! The radial distribution function g(r) of a periodic packing.

use serde::{Deserialize, Serialize};

use crate::geometry::unit_ball_volume;
use crate::neighbor::CellList;
use crate::packing::Packing;

/// g(r) sampled at bin centres, r in mean diameters.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PairCorrelation {
    /// Bin centres, in mean diameters.
    pub r: Vec<f64>,
    /// g(r) per bin: pair count over the ideal-gas count ρ·N·(shell volume)/… at the same ρ.
    pub g: Vec<f64>,
}

/// g(r) of the centres of a periodic packing in `bins` equal bins up to
/// min(half the smallest box length, 3 mean diameters). Distances use the minimum image;
/// empty for no particles or no bins.
pub fn pair_correlation(p: &Packing, bins: usize) -> PairCorrelation {
    let d = p.dim;
    let n = p.n();
    if n == 0 || bins == 0 {
        return PairCorrelation::default();
    }
    let mean = p.mean_diameter();
    let r_max = (0.5
        * p.container
            .lengths
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min))
    .min(3.0 * mean);
    let dr = r_max / bins as f64;
    let mut hist = vec![0usize; bins];
    let mut delta = vec![0.0; d];
    CellList::for_each_near_pair(&p.container, &p.positions, &p.diameters, r_max, |i, j| {
        p.container
            .separation(p.position(i), p.position(j), &mut delta);
        let r = delta.iter().map(|v| v * v).sum::<f64>().sqrt();
        if r < r_max {
            hist[((r / dr) as usize).min(bins - 1)] += 2;
        }
    });
    let rho = n as f64 / p.container.volume();
    let vd = unit_ball_volume(d);
    let (r, g) = hist
        .iter()
        .enumerate()
        .map(|(b, &h)| {
            let (r0, r1) = (b as f64 * dr, (b + 1) as f64 * dr);
            let shell = vd * (r1.powi(d as i32) - r0.powi(d as i32));
            ((r0 + 0.5 * dr) / mean, h as f64 / (n as f64 * rho * shell))
        })
        .unzip();
    PairCorrelation { r, g }
}
