//! FIRE (Bitzek et al. 2006, Particle Assembler): velocity Verlet whose velocity is mixed towards the
//! force, `v ← (1 − α)v + α|v|â`; after N_min steps of positive power P = F·v the time step
//! grows by f_inc (up to dt_max) and α decays by f_α; on P < 0 the velocity is zeroed, the time
//! step cut by f_dec and α reset. Masses are `1/ℓ²` per coordinate (`a = F·ℓ²`).

use crate::params::Params;

pub(super) struct Fire {
    v: Vec<f64>,
    a: Vec<f64>,
    a_old: Vec<f64>,
    started: bool,
    dt: f64,
    dt_max: f64,
    alpha: f64,
    alpha_start: f64,
    n_positive: u32,
    n_min: u32,
    f_inc: f64,
    f_dec: f64,
    f_alpha: f64,
}

impl Fire {
    pub fn new(p: &Params, len: usize) -> Self {
        Fire {
            v: vec![0.0; len],
            a: vec![0.0; len],
            a_old: vec![0.0; len],
            started: false,
            dt: p.fire_dt,
            dt_max: p.fire_dt_max,
            alpha: p.fire_alpha_start,
            alpha_start: p.fire_alpha_start,
            n_positive: 0,
            n_min: p.fire_n_min,
            f_inc: p.fire_f_inc,
            f_dec: p.fire_f_dec,
            f_alpha: p.fire_f_alpha,
        }
    }

    pub fn step(&mut self, q: &mut [f64], force: &[f64], unit0: &[f64], kappa: f64) {
        let dt = self.dt;
        let k2 = kappa * kappa;
        let (mut power, mut v2, mut a2) = (0.0, 0.0, 0.0);
        for k in 0..q.len() {
            let a = force[k] * k2 * unit0[k] * unit0[k];
            self.a[k] = a;
            if self.started {
                self.v[k] += 0.5 * dt * (self.a_old[k] + a);
            }
            power += force[k] * self.v[k];
            v2 += self.v[k] * self.v[k];
            a2 += a * a;
        }
        if power >= 0.0 {
            // Mix the velocity towards the acceleration direction.
            let mix = if a2 > 0.0 {
                self.alpha * (v2 / a2).sqrt()
            } else {
                0.0
            };
            let keep = 1.0 - self.alpha;
            for (v, &a) in self.v.iter_mut().zip(&self.a) {
                *v = keep * *v + mix * a;
            }
            self.n_positive += 1;
            if self.n_positive > self.n_min {
                self.dt = (self.dt * self.f_inc).min(self.dt_max);
                self.alpha *= self.f_alpha;
            }
        } else {
            self.v.fill(0.0);
            self.dt *= self.f_dec;
            self.alpha = self.alpha_start;
            self.n_positive = 0;
        }
        let dt = self.dt;
        for ((qk, &v), &a) in q.iter_mut().zip(&self.v).zip(&self.a) {
            *qk += v * dt + 0.5 * a * dt * dt;
        }
        std::mem::swap(&mut self.a, &mut self.a_old);
        self.started = true;
    }
}
