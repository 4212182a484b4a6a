//! Examples 1A and 1B of Black & Cheviakov 2022 (Method 1, Weibull radii λ = 15.7 µm, k = 3.55;
//! FaceGoal 0.8, BodyGoal 0.55, δ = 0.5) at both sphere contact parameters ε = 0.1 and 0.2, one
//! unit cube each, beside their Table 1: the sphere count per unit cube, the contacts ε
//! records, the placed radii's mean against r̄ and their two-sample Kolmogorov–Smirnov test
//! against 20 000 radii drawn afresh from the Weibull.
//!
//! With `overlap`, ε also bounds the overlap of a new sphere with those placed
//! (`Params::contact_overlap`), the other reading of §2.1.
//!
//! `cargo run --release -p packbench-seqfill --example table1 [-- SEEDS [overlap|plain
//! [TUPLES]]]` (default 3 seeds, 1–3; TUPLES: parent tuples a radius tries, default 64)

use packbench_core::SizeDistribution;
use packbench_core::run::NullObserver;
use packbench_seqfill::{Params, radii_against_distribution, run};

/// Mean radius of the Weibull radii, λΓ(1 + 1/k) with λ = 15.7 µm, k = 3.55 (eqn 2.3).
const WEIBULL_MEAN_R: f64 = 14.136_712_421_627_204;

/// Fresh radii the placed ones are tested against.
const FRESH: usize = 20_000;

/// (example, cube side / r̄, ε, Table 1's N per unit cube).
const TABLE1: [(&str, f64, f64, f64); 4] = [
    ("1A", 15.0, 0.1, 450.0),
    ("1A", 15.0, 0.2, 412.0),
    ("1B", 30.0, 0.1, 3075.0),
    ("1B", 30.0, 0.2, 2867.0),
];

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len().max(1) as f64
}

fn main() {
    let seeds: u64 = std::env::args()
        .nth(1)
        .map_or(3, |s| s.parse().expect("SEEDS is a whole number"));
    let contact_overlap = std::env::args().nth(2).is_some_and(|a| a == "overlap");
    let tuples_per_draw = std::env::args()
        .nth(3)
        .map_or(Params::default().tuples_per_draw, |s| {
            s.parse().expect("TUPLES is a whole number")
        });
    println!(
        "| example | ε | Table 1 N | N per cube (seeds) | N / Table 1 | contacts | placed r / r̄ | KS D | KS p |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    for (name, side, eps, published) in TABLE1 {
        let (mut counts, mut contacts, mut radius, mut ks_d, mut ks_p) =
            (vec![], vec![], vec![], vec![], vec![]);
        for seed in 1..=seeds {
            let params = Params {
                brick_lengths: vec![side * WEIBULL_MEAN_R; 3],
                brick_numbers: vec![1, 1, 1],
                contact_param: eps,
                contact_overlap,
                tuples_per_draw,
                seed,
                distribution: SizeDistribution::Weibull {
                    scale: 31.4,
                    shape: 3.55,
                },
                ..Params::default()
            };
            let out = run(&params, &mut NullObserver).expect("Table 1's parameters are valid");
            let ks =
                radii_against_distribution(&out.radii_placed, &params.distribution, FRESH, seed)
                    .expect("the Weibull samples");
            counts.push(out.unit_brick_spheres as f64);
            contacts.push(out.contacts.len() as f64);
            radius.push(mean(&out.radii_placed) / out.mean_radius);
            ks_d.push(ks.d);
            ks_p.push(ks.p_value);
        }
        let n = mean(&counts);
        let max_p = ks_p.iter().cloned().fold(0.0, f64::max);
        println!(
            "| {name} | {eps} | {published:.0} | {n:.0} ({}) | {:.2} | {:.0} | {:.3} | {:.3} | ≤ {max_p:.1e} |",
            counts
                .iter()
                .map(|c| format!("{c:.0}"))
                .collect::<Vec<_>>()
                .join(", "),
            n / published,
            mean(&contacts),
            mean(&radius),
            mean(&ks_d),
        );
    }
}
