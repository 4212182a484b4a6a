//! A half Verlet neighbour list in compressed-row form (each pair once, in the row of its lower
//! index), built from the core's [`CellList`], with its transpose: the column of a particle
//! lists the entries of the rows above it that name it. Rows and columns let the force loop
//! compute each pair once and still write each particle from one place, so its sums need no
//! atomics and do not depend on the number of threads. Between whole builds the rows of the
//! particles that moved can be refreshed one by one ([`refresh`]).

mod refresh;

use packbench_core::neighbor::CellList;

use crate::system::System;
use refresh::Refresher;

/// Movers per particle above which a refresh rebuilds the whole list instead: the whole-list
/// scan pairs cells at once and costs less per particle than a query each.
const REFRESH_MAX_SHARE: f64 = 0.1;

/// Neighbour rows with the reference state that tells when they go stale.
pub(crate) struct NeighborList {
    /// Row `i` is `nbr[start[i]..start[i] + len[i]]`, with room for `room[i]` entries. After a
    /// build (or [`NeighborList::ensure_columns`]) the rows lie in order, `start[i+1]` =
    /// `start[i] + room[i]`; a refresh moves a row that outgrows its room to the end.
    pub start: Vec<u32>,
    len: Vec<u32>,
    room: Vec<u32>,
    /// Whether the rows lie in order (see `start`).
    in_order: bool,
    /// Entries when the list was built (the moved rows may at most double them), and listed
    /// pairs then and now.
    built_entries: usize,
    built_pairs: usize,
    listed: usize,
    /// Neighbour indices j > i of row i, each row sorted.
    pub nbr: Vec<u32>,
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
            start: Vec::new(),
            len: Vec::new(),
            room: Vec::new(),
            in_order: true,
            built_entries: 0,
            built_pairs: 0,
            listed: 0,
            nbr: Vec::new(),
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
        self.listed
    }

    /// The entries of `nbr` that make row `i`.
    #[inline(always)]
    pub fn row(&self, i: usize) -> std::ops::Range<usize> {
        let a = self.start[i] as usize;
        a..a + self.len[i] as usize
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
        let height = (sys.container.lengths[sys.dim - 1] - self.ref_height).abs();
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
        let (grown, reach) = match &self.refresher {
            Some(r) => (1.0 + r.gamma, r.skin()),
            None => (1.0, self.skin),
        };
        let inflated: Vec<f64>;
        let dia = if grown > 1.0 {
            inflated = sys.dia.iter().map(|&v| v * grown).collect();
            &inflated[..]
        } else {
            &sys.dia[..]
        };
        CellList::near_pairs_into(&sys.container, &sys.x[..nc], dia, reach, &mut self.pairs);
        for p in &mut self.pairs {
            *p = (p.0.min(p.1), p.0.max(p.1));
        }
        // Rows counted, then given room to insert a quarter more partners (and two) when
        // refreshing.
        self.len.clear();
        self.len.resize(n, 0);
        for &(i, _) in &self.pairs {
            self.len[i as usize] += 1;
        }
        self.room.clear();
        self.room.extend(
            self.len
                .iter()
                .map(|&l| if refresh { l + 2 + l / 4 } else { l }),
        );
        let start = &mut self.start;
        start.clear();
        start.resize(n + 1, 0);
        for i in 0..n {
            start[i + 1] = start[i] + self.room[i];
        }
        self.in_order = true;
        self.built_entries = start[n] as usize;
        self.built_pairs = self.pairs.len();
        self.listed = self.pairs.len();
        self.fill.clear();
        self.fill.extend_from_slice(&start[..n]);
        self.nbr.clear();
        self.nbr.resize(start[n] as usize, 0);
        for &(i, j) in &self.pairs {
            self.nbr[self.fill[i as usize] as usize] = j;
            self.fill[i as usize] += 1;
        }
        for i in 0..n {
            let row = self.row(i);
            self.nbr[row].sort_unstable();
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
    /// written anew, and the mover is inserted into the rows of its lower partners that lack
    /// it. Partners it no longer has stay listed until their own refresh or the next build
    /// (a pair apart adds exact zeros). Returns false when the moved rows would double the
    /// list or the pairs listed grew by a quarter: the list is then built again.
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
        for k in 0..r.movers.len() {
            let mu = r.movers[k];
            let m = mu as usize;
            r.search(sys, m);
            let split = r.near.partition_point(|&j| j < mu);
            let upper = &r.near[split..];
            if !self.make_room(m, upper.len()) {
                return false;
            }
            let a = self.start[m] as usize;
            self.nbr[a..a + upper.len()].copy_from_slice(upper);
            self.listed = self.listed + upper.len() - self.len[m] as usize;
            self.len[m] = upper.len() as u32;
            for &ju in &r.near[..split] {
                let j = ju as usize;
                let a = self.start[j] as usize;
                let end = a + self.len[j] as usize;
                if let Err(at) = self.nbr[a..end].binary_search(&mu) {
                    if !self.make_room(j, end - a + 1) {
                        return false;
                    }
                    let (a, end) = (self.start[j] as usize, end - a + self.start[j] as usize);
                    self.nbr.copy_within(a + at..end, a + at + 1);
                    self.nbr[a + at] = mu;
                    self.len[j] += 1;
                    self.listed += 1;
                }
            }
            if !self.near_wall.is_empty() {
                self.near_wall[m] = near_a_wall(sys, m, grown, reach);
            }
            self.refreshed += 1;
            self.columns_current = false;
        }
        // Partners that left stay listed: a quarter more pairs than the build listed costs
        // the force loop more than building the list again.
        self.listed <= self.built_pairs + self.built_pairs / 4 + 16
    }

    /// Gives row `i` room for `need` entries, moving it to the end of `nbr` (with a quarter
    /// more and two) when it has less. Returns false when the moved rows would double the
    /// entries of the build: the list is then built again.
    fn make_room(&mut self, i: usize, need: usize) -> bool {
        if need <= self.room[i] as usize {
            return true;
        }
        let room = need + 2 + need / 4;
        let at = self.nbr.len();
        if at + room > 2 * self.built_entries + 1024 {
            return false;
        }
        let old = self.row(i);
        self.nbr.resize(at + room, 0);
        self.nbr.copy_within(old, at);
        self.start[i] = at as u32;
        self.room[i] = room as u32;
        self.in_order = false;
        true
    }

    /// Puts the rows back in order and builds the columns, if the rows changed since they
    /// were last built (the parallel force loop needs both).
    pub fn ensure_columns(&mut self) {
        if !self.in_order {
            let n = self.len.len();
            let mut nbr = Vec::with_capacity(self.room.iter().map(|&r| r as usize).sum());
            for i in 0..n {
                let row = self.row(i);
                self.start[i] = nbr.len() as u32;
                nbr.extend_from_slice(&self.nbr[row]);
                nbr.resize(self.start[i] as usize + self.room[i] as usize, 0);
            }
            self.start[n] = nbr.len() as u32;
            self.nbr = nbr;
            self.in_order = true;
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
            for &ju in &self.nbr[self.row(i)] {
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
        let n = self.len.len();
        let col_start = &mut self.col_start;
        col_start.clear();
        col_start.resize(n + 1, 0);
        for i in 0..n {
            let a = self.start[i] as usize;
            for &j in &self.nbr[a..a + self.len[i] as usize] {
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
            for e in self.row(i) {
                let j = self.nbr[e] as usize;
                self.col_entry[self.fill[j] as usize] = e as u32;
                self.fill[j] += 1;
            }
        }
    }

    /// Growth of the largest diameter and change of the fix-height length since the build.
    fn growth(&self, sys: &System) -> f64 {
        let height = (sys.container.lengths[sys.dim - 1] - self.ref_height).abs();
        (sys.kappa - self.ref_kappa).max(0.0) * sys.d0_max + height
    }

    /// How far a gap may have closed since the last build (infinite without a list); when
    /// refreshing, also collects the movers.
    fn drift(&mut self, sys: &System) -> f64 {
        if self.build_x.len() != sys.x.len() || self.builds == 0 {
            return f64::INFINITY;
        }
        let d = sys.dim;
        let c = &sys.container;
        // A particle wrapped since the build (as it left the box) moved by the minimum image
        // of the difference.
        let moved2 = |a: &[f64], b: &[f64]| {
            let mut r2 = 0.0;
            for k in 0..d {
                let mut t = a[k] - b[k];
                if c.periodic[k] && t.abs() > 0.5 * c.lengths[k] {
                    t -= c.lengths[k].copysign(t);
                }
                r2 += t * t;
            }
            r2
        };
        let mut refresher = self.refresher.as_mut();
        if let Some(r) = refresher.as_mut() {
            r.movers.clear();
        }
        // A gap closes by at most the two spheres' displacements: the largest two bound it.
        let (mut first, mut second): (f64, f64) = (0.0, 0.0);
        for (i, (a, b)) in sys
            .x
            .chunks_exact(d)
            .zip(self.build_x.chunks_exact(d))
            .enumerate()
        {
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
        first.sqrt() + second.sqrt() + self.growth(sys)
    }
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

#[cfg(test)]
mod tests;
