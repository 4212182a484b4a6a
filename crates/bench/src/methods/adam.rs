//! `adam` and `fire`: Desmond–Weeks expansion–contraction (packbench-adam).

use packbench_adam::{Params, run};

use serde_json::{Map, Value};

use super::flags::{FlagValue, MethodFlag};
use super::method_error;
use super::packer::Packer;
use super::stop_progress::{StopMeasure, number};

/// The options of `pack` both minimisers take; FIRE adds its time step, ADAM the stop
/// tolerance of its default (RCPGenerator) protocol.
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
        "rcpgenerator (adam's default: RCPGenerator 1.0's schedule, jams where it jams), pressure (fire's default; μ lowered in rungs balanced relative to μ: 1.7–5× faster, 0.003–0.004 denser in 3D at N = 10³) or threshold (RCPGenerator 1.0's inflate/deflate loop).",
    ),
    MethodFlag::number(
        "mu-min",
        "mu_min",
        "Pressure protocol: the run ends after the rung whose μ falls below this; smaller is closer to hard-sphere jamming (overlaps of order μ) and slower. fire's accuracy knob.",
    ),
    MethodFlag::number(
        "delta-phi-tol",
        "delta_phi_tol",
        "Threshold protocol: final Δφ step tolerance (termination).",
    ),
];

/// The way to the stopping rule of either minimiser: RCPGenerator's schedule and a target φ
/// report their own fraction; the pressure protocol lowers μ from `mu_start` to `mu_min` in
/// rungs, the threshold protocol Δφ down to `delta_phi_tol`, both geometric.
fn stop_measures(params: &Map<String, Value>) -> Vec<StopMeasure> {
    let protocol = params.get("protocol").and_then(Value::as_str);
    if protocol == Some("rcpgenerator") || number(params, "target_phi").is_some() {
        return vec![StopMeasure::Reported];
    }
    vec![
        StopMeasure::LogTo {
            quantity: Some("mu"),
            start: number(params, "mu_start"),
            target: number(params, "mu_min"),
        },
        StopMeasure::LogTo {
            quantity: Some("delta_phi"),
            start: None,
            target: number(params, "delta_phi_tol"),
        },
    ]
}

/// The note on the parameters both soft-sphere methods leave null until a run decides them.
const PER_RUN_DEFAULTS: &str = "null in the defaults: decided per run from the protocol, the \
     dimension or the size ratio; a run's JSON gives the values it used under `extra`.";

/// RCPGenerator 1.0's schedule (ADAM throughout); RCPGenerator 1.0's chain ADAM → AMSGrad →
/// overdamped Verlet under the other protocols.
pub static ADAM: Packer<Params> = Packer {
    name: "adam",
    summary: "soft spheres compressed by a pressure on RCPGenerator 1.0's schedule, ADAM throughout (Desmond & Weeks; RCPGenerator)",
    knob: "stop_overlap",
    jammed_terminations: &[],
    defaults: Params::default,
    flags: &[
        FLAGS[0],
        FLAGS[1],
        FLAGS[2],
        FLAGS[3],
        MethodFlag::number(
            "stop-overlap",
            "stop_overlap",
            "RCPGenerator protocol: the run stops once the largest overlap stays below this (default 5e-4); smaller is closer to hard-sphere contact. The accuracy knob.",
        ),
    ],
    validate: |p| p.validate().map_err(|e| method_error("adam", e)),
    run: |s, p, o| run(s, p, o).map_err(|e| method_error("adam", e)),
    resume: None,
    budget_key: Some("max_steps"),
    seed_key: None,
    snapshot_key: Some("save_interval"),
    frame_interval: |_| 10,
    stop_measures,
    step_unit: "minimiser steps",
    notes: PER_RUN_DEFAULTS,
};

/// The same protocol minimised by FIRE (Particle Assembler).
pub static FIRE: Packer<Params> = Packer {
    name: "fire",
    summary: "soft spheres under a pressure lowered in rungs, FIRE minimiser (Particle Assembler)",
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
    budget_key: Some("max_steps"),
    seed_key: None,
    snapshot_key: Some("save_interval"),
    frame_interval: |_| 10,
    stop_measures,
    step_unit: "minimiser steps",
    notes: PER_RUN_DEFAULTS,
};
