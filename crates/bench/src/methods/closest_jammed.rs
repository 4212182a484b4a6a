//! `closest-jammed`, `closest-jammed-qp` and `calippso`: exact jamming
//! (packbench-exact-jamming). They need an overlap-free start; an overlapping one (a random
//! initial packing) is first shrunk until it is free of overlaps. A packing at contact (an LS or
//! MLS packing at high pressure, a jammed packing read back from text) overlaps by rounding
//! only; it is passed on as it is, since a shrink would open every contact it has.

use std::borrow::Cow;

use packbench_core::Packing;
use packbench_core::analysis::contact_network;
use packbench_exact_jamming::{
    calippso, closest_jammed, closest_jammed_qp, shrink_to_overlap_free,
};

use super::flags::{FlagValue, MethodFlag};
use super::method_error;
use super::packer::Packer;
use super::stop_progress::{StopMeasure, number};
use crate::error::BenchError;

/// Both integrators end jammed with N_dof non-rattler bonds.
const BONDS_OVER_DOF: [StopMeasure; 1] = [StopMeasure::Ratio {
    numerator: "non_rattler_bonds",
    denominator: "n_dof",
}];

/// Relative gap left between the closest pair after shrinking an overlapping start.
const SHRINK_MARGIN: f64 = 1e-3;

/// Relative overlaps up to this are rounding at contact and are left to the methods, which
/// tolerate overlaps up to their own `overlap_tol` / `tol_overlap` (1e-9 and 1e-8 by default).
/// Before, any overlap above zero led to the 1e-3 shrink: an MLS packing at pressure 1e12
/// (overlaps of 1e-15) lost its contacts, and closest-jammed had to form all of them again
/// (3036 steps at N = 1000, docs/notes/closest-jammed-large-n.md).
const ROUNDING_OVERLAP: f64 = 1e-12;

fn overlap_free<'a>(method: &str, start: &'a Packing) -> Result<Cow<'a, Packing>, BenchError> {
    if contact_network(start, 0.0).max_overlap > ROUNDING_OVERLAP {
        shrink_to_overlap_free(start, SHRINK_MARGIN)
            .map(Cow::Owned)
            .map_err(|e| method_error(method, e))
    } else {
        Ok(Cow::Borrowed(start))
    }
}

/// Minimum-norm closest-jammed integrator (Baranau & Tallarek 2014 App. C).
pub static CLOSEST_JAMMED: Packer<closest_jammed::Params> = Packer {
    name: "closest-jammed",
    summary: "radii grow as t·D with bonds held in contact and minimum-norm velocities (faer), until jammed",
    knob: "contact_tol",
    jammed_terminations: &["jammed"],
    defaults: closest_jammed::Params::default,
    validate: |p| p.validate().map_err(|e| method_error("closest-jammed", e)),
    flags: &[
        MethodFlag::new(
            "qp",
            "",
            FlagValue::RunsVariant("closest-jammed-qp"),
            "Use the QP form (bonds may open), one clarabel QP per step; same as --method closest-jammed-qp.",
        ),
        MethodFlag::new(
            "open-tensile-bonds",
            "open_tensile_bonds",
            FlagValue::Switch,
            "The QP form's steepest descent solved as an active set on the sparse factor: every bond whose force turns tensile opens (tens of times fewer steps than --qp).",
        ),
        MethodFlag::new(
            "factor-updates",
            "factor_updates",
            FlagValue::Switch,
            "Keep the preconditioning factor of A Aᵀ current by CHOLMOD row updates as bonds join and leave, instead of a new numeric factorisation at each release.",
        ),
        MethodFlag::new(
            "refactor-iterations",
            "refactor_iterations",
            FlagValue::Count,
            "Conjugate-gradient iterations of one solve above which a new numeric factorisation is made.",
        ),
    ],
    run: |s, p, o| {
        closest_jammed::run(&*overlap_free("closest-jammed", s)?, p, o)
            .map_err(|e| method_error("closest-jammed", e))
    },
    resume: None,
    budget_key: Some("max_steps"),
    seed_key: None,
    snapshot_key: Some("save_interval"),
    frame_interval: |_| 1,
    stop_measures: |_| BONDS_OVER_DOF.to_vec(),
    step_unit: "bond steps",
    notes: "",
};

/// Its QP form, where bonds may open.
pub static CLOSEST_JAMMED_QP: Packer<closest_jammed_qp::Params> = Packer {
    name: "closest-jammed-qp",
    summary: "the closest-jammed growth with min ‖y‖² under inequality bonds (clarabel QP): bonds may open",
    knob: "contact_tol",
    jammed_terminations: &["jammed"],
    defaults: closest_jammed_qp::Params::default,
    validate: |p| {
        p.validate()
            .map_err(|e| method_error("closest-jammed-qp", e))
    },
    flags: &[],
    run: |s, p, o| {
        closest_jammed_qp::run(&*overlap_free("closest-jammed-qp", s)?, p, o)
            .map_err(|e| method_error("closest-jammed-qp", e))
    },
    resume: None,
    budget_key: Some("max_steps"),
    seed_key: None,
    snapshot_key: Some("save_interval"),
    frame_interval: |_| 1,
    stop_measures: |_| BONDS_OVER_DOF.to_vec(),
    step_unit: "bond steps",
    notes: "",
};

/// CALiPPSO's iterated LP (Artiaco et al. 2022; CALiPPSO.jl).
pub static CALIPPSO: Packer<calippso::Params> = Packer {
    name: "calippso",
    summary: "CALiPPSO: iterated LP maximising the inflation Γ over displacements (own interior point, METIS-ordered normal equations), forces from duals",
    knob: "tol_gamma",
    jammed_terminations: &["converged"],
    defaults: calippso::Params::default,
    validate: |p| p.validate().map_err(|e| method_error("calippso", e)),
    flags: &[
        MethodFlag::number("tol-gamma", "tol_gamma", "Tolerance on √Γ − 1."),
        MethodFlag::number(
            "tol-s",
            "tol_s",
            "Tolerance on the largest non-rattler displacement.",
        ),
        MethodFlag::number(
            "tol-overlap",
            "tol_overlap",
            "Largest overlap tolerated in the overlap checks.",
        ),
        MethodFlag::new(
            "bound-schedule",
            "bound_schedule",
            FlagValue::Text,
            "seed (CALiPPSO.jl's displacement bound by √Γ − 1) or trust-region (doubled while the LP's linear model agrees with the exact distances and the bound binds, halved when it does not).",
        ),
        MethodFlag::new(
            "parallel-factorisation",
            "parallel_factorisation",
            FlagValue::Switch,
            "Factorise each LP's normal equations on every thread (RAYON_NUM_THREADS) from 10⁴ free coordinates on (3D N ≳ 3300). The last digits then depend on the thread count.",
        ),
    ],
    run: |s, p, o| {
        calippso::run(&*overlap_free("calippso", s)?, p, o).map_err(|e| method_error("calippso", e))
    },
    resume: None,
    budget_key: Some("max_iters"),
    seed_key: None,
    snapshot_key: Some("save_interval"),
    frame_interval: |_| 1,
    // √Γ − 1 (the report's value) falls geometrically to `tol_gamma`.
    stop_measures: |params| {
        vec![StopMeasure::LogTo {
            quantity: None,
            start: None,
            target: number(params, "tol_gamma"),
        }]
    },
    step_unit: "LPs",
    notes: "",
};
