//! The closest-jammed integrator's options and their defaults.

use crate::error::JammingError;
use serde::{Deserialize, Serialize};

/// Options of the closest-jammed integrator. Baranau & Tallarek 2014 fixes no constants; the defaults make
/// contacts exact to about 1e-14 relative.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(default)]
pub struct Params {
    /// Largest number of integration steps (one per new contact or growth cap).
    pub max_steps: u64,
    /// Largest relative growth `Δt/t` of one straight step between contacts (accuracy knob).
    pub max_growth_step: f64,
    /// Largest displacement of any particle in one straight step, in mean diameters (keeps the
    /// drift of bonds off contact, which the projection removes, small).
    pub max_displacement_step: f64,
    /// Candidate skin, in mean diameters: pairs closer than this are checked for new contacts.
    pub skin: f64,
    /// Pairs of the starting packing with relative gap `r/σ − 1` at most this start as bonds.
    pub contact_tol: f64,
    /// A new bond is dependent on the basis when its row `a` is within `dependency_tol·‖a‖` of
    /// the basis rows' span.
    pub dependency_tol: f64,
    /// Forces below `−force_tol·max f` count as tensile (the bond is released).
    pub force_tol: f64,
    /// Projection stops when every bond's relative gap is below this.
    pub projection_tol: f64,
    /// Release a bond as soon as its Lagrange multiplier `λ_k` of the minimum-norm solve
    /// (`y = Aᵀλ`, `λ = (A Aᵀ)⁻¹ D`) turns tensile, below `−force_tol·max |λ|`: the growth is
    /// then the steepest descent of Baranau & Tallarek 2014 App. B (the QP form's path, solved as an active
    /// set). When false (the default, App. C literally), bonds are released only when the
    /// bonded system has no solution: at a dependent new bond with tensile forces, or at a
    /// fold of the bond manifold (the bonds cannot all stay in contact as `t` grows, the
    /// velocities diverge, and `λ/|λ|` tends to the fold's forces).
    pub open_tensile_bonds: bool,
    /// Which tensile bond is released at a dependent new bond (App. C's equations leave it
    /// open).
    pub release_rule: ReleaseRule,
    /// Bond counts up to this use the dense SVD pseudoinverse; more use sparse Cholesky of A Aᵀ.
    pub dense_max_bonds: usize,
    /// Largest relative overlap tolerated in the starting packing.
    pub overlap_tol: f64,
    /// Pass a snapshot to the observer every this many steps (0: never).
    pub save_interval: u64,
    /// Keep the sparse factor of `A Aᵀ` that preconditions the solves current by CHOLMOD row
    /// updates as bonds join and leave (`cholmod_rowadd`/`cholmod_rowdel`), instead of
    /// bordering it and making a new numeric factorisation for each release; a new one is made
    /// when conjugate gradients need more than `refactor_iterations` iterations (the particles
    /// moved too far since) or a new bond has no slot.
    pub factor_updates: bool,
    /// Conjugate-gradient iterations of one solve above which the next factorisation is exact
    /// (and becomes the new preconditioner).
    pub refactor_iterations: usize,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            max_steps: 10_000_000,
            max_growth_step: 1e-2,
            max_displacement_step: 5e-3,
            skin: 0.3,
            contact_tol: 1e-9,
            dependency_tol: 1e-6,
            force_tol: 1e-9,
            projection_tol: 1e-14,
            open_tensile_bonds: false,
            release_rule: ReleaseRule::default(),
            dense_max_bonds: 48,
            overlap_tol: 1e-9,
            save_interval: 0,
            factor_updates: false,
            refactor_iterations: 3,
        }
    }
}

/// The bond released when a new bond makes the bonded system unsolvable with tensile forces.
/// Any bond with a tensile force may open while the others stay in contact (`fᵀ A y' = 0` fixes
/// its opening rate `res/(−f_k) > 0`); the rules differ in the path they take.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum ReleaseRule {
    /// The bond with the most tensile force: it opens the slowest, and in the long exchange
    /// phase of N = 300–1000 packings it came back about 15 steps later in 9 releases out of
    /// 10. At N = 1000 it had not jammed after 2·10⁵ steps
    /// (docs/notes/closest-jammed-release-rule.md).
    MostTensile,
    /// The bond whose release leaves the smallest velocities (the default): Baranau & Tallarek 2014 eqn 2
    /// carried over to the choice (`min_norm_release`). It jams in fewer steps than the most
    /// tensile rule (1.1–1.9 times at N = 100, more than 4 times at N = 1000), and is the only
    /// rule that has jammed N = 1000 starts (same note).
    #[default]
    MinimumNorm,
}

impl Params {
    /// Checks every parameter; the error names the one out of range.
    pub fn validate(&self) -> Result<(), JammingError> {
        let positive = [
            ("max_growth_step", self.max_growth_step),
            ("max_displacement_step", self.max_displacement_step),
            ("skin", self.skin),
            ("dependency_tol", self.dependency_tol),
            ("projection_tol", self.projection_tol),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(JammingError::Parameter(format!(
                    "{name} = {v} must be a positive number"
                )));
            }
        }
        for (name, v) in [
            ("contact_tol", self.contact_tol),
            ("force_tol", self.force_tol),
            ("overlap_tol", self.overlap_tol),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(JammingError::Parameter(format!(
                    "{name} = {v} must be a non-negative number"
                )));
            }
        }
        if self.factor_updates && !cfg!(feature = "cholmod") {
            return Err(JammingError::Parameter(
                "factor_updates needs SuiteSparse's CHOLMOD: build packbench with \
                 `--features cholmod` (Debian: apt-get install libsuitesparse-dev)"
                    .into(),
            ));
        }
        Ok(())
    }
}
