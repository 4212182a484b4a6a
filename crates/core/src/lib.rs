//! packbench-core: the shared particle/box model of packbench.
//!
//! What it is: the data every packer and the bench agree on — [`Scene`]s (what a user asks
//! for), [`Container`]s (box, walls, curved walls, exact volume), [`Packing`]s (positions and
//! diameters), size [`distribution`]s, [`init`]ial configurations, neighbour search
//! ([`neighbor::CellList`], [`neighbor::VerletList`]), the [`analysis`] that judges every method
//! the same way, the two-sample [`ks`] test, the file [`format`]s, and the [`run`] types a packer
//! reports through.
//!
//! What it is not: no packing algorithm lives here, and nothing here prints or exits.

// Index loops over axes and particles mirror the formulas they implement.
#![allow(clippy::needless_range_loop)]

pub mod analysis;
pub mod container;
pub mod distribution;
pub mod error;
pub mod fill_ordering;
pub mod format;
pub mod geometry;
pub mod init;
pub mod ks;
pub mod neighbor;
pub mod packing;
pub mod rcp_prediction;
pub mod run;
pub mod scene;
pub mod sparse_pattern;
pub mod widest_simd;

pub use container::{Container, Shape};
pub use distribution::{Moments, SizeDistribution};
pub use error::CoreError;
pub use packing::Packing;
pub use scene::Scene;

/// Largest supported dimension. Fixed-size scratch arrays in hot loops use it; a larger `d`
/// is refused with [`CoreError::Dimension`].
pub const MAX_DIM: usize = 16;

/// Evaluates `$body` with the runtime dimension `$dim` bound to the constant `$D`, for every
/// `d` in `2..=`[`MAX_DIM`] (one monomorphised copy each), and `$fallback` for any other `d`.
///
/// `dispatch_dim!(d, D => kernel::<D>(x), _ => Err(e))` is the one place where a runtime
/// dimension becomes a const generic in packbench. A crate that supports fewer dimensions
/// refuses the others with its own clear error before dispatching; its fallback arm is then
/// unreachable by that check.
#[macro_export]
macro_rules! dispatch_dim {
    ($dim:expr, $D:ident => $body:expr, _ => $fallback:expr $(,)?) => {
        $crate::dispatch_dim!(@arms $dim, $D, $body, $fallback;
            2 3 4 5 6 7 8 9 10 11 12 13 14 15 16)
    };
    (@arms $dim:expr, $D:ident, $body:expr, $fallback:expr; $($d:literal)*) => {
        match $dim {
            $($d => {
                const $D: usize = $d;
                $body
            })*
            _ => $fallback,
        }
    };
}

#[cfg(test)]
mod dispatch_dim_tests {
    /// Every dimension of `2..=MAX_DIM` reaches its own monomorphised copy, and no other.
    #[test]
    fn dispatch_dim_covers_exactly_two_to_max_dim() {
        fn dim_of<const D: usize>() -> Option<usize> {
            Some(D)
        }
        for d in 0..=crate::MAX_DIM + 2 {
            let got = crate::dispatch_dim!(d, D => dim_of::<D>(), _ => None);
            let expected = (2..=crate::MAX_DIM).contains(&d).then_some(d);
            assert_eq!(got, expected, "d = {d}");
        }
    }
}
