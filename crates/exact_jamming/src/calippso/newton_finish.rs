//! The Newton finish: once the LPs' contact network has settled, the jammed packing it
//! belongs to is the root of the network's own equations, `|r_ij| = √Γ σ_ij` on its n_dof
//! contacts with the positions and the inflation as unknowns. An LP step on a fixed network
//! is the linearisation of those equations (Artiaco et al. 2022, the theory page of
//! CALiPPSO.jl's docs) bounded by `s_bound`, so the LPs approach the root linearly; Newton's
//! method on the same sparse system ([`project`] with the growth factor free: METIS-ordered
//! Cholesky of the bonds' Gram matrix) reaches it quadratically.
//!
//! The root is a jammed packing when the network's self-stress is compressive on every
//! contact and no other pair overlaps or touches (Baranau & Tallarek 2014 App. C, Farkas; the
//! core's analysis at contact tolerance 1e-9 decides). Otherwise one batch exchange follows:
//! every tensile contact leaves and every overlapping pair joins at once, with as many of the
//! weakest contacts out as keep the network square, and Newton runs again on it. A batch that
//! fails (more tensile contacts than overlaps, the projection diverges, or the packing is
//! still not jammed after [`MAX_BATCHES`]) puts the configuration back, and the LPs go on.

use packbench_core::analysis::{AnalysisOptions, analyze, not_jammed_because};

use super::network::{CLOSE_DENSE_MAX_BONDS, CLOSE_TOL, Network};
use crate::contacts::{Key, Link};
use crate::growth::Growth;
use crate::min_norm::Solver;
use crate::projection::project;

/// Newton solves on exchanged networks before the finish gives up.
pub(super) const MAX_BATCHES: usize = 8;

/// What a successful finish did.
pub(super) struct Finished {
    /// The network's largest relative gap after the last Newton solve.
    pub(super) gap: f64,
    /// Batch exchanges after the first solve.
    pub(super) batches: usize,
    /// Contacts released and admitted by them.
    pub(super) released: usize,
    pub(super) admitted: usize,
    /// Net force on the worst non-rattler over the mean contact force of the self-stress.
    pub(super) imbalance: f64,
}

/// Why a finish failed, counted in `extra.newton_finish`.
#[derive(Clone, Copy)]
pub(super) enum Failed {
    /// A Newton solve diverged or a factorisation failed.
    Diverged,
    /// More contacts tensile than pairs overlapping: the network would be floppy.
    Unbalanced,
    /// Still not jammed after [`MAX_BATCHES`] batches.
    Batches,
    /// Compressive and overlap-free, but the core's analysis counts another network (a pair
    /// within its contact tolerance outside the network, or a rattler's overlap).
    Disagrees,
}

/// Tries the Newton finish from `net` at `g`; on failure `g` is left as it was.
pub(super) fn newton_finish(g: &mut Growth, net: &Network) -> Result<Finished, Failed> {
    let before = g.snapshot();
    let result = finish(g, net);
    if result.is_err() {
        g.restore(&before);
    }
    result
}

fn finish(g: &mut Growth, net: &Network) -> Result<Finished, Failed> {
    // A network with more contacts than n_dof keeps its strongest, as the final closure does;
    // the strongest goes last, as the dependent row ([`solve_network`]).
    let mut contacts = net.contacts.clone();
    contacts.sort_by(|a, b| a.1.total_cmp(&b.1));
    contacts.drain(..contacts.len() - net.n_dof);
    let mut bonds: Vec<Key> = contacts.iter().map(|c| c.0).collect();
    let mut forces: Vec<f64> = contacts.iter().map(|c| c.1).collect();
    let solver = Solver::new(CLOSE_DENSE_MAX_BONDS);
    let (mut released, mut admitted) = (0, 0);
    for batch in 0..=MAX_BATCHES {
        let gap = solve_network(g, &bonds, &forces, &solver)?;
        g.refresh();
        let links = g.links(&bonds);
        forces = self_stress(g, &bonds, &links, &solver)?;
        let tensile: Vec<usize> = (0..bonds.len()).filter(|&k| forces[k] <= 0.0).collect();
        let overlapping = overlapping_pairs(g, &bonds);
        if tensile.is_empty() && overlapping.is_empty() {
            if !jammed_by_analysis(g) {
                return Err(Failed::Disagrees);
            }
            return Ok(Finished {
                gap,
                batches: batch,
                released,
                admitted,
                imbalance: imbalance(g, &links, &forces),
            });
        }
        if batch == MAX_BATCHES {
            break;
        }
        if tensile.len() > overlapping.len() {
            return Err(Failed::Unbalanced);
        }
        // One batch: every tensile contact out, every overlapping pair in, and as many of the
        // weakest compressive contacts out as keep the network square; the next Newton solve
        // takes its inflation from the new network's self-stress here.
        let mut out = tensile.clone();
        let mut weakest: Vec<usize> = (0..bonds.len() - 1).filter(|&k| forces[k] > 0.0).collect();
        weakest.sort_by(|&a, &b| forces[a].total_cmp(&forces[b]));
        out.extend(weakest.into_iter().take(overlapping.len() - tensile.len()));
        if out.len() != overlapping.len() {
            return Err(Failed::Unbalanced);
        }
        for (&k, key) in out.iter().zip(&overlapping) {
            bonds[k] = *key;
        }
        released += out.len();
        admitted += overlapping.len();
        let links = g.links(&bonds);
        forces = self_stress(g, &bonds, &links, &solver)?;
    }
    Err(Failed::Batches)
}

/// Newton's method on `|r_ij| = t σ_ij` over `bonds` with the positions and `t` free. The last
/// bond is the dependent one, whose row the others span; `forces`, in the order of `bonds`,
/// fix how the inflation takes up the gaps ([`project`]). Returns the largest relative gap
/// left.
fn solve_network(
    g: &mut Growth,
    bonds: &[Key],
    forces: &[f64],
    solver: &Solver,
) -> Result<f64, Failed> {
    let (dependent, basis) = bonds.split_last().ok_or(Failed::Diverged)?;
    project(g, basis, None, Some((dependent, forces)), CLOSE_TOL, solver)
        .map_err(|_| Failed::Diverged)
}

/// The self-stress of a square network at the current configuration: `f` with `Aᵀf = 0` over
/// the coordinates, normalised so that `fᵀσ > 0` (the forces resist the inflation), in the
/// order of `bonds`. The last bond's row is written in the others', which must span it.
fn self_stress(
    g: &Growth,
    bonds: &[Key],
    links: &[Link],
    solver: &Solver,
) -> Result<Vec<f64>, Failed> {
    let (n, d) = (g.n, g.d);
    let (last, rest) = links.split_last().ok_or(Failed::Diverged)?;
    let mn = solver
        .factor(&bonds[..rest.len()], rest, g, [].iter())
        .map_err(|_| Failed::Diverged)?;
    let mut row = vec![0.0; n * d];
    last.add_transposed(1.0, &mut row, d);
    let c = mn.row_combination(rest, &row, d);
    // a_last = Σ c_k a_k, so f = (c, −1) up to sign; a row the others do not span has none.
    for (l, &ck) in rest.iter().zip(&c) {
        l.add_transposed(-ck, &mut row, d);
    }
    // A residual above the tolerance, or NaN, means the others do not span the last row.
    let residual = row.iter().map(|v| v * v).sum::<f64>().sqrt();
    if residual.is_nan() || residual > SPAN_TOL {
        return Err(Failed::Diverged);
    }
    let mut f: Vec<f64> = c.into_iter().chain([-1.0]).collect();
    let load: f64 = f.iter().zip(links).map(|(f, l)| f * l.size).sum();
    if !load.is_finite() || load == 0.0 {
        return Err(Failed::Diverged);
    }
    let sign = load.signum();
    f.iter_mut().for_each(|v| *v *= sign);
    Ok(f)
}

/// Largest distance of the dependent row (a unit normal's coordinates) from the others' span
/// for a self-stress to exist.
const SPAN_TOL: f64 = 1e-8;

/// Candidate pairs other than `bonds` that overlap (relative gap below zero).
fn overlapping_pairs(g: &Growth, bonds: &[Key]) -> Vec<Key> {
    let held: std::collections::HashSet<&Key> = bonds.iter().collect();
    g.candidates
        .keys
        .iter()
        .filter(|k| !held.contains(k) && g.link(k).rel_gap(g.t) < 0.0)
        .copied()
        .collect()
}

/// The core's verdict at its default contact tolerance (1e-9): isostatic, no overlap.
fn jammed_by_analysis(g: &Growth) -> bool {
    let options = AnalysisOptions {
        force_balance: false,
        ..AnalysisOptions::default()
    };
    analyze(&g.packing(), &options).is_ok_and(|m| not_jammed_because(&m).is_none())
}

/// The largest net force on a particle over the mean contact force.
fn imbalance(g: &Growth, links: &[Link], forces: &[f64]) -> f64 {
    let (n, d) = (g.n, g.d);
    let mut net = vec![0.0; n * d];
    for (l, &f) in links.iter().zip(forces) {
        l.add_transposed(f, &mut net, d);
    }
    let worst = net
        .chunks_exact(d)
        .map(|v| v.iter().map(|a| a * a).sum::<f64>().sqrt())
        .fold(0.0, f64::max);
    worst / (forces.iter().sum::<f64>() / forces.len() as f64)
}

/// When the finish is tried, and what its attempts came to (`extra.newton_finish`).
pub(super) struct FinishSchedule {
    /// √Γ − 1 below which the finish is tried (0: never).
    below: f64,
    /// LPs below `below` whose network had fewer contacts than n_dof: still floppy, so no
    /// solve was tried.
    floppy: u64,
    /// Attempts and their failures by reason.
    attempts: u64,
    failed: [u64; 4],
}

impl FinishSchedule {
    pub(super) fn new(below: f64) -> Self {
        FinishSchedule {
            below,
            floppy: 0,
            attempts: 0,
            failed: [0; 4],
        }
    }

    /// Tries the finish after an LP at √Γ − 1 = `excess` below the threshold whose network is
    /// square or more. Every such LP gets its try: the contact network keeps changing until
    /// the last few LPs (tens of contacts per LP at N = 300, hundreds at N = 10⁴), and the LP
    /// from which the finish succeeds cannot be told in advance, not even from the count of
    /// contacts changed. Each try costs two factorisations of the network's Gram matrix; over
    /// a whole run the tries cost more than the LPs they save, which is why the finish is off
    /// by default (`Params::newton_finish_below`).
    pub(super) fn try_after(
        &mut self,
        g: &mut Growth,
        net: &Network,
        excess: f64,
    ) -> Option<Finished> {
        if excess.is_nan() || excess >= self.below {
            return None;
        }
        if !net.can_close() {
            self.floppy += 1;
            return None;
        }
        self.attempts += 1;
        newton_finish(g, net)
            .inspect_err(|why| self.failed[*why as usize] += 1)
            .ok()
    }

    /// The attempts as an `extra` entry, with `done` when one succeeded.
    pub(super) fn to_json(&self, done: Option<&Finished>) -> serde_json::Value {
        let [diverged, unbalanced, batches, disagrees] = self.failed;
        serde_json::json!({
            "attempts": self.attempts,
            "skipped_floppy": self.floppy,
            "failed_diverged": diverged,
            "failed_unbalanced": unbalanced,
            "failed_batches": batches,
            "failed_analysis": disagrees,
            "batches": done.map(|d| d.batches),
            "released": done.map(|d| d.released),
            "admitted": done.map(|d| d.admitted),
        })
    }
}
