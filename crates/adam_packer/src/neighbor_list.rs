//! A half Verlet neighbour list in compressed-row form (each pair once, in the row of its lower
//! index), built from the core's [`CellList`], with its transpose: the column of a particle
//! lists the entries of the rows above it that name it. Rows and columns let the force loop
//! compute each pair once and still write each particle from one place, so its sums need no
//! atomics and do not depend on the number of threads.

use packbench_core::neighbor::CellList;

use crate::system::System;

/// Neighbour rows with the reference state that tells when they go stale.
pub(crate) struct NeighborList {
    /// `start[i]..start[i+1]` indexes `nbr` for particle `i`.
    pub start: Vec<u32>,
    /// Neighbour indices j > i of row i, each row sorted.
    pub nbr: Vec<u32>,
    /// `col_start[j]..col_start[j+1]` indexes `col_entry` for particle `j`.
    pub col_start: Vec<u32>,
    /// Entries `e` of `nbr` with `nbr[e] = j`, in increasing `e` (row order).
    pub col_entry: Vec<u32>,
    /// Whether particle `i` was within its radius plus the skin of a wall at the build: only
    /// these can touch a wall before the list goes stale (empty without walls).
    pub near_wall: Vec<bool>,
    /// Skin in length units at the last build.
    skin: f64,
    /// Updates since the last build.
    lived: u64,
    /// Growth of the staleness bound per step over the last list's life (0 before the first
    /// list went stale).
    drift_rate: f64,
    ref_x: Vec<f64>,
    ref_kappa: f64,
    ref_height: f64,
    builds: u64,
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
            nbr: Vec::new(),
            col_start: Vec::new(),
            col_entry: Vec::new(),
            near_wall: Vec::new(),
            skin: 0.0,
            lived: 0,
            drift_rate: 0.0,
            ref_x: Vec::new(),
            ref_kappa: 0.0,
            ref_height: 0.0,
            builds: 0,
            pairs: Vec::new(),
            fill: Vec::new(),
        }
    }

    /// How many times the list has been built.
    pub fn builds(&self) -> u64 {
        self.builds
    }

    /// Number of listed pairs.
    pub fn pairs(&self) -> usize {
        self.nbr.len()
    }

    /// Rebuilds when a gap may have closed by the skin since the last build: two displacements,
    /// the growth of the largest diameter and any change of the fix-height length together
    /// must stay below the skin. Wraps positions along periodic axes on rebuild. The skin is
    /// `skin_diameters` mean diameters, or, when larger, what the staleness bound grew by in
    /// `lifetime_steps` steps of the last list's life (0: the fixed skin), at most
    /// `max_diameters` mean diameters. Returns whether it rebuilt.
    pub fn update(
        &mut self,
        sys: &mut System,
        (skin_diameters, max_diameters): (f64, f64),
        lifetime_steps: f64,
    ) -> bool {
        self.lived += 1;
        let drift = self.drift(sys);
        let stale = drift >= self.skin;
        if !stale {
            return false;
        }
        if drift.is_finite() {
            self.drift_rate = drift / self.lived as f64;
        }
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
        CellList::near_pairs_into(
            &sys.container,
            &sys.x[..nc],
            &sys.dia,
            self.skin,
            &mut self.pairs,
        );
        for p in &mut self.pairs {
            *p = (p.0.min(p.1), p.0.max(p.1));
        }
        let degree = &mut self.start;
        degree.clear();
        degree.resize(n + 1, 0);
        for &(i, _) in &self.pairs {
            degree[i as usize + 1] += 1;
        }
        for i in 0..n {
            degree[i + 1] += degree[i];
        }
        self.fill.clear();
        self.fill.extend_from_slice(degree);
        self.nbr.clear();
        self.nbr.resize(degree[n] as usize, 0);
        for &(i, j) in &self.pairs {
            self.nbr[self.fill[i as usize] as usize] = j;
            self.fill[i as usize] += 1;
        }
        for i in 0..n {
            self.nbr[degree[i] as usize..degree[i + 1] as usize].sort_unstable();
        }
        self.transpose();
        self.near_wall.clear();
        if sys.container.has_walls() {
            // Reach R + skin: a wall distance shrinks by at most the displacement plus the
            // height change and R grows by at most the growth term, which is_stale keeps
            // below the skin together.
            self.near_wall.extend((0..n).map(|i| {
                let mut near = false;
                sys.container.for_each_wall(
                    &sys.x[i * d..(i + 1) * d],
                    0.5 * sys.dia[i] + self.skin,
                    |_| near = true,
                );
                near
            }));
        }
        self.ref_x.clear();
        self.ref_x.extend_from_slice(&sys.x);
        self.ref_kappa = sys.kappa;
        self.ref_height = sys.container.lengths[d - 1];
        self.builds += 1;
        true
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
            for &ju in &self.nbr[self.start[i] as usize..self.start[i + 1] as usize] {
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
        let n = self.start.len() - 1;
        let col_start = &mut self.col_start;
        col_start.clear();
        col_start.resize(n + 1, 0);
        for &j in &self.nbr {
            col_start[j as usize + 1] += 1;
        }
        for j in 0..n {
            col_start[j + 1] += col_start[j];
        }
        self.fill.clear();
        self.fill.extend_from_slice(col_start);
        self.col_entry.clear();
        self.col_entry.resize(self.nbr.len(), 0);
        for (e, &j) in self.nbr.iter().enumerate() {
            self.col_entry[self.fill[j as usize] as usize] = e as u32;
            self.fill[j as usize] += 1;
        }
    }

    /// How far a gap may have closed since the last build (infinite without a list).
    fn drift(&self, sys: &System) -> f64 {
        if self.ref_x.len() != sys.x.len() || self.builds == 0 {
            return f64::INFINITY;
        }
        let d = sys.dim;
        let c = &sys.container;
        // A gap closes by at most the two spheres' displacements: the largest two bound it.
        let (mut first, mut second): (f64, f64) = (0.0, 0.0);
        for (a, b) in sys.x.chunks_exact(d).zip(self.ref_x.chunks_exact(d)) {
            let mut r2 = 0.0;
            for k in 0..d {
                let mut t = a[k] - b[k];
                // A particle wrapped since the build (as it left the box) moved by the
                // minimum image of the difference.
                if c.periodic[k] && t.abs() > 0.5 * c.lengths[k] {
                    t -= c.lengths[k].copysign(t);
                }
                r2 += t * t;
            }
            if r2 > second {
                if r2 > first {
                    second = first;
                    first = r2;
                } else {
                    second = r2;
                }
            }
        }
        let growth = (sys.kappa - self.ref_kappa).max(0.0) * sys.d0_max;
        let height = (sys.container.lengths[d - 1] - self.ref_height).abs();
        first.sqrt() + second.sqrt() + growth + height
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use packbench_core::{Container, Packing};

    /// The staleness bound (the two largest displacements) keeps the list complete: after
    /// every update each overlapping pair is listed, while all spheres jiggle, the diameters
    /// grow, and the closest pair left out at the last build is driven straight together by
    /// 0.3 skin per step, as far as the bound lets it; with the fixed skin, with one grown
    /// to last four steps, and with that growth capped at half a mean diameter.
    #[test]
    fn every_overlapping_pair_stays_listed() {
        overlapping_pairs_stay_listed(0.0, 0.2);
        overlapping_pairs_stay_listed(4.0, 100.0);
        overlapping_pairs_stay_listed(4.0, 0.5);
    }

    fn overlapping_pairs_stay_listed(lifetime_steps: f64, skin_max: f64) {
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let n = 80;
        let box_len = 12.0;
        let c = Container::with_flags(&[box_len; 3], &[false; 3]).unwrap();
        let x: Vec<f64> = (0..3 * n).map(|_| box_len * uniform()).collect();
        let dia: Vec<f64> = (0..n).map(|_| 1.0 + 2.0 * uniform()).collect();
        let mut sys = System::new(&Packing::new(x, dia, c).unwrap(), &[]).unwrap();
        let mut nl = NeighborList::new();
        let skin = 0.2;
        // Gap between i and j (negative: overlap) and the unit vector from i to j.
        let gap = |sys: &System, i: usize, j: usize| {
            let mut dx: Vec<f64> = (0..3)
                .map(|k| sys.x[3 * j + k] - sys.x[3 * i + k])
                .collect();
            sys.container.min_image(&mut dx);
            let r = dx.iter().map(|t| t * t).sum::<f64>().sqrt();
            dx.iter_mut().for_each(|t| *t /= r);
            (r - 0.5 * (sys.dia[i] + sys.dia[j]), dx)
        };
        let listed = |nl: &NeighborList, i: usize, j: usize| {
            nl.nbr[nl.start[i] as usize..nl.start[i + 1] as usize].contains(&(j as u32))
        };
        let (mut builds, mut overlaps, mut driven) = (0, 0, (0, 0));
        for step in 0..300 {
            if nl.update(&mut sys, (skin, skin_max), lifetime_steps) {
                builds += 1;
                let mean = sys.kappa * sys.d0_mean;
                assert!(
                    nl.skin <= skin_max * mean * (1.0 + 1e-12),
                    "skin {}",
                    nl.skin
                );
                driven = (0..n)
                    .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
                    .filter(|&(i, j)| !listed(&nl, i, j))
                    .min_by(|a, b| gap(&sys, a.0, a.1).0.total_cmp(&gap(&sys, b.0, b.1).0))
                    .unwrap();
            }
            for i in 0..n {
                for j in i + 1..n {
                    if gap(&sys, i, j).0 < 0.0 {
                        overlaps += 1;
                        assert!(listed(&nl, i, j), "step {step}: pair {i}–{j} not listed");
                    }
                }
            }
            let step_len = 0.15 * skin;
            let (i, j) = driven;
            let (_, dir) = gap(&sys, i, j);
            for (k, u) in dir.iter().enumerate() {
                sys.x[3 * i + k] += step_len * u;
                sys.x[3 * j + k] -= step_len * u;
            }
            for v in sys.x.iter_mut() {
                *v += 0.002 * skin * (2.0 * uniform() - 1.0);
            }
            sys.set_kappa(sys.kappa * 1.0002);
        }
        assert!(builds > 20, "{builds} builds");
        assert!(overlaps > 100, "{overlaps} overlapping pairs checked");
    }

    /// A small sphere whose only neighbour is 15× larger, with a wall out of reach: its length
    /// stays within √c̄·R₀, so touching the wall later keeps its stiffness R₀⁻²·ℓ² ≤ c̄ (the
    /// bound the Verlet step is stable under), where the neighbour alone would give ℓ = √c̄·8.
    #[test]
    fn a_small_sphere_near_a_wall_keeps_a_wall_stable_length() {
        let walls = Container::with_flags(&[40.0, 20.0, 40.0], &[false, true, false]).unwrap();
        // Small sphere (D = 1) touching the large one (D = 15) centred 8 away in x; the walls at
        // y = 0 and 20 are beyond its reach (R + skin).
        let packing =
            Packing::new(vec![1.0, 10.0, 5.0, 9.0, 10.0, 5.0], vec![1.0, 15.0], walls).unwrap();
        let mut sys = System::new(&packing, &[]).unwrap();
        let mut nl = NeighborList::new();
        nl.update(&mut sys, (0.1, 0.1), 0.0);
        assert_eq!(nl.pairs(), 1);
        let mut unit0 = vec![0.0; 6];
        nl.contact_lengths(&sys, &mut unit0);
        let small = sys.d0.iter().position(|&v| v == 1.0).unwrap();
        let l = unit0[3 * small];
        // c̄ = 1 (one pair, both ends listed): ℓ ≤ √1·R₀ = 0.5, against 8 without the cap.
        assert!((l - 0.5).abs() < 1e-12, "ℓ = {l}");
    }
}
