//! CALiPPSO's options and their defaults.

use serde::{Deserialize, Serialize};

use crate::error::JammingError;

/// CALiPPSO's options, with its defaults (CALiPPSO.jl and).
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct Params {
    /// Convergence when `√Γ − 1 < tol_gamma` (`--tol-gamma`).
    pub tol_gamma: f64,
    /// … and the largest non-rattler displacement `max |s_iμ|` is below `tol_s` mean
    /// diameters (`--tol-s`).
    pub tol_s: f64,
    /// Largest number of LPs (`--max-iters`).
    pub max_iters: u64,
    /// Largest relative overlap `1 − r/σ` tolerated by the overlap checks (`--tol-overlap`).
    pub tol_overlap: f64,
    /// Duals (contact forces, normalised to sum to one) above this are contacts.
    pub zero_force: f64,
    /// Largest net force on a non-rattler, relative to the mean contact force, before the
    /// fine-tuning LP is run.
    pub tol_mechanical_equilibrium: f64,
    /// Initial cut-off distance ℓ0, in mean radii (pairs closer than ℓ0 − 2R in gap are listed).
    pub ell0: f64,
    /// √Γ assumed before the first LP (selects the first schedule phase).
    pub sqrt_gamma0: f64,
    /// `s_bound` near convergence (√Γ − 1 < 1e-5), in mean radii.
    pub s_bound_final: f64,
    /// Tolerance (gap and feasibility) of each LP's interior-point solve.
    pub lp_tol: f64,
    /// Interior-point iterations per LP solve at most.
    pub lp_max_iter: u32,
    /// The overlap check runs every LP for the first `initial_overlaps_check` LPs and every
    /// `interval_overlaps_check` LPs after, and always at the end.
    pub initial_overlaps_check: u64,
    /// See `initial_overlaps_check`.
    pub interval_overlaps_check: u64,
    /// Pass a snapshot to the observer every this many LPs (0: never).
    pub save_interval: u64,
    /// How `s_bound` is chosen from LP to LP (`--bound-schedule`).
    pub bound_schedule: BoundSchedule,
    /// Start each LP's interior point from the previous LP's duals of the same rows (about half
    /// the iterations per LP near jamming); a warm solve that stops short of `lp_tol` is redone
    /// from the cold start.
    pub warm_start: bool,
    /// After convergence, close the final network's contacts exactly ([`close_network`]).
    pub close_network: bool,
    /// Factorise the LPs' normal equations on every thread of the run's rayon pool from 10⁴
    /// free coordinates on (3D N ≳ 3300). Off by default: the last digits then depend on the
    /// thread count, and packbench gives the same bytes at any thread count unless asked.
    pub parallel_factorisation: bool,
    /// Try the Newton finish ([`super::newton_finish`]) after each LP with √Γ − 1 below
    /// `newton_finish_below` (`--set newton_finish_below=…`; 0 turns it off): the network's
    /// equations solved by Newton's method, its contacts exchanged in batches, the LPs going
    /// on when that fails. Not run without `close_network`. Off (0) by default: the LPs'
    /// network keeps changing until one or two LPs before convergence, so the finish saves
    /// those and no more (N = 4000, 3D ADAM start: 148 LPs against 150, the same packing) and
    /// its failed tries cost more CPU than that.
    pub newton_finish_below: f64,
}

/// How the displacement bound `s_bound` is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundSchedule {
    /// CALiPPSO.jl's schedule by √Γ − 1 (see the module): `gap/(4√d)`, then 0.1 R below 5e-4,
    /// then `s_bound_final` R below 1e-5.
    #[default]
    Seed,
    /// A trust region: the first LP takes the seed's bound; after each LP the bound doubles
    /// when the linear model agreed with the exact non-overlap (ratio > 0.75) and the bound was
    /// binding (max |s| of non-rattlers ≥ 0.99 s_bound), and halves when the agreement is poor
    /// (< 0.25); it never exceeds the cut-off's `gap/(4√d)`.
    TrustRegion,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            tol_gamma: 1e-12,
            tol_s: 1e-9,
            max_iters: 1000,
            tol_overlap: 1e-8,
            zero_force: 1e-10,
            tol_mechanical_equilibrium: 1e-12,
            ell0: 4.0,
            sqrt_gamma0: 1.01,
            s_bound_final: 0.01,
            lp_tol: 1e-12,
            lp_max_iter: 400,
            initial_overlaps_check: 10,
            interval_overlaps_check: 10,
            save_interval: 0,
            bound_schedule: BoundSchedule::Seed,
            warm_start: true,
            close_network: true,
            parallel_factorisation: false,
            newton_finish_below: 0.0,
        }
    }
}

impl Params {
    /// Checks every parameter; the error names the one out of range.
    pub fn validate(&self) -> Result<(), JammingError> {
        for (name, v) in [
            ("tol_gamma", self.tol_gamma),
            ("tol_s", self.tol_s),
            ("tol_overlap", self.tol_overlap),
            ("zero_force", self.zero_force),
            (
                "tol_mechanical_equilibrium",
                self.tol_mechanical_equilibrium,
            ),
            ("s_bound_final", self.s_bound_final),
            ("lp_tol", self.lp_tol),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(JammingError::Parameter(format!(
                    "{name} = {v} must be a positive number"
                )));
            }
        }
        if !(self.newton_finish_below.is_finite() && self.newton_finish_below >= 0.0) {
            return Err(JammingError::Parameter(format!(
                "newton_finish_below = {} must be a non-negative number",
                self.newton_finish_below
            )));
        }
        if !(self.ell0.is_finite() && self.ell0 > 2.0) {
            return Err(JammingError::Parameter(format!(
                "ell0 = {} must exceed 2 radii (the contact distance)",
                self.ell0
            )));
        }
        if !(self.sqrt_gamma0.is_finite() && self.sqrt_gamma0 >= 1.0) {
            return Err(JammingError::Parameter(format!(
                "sqrt_gamma0 = {} must be at least 1",
                self.sqrt_gamma0
            )));
        }
        if self.max_iters == 0 {
            return Err(JammingError::Parameter(
                "max_iters must be at least 1".into(),
            ));
        }
        Ok(())
    }
}
