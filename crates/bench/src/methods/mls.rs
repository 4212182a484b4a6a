//! `ls` and `mls`: event-driven Lubachevsky–Stillinger and its MLS schedule (packbench-mls).

use packbench_mls::{Checkpoint, LsParams, MlsError, MlsParams, resume_mls, run_ls, run_mls};

use super::flags::MethodFlag;
use super::method_error;
use super::packer::Packer;
use super::stop_progress::{StopMeasure, number};

/// The pressure cap both take.
const PRESSURE_CAP: MethodFlag = MethodFlag::number(
    "pressure-cap",
    "pressure_cap",
    "Reduced pressure at which compression stops (ls) or γ is divided (mls) (default 1e12).",
);

/// LS at a fixed compression rate from a Poisson start.
pub static LS: Packer<LsParams> = Packer {
    name: "ls",
    summary: "event-driven hard spheres growing at a fixed rate γ until the reduced pressure reaches the cap",
    knob: "rate",
    jammed_terminations: &[],
    defaults: LsParams::default,
    flags: &[
        MethodFlag::number(
            "rate",
            "rate",
            "Compression rate γ (diameter growth relative to the mean diameter per unit time).",
        ),
        PRESSURE_CAP,
    ],
    validate: |p| p.validate().map_err(|e| method_error("ls", e)),
    run: |s, p, o| run_ls(s, p, o).map_err(|e| method_error("ls", e)),
    resume: None,
    budget_key: Some("max_collisions"),
    seed_key: Some("seed"),
    snapshot_key: Some("save_interval"),
    frame_interval: |n| (n as u64).max(1),
    // The reduced pressure (the report's value) rises geometrically to the cap.
    stop_measures: |params| {
        vec![StopMeasure::LogTo {
            quantity: None,
            start: None,
            target: number(params, "pressure_cap"),
        }]
    },
    step_unit: "collisions",
    notes: "",
};

/// MLS: the closest-jamming search of Baranau & Tallarek (Baranau & Tallarek 2014 §III).
pub static MLS: Packer<MlsParams> = Packer {
    name: "mls",
    summary: "LS whose rate is halved each time the pressure reaches 1e12, with equilibration, until jammed",
    knob: "rate_final",
    jammed_terminations: &[],
    defaults: MlsParams::default,
    flags: &[
        PRESSURE_CAP,
        MethodFlag::number("rate-initial", "rate_initial", "Initial γ (default 10)."),
        MethodFlag::number(
            "rate-factor",
            "rate_factor",
            "Factor γ is divided by at each pressure cap (default 2).",
        ),
        MethodFlag::number(
            "rate-final",
            "rate_final",
            "Stop when γ falls below this (default 1e-4).",
        ),
    ],
    validate: |p| p.validate().map_err(|e| method_error("mls", e)),
    run: |s, p, o| run_mls(s, p, o).map_err(|e| method_error("mls", e)),
    resume: Some(|c, p, o| {
        let checkpoint: Checkpoint = serde_json::from_value(c.clone()).map_err(|e| {
            method_error(
                "mls",
                MlsError::Checkpoint(format!("not an mls checkpoint ({e})")),
            )
        })?;
        resume_mls(&checkpoint, p, o).map_err(|e| method_error("mls", e))
    }),
    budget_key: Some("max_collisions"),
    seed_key: Some("seed"),
    snapshot_key: Some("save_interval"),
    frame_interval: |n| (n as u64).max(1),
    // γ is divided from its first value down to `rate_final`.
    stop_measures: |params| {
        vec![StopMeasure::LogTo {
            quantity: Some("rate"),
            start: None,
            target: number(params, "rate_final"),
        }]
    },
    step_unit: "collisions",
    notes: "with --output it writes NAME.checkpoint.json when interrupted or stopped by \
            --max-steps, and with every --save-interval snapshot; `pack --resume` continues \
            the run from it bit for bit.",
};
