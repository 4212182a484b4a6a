//! packbench-mls: exact event-driven molecular dynamics of hard spheres whose diameters grow
//! linearly in time — the Lubachevsky–Stillinger (LS) algorithm — and the modified LS (MLS)
//! compression-rate schedule of Baranau & Tallarek (2014, Baranau & Tallarek 2014 §III) that searches for the
//! closest jammed configuration of a packing.
//!
//! * [`ls::run`] compresses a Poisson configuration (the start's centres, diameters from 0)
//!   at a fixed rate γ until the reduced pressure reaches the cap (1e12).
//! * [`mls::run`] takes any packing and runs Baranau & Tallarek 2014's schedule: γ₀ = 10, γ halved each time
//!   the pressure reaches the cap, equilibration at γ = 0 in between, until jammed or γ < 1e-4.
//!
//! The dynamics: unit masses, temperature 0.2 held by rescaling velocities after every
//! window of 20 collisions per particle, over which the reduced pressure is measured from the
//! collision virial; collision times from the quadratic for growing spheres in its stable
//! form; collisions elastic relative to the growing surfaces; neighbour lists of bounding
//! spheres (Donev–Torquato–Stillinger 2005) built on a cell grid sized for the largest sphere
//! plus skin, renewed by an event when a sphere may leave its bounding sphere, in place of
//! cell-crossing events; one event calendar (a tournament tree holding each particle's next
//! collision and next renewal) with per-particle version counters for stale partners;
//! positions updated lazily (a collision touches two particles); periodic axes and flat hard
//! walls in any d from 2 to 8, any size distribution. Kernels are monomorphised over d and
//! over "fully periodic or not". How floating-point trouble near jamming is avoided is
//! described in the `system` module.
//!
//! What it is not: it does not compute metrics of its result (the bench analyses
//! [`Outcome::packing`](packbench_core::run::Outcome) with the core's analysis), does not
//! handle curved walls or `--fix-height`, and never prints.

mod cells;
pub mod checkpoint;
mod driver;
mod error;
mod event;
pub mod ls;
pub mod mls;
mod neighbour_lists;
mod params;
mod system;

#[cfg(test)]
mod tests;

pub use checkpoint::Checkpoint;
pub use error::MlsError;
pub use ls::{Params as LsParams, run as run_ls};
pub use mls::{Params as MlsParams, resume as resume_mls, run as run_mls};
pub use params::Dynamics;

use packbench_core::{Packing, Shape};

/// Largest dimension LS and MLS accept, below the core's [`packbench_core::MAX_DIM`]: the
/// event-driven kernels are compiled for `2..=MAX_DIM` only, and a larger `d` is refused with
/// [`MlsError::Dimension`].
pub const MAX_DIM: usize = 8;

/// Checks what LS and MLS need of a starting packing beyond [`Packing::validate`].
fn check_start(start: &Packing) -> Result<(), MlsError> {
    start.validate()?;
    if start.n() == 0 {
        return Err(MlsError::Empty);
    }
    if start.n() >= event::MAX_PARTICLES {
        return Err(MlsError::Parameter(format!(
            "{} particles exceed the event calendar's limit of {}",
            start.n(),
            event::MAX_PARTICLES
        )));
    }
    if !(2..=MAX_DIM).contains(&start.dim) {
        return Err(MlsError::Dimension(start.dim));
    }
    if start.container.shape != Shape::Box {
        return Err(MlsError::Container(format!(
            "{} has a curved wall; only periodic and flat-walled box axes are modelled",
            start.container.describe()
        )));
    }
    if start.container.fix_height.is_some() {
        return Err(MlsError::Container(
            "fix-height ties the box to the largest diameter, but LS grows the spheres in a fixed box".into(),
        ));
    }
    Ok(())
}

/// Calls `f::<D, P>(args…)` for the runtime dimension `D` (by the core's
/// [`packbench_core::dispatch_dim!`]) and boundary kind `P` ("every axis periodic").
/// Dimensions above [`MAX_DIM`] (this crate's limit, below the core's) are refused by
/// [`check_start`] before a dispatch, and answered with [`MlsError::Dimension`] here too; the
/// constant test `D <= MAX_DIM` keeps their kernels from being instantiated.
macro_rules! dispatch {
    ($dim:expr, $periodic:expr, $f:ident, $($arg:expr),*) => {
        packbench_core::dispatch_dim!(
            $dim,
            D => if const { D <= $crate::MAX_DIM } {
                match $periodic {
                    true => $f::<D, true>($($arg),*),
                    false => $f::<D, false>($($arg),*),
                }
            } else {
                Err($crate::MlsError::Dimension(D))
            },
            _ => Err($crate::MlsError::Dimension($dim)),
        )
    };
}
pub(crate) use dispatch;
