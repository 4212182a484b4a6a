//! Collision prediction: the time until particle `i` touches a neighbour-list partner or a
//! wall, scheduled in the calendar (`predict_collisions`). The pair time solves the quadratic
//! of `event::collision` from one set of coefficients ([`PairMotion`]) for the minimum image
//! (the hot loop, or `event::collision_simd` four or eight pairs at a time), for the image
//! anchored at the bounding centres (grids with two or three cells on a periodic axis), or for
//! the three images along axes of a single cell. A pair that never touches has time ∞.

#[cfg(target_arch = "x86_64")]
use crate::event::collision_simd;
use crate::event::{Kind, collision, wall};

use super::{Particle, System, dot};

impl<const D: usize, const P: bool> System<D, P> {
    /// Time from now until `me` (a particle moved to now) touches particle `j`, or ∞ if never.
    #[inline(always)]
    fn pair_time(&self, me: &Particle<D>, j: usize) -> f64 {
        let xj = self.position_at(j, self.now);
        self.pair_time_at(me, j, self.separation(&me.x, &xj))
    }

    /// [`Self::pair_time`] on a grid with two or three cells along some periodic axis (and
    /// none with one). There the minimum image of the positions may flip during a list's
    /// life (the separation can pass ±L/2 while both stay in adjacent cells), but the image
    /// of `j` that can touch `i` is fixed: it is the one whose bounding sphere overlaps that
    /// of `i`, and it is unique because every pair of bounding spheres is narrower than half
    /// of each such axis (cells are at least that wide; `rebuild` keeps it so). So the
    /// separation is taken between the centres and each particle's offset from its centre:
    /// `r = (c_j − c_i) + (x_j − c_j) − (x_i − c_i)`, each term a small minimum image. This
    /// lists ~13–30 partners where trying every image listed all N (4D at N = 500: 2 cells per
    /// axis, 100× slower per collision).
    fn pair_time_anchored(&self, me: &Particle<D>, offset: &[f64; D], i: usize, j: usize) -> f64 {
        let xj = self.position_at(j, self.now);
        let rc = self.separation(&self.centre[i], &self.centre[j]);
        let oj = self.separation(&self.centre[j], &xj);
        let r = std::array::from_fn(|k| rc[k] + oj[k] - offset[k]);
        self.pair_time_at(me, j, r)
    }

    /// The collision time of `me` with `j` at separation `r = x_j − x_i`, or ∞. Always
    /// inlined and without branches: it is the body of the hot prediction loop.
    #[inline(always)]
    fn pair_time_at(&self, me: &Particle<D>, j: usize, r: [f64; D]) -> f64 {
        self.pair_motion(me, j).time(&r)
    }

    /// The relative motion of `me` and particle `j` from now.
    #[inline(always)]
    fn pair_motion(&self, me: &Particle<D>, j: usize) -> PairMotion<D> {
        PairMotion::new(me, &self.p[j], self.scale(self.now), self.growth)
    }

    /// [`Self::pair_time`] on a grid with a single cell along some periodic axis (a box
    /// narrower than two interaction ranges), for every axis with fewer than four cells.
    ///
    /// There the minimum image at prediction time need not be the image that collides later
    /// (the separation along such an axis can pass ±L/2 while both stay in adjacent cells), so
    /// the images shifted by −L, 0, +L along those axes are all tried. Positions lie within a
    /// skin of the box and each particle stays in its bounding sphere until its next renewal,
    /// after which it is predicted afresh (`renew`), so these three images cover every
    /// collision before `horizon` (the particle's next renewal); images that cannot close their
    /// gap before then are skipped.
    fn pair_time_images(&self, me: &Particle<D>, j: usize, horizon: f64) -> f64 {
        let xj = self.position_at(j, self.now);
        let mut r = self.separation(&me.x, &xj);
        let motion = self.pair_motion(me, j);
        let reach = motion.sigma + motion.g * horizon;
        // Per small axis, the shifts whose separation can come within reach before the horizon.
        let mut shifts = [[0.0f64; 3]; D];
        let mut count = [1u8; D];
        for k in (0..D).filter(|&k| self.small[k]) {
            r[k] = xj[k] - me.x[k];
            let travel = reach + motion.v[k].abs() * horizon;
            let mut m = 0;
            for s in [0.0, -self.len[k], self.len[k]] {
                if (r[k] + s).abs() <= travel || horizon.is_infinite() {
                    shifts[k][m] = s;
                    m += 1;
                }
            }
            count[k] = m as u8;
        }
        if count.contains(&0) {
            return f64::INFINITY;
        }
        let mut best = f64::INFINITY;
        let mut idx = [0u8; D];
        loop {
            let ri: [f64; D] = std::array::from_fn(|k| r[k] + shifts[k][idx[k] as usize]);
            best = best.min(motion.time(&ri));
            let mut k = 0;
            loop {
                if k == D {
                    return best;
                }
                idx[k] += 1;
                if idx[k] < count[k] {
                    break;
                }
                idx[k] = 0;
                k += 1;
            }
        }
    }

    /// The earliest collision of `me` (particle `i` moved to now) with its list partners in SIMD
    /// lanes (`event::collision_simd`, bit for bit the scalar result); `None` without a SIMD
    /// set (`self.simd`: d = 3 and AVX2 or AVX-512F).
    #[cfg(target_arch = "x86_64")]
    fn earliest_collision_simd(&self, me: &Particle<D>, i: usize) -> Option<(f64, u32)> {
        let kernel = self.simd?;
        let frame = collision_simd::Frame {
            x: std::array::from_fn(|k| me.x[k]),
            v: std::array::from_fn(|k| me.v[k]),
            ratio: me.ratio,
            now: self.now,
            scale: self.scale(self.now),
            growth: self.growth,
            len: std::array::from_fn(|k| self.len[k]),
            half: std::array::from_fn(|k| self.half[k]),
            periodic: std::array::from_fn(|k| P || self.periodic[k]),
        };
        // SAFETY: `simd` is set only for d = 3, where a particle is one record of 8 doubles
        // (asserted at compile time in `system`), so the slice covers exactly the particles,
        // and every list entry is a particle index.
        Some(unsafe {
            let records = std::slice::from_raw_parts(
                self.p.as_ptr().cast::<f64>(),
                self.p.len() * collision_simd::RECORD,
            );
            kernel.earliest_collision(records, self.lists.get(i), &frame)
        })
    }

    #[cfg(not(target_arch = "x86_64"))]
    fn earliest_collision_simd(&self, _me: &Particle<D>, _i: usize) -> Option<(f64, u32)> {
        None
    }

    /// Schedules the earliest collision of `i` (with a neighbour-list partner or a wall) from
    /// now.
    pub(super) fn predict_collisions(&mut self, i: usize) {
        self.advance(i, self.now);
        let me = self.p[i];
        let xi = me.x;
        let mut best = (f64::INFINITY, Kind::Wall(0));
        let small = self.small.iter().any(|&s| s);
        let horizon = self.calendar.renewal_time(i) - self.now;
        let offset = self.separation(&self.centre[i], &xi);
        if small || self.anchored {
            for &j in self.lists.get(i) {
                let j = j as usize;
                let t = if small {
                    self.pair_time_images(&me, j, best.0.min(horizon))
                } else {
                    self.pair_time_anchored(&me, &offset, i, j)
                };
                if t < best.0 {
                    best = (t, Kind::Pair(j));
                }
            }
        } else {
            // The hot loop: a branch-free running minimum, or the same in SIMD lanes.
            let simd = self.earliest_collision_simd(&me, i);
            let (t_best, j_best) = simd.unwrap_or_else(|| {
                let (mut t_best, mut j_best) = (f64::INFINITY, 0u32);
                for &j in self.lists.get(i) {
                    let t = self.pair_time(&me, j as usize);
                    let better = t < t_best;
                    j_best = if better { j } else { j_best };
                    t_best = if better { t } else { t_best };
                }
                (t_best, j_best)
            });
            if t_best < f64::INFINITY {
                best = (t_best, Kind::Pair(j_best as usize));
            }
        }
        if !P {
            let radius = 0.5 * self.p[i].ratio * self.scale(self.now);
            let g_radius = 0.5 * self.p[i].ratio * self.growth;
            for k in (0..D).filter(|&k| !self.periodic[k]) {
                let v = self.p[i].v[k];
                let sides = [(xi[k] - radius, v), (self.len[k] - xi[k] - radius, -v)];
                for (side, (h, u)) in sides.into_iter().enumerate() {
                    if let Some(t) = wall::collision_time(h, u - g_radius)
                        && t < best.0
                    {
                        best = (t, Kind::Wall(2 * k + side));
                    }
                }
            }
        }
        let (t, kind) = best;
        let vj = match kind {
            Kind::Pair(j) => self.version[j],
            Kind::Wall(_) => 0,
        };
        self.calendar.set_collision(i, self.now + t, kind, vj);
    }
}

/// The relative motion of a pair from now, the part of its collision equation that does not
/// depend on the separation: with `r(t) = r + v t` and contact distance `σ(t) = σ + g t`,
/// contact is `a t² + 2 b t + c = 0` with `a = v·v − g²`, `b = r·v − σ g`, `c = r·r − σ²`
/// (`event::collision`). `event::collision_simd` evaluates the same coefficients four or eight
/// pairs at a time, bit for bit.
struct PairMotion<const D: usize> {
    /// Relative velocity `v_j − v_i`.
    v: [f64; D],
    /// Contact distance now, `(D_i + D_j)/2`.
    sigma: f64,
    /// Growth speed of the contact distance.
    g: f64,
    /// `a = v·v − g²`.
    a: f64,
}

impl<const D: usize> PairMotion<D> {
    /// The motion of `other` relative to `me` at diameter scale `scale` growing at `growth`.
    #[inline(always)]
    fn new(me: &Particle<D>, other: &Particle<D>, scale: f64, growth: f64) -> Self {
        let v: [f64; D] = std::array::from_fn(|k| other.v[k] - me.v[k]);
        let half_sum = 0.5 * (me.ratio + other.ratio);
        let sigma = half_sum * scale;
        let g = half_sum * growth;
        let a = dot(&v, &v) - g * g;
        PairMotion { v, sigma, g, a }
    }

    /// Time until contact at separation `r = x_j − x_i`, or ∞ if never.
    #[inline(always)]
    fn time(&self, r: &[f64; D]) -> f64 {
        let b = dot(r, &self.v) - self.sigma * self.g;
        let c = dot(r, r) - self.sigma * self.sigma;
        collision::collision_time(self.a, b, c)
    }
}
