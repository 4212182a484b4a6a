//! A bracketing search for the one-parameter questions with a target: which value of a single
//! free parameter makes φ_J reach the target (`--objective target`), or the smallest one that
//! does (`min-ratio`, `min-polydispersity` with a size ratio or spread that grows with the
//! parameter). CMA-ES is told only the fitness, |φ_J − target| or a penalty, so it cannot tell
//! a candidate below the target from one above it; this search is told the signed residual
//! φ_J − target and keeps the root of φ_J(x) = target bracketed.
//!
//! Each generation is a function of the history alone (so `--resume` and `--shard` replay it):
//! the first spreads λ points over the whole range; every later one fits a least-squares line
//! of the residual against the parameter through the points in and around the current bracket,
//! takes its root x̂ (regula falsi between the bracket's ends when the fit's slope is not of the
//! data's sign; x̂ may leave the bracket by the fit's window, since near the root the bracket's
//! ends rest on single noisy means), and packs λ points over x̂ ± h, x̂ itself among them. h is
//! half the bracket, but never below [`MIN_HALF_WIDTH`]: once the bracket is inside the seed
//! noise the later generations spread points around the root for the line rather than chase
//! the noise. This is bisection with a local line fit, the strategy of a user bracketing by
//! hand. The search's answer is the packed candidate nearest the root of the line through
//! every packing ([`root`]), not the one whose own mean happened to fall nearest the target.

/// Smallest half-width of a generation's window in the unit range: about the spread in the
/// parameter that the seed noise of a two-seed mean φ_J (≈ 0.001 at N = 10³) leaves in the
/// root for the families searched (a slope of φ_J in the unit range near 0.05).
pub const MIN_HALF_WIDTH: f64 = 1.0 / 16.0;

/// A bracket narrower than this (unit range) with the root at a bound is the bound: the search
/// stops there.
const AT_BOUND: f64 = 1e-9;

/// The next generation's `lambda` points (unit range, one coordinate each) from the earlier
/// generations' `points` and each candidate's signed residual φ_J − target (`None`: not
/// packed, or every packing failed). `None` when the root lies beyond a bound that was
/// already packed (every residual on one side of the target): no generation can help.
pub fn ask(
    lambda: usize,
    points: &[Vec<Vec<f64>>],
    residuals: &[Vec<Option<f64>>],
) -> Option<Vec<Vec<f64>>> {
    let lambda = lambda.max(2);
    let data: Vec<(f64, f64)> = points
        .iter()
        .flatten()
        .zip(residuals.iter().flatten())
        .filter_map(|(p, r)| Some((p[0].clamp(0.0, 1.0), (*r)?)))
        .filter(|(_, r)| r.is_finite())
        .collect();
    if data.len() < 2 {
        return Some(spread(0.5, 0.5, lambda));
    }
    let (lo, hi, root) = bracket(&data)?;
    Some(spread(root, (0.5 * (hi - lo)).max(MIN_HALF_WIDTH), lambda))
}

/// The root of φ_J(x) = target estimated from `data` (unit range x, residual φ_J − target):
/// the line fitted in and around the bracket, as [`ask`] places its next centre. `None` with
/// fewer than two points or when the root lies beyond a packed bound.
pub fn root(data: &[(f64, f64)]) -> Option<f64> {
    (data.len() >= 2)
        .then(|| bracket(data))
        .flatten()
        .map(|b| b.2)
}

/// The bracket `(lo, hi)` of the root and the root within it.
fn bracket(data: &[(f64, f64)]) -> Option<(f64, f64, f64)> {
    // The direction in which φ_J grows with x, from the line through every point.
    let rising = fit(data).is_none_or(|(slope, _)| slope >= 0.0);
    let up = |r: f64| if rising { r } else { -r };
    let below = data.iter().filter(|(_, r)| up(*r) < 0.0).map(|p| p.0);
    let above = data.iter().filter(|(_, r)| up(*r) >= 0.0).map(|p| p.0);
    let lo = below.fold(f64::NEG_INFINITY, f64::max);
    let hi = above.filter(|&x| x > lo).fold(f64::INFINITY, f64::min);
    let (lo, hi) = match (lo.is_finite(), hi.is_finite()) {
        (true, true) => (lo, hi),
        // Every residual on one side: the root lies between the outermost point and the bound.
        (false, _) => (0.0, data.iter().map(|p| p.0).fold(1.0, f64::min)),
        (_, false) => (lo, 1.0),
    };
    if hi - lo <= AT_BOUND {
        return None;
    }
    let margin = (hi - lo).max(2.0 * MIN_HALF_WIDTH);
    let near: Vec<(f64, f64)> = data
        .iter()
        .copied()
        .filter(|(x, _)| *x >= lo - margin && *x <= hi + margin)
        .collect();
    let at = |x: f64| data.iter().find(|p| p.0 == x).map(|p| p.1);
    let root = match fit(&near) {
        Some((slope, intercept)) if slope != 0.0 && (slope > 0.0) == rising => -intercept / slope,
        // Regula falsi between the bracket's ends (a bound not packed counts as the middle).
        _ => match (at(lo), at(hi)) {
            (Some(a), Some(b)) if a != b => lo + (hi - lo) * a / (a - b),
            _ => 0.5 * (lo + hi),
        },
    };
    // The fit's root may leave the bracket: near the root the bracket's ends are set by single
    // noisy means, and clamping to them biased the answer towards the outer end.
    let (a, b) = ((lo - margin).max(0.0), (hi + margin).min(1.0));
    Some((lo, hi, root.clamp(a, b)))
}

/// `lambda` points evenly over `centre ± half` (clipped to the unit range), the one nearest the
/// centre moved onto it.
fn spread(centre: f64, half: f64, lambda: usize) -> Vec<Vec<f64>> {
    let (a, b) = ((centre - half).max(0.0), (centre + half).min(1.0));
    let mut xs: Vec<f64> = (0..lambda)
        .map(|i| a + (b - a) * i as f64 / (lambda - 1) as f64)
        .collect();
    let nearest = (0..lambda)
        .min_by(|&i, &j| (xs[i] - centre).abs().total_cmp(&(xs[j] - centre).abs()))
        .expect("lambda ≥ 2");
    xs[nearest] = centre;
    xs.into_iter().map(|x| vec![x]).collect()
}

/// Least-squares line `r = slope·x + intercept` through `data`; `None` with fewer than two
/// distinct x.
fn fit(data: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = data.len() as f64;
    let mx = data.iter().map(|p| p.0).sum::<f64>() / n;
    let my = data.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = data.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = data.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 1e-300).then(|| {
        let slope = sxy / sxx;
        (slope, my - slope * mx)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The points asked for and the residuals told back, generation by generation.
    type History = (Vec<Vec<Vec<f64>>>, Vec<Vec<Option<f64>>>);

    /// Runs the search on residual(x) for `generations`, returns the history.
    fn search(
        residual: impl Fn(f64, usize) -> Option<f64>,
        generations: usize,
        lambda: usize,
    ) -> History {
        let (mut points, mut told) = (Vec::new(), Vec::new());
        for _ in 0..generations {
            let Some(next) = ask(lambda, &points, &told) else {
                break;
            };
            let k = told.len();
            told.push(next.iter().map(|p| residual(p[0], k)).collect());
            points.push(next);
        }
        (points, told)
    }

    /// On a straight line the second generation already packs the root; a falling residual is
    /// found as well as a rising one.
    #[test]
    fn a_linear_residual_has_its_root_packed() {
        for (slope, root) in [(0.1, 0.37), (-0.05, 0.81)] {
            let (points, _) = search(|x, _| Some(slope * (x - root)), 3, 4);
            let best = points[1..]
                .iter()
                .flatten()
                .map(|p| (p[0] - root).abs())
                .fold(f64::INFINITY, f64::min);
            assert!(
                best < 1e-12,
                "slope {slope}: nearest point {best} from the root"
            );
        }
    }

    /// With noise of the size of a two-seed mean (0.001 on a slope of 0.05 over the unit range,
    /// i.e. 0.02 in x), the last generation's centre lands within 0.03 of the root: the band
    /// is 1.5× the noise's own spread in x, written before the run.
    #[test]
    fn a_noisy_residual_is_bracketed_to_the_noise() {
        let root = 0.42;
        // A fixed pseudo-random noise per point, uniform in ±0.001 (std 0.0006).
        let noise = |x: f64| ((x * 7919.0).sin() * 43758.5453).fract() * 0.001;
        for lambda in [4, 6] {
            let (points, _) = search(|x, _| Some(0.05 * (x - root) + noise(x)), 5, lambda);
            let last = &points[points.len() - 1];
            let centre = last
                .iter()
                .map(|p| p[0])
                .min_by(|a, b| (a - root).abs().total_cmp(&(b - root).abs()))
                .unwrap();
            assert!((centre - root).abs() < 0.03, "λ {lambda}: {centre}");
        }
    }

    /// A target beyond the range (every residual below it) stops at the bound once the bound
    /// is packed; candidates that failed to pack are ignored.
    #[test]
    fn a_root_beyond_the_bound_ends_the_search_there() {
        let (points, told) = search(|x, _| (x > 0.1).then_some(x - 2.0), 6, 4);
        assert!(points.len() < 6, "the search went on past the bound");
        assert_eq!(points.last().unwrap().last().unwrap()[0], 1.0);
        assert!(told.iter().flatten().any(|r| r.is_none()));
        assert_eq!(ask(4, &points, &told), None);
    }
}
