//! packbench-adam: the Desmond–Weeks expansion–contraction packer of RCPGenerator 1.0,
//! with FIRE (Particle Assembler) as an alternative minimizer.
//!
//! What it is: a soft harmonic overlap energy between overlapping spheres and between spheres
//! and walls ([`overlap_energy`](crate) in `overlap_energy/`; flat walls, balls, cylinders,
//! cylindrical shells, hemisphere-cut bricks, periodic axes by minimum image and, for spheres
//! wider than half a periodic length, through their other images too), minimised while
//! the diameter scale is itself minimised against a pressure-like term: on RCPGenerator 1.0's
//! schedule in container units with ADAM throughout ([`Protocol::Rcpgenerator`], the default:
//! it jams where RCPGenerator jams), lowered in rungs balanced relative to μ
//! ([`Protocol::Pressure`], a few times faster), or while the diameters inflate and deflate
//! until the packing jams ([`Protocol::Threshold`], RCPGenerator 1.0's loop, also used for
//! `target_phi`). Minimizers: ADAM → AMSGrad → overdamped Verlet ([`Minimizer::Adam`],
//! RCPGenerator 1.0) or FIRE ([`Minimizer::Fire`]). With
//! [`Params::target_phi`] it grows to a packing fraction below jamming and stops overlap-free
//! (Particle Assembler's use, DEM initial conditions).
//!
//! What it is not: it computes no headline metrics (contacts, rattlers, isostaticity, force
//! balance) — the bench analyses [`Outcome::packing`] with `packbench_core::analysis` — and it
//! neither prints nor exits; progress goes to an [`Observer`].
//!
//! Runs are deterministic: there is no random choice after the starting packing, and forces are
//! summed in a fixed order whatever the number of rayon threads.

mod error;
mod minimizer;
mod neighbor_list;
mod overlap_energy;
mod params;
mod protocol;
mod system;

pub use error::AdamError;
pub use neighbor_list::NeighborUpkeep;
pub use overlap_energy::OverlapForces;
pub use params::{Minimizer, Params, Protocol, expected_jamming_density};

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};

/// Diameter ratio D_max/D_min above which the pressure protocol measures overlaps in the mean
/// diameter (energy harmonic in the absolute overlap) instead of each contact's own length.
pub const ABSOLUTE_OVERLAP_SIZE_RATIO: f64 = 4.0;

/// Most spheres that may touch others through further periodic images (D_i + D_max above a
/// periodic length): their pairs are summed one by one at every step, so a thin periodic slab
/// of many spheres would cost N² per step (`overlap_energy/other_images.rs`); 128 costs about
/// what the neighbour loop of N = 10³ does.
pub const MAX_WIDE_SPHERES: usize = 128;

/// Largest D_max/D_min a run takes. Squares of the smallest spheres' overlaps and steps
/// underflow far beyond it (two disks 2·10¹⁶⁸ apart in size made the first step's energy
/// non-finite, 2·10¹⁵⁸ apart ran without), and no packing of any N a machine holds resolves
/// ratios near it anyway.
pub const MAX_SIZE_RATIO: f64 = 1e12;

/// Packs `start` with `params` (method `adam` with the default minimizer, `fire` with
/// [`Minimizer::Fire`]).
///
/// Returns the final packing (in the input's particle order, positions wrapped), its steps, a
/// termination tag — `converged` (jammed, force-balanced, Δφ or μ below tolerance),
/// `target_reached`, `jammed_below_target`, `max_steps` or `interrupted` (the last two return
/// the densest state whose energy was below threshold) — the φ/energy trace, and in `extra`
/// the protocol's counters.
///
/// # Errors
/// [`AdamError::Parameter`] for a parameter out of range or an empty packing,
/// [`AdamError::Packing`] for an inconsistent starting packing, [`AdamError::BoxTooSmall`] when
/// the largest sphere grows as wide as a periodic length (N = 1 in a periodic box),
/// [`AdamError::SizeRatio`] for diameters spanning more than [`MAX_SIZE_RATIO`], and
/// [`AdamError::NonFinite`] if the dynamics blow up.
pub fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdamError> {
    let (lo, hi) = (start.min_diameter(), start.max_diameter());
    if hi > MAX_SIZE_RATIO * lo {
        return Err(AdamError::SizeRatio {
            smallest: lo,
            largest: hi,
            max: MAX_SIZE_RATIO,
        });
    }
    match params.effective_protocol() {
        Protocol::Rcpgenerator => protocol::rcpgenerator::run(start, params, observer),
        Protocol::Pressure => protocol::pressure::run(start, params, observer),
        Protocol::Threshold => protocol::threshold::run(start, params, observer),
    }
}
