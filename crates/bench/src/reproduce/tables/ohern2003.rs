//! O'Hern, Silbert, Liu & Nagel, Phys. Rev. E 68, 011306 (2003): point J of frictionless soft
//! spheres — φ_J and the contact number z at jamming for 2D disks 1 : 1.4 at equal numbers and
//! 3D equal spheres.
//!
//! Their protocol quenches random states of soft harmonic spheres by energy minimisation and
//! finds the φ at which the energy first stays above zero; `adam` is that protocol (soft
//! harmonic overlaps, inflate while the energy is ~0, deflate when not, minimised at each
//! step). Their φ_J are large-N limits; packbench runs the N given.

use super::super::published::OHERN2003;
use super::super::{Case, Table};
use super::dimensions::{Protocol, jamming_cases};
use crate::error::BenchError;

/// φ_J and z in 2D and 3D.
pub const TABLE: Table = Table {
    name: "ohern-2003",
    source: "C. S. O'Hern, L. E. Silbert, A. J. Liu and S. R. Nagel, Phys. Rev. E 68, 011306 \
        (2003), φ_J (large-N limit) and z_c = 2d in 2D and 3D",
    protocol: "adam (soft harmonic spheres inflated and minimised, RCPGenerator's schedule) \
        from random sequential addition at φ = 0.05, periodic box; z over non-rattlers",
    published_n: None,
    default_n: Some(1000),
    min_n: 50,
    axis: "system",
    cases,
};

fn cases(n: usize) -> Result<Vec<Case>, BenchError> {
    jamming_cases(n, OHERN2003, Protocol::Adam, "phi_j", |d| {
        if d == 2 {
            "2D disks 1:1.4".into()
        } else {
            "3D equal spheres".into()
        }
    })
}
