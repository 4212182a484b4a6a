//! Overdamped velocity Verlet (RCPGenerator 1.0's last stage): `x += v·dt + ½a·dt²`, then
//! `v ← (v + ½(a_old + a)·dt)(1 − damping)`, with mass `1/ℓ²` per coordinate so that `a = F·ℓ²`.

use crate::params::Params;

pub(super) struct OverdampedVerlet {
    v: Vec<f64>,
    a_old: Vec<f64>,
    started: bool,
    dt: f64,
    keep: f64,
}

impl OverdampedVerlet {
    pub fn new(p: &Params, len: usize) -> Self {
        OverdampedVerlet {
            v: vec![0.0; len],
            a_old: vec![0.0; len],
            started: false,
            dt: p.dt_verlet,
            keep: 1.0 - p.stage_schedule().2,
        }
    }

    pub fn step(&mut self, q: &mut [f64], force: &[f64], unit0: &[f64], kappa: f64) {
        let dt = self.dt;
        let k2 = kappa * kappa;
        for k in 0..q.len() {
            let a = force[k] * k2 * unit0[k] * unit0[k];
            if self.started {
                // Second half-kick of the previous step, with the forces at the new positions.
                self.v[k] = (self.v[k] + 0.5 * dt * (self.a_old[k] + a)) * self.keep;
            }
            q[k] += self.v[k] * dt + 0.5 * a * dt * dt;
            self.a_old[k] = a;
        }
        self.started = true;
    }
}
