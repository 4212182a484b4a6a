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
        let (lr, eps) = (self.lr, self.eps);
        match &mut self.v_max {
            None => {
                for k in 0..q.len() {
                    let l = kappa * unit0[k];
                    let g = -force[k] * l;
                    self.m[k] = b1 * self.m[k] + (1.0 - b1) * g;
                    self.v[k] = b2 * self.v[k] + (1.0 - b2) * g * g;
                    q[k] -= lr * l * (self.m[k] * c1) / ((self.v[k] * c2).sqrt() + eps);
                }
            }
            Some(v_max) => {
                for k in 0..q.len() {
                    let l = kappa * unit0[k];
                    let g = -force[k] * l;
                    self.m[k] = b1 * self.m[k] + (1.0 - b1) * g;
                    self.v[k] = b2 * self.v[k] + (1.0 - b2) * g * g;
                    v_max[k] = v_max[k].max(self.v[k] * c2);
                    q[k] -= lr * l * (self.m[k] * c1) / (v_max[k].sqrt() + eps);
                }
            }
        }
    }
}
