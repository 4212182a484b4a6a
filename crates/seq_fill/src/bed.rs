//! The bed of one unit brick as it grows: centres, radii, the spatial grid, each sphere's
//! candidate parents (surface gap ≤ δ·r̄) and the contacts (gap ≤ ε·r̄) recorded as each sphere
//! is placed (Black & Cheviakov 2022 §2.1), plus the fixed spherical obstacles of the hemisphere-cut domain.

use crate::grid::Grid;

/// Ids at or above this refer to obstacles (the hemispheres of Example 3), not spheres.
pub(crate) const OBSTACLE_BASE: u32 = u32::MAX - 16;

/// Relative tolerance of the overlap test: a pair is accepted at r ≥ (R_i + R_j)(1 − 1e-12),
/// so exact tangency survives rounding and no overlap exceeds it.
const OVERLAP_TOL: f64 = 1e-12;

/// A fixed convex spherical obstacle (a hemisphere, seen from inside the domain).
pub(crate) struct Obstacle<const D: usize> {
    pub centre: [f64; D],
    pub radius: f64,
    /// Spheres within δ·r̄ of its surface: candidate co-parents.
    pub near: Vec<u32>,
    /// The wall id the core's container gives this obstacle.
    pub wall: usize,
}

/// The spheres of a unit brick `[0, L_k]` (walled for Method 1 and Example 3, a periodic
/// cell for Method 2).
pub(crate) struct Bed<const D: usize> {
    pub lengths: [f64; D],
    pub periodic: bool,
    pub centres: Vec<[f64; D]>,
    pub radii: Vec<f64>,
    /// Candidate co-parents of each sphere (gap ≤ δ·r̄), obstacles included.
    pub near: Vec<Vec<u32>>,
    /// Contacts (i < j) recorded at placement.
    pub contacts: Vec<[u32; 2]>,
    pub obstacles: Vec<Obstacle<D>>,
    /// Absolute parent gap δ·r̄ and contact gap ε·r̄.
    pub parent_gap: f64,
    pub contact_gap: f64,
    /// Depth of overlap a new sphere may have with a placed one (0: none; ε·r̄ when
    /// [`crate::Params::contact_overlap`] is set).
    pub overlap_allowed: f64,
    grid: Grid<D>,
}

impl<const D: usize> Bed<D> {
    /// An empty bed; `cell` is the grid's nominal cell width, `max_cells` bounds its size.
    pub(crate) fn new(
        lengths: [f64; D],
        periodic: bool,
        parent_gap: f64,
        contact_gap: f64,
        cell: f64,
        max_cells: usize,
    ) -> Self {
        Bed {
            lengths,
            periodic,
            centres: Vec::new(),
            radii: Vec::new(),
            near: Vec::new(),
            contacts: Vec::new(),
            obstacles: Vec::new(),
            parent_gap,
            contact_gap,
            overlap_allowed: 0.0,
            grid: Grid::new(&lengths, cell, max_cells, periodic),
        }
    }

    /// Number of spheres.
    pub(crate) fn len(&self) -> usize {
        self.radii.len()
    }

    fn margin(&self) -> f64 {
        self.parent_gap.max(self.contact_gap)
    }

    /// Separation `b − a`, by minimum image in a periodic brick.
    pub(crate) fn separation(&self, a: &[f64; D], b: &[f64; D]) -> [f64; D] {
        let mut v = [0.0; D];
        for k in 0..D {
            v[k] = b[k] - a[k];
            if self.periodic {
                let l = self.lengths[k];
                v[k] -= l * (v[k] / l).round();
            }
        }
        v
    }

    fn distance(&self, a: &[f64; D], b: &[f64; D]) -> f64 {
        self.separation(a, b)
            .iter()
            .map(|v| v * v)
            .sum::<f64>()
            .sqrt()
    }

    /// Centre and radius of a sphere or obstacle id.
    pub(crate) fn parent(&self, id: u32) -> ([f64; D], f64) {
        if id >= OBSTACLE_BASE {
            let o = &self.obstacles[(id - OBSTACLE_BASE) as usize];
            (o.centre, o.radius)
        } else {
            (self.centres[id as usize], self.radii[id as usize])
        }
    }

    /// Candidate co-parents of a sphere or obstacle.
    pub(crate) fn near_of(&self, id: u32) -> &[u32] {
        if id >= OBSTACLE_BASE {
            &self.obstacles[(id - OBSTACLE_BASE) as usize].near
        } else {
            &self.near[id as usize]
        }
    }

    /// Whether `a` and `b` are candidate co-parents (obstacles are never near each other).
    pub(crate) fn are_near(&self, a: u32, b: u32) -> bool {
        let (s, o) = if a < OBSTACLE_BASE { (a, b) } else { (b, a) };
        s < OBSTACLE_BASE && self.near[s as usize].contains(&o)
    }

    /// True when a sphere of radius `r` at `x` overlaps no obstacle and no sphere by more than
    /// `overlap_allowed`.
    pub(crate) fn is_free(&mut self, x: &[f64; D], r: f64) -> bool {
        for o in &self.obstacles {
            let s = (o.radius + r) * (1.0 - OVERLAP_TOL);
            if self.distance(x, &o.centre) < s {
                return false;
            }
        }
        let mut free = true;
        let (centres, radii, periodic, lengths, allowed) = (
            &self.centres,
            &self.radii,
            self.periodic,
            self.lengths,
            self.overlap_allowed,
        );
        self.grid.for_each_candidate(x, r, |j| {
            if !free {
                return;
            }
            let c = &centres[j as usize];
            let s = (r + radii[j as usize]) * (1.0 - OVERLAP_TOL) - allowed;
            let mut d2 = 0.0;
            for k in 0..D {
                let mut v = c[k] - x[k];
                if periodic {
                    v -= lengths[k] * (v / lengths[k]).round();
                }
                d2 += v * v;
            }
            if d2 < s * s {
                free = false;
            }
        });
        free
    }

    /// Adds a sphere (already checked free), records its contacts and candidate parents, and
    /// returns its id.
    pub(crate) fn place(&mut self, x: [f64; D], r: f64) -> u32 {
        let id = self.radii.len() as u32;
        let (pgap, cgap) = (self.parent_gap, self.contact_gap);
        let mut near = Vec::new();
        let mut contacts = Vec::new();
        let mut found = Vec::new();
        self.grid.for_each_candidate(&x, r, |j| found.push(j));
        for j in found {
            let gap = self.distance(&x, &self.centres[j as usize]) - r - self.radii[j as usize];
            if gap <= pgap {
                near.push(j);
            }
            if gap <= cgap {
                contacts.push([j, id]);
            }
        }
        for (o_idx, o) in self.obstacles.iter_mut().enumerate() {
            let v: f64 = (0..D).map(|k| (x[k] - o.centre[k]).powi(2)).sum();
            if v.sqrt() - o.radius - r <= pgap {
                near.push(OBSTACLE_BASE + o_idx as u32);
                o.near.push(id);
            }
        }
        near.sort_unstable();
        for &j in &near {
            if j < OBSTACLE_BASE {
                self.near[j as usize].push(id);
            }
        }
        contacts.sort_unstable();
        self.contacts.extend(contacts);
        self.centres.push(x);
        self.radii.push(r);
        self.near.push(near);
        let reach = r + self.margin();
        self.grid.insert(id, &x, reach);
        id
    }

    /// Surface gap between sphere `i` and wall `(axis, side)` of the brick (Method 1 geometry).
    pub(crate) fn wall_gap(&self, i: usize, axis: usize, hi: bool) -> f64 {
        let x = self.centres[i][axis];
        let h = if hi { self.lengths[axis] - x } else { x };
        h - self.radii[i]
    }
}
