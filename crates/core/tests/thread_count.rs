//! The analysis gives the same numbers, to the bit, on one rayon thread and on two: the
//! headline metrics with force balance and the whole structure report (S(k) is the part
//! computed in parallel).

use packbench_core::analysis::structure::{StructureOptions, analyze_structure};
use packbench_core::analysis::{AnalysisOptions, analyze};
use packbench_core::init::initial_packing;
use packbench_core::scene::{Placement, Scene};
use packbench_core::{Container, SizeDistribution};

#[test]
fn analysis_is_bit_identical_on_one_and_two_threads() {
    // Poisson centres at φ = 0.6 overlap: a dense contact network, rattlers and a force solve.
    let scene = Scene {
        n: 400,
        distribution: SizeDistribution::Bidisperse {
            d1: 1.0,
            d2: 1.4,
            p: 0.5,
        },
        container: Container::periodic_box(&[1.0, 1.0, 1.0]).unwrap(),
        phi: 0.6,
        seed: Some(3),
        placement: Placement::Poisson,
    };
    let packing = initial_packing(&scene, 3).unwrap();
    let both = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let m = analyze(&packing, &AnalysisOptions::default()).unwrap();
                let s = analyze_structure(&packing, &StructureOptions::default()).unwrap();
                (m, s)
            })
    };
    let (m1, s1) = both(1);
    let (m2, s2) = both(2);
    assert!(m1.contacts > 0 && m1.force_balance.is_some(), "{m1:?}");
    assert!(!s1.structure_factor.as_ref().unwrap().k.is_empty());
    // Bitwise: serialised floats are equal exactly when their bits are.
    assert_eq!(
        serde_json::to_string(&m1).unwrap(),
        serde_json::to_string(&m2).unwrap()
    );
    assert_eq!(
        serde_json::to_string(&s1).unwrap(),
        serde_json::to_string(&s2).unwrap()
    );
}
