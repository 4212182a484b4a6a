//! `packbench analyze`: the core's metrics of any packing file, as one JSON object.

use clap::Args;
use packbench_core::analysis::structure::{
    Neighbours, StructureOptions, StructureReport, analyze_structure,
};
use packbench_core::analysis::{AnalysisOptions, Metrics, analyze};
use serde::Serialize;

use super::Printed;
use crate::args::ContainerArgs;
use crate::error::{BenchError, usage};
use crate::outputs::read_input;
use crate::void_space::{VoidSpace, VoidSpaceRequest, void_space};

/// Flags of `packbench analyze`.
#[derive(Args, Debug)]
pub struct AnalyzeArgs {
    /// Packing file in plain text (`x1 … xd D` per line); `-` reads standard input.
    pub file: String,
    #[command(flatten)]
    pub container: ContainerArgs,
    /// Largest relative gap r/σ − 1 counted as a contact.
    #[arg(long = "contact-tol", default_value_t = 1e-6)]
    pub contact_tol: f64,
    /// Skip the force-balance solve.
    #[arg(long = "no-force-balance")]
    pub no_force_balance: bool,
    /// Add the structure under key `structure`: g(r), S(k) and s_k0, Q4/Q6 (ψ6 in 2D), the
    /// force and gap distributions with θ and γ, and φ_RCP predicted from the diameters.
    #[arg(long)]
    pub structure: bool,
    /// Add the radical Voronoi cells under key `voronoi`: local φ (mean, std, histogram), cell
    /// volume std/mean and entropy, faces per cell (2D and 3D).
    #[arg(long)]
    pub voronoi: bool,
    /// With --voronoi or --pores, add each particle's radical Voronoi cell under key
    /// `per_particle`: `cell_volume` (area in 2D, in the packing's length units), `local_phi`
    /// (its particle's volume over the cell's) and `faces`, in the file's particle order.
    #[arg(long = "per-particle")]
    pub per_particle: bool,
    /// Add the void space: `voronoi`, the pore network under `pores` (D_i, D_f, pore- and
    /// throat-size distributions) and, in a fully periodic box, chord lengths under `chords`.
    #[arg(long)]
    pub pores: bool,
    /// Void points sampled for the pore-size distribution (with --pores).
    #[arg(long = "pore-samples", default_value_t = 20_000)]
    pub pore_samples: usize,
    /// Random lines for the chord-length distributions (with --pores).
    #[arg(long = "chord-lines", default_value_t = 1000)]
    pub chord_lines: usize,
    /// Seed of the pore-size and chord sampling.
    #[arg(long = "void-seed", default_value_t = 1)]
    pub void_seed: u64,
    /// Add under `scaffold_fill` how the spheres below this diameter fill the radical cells of
    /// the spheres at or above it.
    #[arg(long = "scaffold-cutoff")]
    pub scaffold_cutoff: Option<f64>,
}

/// The metrics with whatever analyses were asked for beside them.
#[derive(Serialize)]
struct Report {
    #[serde(flatten)]
    metrics: Metrics,
    #[serde(skip_serializing_if = "Option::is_none")]
    structure: Option<StructureReport>,
    #[serde(flatten)]
    void_space: VoidSpace,
    #[serde(skip_serializing_if = "Option::is_none")]
    per_particle: Option<PerParticle>,
}

/// Each particle's radical Voronoi cell, in the file's order (`--per-particle`).
#[derive(Serialize)]
struct PerParticle {
    cell_volume: Vec<f64>,
    local_phi: Vec<f64>,
    faces: Vec<usize>,
}

/// Prints the metrics JSON.
pub fn run(args: &AnalyzeArgs) -> Result<Printed, BenchError> {
    let packing = read_input(&args.file, &args.container)?;
    // A packing the analysis refuses is bad input: the sentence names the file.
    let named = |e: packbench_core::CoreError| match BenchError::from(e) {
        BenchError::Usage(m) => usage(format!("{}: {m}", args.file)),
        run => run,
    };
    // With --structure the force-balance problem is solved once, for P(f), and its residual
    // is the metrics' (the same contact network and rattlers at the same tolerance).
    let metrics = analyze(
        &packing,
        &AnalysisOptions {
            contact_tol: args.contact_tol,
            force_balance: !args.no_force_balance && !args.structure,
        },
    )
    .map_err(named)?;
    let mut report = Report {
        metrics,
        structure: None,
        void_space: VoidSpace::default(),
        per_particle: None,
    };
    if args.per_particle && !(args.voronoi || args.pores) {
        return Err(usage(
            "--per-particle writes each particle's Voronoi cell: give it with --voronoi (or --pores)",
        ));
    }
    if args.structure {
        let structure = analyze_structure(
            &packing,
            &StructureOptions {
                neighbours: Neighbours::Contact {
                    tol: args.contact_tol,
                },
                contact_tol: args.contact_tol,
                forces: !args.no_force_balance,
                ..StructureOptions::default()
            },
        )?;
        report.metrics.force_balance = structure.forces.as_ref().map(|f| f.residual);
        report.structure = Some(structure);
    }
    report.void_space = void_space(
        &packing,
        &VoidSpaceRequest {
            voronoi: args.voronoi,
            pores: args.pores,
            pore_samples: args.pore_samples,
            chord_lines: args.chord_lines,
            seed: args.void_seed,
            scaffold_cutoff: args.scaffold_cutoff,
        },
    )?;
    if args.per_particle {
        report.per_particle = report.void_space.voronoi.as_ref().map(|v| PerParticle {
            cell_volume: v.cells.volumes.clone(),
            local_phi: v.cells.local_phi.clone(),
            faces: v.cells.faces.clone(),
        });
    }
    let json = serde_json::to_string_pretty(&report);
    let mut out = json.map_err(|e| BenchError::Run(e.to_string()))?;
    out.push('\n');
    Ok(Printed {
        stdout: out,
        stderr: vec![],
    })
}
