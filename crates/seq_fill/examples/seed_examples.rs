//! Reproduces the run examples of Black & Cheviakov 2022: Examples 1A, 1B (Method 1,
//! Weibull radii), 2 (Method 2, Gamma radii) and 3A (the hemisphere-cut cube), printing sphere
//! counts, fill fractions and times; then one large bed timed.
//!
//! `cargo run --release -p packbench-seqfill --example seed_examples [-- big N_BRICKS_XY]`

use std::time::Instant;

use packbench_core::SizeDistribution;
use packbench_core::run::NullObserver;
use packbench_seqfill::{Params, SeqFillOutcome, Variant, run};

/// Mean radius of the seed's Weibull radii, λΓ(1 + 1/k) with λ = 15.7 µm, k = 3.55 (eqn 2.3).
const WEIBULL_MEAN_R: f64 = 14.136_712_421_627_204;

fn report(name: &str, p: &Params) -> SeqFillOutcome {
    let t = Instant::now();
    let out = run(p, &mut NullObserver).expect("seed example parameters are valid");
    let s = t.elapsed().as_secs_f64();
    let faces: Vec<String> = out
        .face_fractions
        .iter()
        .map(|f| format!("{f:.3}"))
        .collect();
    let discarded = out.radii_discarded.len();
    let drawn = discarded + out.radii_placed.len();
    println!(
        "{name}: unit brick N = {}, total N = {}, body fraction {:.3}, face fractions [{}], contacts {}, mean z {:.2}, discarded {}/{} draws, placed mean radius / r̄ = {:.3}, {}, time {:.3} s",
        out.unit_brick_spheres,
        out.outcome.packing.n(),
        out.body_fraction,
        faces.join(", "),
        out.contacts.len(),
        2.0 * out.contacts.len() as f64 / out.outcome.packing.n() as f64,
        discarded,
        drawn,
        out.radii_placed.iter().sum::<f64>()
            / out.radii_placed.len().max(1) as f64
            / out.mean_radius,
        out.outcome.termination,
        s
    );
    out
}

fn main() {
    let weibull = SizeDistribution::Weibull {
        scale: 31.4,
        shape: 3.55,
    };
    let mut ex1a = Params::default();
    // Search budgets can be overridden to study their effect: SEQ_TRIES, SEQ_RETRIES, SEQ_ACCEPT_PERCENT.
    let env = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<usize>().ok());
    if let Some(v) = env("SEQ_TRIES") {
        ex1a.tuples_per_draw = v;
    }
    if let Some(v) = env("SEQ_RETRIES") {
        ex1a.tuple_retries = v as u32;
    }
    if let Some(v) = env("SEQ_ACCEPT_PERCENT") {
        ex1a.min_acceptance = v as f64 / 100.0;
    }
    let args: Vec<String> = std::env::args().collect();
    if args.get(1).map(String::as_str) == Some("big") {
        let n: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(18);
        let p = Params {
            brick_lengths: vec![30.0 * WEIBULL_MEAN_R; 3],
            brick_numbers: vec![n, n, 1],
            ..ex1a
        };
        report(&format!("Method 1, 30 r̄ bricks, {n}×{n}×1"), &p);
        let p2 = Params {
            variant: Variant::Method2,
            face_goal: 1.0,
            body_goal: 0.9,
            contact_param: 0.1,
            ..p.clone()
        };
        report(&format!("Method 2, 30 r̄ bricks, {n}×{n}×1"), &p2);
        return;
    }
    if args.get(1).map(String::as_str) == Some("single") {
        let side: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(60.0);
        let p = Params {
            brick_lengths: vec![side * WEIBULL_MEAN_R; 3],
            brick_numbers: vec![1, 1, 1],
            ..ex1a
        };
        report(&format!("Method 1, one brick of side {side} r̄"), &p);
        return;
    }
    report("Example 1A (Method 1, 15 r̄, ε 0.2)", &ex1a);
    report(
        "Example 1A (Method 1, 15 r̄, ε 0.1)",
        &Params {
            contact_param: 0.1,
            ..ex1a.clone()
        },
    );
    let ex1b = Params {
        brick_lengths: vec![30.0 * WEIBULL_MEAN_R; 3],
        ..ex1a.clone()
    };
    report("Example 1B (Method 1, 30 r̄, ε 0.2)", &ex1b);
    report(
        "Example 1B (Method 1, 30 r̄, ε 0.1)",
        &Params {
            contact_param: 0.1,
            ..ex1b.clone()
        },
    );
    let gamma_mean_r = 14.0;
    let ex2 = Params {
        variant: Variant::Method2,
        distribution: SizeDistribution::Gamma {
            shape: 2.0,
            scale: 14.0,
        },
        face_goal: 1.0,
        body_goal: 0.9,
        contact_param: 0.1,
        brick_lengths: vec![30.0 * gamma_mean_r; 3],
        ..ex1a.clone()
    };
    report("Example 2 (Method 2, Gamma, 30 r̄, ε 0.1)", &ex2);
    report(
        "Example 2 (Method 2, Gamma, 15 r̄, ε 0.1)",
        &Params {
            brick_lengths: vec![15.0 * gamma_mean_r; 3],
            ..ex2.clone()
        },
    );
    report(
        "Method 2 with Weibull (seed Table 3), 30 r̄, ε 0.1",
        &Params {
            distribution: weibull.clone(),
            brick_lengths: vec![30.0 * WEIBULL_MEAN_R; 3],
            ..ex2.clone()
        },
    );
    let side = 30.0 * WEIBULL_MEAN_R;
    report(
        "Example 3A (hemisphere-cut cube, 30 r̄, R = 0.5·30 r̄)",
        &Params {
            brick_lengths: vec![side; 3],
            brick_numbers: vec![1, 1, 1],
            hemispheres: Some([0.5 * side, 0.5 * side]),
            face_goal: 0.4,
            body_goal: 0.4,
            contact_param: 0.1,
            ..ex1a.clone()
        },
    );
    report(
        "Example 3B (hemisphere-cut brick 1.3×1×1 · 30 r̄, R = 0.2, 0.4 · 30 r̄)",
        &Params {
            brick_lengths: vec![1.3 * side, side, side],
            brick_numbers: vec![1, 1, 1],
            hemispheres: Some([0.2 * side, 0.4 * side]),
            face_goal: 0.4,
            body_goal: 0.4,
            contact_param: 0.2,
            ..ex1a
        },
    );
}
