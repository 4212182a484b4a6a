//! A uniform grid of sphere centres in 2D or 3D (z = 0 in 2D) answering the void-space
//! queries: the spheres near a point, and the clearance of a point (its distance to the nearest
//! sphere surface or wall).

use crate::container::Container;
use crate::packing::Packing;

/// Sphere centres binned on a grid of about one particle per cell.
pub(crate) struct SphereGrid<'a> {
    container: &'a Container,
    dim: usize,
    lengths: [f64; 3],
    periodic: [bool; 3],
    counts: [usize; 3],
    widths: [f64; 3],
    /// `start[c]..start[c+1]` indexes `order` for the spheres of cell `c`.
    start: Vec<u32>,
    order: Vec<u32>,
    centres: Vec<[f64; 3]>,
    radii: Vec<f64>,
    /// Largest radius.
    pub r_max: f64,
}

impl<'a> SphereGrid<'a> {
    /// Bins the spheres `members` of `packing` (all when `None`).
    pub fn new(packing: &'a Packing, members: Option<&[usize]>) -> Self {
        let c = &packing.container;
        let d = packing.dim;
        let ids: Vec<usize> = match members {
            Some(m) => m.to_vec(),
            None => (0..packing.n()).collect(),
        };
        let centres: Vec<[f64; 3]> = ids
            .iter()
            .map(|&i| {
                let mut x = [0.0; 3];
                x[..d].copy_from_slice(packing.position(i));
                c.wrap(&mut x[..d]);
                x
            })
            .collect();
        let radii: Vec<f64> = ids.iter().map(|&i| 0.5 * packing.diameters[i]).collect();
        Self::from_spheres(c, d, centres, radii)
    }

    /// Bins spheres given by wrapped `centres` (z = 0 in 2D) and `radii` in `container`.
    pub fn from_spheres(
        container: &'a Container,
        dim: usize,
        centres: Vec<[f64; 3]>,
        radii: Vec<f64>,
    ) -> Self {
        let d = dim;
        let c = container;
        let mut lengths = [1.0; 3];
        let mut periodic = [false; 3];
        lengths[..d].copy_from_slice(&c.lengths[..d]);
        periodic[..d].copy_from_slice(&c.periodic[..d]);
        let volume: f64 = lengths[..d].iter().product();
        let w = (volume / centres.len().max(1) as f64).powf(1.0 / d as f64);
        let mut counts = [1usize; 3];
        let mut widths = [1.0; 3];
        for k in 0..d {
            counts[k] = ((lengths[k] / w).floor() as usize).clamp(1, 1 << 12);
            widths[k] = lengths[k] / counts[k] as f64;
        }
        let total = counts.iter().product::<usize>();
        let mut start = vec![0u32; total + 1];
        let cell_of: Vec<usize> = centres
            .iter()
            .map(|x| {
                let mut cell = 0;
                for k in 0..3 {
                    cell = cell * counts[k] + axis_cell(x[k], widths[k], counts[k]);
                }
                cell
            })
            .collect();
        for &cell in &cell_of {
            start[cell + 1] += 1;
        }
        for cell in 0..total {
            start[cell + 1] += start[cell];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; centres.len()];
        for (s, &cell) in cell_of.iter().enumerate() {
            order[fill[cell] as usize] = s as u32;
            fill[cell] += 1;
        }
        let r_max = radii.iter().cloned().fold(0.0, f64::max);
        SphereGrid {
            container: c,
            dim: d,
            lengths,
            periodic,
            counts,
            widths,
            start,
            order,
            centres,
            radii,
            r_max,
        }
    }

    /// The narrowest cell width: a step along a line that misses no cell.
    pub fn step(&self) -> f64 {
        self.widths[..self.dim]
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min)
    }

    /// `x` wrapped into the box along periodic axes.
    pub fn wrap(&self, mut x: [f64; 3]) -> [f64; 3] {
        for k in 0..self.dim {
            if self.periodic[k] {
                x[k] -= self.lengths[k] * (x[k] / self.lengths[k]).floor();
            }
        }
        x
    }

    /// Centre (wrapped, z = 0 in 2D) and radius of sphere `s` (its index among the members).
    pub fn sphere(&self, s: usize) -> ([f64; 3], f64) {
        (self.centres[s], self.radii[s])
    }

    /// Calls `f(s, v)` for every sphere `s` whose centre may lie within `reach` of `x`
    /// (a superset: every cell within `reach` is visited once), `v` the vector from `x` to the
    /// image of its centre in the visited cell (the minimum image whenever `reach` is below half
    /// a periodic side).
    pub fn for_each_near(&self, x: &[f64; 3], reach: f64, mut f: impl FnMut(usize, [f64; 3])) {
        let mut lo = [0i64; 3];
        let mut hi = [0i64; 3];
        // Axes whose every cell is visited: their images are taken by minimum image per sphere.
        let mut whole = [false; 3];
        for k in 0..3 {
            let home = axis_cell(x[k], self.widths[k], self.counts[k]) as i64;
            let span = (reach / self.widths[k]).ceil() as i64;
            let n = self.counts[k] as i64;
            if k >= self.dim || (self.periodic[k] && 2 * span + 1 >= n) {
                // The whole axis, each cell once.
                lo[k] = 0;
                hi[k] = n - 1;
                whole[k] = k < self.dim && self.periodic[k];
            } else if self.periodic[k] {
                lo[k] = home - span;
                hi[k] = home + span;
            } else {
                lo[k] = (home - span).max(0);
                hi[k] = (home + span).min(n - 1);
            }
        }
        let any_whole = whole.iter().any(|&w| w);
        // The image of a cell `a` on axis k lies `a.div_euclid(n)` box lengths away: one shift per
        // cell rather than one rounding per sphere.
        let axis = |k: usize, a: i64| {
            let n = self.counts[k] as i64;
            let shift = if whole[k] {
                0.0
            } else {
                a.div_euclid(n) as f64 * self.lengths[k]
            };
            (a.rem_euclid(n) as usize, shift - x[k])
        };
        for a in lo[0]..=hi[0] {
            let (ca, oa) = axis(0, a);
            for b in lo[1]..=hi[1] {
                let (cb, ob) = axis(1, b);
                for e in lo[2]..=hi[2] {
                    let (ce, oe) = axis(2, e);
                    let cell = (ca * self.counts[1] + cb) * self.counts[2] + ce;
                    for &s in &self.order[self.start[cell] as usize..self.start[cell + 1] as usize]
                    {
                        let s = s as usize;
                        let c = &self.centres[s];
                        let mut v = [c[0] + oa, c[1] + ob, c[2] + oe];
                        if any_whole {
                            for k in 0..3 {
                                if whole[k] {
                                    v[k] -= self.lengths[k] * (v[k] / self.lengths[k]).round();
                                }
                            }
                        }
                        f(s, v);
                    }
                }
            }
        }
    }

    /// [`Self::clearance`] given an upper `bound` on it (the distance from `x` to the surface of
    /// a sphere known to be near): one search within `bound + R_max`, exact, and much narrower
    /// than a search from scratch when the bound is tight.
    pub fn clearance_below(&self, x: &[f64; 3], bound: f64) -> f64 {
        let mut best = if self.container.has_walls() {
            self.container.wall_clearance(&x[..self.dim]).min(bound)
        } else {
            bound
        };
        // A sphere nearer than `best` has its centre within best + R_max of x.
        let reach = (best + self.r_max).max(0.0).min(self.diagonal());
        self.for_each_near(x, reach, |s, v| {
            let g = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() - self.radii[s];
            best = best.min(g);
        });
        best
    }

    /// Distance from `x` to the nearest sphere surface or container wall: the radius of the
    /// largest empty sphere centred at `x` (negative inside a sphere).
    pub fn clearance(&self, x: &[f64; 3]) -> f64 {
        let mut best = if self.container.has_walls() {
            self.container.wall_clearance(&x[..self.dim])
        } else {
            f64::INFINITY
        };
        let w_min = self.widths[..self.dim]
            .iter()
            .cloned()
            .fold(f64::INFINITY, f64::min);
        let mut reach = w_min + self.r_max;
        loop {
            self.for_each_near(x, reach, |s, v| {
                let g = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() - self.radii[s];
                best = best.min(g);
            });
            // Every unvisited centre is farther than `reach` from x.
            if best <= reach - self.r_max || reach >= self.diagonal() {
                return best;
            }
            reach = (best + self.r_max).min(self.diagonal());
        }
    }

    /// The sphere whose power distance `|x − c|² − R²` from `x` is least: the radical cell
    /// that contains `x`. `None` when no sphere is binned.
    pub fn power_nearest(&self, x: &[f64; 3]) -> Option<usize> {
        if self.radii.is_empty() {
            return None;
        }
        let mut best = (f64::INFINITY, usize::MAX);
        let mut reach = self.step() + self.r_max;
        loop {
            self.for_each_near(x, reach, |s, v| {
                let p = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - self.radii[s] * self.radii[s];
                if p < best.0 || (p == best.0 && s < best.1) {
                    best = (p, s);
                }
            });
            // Every unvisited centre has power above reach² − R_max².
            if best.0 <= reach * reach - self.r_max * self.r_max || reach >= self.diagonal() {
                return Some(best.1);
            }
            reach = (best.0 + self.r_max * self.r_max)
                .max(0.0)
                .sqrt()
                .min(self.diagonal());
        }
    }

    fn diagonal(&self) -> f64 {
        self.lengths[..self.dim]
            .iter()
            .map(|l| l * l)
            .sum::<f64>()
            .sqrt()
    }
}

#[inline]
fn axis_cell(x: f64, width: f64, count: usize) -> usize {
    ((x / width).floor().max(0.0) as usize).min(count - 1)
}
