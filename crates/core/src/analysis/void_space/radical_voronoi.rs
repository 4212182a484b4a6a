//! The radical (Laguerre, power) Voronoi tessellation of a packing by voro++ (Rycroft, Chaos
//! 19, 041111, 2009), through the `voro_rs` binding's `container_poly`.
//!
//! The radical cell of sphere i is `{x : |x − c_i|² − R_i² ≤ |x − c_j|² − R_j² for all j}`;
//! for non-overlapping spheres it contains its sphere, and the cells tile the container.
//! Periodic axes are periodic in voro++; walled axes are its box faces; a ball over the first
//! two or three axes is voro++'s cylinder or sphere wall, which cuts each cell by the tangent
//! plane at the point of the wall nearest the particle (Rycroft 2009), so such cells, and their
//! sum, slightly exceed the curved container.
//!
//! 2D packings are tessellated as a single-layer slab: disks become spheres at mid-height of a
//! walled slab of thickness `h`; every radical plane between two of them is perpendicular to
//! the slab, so each cell is a prism over the 2D power cell and its area is volume / h.

use serde::{Deserialize, Serialize};
use voro_rs::prelude::*;

use super::{check_packing, mean_std};
use crate::analysis::structure::Histogram;
use crate::container::{Container, Shape};
use crate::error::CoreError;
use crate::geometry::ball_volume;
use crate::packing::Packing;

/// voro++'s ids for the six box faces are −1 … −6; the curved wall gets this one.
const CURVED_WALL_ID: i32 = -7;

/// Width, in units of the mean cell volume, of the histogram bins over which the Voronoi-volume
/// entropy is estimated. Fixed, so that entropies of different packings compare.
pub const ENTROPY_BIN_WIDTH: f64 = 0.01;

/// One radical cell as voro++ computed it, in the frame of its particle.
pub(crate) struct CellView<'a> {
    /// Particle index.
    pub id: usize,
    /// Particle centre as voro++ stored it (wrapped into the box), 3 coordinates (z = 0 in 2D).
    pub centre: [f64; 3],
    /// Cell volume (area in 2D).
    pub measure: f64,
    /// Vertices, 3 coordinates each, in the same frame as `centre` (not wrapped).
    pub vertices: &'a [f64],
    /// For each face: its neighbour (negative: a wall) and its vertex indices, in cyclic order.
    pub faces: &'a [(i32, Vec<usize>)],
}

/// Per-particle radical Voronoi cells.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct VoronoiCells {
    /// Cell volume of each particle (area in 2D), in length units to the power d.
    pub volumes: Vec<f64>,
    /// Local packing fraction of each particle: particle volume / cell volume.
    pub local_phi: Vec<f64>,
    /// Voronoi neighbours of each particle: faces shared with other particles (walls excluded;
    /// in 2D, edges of the power cell).
    pub faces: Vec<usize>,
}

/// Summary of the radical Voronoi tessellation (`packbench analyze --voronoi`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VoronoiReport {
    /// Sum of all cell volumes (the container volume, up to round-off, for box containers).
    pub total_volume: f64,
    /// Mean cell volume.
    pub mean_volume: f64,
    /// Standard deviation of the cell volumes divided by their mean.
    pub volume_std_relative: f64,
    /// Differential Shannon entropy `−Σ_b p_b ln p_b · Δ` of the density `p` of reduced cell
    /// volumes `v/⟨v⟩`, histogram estimate with bins of [`ENTROPY_BIN_WIDTH`].
    pub volume_entropy: f64,
    /// Mean local φ over particles.
    pub local_phi_mean: f64,
    /// Standard deviation of local φ over particles.
    pub local_phi_std: f64,
    /// Mean number of faces (Voronoi neighbours).
    pub faces_mean: f64,
    /// Density of local φ on 50 bins over [0, 1].
    pub local_phi_histogram: Histogram,
    /// The per-particle values (not serialised: N numbers each).
    #[serde(skip)]
    pub cells: VoronoiCells,
}

/// Thickness of the slab a 2D packing is tessellated in, relative to the largest diameter
/// (any positive value gives the same areas).
const SLAB_THICKNESS: f64 = 1.0;

/// Calls `visit` for the radical cell of every particle of `packing` (in voro++'s order) and
/// returns the particle count visited. Cells carry face neighbours and vertices.
///
/// Errors: what [`check_packing`] refuses; a container voro++ cannot cut; a cell that vanished
/// (a sphere swallowed by a larger one's power cell).
pub(crate) fn for_each_cell(
    packing: &Packing,
    subset: Option<&[usize]>,
    mut visit: impl FnMut(&CellView<'_>),
) -> Result<(), CoreError> {
    check_packing(packing)?;
    let c = &packing.container;
    let d = packing.dim;
    let max_d = packing.max_diameter();
    let slab = SLAB_THICKNESS * max_d;
    let (lo, hi, periodic) = if d == 3 {
        (
            [0.0; 3],
            [c.lengths[0], c.lengths[1], c.lengths[2]],
            [c.periodic[0], c.periodic[1], c.periodic[2]],
        )
    } else {
        (
            [0.0, 0.0, -0.5 * slab],
            [c.lengths[0], c.lengths[1], 0.5 * slab],
            [c.periodic[0], c.periodic[1], false],
        )
    };
    let (mut sphere_wall, mut cylinder_wall) = convex_walls(c)?;
    let members: Vec<usize> = match subset {
        Some(s) => s.to_vec(),
        None => (0..packing.n()).collect(),
    };
    let grids = block_grid(c, d, members.len());
    let mut con = ContainerRad::new(lo, hi, grids, periodic);
    if let Some(w) = sphere_wall.as_mut() {
        con.add_wall(w);
    }
    if let Some(w) = cylinder_wall.as_mut() {
        con.add_wall(w);
    }
    for &i in &members {
        let x = packing.position(i);
        let mut p = [0.0; 3];
        for k in 0..d {
            // Centres on a walled face (allowed by validation's tolerance) stay in voro++'s box.
            p[k] = if periodic[k] {
                x[k]
            } else {
                x[k].clamp(lo[k], hi[k])
            };
        }
        con.put(i as i32, p, 0.5 * packing.diameters[i]);
    }
    let mut seen = vec![false; packing.n()];
    let mut faces: Vec<(i32, Vec<usize>)> = Vec::new();
    let mut lp = LoopAll::of_container_rad(&mut con);
    if lp.start() {
        loop {
            let id = lp.particle_id() as usize;
            let centre = lp.position();
            let cell: Option<VoroCellNbr> = con.compute_cell(&mut lp);
            let Some(mut cell) = cell else {
                return Err(vanished(id));
            };
            let vertices = cell.vertices_global(centre);
            let neighbours = cell.neighbors();
            let fv = cell.face_vertices();
            faces.clear();
            let mut at = 0;
            for &nb in &neighbours {
                let m = fv[at] as usize;
                faces.push((
                    nb,
                    fv[at + 1..at + 1 + m].iter().map(|&v| v as usize).collect(),
                ));
                at += m + 1;
            }
            let mut measure = cell.volume();
            if d == 2 {
                measure /= slab;
            }
            seen[id] = true;
            visit(&CellView {
                id,
                centre,
                measure,
                vertices: &vertices,
                faces: &faces,
            });
            if !lp.inc() {
                break;
            }
        }
    }
    if let Some(&i) = members.iter().find(|&&i| !seen[i]) {
        return Err(vanished(i));
    }
    Ok(())
}

/// voro++'s walls for a curved container: a cylinder for a disk or cylinder (`Ball` over 2
/// axes), a sphere for a ball over 3; none for a box.
///
/// Errors: a container whose walls are not convex (cylindrical shells, hemisphere-cut bricks).
fn convex_walls(c: &Container) -> Result<(Option<WallSphere>, Option<WallCylinder>), CoreError> {
    let r = 0.5 * c.lengths[0];
    match &c.shape {
        Shape::Box => Ok((None, None)),
        Shape::Ball { axes: 2 } => {
            let axis = [0.0, 0.0, 1.0];
            let wall = WallCylinder::new_with_id([r, r, 0.0], axis, r, CURVED_WALL_ID);
            Ok((None, Some(wall)))
        }
        Shape::Ball { axes: 3 } => Ok((
            Some(WallSphere::new_with_id([r, r, r], r, CURVED_WALL_ID)),
            None,
        )),
        other => Err(CoreError::Container(format!(
            "the Voronoi analysis cannot cut cells by a {} container: voro++ walls must be convex (boxes, circles, cylinders and spheres are)",
            match other {
                Shape::CylindricalShell { .. } => "cylindrical-shell",
                Shape::HemisphereCutBrick { .. } => "hemisphere-cut brick",
                _ => "curved",
            }
        ))),
    }
}

/// Blocks per axis of voro++'s grid for `n` particles in `c`: about five particles per block,
/// where voro++ works best.
fn block_grid(c: &Container, d: usize, n: usize) -> [i32; 3] {
    let n = n.max(1) as f64;
    let extent: Vec<f64> = (0..d).map(|k| c.lengths[k]).collect();
    let block = (extent.iter().product::<f64>() / (n / 5.0)).powf(1.0 / d as f64);
    let mut grids = [1i32; 3];
    for k in 0..d {
        grids[k] = ((extent[k] / block).round() as i32).clamp(1, 1 << 10);
    }
    grids
}

fn vanished(i: usize) -> CoreError {
    CoreError::Packing(format!(
        "the radical Voronoi cell of particle {} is empty: it lies inside a larger sphere's power cell, which only strongly overlapping spheres do",
        i + 1
    ))
}

/// Collects the volume and face count of every cell that [`for_each_cell`] visits, so that
/// one tessellation can feed the cells and the pore network together.
pub(crate) struct CellCollector {
    volumes: Vec<f64>,
    faces: Vec<usize>,
}

impl CellCollector {
    /// Room for the `n` particles of a packing.
    pub fn new(n: usize) -> Self {
        CellCollector {
            volumes: vec![0.0; n],
            faces: vec![0; n],
        }
    }

    /// Records one cell.
    pub fn add(&mut self, cell: &CellView<'_>) {
        self.volumes[cell.id] = cell.measure;
        self.faces[cell.id] = cell.faces.iter().filter(|f| f.0 >= 0).count();
    }

    /// The cells, with local φ from the particle volumes of `packing`.
    pub fn finish(self, packing: &Packing) -> VoronoiCells {
        let local_phi = self
            .volumes
            .iter()
            .zip(&packing.diameters)
            .map(|(&v, &dia)| ball_volume(packing.dim, dia) / v)
            .collect();
        VoronoiCells {
            volumes: self.volumes,
            local_phi,
            faces: self.faces,
        }
    }
}

/// The radical Voronoi cell volume, local φ and face count of every particle.
///
/// Units: volumes in the packing's length unit to the power d (areas in 2D).
/// Errors: a dimension other than 2 or 3, coincident centres, overlaps above
/// [`super::MAX_RELATIVE_OVERLAP`], a cylindrical-shell or hemisphere-cut container, or a cell
/// that vanished.
pub fn radical_voronoi(packing: &Packing) -> Result<VoronoiCells, CoreError> {
    let mut cells = CellCollector::new(packing.n());
    for_each_cell(packing, None, |cell| cells.add(cell))?;
    Ok(cells.finish(packing))
}

/// The radical Voronoi tessellation with its summaries (see [`VoronoiReport`]).
///
/// Errors: those of [`radical_voronoi`].
pub fn voronoi(packing: &Packing) -> Result<VoronoiReport, CoreError> {
    Ok(summarize(radical_voronoi(packing)?))
}

/// The summaries of the cells (see [`VoronoiReport`]).
pub(crate) fn summarize(cells: VoronoiCells) -> VoronoiReport {
    let total_volume = cells.volumes.iter().sum::<f64>();
    let (mean_volume, std_volume) = mean_std(&cells.volumes);
    let reduced: Vec<f64> = cells.volumes.iter().map(|v| v / mean_volume).collect();
    let (local_phi_mean, local_phi_std) = mean_std(&cells.local_phi);
    let faces: Vec<f64> = cells.faces.iter().map(|&f| f as f64).collect();
    VoronoiReport {
        total_volume,
        mean_volume,
        volume_std_relative: std_volume / mean_volume,
        volume_entropy: differential_entropy(&reduced, ENTROPY_BIN_WIDTH),
        local_phi_mean,
        local_phi_std,
        faces_mean: mean_std(&faces).0,
        local_phi_histogram: Histogram::linear(&cells.local_phi, 0.0, 1.0, 50),
        cells,
    }
}

/// Differential Shannon entropy `S = −∫ p ln p dx` of the samples, estimated on bins of width
/// `width` anchored at 0: `S ≈ −Σ_b (n_b/n) ln(n_b/(n·width))` (Voronoi-volume entropy as in
/// the RCP literature cited by Baranau & Tallarek, Soft Matter 10, 3826 (2014), refs 9 and 14).
pub(crate) fn differential_entropy(samples: &[f64], width: f64) -> f64 {
    let mut counts = std::collections::BTreeMap::<i64, usize>::new();
    for &v in samples {
        *counts.entry((v / width).floor() as i64).or_default() += 1;
    }
    let n = samples.len() as f64;
    counts
        .values()
        .map(|&c| {
            let p = c as f64 / n;
            -p * (p / width).ln()
        })
        .sum()
}
