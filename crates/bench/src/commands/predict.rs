//! `packbench predict`: φ_RCP predicted from a size distribution, without packing it.

use clap::Args;
use packbench_core::rcp_prediction::predict_rcp;
use rand::SeedableRng;
use rand::rngs::StdRng;

use super::Printed;
use crate::args::DistributionArgs;
use crate::error::{BenchError, usage};

/// Flags of `packbench predict`.
#[derive(Args, Debug)]
#[command(
    after_help = "Relations and their stated ranges:\n  desmond_weeks: φ_RCP = 0.634 + 0.0658 δ + 0.0857 S δ² (Desmond & Weeks, Phys. Rev. E 90, 022204 (2014)), δ and S the polydispersity and skewness of the diameters; fitted on 3D spheres with δ ≤ 0.4 (`desmond_weeks_in_range` says whether the distribution is inside); no value in 2D or above 3D.\n  farr_groot: Farr & Groot, J. Chem. Phys. 131, 244104 (2009): the diameters mapped to chords of a random line, packed as rods in 1D, calibrated to 0.6435 for equal spheres; for 3D spheres of any size distribution (checked by its authors on bidisperse, tridisperse and log-normal packings, exact at large size ratios); no value in 2D or above 3D."
)]
pub struct PredictArgs {
    #[command(flatten)]
    pub distribution: DistributionArgs,
    /// Dimension the prediction is for (both relations are for 3D spheres).
    #[arg(long = "Ndim", alias = "ndim", default_value_t = 3)]
    pub ndim: usize,
    /// Diameters drawn to measure the distribution's moments.
    #[arg(long = "N", alias = "n", default_value_t = 100_000)]
    pub n: usize,
    /// Seed of the draw.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// Prints the prediction as JSON.
pub fn run(args: &PredictArgs) -> Result<Printed, BenchError> {
    if args.ndim < 2 {
        return Err(usage(format!(
            "--Ndim {}: packings need at least 2 dimensions",
            args.ndim
        )));
    }
    if args.n < 2 {
        return Err(usage(format!(
            "--N {}: at least 2 diameters are needed for moments",
            args.n
        )));
    }
    let dist = args.distribution.distribution()?;
    let diameters = dist.sample(args.n, &mut StdRng::seed_from_u64(args.seed))?;
    let prediction = predict_rcp(args.ndim, &diameters);
    let mut out =
        serde_json::to_string_pretty(&prediction).map_err(|e| BenchError::Run(e.to_string()))?;
    out.push('\n');
    Ok(Printed {
        stdout: out,
        stderr: vec![],
    })
}
