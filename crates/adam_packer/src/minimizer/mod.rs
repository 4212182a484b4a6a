//! Minimizers of the overlap energy. They know nothing about spheres: each sees generalised
//! coordinates `q`, the force `F = −∂U/∂q` and, per coordinate, a length unit `ℓ_k = κ·unit0_k`
//! (for a position, its particle's current contact length, about its diameter). Gradients are
//! measured in these units (ADAM) and masses are `1/ℓ_k²` (Verlet, FIRE), so a small sphere among
//! large ones is neither too stiff nor too slow.
//!
//! [`Relaxer`] runs RCPGenerator 1.0's schedule — ADAM, then AMSGrad, then overdamped Verlet, switched
//! by step number — or FIRE throughout.

mod adam;
mod fire;
mod overdamped_verlet;

use adam::Adam;
use fire::Fire;
use overdamped_verlet::OverdampedVerlet;

use crate::params::{Minimizer, Params};

/// The stage a [`Relaxer`] is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stage {
    Adam,
    AmsGrad,
    Verlet,
    Fire,
}

impl Stage {
    /// Snake-case name for traces.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Adam => "adam",
            Stage::AmsGrad => "amsgrad",
            Stage::Verlet => "verlet",
            Stage::Fire => "fire",
        }
    }
}

/// One minimizer with its schedule.
pub(crate) struct Relaxer {
    stage: Stage,
    adam: Option<Adam>,
    verlet: Option<OverdampedVerlet>,
    fire: Option<Fire>,
    adam_steps: u64,
    amsgrad_steps: u64,
    params: Params,
    len: usize,
}

impl Relaxer {
    /// A relaxer for `len` coordinates.
    pub fn new(params: &Params, len: usize) -> Self {
        let mut r = Relaxer {
            stage: Stage::Adam,
            adam: None,
            verlet: None,
            fire: None,
            adam_steps: params.stage_schedule().0,
            amsgrad_steps: params.stage_schedule().1,
            params: params.clone(),
            len,
        };
        match params.minimizer {
            Minimizer::Fire => {
                r.stage = Stage::Fire;
                r.fire = Some(Fire::new(params, len));
            }
            Minimizer::Adam => r.enter_stage(Stage::Adam),
        }
        r
    }

    fn enter_stage(&mut self, stage: Stage) {
        self.stage = stage;
        match stage {
            Stage::Adam => self.adam = Some(Adam::new(&self.params, self.len)),
            // AMSGrad keeps ADAM's moments and switches on the running maximum (RCPGenerator 1.0).
            Stage::AmsGrad => {
                if let Some(a) = &mut self.adam {
                    a.switch_to_amsgrad(&self.params);
                }
            }
            Stage::Verlet => {
                self.adam = None;
                self.verlet = Some(OverdampedVerlet::new(&self.params, self.len));
            }
            Stage::Fire => {}
        }
    }

    /// The current stage.
    pub fn stage(&self) -> Stage {
        self.stage
    }

    /// Sets ADAM's learning rate for the next steps (RCPGenerator's adaptive α); no effect on
    /// the other stages.
    pub fn set_learning_rate(&mut self, lr: f64) {
        if let Some(a) = &mut self.adam {
            a.set_learning_rate(lr);
        }
    }

    /// One minimisation step at protocol step `step` (1-based).
    pub fn step(&mut self, step: u64, q: &mut [f64], force: &[f64], unit0: &[f64], kappa: f64) {
        if self.stage == Stage::Adam && step > self.adam_steps {
            self.enter_stage(Stage::AmsGrad);
        }
        if self.stage == Stage::AmsGrad && step > self.amsgrad_steps {
            self.enter_stage(Stage::Verlet);
        }
        match self.stage {
            Stage::Adam | Stage::AmsGrad => self
                .adam
                .as_mut()
                .expect("ADAM state exists in its stages")
                .step(q, force, unit0, kappa),
            Stage::Verlet => self
                .verlet
                .as_mut()
                .expect("Verlet state exists in its stage")
                .step(q, force, unit0, kappa),
            Stage::Fire => self
                .fire
                .as_mut()
                .expect("FIRE state exists in its stage")
                .step(q, force, unit0, kappa),
        }
    }
}
