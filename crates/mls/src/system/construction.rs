//! Building the system and taking it apart: from a starting packing (Maxwell–Boltzmann
//! velocities with zero total momentum), from a checkpoint and back into one, and the packing it
//! holds now.

use packbench_core::Packing;
use packbench_core::geometry::ball_volume;
use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};
use rand_distr::StandardNormal;

use super::{MIN_PARTING, Particle, System, wrap};
use crate::cells::CellGrid;
use crate::checkpoint::Checkpoint;
use crate::event::Calendar;
use crate::neighbour_lists::NeighbourLists;

impl<const D: usize, const P: bool> System<D, P> {
    /// A system with the packing's centres and diameter ratios, mean diameter `scale0` at
    /// time 0 (0 for a Poisson start), Maxwell–Boltzmann velocities at `temperature` drawn from
    /// `seed` with zero total momentum. The caller has validated the packing.
    pub fn new(start: &Packing, scale0: f64, temperature: f64, seed: u64) -> Self {
        let n = start.n();
        let len: [f64; D] = std::array::from_fn(|k| start.container.lengths[k]);
        let periodic: [bool; D] = std::array::from_fn(|k| start.container.periodic[k]);
        let mean = start.diameters.iter().sum::<f64>() / n as f64;
        let ratio: Vec<f64> = start.diameters.iter().map(|&x| x / mean).collect();
        // ℓ: Σ v_d (ratio_i ℓ / 2)^d = V.
        let unit_volume: f64 = ratio.iter().map(|&r| ball_volume(D, r)).sum();
        let length_unit = (start.container.volume() / unit_volume).powf(1.0 / D as f64);
        let mut rng = StdRng::seed_from_u64(seed);
        let thermal = temperature.sqrt() * length_unit;
        let mut vel: Vec<[f64; D]> = (0..n)
            .map(|_| std::array::from_fn(|_| rng.sample::<f64, _>(StandardNormal) * thermal))
            .collect();
        if n > 1 {
            let mut drift = [0.0; D];
            for v in &vel {
                for k in 0..D {
                    drift[k] += v[k] / n as f64;
                }
            }
            for v in &mut vel {
                for k in 0..D {
                    v[k] -= drift[k];
                }
            }
        }
        let p = start
            .positions
            .chunks_exact(D)
            .zip(vel)
            .zip(ratio)
            .map(|((x, v), ratio)| {
                let mut x = std::array::from_fn(|k| x[k]);
                wrap::<D>(&mut x, &len, &periodic);
                Particle {
                    x,
                    v,
                    t: 0.0,
                    ratio,
                }
            })
            .collect();
        let mut s = Self::assemble(
            &start.container,
            p,
            (0..n).collect(),
            scale0,
            length_unit,
            temperature,
        );
        s.rescale_velocities();
        s
    }

    /// The system at the window boundary `c` was taken at (see `checkpoint`): every particle
    /// at the clock origin, nothing predicted yet. The caller has validated `c`.
    pub fn from_checkpoint(c: &Checkpoint) -> Self {
        let p = (0..c.id.len())
            .map(|i| Particle {
                x: std::array::from_fn(|k| c.x[i * D + k]),
                v: std::array::from_fn(|k| c.v[i * D + k]),
                t: 0.0,
                ratio: c.ratio[i],
            })
            .collect();
        let mut s = Self::assemble(
            &c.container,
            p,
            c.id.clone(),
            c.scale,
            c.length_unit,
            c.temperature,
        );
        s.ke = s.kinetic_energy();
        s.pressure = c.pressure.unwrap_or(f64::NAN);
        s.collisions = c.collisions;
        s.events = c.events;
        s.rebuilds = c.rebuilds;
        s
    }

    /// Writes the state at the end of a completed window (every particle moved to the clock
    /// origin by `run_window`) into `c`, reusing its buffers; the run-level fields (container,
    /// schedule, windows, run time, shrink) are the caller's.
    pub fn write_checkpoint(&self, c: &mut Checkpoint) {
        debug_assert!(self.now == 0.0 && self.p.iter().all(|q| q.t == 0.0));
        c.dim = D;
        c.length_unit = self.length_unit;
        c.scale = self.scale0;
        c.temperature = self.temperature;
        c.pressure = self.pressure.is_finite().then_some(self.pressure);
        c.id.clone_from(&self.id);
        c.ratio.clear();
        c.ratio.extend(self.p.iter().map(|q| q.ratio));
        c.x.clear();
        c.x.extend(self.p.iter().flat_map(|q| q.x));
        c.v.clear();
        c.v.extend(self.p.iter().flat_map(|q| q.v));
        c.collisions = self.collisions;
        c.events = self.events;
        c.rebuilds = self.rebuilds;
    }

    /// Everything but the particles' state: box, grid, buffers, clock at 0, no events.
    fn assemble(
        container: &packbench_core::Container,
        p: Vec<Particle<D>>,
        id: Vec<usize>,
        scale0: f64,
        length_unit: f64,
        temperature: f64,
    ) -> Self {
        let n = p.len();
        let len: [f64; D] = std::array::from_fn(|k| container.lengths[k]);
        let periodic: [bool; D] = std::array::from_fn(|k| container.periodic[k]);
        let ratio_max = p.iter().fold(0.0f64, |m, q| m.max(q.ratio));
        let thermal = temperature.sqrt() * length_unit;
        let cell_floor = (container.volume() / n as f64).powf(1.0 / D as f64);
        let grid = CellGrid::build(&len, &periodic, cell_floor, 0.0, n, |i| p[i].x);
        System {
            len,
            half: std::array::from_fn(|k| 0.5 * len[k]),
            periodic,
            p,
            id,
            ratio_max,
            version: vec![0; n],
            grid,
            small: [false; D],
            anchored: false,
            centre: vec![[0.0; D]; n],
            bound: vec![0.0; n],
            lists: NeighbourLists::default(),
            skin: 0.0,
            mark: vec![0; n],
            stamp: 0,
            spare: Vec::new(),
            spare_old: Vec::new(),
            order: Vec::new(),
            p_spare: Vec::new(),
            id_spare: Vec::new(),
            calendar: Calendar::default(),
            now: 0.0,
            scale0,
            growth: 0.0,
            length_unit,
            temperature,
            min_impulse: MIN_PARTING * thermal,
            cell_floor,
            t_grid: f64::INFINITY,
            t_box: f64::INFINITY,
            ke: 0.0,
            collisions: 0,
            events: 0,
            rebuilds: 0,
            window_collisions: 0,
            virial: 0.0,
            ke_integral: 0.0,
            t_mark: 0.0,
            idle_renewals: 0,
            pressure: f64::NAN,
            #[cfg(target_arch = "x86_64")]
            simd: super::simd_kernel::<D>(),
            #[cfg(test)]
            audit: None,
        }
    }

    /// The packing now: positions wrapped into the box, diameters `ratio·scale`.
    pub fn packing(&self, template: &Packing) -> Packing {
        let s = self.scale(self.now);
        let mut positions = vec![0.0; self.n() * D];
        let mut diameters = vec![0.0; self.n()];
        for i in 0..self.n() {
            let mut x = self.position_at(i, self.now);
            wrap::<D>(&mut x, &self.len, &self.periodic);
            if !P {
                // Rounding may leave a touching sphere's centre a hair outside; clamp to the box.
                for k in (0..D).filter(|&k| !self.periodic[k]) {
                    x[k] = x[k].clamp(0.0, self.len[k]);
                }
            }
            let id = self.id[i];
            positions[id * D..(id + 1) * D].copy_from_slice(&x);
            diameters[id] = self.p[i].ratio * s;
        }
        Packing {
            dim: D,
            positions,
            diameters,
            container: template.container.clone(),
        }
    }
}
