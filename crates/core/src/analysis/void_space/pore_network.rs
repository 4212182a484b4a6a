//! The pore network of a packing over its radical Voronoi tessellation (the Voronoi-network
//! approach of Zeo++, Willems et al., Micropor. Mesopor. Mat. 149, 134 (2012), and of Sastry,
//! Truskett, Debenedetti, Torquato & Stillinger, Mol. Phys. 95, 289 (1998)).
//!
//! - A **pore** is a Voronoi vertex; its size is the radius of the largest empty sphere centred
//!   there, the vertex's clearance (distance to the nearest sphere surface or wall).
//! - A **throat** is a Voronoi edge; its size is the radius of the largest sphere that can pass
//!   along it: the clearance at the edge's point of least power distance to its generating
//!   spheres (the bottleneck, where the edge crosses the plane of its three generators in the
//!   monodisperse case), clamped to the edge.
//! - **D_i**, the largest included sphere, is twice the largest pore radius.
//! - **D_f**, the largest free sphere, is twice the largest throat radius `r` such that the
//!   throats of radius ≥ `r` connect a pore to one of its own periodic images (a path that
//!   crosses the periodic box), found by adding throats from the widest down to a union–find
//!   that tracks image shifts. Undefined in a container with no periodic axis.
//! - The **pore-size distribution** (volume-weighted, Gelb & Gubbins, Langmuir 15, 305 (1999)):
//!   for void points drawn uniformly with a fixed seed, the diameter of the largest empty sphere
//!   covering the point, taken over the spheres centred at the point itself and at every pore.
//!
//! In 2D the network is that of the power diagram of the disks (vertices where three cells meet,
//! edges along cell boundaries). Pores are not merged into pore bodies.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};

use super::mean_std;
use super::radical_voronoi::{CellView, for_each_cell};
use super::sphere_grid::SphereGrid;
use crate::analysis::structure::Histogram;
use crate::error::CoreError;
use crate::packing::Packing;

/// Options of [`pores`].
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct PoreOptions {
    /// Void points sampled for the pore-size distribution (default 20 000).
    pub samples: usize,
    /// Seed of the void-point sampler.
    pub seed: u64,
    /// Bins of the pore- and throat-size histograms.
    pub bins: usize,
}

impl Default for PoreOptions {
    fn default() -> Self {
        PoreOptions {
            samples: 20_000,
            seed: 1,
            bins: 40,
        }
    }
}

/// The Voronoi network: pores (vertices) joined by throats (edges).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PoreNetwork {
    /// Dimension (2 or 3).
    pub dim: usize,
    /// Pore centres wrapped into the box, 3 coordinates each (z = 0 in 2D).
    pub centres: Vec<[f64; 3]>,
    /// Radius of the largest empty sphere at each pore.
    pub pore_radius: Vec<f64>,
    /// The two pores each throat joins.
    pub throats: Vec<[u32; 2]>,
    /// Radius of the largest sphere that passes along each throat.
    pub throat_radius: Vec<f64>,
    /// Periodic image shift of each throat: its second pore is `centres[b] + shift·L` seen from
    /// its first.
    pub throat_shift: Vec<[i32; 3]>,
}

/// Summary of the pore space (`packbench analyze --pores`). Lengths are diameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PoreReport {
    /// Number of pores (Voronoi vertices).
    pub pores: usize,
    /// Number of throats (Voronoi edges).
    pub throats: usize,
    /// Largest included sphere diameter D_i.
    pub included_sphere_diameter: f64,
    /// Largest free sphere diameter D_f; `None` without a periodic axis.
    pub free_sphere_diameter: Option<f64>,
    /// Mean covering diameter over sampled void points (volume-weighted mean pore size).
    pub pore_size_mean: f64,
    /// Volume-weighted pore-size distribution: density of the covering diameter.
    pub pore_size_distribution: Histogram,
    /// Mean throat diameter over throats.
    pub throat_size_mean: f64,
    /// Throat-size distribution: density of throat diameters over throats.
    pub throat_size_distribution: Histogram,
    /// Fraction of sampled points of the container that were void (estimates 1 − φ).
    pub void_fraction_sampled: f64,
    /// Covering diameters of the sampled void points (not serialised).
    #[serde(skip)]
    pub pore_size_samples: Vec<f64>,
    /// The network itself (not serialised).
    #[serde(skip)]
    pub network: Option<PoreNetwork>,
}

/// A multiplicative hasher for integer keys (the std SipHash is 3× slower here).
#[derive(Default)]
struct IntHasher(u64);

impl Hasher for IntHasher {
    fn finish(&self) -> u64 {
        // Fold the well-mixed high bits into the low ones, which index the table.
        self.0 ^ (self.0 >> 29)
    }
    fn write(&mut self, bytes: &[u8]) {
        // Integer arrays hash as one byte slice: take it eight bytes at a time.
        let mut words = bytes.chunks_exact(8);
        for w in &mut words {
            self.write_u64(u64::from_le_bytes(w.try_into().expect("eight bytes")));
        }
        for &b in words.remainder() {
            self.write_u64(b as u64);
        }
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }
    fn write_u32(&mut self, v: u32) {
        self.write_u64(v as u64);
    }
    fn write_i32(&mut self, v: i32) {
        self.write_u64(v as u32 as u64);
    }
    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }
}

type FastMap<K, V> = HashMap<K, V, BuildHasherDefault<IntHasher>>;

/// Voronoi vertices closer than this, relative to the mean particle spacing, are one pore
/// (voro++ splits degenerate vertices, as in crystals, into copies a round-off apart).
const MERGE_TOL: f64 = 1e-8;

/// Builds the pore network of `packing`.
///
/// Errors: those of [`super::radical_voronoi`].
pub fn pore_network(packing: &Packing) -> Result<PoreNetwork, CoreError> {
    let mut builder = NetworkBuilder::new(packing);
    for_each_cell(packing, None, |cell| builder.add(cell))?;
    Ok(builder.finish().0)
}

/// Builds the pore network from the cells [`for_each_cell`] visits, one at a time, so that
/// the tessellation that gives the cells gives the network too.
pub(crate) struct NetworkBuilder<'a> {
    packing: &'a Packing,
    grid: SphereGrid<'a>,
    /// Merge tolerance and the bins of the vertex index (`i64::MAX` on walled axes).
    q: f64,
    bins: [i64; 3],
    lengths: [f64; 3],
    periodic: [bool; 3],
    index: FastMap<[i64; 3], u32>,
    edges: FastMap<(u32, u32, [i32; 3]), ()>,
    /// The pore of each vertex of the current cell (`None`: the top copy of a 2D prism).
    local: Vec<Option<u32>>,
    net: PoreNetwork,
}

impl<'a> NetworkBuilder<'a> {
    /// An empty network over the spheres of `packing`.
    pub fn new(packing: &'a Packing) -> Self {
        let d = packing.dim;
        let c = &packing.container;
        let spacing = (c.lengths.iter().product::<f64>() / packing.n() as f64).powf(1.0 / d as f64);
        let q = MERGE_TOL * spacing;
        let mut lengths = [f64::INFINITY; 3];
        let mut periodic = [false; 3];
        lengths[..d].copy_from_slice(&c.lengths[..d]);
        periodic[..d].copy_from_slice(&c.periodic[..d]);
        let bins = std::array::from_fn(|k| {
            if periodic[k] {
                (lengths[k] / q).ceil() as i64
            } else {
                i64::MAX
            }
        });
        NetworkBuilder {
            packing,
            grid: SphereGrid::new(packing, None),
            q,
            bins,
            lengths,
            periodic,
            index: FastMap::default(),
            edges: FastMap::default(),
            local: Vec::new(),
            net: PoreNetwork {
                dim: d,
                centres: Vec::new(),
                pore_radius: Vec::new(),
                throats: Vec::new(),
                throat_radius: Vec::new(),
                throat_shift: Vec::new(),
            },
        }
    }

    /// Adds the vertices and edges of one cell: new pores and throats get their clearance.
    pub fn add(&mut self, cell: &CellView<'_>) {
        let d = self.packing.dim;
        let c = &self.packing.container;
        // Every vertex and edge of the cell touches its particle's power cell, so the distance
        // to that particle's surface bounds the clearance and narrows its search.
        let own_radius = 0.5 * self.packing.diameters[cell.id];
        let own_gap = |p: &[f64]| {
            let mut r2 = 0.0;
            for k in 0..d {
                r2 += (p[k] - cell.centre[k]) * (p[k] - cell.centre[k]);
            }
            r2.sqrt() - own_radius
        };
        let nv = cell.vertices.len() / 3;
        self.local.clear();
        self.local.resize(nv, None);
        for v in 0..nv {
            let p = &cell.vertices[3 * v..3 * v + 3];
            // In 2D each vertex of the power cell is a vertical edge of the prism: keep its foot.
            if d == 2 && p[2] > 0.0 {
                continue;
            }
            let mut w = [p[0], p[1], if d == 2 { 0.0 } else { p[2] }];
            c.wrap(&mut w[..d]);
            let id = find_or_insert(
                &mut self.index,
                &mut self.net.centres,
                &w,
                self.q,
                &self.bins,
            );
            if id as usize == self.net.pore_radius.len() {
                self.net
                    .pore_radius
                    .push(self.grid.clearance_below(&w, own_gap(p)));
            }
            self.local[v] = Some(id);
        }
        for (_, face) in cell.faces {
            for (t, &a) in face.iter().enumerate() {
                let b = face[(t + 1) % face.len()];
                // Each edge of the cell borders two faces, once in each direction: take it once.
                if a > b {
                    continue;
                }
                let (Some(ga), Some(gb)) = (self.local[a], self.local[b]) else {
                    continue;
                };
                if ga == gb {
                    continue;
                }
                let pa = &cell.vertices[3 * a..3 * a + 3];
                let pb = &cell.vertices[3 * b..3 * b + 3];
                let (wa, wb) = (self.net.centres[ga as usize], self.net.centres[gb as usize]);
                let mut shift = [0i32; 3];
                for k in 0..d {
                    if self.periodic[k] {
                        let jump = (pb[k] - pa[k]) - (wb[k] - wa[k]);
                        shift[k] = (jump / self.lengths[k]).round() as i32;
                    }
                }
                let key = if ga < gb {
                    (ga, gb, shift)
                } else {
                    (gb, ga, shift.map(|s| -s))
                };
                if self.edges.insert(key, ()).is_some() {
                    continue;
                }
                // The point of least power along the edge (the same for all its generators).
                let mut e = [0.0; 3];
                let mut ce = 0.0;
                let mut ee = 0.0;
                for k in 0..d {
                    e[k] = pb[k] - pa[k];
                    ce += (cell.centre[k] - pa[k]) * e[k];
                    ee += e[k] * e[k];
                }
                let t_star = if ee > 0.0 {
                    (ce / ee).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let mut x = [0.0; 3];
                for k in 0..d {
                    x[k] = pa[k] + t_star * e[k];
                }
                let bound = own_gap(&x);
                c.wrap(&mut x[..d]);
                self.net.throats.push([key.0, key.1]);
                self.net.throat_shift.push(key.2);
                self.net
                    .throat_radius
                    .push(self.grid.clearance_below(&x, bound));
            }
        }
    }

    /// The network, and the grid of the packing's spheres it measured clearances on.
    pub fn finish(self) -> (PoreNetwork, SphereGrid<'a>) {
        (self.net, self.grid)
    }
}

/// The id of the stored vertex within `q` of `w` on every axis, inserting `w` if there is none.
fn find_or_insert(
    index: &mut FastMap<[i64; 3], u32>,
    centres: &mut Vec<[f64; 3]>,
    w: &[f64; 3],
    q: f64,
    bins: &[i64],
) -> u32 {
    let mut home = [0i64; 3];
    let mut toward = [0i64; 3];
    for k in 0..3 {
        let s = w[k] / q;
        home[k] = s.floor() as i64;
        toward[k] = if s - s.floor() < 0.5 { -1 } else { 1 };
    }
    for corner in 0..8u32 {
        let mut key = home;
        for k in 0..3 {
            if corner & (1 << k) != 0 {
                key[k] += toward[k];
            }
            if bins[k] != i64::MAX {
                key[k] = key[k].rem_euclid(bins[k]);
            }
        }
        if let Some(&id) = index.get(&key) {
            return id;
        }
    }
    let mut key = home;
    for k in 0..3 {
        if bins[k] != i64::MAX {
            key[k] = key[k].rem_euclid(bins[k]);
        }
    }
    let id = centres.len() as u32;
    index.insert(key, id);
    centres.push(*w);
    id
}

/// Radius of the largest free sphere: the largest throat radius `r` such that the throats of
/// radius ≥ `r` contain a cycle that winds around a periodic axis. `None` if none does (no
/// periodic axis, or a network that never spans the box).
pub fn free_sphere_radius(net: &PoreNetwork) -> Option<f64> {
    let n = net.centres.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    // offset[x]: image of x's parent, in box lengths, as seen from x.
    let mut offset: Vec<[i32; 3]> = vec![[0; 3]; n];
    let mut order: Vec<usize> = (0..net.throats.len()).collect();
    order.sort_by(|&a, &b| net.throat_radius[b].total_cmp(&net.throat_radius[a]));
    let mut size: Vec<u32> = vec![1; n];
    let mut path: Vec<u32> = Vec::new();
    // Root of x and g(x) − g(root), g the integer image of a node in its cluster's lift.
    let mut find = |parent: &mut [u32], offset: &mut [[i32; 3]], x: u32| {
        path.clear();
        let mut r = x;
        while parent[r as usize] != r {
            path.push(r);
            r = parent[r as usize];
        }
        // Compress from the node nearest the root down, summing offsets to the root.
        let mut acc = [0i32; 3];
        for &y in path.iter().rev() {
            for k in 0..3 {
                acc[k] += offset[y as usize][k];
            }
            offset[y as usize] = acc;
            parent[y as usize] = r;
        }
        (r, if x == r { [0; 3] } else { offset[x as usize] })
    };
    for t in order {
        let [a, b] = net.throats[t];
        let s = net.throat_shift[t];
        let (ra, oa) = find(&mut parent, &mut offset, a);
        let (rb, ob) = find(&mut parent, &mut offset, b);
        // The throat asks g(b) − g(a) = s; in the lifts so far g(b) − g(a) = ob − oa + g(rb) − g(ra).
        let mut rel = [0i32; 3];
        for k in 0..3 {
            rel[k] = ob[k] - oa[k] - s[k];
        }
        if ra == rb {
            if rel != [0; 3] {
                return Some(net.throat_radius[t]);
            }
        } else if size[ra as usize] <= size[rb as usize] {
            // g(ra) − g(rb) = ob − s − oa.
            parent[ra as usize] = rb;
            offset[ra as usize] = rel;
            size[rb as usize] += size[ra as usize];
        } else {
            parent[rb as usize] = ra;
            offset[rb as usize] = rel.map(|v| -v);
            size[ra as usize] += size[rb as usize];
        }
    }
    None
}

/// The pore network with its summaries (see [`PoreReport`]).
///
/// Errors: those of [`super::radical_voronoi`], and `options.samples` or `options.bins` zero.
pub fn pores(packing: &Packing, options: &PoreOptions) -> Result<PoreReport, CoreError> {
    check_options(options)?;
    let mut builder = NetworkBuilder::new(packing);
    for_each_cell(packing, None, |cell| builder.add(cell))?;
    let (net, spheres) = builder.finish();
    pore_report(packing, net, &spheres, options)
}

/// Refuses options that leave nothing to sample or bin.
pub(crate) fn check_options(options: &PoreOptions) -> Result<(), CoreError> {
    if options.samples == 0 || options.bins == 0 {
        return Err(CoreError::Parameter(
            "the pore analysis needs at least one sample point and one histogram bin".into(),
        ));
    }
    Ok(())
}

/// The summaries of the network `net` of `packing`, whose spheres `spheres` holds.
pub(crate) fn pore_report(
    packing: &Packing,
    net: PoreNetwork,
    spheres: &SphereGrid<'_>,
    options: &PoreOptions,
) -> Result<PoreReport, CoreError> {
    let d = packing.dim;
    let c = &packing.container;
    let r_pore_max = net.pore_radius.iter().cloned().fold(0.0, f64::max);
    let pore_grid = SphereGrid::from_spheres(c, d, net.centres.clone(), net.pore_radius.clone());
    let mut rng = StdRng::seed_from_u64(options.seed);
    let mut samples = Vec::with_capacity(options.samples);
    let mut drawn = 0usize;
    let mut inside = 0usize;
    // Rejection sampling stops after many tries, should the void be (almost) empty.
    let max_draws = 1000 * options.samples;
    while samples.len() < options.samples && drawn < max_draws {
        drawn += 1;
        let mut x = [0.0; 3];
        for k in 0..d {
            x[k] = rng.random_range(0.0..c.lengths[k]);
        }
        if !c.contains(&x[..d], 0.0, 0.0) {
            continue;
        }
        inside += 1;
        let own = spheres.clearance(&x);
        if own <= 0.0 {
            continue;
        }
        let mut cover = own;
        pore_grid.for_each_near(&x, r_pore_max, |s, v| {
            let (_, r) = pore_grid.sphere(s);
            if r > cover && v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= r * r {
                cover = r;
            }
        });
        samples.push(2.0 * cover);
    }
    if samples.is_empty() {
        return Err(CoreError::Packing(
            "no void point was found in the container, so there is no pore space to measure".into(),
        ));
    }
    let throat_d: Vec<f64> = net.throat_radius.iter().map(|r| 2.0 * r).collect();
    let hist = |v: &[f64]| {
        let hi = v.iter().cloned().fold(0.0, f64::max);
        Histogram::linear(v, 0.0, hi * (1.0 + 1e-9), options.bins)
    };
    let free = if c.periodic.iter().any(|&p| p) {
        free_sphere_radius(&net).map(|r| 2.0 * r)
    } else {
        None
    };
    Ok(PoreReport {
        pores: net.centres.len(),
        throats: net.throats.len(),
        included_sphere_diameter: 2.0 * r_pore_max,
        free_sphere_diameter: free,
        pore_size_mean: mean_std(&samples).0,
        pore_size_distribution: hist(&samples),
        throat_size_mean: mean_std(&throat_d).0,
        throat_size_distribution: hist(&throat_d),
        void_fraction_sampled: samples.len() as f64 / inside.max(1) as f64,
        pore_size_samples: samples,
        network: Some(net),
    })
}
