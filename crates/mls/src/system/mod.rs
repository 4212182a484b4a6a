//! The event-driven hard-sphere system with linearly growing diameters: particles, their
//! neighbour lists, the cell grid that builds them, the event calendar, the clock and the
//! pressure window. Monomorphised over the
//! dimension `D` and over `P` (true: every axis periodic, so no wall is ever looked at).
//!
//! Particles are updated lazily: particle `i` stores its position at its own time `time[i]`
//! and is moved only when an event involves it. Diameters are not stored: all of them grow
//! with the common scale, `D_i(t) = ratio[i]·scale(t)` with `scale(t) = scale0 + growth·t`
//! the current mean diameter.
//!
//! The collision prediction is in `pair_time`, the pressure window and thermostat in
//! `pressure_window`, the cell-grid rebuild and the skin in `rebuild`, the system built from a
//! packing or a checkpoint (and back) in `construction`; this file holds the state, the clock
//! and the collision rules.
//!
//! Neighbour lists with bounding spheres (Donev, Torquato & Stillinger 2005): when particle `i`
//! renews its list it gets a bounding sphere of radius `R_i = D_i/2 + skin` centred at its
//! position, and its list holds every `j` whose bounding sphere overlaps its own (found on the
//! cell grid of bounding centres, and kept symmetric). A renewal event fires before the growing
//! sphere can leave its bounding sphere (`event::neighbour_exit`), so two spheres can only touch
//! while they are in each other's lists: a prediction tests ~13 list partners near jamming
//! instead of the ~36 particles of 27 cells, and there are no cell-crossing events.
//!
//! Floating-point care near jamming (reduced pressures ~1e12, gaps ~1e-12 of a diameter):
//! * times are measured from a clock origin that is moved to "now" after every pressure window
//!   and every grid rebuild (`move_origin`), so event times stay small and keep their digits;
//! * a pair or wall that rounding leaves touching or overlapping collides at once only if it
//!   still approaches (`event::collision::collision_time`), so spheres cannot pass through
//!   each other;
//! * every collision parts the surfaces at least at `min_impulse` (1e-10 of the thermal
//!   speed), far above the rounding of the next prediction, so a just-collided pair is never
//!   predicted to collide again at time 0 (no Zeno cascade of zero-time collisions).

use crate::cells::CellGrid;
#[cfg(target_arch = "x86_64")]
use crate::event::collision_simd;
use crate::event::neighbour_exit::exit_time;
use crate::event::{Calendar, collision, wall};
use crate::neighbour_lists::NeighbourLists;

mod construction;
mod pair_time;
mod pressure_window;
mod rebuild;

/// Cells are this much wider than the largest interaction range (largest diameter plus twice
/// the skin) when built, so growth triggers few rebuilds.
const CELL_MARGIN: f64 = 0.05;
/// Relative slack on the bounding-sphere overlap test, far above rounding and far below the
/// cell margin, so a partner on the boundary by rounding is listed.
const LIST_SLACK: f64 = 1e-9;
/// Smallest post-collision parting speed, as a fraction of the thermal speed √T·ℓ.
const MIN_PARTING: f64 = 1e-10;
/// At zero growth, neighbour-list renewals without any collision after which a window is
/// declared idle (per particle, plus a constant).
const IDLE_RENEWALS_PER_PARTICLE: u64 = 10_000;
/// Events between two calls of the poll callback.
const POLL_EVERY: u64 = 1 << 13;

/// How a window ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum WindowEnd {
    /// The window collected its collisions; the reduced pressure over it.
    Completed { pressure: f64 },
    /// The largest sphere reached half the smallest periodic box length, beyond which minimum
    /// images are ambiguous.
    BoxLimit,
    /// Nothing will ever happen again, or nothing but list renewals at zero growth.
    Idle,
    /// The poll callback asked to stop.
    Stopped,
}

/// One sphere: position `x` at its own time `t`, velocity `v`, and diameter relative to the
/// mean diameter. Kept together so a pair test touches one cache line per particle in 3D.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Particle<const D: usize> {
    x: [f64; D],
    v: [f64; D],
    t: f64,
    ratio: f64,
}

// The SIMD prediction reads 3D particles as records of 8 doubles in this field order.
#[cfg(target_arch = "x86_64")]
const _: () = assert!(std::mem::size_of::<Particle<3>>() == collision_simd::RECORD * 8);

/// The state of one LS run.
pub(crate) struct System<const D: usize, const P: bool> {
    len: [f64; D],
    half: [f64; D],
    periodic: [bool; D],
    p: Vec<Particle<D>>,
    /// Index in the starting packing of each particle (they are renumbered in cell order).
    id: Vec<usize>,
    ratio_max: f64,
    /// Trajectory version (changes at every collision of the particle).
    version: Vec<u32>,
    /// Cell grid of the bounding-sphere centres.
    grid: CellGrid<D>,
    /// Periodic axes with fewer than four cells when some periodic axis has a single cell:
    /// every image along them is tried (see `pair_time_images`).
    small: [bool; D],
    /// Some periodic axis has two or three cells and none has one: each pair is imaged
    /// through its bounding-sphere centres (see `pair_time_anchored`).
    anchored: bool,
    /// Bounding-sphere centre of each particle (in the box).
    centre: Vec<[f64; D]>,
    /// Bounding-sphere radius of each particle.
    bound: Vec<f64>,
    /// Neighbour list of each particle: every particle whose bounding sphere overlaps its own.
    lists: NeighbourLists,
    /// Bounding radius minus particle radius at the last grid rebuild.
    skin: f64,
    /// Per-particle stamps marking the old list during a renewal.
    mark: Vec<u32>,
    stamp: u32,
    /// List buffers kept between renewals (no allocation in the event loop).
    spare: Vec<u32>,
    spare_old: Vec<u32>,
    /// Scratch buffers of `rebuild` (cell order, renumbered particles and ids), kept so that
    /// rebuilding every window allocates nothing.
    order: Vec<usize>,
    p_spare: Vec<Particle<D>>,
    id_spare: Vec<usize>,
    calendar: Calendar,
    /// Current time, relative to the clock origin.
    pub now: f64,
    /// Mean diameter at the clock origin.
    scale0: f64,
    /// Growth speed of the mean diameter, γ·ℓ.
    growth: f64,
    /// The length unit ℓ: the mean diameter at which φ = 1.
    pub length_unit: f64,
    temperature: f64,
    min_impulse: f64,
    /// Cells are never narrower than (V/N)^(1/d) (about one particle per cell).
    cell_floor: f64,
    /// Time at which the largest sphere outgrows the grid.
    t_grid: f64,
    /// Time at which the largest sphere reaches half the smallest periodic length.
    t_box: f64,
    /// Total kinetic energy Σ v²/2.
    ke: f64,
    /// Collisions (pairs and walls) since the start.
    pub collisions: u64,
    /// Events popped since the start, stale ones included.
    pub events: u64,
    /// Grid rebuilds since the start.
    pub rebuilds: u64,
    window_collisions: u64,
    /// Σ r·Δp over the window's collisions (Baranau & Tallarek 2014 §III.B's collision virial).
    virial: f64,
    /// ∫ KE dt over the window up to `t_mark`.
    ke_integral: f64,
    t_mark: f64,
    idle_renewals: u64,
    /// Reduced pressure of the last completed window (NaN before the first), which sets the
    /// skin (`skin_fraction`).
    pressure: f64,
    /// The SIMD set 3D predictions run on, eight or four partners at a time
    /// (`event::collision_simd`); none for other d, other processors, and tests that compare
    /// with the scalar path.
    #[cfg(target_arch = "x86_64")]
    pub(crate) simd: Option<collision_simd::Kernel>,
    /// Largest relative overlap `1 − r/σ` seen after any collision (test audit hook).
    #[cfg(test)]
    pub audit: Option<f64>,
}

impl<const D: usize, const P: bool> System<D, P> {
    pub fn n(&self) -> usize {
        self.p.len()
    }

    /// Mean diameter at time `t`.
    #[inline]
    fn scale(&self, t: f64) -> f64 {
        self.scale0 + self.growth * t
    }

    /// Current packing fraction, exactly `(scale/ℓ)^d` by the definition of ℓ.
    pub fn phi(&self) -> f64 {
        (self.scale(self.now) / self.length_unit).powi(D as i32)
    }

    /// Multiplies every diameter by `factor` now (used to clear overlaps in a starting packing).
    pub fn shrink(&mut self, factor: f64) {
        self.move_origin();
        self.scale0 *= factor;
        self.rebuild();
    }

    /// Smallest `r/σ` over all pairs and `distance/radius` over all walls, now (∞ if none).
    pub fn min_contact_ratio(&self) -> f64 {
        let s = self.scale(self.now);
        // A grid of its own: the neighbour lists may not exist yet, and a start that overlaps
        // has no bound on its pair distances but the diameters.
        let d_max = self.ratio_max * s;
        let pos: Vec<[f64; D]> = (0..self.n())
            .map(|i| {
                let mut x = self.position_at(i, self.now);
                wrap::<D>(&mut x, &self.len, &self.periodic);
                x
            })
            .collect();
        let cell = (d_max * (1.0 + CELL_MARGIN)).max(self.cell_floor);
        let grid = CellGrid::build(&self.len, &self.periodic, cell, d_max, self.n(), |i| pos[i]);
        let mut best = f64::INFINITY;
        for i in 0..self.n() {
            let xi = pos[i];
            let ri = 0.5 * self.p[i].ratio * s;
            grid.for_each_near(&grid.coord[i], |j| {
                if j > i {
                    let r = self.separation(&xi, &pos[j]);
                    let sigma = 0.5 * (self.p[i].ratio + self.p[j].ratio) * s;
                    best = best.min(norm(&r) / sigma);
                }
            });
            if !P {
                for k in (0..D).filter(|&k| !self.periodic[k]) {
                    best = best.min(xi[k].min(self.len[k] - xi[k]) / ri);
                }
            }
        }
        best
    }

    #[inline]
    fn position_at(&self, i: usize, t: f64) -> [f64; D] {
        let dt = t - self.p[i].t;
        std::array::from_fn(|k| self.p[i].x[k] + self.p[i].v[k] * dt)
    }

    #[inline]
    fn advance(&mut self, i: usize, t: f64) {
        self.p[i].x = self.position_at(i, t);
        self.p[i].t = t;
    }

    /// Minimum-image separation `b − a`. Stored positions stay within one skin of the box
    /// (renewals and origin moves wrap them), so one conditional shift per axis suffices.
    #[inline]
    fn separation(&self, a: &[f64; D], b: &[f64; D]) -> [f64; D] {
        std::array::from_fn(|k| {
            let mut d = b[k] - a[k];
            if P || self.periodic[k] {
                if d > self.half[k] {
                    d -= self.len[k];
                } else if d < -self.half[k] {
                    d += self.len[k];
                }
            }
            d
        })
    }

    /// Moves every particle to now, wraps positions into the box and moves the clock origin to
    /// now, so that later times keep their precision.
    fn move_origin(&mut self) {
        let now = self.now;
        for i in 0..self.n() {
            self.advance(i, now);
            wrap::<D>(&mut self.p[i].x, &self.len, &self.periodic);
            self.p[i].t = 0.0;
        }
        self.scale0 = self.scale(now);
        self.t_mark -= now;
        self.now = 0.0;
    }

    /// Accounts a collision at `now`: kinetic-energy integral, counters, versions.
    fn count_collision(&mut self, ke_before: f64, ke_after: f64) {
        self.ke_integral += self.ke * (self.now - self.t_mark);
        self.t_mark = self.now;
        self.ke += ke_after - ke_before;
        self.collisions += 1;
        self.window_collisions += 1;
        self.idle_renewals = 0;
    }

    /// Elastic collision of growing spheres `i` and `j` at `now` (see `event::collision`).
    fn collide(&mut self, i: usize, j: usize) {
        let t = self.now;
        self.advance(i, t);
        self.advance(j, t);
        let r = self.separation(&self.p[i].x, &self.p[j].x);
        let dist = norm(&r);
        // Coincident centres (possible in a Poisson start) part along the first axis.
        let n: [f64; D] = if dist > 0.0 {
            std::array::from_fn(|k| r[k] / dist)
        } else {
            std::array::from_fn(|k| if k == 0 { 1.0 } else { 0.0 })
        };
        let (vi, vj) = (self.p[i].v, self.p[j].v);
        let vn: f64 = (0..D).map(|k| (vj[k] - vi[k]) * n[k]).sum();
        let g = 0.5 * (self.p[i].ratio + self.p[j].ratio) * self.growth;
        let jn = collision::impulse(vn, g, self.min_impulse);
        let before = 0.5 * (dot(&vi, &vi) + dot(&vj, &vj));
        for (k, nk) in n.iter().enumerate() {
            self.p[i].v[k] -= jn * nk;
            self.p[j].v[k] += jn * nk;
        }
        let after = 0.5 * (dot(&self.p[i].v, &self.p[i].v) + dot(&self.p[j].v, &self.p[j].v));
        self.count_collision(before, after);
        // Virial r·Δp_j with r = r_j − r_i at contact.
        self.virial += dist * jn;
        for p in [i, j] {
            self.version[p] = self.version[p].wrapping_add(1);
        }
        #[cfg(test)]
        {
            self.audit_particle(i);
            self.audit_particle(j);
        }
        self.predict_renewal(i);
        self.predict_collisions(i);
        self.predict_renewal(j);
        self.predict_collisions(j);
        self.calendar.commit_pair(i, j);
    }

    /// Collision of `i` with flat wall `w = 2·axis + side` at `now` (see `event::wall`).
    fn bounce(&mut self, i: usize, w: usize) {
        let t = self.now;
        self.advance(i, t);
        let (k, outward) = (w / 2, if w.is_multiple_of(2) { -1.0 } else { 1.0 });
        let before = 0.5 * dot(&self.p[i].v, &self.p[i].v);
        let vn = self.p[i].v[k] * outward;
        let dp = wall::impulse(vn, 0.5 * self.p[i].ratio * self.growth, self.min_impulse);
        self.p[i].v[k] -= outward * dp;
        let after = 0.5 * dot(&self.p[i].v, &self.p[i].v);
        self.count_collision(before, after);
        // Mirror-image pair: r·Δp = D_i·dp/2 per real particle.
        self.virial += 0.5 * self.p[i].ratio * self.scale(t) * dp;
        self.version[i] = self.version[i].wrapping_add(1);
        #[cfg(test)]
        self.audit_particle(i);
        self.predict_renewal(i);
        self.predict_collisions(i);
        self.calendar.commit(i);
    }

    /// Whether the bounding spheres of `i` and `j` overlap (symmetric in `i` and `j`). On a
    /// grid with a single cell along some periodic axis every particle of the adjacent cells
    /// is listed, since there several images may matter (see `pair_time_images`).
    #[inline]
    fn listed(&self, i: usize, j: usize) -> bool {
        if self.small.iter().any(|&s| s) {
            return true;
        }
        let r = self.separation(&self.centre[i], &self.centre[j]);
        let reach = (self.bound[i] + self.bound[j]) * (1.0 + LIST_SLACK);
        dot(&r, &r) <= reach * reach
    }

    /// Particle `i` may be about to leave its bounding sphere: a new bounding sphere centred
    /// where it is now, a new neighbour list (the change applied to the partners' lists too),
    /// and its events predicted afresh.
    fn renew(&mut self, i: usize) {
        let t = self.now;
        self.advance(i, t);
        wrap::<D>(&mut self.p[i].x, &self.len, &self.periodic);
        self.centre[i] = self.p[i].x;
        self.bound[i] = 0.5 * self.p[i].ratio * self.scale(t) + self.skin;
        self.grid.relocate(i, &self.centre[i]);
        // Most partners stay: mark the old list, and edit the partners' lists only for those
        // that leave (`stamp`) or join (unmarked); those that stay get `stamp + 1`.
        if self.stamp >= u32::MAX - 2 {
            self.mark.fill(0);
            self.stamp = 0;
        }
        self.stamp += 2;
        let stamp = self.stamp;
        let mut old = std::mem::take(&mut self.spare_old);
        old.clear();
        old.extend_from_slice(self.lists.get(i));
        for &j in &old {
            self.mark[j as usize] = stamp;
        }
        let mut new = std::mem::take(&mut self.spare);
        new.clear();
        self.grid.for_each_near(&self.grid.coord[i], |j| {
            if j != i && self.listed(i, j) {
                new.push(j as u32);
            }
        });
        for &j in &new {
            let m = &mut self.mark[j as usize];
            if *m == stamp {
                *m = stamp + 1;
            } else {
                self.lists.push(j as usize, i as u32);
            }
        }
        for &j in &old {
            if self.mark[j as usize] == stamp {
                self.lists.remove(j as usize, i as u32);
            }
        }
        self.lists.set(i, &new);
        self.spare = new;
        self.spare_old = old;
        self.predict_renewal(i);
        self.predict_collisions(i);
        self.calendar.commit(i);
    }

    /// Schedules the renewal of `i`'s neighbour list: the earliest time its growing sphere may
    /// touch its bounding sphere on its current trajectory.
    fn predict_renewal(&mut self, i: usize) {
        let x = self.position_at(i, self.now);
        let offset = norm(&self.separation(&self.centre[i], &x));
        let q = &self.p[i];
        let dt = exit_time(
            offset,
            norm(&q.v),
            0.5 * q.ratio * self.scale(self.now),
            0.5 * q.ratio * self.growth,
            self.bound[i],
        );
        self.calendar.set_renewal(i, self.now + dt);
    }

    /// Test hook: records the largest relative overlap of `i` with any particle or wall now.
    #[cfg(test)]
    ///
    /// Also checks the neighbour-list invariants: `i` is inside its bounding sphere, and every
    /// particle within the skin of `i` is in its list (and the lists are symmetric).
    fn audit_particle(&mut self, i: usize) {
        let s = self.scale(self.now);
        let xi = self.position_at(i, self.now);
        let mut worst = self.audit.unwrap_or(0.0f64);
        let offset = norm(&self.separation(&self.centre[i], &xi));
        assert!(
            offset + 0.5 * self.p[i].ratio * s <= self.bound[i] * (1.0 + 1e-9),
            "particle {i} left its bounding sphere"
        );
        for j in (0..self.n()).filter(|&j| j != i) {
            let r = norm(&self.separation(&xi, &self.position_at(j, self.now)));
            let sigma = 0.5 * (self.p[i].ratio + self.p[j].ratio) * s;
            if sigma > 0.0 {
                worst = worst.max(1.0 - r / sigma);
            }
            let listed = self.lists.get(i).contains(&(j as u32));
            assert_eq!(
                listed,
                self.lists.get(j).contains(&(i as u32)),
                "asymmetric lists"
            );
            assert!(listed || r > sigma, "particles {i} and {j} touch unlisted");
        }
        let radius = 0.5 * self.p[i].ratio * s;
        for k in (0..D).filter(|&k| !(P || self.periodic[k])) {
            if radius > 0.0 {
                worst = worst.max(1.0 - xi[k].min(self.len[k] - xi[k]) / radius);
            }
        }
        self.audit = Some(worst);
    }

    /// Test access: adds `dv` to the velocity of `i` (then restart a window to re-predict).
    #[cfg(test)]
    pub fn add_velocity(&mut self, i: usize, dv: [f64; D]) {
        for (v, d) in self.p[i].v.iter_mut().zip(dv) {
            *v += d;
        }
        self.ke = self.kinetic_energy();
    }

    /// Test access: total momentum Σ v.
    #[cfg(test)]
    pub fn momentum(&self) -> [f64; D] {
        let mut m = [0.0; D];
        for q in &self.p {
            for (mk, vk) in m.iter_mut().zip(q.v) {
                *mk += vk;
            }
        }
        m
    }

    /// Σ v²/2 recomputed from the velocities.
    pub fn kinetic_energy(&self) -> f64 {
        self.p.iter().map(|q| 0.5 * dot(&q.v, &q.v)).sum()
    }
}

#[inline]
fn dot<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
    let mut s = 0.0;
    for k in 0..D {
        s += a[k] * b[k];
    }
    s
}

#[inline]
fn norm<const D: usize>(a: &[f64; D]) -> f64 {
    dot(a, a).sqrt()
}

/// The widest SIMD set 3D predictions can run on here (none for d ≠ 3).
#[cfg(target_arch = "x86_64")]
fn simd_kernel<const D: usize>() -> Option<collision_simd::Kernel> {
    (D == 3).then(collision_simd::Kernel::widest).flatten()
}

/// Wraps `x` into `[0, L)` along periodic axes.
fn wrap<const D: usize>(x: &mut [f64; D], len: &[f64; D], periodic: &[bool; D]) {
    for k in 0..D {
        if periodic[k] {
            x[k] = x[k].rem_euclid(len[k]);
            if x[k] >= len[k] {
                x[k] = 0.0;
            }
        }
    }
}
