//! The soft harmonic overlap energy and its forces (RCPGenerator 1.0, `GetForcesND_3`'s role):
//!
//! U = Σ_pairs ½ w_ij ε_ij² + Σ_walls ½ w_i ε_iw²,  ε_ij = 1 − r_ij/σ_ij (σ_ij = (D_i + D_j)/2),
//! ε_iw = 1 − h_iw/R_i (h: signed distance of the centre to the wall, R_i = D_i/2),
//!
//! counting only overlapping pairs (ε > 0). The weights are 1 (relative overlaps, RCPGenerator 1.0) or
//! (σ/D̄)² with σ = σ_ij or D_i (absolute overlaps in units of the mean diameter D̄, see
//! [`OverlapScale`](crate::system::OverlapScale)). Periodic axes use the minimum image, and
//! spheres wider than half a periodic length add their other images (`other_images.rs`);
//! walled axes never do. Each pair is listed once (half rows) and its force computed once;
//! where the processor has AVX2 a chunk's pairs are computed four at a time in lanes first
//! (`lanes.rs`, the same bytes), then added up in list order. On one thread
//! it is added to the row particle and scattered to the other in the same loop; on several,
//! pair forces are stored first and each particle then adds its column and its row in the
//! order the scatter would. Scalar sums go by fixed chunks of particles merged in chunk
//! order, so forces and energies are bit-identical for any number of threads.

#[cfg(target_arch = "x86_64")]
mod lanes;
mod other_images;

#[cfg(target_arch = "x86_64")]
use lanes::Avx2;

/// No vector lanes off x86-64: the pairs go one at a time.
#[cfg(not(target_arch = "x86_64"))]
#[derive(Clone, Copy, Debug)]
enum Avx2 {}

#[cfg(not(target_arch = "x86_64"))]
impl Avx2 {
    fn detect() -> Option<Avx2> {
        None
    }
}

use packbench_core::Container;
use packbench_core::widest_simd::with_avx2;
use rayon::prelude::*;
use std::ops::Range;

use crate::neighbor_list::{NeighborList, Rows};
use crate::system::{Geometry, OverlapScale, System, absolute_weight};

/// Particles per chunk of the force loop (fixed, so sums do not depend on threads).
const CHUNK: usize = 256;

/// What one force evaluation measures besides the forces.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Evaluation {
    /// U = Σ ½ ε² over overlapping pairs and walls.
    pub energy: f64,
    /// Largest ε over pairs and walls (0 without overlaps).
    pub max_overlap: f64,
    /// Squared norm of the force with each particle's coordinates measured in the overlaps'
    /// length: Σ_i |F_i D_i|² for relative overlaps, Σ_i |F_i D̄|² for absolute ones.
    pub residual2: f64,
    /// Σ g w ε(1 − ε) over contacts = −∂U/∂ln κ, the "virial" that drives the pressure
    /// protocol; g, the share of the contact's length that scales with κ, is 1 unless some
    /// diameters are held. 0 unless the evaluation was asked for it (the pressure protocol).
    pub virial: f64,
    /// Σ g w ε over contacts: Σ σ_g δ/D̄² under absolute overlaps (σ_g: the growing part of
    /// σ), the overlap term of RCPGenerator's force on its diameter scale.
    pub weighted_overlap: f64,
    /// Σ (σ/r − 1) over overlapping pairs, 2(R/h − 1) over walls: RCPGenerator's measure of
    /// the mean contact overlap (divided by 1 + `contacts`).
    pub stretch: f64,
    /// Number of overlapping pairs and walls.
    pub contacts: f64,
}

impl Evaluation {
    fn merge(mut self, o: Evaluation) -> Evaluation {
        self.energy += o.energy;
        self.max_overlap = self.max_overlap.max(o.max_overlap);
        self.residual2 += o.residual2;
        self.virial += o.virial;
        self.weighted_overlap += o.weighted_overlap;
        self.stretch += o.stretch;
        self.contacts += o.contacts;
        self
    }
}

/// Running pair sums of one force loop: Σwε², Σwε(1 − ε) (with `VIRIAL`), max ε, Σwε,
/// Σ(σ/r − 1) and the contact count.
#[derive(Default)]
struct PairSums<const VIRIAL: bool> {
    eps2: f64,
    virial: f64,
    max_eps: f64,
    weighted: f64,
    stretch: f64,
    contacts: f64,
}

impl<const VIRIAL: bool> PairSums<VIRIAL> {
    /// A contact's terms; `g` is the growing share of its length (see [`Evaluation::virial`]).
    #[inline(always)]
    fn add(&mut self, eps: f64, stretch: f64, w: f64, g: f64) {
        self.eps2 += w * eps * eps;
        if VIRIAL {
            self.virial += g * w * eps * (1.0 - eps);
        }
        self.max_eps = self.max_eps.max(eps);
        self.weighted += g * w * eps;
        self.stretch += stretch;
        self.contacts += f64::from(u8::from(eps > 0.0));
    }

    /// Adds the pair terms to `ev`, each listed entry weighted by `weight` (½ when every pair
    /// is listed from both ends): U gets ½wε², the virial wε(1 − ε).
    fn add_to(self, ev: &mut Evaluation, weight: f64) {
        ev.max_overlap = ev.max_overlap.max(self.max_eps);
        ev.energy += 0.5 * weight * self.eps2;
        ev.virial += weight * self.virial;
        ev.weighted_overlap += weight * self.weighted;
        ev.stretch += weight * self.stretch;
        ev.contacts += weight * self.contacts;
    }
}

/// The overlap energy of a fixed packing, evaluated on demand with the packer's own force
/// kernel and neighbour list: for benchmarks of the force loop (pair interactions per second)
/// and for inspecting a packing's residual overlaps.
pub struct OverlapForces {
    sys: System,
    nl: NeighborList,
    force: Vec<f64>,
    reactions: Vec<f64>,
    parallel: bool,
}

impl OverlapForces {
    /// Builds the neighbour list of `packing` (skin: `neighbor_skin` mean diameters); with
    /// `parallel` the force passes run on rayon's threads.
    pub fn new(
        packing: &packbench_core::Packing,
        neighbor_skin: f64,
        parallel: bool,
    ) -> Result<Self, crate::AdamError> {
        let mut sys = System::new(packing, &[])?;
        let mut nl = NeighborList::new();
        nl.update(&mut sys, (neighbor_skin, neighbor_skin), 0.0, false);
        let force = vec![0.0; sys.x.len()];
        Ok(OverlapForces {
            sys,
            nl,
            force,
            reactions: Vec::new(),
            parallel,
        })
    }

    /// Listed neighbour pairs (each once), the pair interactions one evaluation computes.
    pub fn listed_pairs(&self) -> usize {
        self.nl.pairs()
    }

    /// Evaluates the forces; returns the energy U and the largest overlap ε.
    pub fn evaluate(&mut self) -> (f64, f64) {
        let ev = evaluate(
            &self.sys,
            &mut self.nl,
            &mut self.force,
            &mut self.reactions,
            self.parallel,
            false,
        );
        (ev.energy, ev.max_overlap)
    }
}

/// Fills `force` (N·d, sorted order) with F = −∂U/∂x and returns the energy and friends.
/// `reactions` is scratch for the pair terms (resized here); with `parallel` and more than one
/// rayon thread the work is shared between threads, with the same result to the bit; the
/// virial is summed only with `virial`.
pub(crate) fn evaluate(
    sys: &System,
    nl: &mut NeighborList,
    force: &mut [f64],
    reactions: &mut Vec<f64>,
    parallel: bool,
    virial: bool,
) -> Evaluation {
    let parallel = parallel && rayon::current_num_threads() > 1;
    if parallel {
        nl.ensure_columns();
    }
    reactions.resize(nl.rows.entries.len() * sys.dim, 0.0);
    // Only the pressure protocol uses the virial; the others save 3–6 % of their runs' CPU.
    if virial {
        dispatch::<true>(sys, nl, force, reactions, parallel)
    } else {
        dispatch::<false>(sys, nl, force, reactions, parallel)
    }
}

/// [`evaluate`] with the virial summed or not, monomorphised on the dimension and the case.
fn dispatch<const VIRIAL: bool>(
    sys: &System,
    nl: &NeighborList,
    force: &mut [f64],
    reactions: &mut [f64],
    parallel: bool,
) -> Evaluation {
    let all_periodic = sys.container.is_fully_periodic();
    let absolute = sys.overlap_scale == OverlapScale::Absolute;
    let lanes = Avx2::detect();
    // Monomorphised per case, so relative overlaps (weight 1) pay nothing for the weights.
    // Under AVX2 the SSE2 build's register copies go (7–8 % of a whole run's CPU at N = 10³,
    // docs/notes/adam-step-profile.md), with the same bytes (test
    // `the_avx2_force_loop_gives_the_baseline_bytes`).
    packbench_core::dispatch_dim!(
        sys.dim,
        D => match (all_periodic, absolute) {
            (true, false) => with_avx2(#[inline(always)] || run::<D, true, false, VIRIAL>(sys, nl, force, reactions, parallel, lanes)),
            (false, false) => with_avx2(#[inline(always)] || run::<D, false, false, VIRIAL>(sys, nl, force, reactions, parallel, lanes)),
            (true, true) => with_avx2(#[inline(always)] || run::<D, true, true, VIRIAL>(sys, nl, force, reactions, parallel, lanes)),
            (false, true) => with_avx2(#[inline(always)] || run::<D, false, true, VIRIAL>(sys, nl, force, reactions, parallel, lanes)),
        },
        _ => unreachable!("dimension {} is refused by Container::validate", sys.dim),
    )
}

/// Box geometry, walls and overlap weights of one evaluation.
struct Frame<'a, const D: usize, const ABSOLUTE: bool> {
    geo: Geometry<D>,
    /// The container when it has walls, with the particles that may touch one.
    walls: Option<(&'a Container, &'a [bool])>,
    mean_diameter: f64,
    /// 1 where a diameter scales with κ, 0 where it is held; `None` when all scale.
    grows: Option<&'a [f64]>,
    /// AVX2, where both loops take the pairs four at a time in lanes (`lane_terms`).
    lanes: Option<Avx2>,
}

impl<const D: usize, const ABSOLUTE: bool> Frame<'_, D, ABSOLUTE> {
    /// The weight of a contact of length σ, as [`System::overlap_weight`].
    #[inline(always)]
    fn weight(&self, sigma: f64) -> f64 {
        if ABSOLUTE {
            absolute_weight(sigma, self.mean_diameter)
        } else {
            1.0
        }
    }

    /// The share of a pair's length σ = (D_i + D_j)/2 that scales with κ: ∂σ/∂ln κ over σ.
    #[inline(always)]
    fn growth(&self, i: usize, j: usize, di: f64, dj: f64) -> f64 {
        match self.grows {
            None => 1.0,
            Some(g) => (g[i] * di + g[j] * dj) / (di + dj),
        }
    }
}

#[inline(always)]
fn run<const D: usize, const ALL_PERIODIC: bool, const ABSOLUTE: bool, const VIRIAL: bool>(
    sys: &System,
    nl: &NeighborList,
    force: &mut [f64],
    reactions: &mut [f64],
    parallel: bool,
    lanes: Option<Avx2>,
) -> Evaluation {
    let c = &sys.container;
    let frame = Frame::<D, ABSOLUTE> {
        geo: Geometry::of(c),
        walls: (!ALL_PERIODIC && c.has_walls()).then_some((c, &nl.near_wall[..])),
        mean_diameter: sys.mean_diameter(),
        grows: sys.grows(),
        lanes,
    };
    force.fill(0.0);
    let mut images = Evaluation::default();
    other_images::add_forces::<D, ABSOLUTE, VIRIAL>(sys, force.as_chunks_mut::<D>().0, &frame)
        .add_to(&mut images, 1.0);
    let partials = if parallel {
        two_passes::<D, ALL_PERIODIC, ABSOLUTE, VIRIAL>(sys, nl, force, reactions, &frame)
    } else {
        scatter::<D, ALL_PERIODIC, ABSOLUTE, VIRIAL>(sys, nl, force, &frame)
    };
    partials.into_iter().fold(images, Evaluation::merge)
}

/// One thread: each row's pairs once, the force on the row particle accumulated and the
/// reaction scattered to the neighbour, whose row comes later (j > i), so a particle's force
/// is final once its row is done. Per particle: (other images, already in `force`) −
/// (reactions in row order) + (own pairs in row order) + walls; per chunk of `CHUNK` particles
/// one partial [`Evaluation`].
#[inline(always)]
fn scatter<const D: usize, const ALL_PERIODIC: bool, const ABSOLUTE: bool, const VIRIAL: bool>(
    sys: &System,
    nl: &NeighborList,
    force: &mut [f64],
    frame: &Frame<D, ABSOLUTE>,
) -> Vec<Evaluation> {
    let (x, _) = sys.x.as_chunks::<D>();
    let dia = &sys.dia;
    let (f, _) = force.as_chunks_mut::<D>();
    let mut partials = Vec::with_capacity(f.len().div_ceil(CHUNK));
    let mut scratch = LaneScratch::default();
    for first in (0..f.len()).step_by(CHUNK) {
        let mut ev = Evaluation::default();
        let mut sums = PairSums::<VIRIAL>::default();
        let last = f.len().min(first + CHUNK);
        let mut lane_terms = lane_terms::<D, ALL_PERIODIC, ABSOLUTE>(
            x,
            dia,
            &nl.rows,
            first..last,
            frame,
            &mut scratch,
        );
        for i in first..last {
            let di = dia[i];
            let mut acc = f[i];
            for &ju in nl.rows.get(i) {
                let j = ju as usize;
                let (eps, stretch, w, fij) = lane_terms.next().unwrap_or_else(|| {
                    pair_terms::<D, ALL_PERIODIC, ABSOLUTE>(x, dia, i, j, frame)
                });
                sums.add(eps, stretch, w, frame.growth(i, j, di, dia[j]));
                for k in 0..D {
                    acc[k] += fij[k];
                    f[j][k] -= fij[k];
                }
            }
            finish_particle::<D, ABSOLUTE, VIRIAL>(sys, i, acc, &mut f[i], frame, &mut ev);
        }
        sums.add_to(&mut ev, 1.0);
        partials.push(ev);
    }
    partials
}

/// Several threads, the same sums as [`scatter`] in the same order: pass 1 computes each
/// listed pair's force on its row particle into `reactions` (chunks of rows in parallel);
/// pass 2 gives each particle (its other images, already in `force`) − (its column's reactions
/// in row order) + (its row's pair forces in row order) + walls (chunks of particles in
/// parallel).
fn two_passes<
    const D: usize,
    const ALL_PERIODIC: bool,
    const ABSOLUTE: bool,
    const VIRIAL: bool,
>(
    sys: &System,
    nl: &NeighborList,
    force: &mut [f64],
    reactions: &mut [f64],
    frame: &Frame<D, ABSOLUTE>,
) -> Vec<Evaluation> {
    let (x, _) = sys.x.as_chunks::<D>();
    let dia = &sys.dia;
    let n = sys.n();
    let (pf, _) = reactions.as_chunks_mut::<D>();
    // Each chunk of rows owns the entries of those rows.
    let mut rows = Vec::with_capacity(n.div_ceil(CHUNK));
    let mut rest = pf;
    for first in (0..n).step_by(CHUNK) {
        let last = n.min(first + CHUNK);
        let (mine, tail) = rest.split_at_mut((nl.rows.start[last] - nl.rows.start[first]) as usize);
        rest = tail;
        rows.push((first..last, mine));
    }
    let pair_sums: Vec<PairSums<VIRIAL>> = rows
        .into_par_iter()
        // One scratch for the lanes per rayon job, not per chunk.
        .map_init(LaneScratch::default, |scratch, (range, own)| {
            let mut sums = PairSums::<VIRIAL>::default();
            let offset = nl.rows.start[range.start] as usize;
            let mut lane_terms = lane_terms::<D, ALL_PERIODIC, ABSOLUTE>(
                x,
                dia,
                &nl.rows,
                range.clone(),
                frame,
                scratch,
            );
            for i in range {
                let di = dia[i];
                for e in nl.rows.row(i) {
                    let j = nl.rows.entries[e] as usize;
                    let (eps, stretch, w, fij) = lane_terms.next().unwrap_or_else(|| {
                        pair_terms::<D, ALL_PERIODIC, ABSOLUTE>(x, dia, i, j, frame)
                    });
                    sums.add(eps, stretch, w, frame.growth(i, j, di, dia[j]));
                    own[e - offset] = fij;
                }
            }
            sums
        })
        .collect();
    let pf: &[[f64; D]] = reactions.as_chunks::<D>().0;
    let (f, _) = force.as_chunks_mut::<D>();
    f.par_chunks_mut(CHUNK)
        .zip(pair_sums)
        .enumerate()
        .map(|(ci, (fc, sums))| {
            let mut ev = Evaluation::default();
            for (local, fi) in fc.iter_mut().enumerate() {
                let i = ci * CHUNK + local;
                let mut acc = *fi;
                for &e in &nl.col_entry[nl.col_start[i] as usize..nl.col_start[i + 1] as usize] {
                    let r = pf[e as usize];
                    for k in 0..D {
                        acc[k] -= r[k];
                    }
                }
                for r in &pf[nl.rows.row(i)] {
                    for k in 0..D {
                        acc[k] += r[k];
                    }
                }
                finish_particle::<D, ABSOLUTE, VIRIAL>(sys, i, acc, fi, frame, &mut ev);
            }
            sums.add_to(&mut ev, 1.0);
            ev
        })
        .collect()
}

/// Adds particle `i`'s wall terms to its pair forces `acc`, stores the total in `fi` and adds
/// its scaled squared force to the residual.
#[inline(always)]
fn finish_particle<const D: usize, const ABSOLUTE: bool, const VIRIAL: bool>(
    sys: &System,
    i: usize,
    mut acc: [f64; D],
    fi: &mut [f64; D],
    frame: &Frame<D, ABSOLUTE>,
    ev: &mut Evaluation,
) {
    let di = sys.dia[i];
    let wi = frame.weight(di);
    if let Some((c, near_wall)) = frame.walls
        && near_wall[i]
    {
        let (x, _) = sys.x.as_chunks::<D>();
        let gi = frame.grows.map_or(1.0, |g| g[i]);
        wall_forces::<D, VIRIAL>(c, &x[i], di, wi, gi, &mut acc, ev);
    }
    *fi = acc;
    // |F·L|² with L = D_i or D̄: D̄² = D_i²/w_i.
    let unit2 = if ABSOLUTE { di * di / wi } else { di * di };
    ev.residual2 += acc.iter().map(|a| a * a).sum::<f64>() * unit2;
}

/// Where [`lane_terms`] keeps its terms.
#[cfg(target_arch = "x86_64")]
type LaneScratch<const D: usize> = Vec<lanes::FourPairs<D>>;
#[cfg(not(target_arch = "x86_64"))]
type LaneScratch<const D: usize> = ();

/// The terms of every listed pair of the rows `rows`, in list order, computed now four at a
/// time in AVX2 lanes where the processor has them (as [`pair_terms`] computes them, to the
/// bit); elsewhere none, and the caller computes each pair's terms as it adds them. Computing
/// a chunk of rows before adding any of it up lets the processor overlap many pairs' square
/// roots and divisions.
#[inline(always)]
fn lane_terms<'s, const D: usize, const ALL_PERIODIC: bool, const ABSOLUTE: bool>(
    x: &[[f64; D]],
    dia: &[f64],
    list: &Rows,
    rows: Range<usize>,
    frame: &Frame<D, ABSOLUTE>,
    scratch: &'s mut LaneScratch<D>,
) -> impl Iterator<Item = PairTerms<D>> + 's {
    #[cfg(target_arch = "x86_64")]
    {
        let written: &[lanes::FourPairs<D>] = match frame.lanes {
            // SAFETY: the token exists only where the processor has AVX2.
            Some(avx2) => unsafe {
                avx2.rows_terms::<D, ALL_PERIODIC, ABSOLUTE>(x, dia, list, rows, frame, scratch)
            },
            None => &[],
        };
        written.iter().flat_map(|four| (0..4).map(|l| four.lane(l)))
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        let _ = (x, dia, list, rows, frame, scratch);
        std::iter::empty()
    }
}

/// A pair's overlap ε, σ/r − 1, weight and force on the row particle.
type PairTerms<const D: usize> = (f64, f64, f64, [f64; D]);

/// The terms of the listed pair (`i`, `j`), one at a time.
#[inline(always)]
fn pair_terms<const D: usize, const ALL_PERIODIC: bool, const ABSOLUTE: bool>(
    x: &[[f64; D]],
    dia: &[f64],
    i: usize,
    j: usize,
    frame: &Frame<D, ABSOLUTE>,
) -> PairTerms<D> {
    let sigma = 0.5 * (dia[i] + dia[j]);
    let w = frame.weight(sigma);
    let (eps, stretch, fij) =
        pair_force::<D, ALL_PERIODIC>(&x[i], &x[j], sigma, w, i < j, &frame.geo);
    (eps, stretch, w, fij)
}

/// One pair term: the overlap ε (0 when apart), σ/r − 1 (0 when apart) and the force on `i`,
/// −w(ε/σ) r̂_ij, from the separation `xj − xi` (minimum image along periodic axes).
#[inline(always)]
fn pair_force<const D: usize, const ALL_PERIODIC: bool>(
    xi: &[f64; D],
    xj: &[f64; D],
    sigma: f64,
    w: f64,
    lower_first: bool,
    geo: &Geometry<D>,
) -> (f64, f64, [f64; D]) {
    let mut dx = [0.0; D];
    let mut r2 = 0.0;
    for k in 0..D {
        let mut t = xj[k] - xi[k];
        if ALL_PERIODIC || geo.periodic[k] {
            t = geo.nearest_image(t, k);
        }
        dx[k] = t;
        r2 += t * t;
    }
    if r2 == 0.0 {
        // Coincident centres: separate them along the first axis, lower index first.
        dx[0] = if lower_first { 1e-9 } else { -1e-9 } * sigma;
        r2 = dx[0] * dx[0];
    }
    // Branch-free (rows mix overlapping and separated neighbours unpredictably), with one
    // division: q = 1/(σ r), so r/σ = r² q and ε/(σ r) = ε q.
    let q = 1.0 / (sigma * r2.sqrt());
    let eps = (1.0 - r2 * q).max(0.0);
    let stretch = (sigma * sigma * q - 1.0).max(0.0);
    let c = w * eps * q;
    (eps, stretch, dx.map(|t| -c * t))
}

/// Wall terms of particle `i` (contact weight `weight`) added to `acc` and `ev`; `grows` is 1
/// when its diameter scales with κ, 0 when it is held.
#[inline(always)]
fn wall_forces<const D: usize, const VIRIAL: bool>(
    container: &Container,
    xi: &[f64; D],
    di: f64,
    weight: f64,
    grows: f64,
    acc: &mut [f64; D],
    ev: &mut Evaluation,
) {
    let ri = 0.5 * di;
    container.for_each_wall(xi, ri, |w| {
        let eps = 1.0 - w.distance / ri;
        ev.energy += 0.5 * weight * eps * eps;
        if VIRIAL {
            ev.virial += grows * weight * eps * (1.0 - eps);
        }
        ev.max_overlap = ev.max_overlap.max(eps);
        ev.weighted_overlap += grows * weight * eps;
        ev.stretch += 2.0 * (ri / w.distance.max(f64::MIN_POSITIVE) - 1.0);
        ev.contacts += 1.0;
        // ∂ε/∂x = n̂_out / R, so the wall pushes inwards with wε/R.
        let c = weight * eps / ri;
        for (a, &nk) in acc.iter_mut().zip(w.normal) {
            *a -= c * nk;
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use packbench_core::Packing;

    /// Evaluates `packing` under `scale`: (U, virial, force on particle 0 along x).
    fn evaluate_under(packing: &Packing, scale: OverlapScale) -> (f64, f64, f64) {
        let mut sys = System::new(packing, &[]).unwrap();
        sys.overlap_scale = scale;
        let mut nl = NeighborList::new();
        nl.update(&mut sys, (0.2, 0.2), 0.0, false);
        let mut force = vec![0.0; sys.x.len()];
        let ev = evaluate(&sys, &mut nl, &mut force, &mut Vec::new(), false, true);
        let first = sys
            .d0
            .iter()
            .position(|&v| v == packing.diameters[0])
            .unwrap();
        (ev.energy, ev.virial, force[first * sys.dim])
    }

    /// The force loop's baseline build (pairs one at a time) and its AVX2 build (pairs four at
    /// a time in lanes) on one 3D packing: (sums, forces) each.
    #[cfg(target_arch = "x86_64")]
    fn both_builds<const ALL_PERIODIC: bool, const ABSOLUTE: bool>(
        sys: &System,
        nl: &NeighborList,
    ) -> ((Evaluation, Vec<f64>), (Evaluation, Vec<f64>)) {
        let mut f_base = vec![0.0; sys.x.len()];
        let mut f_avx2 = vec![0.0; sys.x.len()];
        let base =
            run::<3, ALL_PERIODIC, ABSOLUTE, true>(sys, nl, &mut f_base, &mut [], false, None);
        let lanes = Avx2::detect();
        assert!(lanes.is_some());
        let avx2 = with_avx2(
            #[inline(always)]
            || run::<3, ALL_PERIODIC, ABSOLUTE, true>(sys, nl, &mut f_avx2, &mut [], false, lanes),
        );
        ((base, f_base), (avx2, f_avx2))
    }

    /// The AVX2 build of the force loop, with its pairs in lanes, gives the baseline's bytes:
    /// forces and every sum, on overlapping polydisperse spheres (two of them at one centre)
    /// between walls on one axis and in a periodic box, under both overlap scales.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn the_avx2_force_loop_gives_the_baseline_bytes() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        for walls in [true, false] {
            let scene = packbench_core::scene::Scene {
                n: 200,
                distribution: packbench_core::SizeDistribution::Flat {
                    d_min: 0.6,
                    d_max: 1.5,
                },
                container: Container::with_flags(&[6.0, 6.0, 6.0], &[false, walls, false]).unwrap(),
                phi: 0.6,
                seed: Some(3),
                placement: packbench_core::scene::Placement::Random,
            };
            let mut packing = packbench_core::init::initial_packing(&scene, 3).unwrap();
            let first: Vec<f64> = packing.positions[..3].to_vec();
            packing.positions[3..6].copy_from_slice(&first);
            for scale in [OverlapScale::Relative, OverlapScale::Absolute] {
                let mut sys = System::new(&packing, &[]).unwrap();
                sys.overlap_scale = scale;
                let mut nl = NeighborList::new();
                nl.update(&mut sys, (0.2, 0.2), 0.0, false);
                let ((base, f_base), (avx2, f_avx2)) = match (walls, scale) {
                    (true, OverlapScale::Relative) => both_builds::<false, false>(&sys, &nl),
                    (true, OverlapScale::Absolute) => both_builds::<false, true>(&sys, &nl),
                    (false, OverlapScale::Relative) => both_builds::<true, false>(&sys, &nl),
                    (false, OverlapScale::Absolute) => both_builds::<true, true>(&sys, &nl),
                };
                assert!(base.contacts > 50.0 && base.energy > 0.0, "{base:?}");
                assert!(base.max_overlap > 0.99, "the coincident pair: {base:?}");
                assert!(
                    f_base
                        .iter()
                        .zip(&f_avx2)
                        .all(|(a, b)| a.to_bits() == b.to_bits())
                );
                assert_eq!(format!("{base:?}"), format!("{avx2:?}"));
            }
        }
    }

    /// Absolute overlaps weigh a pair by (σ/D̄)²: a pair of spheres of diameter 3 in a packing
    /// whose mean diameter is 1.5 (the other pair has diameter 0) counts 4× its relative
    /// energy, virial and force, and equal spheres at the mean diameter count the same.
    #[test]
    fn absolute_overlaps_weigh_a_contact_by_its_length_over_the_mean_diameter_squared() {
        let c = Container::periodic_box(&[40.0, 40.0]).unwrap();
        // Two spheres of D = 3 overlapping by 0.3, two tiny ones far apart (mean D = 1.5).
        let big = Packing::new(
            vec![10.0, 10.0, 12.7, 10.0, 30.0, 30.0, 30.0, 20.0],
            vec![3.0, 3.0, 1e-9, 1e-9],
            c.clone(),
        )
        .unwrap();
        let (u_r, v_r, f_r) = evaluate_under(&big, OverlapScale::Relative);
        let (u_a, v_a, f_a) = evaluate_under(&big, OverlapScale::Absolute);
        let w = (3.0 / ((6.0 + 2e-9) / 4.0f64)).powi(2);
        assert!(u_r > 0.0 && f_r < 0.0, "U {u_r}, F {f_r}");
        for (r, a) in [(u_r, u_a), (v_r, v_a), (f_r, f_a)] {
            assert!((a - w * r).abs() <= 1e-12 * a.abs(), "{a} against {w}·{r}");
        }
        let equal = Packing::new(vec![10.0, 10.0, 10.8, 10.0], vec![1.0, 1.0], c).unwrap();
        assert_eq!(
            evaluate_under(&equal, OverlapScale::Relative),
            evaluate_under(&equal, OverlapScale::Absolute)
        );
    }
}
