//! ADAM (Kingma & Ba) and its AMSGrad variant (Reddi et al.), as RCPGenerator 1.0 uses them: the
//! gradient of each coordinate is measured in its length unit ℓ, and the step is
//! `lr·ℓ·m̂/(√v̂ + ε)`, so `lr` is in particle diameters per step.

use crate::params::Params;

pub(crate) struct Adam {
    m: Vec<f64>,
    v: Vec<f64>,
    /// Running maximum of v̂ (AMSGrad only).
    v_max: Option<Vec<f64>>,
    t: i32,
    lr: f64,
    beta1: f64,
    beta2: f64,
    eps: f64,
}

impl Adam {
    pub fn new(p: &Params, len: usize) -> Self {
        Adam {
            m: vec![0.0; len],
            v: vec![0.0; len],
            v_max: None,
            t: 0,
            lr: p.lr_adam,
            beta1: p.beta1,
            beta2: p.beta2,
            eps: p.epsilon_adam,
        }
    }

    /// Sets the learning rate of the next steps (RCPGenerator's adaptive α).
    pub fn set_learning_rate(&mut self, lr: f64) {
        self.lr = lr;
    }

    /// Keeps the moments and switches to AMSGrad's non-decreasing second moment and its
    /// learning rate `lr_ams` (RCPGenerator 1.0, step 2501).
    pub fn switch_to_amsgrad(&mut self, p: &Params) {
        let c2 = 1.0 - self.beta2.powi(self.t.max(1));
        self.v_max = Some(self.v.iter().map(|&v| v / c2).collect());
        self.lr = p.lr_ams;
        self.eps = p.epsilon_ams;
    }

    pub fn step(&mut self, q: &mut [f64], force: &[f64], unit0: &[f64], kappa: f64) {
        self.t = self.t.saturating_add(1);
        let (b1, b2) = (self.beta1, self.beta2);
        // Bias corrections of the first and second moments.
        let c1 = 1.0 / (1.0 - b1.powi(self.t));
        let c2 = 1.0 / (1.0 - b2.powi(self.t));
        let rates = Rates {
            b1,
            b2,
            c1,
            c2,
            lr: self.lr,
            eps: self.eps,
            kappa,
        };
        let (m, v) = (&mut self.m[..], &mut self.v[..]);
        // Two square roots and divisions in flight per instruction under SSE2, four under
        // AVX2: the update is bound by them (7 % of a run's CPU at N = 10³ under SSE2).
        packbench_core::widest_simd::with_avx2(
            #[inline(always)]
            || match &mut self.v_max {
                None => update(rates, q, force, unit0, m, v),
                Some(v_max) => update_amsgrad(rates, q, force, unit0, m, v, v_max),
            },
        );
    }
}

/// The constants of one update.
#[derive(Clone, Copy)]
struct Rates {
    b1: f64,
    b2: f64,
    c1: f64,
    c2: f64,
    lr: f64,
    eps: f64,
    kappa: f64,
}

/// ADAM's update of every coordinate, by iterators so that the loop vectorises.
#[inline(always)]
fn update(r: Rates, q: &mut [f64], force: &[f64], unit0: &[f64], m: &mut [f64], v: &mut [f64]) {
    let coords = q.iter_mut().zip(force).zip(unit0);
    for (((qk, &fk), &uk), (mk, vk)) in coords.zip(m.iter_mut().zip(v.iter_mut())) {
        let l = r.kappa * uk;
        let g = -fk * l;
        *mk = r.b1 * *mk + (1.0 - r.b1) * g;
        *vk = r.b2 * *vk + (1.0 - r.b2) * g * g;
        *qk -= r.lr * l * (*mk * r.c1) / ((*vk * r.c2).sqrt() + r.eps);
    }
}

/// AMSGrad's update: ADAM's with the running maximum of v̂ in the denominator.
#[inline(always)]
fn update_amsgrad(
    r: Rates,
    q: &mut [f64],
    force: &[f64],
    unit0: &[f64],
    m: &mut [f64],
    v: &mut [f64],
    v_max: &mut [f64],
) {
    let coords = q.iter_mut().zip(force).zip(unit0);
    let moments = m.iter_mut().zip(v.iter_mut()).zip(v_max.iter_mut());
    for (((qk, &fk), &uk), ((mk, vk), vmk)) in coords.zip(moments) {
        let l = r.kappa * uk;
        let g = -fk * l;
        *mk = r.b1 * *mk + (1.0 - r.b1) * g;
        *vk = r.b2 * *vk + (1.0 - r.b2) * g * g;
        *vmk = vmk.max(*vk * r.c2);
        *qk -= r.lr * l * (*mk * r.c1) / (vmk.sqrt() + r.eps);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX2 build of both updates gives the baseline's bytes, over coordinates of many
    /// magnitudes and an odd count (a remainder after the vector lanes).
    #[test]
    fn the_avx2_update_gives_the_baseline_bytes() {
        let n = 1001;
        let wave = |k: usize, a: f64| (a * k as f64).sin() * 10f64.powi((k % 9) as i32 - 4);
        let force: Vec<f64> = (0..n).map(|k| wave(k, 0.7)).collect();
        let unit0: Vec<f64> = (0..n).map(|k| 1.0 + wave(k, 1.3).abs()).collect();
        let rates = Rates {
            b1: 0.9,
            b2: 0.999,
            c1: 1.0 / (1.0 - 0.9f64.powi(7)),
            c2: 1.0 / (1.0 - 0.999f64.powi(7)),
            lr: 0.0045,
            eps: 1e-8,
            kappa: 1.3,
        };
        let start = || -> [Vec<f64>; 4] {
            let q = (0..n).map(|k| wave(k, 0.3)).collect();
            let m = (0..n).map(|k| wave(k, 0.5) * 1e-3).collect();
            let v = (0..n).map(|k| wave(k, 0.9).powi(2)).collect();
            let v_max = (0..n).map(|k| wave(k, 1.1).powi(2)).collect();
            [q, m, v, v_max]
        };
        let (mut base, mut avx2) = (start(), start());
        let [q, m, v, v_max] = &mut base;
        update(rates, q, &force, &unit0, m, v);
        update_amsgrad(rates, q, &force, &unit0, m, v, v_max);
        let [q, m, v, v_max] = &mut avx2;
        packbench_core::widest_simd::with_avx2(
            #[inline(always)]
            || {
                update(rates, q, &force, &unit0, m, v);
                update_amsgrad(rates, q, &force, &unit0, m, v, v_max);
            },
        );
        let bits =
            |a: &[Vec<f64>; 4]| -> Vec<u64> { a.iter().flatten().map(|x| x.to_bits()).collect() };
        assert_eq!(bits(&base), bits(&avx2));
        let moved = base[0]
            .iter()
            .zip(&start()[0])
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            moved > n / 2,
            "the updates moved {moved} of {n} coordinates"
        );
    }
}
