//! `packbench analyze`: the core's metrics of any packing file, as one JSON object.

use clap::Args;
use packbench_core::analysis::structure::{
    Neighbours, StructureOptions, StructureReport, analyze_structure,
};
use packbench_core::analysis::{AnalysisOptions, Metrics, analyze};
use serde::Serialize;

use super::Printed;
use crate::args::ContainerArgs;
use crate::error::BenchError;
use crate::outputs::read_input;

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
}

/// The metrics with the structure beside them.
#[derive(Serialize)]
struct WithStructure {
    #[serde(flatten)]
    metrics: Metrics,
    structure: StructureReport,
}

/// Prints the metrics JSON.
pub fn run(args: &AnalyzeArgs) -> Result<Printed, BenchError> {
    let packing = read_input(&args.file, &args.container)?;
    let metrics = analyze(
        &packing,
        &AnalysisOptions {
            contact_tol: args.contact_tol,
            force_balance: !args.no_force_balance,
        },
    )?;
    let json = if args.structure {
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
        serde_json::to_string_pretty(&WithStructure { metrics, structure })
    } else {
        serde_json::to_string_pretty(&metrics)
    };
    let mut out = json.map_err(|e| BenchError::Run(e.to_string()))?;
    out.push('\n');
    Ok(Printed {
        stdout: out,
        stderr: vec![],
    })
}
