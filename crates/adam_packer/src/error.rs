//! The packer's error type: one clear sentence per failure.

use packbench_core::CoreError;
use thiserror::Error;

/// Why a run could not start or had to stop without a result.
#[derive(Debug, Error)]
pub enum AdamError {
    /// A parameter is out of range (the message names it and its range).
    #[error("invalid parameter: {0}")]
    Parameter(String),
    /// The starting packing is inconsistent (NaN, negative diameter, particle outside…).
    #[error("invalid starting packing: {0}")]
    Packing(#[from] CoreError),
    /// The largest sphere grew as wide as a periodic box length, where it would overlap its
    /// own image.
    #[error(
        "the largest diameter {diameter:.6} reached the periodic box length {length:.6} on axis {axis} at phi = {phi:.6}, where a sphere overlaps its own image; use more particles or a larger box"
    )]
    BoxTooSmall {
        /// The largest diameter.
        diameter: f64,
        /// The periodic length it outgrew.
        length: f64,
        /// The axis.
        axis: usize,
        /// The packing fraction at that moment.
        phi: f64,
    },
    /// More spheres than [`MAX_WIDE_SPHERES`](crate::MAX_WIDE_SPHERES) grew wide enough to touch
    /// through further periodic images, whose pairs are summed one by one.
    #[error(
        "{count} spheres grew wider than the periodic length {length:.6} on axis {axis} minus the largest diameter at phi = {phi:.6}; adam sums contacts through further images for at most {max} such spheres; use a larger box or more particles"
    )]
    TooManyWide {
        /// How many spheres were that wide.
        count: usize,
        /// The most it takes.
        max: usize,
        /// The periodic length and its axis.
        length: f64,
        axis: usize,
        /// The packing fraction at that moment.
        phi: f64,
    },
    /// The diameters span more than [`MAX_SIZE_RATIO`](crate::MAX_SIZE_RATIO).
    #[error(
        "the diameters span {smallest:e} to {largest:e}, a ratio beyond the {max:e} adam resolves (the smallest spheres' overlaps would underflow); drop or enlarge the smallest spheres"
    )]
    SizeRatio {
        /// The smallest and the largest diameter of the input.
        smallest: f64,
        largest: f64,
        /// The largest ratio taken.
        max: f64,
    },
    /// The energy or a position became NaN or infinite.
    #[error(
        "the overlap energy became non-finite at step {step}; lower lr_adam, dt_verlet or fire_dt_max"
    )]
    NonFinite {
        /// The step at which it happened.
        step: u64,
    },
}

impl packbench_core::run::MethodError for AdamError {
    /// A box too small for the particles in it is the input's fault too: the user changes the
    /// box or the count, not the method.
    fn is_input_error(&self) -> bool {
        matches!(
            self,
            AdamError::Parameter(_)
                | AdamError::Packing(_)
                | AdamError::BoxTooSmall { .. }
                | AdamError::SizeRatio { .. }
                | AdamError::TooManyWide { .. }
        )
    }
}
