//! The pressure window (Baranau & Tallarek 2014 §III.B): a run of events at a fixed compression rate that
//! ends after a number of collisions, with the reduced pressure from the virial theorem
//! (`PV/(N k T) = 1 + Σ r·Δp / (2 ∫ KE dt)`), and the thermostat that rescales velocities to
//! the temperature at the start of each window. A window also ends when it is stopped by the
//! poll callback, when the box limits further growth, or when it is idle.

use crate::event::{Kind, Next};

use super::{IDLE_RENEWALS_PER_PARTICLE, POLL_EVERY, System, WindowEnd, dot};

impl<const D: usize, const P: bool> System<D, P> {
    /// Rescales velocities to the temperature: Σ v²/2 = d·N·T·ℓ²/2.
    pub(super) fn rescale_velocities(&mut self) {
        let ke: f64 = self.p.iter().map(|q| 0.5 * dot(&q.v, &q.v)).sum();
        let target = 0.5 * (D * self.n()) as f64 * self.temperature * self.length_unit.powi(2);
        if ke > 0.0 {
            let f = (target / ke).sqrt();
            for q in &mut self.p {
                for x in q.v.iter_mut() {
                    *x *= f;
                }
            }
            self.ke = self.p.iter().map(|q| 0.5 * dot(&q.v, &q.v)).sum();
        } else {
            self.ke = 0.0;
        }
    }

    /// Starts a pressure window at compression rate `rate`: moves the clock origin, rescales
    /// velocities to the temperature (Baranau & Tallarek 2014 §III.B), resets the pressure sums and
    /// re-predicts everything.
    pub fn begin_window(&mut self, rate: f64) {
        self.start_window(rate, true);
    }

    /// [`Self::begin_window`], with the thermostat optional (tests check conservation laws
    /// across windows with it off).
    pub(crate) fn start_window(&mut self, rate: f64, thermostat: bool) {
        self.move_origin();
        self.growth = rate * self.length_unit;
        if thermostat {
            self.rescale_velocities();
        }
        self.window_collisions = 0;
        self.virial = 0.0;
        self.ke_integral = 0.0;
        self.t_mark = 0.0;
        self.idle_renewals = 0;
        self.rebuild();
    }

    /// Runs events until the window has `collisions` collisions. `poll(collisions, φ)` is
    /// called every few thousand events and stops the run when it returns true.
    pub fn run_window(
        &mut self,
        collisions: u64,
        poll: &mut dyn FnMut(u64, f64) -> bool,
    ) -> WindowEnd {
        let idle_limit = IDLE_RENEWALS_PER_PARTICLE * (self.n() as u64 + 10);
        while self.window_collisions < collisions {
            self.events += 1;
            if self.events.is_multiple_of(POLL_EVERY) && poll(self.collisions, self.phi()) {
                return WindowEnd::Stopped;
            }
            let t_next = self.calendar.next_time();
            let t_geometry = self.t_grid.min(self.t_box);
            if t_geometry <= t_next {
                if t_geometry == f64::INFINITY {
                    return WindowEnd::Idle;
                }
                self.now = t_geometry;
                self.move_origin();
                if self.t_box <= self.t_grid {
                    return WindowEnd::BoxLimit;
                }
                self.rebuild();
                continue;
            }
            match self.calendar.next() {
                Next::Collision {
                    t,
                    i,
                    kind: Kind::Pair(j),
                    partner_version,
                } => {
                    self.now = t;
                    if self.version[j] != partner_version {
                        // `i` lost its partner: its other candidates were later than this
                        // event, so predicting afresh from now finds its next event.
                        self.predict_collisions(i);
                        self.calendar.commit(i);
                    } else {
                        self.collide(i, j);
                    }
                }
                Next::Collision {
                    t,
                    i,
                    kind: Kind::Wall(w),
                    ..
                } => {
                    self.now = t;
                    self.bounce(i, w);
                }
                Next::Renewal { t, i } => {
                    self.now = t;
                    self.renew(i);
                    if self.growth == 0.0 {
                        self.idle_renewals += 1;
                        if self.idle_renewals > idle_limit {
                            return WindowEnd::Idle;
                        }
                    }
                }
            }
        }
        self.ke_integral += self.ke * (self.now - self.t_mark);
        self.t_mark = self.now;
        // Baranau & Tallarek 2014 §III.B / the virial theorem: PV/(N k T) = 1 + Σ r·Δp / (d N k T Δt), and
        // d N k T Δt = 2 ∫ KE dt for unit masses.
        let pressure = if self.ke_integral > 0.0 {
            1.0 + self.virial / (2.0 * self.ke_integral)
        } else if self.virial > 0.0 {
            f64::INFINITY
        } else {
            1.0
        };
        self.pressure = pressure;
        // End at a boundary: every particle at the clock origin, the state a checkpoint holds.
        // (The next window's `move_origin` is then exact no-op, so runs are the same with or
        // without checkpoints.)
        self.move_origin();
        WindowEnd::Completed { pressure }
    }
}
