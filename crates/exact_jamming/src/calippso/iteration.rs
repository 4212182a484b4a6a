//! One CALiPPSO iteration (Artiaco et al. 2022) and the LP that may follow the last: the next LP's
//! cut-off and displacement bound (the schedule of the module doc, or the trust region), the
//! LP, the update `r ← r + s`, `σ ← √Γ σ` (Γ capped by curved walls), the duals' contact
//! network, and what the progress line and the trace show of it; after convergence, the
//! fine-tuning LP without a bound whose network is kept when it is better balanced.
//!
//! Fails with [`JammingError::Solver`] when an LP's normal equations cannot be factorised; a
//! scheduled overlap check that finds pairs overlapping beyond `tol_overlap` shrinks the
//! diameters to clear them ([`Iteration::clear_overlaps`]).

use std::sync::atomic::AtomicBool;

use serde_json::{Map, Value, json};

use super::curved_walls::curved_wall_gamma;
use super::held_coordinates::held_coordinates;
use super::lp::{
    LAZY_GAP, LpScope, LpStep, WARM_MAX_CHANGED, WARM_MIN_EXCESS, WARM_MIN_MOVE, solve_lp,
};
use super::network::{Network, network};
use super::newton_finish::Finished;
use super::params::{BoundSchedule, Params};
use super::trust_region::{model_agreement, trust_update};
use super::worst_overlap;
use crate::error::JammingError;
use crate::growth::Growth;

/// Interior-point iterations the fine-tuning LP may take ([`Iteration::final_network`]).
const FINE_TUNING_MAX_ITER: u32 = 60;

/// The state of a run between LPs.
pub(super) struct Iteration<'p> {
    pub(super) g: Growth,
    params: &'p Params,
    /// √Γ of the last LP.
    pub(super) sqrt_gamma: f64,
    /// Coordinates held at zero in the next LP ([`held_coordinates`]).
    held: Vec<usize>,
    /// The last LP and its contact network.
    pub(super) last: Option<(LpStep, Network)>,
    /// Contacts the last LP made or broke, as a fraction of its contacts.
    changed_fraction: f64,
    /// Largest |s| of a non-rattler in the last LP, in mean diameters.
    pub(super) max_s_active: f64,
    /// The trust region's bound in mean radii (none before the first LP).
    trust_bound: Option<f64>,
    /// Whether the bound carried a dual in the last LP.
    bound_was_binding: bool,
    /// LPs solved (the fine-tuning LP not counted).
    pub(super) lps: u64,
    pub(super) counts: LpCounts,
}

/// What the LPs cost, reported in `extra` under these names.
#[derive(Default)]
pub(super) struct LpCounts {
    /// Interior-point iterations over all solves (`lp_iterations`).
    iterations: u64,
    /// One per LP plus one per round of lazy rows (`lp_solves`).
    solves: u64,
    /// Solves that stopped short of `lp_tol` (`lp_unconverged`).
    unconverged: u64,
    /// Solves handed to clarabel (`lp_clarabel`).
    clarabel: u64,
    /// LPs whose Γ a curved wall capped (`wall_limited_lps`).
    wall_limited: u64,
    /// Changes between the bound carrying a dual and not (`bound_switches`).
    bound_switches: u64,
    /// Overlap checks that found pairs overlapping beyond `tol_overlap` and shrank the
    /// diameters to clear them (`overlap_repairs`), and the largest overlap cleared
    /// (`largest_repaired_overlap`).
    overlap_repairs: u64,
    largest_repaired: f64,
}

impl LpCounts {
    fn add(&mut self, step: &LpStep) {
        self.iterations += u64::from(step.iterations);
        self.solves += u64::from(step.solves);
        self.unconverged += u64::from(step.unconverged);
        self.clarabel += u64::from(step.by_clarabel);
    }

    /// The counts as `extra` entries.
    pub(super) fn insert_into(&self, extra: &mut Map<String, Value>) {
        extra.insert("lp_iterations".into(), json!(self.iterations));
        extra.insert("lp_solves".into(), json!(self.solves));
        extra.insert("lp_unconverged".into(), json!(self.unconverged));
        extra.insert("lp_clarabel".into(), json!(self.clarabel));
        extra.insert("wall_limited_lps".into(), json!(self.wall_limited));
        extra.insert("bound_switches".into(), json!(self.bound_switches));
        extra.insert("overlap_repairs".into(), json!(self.overlap_repairs));
        extra.insert(
            "largest_repaired_overlap".into(),
            json!(self.largest_repaired),
        );
    }
}

/// What one LP did, beyond the iteration's state: the trace's columns.
pub(super) struct LpRecord {
    pub(super) contacts: usize,
    pub(super) n_dof: usize,
    /// Contacts of the dual network made or lost since the previous LP.
    pub(super) changed: usize,
    pub(super) rattlers: usize,
    /// The displacement bound, in mean radii.
    pub(super) bound_over_r: f64,
    /// Largest non-rattler |s| over the bound.
    pub(super) max_s_over_bound: f64,
    /// What limited the LP: 1 non-overlap, 2 the bound, 3 both, 0 neither.
    pub(super) binds: f64,
    /// How well the LP's linear model predicted the exact gaps ([`model_agreement`]).
    pub(super) agreement: f64,
    pub(super) ipm_iterations: u32,
}

impl<'p> Iteration<'p> {
    pub(super) fn new(g: Growth, params: &'p Params) -> Self {
        let held = held_coordinates(&g, 0, None);
        Iteration {
            g,
            params,
            sqrt_gamma: params.sqrt_gamma0,
            held,
            last: None,
            changed_fraction: 1.0,
            max_s_active: f64::INFINITY,
            trust_bound: None,
            bound_was_binding: false,
            lps: 0,
            counts: LpCounts::default(),
        }
    }

    /// The mean radius at the current growth factor.
    fn r_mean(&self) -> f64 {
        0.5 * self.g.t * self.g.diameters.iter().sum::<f64>() / self.g.n as f64
    }

    /// The next LP's rows and bound (module doc of [`super`]): the cut-off gap and the seed's
    /// bound by √Γ − 1, or the trust region's bound, and the cap on Γ after the first LP.
    fn scope(&self, r_mean: f64) -> LpScope {
        let p = self.params;
        let sqrt_d = (self.g.d as f64).sqrt();
        let excess = self.sqrt_gamma - 1.0;
        let base_gap = (p.ell0 - 2.0) * r_mean;
        let (gap, seed_sb) = if excess >= 5e-4 {
            (base_gap, base_gap / (4.0 * sqrt_d))
        } else if excess >= 1e-5 {
            let gap = base_gap.min(r_mean);
            (gap, (0.1 * r_mean).min(gap / (4.0 * sqrt_d)))
        } else {
            let gap = base_gap.min(0.5 * r_mean);
            (gap, (p.s_bound_final * r_mean).min(gap / (4.0 * sqrt_d)))
        };
        // After the first LP, Γ is capped at (1 + 4(√Γ_prev − 1))², which rarely binds (Γ
        // falls from LP to LP) and lets the far part of the cut-off shell drop out.
        let sb = match (p.bound_schedule, self.trust_bound) {
            (BoundSchedule::TrustRegion, Some(b)) => (b * r_mean).min(gap / (4.0 * sqrt_d)),
            _ => seed_sb,
        };
        LpScope {
            cutoff_gap: gap,
            s_bound: Some(sb),
            excess_cap: (self.lps > 0).then(|| (4.0 * excess).max(1e-5)),
            working_gap: LAZY_GAP,
            clarabel_fallback: true,
        }
    }

    /// Solves the next LP and moves the packing by it. `Ok(None)` when `stop` ended the solve
    /// (nothing changed).
    pub(super) fn lp(
        &mut self,
        stop: Option<&'static AtomicBool>,
    ) -> Result<Option<LpRecord>, JammingError> {
        let p = self.params;
        let (n, d) = (self.g.n, self.g.d);
        let r_mean = self.r_mean();
        let scope = self.scope(r_mean);
        let sb = scope.s_bound.expect("a bounded LP");
        // Warm starts pay where the active set barely changes (near jamming); far from it the
        // old duals are no guide. At the very end a warm start's displacements carry noise of
        // ~1e-8 D (N = 4000: 300 LPs with 1e-8 < max |s| < 5e-8 after √Γ − 1 had reached
        // 1e-13), which `tol_s` = 1e-9 does not accept, so the last LPs start cold.
        let excess = self.sqrt_gamma - 1.0;
        let moving = excess >= WARM_MIN_EXCESS || self.max_s_active >= WARM_MIN_MOVE;
        let warm = self
            .last
            .as_ref()
            .map(|l| &l.0)
            .filter(|_| p.warm_start && self.changed_fraction <= WARM_MAX_CHANGED && moving);
        let Some(step) = solve_lp(&self.g, &scope, &self.held, p, stop, warm)? else {
            return Ok(None);
        };
        self.counts.add(&step);
        // Update r ← r + s, σ ← √Γ σ, with Γ no larger than the curved walls allow.
        let g = &mut self.g;
        g.x.iter_mut().zip(&step.s).for_each(|(x, s)| *x += s);
        let agreement = model_agreement(g, &step);
        let gamma_walls = curved_wall_gamma(g);
        if gamma_walls < 1.0 + step.g {
            self.counts.wall_limited += 1;
        }
        let gamma = (1.0 + step.g).min(gamma_walls);
        self.sqrt_gamma = gamma.max(0.0).sqrt();
        g.t *= self.sqrt_gamma;
        self.lps += 1;
        let net = network(g, &step, p.zero_force);
        // Contacts made or lost since the previous LP: near jamming the network settles and
        // this falls to zero; while it stays high the packing is still rearranging.
        let changed = self.last.as_ref().map_or(net.keys.len(), |(_, prev)| {
            prev.keys.symmetric_difference(&net.keys).count()
        });
        self.changed_fraction = changed as f64 / net.keys.len().max(1) as f64;
        let d_mean = 2.0 * r_mean;
        self.max_s_active = (0..n)
            .filter(|&i| !net.rattler[i])
            .flat_map(|i| step.s[i * d..(i + 1) * d].iter().map(|v| v.abs()))
            .fold(0.0, f64::max)
            / d_mean;
        // What limited this LP: the bound binds when its rows carry a dual, non-overlap when
        // the pair and wall rows do (their duals sum to one unless the cap on Γ binds).
        let bound_binds = step.bound_dual > p.zero_force;
        let overlap_binds = step.duals.iter().sum::<f64>() > 0.5;
        let binds = match (bound_binds, overlap_binds) {
            (false, true) => 1.0,
            (true, false) => 2.0,
            (true, true) => 3.0,
            (false, false) => 0.0,
        };
        if self.lps > 1 && bound_binds != self.bound_was_binding {
            self.counts.bound_switches += 1;
        }
        self.bound_was_binding = bound_binds;
        let s_over_bound = self.max_s_active * d_mean / sb;
        self.trust_bound = Some(trust_update(sb / r_mean, agreement, s_over_bound));
        let anchor = (0..n)
            .max_by_key(|&i| (net.degree[i], std::cmp::Reverse(i)))
            .unwrap_or(0);
        self.held = held_coordinates(&self.g, anchor, Some(&net.rattler));
        if self.lps <= p.initial_overlaps_check
            || (p.interval_overlaps_check > 0 && self.lps.is_multiple_of(p.interval_overlaps_check))
        {
            self.clear_overlaps();
        }
        let record = LpRecord {
            contacts: net.contacts.len(),
            n_dof: net.n_dof,
            changed,
            rattlers: net.rattler.iter().filter(|&&r| r).count(),
            bound_over_r: sb / r_mean,
            max_s_over_bound: s_over_bound,
            binds,
            agreement,
            ipm_iterations: step.iterations,
        };
        self.last = Some((step, net));
        Ok(Some(record))
    }

    /// Shrinks every diameter by the largest relative overlap when that exceeds `tol_overlap`.
    /// An LP solved to its tolerance, not exactly, may leave a pair overlapping (no run has
    /// been seen to; the N = 4000 overlap that motivated this came from the final closure, see
    /// [`super::run`]). Every pair's and wall's relative overlap `1 − r/σ` is at most that
    /// largest one, so shrinking σ by it clears them all, for ≈ 3× that fraction of φ, which
    /// the next LPs win back; the repair is counted in `extra`.
    pub(super) fn clear_overlaps(&mut self) {
        let (overlap, _, _) = worst_overlap(&self.g);
        if overlap > self.params.tol_overlap {
            self.g.t *= 1.0 - overlap;
            self.counts.overlap_repairs += 1;
            self.counts.largest_repaired = self.counts.largest_repaired.max(overlap);
        }
    }

    /// √Γ − 1 and the non-rattlers' largest displacement below their tolerances.
    pub(super) fn converged(&self) -> bool {
        self.sqrt_gamma - 1.0 < self.params.tol_gamma && self.max_s_active < self.params.tol_s
    }

    /// What `final_network` reports, for a run the Newton finish ended: the force balance of
    /// its self-stress, and its square network of n_dof contacts among the last LP's
    /// non-rattlers.
    pub(super) fn finished_network(&self, done: &Finished, extra: &mut Map<String, Value>) {
        let Some((_, net)) = &self.last else {
            return;
        };
        extra.insert("force_imbalance_lp".into(), json!(net.imbalance));
        extra.insert("force_imbalance".into(), json!(done.imbalance));
        extra.insert("fine_tuned".into(), json!(false));
        extra.insert("contacts".into(), json!(net.n_dof));
        extra.insert("n_dof".into(), json!(net.n_dof));
        extra.insert(
            "rattlers".into(),
            json!(net.rattler.iter().filter(|&&r| r).count()),
        );
    }

    /// The final network's force balance into `extra`: the last LP's, or, when it is above
    /// `tol_mechanical_equilibrium`, the fine-tuning LP's (no bound) when that is better
    /// balanced; with the network's contacts, n_dof and rattlers. A stop request skips the
    /// fine-tuning LP, and so does its failure, whose reason goes to `fine_tuning_skipped`.
    pub(super) fn final_network(
        &mut self,
        stop: Option<&'static AtomicBool>,
        extra: &mut Map<String, Value>,
    ) {
        let p = self.params;
        let Some((_, net)) = &self.last else {
            return;
        };
        let mut imbalance = net.imbalance;
        extra.insert("force_imbalance_lp".into(), json!(imbalance));
        let mut net_final = None;
        if imbalance > p.tol_mechanical_equilibrium {
            let scope = LpScope {
                cutoff_gap: 0.5 * self.r_mean(),
                s_bound: None,
                excess_cap: None,
                working_gap: LAZY_GAP,
                clarabel_fallback: false,
            };
            // The packing is final: this LP only offers a better balanced network, so it gets
            // no clarabel and few iterations. On an `mls7` start at N = 4000 its interior point
            // ran 263 iterations (65 s, against 81 s for all 38 LPs) before the factor failed,
            // and clarabel then took 80 s more; where it succeeds it takes 18–23.
            let tuning = Params {
                lp_max_iter: p.lp_max_iter.min(FINE_TUNING_MAX_ITER),
                ..p.clone()
            };
            match solve_lp(&self.g, &scope, &self.held, &tuning, stop, None) {
                Ok(Some(tuned)) => {
                    self.counts.add(&tuned);
                    if tuned.converged {
                        // Its duals come from an unbounded LP solved to the same `lp_tol` and
                        // are not always better balanced (N = 4000, seed 82 run again: 8.9e-7
                        // against the last LP's 3.0e-8), so the better network is kept.
                        let tn = network(&self.g, &tuned, p.zero_force);
                        if tn.imbalance < imbalance {
                            imbalance = tn.imbalance;
                            net_final = Some(tn);
                        }
                    } else {
                        extra.insert(
                            "fine_tuning_skipped".into(),
                            json!(format!("no convergence in {} iterations", tuned.iterations)),
                        );
                    }
                }
                Ok(None) => {}
                Err(e) => {
                    extra.insert("fine_tuning_skipped".into(), json!(e.to_string()));
                }
            }
        }
        let fine_tuned = net_final.is_some();
        let net = net_final.as_ref().unwrap_or(net);
        extra.insert("force_imbalance".into(), json!(imbalance));
        extra.insert("fine_tuned".into(), json!(fine_tuned));
        extra.insert("contacts".into(), json!(net.contacts.len()));
        extra.insert("n_dof".into(), json!(net.n_dof));
        extra.insert(
            "rattlers".into(),
            json!(net.rattler.iter().filter(|&&r| r).count()),
        );
    }
}
