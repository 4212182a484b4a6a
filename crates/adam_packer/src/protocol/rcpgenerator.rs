//! The `rcpgenerator` protocol: RCPGenerator 1.0's schedule, so that `adam` jams where the code
//! it implements jams (docs/notes/adam-fidelity.md).
//!
//! Positions and the diameter scale κ are one ADAM problem throughout, with the step α and the
//! pressure μ in lengths L of the container's longest side (RCPGenerator's unit box):
//!
//! - energy ½ Σ δ² over overlapping pairs (δ = σ − r, absolute) and the κ-force
//!   −Σ σ δ + μ·ΣD (lengths in L); κ is measured from the diameters at φ_ref (0.33 in 3D), where
//!   the run starts, so its ADAM step α means what it means in RCPGenerator;
//! - **first rung**: μ·(1 + (b − 1)e^(−step/τ)) for `first_rung_steps` steps;
//! - **decay**: μ ×0.85 per tick down to μ/10 (a tick every 250 steps at the earliest, once φ
//!   moved less than 5e-3 in the last 250);
//! - **oscillation**: μ = μ_ref(t)·s^(−sin 2πt/T), μ_ref decaying from μ₀ to μ₀/10 over the
//!   decay's duration, T half the first rung, `oscillation_cycles` periods; the run stops from
//!   the last peak on once the largest overlap stayed below `stop_overlap` for `stop_steps`
//!   steps, or else after a final descent of μ by ticks;
//! - α grows by 1.00005 per step and 1.1 every 500 steps up to α_max, is cut by 1.5 when the
//!   mean force stops falling or φ drops, grows by 1.15 when the force has fallen, is halved
//!   at each phase change and capped at α_max/100 while μ oscillates.
//!
//! RCPGenerator's stop test also asks its relative mean force to be below 5e-3, but reads it
//! from a slot of its history not yet written in that step (always 0), so only the overlap
//! decides; this port does the same. Walls push with twice its stiffness (packbench's wall
//! energy is harmonic in the overlap of the radius).

use packbench_core::Packing;
use packbench_core::run::{Observer, Outcome};
use serde_json::Map;

use super::Driver;
use crate::error::AdamError;
use crate::overlap_energy::Evaluation;
use crate::params::Params;
use crate::system::OverlapScale;

/// Steps between ticks of the μ decay, and the window of its φ-flatness test.
const TICK: u64 = 250;
/// φ range over the last `TICK` steps below which a tick lowers μ.
const TICK_FLAT_PHI: f64 = 5e-3;
/// Longest look-back of the α trends, in steps.
const HISTORY: usize = 3001;
/// Growth of α per step, and every 500 steps, up to α_max.
const ALPHA_CREEP: f64 = 1.00005;
const ALPHA_BOOST: f64 = 1.1;

/// The phases of the schedule (RCPGenerator's `mu_flag` 1, 0, −1 and its final descent).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Phase {
    FirstRung,
    Decay,
    Oscillation,
    FinalDescent,
}

impl Phase {
    fn name(self) -> &'static str {
        match self {
            Phase::FirstRung => "first_rung",
            Phase::Decay => "decay",
            Phase::Oscillation => "oscillation",
            Phase::FinalDescent => "final_descent",
        }
    }
}

/// The last `HISTORY` values of a per-step series, addressed by step (1-based).
struct History {
    values: Vec<f64>,
}

impl History {
    fn new() -> Self {
        History {
            values: vec![0.0; HISTORY],
        }
    }

    fn set(&mut self, step: u64, v: f64) {
        self.values[step as usize % HISTORY] = v;
    }

    /// The value at `step` (0 before the run).
    fn at(&self, step: u64) -> f64 {
        self.values[step as usize % HISTORY]
    }

    /// Mean over steps `from..=to`.
    fn mean(&self, from: u64, to: u64) -> f64 {
        (from..=to).map(|s| self.at(s)).sum::<f64>() / (to - from + 1) as f64
    }

    /// max − min over steps `from..=to`.
    fn range(&self, from: u64, to: u64) -> f64 {
        let (lo, hi) = (from..=to).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
            (lo.min(self.at(s)), hi.max(self.at(s)))
        });
        hi - lo
    }
}

/// μ's schedule: the phase and the state of its decay, oscillation and stop test.
struct Schedule {
    phase: Phase,
    mu: f64,
    decay_target: f64,
    decaying: bool,
    next_tick: u64,
    /// Step of the last phase change (RCPGenerator's `mu_change`).
    changed_at: u64,
    osc_mu0: f64,
    osc_start: u64,
    osc_period: f64,
    osc_relax: f64,
    final_start: u64,
    below_for: u32,
}

impl Schedule {
    /// The schedule at the start of a run: the first rung at pressure `mu`.
    fn new(mu: f64) -> Self {
        Schedule {
            phase: Phase::FirstRung,
            mu,
            decay_target: 0.0,
            decaying: false,
            next_tick: 0,
            changed_at: 0,
            osc_mu0: 0.0,
            osc_start: 0,
            osc_period: 0.0,
            osc_relax: 0.0,
            final_start: 0,
            below_for: 0,
        }
    }

    /// True once the last `stop_steps` checks found the largest overlap below `stop_overlap`.
    fn check_stop(&mut self, max_overlap: f64, p: &Params) -> bool {
        if max_overlap < p.stop_overlap {
            self.below_for += 1;
        } else {
            self.below_for = 0;
        }
        self.below_for >= p.stop_steps
    }

    /// Advances μ at the top of `step` (halving `alpha` when the oscillation starts); true
    /// when the run is done.
    fn advance(
        &mut self,
        step: u64,
        phi: &History,
        max_overlap: f64,
        p: &Params,
        alpha: &mut f64,
    ) -> bool {
        let flat = |s: u64| s > TICK && phi.range(s - TICK + 1, s - 1) < TICK_FLAT_PHI;
        if self.decaying && step >= self.next_tick && flat(step) {
            self.mu *= p.mu_decay;
            if self.mu <= self.decay_target {
                self.mu = self.decay_target;
                self.decaying = false;
            }
            self.next_tick = step + TICK;
        }
        if self.phase == Phase::Decay && !self.decaying && step > self.changed_at {
            // The oscillation's period is half the first rung; its reference relaxes over the
            // time the decay took.
            self.osc_mu0 = self.mu;
            self.osc_relax = ((step - self.changed_at) as f64).max(TICK as f64);
            self.osc_period = (0.5 * self.changed_at as f64).max(1000.0);
            self.osc_start = step;
            self.phase = Phase::Oscillation;
            self.changed_at = step;
            *alpha /= 2.0;
        }
        match self.phase {
            Phase::Oscillation => {
                let t = (step - self.osc_start) as f64;
                let progress = t / self.osc_period;
                let cycles = f64::from(p.oscillation_cycles);
                let mu_low = self.osc_mu0 / 10.0;
                if progress >= cycles {
                    self.mu = mu_low;
                    self.phase = Phase::FinalDescent;
                    self.final_start = step;
                    self.next_tick = step + TICK;
                } else {
                    let sin = -(2.0 * std::f64::consts::PI * progress.fract()).sin();
                    let reference = (self.osc_mu0 - mu_low) * (-t / self.osc_relax).exp() + mu_low;
                    self.mu = reference * p.oscillation_swing.powf(sin);
                    // From the last peak of μ on, the first state that holds below the overlap
                    // tolerance ends the run.
                    if progress >= cycles - 0.25 && self.check_stop(max_overlap, p) {
                        return true;
                    }
                }
                false
            }
            Phase::FinalDescent if step >= self.next_tick && flat(step) => {
                if self.check_stop(max_overlap, p) {
                    return true;
                }
                if self.below_for == 0 {
                    self.mu *= p.mu_decay;
                }
                self.next_tick = step + TICK;
                step - self.final_start > p.final_descent_steps
            }
            _ => false,
        }
    }

    /// μ at `step`: in the first rung boosted by 1 + (b − 1)e^(−step/τ).
    fn mu_at(&self, step: u64, p: &Params) -> f64 {
        if self.phase == Phase::FirstRung {
            let boost = (-(step as f64) / p.first_rung_boost_steps).exp();
            self.mu * (1.0 + (p.first_rung_boost - 1.0) * boost)
        } else {
            self.mu
        }
    }

    /// Ends the first rung after its fixed length.
    fn end_first_rung(&mut self, step: u64, first_rung_steps: u64) -> bool {
        if self.phase == Phase::FirstRung && step > 500 && step > first_rung_steps {
            self.decay_target = self.mu / 10.0;
            self.decaying = true;
            self.next_tick = step + TICK;
            self.phase = Phase::Decay;
            self.changed_at = step;
            return true;
        }
        false
    }
}

/// RCPGenerator's adaptive α (its "alpha trend" block), at the top of `step`; `phi` is the
/// previous step's φ.
struct StepSize {
    alpha: f64,
    alpha_max: f64,
    last_update: u64,
}

impl StepSize {
    fn adapt(&mut self, step: u64, phi: f64, hist: (&History, &History), sched: &Schedule) {
        let (phis, forces) = hist;
        let rise = phi - phis.at((step - 250).max(1) + 1);
        if step > 2500
            && step - self.last_update > 500
            && step > sched.changed_at + 500
            && rise < 5e-4
        {
            let compressing = sched.phase == Phase::FirstRung;
            // The mean force 250 steps ago against now: falling slower than 15 % means the
            // step is too coarse to settle.
            let trend = forces.mean(step - 449, step - 249) / forces.mean(step - 74, step);
            if (!compressing && trend < 0.85) || rise < -5e-4 {
                self.last_update = step;
                self.alpha /= 1.5;
            } else if !compressing && step - self.last_update > 1500 && step > 3000 {
                let trend = forces.mean(step - 199, step) / forces.mean(step - 2999, step - 2499);
                if trend > 0.5 {
                    self.last_update = step;
                    self.alpha *= 1.15;
                }
            }
            if compressing {
                self.alpha = self.alpha.max(self.alpha_max / 10.0);
            }
        }
        self.alpha = (self.alpha * ALPHA_CREEP).min(self.alpha_max);
        if step.is_multiple_of(500) {
            self.alpha = (ALPHA_BOOST * self.alpha).min(self.alpha_max);
        }
        if sched.phase == Phase::Oscillation {
            self.alpha = self.alpha.min(self.alpha_max / 100.0);
        }
    }
}

/// RCPGenerator's φ at which its κ is 1: where its run starts.
fn reference_phi(d: usize) -> f64 {
    match d {
        2 => 0.575,
        3 => 0.33,
        4 => 0.15,
        5 => 0.10,
        _ => 0.10 / 2f64.powi(d as i32 - 4),
    }
}

/// The run's fixed frame: RCPGenerator's unit of length (the container's longest side, its
/// box being the unit box), κ at φ_ref, and ADAM's length per coordinate.
struct Units {
    unit: f64,
    kappa_ref: f64,
    /// L for positions, 1 for κ (measured from κ_ref).
    lengths: Vec<f64>,
}

/// What one step's forces say, besides the forces themselves.
struct StepForces {
    mu: f64,
    mean_force: f64,
}

/// Runs the RCPGenerator protocol from `start`.
pub(crate) fn run(
    start: &Packing,
    params: &Params,
    observer: &mut dyn Observer,
) -> Result<Outcome, AdamError> {
    let mut dr = Driver::new(start, params, observer, 1)?;
    let units = set_up(&mut dr)?;
    let d = dr.sys.dim;
    let alpha_max = params.box_alpha_for(d);
    let mut alpha = StepSize {
        alpha: alpha_max,
        alpha_max,
        last_update: 0,
    };
    let first_rung_steps = params.first_rung_steps_for(dr.sys.n(), d);
    // The first rung, about 15 ticks of decay, and two periods of half the first rung.
    dr.expected_steps = (2 * first_rung_steps + 15 * TICK).min(params.max_steps);
    let mut sched = Schedule::new(params.box_mu);
    let mut phis = History::new();
    let mut forces = History::new();
    let mut termination = "max_steps";
    let mut use_best = true;
    let mut last = dr.evaluate(0)?;
    let mut phi = dr.sys.phi();
    let mut kappa_evaluated = units.kappa_ref;
    let mut step = 0;
    while step < params.max_steps {
        step += 1;
        if dr.stop_requested(step) {
            termination = "interrupted";
            break;
        }
        if sched.advance(step, &phis, last.max_overlap, params, &mut alpha.alpha) {
            // RCPGenerator returns the diameters its last force evaluation saw.
            dr.sys.set_kappa(kappa_evaluated);
            termination = "converged";
            use_best = false;
            break;
        }
        // This step's mean force is not known yet: RCPGenerator's trends read it as 0.
        forces.set(step, 0.0);
        alpha.adapt(step, phi, (&phis, &forces), &sched);
        phi = dr.sys.phi();
        phis.set(step, phi);
        if sched.end_first_rung(step, first_rung_steps) {
            alpha.alpha /= 2.0;
        }
        let ev = dr.evaluate(step)?;
        last = ev;
        kappa_evaluated = dr.sys.kappa;
        let now = box_forces(&mut dr, &ev, &units, sched.mu_at(step, params));
        forces.set(step, now.mean_force);
        if dr.scaled_energy(&ev) < params.energy_threshold {
            dr.remember_if_densest();
        }
        move_by_adam(&mut dr, step, alpha.alpha, &units)?;
        let values = [
            ("mu", now.mu),
            ("alpha", alpha.alpha),
            ("mean_force", now.mean_force),
        ];
        dr.report(step, &ev, &values);
    }
    let mut extra = Map::new();
    extra.insert("protocol".into(), "rcpgenerator".into());
    extra.insert("mu".into(), sched.mu.into());
    extra.insert("phase".into(), sched.phase.name().into());
    extra.insert("first_rung_steps".into(), first_rung_steps.into());
    extra.insert("box_alpha".into(), alpha_max.into());
    extra.insert("final_energy".into(), last.energy.into());
    extra.insert("final_max_overlap".into(), last.max_overlap.into());
    let values = [("mu", sched.mu), ("alpha", alpha.alpha)];
    Ok(dr.finish(step, &last, &values, termination, use_best, extra))
}

/// Puts the run in RCPGenerator's frame: absolute overlaps, box lengths for ADAM, φ at φ_ref
/// with κ = 1 there.
fn set_up(dr: &mut Driver<'_>) -> Result<Units, AdamError> {
    // ADAM's lengths here are the container's, not the contacts'.
    dr.jacobi_lengths = false;
    dr.sys.overlap_scale = OverlapScale::Absolute;
    let nc = dr.n_coords();
    let unit = dr
        .sys
        .container
        .lengths
        .iter()
        .fold(0.0f64, |m, &l| m.max(l));
    dr.set_phi(reference_phi(dr.sys.dim))?;
    dr.sys.x[nc] = 1.0;
    let mut lengths = vec![unit; nc + 1];
    lengths[nc] = 1.0;
    Ok(Units {
        unit,
        kappa_ref: dr.sys.kappa,
        lengths,
    })
}

/// Converts the forces to RCPGenerator's units, sets the κ-force for pressure `mu` and returns
/// RCPGenerator's relative mean force.
fn box_forces(dr: &mut Driver<'_>, ev: &Evaluation, units: &Units, mu: f64) -> StepForces {
    let d = dr.sys.dim;
    let nc = dr.n_coords();
    let unit = units.unit;
    // packbench's absolute-overlap forces are δ/D̄² per contact: in RCPGenerator's units
    // (δ in L) they are these times D̄²/L.
    let dbar = dr.sys.mean_diameter();
    let to_box = dbar * dbar / unit;
    let mut norm_sum = 0.0;
    let mut moving = 0usize;
    for f in dr.force[..nc].chunks_exact_mut(d) {
        let mut f2 = 0.0;
        for v in f.iter_mut() {
            *v *= to_box;
            f2 += *v * *v;
        }
        if f2 > 1e-16 {
            norm_sum += f2.sqrt();
            moving += 1;
        }
    }
    // κ-force: −Σσδ + μΣD in L² (Σwε = Σσδ/D̄² under absolute overlaps), both over the
    // growing diameters when some are held (RCPGenerator's active-only sums).
    let (growing, growing_dbar) = dr.sys.growing();
    dr.force[nc] =
        -ev.weighted_overlap * dbar * dbar / (unit * unit) + mu * growing * growing_dbar / unit;
    // RCPGenerator's relative mean force: the mean net force per moving particle and axis
    // over its mean contact overlap.
    let mean_overlap = ev.stretch / (1.0 + ev.contacts);
    let mean_force = if moving > 0 && mean_overlap > 0.0 {
        norm_sum / moving as f64 / (d as f64).sqrt() / mean_overlap
    } else {
        0.0
    };
    StepForces { mu, mean_force }
}

/// One ADAM step of positions and κ with step `alpha`, then κ applied to the diameters.
fn move_by_adam(
    dr: &mut Driver<'_>,
    step: u64,
    alpha: f64,
    units: &Units,
) -> Result<(), AdamError> {
    let nc = dr.n_coords();
    // The driver's relaxer stays in its ADAM stage throughout under this protocol.
    dr.relaxer.set_learning_rate(alpha);
    dr.relaxer
        .step(step, &mut dr.sys.x, &dr.force, &units.lengths, 1.0);
    let k = dr.sys.x[nc];
    if !(k.is_finite() && k > 0.0) {
        return Err(AdamError::NonFinite { step });
    }
    dr.sys.set_kappa(units.kappa_ref * k);
    dr.sys.check_own_image()
}
