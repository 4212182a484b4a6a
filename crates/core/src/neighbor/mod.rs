//! Neighbour search: a [`CellList`] that finds every pair closer than contact plus a skin,
//! a [`NearQuery`] that lists the partners of one particle at a time, a [`VerletList`] that keeps such a list and rebuilds it only when particles have moved
//! or grown enough to invalidate it, and an enumeration over every periodic image for boxes
//! too small for the minimum image.

mod cell_list;
mod images;
mod near_query;
mod verlet;

pub use cell_list::{CellList, typical_diameter};
pub use images::{for_each_image_pair, needs_images};
pub use near_query::{NearQuery, Reach};
pub use verlet::VerletList;
