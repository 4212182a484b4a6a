//! RCPGenerator 1.0's expansion–contraction loop (Desmond & Weeks 2009) — the `threshold` protocol.
//!
//! The energy and force thresholds are RCPGenerator 1.0's totals for `threshold_n` particles, applied
//! per particle (`Driver::scaled_energy`, `Driver::scaled_force`).
//!
//! Every step evaluates forces, decides the growth direction, takes one minimizer step and
//! rescales the diameters:
//! - inflate by Δφ when U < U_threshold or the largest overlap is below the overlap threshold
//!   (RCPGenerator 1.0: 10·√U_threshold at Δφ₀; here scaled by Δφ/Δφ₀ so fine steps are judged by the
//!   energy alone);
//! - otherwise, past the warm-up, deflate by Δφ/2 when the force residual is below F_tol
//!   (overlapped and force-balanced: jammed above φ_J);
//! - otherwise hold.
//!
//! Δφ shrinks by `step_shrink` at every reversal and grows by `step_grow` after `grow_after`
//! decisions in the same direction (never above Δφ₀). The run converges when a jammed,
//! force-balanced state is reached with Δφ below its tolerance, after polishing its forces.
//! The first step jumps to the floor `phi_min` (RCPGenerator 1.0: φ = max(φ + Δφ, φ_min)); later
//! deflations may go below it, so a floor above what few particles can reach does no harm.
//! With `target_phi`, φ is capped at the target and the
//! run stops there once the largest overlap is below `target_overlap_tol`.

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde_json::{Map, Value};

use super::Driver;
use crate::error::AdamError;
use crate::overlap_energy::Evaluation;
use crate::params::Params;

/// Runs the threshold protocol from `start`.
pub(crate) fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdamError> {
    let mut dr = Driver::new(start, params, observer, 0)?;
    let target = params.target_phi;
    let mut phi = starting_phi(&mut dr, params)?;
    let mut size = StepSize::new(params, dr.sys.n());
    let (mut inflations, mut deflations) = (0u64, 0u64);
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
        let at_target = target.is_some_and(|t| phi >= t * (1.0 - 1e-12));
        if at_target && ev.max_overlap <= params.target_overlap_tol {
            termination = "target_reached";
            use_best = false;
            break;
        }
        let low_energy = dr.scaled_energy(&ev) < params.energy_threshold;
        if low_energy {
            dr.remember_if_densest();
        }
        let low =
            low_energy || ev.max_overlap < params.overlap_threshold * size.delta / size.delta0;
        let balanced = dr.scaled_force(ev.residual2) < params.force_tol;
        let dir: i8 = if low {
            if at_target { 0 } else { 1 }
        } else if step > params.warmup_steps && balanced {
            if size.delta < params.delta_phi_tol {
                // Jammed with a fine step: φ_J is bracketed within Δφ < tolerance. Polish the
                // forces and stop (RCPGenerator 1.0: Δφ below tolerance with forces balanced). If the
                // polish relaxed the energy below threshold the state was jammed by less than
                // the threshold resolves; inflating again by Δφ only creeps (with 80 %
                // rattlers, RCPGenerator 1.0's power law crept 3e-4 in 2·10⁵ steps), so it stops too.
                // A polish cut by the step budget still ends here (`polished` says so).
                last = dr.polish(&mut step, ev)?;
                termination = if dr.stop_requested(step) {
                    "interrupted"
                } else if target.is_some() {
                    "jammed_below_target"
                } else {
                    "converged"
                };
                use_best = false;
                break;
            }
            -1
        } else {
            0
        };
        size.record(dir, params);
        let nc = dr.n_coords();
        dr.relaxer.step(
            step,
            &mut dr.sys.x[..nc],
            &dr.force[..nc],
            &dr.unit0[..nc],
            dr.sys.kappa,
        );
        if dir != 0 {
            let dphi = if dir > 0 {
                inflations += 1;
                size.delta
            } else {
                deflations += 1;
                -0.5 * size.delta
            };
            phi += dphi;
            if let Some(t) = target {
                phi = phi.min(t);
            }
            dr.set_phi(phi)?;
        }
        dr.report(step, &ev, &[("delta_phi", size.delta)]);
    }
    let mut extra = Map::new();
    extra.insert("protocol".into(), "threshold".into());
    extra.insert("delta_phi".into(), size.delta.into());
    extra.insert("inflations".into(), inflations.into());
    extra.insert("deflations".into(), deflations.into());
    extra.insert("reversals".into(), size.reversals.into());
    record_final_state(&dr, &last, &mut extra);
    let values = [("delta_phi", size.delta)];
    Ok(dr.finish(step, &last, &values, termination, use_best, extra))
}

/// The final energy and force residual, and whether the polish brought the force below
/// `final_force_tol`.
fn record_final_state(dr: &Driver<'_>, last: &Evaluation, extra: &mut Map<String, Value>) {
    extra.insert("final_energy".into(), last.energy.into());
    let final_force = dr.scaled_force(last.residual2);
    extra.insert(
        "polished".into(),
        (final_force < dr.params.final_force_tol).into(),
    );
    extra.insert("final_force_residual".into(), final_force.into());
}

/// Sets φ to the floor `phi_min` (capped at the target) when the start is below it, and
/// returns φ; refuses a target below the starting packing fraction.
fn starting_phi(dr: &mut Driver<'_>, params: &Params) -> Result<f64, AdamError> {
    let target = params.target_phi;
    let floor = params
        .phi_floor(dr.sys.dim)
        .min(target.unwrap_or(f64::INFINITY));
    let phi = dr.sys.phi();
    if phi < floor {
        dr.set_phi(floor)?;
        return Ok(floor);
    }
    if let Some(t) = target
        && phi > t
    {
        return Err(AdamError::Parameter(format!(
            "target_phi = {t} lies below the starting packing fraction {phi:.6}"
        )));
    }
    Ok(phi)
}

/// The step Δφ: shrunk at each reversal, grown after `grow_after` decisions the same way.
struct StepSize {
    delta: f64,
    delta0: f64,
    last_dir: i8,
    streak: u32,
    reversals: u64,
}

impl StepSize {
    fn new(params: &Params, n: usize) -> Self {
        // Large systems relax more slowly than Δφ₀ inflates them: with RCPGenerator 1.0's Δφ₀,
        // 3D N = 10⁴ overshot φ_J and held an overcompressed state that never balanced
        // (docs/notes/adam-protocol-large-n.md); Δφ₀·n_ref/N converged there. N ≤ n_ref keeps
        // the seed's step.
        let delta0 = (params.delta_phi0 * (params.threshold_n / n as f64).min(1.0))
            .max(4.0 * params.delta_phi_tol)
            .min(params.delta_phi0);
        StepSize {
            delta: delta0,
            delta0,
            last_dir: 0,
            streak: 0,
            reversals: 0,
        }
    }

    /// Takes a decision `dir` (+1 inflate, −1 deflate, 0 hold).
    fn record(&mut self, dir: i8, params: &Params) {
        if dir == 0 {
            return;
        }
        if self.last_dir != 0 && dir != self.last_dir {
            // Oscillation around φ_J: refine the step.
            self.delta *= params.step_shrink;
            self.streak = 0;
            self.reversals += 1;
        } else {
            self.streak += 1;
            if self.streak >= params.grow_after {
                self.delta = (self.delta * params.step_grow).min(self.delta0);
                self.streak = 0;
            }
        }
        self.last_dir = dir;
    }
}
