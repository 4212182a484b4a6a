//! `ls` and `mls`: event-driven Lubachevsky–Stillinger and its MLS schedule (packbench-mls).

use packbench_mls::{Checkpoint, LsParams, MlsParams, resume_mls, run_ls, run_mls};

use super::packer::Packer;

/// LS at a fixed compression rate from a Poisson start.
pub static LS: Packer<LsParams> = Packer {
    name: "ls",
    summary: "event-driven hard spheres growing at a fixed rate γ until the reduced pressure reaches the cap",
    knob: "rate",
    defaults: LsParams::default,
    run: |s, p, o| run_ls(s, p, o).map_err(|e| e.to_string()),
    resume: None,
};

/// MLS: the closest-jamming search of Baranau & Tallarek (seed 001 §III).
pub static MLS: Packer<MlsParams> = Packer {
    name: "mls",
    summary: "LS whose rate is halved each time the pressure reaches 1e12, with equilibration, until jammed",
    knob: "rate_final",
    defaults: MlsParams::default,
    run: |s, p, o| run_mls(s, p, o).map_err(|e| e.to_string()),
    resume: Some(|c, p, o| {
        let checkpoint: Checkpoint = serde_json::from_value(c.clone())
            .map_err(|e| format!("not an mls checkpoint ({e})"))?;
        resume_mls(&checkpoint, p, o).map_err(|e| e.to_string())
    }),
};
