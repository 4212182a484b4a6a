//! The `pressure` protocol: the diameter scale is itself an optimisation variable.
//!
//! With u = ln(κ/κ_r) as one more coordinate (κ_r: the scale at the start of the rung) the
//! minimizer works on E(x, u) = U(x, κ) − μ·(κ/κ_r)·ΣD₀/D̄₀, the term −μ·κ·ΣD₀ of RCPGenerator's
//! maintained engine with D₀ the rung's diameters in units of their mean. Its u-force is
//! F_u = −Σ w ε(1 − ε) + μ·N·e^u, so at balance the mean contact overlap is about μ/d. Above
//! a diameter ratio of `ABSOLUTE_OVERLAP_SIZE_RATIO` the energy weighs each contact by
//! w = (σ/D̄)² (absolute overlaps, as RCPGenerator's engine): under relative overlaps RCPGenerator 1.0's
//! power law 1–15 crept at every rung without converging. A rung ends
//! when the system is balanced relative to μ — the RMS net force per particle below
//! `rung_force_rel`·μ and |F_u| below `rung_force_rel`·μ·N (`final_rung_force_rel` for the last
//! rung) — or when φ changed by less than `rung_phi_tol`·μ/μ_min (relative; `rung_phi_tol` by
//! default 1e-5, 3e-5 for absolute overlaps; the last rung at `rung_phi_tol` itself) over
//! `rung_window` steps; μ
//! is then multiplied by `mu_factor`, and the run converges once μ falls below `mu_min`,
//! returning the last rung's balanced, slightly compressed state (mean overlap about μ/d).

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde_json::Map;

use super::Driver;
use crate::ABSOLUTE_OVERLAP_SIZE_RATIO;
use crate::error::AdamError;
use crate::overlap_energy::Evaluation;
use crate::params::Params;
use crate::system::OverlapScale;

/// Runs the pressure protocol from `start`.
pub(crate) fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdamError> {
    let mut dr = Driver::new(start, params, observer, 1)?;
    // The κ-force below is the virial.
    dr.virial = true;
    if start.max_diameter() > ABSOLUTE_OVERLAP_SIZE_RATIO * start.min_diameter() {
        dr.sys.overlap_scale = OverlapScale::Absolute;
    }
    let n = dr.sys.n() as f64;
    let d = dr.sys.dim as f64;
    let nc = dr.n_coords();
    let floor = params.phi_floor(dr.sys.dim);
    if dr.sys.phi() < floor {
        dr.set_phi(floor)?;
    }
    // Mass of u: the stiffness along u is about the contact count d·N, so ℓ_u = 1/√(dN).
    let unit_u = 1.0 / (d * n).sqrt();
    let stall_tolerance = params.stall_tolerance(dr.sys.overlap_scale);
    let mut mu = params.mu_start;
    let mut kappa_ref = dr.sys.kappa;
    let mut rungs = 0u64;
    let mut window_phi = dr.sys.phi();
    let mut window_start = 0u64;
    let mut termination = "max_steps";
    let mut use_best = true;
    let mut last = dr.evaluate(0)?;
    let mut step = 0;
    while step < params.max_steps {
        step += 1;
        if dr.stop_requested(step) {
            termination = "interrupted";
            break;
        }
        let ev = dr.evaluate(step)?;
        last = ev;
        let scale = (dr.sys.kappa / kappa_ref).max(f64::MIN_POSITIVE);
        // The pressure acts on the growing diameters only (all of them unless some are held).
        let f_u = -ev.virial + mu * dr.sys.growing().0 * scale;
        dr.force[nc] = f_u;
        dr.unit0[nc] = unit_u / dr.sys.kappa;
        let last_rung = mu * params.mu_factor < params.mu_min;
        let balanced = is_balanced(&ev, f_u, mu, n, last_rung, params);
        if dr.scaled_energy(&ev) < params.energy_threshold {
            dr.remember_if_densest();
        }
        let phi = dr.sys.phi();
        // A rung's over-compression grows with μ (mean overlap μ/d), so an earlier rung stalls
        // at a tolerance μ/μ_min times the last rung's: φ creeping by less is below its accuracy.
        let rung_tolerance = if last_rung {
            stall_tolerance
        } else {
            stall_tolerance * mu / params.mu_min
        };
        let stalled = step - window_start >= params.rung_window
            && (phi - window_phi).abs() < rung_tolerance * phi;
        if step - window_start >= params.rung_window {
            window_start = step;
            window_phi = phi;
        }
        if balanced || stalled {
            rungs += 1;
            mu *= params.mu_factor;
            if mu < params.mu_min {
                termination = "converged";
                use_best = false;
                break;
            }
            kappa_ref = dr.sys.kappa;
            dr.sys.x[nc] = 0.0;
            window_start = step;
            window_phi = phi;
            continue;
        }
        let kappa = dr.sys.kappa;
        dr.relaxer
            .step(step, &mut dr.sys.x, &dr.force, &dr.unit0, kappa);
        let u = dr.sys.x[nc];
        if !u.is_finite() {
            return Err(AdamError::NonFinite { step });
        }
        dr.sys.set_kappa(kappa_ref * u.exp());
        dr.sys.check_own_image()?;
        dr.report(step, &ev, &[("mu", mu)]);
    }
    let mut extra = Map::new();
    extra.insert("protocol".into(), "pressure".into());
    extra.insert("mu".into(), mu.into());
    extra.insert("rungs".into(), rungs.into());
    // Left open (`null`) in the parameters by default: the value this run used.
    extra.insert("rung_phi_tol".into(), stall_tolerance.into());
    extra.insert("final_energy".into(), last.energy.into());
    Ok(dr.finish(step, &last, &[("mu", mu)], termination, use_best, extra))
}

/// Balance relative to the pressure scale: the RMS net force per particle (in units of the
/// overlap ε) and the u-force `f_u` per particle, against μ, the rung's contact scale.
fn is_balanced(ev: &Evaluation, f_u: f64, mu: f64, n: f64, last_rung: bool, p: &Params) -> bool {
    let rel_tol = if last_rung {
        p.final_rung_force_rel
    } else {
        p.rung_force_rel
    };
    (ev.residual2 / n).sqrt() < rel_tol * mu && f_u.abs() < rel_tol * mu * n
}
