//! The container keywords of every function (`box`, `walls`, `fix_height`, `shell`,
//! `hemispheres`), read by the command line's own container flags so that they mean what
//! `--box`, `--walls`, `--fix-height`, `--shell` and `--hemispheres` mean.

use packbench::args::ContainerArgs;
use packbench_core::{Container, Shape};
use pyo3::PyResult;

use crate::errors::value_err;

/// The container keywords as given from Python: the command line's container flags
/// themselves, so that each keyword is read exactly as its flag.
#[derive(Clone, Debug, Default)]
pub struct ContainerKeywords(ContainerArgs);

impl ContainerKeywords {
    /// The keywords `box`, `walls`, `fix_height`, `shell` and `hemispheres` of a function.
    pub fn new(
        box_lengths: Option<Vec<f64>>,
        walls: Option<Vec<i64>>,
        fix_height: bool,
        shell: Option<Vec<f64>>,
        hemispheres: Option<Vec<f64>>,
    ) -> Self {
        ContainerKeywords(ContainerArgs {
            box_lengths,
            walls,
            fix_height,
            shell,
            hemispheres,
        })
    }

    /// Refuses keywords given with a `Packing`, which has its container (ValueError).
    pub fn refuse_for_packing(&self) -> PyResult<()> {
        if self.0.is_empty() && !self.0.fix_height {
            return Ok(());
        }
        Err(value_err(
            "box, walls, fix_height, shell and hemispheres apply to positions and diameters; a Packing has its container",
        ))
    }

    /// The command-line flags these keywords stand for.
    pub fn args(&self) -> ContainerArgs {
        self.0.clone()
    }
}

/// RCPGenerator's `--walls` list of a container: 0 periodic and 1 walled per axis, with −t
/// first for a ball over t axes. `None` for the shapes RCPGenerator lacks (a shell, a
/// hemisphere-cut brick).
pub fn rcp_walls(c: &Container) -> Option<Vec<i64>> {
    let flags = c.periodic.iter().map(|&p| i64::from(!p));
    match c.shape {
        Shape::Box => Some(flags.collect()),
        Shape::Ball { axes } => Some(
            flags
                .enumerate()
                .map(|(k, f)| match k {
                    0 => -(axes as i64),
                    k if k < axes => 1,
                    _ => f,
                })
                .collect(),
        ),
        Shape::CylindricalShell { .. } | Shape::HemisphereCutBrick { .. } => None,
    }
}
