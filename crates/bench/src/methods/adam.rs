//! `adam` and `fire`: Desmond–Weeks expansion–contraction (packbench-adam).

use packbench_adam::{Params, run};

use super::flags::{FlagValue, MethodFlag};
use super::method_error;
use super::packer::Packer;

/// The options of `pack` both minimisers take; FIRE adds its time step.
const FLAGS: [MethodFlag; 4] = [
    MethodFlag::number(
        "target-phi",
        "target_phi",
        "Grow to this φ and stop overlap-free (below jamming; DEM initial conditions).",
    ),
    MethodFlag::new(
        "protocol",
        "protocol",
        FlagValue::Text,
        "threshold (seed 000's inflate/deflate loop) or pressure (diameter scale minimised against a pressure term lowered in rungs).",
    ),
    MethodFlag::number(
        "mu-min",
        "mu_min",
        "Pressure protocol: the run ends after the rung whose μ falls below this; smaller is closer to hard-sphere jamming (overlaps of order μ) and slower. The accuracy knob.",
    ),
    MethodFlag::number(
        "delta-phi-tol",
        "delta_phi_tol",
        "Threshold protocol: final Δφ step tolerance (termination).",
    ),
];

/// ADAM → AMSGrad → overdamped Verlet (seed 000).
pub static ADAM: Packer<Params> = Packer {
    name: "adam",
    summary: "soft-sphere inflate/deflate (Desmond & Weeks), ADAM → AMSGrad → Verlet minimiser (RCPGenerator)",
    knob: "mu_min",
    jammed_terminations: &[],
    defaults: Params::default,
    flags: &FLAGS,
    validate: |p| p.validate().map_err(|e| method_error("adam", e)),
    run: |s, p, o| run(s, p, o).map_err(|e| method_error("adam", e)),
    resume: None,
};

/// The same protocol minimised by FIRE (seed 004).
pub static FIRE: Packer<Params> = Packer {
    name: "fire",
    summary: "the same inflate/deflate protocol with the FIRE minimiser (Particle Assembler)",
    knob: "mu_min",
    jammed_terminations: &[],
    defaults: Params::fire,
    flags: &[
        FLAGS[0],
        FLAGS[1],
        FLAGS[2],
        FLAGS[3],
        MethodFlag::number("dt-max", "fire_dt_max", "Largest FIRE time step."),
    ],
    validate: |p| p.validate().map_err(|e| method_error("fire", e)),
    run: |s, p, o| run(s, p, o).map_err(|e| method_error("fire", e)),
    resume: None,
};
