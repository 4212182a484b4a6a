//! packbench: runs and compares sphere-packing methods on the same starting configurations.
//!
//! What it is: the method registry, running one method and recording it, the figures and
//! reports of comparisons, and the subcommands of the `packbench` binary. What it is not: no
//! physics lives here — packers live in their own crates and every metric comes from
//! `packbench-core`.
//!
//! The modules are layered; each imports only from the layers below it:
//! 1. records and inputs: [`error`], [`records`] (rows, comparisons, shards, statistics),
//!    [`interrupt`] (the stop flag), [`args`] (scene and container flags), [`allocation`]
//!    (how many runs at once), [`outputs`] (reading and writing packing files);
//! 2. [`methods`]: every packer behind one trait, with its own flags, and the one order in
//!    which a run's parameters are resolved from their sources ([`methods::run_params`]);
//! 3. [`runs`]: one method on one start (or from its checkpoint), timed and analysed by the
//!    core, as a result or as a row; [`refinement`]: a run's packing chained into further
//!    methods (`--refine`, and the fastest exact chain by N); [`shards`]: which rows of shard
//!    folders stand for which runs;
//!    [`void_space`]: the core's void-space analyses a user asks for together;
//! 4. [`figures`], [`report`] and [`pore_comparison`]: drawn and written from records and
//!    packings only;
//! 5. [`commands`] (every subcommand) and [`progress`] (what the terminal shows).

pub mod allocation;
pub mod args;
pub mod commands;
pub mod comparison_runs;
pub mod design;
pub mod error;
pub mod figures;
pub mod interrupt;
pub mod methods;
pub mod outputs;
pub mod pore_comparison;
pub mod progress;
pub mod records;
pub mod refinement;
pub mod report;
pub mod reproduce;
pub mod runs;
pub mod shards;
pub mod viewer;
pub mod void_space;
