//! The growth protocols and the bookkeeping they share: the [`Driver`] owns the system, its
//! neighbour list, the force buffer and the minimizer, and talks to the observer (progress a few
//! times per second, snapshots every `save_interval` steps, stop requests), keeps the trace and
//! the densest low-energy state seen so far, and builds the [`Outcome`].

pub(crate) mod pressure;
pub(crate) mod rcpgenerator;
pub(crate) mod threshold;

use std::time::Instant;

use packbench_core::Packing;
use packbench_core::neighbor::typical_diameter;
use packbench_core::run::{Observer, Outcome, Progress, TraceRow};
use serde_json::{Map, Value};

use crate::error::AdamError;
use crate::minimizer::Relaxer;
use crate::neighbor_list::NeighborList;
use crate::overlap_energy::{self, Evaluation};
use crate::params::{Minimizer, Params, Protocol};
use crate::system::System;

/// Steps between checks of the clock and of the observer's stop flag.
const POLL_EVERY: u64 = 64;
/// Seconds between progress reports.
const PROGRESS_EVERY_S: f64 = 0.25;

/// A saved state: positions (with trailing coordinates), κ and the container lengths.
struct Saved {
    phi: f64,
    x: Vec<f64>,
    kappa: f64,
    lengths: Vec<f64>,
}

/// Shared state of a run.
pub(crate) struct Driver<'a> {
    pub sys: System,
    pub nl: NeighborList,
    /// Forces on the coordinates of `sys.x` (positions, then trailing coordinates).
    pub force: Vec<f64>,
    /// Scratch of the force loop: each listed pair's force on its row particle.
    reactions: Vec<f64>,
    /// Length unit of each coordinate at κ = 1 (a position's: its particle's contact length,
    /// refreshed at each neighbour-list build).
    pub unit0: Vec<f64>,
    /// Whether `unit0` is refreshed at each build: a protocol with lengths of its own (the
    /// RCPGenerator schedule's box units) turns it off and saves a pass over the list.
    pub jacobi_lengths: bool,
    /// Whether the force loop sums the virial (the pressure protocol's κ-force; off by default).
    pub virial: bool,
    pub relaxer: Relaxer,
    pub params: &'a Params,
    /// The run's expected length in steps, against which progress is reported (`max_steps`
    /// unless the protocol knows better).
    pub expected_steps: u64,
    observer: &'a mut dyn Observer,
    parallel: bool,
    /// Whether the neighbour list refreshes the rows of particles that moved between whole
    /// builds (`Params::neighbor_refresh_min_ratio`).
    refresh_rows: bool,
    started: Instant,
    last_progress: f64,
    trace: Vec<TraceRow>,
    best: Option<Saved>,
}

impl<'a> Driver<'a> {
    /// Sets up a run from `start` with `extra` generalised coordinates after the positions.
    pub fn new(
        start: &Packing,
        params: &'a Params,
        observer: &'a mut dyn Observer,
        extra: usize,
    ) -> Result<Self, AdamError> {
        params.validate()?;
        if start.n() == 0 {
            return Err(AdamError::Parameter(
                "the starting packing has no particles".into(),
            ));
        }
        let mut sys = System::new(start, &params.fixed_diameters)?;
        let d = sys.dim;
        let len = sys.x.len() + extra;
        sys.x.resize(len, 0.0);
        let mut unit0: Vec<f64> = sys
            .d0
            .iter()
            .flat_map(|&v| std::iter::repeat_n(v, d))
            .collect();
        unit0.resize(len, 1.0);
        let parallel = sys.n() >= params.parallel_min_particles;
        // D_max against the diameter the cell lists are sized for.
        let refresh_rows = sys.n() > 1
            && sys.d0_max >= params.neighbor_refresh_min_ratio * typical_diameter(&sys.d0);
        Ok(Driver {
            relaxer: Relaxer::new(params, len),
            force: vec![0.0; len],
            unit0,
            jacobi_lengths: true,
            virial: false,
            nl: NeighborList::new(),
            reactions: Vec::new(),
            sys,
            params,
            expected_steps: params.max_steps,
            observer,
            parallel,
            refresh_rows,
            started: Instant::now(),
            last_progress: 0.0,
            trace: Vec::new(),
            best: None,
        })
    }

    /// Number of position coordinates N·d.
    pub fn n_coords(&self) -> usize {
        self.sys.n() * self.sys.dim
    }

    /// Sets φ through κ, refusing diameters the periodic box cannot hold.
    pub fn set_phi(&mut self, phi: f64) -> Result<(), AdamError> {
        let kappa = self.sys.kappa_for_phi(phi)?;
        self.sys.set_kappa(kappa);
        self.sys.check_own_image()
    }

    /// Updates the neighbour list if needed and evaluates forces and energy.
    pub fn evaluate(&mut self, step: u64) -> Result<Evaluation, AdamError> {
        let nc = self.n_coords();
        // Without Jacobi lengths the list's contents do not enter the path (pairs apart add
        // exact zeros); wrapping particles as they leave the box, rather than at the list's
        // builds, makes the path independent of when the list is rebuilt too, so the skin may
        // follow the step.
        let lifetime = if self.jacobi_lengths {
            0.0
        } else {
            self.sys.wrap_escaped();
            self.params.neighbor_lifetime_steps
        };
        let skin = (self.params.neighbor_skin, self.params.neighbor_skin_max);
        // Rows refreshed one by one list other pairs apart than a whole build would, which
        // only the Jacobi lengths would see.
        let refresh = self.refresh_rows && !self.jacobi_lengths;
        if self.nl.update(&mut self.sys, skin, lifetime, refresh) && self.jacobi_lengths {
            self.nl.contact_lengths(&self.sys, &mut self.unit0[..nc]);
        }
        let ev = overlap_energy::evaluate(
            &self.sys,
            &mut self.nl,
            &mut self.force[..nc],
            &mut self.reactions,
            self.parallel,
            self.virial,
        );
        if !(ev.energy.is_finite() && ev.residual2.is_finite()) {
            return Err(AdamError::NonFinite { step });
        }
        Ok(ev)
    }

    /// The factor n_ref/N that puts this system's energy on the scale of RCPGenerator 1.0's thresholds
    /// (`Params::threshold_n`).
    pub fn intensive(&self) -> f64 {
        self.params.threshold_n / self.sys.n() as f64
    }

    /// The energy on the scale of `energy_threshold`.
    pub fn scaled_energy(&self, ev: &Evaluation) -> f64 {
        ev.energy * self.intensive()
    }

    /// The force norm on the scale of `force_tol`, from its square `residual2`.
    pub fn scaled_force(&self, residual2: f64) -> f64 {
        (residual2 * self.intensive()).sqrt()
    }

    /// Minimises at fixed diameters until the force norm is below `final_force_tol`, for at
    /// most `polish_steps` steps within the step budget, or until the observer asks to stop;
    /// returns the last evaluation.
    pub fn polish(&mut self, step: &mut u64, mut ev: Evaluation) -> Result<Evaluation, AdamError> {
        let nc = self.n_coords();
        let end = self
            .params
            .max_steps
            .min(step.saturating_add(self.params.polish_steps));
        while self.scaled_force(ev.residual2) >= self.params.final_force_tol && *step < end {
            if self.stop_requested(*step) {
                break;
            }
            let kappa = self.sys.kappa;
            self.relaxer.step(
                *step,
                &mut self.sys.x[..nc],
                &self.force[..nc],
                &self.unit0[..nc],
                kappa,
            );
            *step += 1;
            ev = self.evaluate(*step)?;
            self.report(*step, &ev, &[]);
        }
        Ok(ev)
    }

    /// True when the observer asks to stop (checked every few steps).
    pub fn stop_requested(&self, step: u64) -> bool {
        step.is_multiple_of(POLL_EVERY) && self.observer.should_stop()
    }

    /// Progress (throttled), trace rows and snapshots for this step.
    pub fn report(&mut self, step: u64, ev: &Evaluation, values: &[(&'static str, f64)]) {
        let phi = self.sys.phi();
        if step.is_multiple_of(self.params.trace_every) {
            self.push_trace(step, phi, ev, values);
        }
        if step.is_multiple_of(POLL_EVERY) {
            let t = self.started.elapsed().as_secs_f64();
            if t - self.last_progress >= PROGRESS_EVERY_S {
                self.last_progress = t;
                self.observer.progress(&Progress {
                    step,
                    phi,
                    value: ev.energy,
                    label: "energy",
                    fraction: Some((step as f64 / self.expected_steps as f64).min(1.0)),
                    more: values.to_vec(),
                });
            }
        }
        let k = self.params.save_interval;
        if k > 0 && step.is_multiple_of(k) {
            let p = self.sys.to_packing();
            self.observer.snapshot(step, &p);
        }
    }

    fn push_trace(&mut self, step: u64, phi: f64, ev: &Evaluation, values: &[(&str, f64)]) {
        let mut v = vec![
            ("energy".to_string(), ev.energy),
            ("max_overlap".to_string(), ev.max_overlap),
            ("force_residual".to_string(), ev.residual2.sqrt()),
        ];
        v.extend(values.iter().map(|&(k, x)| (k.to_string(), x)));
        self.trace.push(TraceRow {
            step,
            time_s: self.started.elapsed().as_secs_f64(),
            phi,
            values: v,
        });
    }

    /// Remembers the current state if it is the densest low-energy one so far.
    pub fn remember_if_densest(&mut self) {
        let phi = self.sys.phi();
        if self.best.as_ref().is_some_and(|b| b.phi >= phi) {
            return;
        }
        let b = self.best.get_or_insert_with(|| Saved {
            phi,
            x: Vec::new(),
            kappa: 0.0,
            lengths: Vec::new(),
        });
        b.phi = phi;
        b.x.clear();
        b.x.extend_from_slice(&self.sys.x);
        b.kappa = self.sys.kappa;
        b.lengths.clone_from(&self.sys.container.lengths);
    }

    /// Ends the run. With `use_best` the densest low-energy state replaces the current one
    /// (for `max_steps` and `interrupted`, whose current state may be mid-relaxation).
    pub fn finish(
        mut self,
        step: u64,
        last: &Evaluation,
        values: &[(&str, f64)],
        termination: &str,
        use_best: bool,
        mut extra: Map<String, Value>,
    ) -> Outcome {
        let phi = self.sys.phi();
        self.push_trace(step, phi, last, values);
        let mut returned = "current";
        if use_best && let Some(b) = self.best.take() {
            self.sys.x = b.x;
            self.sys.container.lengths = b.lengths;
            let k = b.kappa;
            // set_kappa under fix-height rescales from the restored height, a no-op here.
            self.sys.set_kappa(k);
            returned = "densest_low_energy";
        }
        extra.insert("returned_state".into(), returned.into());
        // The defaults left open (`null`) in the parameters, as this run resolved them.
        extra.insert("phi_min".into(), self.params.phi_floor(self.sys.dim).into());
        if self.params.minimizer == Minimizer::Adam
            && self.params.effective_protocol() != Protocol::Rcpgenerator
        {
            let (adam_steps, amsgrad_steps, verlet_damping) = self.params.stage_schedule();
            extra.insert("adam_steps".into(), adam_steps.into());
            extra.insert("amsgrad_steps".into(), amsgrad_steps.into());
            extra.insert("verlet_damping".into(), verlet_damping.into());
        }
        extra.insert("neighbor_builds".into(), self.nl.builds().into());
        extra.insert("neighbor_pairs".into(), self.nl.pairs().into());
        extra.insert("neighbor_refreshes".into(), self.nl.refreshed().into());
        extra.insert("final_stage".into(), self.relaxer.stage().name().into());
        extra.insert(
            "runtime_s".into(),
            self.started.elapsed().as_secs_f64().into(),
        );
        Outcome {
            packing: self.sys.to_packing(),
            steps: step,
            termination: termination.to_string(),
            trace: self.trace,
            extra,
        }
    }
}
