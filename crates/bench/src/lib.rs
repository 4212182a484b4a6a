//! packbench: runs and compares sphere-packing methods on the same starting configurations.
//!
//! What it is: the method registry ([`methods`]), the subcommands of the `packbench` binary
//! ([`commands`]) and the terminal observer ([`progress`]). What it is not: no physics lives
//! here — packers live in their own crates and every metric comes from `packbench-core`.

pub mod args;
pub mod commands;
pub mod compare;
pub mod error;
pub mod figures;
pub mod figures_structure;
pub mod method_flags;
pub mod methods;
pub mod outputs;
pub mod progress;
pub mod report;
pub mod runs;
pub mod sweep;
