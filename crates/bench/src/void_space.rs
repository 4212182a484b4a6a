//! The void-space analyses asked for together, as `packbench analyze --voronoi/--pores
//! --scaffold-cutoff` and Python's `packbench.pores` ask for them: which analyses run on which
//! container, with which samples, and under which JSON keys.

use packbench_core::CoreError;
use packbench_core::Packing;
use packbench_core::analysis::void_space::{
    ChordOptions, ChordReport, PoreOptions, PoreReport, ScaffoldFill, VoronoiReport, chords,
    scaffold_fill, voronoi, voronoi_and_pores,
};
use serde::Serialize;

/// What to measure of the void space.
#[derive(Clone, Copy, Debug)]
pub struct VoidSpaceRequest {
    /// The radical Voronoi cells alone.
    pub voronoi: bool,
    /// The cells, the pore network and, in a fully periodic box, the chord lengths.
    pub pores: bool,
    /// Void points sampled for the pore-size distribution.
    pub pore_samples: usize,
    /// Random lines for the chord-length distributions.
    pub chord_lines: usize,
    /// Seed of the pore-size and chord sampling.
    pub seed: u64,
    /// Diameter below which spheres are fines in the scaffold-fill analysis.
    pub scaffold_cutoff: Option<f64>,
}

/// The void-space analyses that were asked for, each under its JSON key.
#[derive(Clone, Debug, Default, Serialize)]
pub struct VoidSpace {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub voronoi: Option<VoronoiReport>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pores: Option<PoreReport>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chords: Option<ChordReport>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scaffold_fill: Option<ScaffoldFill>,
}

/// Runs the analyses of `request` on `packing`; the cells and the pores share one
/// tessellation.
///
/// Errors: the sentence of the first analysis that refuses the packing or the options.
pub fn void_space(packing: &Packing, request: &VoidSpaceRequest) -> Result<VoidSpace, CoreError> {
    let mut out = VoidSpace::default();
    if request.pores {
        let options = PoreOptions {
            samples: request.pore_samples,
            seed: request.seed,
            ..PoreOptions::default()
        };
        let (cells, pores) = voronoi_and_pores(packing, &options)?;
        out.voronoi = Some(cells);
        out.pores = Some(pores);
        if packing.container.is_fully_periodic() {
            let options = ChordOptions {
                lines: request.chord_lines,
                seed: request.seed,
                ..ChordOptions::default()
            };
            out.chords = Some(chords(packing, &options)?);
        }
    } else if request.voronoi {
        out.voronoi = Some(voronoi(packing)?);
    }
    if let Some(cutoff) = request.scaffold_cutoff {
        out.scaffold_fill = Some(scaffold_fill(packing, cutoff)?);
    }
    Ok(out)
}
