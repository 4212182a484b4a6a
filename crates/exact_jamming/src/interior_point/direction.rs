//! One iteration's step: Newton directions of the perturbed KKT system through the factor of
//! the normal equations, Mehrotra's predictor–corrector with centring `σ = (μ_aff/μ)³`, and
//! Gondzio's centrality correctors, with separate primal and dual step lengths.

use super::normal_equations::{Factor, NormalEquations, REFINEMENTS, max_abs, max_step};

/// Gondzio correctors per iteration at most.
const CORRECTORS: usize = 2;

/// A step: the directions `(Δx, Δs, Δz)` and the primal and dual step lengths.
pub(super) type Step = (Vec<f64>, Vec<f64>, Vec<f64>, f64, f64);

/// The Newton system of one iterate: the factor of `GᵀWG` at the weights `w = z/s`.
pub(super) struct Newton<'a> {
    pub normal: &'a NormalEquations,
    pub factor: &'a Factor<'a>,
    pub w: &'a [f64],
    pub s: &'a [f64],
    /// The size of `c`, which scales the refinement's stopping test.
    pub c_norm: f64,
}

impl Newton<'_> {
    /// `(Δx, Δs, Δz)` for the residuals `r_x`, `r_z` and the complementarity target `r_c`:
    /// GᵀWG Δx = −r_x − Gᵀ(W r_z − r_c/s); Δz = W(GΔx + r_z) − r_c/s; Δs = −r_z − GΔx. Near
    /// the optimum W spans many decades and Δz amplifies the error of Δx, so Δx is refined
    /// against the residual of GᵀΔz = −r_x itself.
    fn direction(&self, r_x: &[f64], r_z: &[f64], r_c: &[f64]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (normal, factor, w, s) = (self.normal, self.factor, self.w, self.s);
        let (m, nv) = (s.len(), normal.n);
        let t: Vec<f64> = (0..m).map(|k| w[k] * r_z[k] - r_c[k] / s[k]).collect();
        let gtt = normal.gt_times(&t);
        let rhs: Vec<f64> = (0..nv).map(|j| -r_x[j] - gtt[j]).collect();
        let mut dx = factor.solve(&rhs);
        let mut gdx = normal.g_times(&dx);
        let mut dz: Vec<f64> = (0..m)
            .map(|k| w[k] * (gdx[k] + r_z[k]) - r_c[k] / s[k])
            .collect();
        let mut error = f64::INFINITY;
        for _ in 0..REFINEMENTS {
            let gtdz = normal.gt_times(&dz);
            let e: Vec<f64> = (0..nv).map(|j| -r_x[j] - gtdz[j]).collect();
            let size = max_abs(&e);
            if size >= 0.5 * error || size <= 1e-15 * self.c_norm {
                break;
            }
            error = size;
            let fix = factor.solve(&e);
            let gfix = normal.g_times(&fix);
            dx.iter_mut().zip(&fix).for_each(|(a, b)| *a += b);
            gdx.iter_mut().zip(&gfix).for_each(|(a, b)| *a += b);
            dz.iter_mut()
                .zip(&gfix)
                .zip(w)
                .for_each(|((a, b), w)| *a += w * b);
        }
        let ds: Vec<f64> = (0..m).map(|k| -r_z[k] - gdx[k]).collect();
        (dx, ds, dz)
    }

    /// Mehrotra's step from the iterate with duals `z`, residuals `r_x`, `r_z` and
    /// complementarity `sz = sᵀz`: the affine direction, the centring it implies, the
    /// corrected direction, then Gondzio's correctors.
    pub fn predictor_corrector(&self, z: &[f64], r_x: &[f64], r_z: &[f64], sz: f64) -> Step {
        let s = self.s;
        let m = s.len();
        let mu = sz / m as f64;
        let r_c: Vec<f64> = s.iter().zip(z).map(|(a, b)| a * b).collect();
        let (_, ds_a, dz_a) = self.direction(r_x, r_z, &r_c);
        let (ap, ad) = (max_step(s, &ds_a), max_step(z, &dz_a));
        let mu_aff = (0..m)
            .map(|k| (s[k] + ap * ds_a[k]) * (z[k] + ad * dz_a[k]))
            .sum::<f64>()
            / m as f64;
        let sigma = (mu_aff / mu).clamp(0.0, 1.0).powi(3);
        let r_c: Vec<f64> = (0..m)
            .map(|k| s[k] * z[k] + ds_a[k] * dz_a[k] - sigma * mu)
            .collect();
        let (dx, ds, dz) = self.direction(r_x, r_z, &r_c);
        let ap = (0.99 * max_step(s, &ds)).min(1.0);
        let ad = (0.99 * max_step(z, &dz)).min(1.0);
        self.centrality_correctors(z, sigma * mu, (dx, ds, dz, ap, ad))
    }

    /// Gondzio's centrality correctors (Colombo & Gondzio, Comput. Optim. Appl. 41, 2008): aim
    /// at longer steps by pulling the products s∘z of a trial step into [0.1, 10]·σμ
    /// (`target`); a corrector costs a solve, not a factorisation, and is kept only if it
    /// lengthens the step.
    fn centrality_correctors(&self, z: &[f64], target: f64, step: Step) -> Step {
        let s = self.s;
        let (m, nv) = (s.len(), self.normal.n);
        let (mut dx, mut ds, mut dz, mut ap, mut ad) = step;
        let (zero_x, zero_z) = (vec![0.0; nv], vec![0.0; m]);
        for _ in 0..CORRECTORS {
            let (tp, td) = ((1.5 * ap).min(1.0), (1.5 * ad).min(1.0));
            let t: Vec<f64> = (0..m)
                .map(|k| {
                    let v = (s[k] + tp * ds[k]) * (z[k] + td * dz[k]);
                    if v < 0.1 * target {
                        v - 0.1 * target
                    } else if v > 10.0 * target {
                        (v - 10.0 * target).min(10.0 * target)
                    } else {
                        0.0
                    }
                })
                .collect();
            let (cx, cs, cz) = self.direction(&zero_x, &zero_z, &t);
            let tx: Vec<f64> = dx.iter().zip(&cx).map(|(a, b)| a + b).collect();
            let ts: Vec<f64> = ds.iter().zip(&cs).map(|(a, b)| a + b).collect();
            let tz: Vec<f64> = dz.iter().zip(&cz).map(|(a, b)| a + b).collect();
            let np = (0.99 * max_step(s, &ts)).min(1.0);
            let nd = (0.99 * max_step(z, &tz)).min(1.0);
            if np + nd < 1.01 * (ap + ad) {
                break;
            }
            (dx, ds, dz, ap, ad) = (tx, ts, tz, np, nd);
        }
        (dx, ds, dz, ap, ad)
    }
}
