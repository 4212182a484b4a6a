//! Every registered method gives the same bytes on one rayon thread and on two, from the same
//! start with the same parameters: positions, diameters, steps, termination and the core's
//! metrics. adam and fire are made to run their parallel force loop at this small N, and the
//! start is dense so that the exact methods finish in a few steps.

use packbench::methods::{ParamSources, registry};
use packbench::runs::{RunFrom, pack_run};
use packbench_core::analysis::AnalysisOptions;
use packbench_core::init::initial_packing;
use packbench_core::run::NullObserver;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, Packing, SizeDistribution};
use serde_json::Value;

/// What a run leaves that must not depend on the thread count, as bits.
fn fingerprint(run: &packbench::runs::PackRun) -> (Vec<u64>, u64, String, String) {
    let p = &run.outcome.packing;
    let bits = p
        .positions
        .iter()
        .chain(&p.diameters)
        .map(|v| v.to_bits())
        .collect();
    (
        bits,
        run.outcome.steps,
        run.outcome.termination.clone(),
        format!("{:?}", run.metrics),
    )
}

#[test]
fn every_method_gives_the_same_bytes_on_one_and_two_threads() {
    let scene = Scene {
        n: 64,
        distribution: SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 1.4,
            p: 0.5,
        },
        container: Container::periodic_box(&[1.0, 1.0, 1.0]).unwrap(),
        phi: 0.3,
        seed: Some(11),
        placement: Placement::Rsa,
    };
    // A dense, overlap-free start every method takes quickly: an adam packing with its
    // diameters shrunk by 3 % (φ about 0.59), so the exact methods need a few steps only.
    let loose = initial_packing(&scene, 11).unwrap();
    let adam = packbench_adam::run(&loose, &Default::default(), &mut NullObserver).unwrap();
    let p = adam.packing;
    let shrunk = p.diameters.iter().map(|d| 0.97 * d).collect();
    let start = Packing::new(p.positions, shrunk, p.container).unwrap();
    for method in registry() {
        let mut sources = ParamSources {
            seed: Some(11),
            ..Default::default()
        };
        if method
            .default_params()
            .contains_key("parallel_min_particles")
        {
            sources
                .set
                .push(("parallel_min_particles".into(), Value::from(1)));
        }
        let params = sources.resolve(method).unwrap();
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| {
                    let run = pack_run(
                        method,
                        RunFrom::Start(&start),
                        &params,
                        &mut NullObserver,
                        false,
                        &AnalysisOptions::default(),
                    )
                    .unwrap_or_else(|e| panic!("{}: {e}", method.name()));
                    fingerprint(&run)
                })
        };
        let one = on(1);
        let two = on(2);
        assert!(one.1 > 0, "{}: a real run, {} steps", method.name(), one.1);
        assert!(one == two, "{}: one and two threads differ", method.name());
    }
}
