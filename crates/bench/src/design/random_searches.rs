//! Robustness of the search: fifty random families, bounds, objectives, dimensions and N (small,
//! so that the whole takes seconds), each of which must end with a report — never an error, a
//! panic or a NaN in the best distribution — however many of its candidates are invalid,
//! screened out or fail to pack.

use packbench_core::Container;
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};

use super::family::{Draw, Family, Fractions, Shape};
use super::objective::{Constraints, Objective};
use super::optimizer::Optimizer;
use super::screen::Screen;
use super::{DesignConfig, design, report};
use crate::runs::QuietObserver;

const NAMES: [&str; 7] = [
    "lognormal",
    "powerlaw",
    "bidisperse",
    "weibull",
    "gamma",
    "mixture",
    "discrete",
];

/// A random interval inside each parameter's default one; sometimes a single value (fixed),
/// sometimes a mixture's weight pinned at 0 so that whole candidates have no distribution.
fn random_bounds(family: &mut Family, rng: &mut StdRng) {
    let params = family.params.clone();
    for p in &params {
        let roll: f64 = rng.random();
        let a = p.lo + (p.hi - p.lo) * rng.random::<f64>();
        let b = p.lo + (p.hi - p.lo) * rng.random::<f64>();
        let (lo, hi) = if roll < 0.15 {
            (a, a)
        } else if roll < 0.3 && p.name.starts_with('w') {
            (0.0, 0.0)
        } else {
            (a.min(b), a.max(b))
        };
        family
            .set_range(&p.name, lo, hi)
            .expect("inside the domain");
    }
    // Keep one weight of a mixture free above 0 and one parameter free, as `validate` asks.
    if let Some(w) = family.params.iter_mut().find(|p| p.name.starts_with('w')) {
        w.lo = 0.0;
        w.hi = 1.0;
    }
    if !family.params.iter().any(|p| p.is_free()) {
        family.params[0] = params[0].clone();
    }
}

/// A random search that [`DesignConfig::check`] accepts.
fn random_config(rng: &mut StdRng) -> DesignConfig {
    let dim = if rng.random::<f64>() < 0.5 { 2 } else { 3 };
    let name = NAMES[rng.random_range(0..NAMES.len())];
    let shape = Shape {
        components: rng.random_range(if name == "discrete" { 2 } else { 1 }..=3),
        max_ratio: Some(1.5 + 3.0 * rng.random::<f64>()),
        dim,
        fractions: if rng.random::<f64>() < 0.5 {
            Fractions::Volume
        } else {
            Fractions::Number
        },
        draw: if rng.random::<f64>() < 0.5 {
            Draw::Quantile
        } else {
            Draw::Random
        },
    };
    let mut family = Family::with_defaults(name, &shape).expect("a known family");
    random_bounds(&mut family, rng);
    let target = 0.55 + 0.2 * rng.random::<f64>();
    let objective = match rng.random_range(0..4) {
        0 => Objective::MaxPhi,
        1 => Objective::Target { target },
        2 => Objective::MinRatio { target },
        _ => Objective::MinPolydispersity { target },
    };
    let n = rng.random_range(6..=24);
    let mut scene = crate::args::default_scene();
    scene.n = n;
    scene.container = Container::periodic_box(&vec![1.0; dim]).expect("a unit box");
    let population = rng.random_range(2..=5);
    let seeds_per_candidate = rng.random_range(1..=2);
    let max_ratio = family.ratio_constraint(shape.max_ratio);
    DesignConfig {
        family,
        objective,
        constraints: Constraints::new((rng.random::<f64>() < 0.3).then(|| rng.random::<f64>()))
            .expect("a fraction"),
        max_ratio,
        search_n: (rng.random::<f64>() < 0.3).then(|| rng.random_range(4..=n)),
        scene,
        method: "adam".into(),
        refine: None,
        overrides: Vec::new(),
        seeds_per_candidate,
        base_seed: rng.random_range(1..1000),
        budget: population * seeds_per_candidate as usize * rng.random_range(1..=3),
        population: Some(population),
        optimizer: Optimizer::Cmaes,
        screen: [Screen::DesmondWeeks, Screen::FarrGroot, Screen::None][rng.random_range(0..3)],
        screen_margin: 0.01,
        confirm: rng.random_range(0..=2),
    }
}

#[test]
fn fifty_random_searches_each_end_with_a_report() {
    let mut rng = StdRng::seed_from_u64(84);
    let dir =
        std::env::temp_dir().join(format!("packbench-random-searches-{}", std::process::id()));
    for i in 0..50 {
        let config = random_config(&mut rng);
        let what = format!(
            "search {i}: {} {:?} {:?} N = {}",
            config.family.name(),
            config.family.params,
            config.objective,
            config.scene.n
        );
        config.check(1).unwrap_or_else(|e| panic!("{what}: {e}"));
        let out = design(&config, Some(1), || Box::new(QuietObserver), |_| Ok(()))
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        let folder = dir.join(i.to_string());
        std::fs::create_dir_all(&folder).expect("a folder");
        report::write_outputs(&folder, &config, &out.rows, out.best.as_ref(), &out.stop)
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        let md = std::fs::read_to_string(folder.join("report.md")).expect("report.md");
        assert!(md.contains("Stopped: "), "{what}: {md}");
        assert!(
            out.packings <= config.budget,
            "{what}: {} packings",
            out.packings
        );
        if let Some(b) = &out.best {
            assert!(
                b.search_phi.is_finite() && b.search_phi > 0.0,
                "{what}: {b:?}"
            );
            assert!(b.values.iter().all(|v| v.is_finite()), "{what}: {b:?}");
            assert_eq!(b.diameters.len(), config.scene.n, "{what}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
