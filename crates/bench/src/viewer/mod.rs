//! The interactive viewer: one self-contained HTML page that draws packings in 3D (or 2D
//! disks) with three.js, their contact network, container and the core's metrics, runs as a
//! timeline, and comparisons side by side. The page opens from disk with no network.
//!
//! What it is not: no physics is computed in the page; every number comes from
//! `packbench-core`'s analysis here.

pub mod encode;
pub mod frame;
pub mod page;
pub mod run_files;

pub use frame::{Frame, FrameOptions};
pub use page::{FrameKind, Panel, Trace, ViewerPage, render};
pub use run_files::{RunFiles, read_run, thin};
