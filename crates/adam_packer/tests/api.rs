//! Parameters, errors and the observer contract.

mod common;
use common::*;

use packbench_adam::{AdamError, Params};
use packbench_core::Packing;
use packbench_core::run::{Observer, Progress};

fn refused(params: Params, field: &str) {
    let err = pack(&start(20, mono(), periodic(3), 0.05, 1), &params).unwrap_err();
    assert!(matches!(err, AdamError::Parameter(_)), "{err}");
    assert!(err.to_string().contains(field), "{err}");
}

#[test]
fn bad_parameters_are_named() {
    refused(
        Params {
            delta_phi0: -1.0,
            ..Params::default()
        },
        "delta_phi0",
    );
    refused(
        Params {
            beta1: 1.5,
            ..Params::default()
        },
        "beta1",
    );
    refused(
        Params {
            lr_adam: f64::NAN,
            ..Params::default()
        },
        "lr_adam",
    );
    refused(
        Params {
            fire_dt: 2.0,
            ..fire()
        },
        "fire_dt",
    );
    refused(
        Params {
            target_phi: Some(1.2),
            ..fire()
        },
        "target_phi",
    );
    refused(
        Params {
            max_steps: 0,
            ..fire()
        },
        "max_steps",
    );
    refused(
        Params {
            target_phi: Some(0.01),
            ..fire()
        },
        "target_phi",
    );
}

#[test]
fn params_round_trip_through_json_with_defaults() {
    let p: Params = serde_json::from_str(r#"{"minimizer":"fire","fire_dt_max":0.4}"#).unwrap();
    assert_eq!(p.fire_dt_max, 0.4);
    assert_eq!(p.delta_phi0, 1.5 * 1.5e-3);
    assert_eq!(p.energy_threshold, 6.25e-8);
    let back: Params = serde_json::from_str(&serde_json::to_string(&p).unwrap()).unwrap();
    assert_eq!(back, p);
}

#[test]
fn empty_and_invalid_packings_are_refused() {
    let empty = Packing {
        dim: 3,
        positions: vec![],
        diameters: vec![],
        container: periodic(3),
    };
    assert!(
        pack(&empty, &fire())
            .unwrap_err()
            .to_string()
            .contains("no particles")
    );
    let mut bad = start(10, mono(), periodic(3), 0.05, 2);
    bad.diameters[3] = f64::NAN;
    assert!(matches!(
        pack(&bad, &fire()).unwrap_err(),
        AdamError::Packing(_)
    ));
}

#[derive(Default)]
struct Recorder {
    snapshots: Vec<u64>,
    progress: usize,
    stop_after: Option<usize>,
}

impl Observer for Recorder {
    fn progress(&mut self, _p: &Progress) {
        self.progress += 1;
    }
    fn snapshot(&mut self, step: u64, packing: &Packing) {
        packing.validate().expect("a snapshot is a valid packing");
        assert!(packing.n() > 0, "a snapshot without particles");
        self.snapshots.push(step);
    }
    fn should_stop(&self) -> bool {
        self.stop_after.is_some_and(|k| self.snapshots.len() >= k)
    }
}

#[test]
fn snapshots_and_interrupts() {
    let s = start(100, mono(), periodic(3), 0.05, 3);
    let params = Params {
        save_interval: 100,
        ..fire()
    };
    let mut rec = Recorder {
        stop_after: Some(5),
        ..Recorder::default()
    };
    let out = packbench_adam::run(&s, &params, &mut rec).unwrap();
    assert_eq!(out.termination, "interrupted");
    // Stopped at the first step after the fifth snapshot was asked for.
    assert_eq!(rec.snapshots, [100, 200, 300, 400, 500]);
    assert!(out.packing.phi() > 0.3);
    assert!(out.packing.positions.iter().all(|v| v.is_finite()));
}

#[test]
fn max_steps_is_reported_with_the_densest_low_energy_state() {
    let params = Params {
        max_steps: 600,
        ..fire()
    };
    let out = pack(&start(100, mono(), periodic(3), 0.05, 4), &params).unwrap();
    assert_eq!(out.termination, "max_steps");
    assert_eq!(out.steps, 600);
    assert!(!out.trace.is_empty());
}

/// A mask of held diameters that names no particle, holds every one, or meets fix-height is
/// refused with a sentence naming `fixed_diameters`; so is a φ the held spheres alone exceed.
#[test]
fn held_diameters_out_of_range_are_refused() {
    let s = start(20, mono(), periodic(3), 0.05, 1);
    for (held, words) in [
        (vec![3, 20], "names particle 20"),
        ((0..20).collect(), "holds every diameter"),
    ] {
        let params = Params {
            fixed_diameters: held,
            ..Params::default()
        };
        let err = pack(&s, &params).unwrap_err().to_string();
        assert!(
            err.contains("fixed_diameters") && err.contains(words),
            "{err}"
        );
    }
    let mut c =
        packbench_core::Container::with_flags(&[1.0, 1.0, 4.0], &[false, false, true]).unwrap();
    c.fix_height = Some(4.0);
    let tall = start(20, mono(), c, 0.05, 1);
    let params = Params {
        fixed_diameters: vec![0],
        ..Params::default()
    };
    let err = pack(&tall, &params).unwrap_err().to_string();
    assert!(err.contains("fix-height"), "{err}");
    // Two large spheres held at φ 0.5 of the box on their own: the schedule's φ 0.33 start
    // cannot be set by shrinking the others.
    let big = Packing::new(
        vec![
            0.25, 0.25, 0.25, 0.75, 0.75, 0.75, 0.5, 0.5, 0.5, 0.1, 0.9, 0.5,
        ],
        vec![0.78, 0.78, 0.05, 0.05],
        packbench_core::Container::periodic_box(&[1.0, 1.0, 1.0]).unwrap(),
    )
    .unwrap();
    let params = Params {
        fixed_diameters: vec![0, 1],
        ..Params::default()
    };
    let err = pack(&big, &params).unwrap_err().to_string();
    assert!(err.contains("held fill"), "{err}");
}
