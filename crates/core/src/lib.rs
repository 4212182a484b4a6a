//! packbench-core: the shared particle/box model of packbench.
//!
//! What it is: the data every packer and the bench agree on — [`Scene`]s (what a user asks
//! for), [`Container`]s (box, walls, curved walls, exact volume), [`Packing`]s (positions and
//! diameters), size [`distribution`]s, [`init`]ial configurations, neighbour search
//! ([`neighbor::CellList`], [`neighbor::VerletList`]), the [`analysis`] that judges every method
//! the same way, the file [`format`]s, and the [`run`] types a packer reports through.
//!
//! What it is not: no packing algorithm lives here, and nothing here prints or exits.

// Index loops over axes and particles mirror the formulas they implement.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod container;
pub mod distribution;
pub mod error;
pub mod format;
pub mod geometry;
pub mod init;
pub mod neighbor;
pub mod packing;
pub mod rcp_prediction;
pub mod run;
pub mod scene;

pub use container::{Container, Shape};
pub use distribution::{Moments, SizeDistribution};
pub use error::CoreError;
pub use packing::Packing;
pub use scene::Scene;

/// Largest supported dimension. Fixed-size scratch arrays in hot loops use it; a larger `d`
/// is refused with [`CoreError::Dimension`].
pub const MAX_DIM: usize = 16;
