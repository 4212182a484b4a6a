//! Neighbour search: a [`CellList`] that finds every pair closer than contact plus a skin,
//! and a [`VerletList`] that keeps such a list and rebuilds it only when particles have moved
//! or grown enough to invalidate it.

mod cell_list;
mod verlet;

pub use cell_list::CellList;
pub use verlet::VerletList;
