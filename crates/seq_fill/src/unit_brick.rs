//! Filling one unit brick (Black & Cheviakov 2022 §2.1 for Method 1, §3 for Method 2, §4 for the
//! hemisphere-cut domain): a sphere of mean radius in each corner, then every edge, face and
//! the volume in turn, each new sphere placed in contact with a tuple of parents and kept only
//! if it lies inside and overlaps nothing; a radius that fits nowhere is discarded.
//!
//! Parent tuples of a stratum wait in a double-ended queue. A drawn radius tries up to
//! `tuples_per_draw` of them, newest first, so every radius meets the open front of the bed
//! (trying the oldest first would offer large radii only the narrow interior gaps and bias the
//! fill towards small spheres). A tuple that hosts the sphere goes back on the new end (its
//! other root may still be free); one that fails goes to the old end, to be tried again when the
//! front is exhausted, until it has failed `tuple_retries` radii. The work per placed sphere is
//! bounded by those budgets, independent of how many spheres are already placed.

use std::collections::VecDeque;
use std::time::Instant;

use packbench_core::geometry::{ball_volume, unit_ball_volume};
use packbench_core::run::{Observer, Progress, TraceRow};
use packbench_core::{Container, Packing};

use crate::bed::{Bed, OBSTACLE_BASE, Obstacle};
use crate::draws::Draws;
use crate::error::SeqFillError;
use crate::params::{ACCEPTANCE_WINDOW, MAX_SPHERES, Params, Variant};
use crate::stratum::{Goal, Stratum};
use crate::tangent_sphere::{Parent, tangent_centres};

/// Seconds between progress reports.
const PROGRESS_EVERY_S: f64 = 0.25;
/// Draws between checks of the clock and of `should_stop`.
const CHECK_EVERY: u64 = 512;
/// Memory the queue of parent tuples of one stratum may take. Around a sphere much larger
/// than the rest (sizes 1 and 20) tuples are made far faster than they are used up, and the
/// queue grew without bound (tens of GB); past this budget the oldest tuples, which have failed
/// before, are dropped.
const TUPLE_QUEUE_BYTES: usize = 1 << 30;

/// How the fill of one stratum ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum End {
    GoalReached,
    NothingFits,
    Interrupted,
}

/// A unit brick being filled and its bookkeeping.
pub(crate) struct UnitBrick<'a, const D: usize> {
    pub bed: Bed<D>,
    pub variant: Variant,
    params: &'a Params,
    pub draws: Draws,
    pub mean_radius: f64,
    /// Per core wall id (2·axis + high side): projected area of the spheres touching it.
    pub cover: Vec<f64>,
    /// Per core wall id: the face area.
    face_area: Vec<f64>,
    /// Domain volume of the brick (the container's exact volume).
    volume: f64,
    placed_volume: f64,
    /// The unit brick as a core container (walled box, periodic cell or hemisphere-cut brick).
    pub container: Container,
    observer: &'a mut dyn Observer,
    started: Instant,
    last_report: f64,
    pub trace: Vec<TraceRow>,
}

impl<'a, const D: usize> UnitBrick<'a, D> {
    /// An empty unit brick for `params` (already validated, `D == params.dim()`).
    pub(crate) fn new(
        params: &'a Params,
        observer: &'a mut dyn Observer,
    ) -> Result<Self, SeqFillError> {
        let mut lengths = [0.0; D];
        lengths.copy_from_slice(&params.brick_lengths);
        let mean_radius = Draws::mean_radius(&params.distribution, params.seed)?;
        if let Some((k, l)) = lengths
            .iter()
            .enumerate()
            .find(|(_, l)| **l < 2.0 * mean_radius)
        {
            return Err(SeqFillError::Parameter(format!(
                "brick length {l} on axis {k} is shorter than the mean diameter {}, so the corner spheres do not fit",
                2.0 * mean_radius
            )));
        }
        let container = match (params.variant, params.hemispheres) {
            (_, Some(radii)) => Container::hemisphere_cut_brick(&lengths, radii)?,
            (Variant::Method1, None) => Container::with_flags(&lengths, &[true; D])?,
            (Variant::Method2, None) => Container::periodic_box(&lengths)?,
        };
        let volume = container.volume();
        let mean_ball = ball_volume(D, 2.0 * mean_radius);
        // Generous estimate of the spheres a brick can hold (random close packing is below 0.7).
        let per_brick = 0.7 * volume / mean_ball;
        let bricks: f64 = params.brick_numbers.iter().map(|&n| n as f64).product();
        // The refusal counts spheres of the small radii, which fill the gaps of the large.
        let small_ball = ball_volume(
            D,
            2.0 * Draws::small_radius(&params.distribution, params.seed)?,
        );
        let most = 0.7 * volume / small_ball * bricks;
        if most > MAX_SPHERES {
            return Err(SeqFillError::Parameter(format!(
                "the domain could take up to about {most:.1e} spheres of its smaller sizes, more than the limit {MAX_SPHERES:.0e}; use a smaller brick, fewer bricks or a narrower size distribution"
            )));
        }
        let parent_gap = params.parent_param * mean_radius;
        let contact_gap = params.contact_param * mean_radius;
        let margin = parent_gap.max(contact_gap);
        let mut bed = Bed::new(
            lengths,
            params.variant == Variant::Method2,
            parent_gap,
            contact_gap,
            2.0 * (mean_radius + margin),
            (4.0 * per_brick) as usize + 64,
        );
        if params.contact_overlap {
            bed.overlap_allowed = contact_gap;
        }
        let mut face_area = Vec::with_capacity(2 * D);
        for a in 0..D {
            let area: f64 = (0..D).filter(|&b| b != a).map(|b| lengths[b]).product();
            face_area.extend([area, area]);
        }
        if let Some(radii) = params.hemispheres {
            for (side, &r) in radii.iter().enumerate() {
                if r <= 0.0 {
                    continue;
                }
                let mut centre = lengths.map(|l| 0.5 * l);
                centre[0] = if side == 0 { 0.0 } else { lengths[0] };
                // The flat x face loses the hemisphere's disc.
                face_area[side] -= unit_ball_volume(D - 1) * r.powi(D as i32 - 1);
                bed.obstacles.push(Obstacle {
                    centre,
                    radius: r,
                    near: Vec::new(),
                    wall: side,
                });
            }
        }
        Ok(UnitBrick {
            bed,
            variant: params.variant,
            params,
            draws: Draws::new(&params.distribution, params.seed),
            mean_radius,
            cover: vec![0.0; 2 * D],
            face_area,
            volume,
            placed_volume: 0.0,
            container,
            observer,
            started: Instant::now(),
            last_report: 0.0,
            trace: Vec::new(),
        })
    }

    /// Fraction of the brick volume filled so far.
    pub(crate) fn body_fraction(&self) -> f64 {
        self.placed_volume / self.volume
    }

    /// Per core wall id, the fraction of the face covered by the spheres touching it.
    pub(crate) fn face_fractions(&self) -> Vec<f64> {
        self.cover
            .iter()
            .zip(&self.face_area)
            .map(|(c, a)| if *a > 0.0 { c / a } else { 0.0 })
            .collect()
    }

    /// Fills the whole brick: corners, then every stratum in order. Returns how the volume
    /// fill ended (or `Interrupted` as soon as the observer asks to stop).
    pub(crate) fn fill(&mut self) -> Result<End, SeqFillError> {
        self.place_corners();
        self.record_trace("corners");
        let strata = Stratum::all(D, self.variant);
        let mut end = End::NothingFits;
        for st in &strata {
            end = self.fill_stratum(st)?;
            if end == End::Interrupted {
                break;
            }
            if st.goal == Goal::Body || matches!(st.goal, Goal::Face(_)) {
                self.record_trace(match st.goal {
                    Goal::Body => "volume",
                    _ => "face",
                });
            }
        }
        Ok(end)
    }

    /// A sphere of mean radius in each corner (Method 1: inside, touching the d faces; Method 2:
    /// centred on the corner, one sphere standing for all 2^d copies). Corners cut by a
    /// hemisphere stay empty.
    fn place_corners(&mut self) {
        let r = self.mean_radius;
        let corners = match self.variant {
            Variant::Method1 => 1usize << D,
            Variant::Method2 => 1,
        };
        for c in 0..corners {
            let mut x = [0.0; D];
            if self.variant == Variant::Method1 {
                for (a, xa) in x.iter_mut().enumerate() {
                    *xa = if c & (1 << a) != 0 {
                        self.bed.lengths[a] - r
                    } else {
                        r
                    };
                }
            }
            if self.bed.is_free(&x, r) {
                self.add(x, r);
            }
        }
    }

    /// Places a sphere and updates the face covers and the body fraction.
    fn add(&mut self, x: [f64; D], r: f64) -> u32 {
        let id = self.bed.place(x, r);
        let projected = unit_ball_volume(D - 1) * r.powi(D as i32 - 1);
        for (a, &xa) in x.iter().enumerate() {
            match self.variant {
                Variant::Method1 => {
                    for hi in [false, true] {
                        if self.bed.wall_gap(id as usize, a, hi) <= self.bed.contact_gap {
                            self.cover[2 * a + hi as usize] += projected;
                        }
                    }
                }
                // A Method 2 face sphere is centred on x_a = 0, which is also the face x_a = L_a.
                Variant::Method2 => {
                    if xa == 0.0 {
                        self.cover[2 * a] += projected;
                        self.cover[2 * a + 1] += projected;
                    }
                }
            }
        }
        self.placed_volume += ball_volume(D, 2.0 * r);
        let n = self.bed.len() as u64;
        if self.params.save_interval > 0 && n.is_multiple_of(self.params.save_interval) {
            let packing = self.packing();
            self.observer.snapshot(self.draws.count(), &packing);
        }
        id
    }

    fn goal_reached(&self, goal: Goal) -> bool {
        match goal {
            Goal::Full => false,
            Goal::Face(w) => self.cover[w] >= self.params.face_goal * self.face_area[w],
            Goal::Body => self.body_fraction() >= self.params.body_goal,
        }
    }

    /// The sequential fill of one stratum (Black & Cheviakov 2022 §2.1).
    fn fill_stratum(&mut self, st: &Stratum) -> Result<End, SeqFillError> {
        let k = st.parents();
        let mut queue: VecDeque<([u32; D], u32)> = VecDeque::new();
        let mut fresh = Vec::new();
        for s in 0..self.bed.len() as u32 {
            if st.contains(&self.bed, self.variant, s, self.mean_radius) {
                st.tuples_closing_at(&self.bed, self.variant, s, self.mean_radius, &mut fresh);
            }
        }
        if k == 1 {
            for o in 0..self.bed.obstacles.len() as u32 {
                if st.contains(&self.bed, self.variant, OBSTACLE_BASE + o, self.mean_radius) {
                    let mut t = [0; D];
                    t[0] = OBSTACLE_BASE + o;
                    fresh.push(t);
                }
            }
        }
        queue.extend(fresh.drain(..).map(|t| (t, 0)));
        let max_queued = TUPLE_QUEUE_BYTES / std::mem::size_of::<([u32; D], u32)>();
        // Outcomes of the last ACCEPTANCE_WINDOW draws of this stratum (true: placed).
        let mut window = [false; ACCEPTANCE_WINDOW];
        let (mut drawn, mut accepted) = (0usize, 0usize);
        let needed = self.params.min_acceptance * ACCEPTANCE_WINDOW as f64;
        loop {
            if self.goal_reached(st.goal) {
                return Ok(End::GoalReached);
            }
            if queue.is_empty() || (drawn >= ACCEPTANCE_WINDOW && (accepted as f64) < needed) {
                return Ok(End::NothingFits);
            }
            if self.draws.count().is_multiple_of(CHECK_EVERY) && self.check_in() {
                return Ok(End::Interrupted);
            }
            let r = self.draws.radius()?;
            let (held, n_held) = st.held_values(self.variant, &self.bed.lengths, r);
            let held = &held[..n_held];
            let tries = queue.len().min(self.params.tuples_per_draw);
            let mut placed = None;
            for _ in 0..tries {
                let (t, fails) = queue.pop_back().expect("tries ≤ queue length");
                if let Some(x) = self.try_tuple(st, held, &t[..k], r) {
                    placed = Some(x);
                    queue.push_back((t, fails));
                    break;
                }
                if fails + 1 < self.params.tuple_retries {
                    queue.push_front((t, fails + 1));
                }
            }
            let slot = drawn % ACCEPTANCE_WINDOW;
            accepted -= window[slot] as usize;
            window[slot] = placed.is_some();
            accepted += window[slot] as usize;
            drawn += 1;
            match placed {
                Some(x) => {
                    let id = self.add(x, r);
                    self.draws.placed.push(r);
                    st.tuples_closing_at(&self.bed, self.variant, id, self.mean_radius, &mut fresh);
                    queue.extend(fresh.drain(..).map(|t| (t, 0)));
                    if queue.len() > max_queued {
                        queue.drain(..queue.len() - max_queued);
                    }
                }
                None => self.draws.discarded.push(r),
            }
        }
    }

    /// Tries both roots of a sphere of radius `r` touching the parents `ids`; returns the first
    /// that lies inside the brick and overlaps nothing.
    fn try_tuple(
        &mut self,
        st: &Stratum,
        held: &[(usize, f64)],
        ids: &[u32],
        r: f64,
    ) -> Option<[f64; D]> {
        let bed = &self.bed;
        // Unwrap the parents and held values into one frame around the first parent.
        let mut parents: [Parent<D>; D] = [([0.0; D], 0.0); D];
        parents[0] = bed.parent(ids[0]);
        let c0 = parents[0].0;
        for (p, &id) in parents.iter_mut().zip(ids).skip(1) {
            let (c, rp) = bed.parent(id);
            let v = bed.separation(&c0, &c);
            *p = (std::array::from_fn(|a| c0[a] + v[a]), rp);
        }
        let mut held_frame = [(0, 0.0); D];
        for (h, &(a, v)) in held_frame.iter_mut().zip(held) {
            let mut probe = c0;
            probe[a] = v;
            *h = (a, c0[a] + bed.separation(&c0, &probe)[a]);
        }
        let roots = tangent_centres(
            &held_frame[..held.len()],
            &st.free,
            &parents[..ids.len()],
            r,
        )?;
        for mut x in roots {
            if x.iter().any(|v| !v.is_finite()) {
                continue;
            }
            for &(a, v) in held {
                x[a] = v;
            }
            if self.bed.periodic {
                for &a in &st.free {
                    let l = self.bed.lengths[a];
                    x[a] -= l * (x[a] / l).floor();
                }
            }
            // Inside: Method 1 spheres within the brick on every axis (a held coordinate r or
            // L − r is outside when 2r > L); Method 2 spheres cross only their own faces…
            let within = |a: usize| {
                let tol = 1e-12 * self.bed.lengths[a];
                x[a] >= r - tol && x[a] <= self.bed.lengths[a] - r + tol
            };
            let inside = match self.variant {
                Variant::Method1 => (0..D).all(within),
                // …and never touch their own periodic image across a held axis.
                Variant::Method2 => {
                    st.free.iter().all(|&a| within(a))
                        && st
                            .fixed
                            .iter()
                            .all(|&(a, _)| 2.0 * r <= self.bed.lengths[a])
                }
            };
            if inside && self.bed.is_free(&x, r) {
                return Some(x);
            }
        }
        None
    }

    /// Reports progress at most every [`PROGRESS_EVERY_S`]; true when the observer asks to stop.
    fn check_in(&mut self) -> bool {
        let t = self.started.elapsed().as_secs_f64();
        if t - self.last_report >= PROGRESS_EVERY_S {
            self.last_report = t;
            self.observer.progress(&Progress {
                step: self.draws.count(),
                phi: self.body_fraction(),
                value: self.bed.len() as f64,
                label: "spheres",
                fraction: Some((self.body_fraction() / self.params.body_goal.max(1e-12)).min(1.0)),
                more: Vec::new(),
            });
        }
        self.observer.should_stop()
    }

    fn record_trace(&mut self, phase: &str) {
        let phase_code = match phase {
            "corners" => 0.0,
            "face" => 1.0,
            _ => 2.0,
        };
        self.trace.push(TraceRow {
            step: self.draws.count(),
            time_s: self.started.elapsed().as_secs_f64(),
            phi: self.body_fraction(),
            values: vec![
                ("spheres".into(), self.bed.len() as f64),
                ("discarded".into(), self.draws.discarded.len() as f64),
                ("phase".into(), phase_code),
            ],
        });
    }

    /// The unit brick's spheres as a packing in its container.
    pub(crate) fn packing(&self) -> Packing {
        Packing {
            dim: D,
            positions: self.bed.centres.iter().flatten().copied().collect(),
            diameters: self.bed.radii.iter().map(|r| 2.0 * r).collect(),
            container: self.container.clone(),
        }
    }
}
