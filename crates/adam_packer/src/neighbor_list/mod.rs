//! A half Verlet neighbour list in compressed-row form (each pair once, in the row of its lower
//! index), built from the core's [`CellList`], with its transpose: the column of a particle
//! lists the entries of the rows above it that name it. Rows and columns let the force loop
//! compute each pair once and still write each particle from one place, so its sums need no
//! atomics and do not depend on the number of threads. Between whole builds the rows of the
//! particles that moved can be refreshed one by one ([`refresh`]).

mod refresh;
mod rows;
mod upkeep;

use packbench_core::neighbor::CellList;

use crate::system::{Geometry, System};
use refresh::Refresher;
pub(crate) use rows::Rows;
pub use upkeep::NeighborUpkeep;

/// Movers per particle above which a refresh rebuilds the whole list instead: the whole-list
/// scan pairs cells at once and costs less per particle than a query each.
const REFRESH_MAX_SHARE: f64 = 0.1;

/// Neighbour rows with the reference state that tells when they go stale.
pub(crate) struct NeighborList {
    /// Row `i` holds the neighbours j > i of particle `i`, sorted.
    pub rows: Rows,
    /// While refreshing, row `j` holds the particles i < j whose rows hold `j`, sorted (empty
    /// otherwise): what a refreshed particle's lower partners were.
    lower: Rows,
    /// `col_start[j]..col_start[j+1]` indexes `col_entry` for particle `j`.
    pub col_start: Vec<u32>,
    /// Entries `e` of `nbr` with `nbr[e] = j`, in increasing `e` (row order).
    pub col_entry: Vec<u32>,
    /// Whether the columns describe the rows (they are built only when asked for).
    columns_current: bool,
    /// Whether particle `i` was within its radius plus the skin of a wall at the build (or at
    /// its row's last refresh): only these can touch a wall before the list goes stale (empty
    /// without walls).
    pub near_wall: Vec<bool>,
    /// Skin in length units at the last build.
    skin: f64,
    /// Updates since the last build.
    lived: u64,
    /// Growth of the staleness bound per step over the last list's life (0 before the first
    /// list went stale).
    drift_rate: f64,
    /// Positions at the last build.
    build_x: Vec<f64>,
    /// What refreshing the movers' rows needs (`None`: whole builds only).
    refresher: Option<Refresher>,
    ref_kappa: f64,
    ref_height: f64,
    builds: u64,
    refreshed: u64,
    /// The last build's pairs and a counting sort's cursors, kept so that builds reuse their
    /// memory (at N = 10⁶ mapping it afresh each build was 8 % of the CPU).
    pairs: Vec<(u32, u32)>,
    fill: Vec<u32>,
}

impl NeighborList {
    /// An empty list that is stale until the first [`NeighborList::update`].
    pub fn new() -> Self {
        NeighborList {
            rows: Rows::new(),
            lower: Rows::new(),
            col_start: Vec::new(),
            col_entry: Vec::new(),
            columns_current: false,
            near_wall: Vec::new(),
            skin: 0.0,
            lived: 0,
            drift_rate: 0.0,
            build_x: Vec::new(),
            refresher: None,
            ref_kappa: 0.0,
            ref_height: 0.0,
            builds: 0,
            refreshed: 0,
            pairs: Vec::new(),
            fill: Vec::new(),
        }
    }

    /// How many times the whole list has been built.
    pub fn builds(&self) -> u64 {
        self.builds
    }

    /// How many particles' rows have been refreshed one by one.
    pub fn refreshed(&self) -> u64 {
        self.refreshed
    }

    /// Number of listed pairs.
    pub fn pairs(&self) -> usize {
        self.rows.held()
    }

    /// Keeps every pair that may overlap listed. The list is built whole when a gap may have
    /// closed by the skin since the last build: two displacements, the growth of the largest
    /// diameter and any change of the fix-height length together must stay below the skin.
    /// With `refresh`, as RCPGenerator 1.0 keeps its lists, only the rows of particles that
    /// moved a fifth of the skin since their own last search are searched again (the bound is
    /// in [`refresh`]); the whole list is built when more than a tenth of the particles moved,
    /// the diameters or the height changed too much, or the refreshed rows grew too much
    /// ([`NeighborList::refresh_movers`]). The pairs
    /// listed differ, the pairs that overlap do not. Wraps positions along periodic axes on a
    /// whole build. The skin is `skin_diameters` mean diameters, or, when larger, what the
    /// staleness bound grew by in `lifetime_steps` steps of the last list's life (0: the fixed
    /// skin), at most `max_diameters` mean diameters. Returns whether it built the whole list.
    pub fn update(
        &mut self,
        sys: &mut System,
        (skin_diameters, max_diameters): (f64, f64),
        lifetime_steps: f64,
        refresh: bool,
    ) -> bool {
        self.lived += 1;
        let drift = self.drift(sys);
        let height = self.height_change(sys);
        let stale = match self.refresher.as_mut() {
            Some(r) if refresh && drift.is_finite() => {
                let whole = r.outgrown(sys)
                    || height >= r.budget
                    || r.movers.len() as f64 > REFRESH_MAX_SHARE * sys.n() as f64;
                let movers = !r.movers.is_empty();
                whole || (movers && !self.refresh_movers(sys))
            }
            _ => drift >= self.skin || refresh != self.refresher.is_some(),
        };
        if !stale {
            return false;
        }
        if drift.is_finite() {
            self.drift_rate = drift / self.lived as f64;
        }
        self.build(
            sys,
            (skin_diameters, max_diameters),
            lifetime_steps,
            refresh,
        );
        true
    }

    /// Builds the whole list from the core's cell list.
    fn build(
        &mut self,
        sys: &mut System,
        (skin_diameters, max_diameters): (f64, f64),
        lifetime_steps: f64,
        refresh: bool,
    ) {
        self.lived = 0;
        let d = sys.dim;
        for xi in sys.x.chunks_exact_mut(d) {
            sys.container.wrap(xi);
        }
        let mean = sys.kappa * sys.d0_mean;
        self.skin = (skin_diameters * mean)
            .max((lifetime_steps * self.drift_rate).min(max_diameters * mean));
        let n = sys.n();
        let nc = n * d;
        self.refresher = refresh.then(|| Refresher::new(sys, self.skin));
        // Refreshing lists the pairs within σ(1 + γ) + 4b (see `refresh`).
        let (grown, reach, dia) = match &self.refresher {
            Some(r) => (1.0 + r.gamma, r.skin(), r.inflated()),
            None => (1.0, self.skin, &sys.dia[..]),
        };
        CellList::near_pairs_into(&sys.container, &sys.x[..nc], dia, reach, &mut self.pairs);
        for p in &mut self.pairs {
            *p = (p.0.min(p.1), p.0.max(p.1));
        }
        let pairs = self.pairs.iter().copied();
        self.rows.lay_out(n, pairs.clone(), refresh, &mut self.fill);
        if refresh {
            self.lower
                .lay_out(n, pairs.map(|(i, j)| (j, i)), true, &mut self.fill);
        } else {
            self.lower = Rows::new();
        }
        self.columns_current = false;
        self.near_wall.clear();
        if sys.container.has_walls() {
            self.near_wall
                .extend((0..n).map(|i| near_a_wall(sys, i, grown, reach)));
        }
        self.build_x.clear();
        self.build_x.extend_from_slice(&sys.x);
        self.ref_kappa = sys.kappa;
        self.ref_height = sys.container.lengths[d - 1];
        self.builds += 1;
    }

    /// Searches the rows of the movers again at the current positions: each mover's row is
    /// written anew, and the rows of its lower partners gain or lose it, so that the list
    /// holds the same pairs as a whole build would at the positions each row was searched at.
    /// Returns false when the moved rows would double the list: it is then built again.
    fn refresh_movers(&mut self, sys: &System) -> bool {
        let Some(mut r) = self.refresher.take() else {
            return false;
        };
        let fits = self.refresh_rows(sys, &mut r);
        self.refresher = Some(r);
        fits
    }

    /// [`NeighborList::refresh_movers`] with its refresher.
    fn refresh_rows(&mut self, sys: &System, r: &mut Refresher) -> bool {
        r.place_movers(sys);
        let (grown, reach) = (1.0 + r.gamma, r.skin());
        let mut old = Vec::new();
        for k in 0..r.movers.len() {
            let mu = r.movers[k];
            let m = mu as usize;
            r.search(sys, m);
            let split = r.near.partition_point(|&j| j < mu);
            let (below, above) = r.near.split_at(split);
            // The partners above list m in their lower rows; those below in their rows.
            old.clear();
            old.extend_from_slice(self.rows.get(m));
            let fits = follow(&mut self.lower, &old, above, mu) && self.rows.replace(m, above);
            old.clear();
            old.extend_from_slice(self.lower.get(m));
            let fits =
                fits && follow(&mut self.rows, &old, below, mu) && self.lower.replace(m, below);
            if !fits {
                return false;
            }
            if !self.near_wall.is_empty() {
                self.near_wall[m] = near_a_wall(sys, m, grown, reach);
            }
            self.refreshed += 1;
            self.columns_current = false;
        }
        true
    }

    /// Puts the rows back in order and builds the columns, if the rows changed since they
    /// were last built (the parallel force loop needs both).
    pub fn ensure_columns(&mut self) {
        if self.rows.put_in_order() {
            self.columns_current = false;
        }
        if !self.columns_current {
            self.transpose();
            self.columns_current = true;
        }
    }

    /// Writes into `unit0` (N·d, at κ = 1) each particle's length scale
    /// ℓ_i = (c̄ / Σ_j w_ij σ₀_ij⁻²)^(1/2), a Jacobi preconditioner: Σ_j w_ij σ₀_ij⁻² is the
    /// diagonal of the overlap energy's Hessian over the listed neighbours j (w: the contact's
    /// weight in U, 1 for relative overlaps, making every pair's term D̄⁻² for absolute
    /// ones), and c̄, the mean neighbour
    /// count, keeps ℓ near D for equal spheres (D·(c̄/c_i)^(1/2) for c_i neighbours). A small
    /// sphere among large ones gets the larger σ that sets its stiffness; a large sphere
    /// touched by hundreds of small ones (RCPGenerator 1.0's power law 1–15) gets a length near the
    /// small ones', so it neither oscillates nor forces every step down.
    /// Walls within reach add to the diagonal too. Particles without neighbours keep D₀_i.
    /// Call it right after a build ([`NeighborList::update`] returning true).
    pub fn contact_lengths(&self, sys: &System, unit0: &mut [f64]) {
        let n = sys.n();
        let d = sys.dim;
        let mut inv2 = vec![0.0; n];
        let mut count = vec![0u32; n];
        for i in 0..n {
            for &ju in self.rows.get(i) {
                let j = ju as usize;
                let s = 0.5 * (sys.d0[i] + sys.d0[j]);
                let h = sys.overlap_weight(sys.kappa * s) / (s * s);
                inv2[i] += h;
                count[i] += 1;
                inv2[j] += h;
                count[j] += 1;
            }
        }
        // A wall in reach adds w_i R₀_i⁻² (ε_iw = 1 − h/R_i): 4× a pair of equal spheres, and 256×
        // the pairs of a small sphere between spheres 15× larger, which without this term
        // oscillated against the walls and stalled FIRE in RCPGenerator 1.0's walled power law. The
        // build found which particles have a wall in that reach (`near_wall`, empty without
        // walls); only they are asked which walls.
        for (i, (h, _)) in inv2
            .iter_mut()
            .zip(&self.near_wall)
            .enumerate()
            .filter(|(_, (_, near))| **near)
        {
            let r = 0.5 * sys.dia[i];
            let r0 = 0.5 * sys.d0[i];
            let wall = sys.overlap_weight(sys.dia[i]) / (r0 * r0);
            sys.container
                .for_each_wall(&sys.x[i * d..(i + 1) * d], r + self.skin, |_| {
                    *h += wall;
                });
        }
        let with_neighbours = count.iter().filter(|&&c| c > 0).count().max(1);
        // At least one, so a sphere alone between walls still moves.
        let mean_count =
            (count.iter().map(|&c| c as f64).sum::<f64>() / with_neighbours as f64).max(1.0);
        // A wall out of reach at this build may be touched before the next: its stiffness
        // w_i R₀_i⁻² must then stay within mean_count, so ℓ_i ≤ √mean_count·R₀_i/√w_i. Without this cap a
        // small sphere whose only neighbours are 15× larger had ℓ² 64× its wall's limit and went
        // through the wall under Verlet (RCPGenerator 1.0's walled power law).
        let wall_cap = sys.container.has_walls().then(|| mean_count.sqrt() * 0.5);
        for i in 0..n {
            let mut l = if inv2[i] > 0.0 {
                (mean_count / inv2[i]).sqrt()
            } else {
                sys.d0[i]
            };
            if let Some(cap) = wall_cap {
                l = l.min(cap * sys.d0[i] / sys.overlap_weight(sys.dia[i]).sqrt());
            }
            unit0[i * d..(i + 1) * d].fill(l);
        }
    }

    /// Builds the columns from the rows: a counting sort of the entries by neighbour, which
    /// keeps them in row order.
    fn transpose(&mut self) {
        let n = self.rows.start.len() - 1;
        let col_start = &mut self.col_start;
        col_start.clear();
        col_start.resize(n + 1, 0);
        for i in 0..n {
            for &j in self.rows.get(i) {
                col_start[j as usize + 1] += 1;
            }
        }
        for j in 0..n {
            col_start[j + 1] += col_start[j];
        }
        self.fill.clear();
        self.fill.extend_from_slice(col_start);
        self.col_entry.clear();
        self.col_entry.resize(col_start[n] as usize, 0);
        for i in 0..n {
            for e in self.rows.row(i) {
                let j = self.rows.entries[e] as usize;
                self.col_entry[self.fill[j] as usize] = e as u32;
                self.fill[j] += 1;
            }
        }
    }

    /// Change of the fix-height length since the build.
    fn height_change(&self, sys: &System) -> f64 {
        (sys.container.lengths[sys.dim - 1] - self.ref_height).abs()
    }

    /// Growth of the largest diameter and change of the fix-height length since the build.
    fn growth(&self, sys: &System) -> f64 {
        (sys.kappa - self.ref_kappa).max(0.0) * sys.d0_max + self.height_change(sys)
    }

    /// How far a gap may have closed since the last build (infinite without a list); when
    /// refreshing, also collects the movers.
    fn drift(&mut self, sys: &System) -> f64 {
        if self.build_x.len() != sys.x.len() || self.builds == 0 {
            return f64::INFINITY;
        }
        let mut refresher = self.refresher.as_mut();
        if let Some(r) = refresher.as_mut() {
            r.movers.clear();
        }
        let build_x = &self.build_x[..];
        // A gap closes by at most the two spheres' displacements: the largest two bound it.
        let (first, second) = packbench_core::dispatch_dim!(
            sys.dim,
            D => packbench_core::widest_simd::with_avx2(#[inline(always)] || {
                largest_two_moves::<D>(sys, build_x, refresher)
            }),
            _ => unreachable!("dimension {} is refused by Container::validate", sys.dim),
        );
        first.sqrt() + second.sqrt() + self.growth(sys)
    }
}

/// The two largest squared displacements since the build (`build_x`), each by the minimum
/// image along periodic axes (a particle wrapped since the build, as it left the box, moved by
/// the minimum image of the difference); the refresher's movers are collected on the way.
#[inline(always)]
fn largest_two_moves<const D: usize>(
    sys: &System,
    build_x: &[f64],
    mut refresher: Option<&mut Refresher>,
) -> (f64, f64) {
    let geo = Geometry::<D>::of(&sys.container);
    let moved2 = |a: &[f64], b: &[f64]| {
        let mut r2 = 0.0;
        for k in 0..D {
            let mut t = a[k] - b[k];
            if geo.periodic[k] {
                t = geo.nearest_image(t, k);
            }
            r2 += t * t;
        }
        r2
    };
    let (mut first, mut second): (f64, f64) = (0.0, 0.0);
    let now = sys.x.as_chunks::<D>().0;
    for (i, (a, b)) in now.iter().zip(build_x.as_chunks::<D>().0).enumerate() {
        let r2 = moved2(a, b);
        if r2 > second {
            if r2 > first {
                second = first;
                first = r2;
            } else {
                second = r2;
            }
        }
        if let Some(r) = refresher.as_mut()
            && r.moved(i, a, moved2)
        {
            r.movers.push(i as u32);
        }
    }
    (first, second)
}

/// Whether particle `i` is within its radius grown by `grown` plus `reach` of a wall: a wall
/// distance shrinks by at most the displacement plus the height change and the radius grows
/// by at most the growth term, which the staleness tests keep below the reach together.
fn near_a_wall(sys: &System, i: usize, grown: f64, reach: f64) -> bool {
    let d = sys.dim;
    let mut near = false;
    sys.container.for_each_wall(
        &sys.x[i * d..(i + 1) * d],
        0.5 * sys.dia[i] * grown + reach,
        |_| near = true,
    );
    near
}

/// Makes the rows of `target` named in exactly one of the sorted lists `old` and `new` follow
/// the change: those in `new` gain `m`, those in `old` lose it. False when a row could not
/// grow ([`Rows::insert`]).
fn follow(target: &mut Rows, old: &[u32], new: &[u32], m: u32) -> bool {
    changes(old, new, |k, joined| {
        if joined {
            target.insert(k as usize, m)
        } else {
            target.remove(k as usize, m);
            true
        }
    })
}

/// Calls `f(value, joined)` for each value in exactly one of the sorted lists `old` and `new`
/// (joined: in `new`), stopping at the first false.
fn changes(old: &[u32], new: &[u32], mut f: impl FnMut(u32, bool) -> bool) -> bool {
    let (mut a, mut b) = (0, 0);
    while a < old.len() || b < new.len() {
        let ok = match (old.get(a), new.get(b)) {
            (Some(&x), Some(&y)) if x == y => {
                a += 1;
                b += 1;
                true
            }
            (Some(&x), Some(&y)) if x > y => {
                b += 1;
                f(y, true)
            }
            (Some(&x), _) => {
                a += 1;
                f(x, false)
            }
            (None, Some(&y)) => {
                b += 1;
                f(y, true)
            }
            (None, None) => unreachable!("the loop runs while either list has values"),
        };
        if !ok {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests;
