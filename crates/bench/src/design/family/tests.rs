//! Tests of the families: the diameters a packing gets for each draw, mixtures on their
//! support, discrete counts, and bad bounds.

use super::*;

#[test]
fn random_diameters_are_those_the_initial_packing_draws() {
    let shape = Shape {
        draw: Draw::Random,
        ..Shape::default()
    };
    let f = Family::with_defaults("lognormal", &shape).unwrap();
    let values = f.values_from_unit(&[0.5]);
    let d = f.diameters(&values, 50, 9).unwrap();
    let dist = f.distribution(&values).unwrap();
    let again = dist.sample(50, &mut StdRng::seed_from_u64(9)).unwrap();
    assert_eq!(d, again);
    assert_ne!(d, f.diameters(&values, 50, 10).unwrap());
}

#[test]
fn the_scene_packs_the_diameters_searched() {
    for draw in [Draw::Quantile, Draw::Random] {
        let shape = Shape {
            draw,
            ..Shape::default()
        };
        let f = Family::with_defaults("lognormal", &shape).unwrap();
        let values = f.values_from_unit(&[0.5]);
        let scene = f.scene_distribution(&values, 40, 3).unwrap();
        let packed = scene.sample(40, &mut StdRng::seed_from_u64(3)).unwrap();
        assert_eq!(packed, f.diameters(&values, 40, 3).unwrap(), "{draw:?}");
    }
}

#[test]
fn quantile_diameters_are_the_same_for_every_seed() {
    let f = Family::with_defaults("lognormal", &Shape::default()).unwrap();
    let values = f.values_from_unit(&[0.75]);
    let d = f.diameters(&values, 1000, 1).unwrap();
    assert_eq!(d, f.diameters(&values, 1000, 2).unwrap());
    // ln D: mean 0, std σ = 0.3 less the grid's missing tails (0.2998 at N = 1000).
    let ln: Vec<f64> = d.iter().map(|x| x.ln()).collect();
    let std = (ln.iter().map(|x| x * x).sum::<f64>() / 1000.0).sqrt();
    assert!((std - 0.2998).abs() < 5e-4, "{std}");
}

#[test]
fn a_mixture_stays_on_its_support_and_follows_its_weights() {
    for draw in [Draw::Quantile, Draw::Random] {
        let shape = Shape {
            draw,
            ..ratio(2, 10.0)
        };
        let f = Family::with_defaults("mixture", &shape).unwrap();
        // Component 1 at ln 1 (weight 3), component 2 at ln 10 (weight 1), both narrow.
        let values = vec![3.0, 0.0, 0.02, 1.0, 1.0, 0.02];
        let d = f.diameters(&values, 4000, 1).unwrap();
        assert!(d.iter().all(|&x| (1.0..=10.0).contains(&x)), "{draw:?}");
        let large = d.iter().filter(|&&x| x > 3.0).count() as f64 / d.len() as f64;
        assert!((large - 0.25).abs() < 0.03, "{draw:?}: {large}");
        // A component centred on an end of the support is its half-Gaussian there: the
        // mean of |Z| is √(2/π) widths, 0.02 · ln 10 · 0.798 in ln D for the small spheres.
        let small: Vec<f64> = d.iter().filter(|&&x| x < 3.0).map(|x| x.ln()).collect();
        let mean = small.iter().sum::<f64>() / small.len() as f64;
        let half = 0.02 * 10f64.ln() * (2.0 / std::f64::consts::PI).sqrt();
        assert!(
            (mean - half).abs() < 0.05 * half,
            "{draw:?}: {mean} against {half}"
        );
    }
}

#[test]
fn bad_bounds_and_unknown_parameters_are_usage_errors() {
    let mut f = Family::with_defaults("bidisperse", &Shape::default()).unwrap();
    assert_eq!(f.set_bounds("ratio", "1.4:1.0").unwrap_err().exit_code(), 2);
    assert_eq!(f.set_bounds("sigma", "0:1").unwrap_err().exit_code(), 2);
    assert_eq!(f.set_bounds("p", "0.5:1.5").unwrap_err().exit_code(), 2);
    assert_eq!(f.set_bounds("ratio", "x").unwrap_err().exit_code(), 2);
    f.set_bounds("ratio", "1.4").unwrap();
    f.set_bounds("p", "0.5").unwrap();
    assert_eq!(f.validate().unwrap_err().exit_code(), 2);
    assert!(Family::with_defaults("cauchy", &Shape::default()).is_err());
    assert!(Family::with_defaults("mixture", &ratio(0, 10.0)).is_err());
    assert!(Family::with_defaults("discrete", &ratio(7, 10.0)).is_err());
    assert!(Family::with_defaults("discrete", &ratio(1, 10.0)).is_err());
    assert!(Family::with_defaults("mixture", &ratio(2, 0.5)).is_err());
}

fn ratio(components: usize, max_ratio: f64) -> Shape {
    Shape {
        components,
        max_ratio: Some(max_ratio),
        ..Shape::default()
    }
}

#[test]
fn a_discrete_mixture_has_the_counts_of_its_volume_fractions() {
    // 3D, sizes 1 and 10, 25 % of the volume small: number fractions 0.25 : 0.75/1000, so
    // N = 1000 has 997.0… small and 2.99… large spheres, rounded to 997 and 3.
    let f = Family::with_defaults("discrete", &ratio(2, 10.0)).unwrap();
    assert_eq!(f.free().len(), 2);
    let d = f.diameters(&[10.0, 0.25], 1000, 1).unwrap();
    assert_eq!(d.len(), 1000);
    assert_eq!(d.iter().filter(|&&x| x == 10.0).count(), 3);
    assert_eq!(d, f.diameters(&[10.0, 0.25], 1000, 2).unwrap());
    // Every corner of the box is a valid mixture, down to one component.
    for v in [[1.0, 0.0], [10.0, 1.0], [10.0, 0.0], [1.0, 1.0]] {
        let d = f.diameters(&v, 7, 1).unwrap();
        assert_eq!(d.len(), 7);
    }
    let by_number = Shape {
        fractions: Fractions::Number,
        ..ratio(3, 4.0)
    };
    let f = Family::with_defaults("discrete", &by_number).unwrap();
    // Shares 0.5, then half of the rest, then the rest: 50 %, 25 %, 25 % of 8 spheres.
    let d = f.diameters(&[2.0, 4.0, 0.5, 0.5], 8, 1).unwrap();
    assert_eq!(d, vec![1.0, 1.0, 1.0, 1.0, 2.0, 2.0, 4.0, 4.0]);
}
