//! The `packbench` binary: parses arguments, calls the library, prints, exits
//! (0 success, 1 a run failed, 2 bad input).

use std::io::Write;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
use packbench::commands::{self, Printed};
use packbench::error::BenchError;

/// Jammed and random close packings of spheres in any dimension, by several published
/// algorithms on one core, compared on the same starting configurations.
#[derive(Parser)]
#[command(name = "packbench", version, about = "Jammed and random close packings of spheres in any dimension, by several published algorithms on one shared core, compared on the same starting configurations.", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// Parsed once per process: the size of the larger variants does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// Random initial packing at a low φ (RCPGenerator's InitializeParticles).
    #[command(allow_negative_numbers = true)]
    Init(commands::init::InitArgs),
    /// Run one packing method on a starting packing.
    #[command(allow_negative_numbers = true)]
    Pack(commands::pack::PackArgs),
    /// Metrics of a packing file as JSON (φ, contacts, rattlers, isostaticity, force balance).
    #[command(allow_negative_numbers = true)]
    Analyze(commands::analyze::AnalyzeArgs),
    /// Convert a packing for OVITO, ParaView and LAMMPS: extended XYZ, LAMMPS data or dump, VTK.
    #[command(allow_negative_numbers = true)]
    Export(commands::export::ExportArgs),
    /// Several methods on the same starting packings: runs.csv, runs.json, report.md, figures.
    #[command(allow_negative_numbers = true)]
    Compare(commands::compare::CompareArgs),
    /// One method over its accuracy knob: the speed–accuracy curve.
    #[command(allow_negative_numbers = true)]
    Sweep(commands::sweep::SweepArgs),
    /// Draw a packing (2D to scale, or a slice), g(r) of packings, or the traces of runs.
    Plot(commands::plot::PlotArgs),
    /// φ_RCP predicted from a size distribution (same flags as init), without packing.
    #[command(allow_negative_numbers = true)]
    Predict(commands::predict::PredictArgs),
    /// Search a family of size distributions for the one that maximises or reaches a φ_J.
    #[command(allow_negative_numbers = true)]
    Design(commands::design::DesignArgs),
    /// One self-contained HTML page showing packings in 3D, runs as a timeline, comparisons side by side.
    View(commands::view::ViewArgs),
    /// A run as an animated GIF (2D, or a 3D slice), frame by frame with φ.
    Animate(commands::animate::AnimateArgs),
    /// Recompute a published table (Baranau & Tallarek 2014, Desmond & Weeks 2014, …) beside its published values; --list names them.
    Reproduce(commands::reproduce::ReproduceArgs),
    /// Join shard folders of a comparison (and reruns of some of its runs) into one.
    Merge(commands::merge::MergeArgs),
    /// List the available methods and their parameters.
    Methods,
}

fn methods_listing() -> Printed {
    Printed {
        stdout: packbench::methods::listing(),
        stderr: vec![],
    }
}

/// Parses the command line: the derived flags, plus the options each method declares for
/// `pack` (`methods::flags`).
fn parse() -> Cli {
    let command = Cli::command().mut_subcommand("pack", packbench::methods::flags::add_to);
    let matches = command.get_matches();
    let mut cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let (Command::Pack(args), Some(("pack", sub))) = (&mut cli.command, matches.subcommand()) {
        args.method_flags = packbench::methods::flags::given(sub);
    }
    cli
}

fn main() {
    let cli = parse();
    let result: Result<Printed, BenchError> = match &cli.command {
        Command::Init(a) => commands::init::run(a),
        Command::Pack(a) => commands::pack::run(a),
        Command::Analyze(a) => commands::analyze::run(a),
        Command::Export(a) => commands::export::run(a),
        Command::Compare(a) => commands::compare::run(a),
        Command::Sweep(a) => commands::sweep::run(a),
        Command::Plot(a) => commands::plot::run(a),
        Command::Predict(a) => commands::predict::run(a),
        Command::Design(a) => commands::design::run(a),
        Command::View(a) => commands::view::run(a),
        Command::Animate(a) => commands::animate::run(a),
        Command::Reproduce(a) => commands::reproduce::run(a),
        Command::Merge(a) => commands::merge::run(a),
        Command::Methods => Ok(methods_listing()),
    };
    match result {
        Ok(p) => {
            for line in &p.stderr {
                eprintln!("{line}");
            }
            let mut out = std::io::stdout().lock();
            // A closed pipe (e.g. `| head`) is not an error worth reporting.
            let _ = out.write_all(p.stdout.as_bytes());
            let _ = out.flush();
        }
        Err(e) => {
            eprintln!("packbench: {e}");
            std::process::exit(e.exit_code());
        }
    }
}
