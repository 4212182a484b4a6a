//! packbench-exact-jamming: exact jamming of hard-sphere packings.
//!
//! What it is: three methods that take an unjammed, overlap-free packing (periodic or walled,
//! any dimension ≥ 2, any size distribution) and drive it to a jammed, isostatic,
//! force-balanced packing whose contacts are exact to near machine precision:
//! - [`closest_jammed::run`]: the minimum-norm closest-jammed integrator of Baranau & Tallarek 2014
//!   (Appendix C, eqns 1–4), with faer's SVD and sparse Cholesky;
//! - [`closest_jammed_qp::run`]: the same growth where each step solves a QP (clarabel) over
//!   every contact, so bonds open when steepest descent says so;
//! - [`calippso::run`]: CALiPPSO's iterated linear programming (CALiPPSO.jl), with this crate's
//!   interior-point LP solver over faer's sparse Cholesky.
//!
//! These methods are not monomorphised over the dimension (no `packbench_core::dispatch_dim!`):
//! their time goes into sparse factorisations and LPs over all bonds, not per-pair arithmetic,
//! so a bond's normal is a `[f64; MAX_DIM]` with `d` entries used, and one copy of the code
//! serves every `d` up to [`packbench_core::MAX_DIM`].
//!
//! What it is not: no compression protocol (start from an LS or ADAM packing, or a random
//! configuration), and no metrics: the core's analysis judges the outputs.

pub mod calippso;
pub mod closest_jammed;
mod conic;
mod contacts;
mod error;
mod growth;
mod interior_point;
mod min_norm;
mod projection;
mod start;
mod verdict;

pub use start::shrink_to_overlap_free;

pub use closest_jammed::qp_form as closest_jammed_qp;
pub use error::JammingError;
pub use verdict::NOT_JAMMED;
