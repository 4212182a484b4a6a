//! The soft harmonic overlap energy and its forces (seed 000, `GetForcesND_3`'s role):
//!
//! U = Σ_pairs ½ ε_ij² + Σ_walls ½ ε_iw²,  ε_ij = 1 − r_ij/σ_ij (σ_ij = (D_i + D_j)/2),
//! ε_iw = 1 − h_iw/R_i (h: signed distance of the centre to the wall, R_i = D_i/2),
//!
//! counting only overlapping pairs (ε > 0). Periodic axes use the minimum image; walled axes
//! never do. With a full neighbour list (parallel runs) forces F_i = −∂U/∂x_i are gathered per
//! particle over its row, in fixed chunks of particles whose partial sums are added in chunk
//! order, so the result is bit-identical for any number of threads; with a half list
//! (single-threaded runs) each pair is visited once and its force scattered to both ends.

use packbench_core::Container;
use rayon::prelude::*;

use crate::neighbor_list::NeighborList;
use crate::system::System;

/// Particles per chunk of the force loop (fixed, so sums do not depend on threads).
const CHUNK: usize = 256;

/// What one force evaluation measures besides the forces.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Evaluation {
    /// U = Σ ½ ε² over overlapping pairs and walls.
    pub energy: f64,
    /// Largest ε over pairs and walls (0 without overlaps).
    pub max_overlap: f64,
    /// Squared norm of the force with each particle's coordinates measured in its own
    /// diameter: Σ_i |F_i D_i|².
    pub residual2: f64,
    /// Σ ε(1 − ε) over contacts = −∂U/∂ln κ, the "virial" that drives the pressure protocol.
    pub virial: f64,
}

impl Evaluation {
    fn merge(mut self, o: Evaluation) -> Evaluation {
        self.energy += o.energy;
        self.max_overlap = self.max_overlap.max(o.max_overlap);
        self.residual2 += o.residual2;
        self.virial += o.virial;
        self
    }
}

/// Running pair sums of one force loop: Σε², Σε(1 − ε) and max ε.
#[derive(Default)]
struct PairSums {
    eps2: f64,
    virial: f64,
    max_eps: f64,
}

impl PairSums {
    #[inline(always)]
    fn add(&mut self, eps: f64) {
        self.eps2 += eps * eps;
        self.virial += eps * (1.0 - eps);
        self.max_eps = self.max_eps.max(eps);
    }

    /// Adds the pair terms to `ev`, each listed entry weighted by `weight` (½ when every pair
    /// is listed from both ends): U gets ½ε², the virial ε(1 − ε).
    fn add_to(self, ev: &mut Evaluation, weight: f64) {
        ev.max_overlap = ev.max_overlap.max(self.max_eps);
        ev.energy += 0.5 * weight * self.eps2;
        ev.virial += weight * self.virial;
    }
}

/// Box geometry as fixed-size arrays for the monomorphised kernel.
struct Geometry<const D: usize> {
    length: [f64; D],
    half: [f64; D],
    periodic: [bool; D],
}

/// The overlap energy of a fixed packing, evaluated on demand with the packer's own force
/// kernel and neighbour list: for benchmarks of the force loop (pair interactions per second)
/// and for inspecting a packing's residual overlaps.
pub struct OverlapForces {
    sys: System,
    nl: NeighborList,
    force: Vec<f64>,
    parallel: bool,
}

impl OverlapForces {
    /// Builds the neighbour list of `packing` (skin: `neighbor_skin` mean diameters); with
    /// `parallel` the forces are gathered over full rows with rayon.
    pub fn new(
        packing: &packbench_core::Packing,
        neighbor_skin: f64,
        parallel: bool,
    ) -> Result<Self, crate::AdamError> {
        let mut sys = System::new(packing)?;
        let mut nl = NeighborList::new(parallel);
        nl.update(&mut sys, neighbor_skin);
        let force = vec![0.0; sys.x.len()];
        Ok(OverlapForces {
            sys,
            nl,
            force,
            parallel,
        })
    }

    /// Listed neighbour pairs (each once), the pair interactions one evaluation computes.
    pub fn listed_pairs(&self) -> usize {
        self.nl.pairs()
    }

    /// Evaluates the forces; returns the energy U and the largest overlap ε.
    pub fn evaluate(&mut self) -> (f64, f64) {
        let ev = evaluate(&self.sys, &self.nl, &mut self.force, self.parallel);
        (ev.energy, ev.max_overlap)
    }
}

/// Fills `force` (N·d, sorted order) with F = −∂U/∂x and returns the energy and friends.
pub(crate) fn evaluate(
    sys: &System,
    nl: &NeighborList,
    force: &mut [f64],
    parallel: bool,
) -> Evaluation {
    let all_periodic = sys.container.is_fully_periodic();
    packbench_core::dispatch_dim!(
        sys.dim,
        D => match all_periodic {
            true => run::<D, true>(sys, nl, force, parallel),
            false => run::<D, false>(sys, nl, force, parallel),
        },
        _ => unreachable!("dimension {} is refused by Container::validate", sys.dim),
    )
}

fn run<const D: usize, const ALL_PERIODIC: bool>(
    sys: &System,
    nl: &NeighborList,
    force: &mut [f64],
    parallel: bool,
) -> Evaluation {
    let c = &sys.container;
    let geo = Geometry::<D> {
        length: std::array::from_fn(|k| c.lengths[k]),
        half: std::array::from_fn(|k| 0.5 * c.lengths[k]),
        periodic: std::array::from_fn(|k| ALL_PERIODIC || c.periodic[k]),
    };
    let walls = (!ALL_PERIODIC && c.has_walls()).then_some(c);
    if !nl.full {
        return scatter::<D, ALL_PERIODIC>(force, sys, nl, &geo, walls);
    }
    let chunk_eval = |(ci, f): (usize, &mut [f64])| {
        chunk::<D, ALL_PERIODIC>(ci * CHUNK, f, sys, nl, &geo, walls)
    };
    let partials: Vec<Evaluation> = if parallel {
        force
            .par_chunks_mut(CHUNK * D)
            .enumerate()
            .map(chunk_eval)
            .collect()
    } else {
        force
            .chunks_mut(CHUNK * D)
            .enumerate()
            .map(chunk_eval)
            .collect()
    };
    partials
        .into_iter()
        .fold(Evaluation::default(), Evaluation::merge)
}

/// One pair term: the overlap ε (0 when apart) and the force on `i`, −(ε/σ) r̂_ij, from the
/// separation `xj − xi` (minimum image along periodic axes).
#[inline(always)]
fn pair_force<const D: usize, const ALL_PERIODIC: bool>(
    xi: &[f64; D],
    xj: &[f64; D],
    sigma: f64,
    lower_first: bool,
    geo: &Geometry<D>,
) -> (f64, [f64; D]) {
    let mut dx = [0.0; D];
    let mut r2 = 0.0;
    for k in 0..D {
        let mut t = xj[k] - xi[k];
        if ALL_PERIODIC || geo.periodic[k] {
            // Positions are wrapped at each rebuild and move less than the skin between
            // rebuilds, so one correction gives the minimum image.
            if t > geo.half[k] {
                t -= geo.length[k];
            } else if t < -geo.half[k] {
                t += geo.length[k];
            }
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
    let c = eps * q;
    (eps, dx.map(|t| -c * t))
}

/// Wall terms of particle `i` added to `acc` and `ev`.
#[inline(always)]
fn wall_forces<const D: usize>(
    container: &Container,
    xi: &[f64; D],
    di: f64,
    acc: &mut [f64; D],
    ev: &mut Evaluation,
) {
    let ri = 0.5 * di;
    container.for_each_wall(xi, ri, |w| {
        let eps = 1.0 - w.distance / ri;
        ev.energy += 0.5 * eps * eps;
        ev.virial += eps * (1.0 - eps);
        ev.max_overlap = ev.max_overlap.max(eps);
        // ∂ε/∂x = n̂_out / R, so the wall pushes inwards with ε/R.
        let c = eps / ri;
        for (a, &nk) in acc.iter_mut().zip(w.normal) {
            *a -= c * nk;
        }
    });
}

/// Gather over full rows: forces on the particles `first..first + f.len()/D`.
#[inline(always)]
fn chunk<const D: usize, const ALL_PERIODIC: bool>(
    first: usize,
    f: &mut [f64],
    sys: &System,
    nl: &NeighborList,
    geo: &Geometry<D>,
    walls: Option<&Container>,
) -> Evaluation {
    let (x, _) = sys.x.as_chunks::<D>();
    let dia = &sys.dia;
    let mut ev = Evaluation::default();
    let mut sums = PairSums::default();
    for (local, fi) in f.chunks_exact_mut(D).enumerate() {
        let i = first + local;
        let di = dia[i];
        let mut acc = [0.0; D];
        for &ju in &nl.nbr[nl.start[i] as usize..nl.start[i + 1] as usize] {
            let j = ju as usize;
            let sigma = 0.5 * (di + dia[j]);
            let (eps, fij) = pair_force::<D, ALL_PERIODIC>(&x[i], &x[j], sigma, i < j, geo);
            sums.add(eps);
            for k in 0..D {
                acc[k] += fij[k];
            }
        }
        if let Some(c) = walls {
            wall_forces(c, &x[i], di, &mut acc, &mut ev);
        }
        fi.copy_from_slice(&acc);
        ev.residual2 += acc.iter().map(|a| a * a).sum::<f64>() * di * di;
    }
    // Full rows list each pair from both ends.
    sums.add_to(&mut ev, 0.5);
    ev
}

/// Scatter over half rows (each pair once), single-threaded: half the pair work of [`chunk`].
fn scatter<const D: usize, const ALL_PERIODIC: bool>(
    force: &mut [f64],
    sys: &System,
    nl: &NeighborList,
    geo: &Geometry<D>,
    walls: Option<&Container>,
) -> Evaluation {
    let (x, _) = sys.x.as_chunks::<D>();
    let dia = &sys.dia;
    let (f, _) = force.as_chunks_mut::<D>();
    f.fill([0.0; D]);
    let mut ev = Evaluation::default();
    let mut sums = PairSums::default();
    for i in 0..f.len() {
        let di = dia[i];
        let mut acc = f[i];
        for &ju in &nl.nbr[nl.start[i] as usize..nl.start[i + 1] as usize] {
            let j = ju as usize;
            let sigma = 0.5 * (di + dia[j]);
            let (eps, fij) = pair_force::<D, ALL_PERIODIC>(&x[i], &x[j], sigma, i < j, geo);
            sums.add(eps);
            for k in 0..D {
                acc[k] += fij[k];
                f[j][k] -= fij[k];
            }
        }
        if let Some(c) = walls {
            wall_forces(c, &x[i], di, &mut acc, &mut ev);
        }
        f[i] = acc;
    }
    for (fi, &di) in f.iter().zip(dia) {
        ev.residual2 += fi.iter().map(|a| a * a).sum::<f64>() * di * di;
    }
    sums.add_to(&mut ev, 1.0);
    ev
}
