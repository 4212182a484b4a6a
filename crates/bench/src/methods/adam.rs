//! `adam` and `fire`: Desmond–Weeks expansion–contraction (packbench-adam).

use packbench_adam::{Params, run};

use super::packer::Packer;

/// ADAM → AMSGrad → overdamped Verlet (seed 000).
pub static ADAM: Packer<Params> = Packer {
    name: "adam",
    summary: "soft-sphere inflate/deflate (Desmond & Weeks), ADAM → AMSGrad → Verlet minimiser (RCPGenerator)",
    knob: "delta_phi_tol",
    defaults: Params::default,
    run: |s, p, o| run(s, p, o).map_err(|e| e.to_string()),
    resume: None,
};

/// The same protocol minimised by FIRE (seed 004).
pub static FIRE: Packer<Params> = Packer {
    name: "fire",
    summary: "the same inflate/deflate protocol with the FIRE minimiser (Particle Assembler)",
    knob: "delta_phi_tol",
    defaults: Params::fire,
    run: |s, p, o| run(s, p, o).map_err(|e| e.to_string()),
    resume: None,
};
