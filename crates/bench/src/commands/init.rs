//! `packbench init`: RCPGenerator's InitializeParticles.

use std::path::PathBuf;

use clap::Args;
use packbench_core::format::{write_atomic, write_text};
use packbench_core::init::{initial_packing, time_seed};

use super::Printed;
use crate::args::SceneArgs;
use crate::error::BenchError;

/// Flags of `packbench init`.
#[derive(Args, Debug)]
pub struct InitArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Seed of the random generator (default: time-based, printed to stderr).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Write the packing here instead of standard output.
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Print the scene's moments (mean diameter, polydispersity, skewness) to stderr.
    #[arg(long)]
    pub verbose: bool,
    /// Write the resolved scene (TOML) here, to rerun it with --scene.
    #[arg(long = "write-scene")]
    pub write_scene: Option<PathBuf>,
}

/// Builds the initial packing.
pub fn run(args: &InitArgs) -> Result<Printed, BenchError> {
    let mut printed = Printed::default();
    let scene = args.scene.scene(args.seed)?;
    let seed = scene.seed.unwrap_or_else(|| {
        let s = time_seed();
        printed
            .stderr
            .push(format!("packbench init: no --seed given, using --seed {s}"));
        s
    });
    let packing = initial_packing(&scene, seed)?;
    let text = write_text(&packing);
    if let Some(path) = &args.write_scene {
        let mut s = scene.clone();
        s.seed = Some(seed);
        write_atomic(path, s.to_toml().as_bytes())?;
    }
    let m = packbench_core::Moments::of(&packing.diameters);
    let summary = format!(
        "packbench init: {} particles, phi = {:.6}, mean D = {:.6}, polydispersity = {:.4}, skewness = {:.4}, container {}",
        packing.n(),
        packing.phi(),
        m.mean,
        m.polydispersity,
        m.skewness,
        packing.container.describe()
    );
    match &args.output {
        Some(path) => {
            write_atomic(path, text.as_bytes())?;
            printed
                .stderr
                .push(format!("{summary} -> {}", path.display()));
        }
        None => {
            printed.stdout = text;
            if args.verbose {
                printed.stderr.push(summary);
            }
        }
    }
    Ok(printed)
}
