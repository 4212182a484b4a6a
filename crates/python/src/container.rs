//! The container keywords of every function (`box`, `walls`, `fix_height`, `shell`,
//! `hemispheres`), read by the command line's own container flags so that they mean what
//! `--box`, `--walls`, `--fix-height`, `--shell` and `--hemispheres` mean.

use packbench::args::ContainerArgs;
use packbench_core::{Container, Shape};
use pyo3::PyResult;

use crate::errors::value_err;

/// The container keywords as given from Python.
#[derive(Clone, Debug, Default)]
pub struct ContainerKeywords {
    /// Box lengths per axis (default 1 on every axis).
    pub box_lengths: Option<Vec<f64>>,
    /// Per axis 0 periodic, 1 hard wall; a negative first entry −t: a ball over t axes.
    pub walls: Option<Vec<i64>>,
    /// The last box length is a multiple of the largest diameter, held there.
    pub fix_height: bool,
    /// A cylindrical shell over the first two axes: inner and outer radius.
    pub shell: Option<Vec<f64>>,
    /// A walled brick minus two hemispheres of these radii.
    pub hemispheres: Option<Vec<f64>>,
}

impl ContainerKeywords {
    /// The keywords `box`, `walls`, `fix_height`, `shell` and `hemispheres` of a function.
    pub fn new(
        box_lengths: Option<Vec<f64>>,
        walls: Option<Vec<i64>>,
        fix_height: bool,
        shell: Option<Vec<f64>>,
        hemispheres: Option<Vec<f64>>,
    ) -> Self {
        ContainerKeywords {
            box_lengths,
            walls,
            fix_height,
            shell,
            hemispheres,
        }
    }

    /// Refuses keywords given with a `Packing`, which has its container (ValueError).
    pub fn refuse_for_packing(&self) -> PyResult<()> {
        if self.args().is_empty() && !self.fix_height {
            return Ok(());
        }
        Err(value_err(
            "box, walls, fix_height, shell and hemispheres apply to positions and diameters; a Packing has its container",
        ))
    }

    /// The command-line flags these keywords stand for.
    pub fn args(&self) -> ContainerArgs {
        ContainerArgs {
            box_lengths: self.box_lengths.clone(),
            walls: self.walls.clone(),
            fix_height: self.fix_height,
            shell: self.shell.clone(),
            hemispheres: self.hemispheres.clone(),
        }
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
