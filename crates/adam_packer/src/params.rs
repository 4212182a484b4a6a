//! The packer's parameters. Defaults are the constants of RCPGenerator 1.0 (, section
//! "Rough Overview of Algorithm") and Particle Assembler ('s FIRE).

use serde::{Deserialize, Serialize};

use crate::error::AdamError;
use crate::system::OverlapScale;

/// Which minimizer relaxes positions between diameter changes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Minimizer {
    /// RCPGenerator 1.0's chain: ADAM up to `adam_steps`, AMSGrad up to `amsgrad_steps`, then
    /// overdamped (velocity-damped) Verlet.
    #[default]
    Adam,
    /// FIRE (Particle Assembler): velocity Verlet with adaptive time step and velocity mixing.
    Fire,
}

/// How the diameters grow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Protocol {
    /// RCPGenerator 1.0's loop: inflate by Δφ while the energy (or the largest overlap) is below
    /// threshold, deflate by Δφ/2 when overlapped and force-balanced, hold otherwise; Δφ shrinks
    /// on every reversal. Also the protocol of every run with `target_phi`.
    Threshold,
    /// The diameter scale κ is an optimisation variable with a pressure-like term
    /// −μ·κ·ΣD₀ added to the overlap energy; μ is lowered in rungs each time the system is
    /// balanced relative to μ. It needs a few times fewer steps than `Threshold`, which holds
    /// every over-compressed trial state until its forces balance absolutely
    /// (docs/notes/adam-pressure-protocol.md).
    Pressure,
    /// The default: RCPGenerator 1.0's schedule. ADAM throughout on positions and κ with a
    /// step in container lengths, under a pressure in container lengths: a boosted first rung
    /// of fixed length, a decay of μ by ten, an oscillation of μ by ±10× around a decaying
    /// reference, and a stop once the largest overlap stays below `stop_overlap`
    /// (docs/notes/adam-fidelity.md).
    #[default]
    Rcpgenerator,
}

/// Every knob of the packer. Lengths are in units of the particles' own diameters unless a
/// field says otherwise; energies are the dimensionless overlap energy U = Σ ½ ε² summed over
/// contacts (ε = 1 − r/σ for pairs, 1 − h/R for walls); forces are its gradient with respect to
/// positions measured in each particle's diameter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Params {
    /// The minimizer (`adam` or `fire`).
    pub minimizer: Minimizer,
    /// The growth protocol (`threshold` or `pressure`).
    pub protocol: Protocol,
    /// Largest number of steps (RCPGenerator 1.0 `N_STEPS`); the run then stops with termination
    /// `max_steps` and returns its densest low-energy packing.
    pub max_steps: u64,
    /// Grow to this packing fraction and stop overlap-free (Particle Assembler's use); `None`
    /// jams. When the system jams below it the run stops with `jammed_below_target`.
    pub target_phi: Option<f64>,
    /// Indices (input order) of the particles whose diameters are held at their starting
    /// values while the others grow or shrink (empty: every diameter scales). The pressure
    /// acts on the growing diameters only, so the growing spheres jam around the fixed ones:
    /// fines filling a scaffold, or a seeded inclusion. RCPGenerator 1.0 keeps such a mask
    /// until its first rung ends and then frees it; here it holds for the whole run.
    pub fixed_diameters: Vec<usize>,
    /// Largest relative overlap 1 − r/σ accepted as "overlap-free" at `target_phi`.
    pub target_overlap_tol: f64,
    /// Initial growth step in φ (RCPGenerator 1.0 `DELTA_PHI0` = 1.5 × 1.5e-3); above `threshold_n`
    /// particles the threshold protocol starts from Δφ₀·threshold_n/N (at least 4·`delta_phi_tol`).
    pub delta_phi0: f64,
    /// Stop once the growth step falls below this (RCPGenerator 1.0: 5e-6).
    pub delta_phi_tol: f64,
    /// Floor of φ: the first step jumps to it (RCPGenerator 1.0 `phi_min`); later deflations may go below. `None` = half the jamming
    /// density expected in this dimension (Skoge et al. 2006 fit 2^−d (2.56 d − 2.72); 0.42 in 2D).
    pub phi_min: Option<f64>,
    /// Energy below which the diameters inflate (RCPGenerator 1.0 `U_threshold`).
    pub energy_threshold: f64,
    /// Largest relative overlap below which the diameters inflate whatever the energy, at the
    /// initial step Δφ₀ (RCPGenerator 1.0: 10·√U_threshold). It scales with Δφ/Δφ₀ so that the final,
    /// fine steps are decided by the energy alone.
    pub overlap_threshold: f64,
    /// Force-balance tolerance (RCPGenerator 1.0 `F_tol`) on the force norm.
    pub force_tol: f64,
    /// Number of particles for which `energy_threshold`, `force_tol` and `final_force_tol`
    /// hold as totals (RCPGenerator 1.0's constants are totals, tuned on its N = 1000 examples). A run
    /// of N particles compares U·n_ref/N and |F|·√(n_ref/N) with them, so the thresholds mean
    /// the same energy and RMS force per particle at any N: as totals they would demand
    /// ever smaller overlaps as N grows and a run of 10⁴ particles would never balance.
    pub threshold_n: f64,
    /// Force norm the converged packing is polished to at its final diameters, so that the
    /// weakest contacts are closed to well within a 1e-6 contact tolerance.
    pub final_force_tol: f64,
    /// Largest number of polishing steps; the packing is returned as converged after them even
    /// if `final_force_tol` was not reached (`extra.polished` says whether it was).
    pub polish_steps: u64,
    /// Steps before the first deflation is allowed (RCPGenerator 1.0: 125).
    pub warmup_steps: u64,
    /// Factor applied to Δφ at each reversal of growth direction.
    pub step_shrink: f64,
    /// Factor applied to Δφ after `grow_after` growth decisions in the same direction (capped at
    /// `delta_phi0`).
    pub step_grow: f64,
    /// Same-direction growth decisions before Δφ grows.
    pub grow_after: u32,
    /// Last step that uses ADAM; `None` = the protocol's own: RCPGenerator 1.0's 2500 for `threshold`,
    /// 500 for `pressure` (ADAM and AMSGrad stall at a noise floor; the damped Verlet stage is
    /// what balances the rungs).
    pub adam_steps: Option<u64>,
    /// Last step that uses AMSGrad, overdamped Verlet following; `None` = RCPGenerator 1.0's 4000 for
    /// `threshold`, 1000 for `pressure`.
    pub amsgrad_steps: Option<u64>,
    /// ADAM learning rate, in particle diameters per step (RCPGenerator 1.0 `LR_ADAM`).
    pub lr_adam: f64,
    /// AMSGrad learning rate, in particle diameters per step (RCPGenerator 1.0 `LR_AMS`).
    pub lr_ams: f64,
    /// ADAM first-moment decay (RCPGenerator 1.0 `BETA1`).
    pub beta1: f64,
    /// ADAM second-moment decay (RCPGenerator 1.0 `BETA2`).
    pub beta2: f64,
    /// ADAM stability constant (RCPGenerator 1.0 `EPSILON_ADAM`).
    pub epsilon_adam: f64,
    /// AMSGrad stability constant (RCPGenerator 1.0 `EPSILON_AMS`).
    pub epsilon_ams: f64,
    /// Overdamped Verlet time step, in units where a contact's stiffness and a particle's mass
    /// are 1 (RCPGenerator 1.0's `DT` = 0.1 is in its own units). With the Jacobi length scales 0.5
    /// converges fastest and jams RCPGenerator 1.0's power law, where 0.3 stalled
    /// (docs/notes/adam-protocol-large-n.md).
    pub dt_verlet: f64,
    /// Fraction of the velocity the overdamped Verlet integrator removes per step; `None` =
    /// 0.02 for `threshold`, 0.01 for `pressure` (measured fastest at N = 10³; 0.05 stalled).
    pub verlet_damping: Option<f64>,
    /// FIRE initial time step (same units as `dt_verlet`).
    pub fire_dt: f64,
    /// FIRE largest time step.
    pub fire_dt_max: f64,
    /// FIRE initial mixing α_start (Particle Assembler: 0.1).
    pub fire_alpha_start: f64,
    /// FIRE steps with positive power before dt grows, N_min (Particle Assembler: 5).
    pub fire_n_min: u32,
    /// FIRE time-step growth f_inc (Particle Assembler: 1.1).
    pub fire_f_inc: f64,
    /// FIRE time-step cut on uphill motion f_dec (Particle Assembler: 0.5).
    pub fire_f_dec: f64,
    /// FIRE mixing decay f_α (Particle Assembler: 0.99).
    pub fire_f_alpha: f64,
    /// Pressure protocol: initial μ of the term −μ·κ·ΣD₀ (ΣD₀ in units of the mean diameter);
    /// at balance the mean contact overlap is about μ/d.
    pub mu_start: f64,
    /// Pressure protocol: factor applied to μ at each rung.
    pub mu_factor: f64,
    /// Pressure protocol: the run stops once μ falls below this.
    pub mu_min: f64,
    /// Pressure protocol: a rung also ends when φ changed by less than `rung_phi_tol` (relative)
    /// over this many steps.
    pub rung_window: u64,
    /// Pressure protocol: relative φ change over `rung_window` steps that counts as a stall in
    /// the last rung (earlier rungs: μ/μ_min times it, their over-compression being that much
    /// larger); `None` resolves by the overlap scale ([`Params::stall_tolerance`]). 1e-5 with
    /// relative overlaps: the last rung's creep (φ +3·10⁻⁵ over 23 000 steps on one N = 10⁴
    /// start, force residual level at twice its target) is below the rung's own accuracy in φ
    /// (~10⁻⁴, BENCHMARKS' `mu_min` sweep); at 1e-6 it set the ±30 % spread of step counts.
    /// 3e-5 with absolute overlaps (broad size distributions): RCPGenerator 1.0's walled power law
    /// creeps at every rung by ~10⁻³ over 10⁴–10⁵ steps (the large spheres rearranging), and
    /// at 1e-5 the last rung's length alone varied from 6·10³ to 8·10⁴ steps
    /// (docs/notes/adam-pressure-protocol.md). FIRE keeps 1e-6 ([`Params::fire`]).
    pub rung_phi_tol: Option<f64>,
    /// Pressure protocol: a rung ends once the RMS net force per particle (in units of the
    /// overlap ε) is below `rung_force_rel`·μ and the force on the diameter scale below
    /// `rung_force_rel`·μ·N: balanced relative to the rung's own contact scale (mean overlap
    /// about μ/d), so early rungs at high pressure are not held to the last rung's accuracy.
    pub rung_force_rel: f64,
    /// Pressure protocol: the same relative balance demanded of the last rung (μ below
    /// `mu_min` after it), whose state is returned.
    pub final_rung_force_rel: f64,
    /// RCPGenerator protocol: the largest ADAM step per coordinate, in lengths of the
    /// container's longest side (RCPGenerator 1.0's α_max); `None` = its value for the
    /// dimension: 0.005 in 2D, 0.0045 in 3D, 0.0035 in 4D, 0.0025 above.
    pub box_alpha: Option<f64>,
    /// RCPGenerator protocol: the pressure μ of the term −μ·κ·ΣD, in lengths of the
    /// container's longest side (RCPGenerator 1.0: 2.5e-4). At balance the mean contact
    /// overlap is about 2μ/(z·D̄) relative.
    pub box_mu: f64,
    /// RCPGenerator protocol: μ is boosted by 1 + (boost − 1)·e^(−step/`first_rung_boost_steps`)
    /// in the first rung (RCPGenerator 1.0: 5).
    pub first_rung_boost: f64,
    /// RCPGenerator protocol: the decay length of the boost, in steps (350).
    pub first_rung_boost_steps: f64,
    /// RCPGenerator protocol: the first rung's length in steps; `None` = 6000 + 9·√(N·d)
    /// (RCPGenerator 1.0's "quick" preset, at least 1500).
    pub first_rung_steps: Option<u64>,
    /// RCPGenerator protocol: factor applied to μ at each tick of the decay after the first
    /// rung and of the final descent (0.85; a tick every 250 steps at the earliest, when φ
    /// moved by less than 5e-3 over the last 250).
    pub mu_decay: f64,
    /// RCPGenerator protocol: number of oscillation periods of μ (2, the "quick" preset).
    pub oscillation_cycles: u32,
    /// RCPGenerator protocol: μ swings between the reference over and times this (10).
    pub oscillation_swing: f64,
    /// RCPGenerator protocol: the run stops, in the last quarter period of the oscillation or
    /// after it, once the largest relative overlap stayed below this for `stop_steps` steps
    /// (5e-4). The accuracy knob: smaller is closer to hard-sphere contact and slower.
    pub stop_overlap: f64,
    /// RCPGenerator protocol: consecutive steps below `stop_overlap` that stop the run (3).
    pub stop_steps: u32,
    /// RCPGenerator protocol: largest number of steps of the final descent after the
    /// oscillation (50 000).
    pub final_descent_steps: u64,
    /// Neighbour-list skin, in mean diameters.
    pub neighbor_skin: f64,
    /// RCPGenerator protocol: the skin grows beyond `neighbor_skin` to last this many steps
    /// at the step size of the last list's life (0: the fixed skin). The list's contents do
    /// not change this protocol's path, only its cost.
    pub neighbor_lifetime_steps: f64,
    /// The largest skin the lifetime may grow it to, in mean diameters. The listed pairs grow
    /// with the cube of the skin: in the first rung at N = 10⁶ a step moves particles by about
    /// a diameter (α is a fraction of the box length), and the uncapped skin peaked at 5.6 GB
    /// in the first 60 steps and held 13 GB after 13 CPU minutes (757 MB and 0.6× the CPU with
    /// this cap; docs/notes/adam-step-profile.md).
    pub neighbor_skin_max: f64,
    /// RCPGenerator protocol: between whole builds, refresh only the rows of particles that
    /// moved a fifth of the skin since their own last search, as RCPGenerator 1.0 does, when
    /// D_max is at least this multiple of the 90th-percentile diameter (0: always; a huge
    /// value: never). The path is the same either way, only the cost differs: for the walled
    /// power law 1–15 at N = 10⁴ it took 32 % off the run, for equal spheres it added 11 %
    /// (docs/notes/adam-step-profile.md).
    pub neighbor_refresh_min_ratio: f64,
    /// Particles from which the force loop runs on rayon's threads (below it, on the calling
    /// thread); results are bit-identical either way and for any number of threads.
    pub parallel_min_particles: usize,
    /// Steps between snapshots sent to the observer (0 = none; `--save-interval`).
    pub save_interval: u64,
    /// Steps between rows of the trace (1: every step; the final state is always a row).
    pub trace_every: u64,
}

impl Default for Params {
    fn default() -> Self {
        let energy_threshold = 6.25e-8;
        Params {
            minimizer: Minimizer::Adam,
            protocol: Protocol::Rcpgenerator,
            max_steps: 150_000,
            target_phi: None,
            fixed_diameters: Vec::new(),
            target_overlap_tol: 1e-6,
            delta_phi0: 1.5 * 1.5e-3,
            delta_phi_tol: 5e-6,
            phi_min: None,
            energy_threshold,
            overlap_threshold: 10.0 * energy_threshold.sqrt(),
            force_tol: 5e-6,
            threshold_n: 1000.0,
            final_force_tol: 1e-7,
            polish_steps: 20_000,
            warmup_steps: 125,
            step_shrink: 0.5,
            step_grow: 1.1,
            grow_after: 20,
            adam_steps: None,
            amsgrad_steps: None,
            lr_adam: 1e-2,
            lr_ams: 1e-3,
            beta1: 0.9,
            beta2: 0.999,
            epsilon_adam: 1e-8,
            epsilon_ams: 1e-8,
            dt_verlet: 0.5,
            verlet_damping: None,
            fire_dt: 0.1,
            fire_dt_max: 0.5,
            fire_alpha_start: 0.1,
            fire_n_min: 5,
            fire_f_inc: 1.1,
            fire_f_dec: 0.5,
            fire_f_alpha: 0.99,
            mu_start: 1e-2,
            mu_factor: 0.1,
            mu_min: 1e-4,
            rung_window: 2000,
            rung_phi_tol: None,
            rung_force_rel: 1e-2,
            final_rung_force_rel: 1e-3,
            box_alpha: None,
            box_mu: 2.5e-4,
            first_rung_boost: 5.0,
            first_rung_boost_steps: 350.0,
            first_rung_steps: None,
            mu_decay: 0.85,
            oscillation_cycles: 2,
            oscillation_swing: 10.0,
            stop_overlap: 5e-4,
            stop_steps: 3,
            final_descent_steps: 50_000,
            neighbor_skin: 0.2,
            neighbor_lifetime_steps: 2.0,
            neighbor_skin_max: 1.0,
            neighbor_refresh_min_ratio: 2.0,
            parallel_min_particles: 4096,
            save_interval: 0,
            trace_every: 250,
        }
    }
}

impl Params {
    /// The defaults with FIRE as the minimizer (`--method fire`).
    pub fn fire() -> Self {
        Params {
            minimizer: Minimizer::Fire,
            // FIRE relaxes the last rung more slowly than ADAM: at 1e-5 one of three N = 10⁴
            // starts (seed 1) stopped with twice the rattlers and iso_gap −333 of 28 930
            // (+64 at 1e-6) for 6 % fewer steps over the three (BENCHMARKS, fire).
            rung_phi_tol: Some(1e-6),
            // RCPGenerator's schedule is ADAM's; FIRE keeps the pressure protocol.
            protocol: Protocol::Pressure,
            ..Params::default()
        }
    }

    /// Checks every knob; the error names the field and its admissible range.
    pub fn validate(&self) -> Result<(), AdamError> {
        if self.trace_every == 0 {
            return Err(AdamError::Parameter(
                "trace_every must be at least 1 (steps between trace rows)".into(),
            ));
        }
        self.check_ranges()?;
        self.check_consistency()
    }

    /// Each number in its range: positive, a fraction, at least 1.
    fn check_ranges(&self) -> Result<(), AdamError> {
        for (name, v) in [
            ("delta_phi0", self.delta_phi0),
            ("delta_phi_tol", self.delta_phi_tol),
            ("energy_threshold", self.energy_threshold),
            ("overlap_threshold", self.overlap_threshold),
            ("force_tol", self.force_tol),
            ("threshold_n", self.threshold_n),
            ("final_force_tol", self.final_force_tol),
            ("target_overlap_tol", self.target_overlap_tol),
            ("lr_adam", self.lr_adam),
            ("lr_ams", self.lr_ams),
            ("epsilon_adam", self.epsilon_adam),
            ("epsilon_ams", self.epsilon_ams),
            ("dt_verlet", self.dt_verlet),
            ("fire_dt", self.fire_dt),
            ("fire_dt_max", self.fire_dt_max),
            ("mu_start", self.mu_start),
            ("mu_min", self.mu_min),
            ("rung_phi_tol", self.stall_tolerance(OverlapScale::Relative)),
            ("rung_force_rel", self.rung_force_rel),
            ("final_rung_force_rel", self.final_rung_force_rel),
            ("neighbor_skin", self.neighbor_skin),
            ("box_alpha", self.box_alpha.unwrap_or(1.0)),
            ("box_mu", self.box_mu),
            ("first_rung_boost_steps", self.first_rung_boost_steps),
            ("stop_overlap", self.stop_overlap),
        ] {
            positive(name, v)?;
        }
        for (name, v) in [
            ("beta1", self.beta1),
            ("beta2", self.beta2),
            ("step_shrink", self.step_shrink),
            ("fire_alpha_start", self.fire_alpha_start),
            ("fire_f_dec", self.fire_f_dec),
            ("fire_f_alpha", self.fire_f_alpha),
            ("mu_factor", self.mu_factor),
            ("mu_decay", self.mu_decay),
        ] {
            fraction(name, v)?;
        }
        for (name, v) in [
            ("first_rung_boost", self.first_rung_boost),
            ("oscillation_swing", self.oscillation_swing),
        ] {
            if !(v.is_finite() && v >= 1.0) {
                return Err(AdamError::Parameter(format!(
                    "{name} = {v} must be a finite number ≥ 1"
                )));
            }
        }
        let lifetime = self.neighbor_lifetime_steps;
        if !(lifetime.is_finite() && lifetime >= 0.0) {
            return Err(AdamError::Parameter(format!(
                "neighbor_lifetime_steps = {lifetime} must be a finite number ≥ 0"
            )));
        }
        if self.neighbor_refresh_min_ratio.is_nan() || self.neighbor_refresh_min_ratio < 0.0 {
            return Err(AdamError::Parameter(format!(
                "neighbor_refresh_min_ratio = {} must be a number ≥ 0",
                self.neighbor_refresh_min_ratio
            )));
        }
        if !(self.neighbor_skin_max.is_finite() && self.neighbor_skin_max >= self.neighbor_skin) {
            return Err(AdamError::Parameter(format!(
                "neighbor_skin_max = {} must be a finite number ≥ neighbor_skin = {}",
                self.neighbor_skin_max, self.neighbor_skin
            )));
        }
        for (name, v) in [("target_phi", self.target_phi), ("phi_min", self.phi_min)] {
            if let Some(p) = v {
                fraction(name, p)?;
            }
        }
        Ok(())
    }

    /// The choices that must agree with each other (minimizer and protocol, step schedules,
    /// tolerances against their starting values).
    fn check_consistency(&self) -> Result<(), AdamError> {
        if self.minimizer == Minimizer::Fire && self.effective_protocol() == Protocol::Rcpgenerator
        {
            return Err(AdamError::Parameter(
                "the rcpgenerator protocol runs ADAM throughout; with the FIRE minimizer choose \
                 protocol pressure or threshold"
                    .into(),
            ));
        }
        if self.oscillation_cycles == 0 || self.stop_steps == 0 {
            return Err(AdamError::Parameter(
                "oscillation_cycles and stop_steps must be at least 1".into(),
            ));
        }
        let (adam_steps, amsgrad_steps, verlet_damping) = self.stage_schedule();
        if !(0.0..1.0).contains(&verlet_damping) {
            return Err(AdamError::Parameter(format!(
                "verlet_damping = {verlet_damping} must lie in [0, 1)"
            )));
        }
        if !(self.step_grow >= 1.0 && self.step_grow.is_finite()) {
            return Err(AdamError::Parameter(format!(
                "step_grow = {} must be a finite number ≥ 1",
                self.step_grow
            )));
        }
        if !(self.fire_f_inc >= 1.0 && self.fire_f_inc.is_finite()) {
            return Err(AdamError::Parameter(format!(
                "fire_f_inc = {} must be a finite number ≥ 1",
                self.fire_f_inc
            )));
        }
        if self.fire_dt > self.fire_dt_max {
            return Err(AdamError::Parameter(format!(
                "fire_dt = {} must not exceed fire_dt_max = {}",
                self.fire_dt, self.fire_dt_max
            )));
        }
        if self.delta_phi_tol >= self.delta_phi0 {
            return Err(AdamError::Parameter(format!(
                "delta_phi_tol = {} must be smaller than delta_phi0 = {}",
                self.delta_phi_tol, self.delta_phi0
            )));
        }
        if self.mu_min >= self.mu_start {
            return Err(AdamError::Parameter(format!(
                "mu_min = {} must be smaller than mu_start = {}",
                self.mu_min, self.mu_start
            )));
        }
        if amsgrad_steps < adam_steps {
            return Err(AdamError::Parameter(format!(
                "amsgrad_steps = {amsgrad_steps} must not be smaller than adam_steps = {adam_steps}"
            )));
        }
        if self.max_steps == 0 || self.rung_window == 0 {
            return Err(AdamError::Parameter(
                "max_steps and rung_window must be at least 1".into(),
            ));
        }
        Ok(())
    }

    /// The protocol this run follows: `threshold` whenever `target_phi` is set.
    pub fn effective_protocol(&self) -> Protocol {
        if self.target_phi.is_some() {
            Protocol::Threshold
        } else {
            self.protocol
        }
    }

    /// The ADAM chain's schedule (last ADAM step, last AMSGrad step, Verlet damping), with each
    /// `None` resolved for the protocol the run follows.
    pub fn stage_schedule(&self) -> (u64, u64, f64) {
        let (a, m, g) = match self.effective_protocol() {
            Protocol::Threshold => (2500, 4000, 0.02),
            Protocol::Pressure => (500, 1000, 0.01),
            // ADAM throughout (RCPGenerator 1.0 never switches).
            Protocol::Rcpgenerator => (u64::MAX, u64::MAX, 0.0),
        };
        (
            self.adam_steps.unwrap_or(a),
            self.amsgrad_steps.unwrap_or(m),
            self.verlet_damping.unwrap_or(g),
        )
    }

    /// The relative φ change per `rung_window` that ends a rung as stalled, for overlaps
    /// measured on `scale`: `rung_phi_tol`, or its default for that scale.
    pub(crate) fn stall_tolerance(&self, scale: OverlapScale) -> f64 {
        self.rung_phi_tol.unwrap_or(match scale {
            OverlapScale::Relative => 1e-5,
            OverlapScale::Absolute => 3e-5,
        })
    }

    /// RCPGenerator protocol: the largest ADAM step in container lengths for dimension `d`.
    pub fn box_alpha_for(&self, d: usize) -> f64 {
        self.box_alpha.unwrap_or(match d {
            2 => 0.005,
            3 => 0.0045,
            4 => 0.0035,
            _ => 0.0025,
        })
    }

    /// RCPGenerator protocol: the first rung's length for `n` particles in dimension `d`.
    pub fn first_rung_steps_for(&self, n: usize, d: usize) -> u64 {
        self.first_rung_steps
            .unwrap_or_else(|| (6000.0 + 9.0 * ((n * d) as f64).sqrt()).max(1500.0) as u64)
    }

    /// The φ floor for dimension `d`: `phi_min` or half the expected jamming density.
    pub fn phi_floor(&self, d: usize) -> f64 {
        self.phi_min
            .unwrap_or_else(|| 0.5 * expected_jamming_density(d))
    }
}

/// `Ok` when `v` is a positive finite number.
fn positive(name: &str, v: f64) -> Result<(), AdamError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(AdamError::Parameter(format!(
            "{name} = {v} must be a positive finite number"
        )))
    }
}

/// `Ok` when `v` lies strictly between 0 and 1.
fn fraction(name: &str, v: f64) -> Result<(), AdamError> {
    if v > 0.0 && v < 1.0 {
        Ok(())
    } else {
        Err(AdamError::Parameter(format!(
            "{name} = {v} must lie strictly between 0 and 1"
        )))
    }
}

/// Rough jamming density of monodisperse spheres in `d` dimensions, used only to pick the φ
/// floor: 0.84 in 2D, the fit φ ≈ 2^−d (2.56 d − 2.72) of Skoge et al. (2006) above.
pub fn expected_jamming_density(d: usize) -> f64 {
    if d <= 2 {
        0.84
    } else {
        (2.56 * d as f64 - 2.72) * 0.5f64.powi(d as i32)
    }
}
