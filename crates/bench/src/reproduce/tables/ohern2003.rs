//! O'Hern, Silbert, Liu & Nagel, Phys. Rev. E 68, 011306 (2003): point J of frictionless soft
//! spheres — φ_J and the contact number z at jamming for 2D disks 1 : 1.4 at equal numbers and
//! 3D equal spheres.
//!
//! Their protocol quenches random states (infinite temperature) of soft harmonic spheres by
//! energy minimisation and compresses or decompresses, bisecting, to the φ at which the
//! minimised energy first stays above zero; packbench runs that quench (`fire` with the
//! `threshold` protocol, FIRE standing for their conjugate gradients). Their φ_J are large-N
//! limits; packbench runs the N given.

use super::super::published::OHERN2003;
use super::super::{Case, Table};
use super::dimensions::{Protocol, jamming_cases};
use crate::error::BenchError;

/// φ_J and z in 2D and 3D.
pub const TABLE: Table = Table {
    name: "ohern-2003",
    source: "C. S. O'Hern, L. E. Silbert, A. J. Liu and S. R. Nagel, Phys. Rev. E 68, 011306 \
        (2003), φ_J (large-N limit) and z_c = 2d in 2D and 3D",
    protocol: "O'Hern et al.'s quench: soft harmonic spheres at random positions (infinite \
        temperature, φ = 0.05), periodic box, minimised by FIRE and inflated while the minimised \
        energy is zero, deflated when not, the step halved at each reversal down to Δφ = 5e-6 \
        (`fire`, protocol `threshold`); z over non-rattlers",
    published_n: None,
    default_n: Some(1000),
    min_n: 50,
    axis: "system",
    cases,
};

fn cases(n: usize) -> Result<Vec<Case>, BenchError> {
    jamming_cases(n, OHERN2003, Protocol::Quench, "phi_j", |d| {
        if d == 2 {
            "2D disks 1:1.4".into()
        } else {
            "3D equal spheres".into()
        }
    })
}
