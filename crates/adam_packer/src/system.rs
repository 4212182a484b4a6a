//! The particle system being packed: positions in a cache-friendly order, reference diameters
//! D₀ and the diameter scale κ (D = κ·D₀), the container (whose last length follows the largest
//! diameter under `--fix-height`), the length that measures overlaps, and the exact packing
//! fraction as a function of κ.

use packbench_core::geometry::ball_volume;
use packbench_core::{Container, Packing};

use crate::MAX_WIDE_SPHERES;
use crate::error::AdamError;

/// Positions and diameters in spatially sorted order, with the way back to the input order.
pub(crate) struct System {
    /// Dimension.
    pub dim: usize,
    /// The container (its last length changes under fix-height).
    pub container: Container,
    /// N·d positions, sorted order.
    pub x: Vec<f64>,
    /// Reference diameters D₀ (the input's), sorted order.
    pub d0: Vec<f64>,
    /// Current diameters κ·D₀.
    pub dia: Vec<f64>,
    /// Diameter scale κ relative to the input.
    pub kappa: f64,
    /// `perm[s]` is the input index of sorted particle `s`.
    perm: Vec<u32>,
    /// Σ v_d(D₀) over the growing particles: their volume at κ = 1.
    volume0: f64,
    /// Largest D₀.
    pub d0_max: f64,
    /// Mean D₀.
    pub d0_mean: f64,
    /// The particles whose diameters are held fixed, when there are any.
    held: Option<HeldDiameters>,
    /// What an overlap is measured in (relative by default).
    pub overlap_scale: OverlapScale,
}

/// What a mask of fixed diameters changes: which diameters scale with κ, and the sums that
/// the packing fraction, the pressure and the largest diameter then need.
struct HeldDiameters {
    /// 1 where the diameter scales with κ, 0 where it is held (sorted order).
    grows: Vec<f64>,
    /// Σ v_d(D₀) over the held particles.
    volume: f64,
    /// Number of growing particles.
    growing: f64,
    /// Σ D₀ over the growing particles and over the held ones.
    growing_d0_sum: f64,
    held_d0_sum: f64,
    /// Largest D₀ among the growing particles and among the held ones.
    growing_d0_max: f64,
    held_d0_max: f64,
}

/// The length an overlap δ is measured in by the energy U = Σ ½ (δ/L)².
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OverlapScale {
    /// L = σ_ij (pairs) or R_i (walls): U = Σ ½ ε², RCPGenerator 1.0's relative overlap.
    Relative,
    /// L = D̄, the mean diameter, for every contact: U = Σ ½ (σ/D̄)² ε², harmonic in the
    /// absolute overlap as RCPGenerator's engine is. Under a broad size distribution it makes a
    /// contact between large spheres as stiff as one between small spheres, so the skeleton
    /// of large spheres that carries the load relaxes as fast as the rest (under the relative
    /// energy a contact of σ = 10 D_min is 100× softer, and the pressure protocol crept without
    /// converging on RCPGenerator 1.0's power law; docs/notes/adam-pressure-protocol.md).
    Absolute,
}

impl System {
    /// Takes `start`, validated, and sorts its particles by cell for memory locality; the
    /// particles listed in `held` (input order) keep their diameters.
    pub fn new(start: &Packing, held: &[usize]) -> Result<Self, AdamError> {
        start.validate()?;
        let d = start.dim;
        let n = start.n();
        let container = start.container.clone();
        let d0_mean = if n > 0 {
            start.diameters.iter().sum::<f64>() / n as f64
        } else {
            1.0
        };
        let perm = spatial_order(&container, &start.positions, d0_mean);
        let mut x = Vec::with_capacity(n * d);
        let mut d0 = Vec::with_capacity(n);
        for &p in &perm {
            let p = p as usize;
            x.extend_from_slice(&start.positions[p * d..(p + 1) * d]);
            d0.push(start.diameters[p]);
        }
        let held = HeldDiameters::new(start, &perm, held)?;
        let volume0 = match &held {
            None => d0.iter().map(|&v| ball_volume(d, v)).sum(),
            Some(h) => (d0.iter().zip(&h.grows))
                .map(|(&v, &g)| g * ball_volume(d, v))
                .sum(),
        };
        let d0_max = d0.iter().fold(0.0f64, |m, &v| m.max(v));
        let mut sys = System {
            dim: d,
            container,
            dia: d0.clone(),
            x,
            d0,
            kappa: 1.0,
            perm,
            volume0,
            d0_max,
            d0_mean,
            held,
            overlap_scale: OverlapScale::Relative,
        };
        // Fix-height holds the last length at k·D_max from the first step on.
        sys.set_kappa(1.0);
        Ok(sys)
    }

    /// The weight w of a contact of length σ (σ_ij, or D_i for a wall) in U = Σ ½ w ε²:
    /// 1 for relative overlaps, (σ/D̄)² for absolute ones.
    #[inline(always)]
    pub fn overlap_weight(&self, sigma: f64) -> f64 {
        match self.overlap_scale {
            OverlapScale::Relative => 1.0,
            OverlapScale::Absolute => absolute_weight(sigma, self.mean_diameter()),
        }
    }

    /// The current mean diameter: κ·D̄₀, or with held diameters (κ Σ_growing D₀ + Σ_held D₀)/N.
    pub fn mean_diameter(&self) -> f64 {
        match &self.held {
            None => self.kappa * self.d0_mean,
            Some(h) => (self.kappa * h.growing_d0_sum + h.held_d0_sum) / self.n() as f64,
        }
    }

    /// The particles the pressure acts on: their number and their current mean diameter (every
    /// particle, unless some diameters are held).
    pub fn growing(&self) -> (f64, f64) {
        match &self.held {
            None => (self.n() as f64, self.mean_diameter()),
            Some(h) => (h.growing, self.kappa * h.growing_d0_sum / h.growing),
        }
    }

    /// 1 where particle `i`'s (sorted order) diameter scales with κ, 0 where it is held; `None`
    /// when every diameter scales.
    pub fn grows(&self) -> Option<&[f64]> {
        self.held.as_ref().map(|h| &h.grows[..])
    }

    /// Wraps along the periodic axes the particles that have left the box. A coordinate in
    /// [0, L) is left as it is (wrapping would not change it), so calling this after every
    /// move puts the wrap where a particle crosses the box's face, whenever the list is rebuilt.
    pub fn wrap_escaped(&mut self) {
        let nc = self.n() * self.dim;
        let (x, c) = (&mut self.x[..nc], &self.container);
        packbench_core::dispatch_dim!(
            self.dim,
            D => packbench_core::widest_simd::with_avx2(#[inline(always)] || wrap_escaped_in::<D>(x, c)),
            _ => unreachable!("dimension {} is refused by Container::validate", self.dim),
        )
    }

    /// Number of particles.
    pub fn n(&self) -> usize {
        self.d0.len()
    }

    /// Packing fraction φ = (V_held + κ^d Σ_growing v(D₀)) / V(container), exact.
    pub fn phi(&self) -> f64 {
        (self.held_volume() + self.volume0 * self.kappa.powi(self.dim as i32))
            / self.container.volume()
    }

    /// Σ v(D) over the held particles (0 without any).
    fn held_volume(&self) -> f64 {
        self.held.as_ref().map_or(0.0, |h| h.volume)
    }

    /// The κ at which φ equals `phi`. Under fix-height the container's volume is linear in κ,
    /// so φ ∝ κ^(d−1); otherwise φ ∝ κ^d.
    /// Held diameters (never together with fix-height) take their volume off the growing ones'.
    pub fn kappa_for_phi(&self, phi: f64) -> Result<f64, AdamError> {
        let d = self.dim as f64;
        Ok(match self.container.fix_height {
            Some(k) => {
                let per_kappa = self.container.volume_per_height() * k * self.d0_max;
                (phi * per_kappa / self.volume0).powf(1.0 / (d - 1.0))
            }
            None => {
                let growing_volume = phi * self.container.volume() - self.held_volume();
                if growing_volume <= 0.0 {
                    return Err(AdamError::Parameter(format!(
                        "the spheres whose diameters are held fill φ = {:.4} on their own, \
                         not below the φ = {phi:.4} the run must set",
                        self.held_volume() / self.container.volume()
                    )));
                }
                (growing_volume / self.volume0).powf(1.0 / d)
            }
        })
    }

    /// Sets D = κ·D₀; under fix-height the last length becomes k·κ·D₀_max and positions along
    /// it scale with it (the constraint is re-derived from D_max each time, never compounded).
    pub fn set_kappa(&mut self, kappa: f64) {
        self.kappa = kappa;
        match &self.held {
            None => {
                for (d, &d0) in self.dia.iter_mut().zip(&self.d0) {
                    *d = kappa * d0;
                }
            }
            Some(h) => {
                for ((d, &d0), &g) in self.dia.iter_mut().zip(&self.d0).zip(&h.grows) {
                    *d = if g > 0.0 { kappa * d0 } else { d0 };
                }
            }
        }
        if let Some(k) = self.container.fix_height {
            let dim = self.dim;
            let new_h = k * kappa * self.d0_max;
            let old_h = self.container.lengths[dim - 1];
            let ratio = new_h / old_h;
            for xi in self.x.chunks_exact_mut(dim) {
                xi[dim - 1] *= ratio;
            }
            self.container.lengths[dim - 1] = new_h;
        }
    }

    /// The largest current diameter.
    pub fn max_diameter(&self) -> f64 {
        match &self.held {
            None => self.kappa * self.d0_max,
            Some(h) => (self.kappa * h.growing_d0_max).max(h.held_d0_max),
        }
    }

    /// The spheres wide enough to touch another through a further periodic image (D_i + D_max
    /// above the shortest periodic length L, so only while 2·D_max > L), with L's axis and L;
    /// `None` when there can be none.
    pub fn wide_spheres(&self) -> Option<(usize, f64, impl Iterator<Item = usize> + '_)> {
        let (axis, length) = self.container.shortest_periodic_length()?;
        let d_max = self.max_diameter();
        (2.0 * d_max > length).then(|| {
            let wide = (0..self.n()).filter(move |&i| self.dia[i] + d_max > length);
            (axis, length, wide)
        })
    }

    /// Refuses a sphere as wide as a periodic length, which would overlap its own image, and
    /// more than [`MAX_WIDE_SPHERES`] spheres wide enough (D_i + D_max above a periodic length)
    /// to touch others through further images, which the energy sums pair by pair
    /// (`overlap_energy/other_images.rs`).
    pub fn check_own_image(&self) -> Result<(), AdamError> {
        let d_max = self.max_diameter();
        if let Some((axis, length, wide)) = self.wide_spheres() {
            let count = wide.count();
            if count > MAX_WIDE_SPHERES {
                return Err(AdamError::TooManyWide {
                    count,
                    max: MAX_WIDE_SPHERES,
                    length,
                    axis,
                    phi: self.phi(),
                });
            }
        }
        for (axis, (&l, &p)) in self
            .container
            .lengths
            .iter()
            .zip(&self.container.periodic)
            .enumerate()
        {
            if p && d_max >= l {
                return Err(AdamError::BoxTooSmall {
                    diameter: d_max,
                    length: l,
                    axis,
                    phi: self.phi(),
                });
            }
        }
        Ok(())
    }

    /// The packing in the input's particle order, positions wrapped along periodic axes.
    pub fn to_packing(&self) -> Packing {
        let d = self.dim;
        let n = self.n();
        let mut positions = vec![0.0; n * d];
        let mut diameters = vec![0.0; n];
        for (s, &p) in self.perm.iter().enumerate() {
            let p = p as usize;
            let xs = &mut positions[p * d..(p + 1) * d];
            xs.copy_from_slice(&self.x[s * d..(s + 1) * d]);
            self.container.wrap(xs);
            diameters[p] = self.dia[s];
        }
        Packing {
            dim: d,
            positions,
            diameters,
            container: self.container.clone(),
        }
    }
}

impl HeldDiameters {
    /// The mask of `held` (input indices) over the sorted order `perm`; `None` when `held` is
    /// empty. Refuses an index outside the packing, every diameter held, and fix-height (whose
    /// height follows the largest diameter, which a held sphere would pin).
    fn new(start: &Packing, perm: &[u32], held: &[usize]) -> Result<Option<Self>, AdamError> {
        if held.is_empty() {
            return Ok(None);
        }
        let n = start.n();
        if let Some(&i) = held.iter().find(|&&i| i >= n) {
            return Err(AdamError::Parameter(format!(
                "fixed_diameters names particle {i}, but the packing has {n} (indices start at 0)"
            )));
        }
        if start.container.fix_height.is_some() {
            return Err(AdamError::Parameter(
                "fixed_diameters cannot be combined with --fix-height (the height follows the \
                 largest diameter)"
                    .into(),
            ));
        }
        let mut held_input = vec![false; n];
        for &i in held {
            held_input[i] = true;
        }
        let grows: Vec<f64> = perm
            .iter()
            .map(|&p| if held_input[p as usize] { 0.0 } else { 1.0 })
            .collect();
        let mut h = HeldDiameters {
            grows,
            volume: 0.0,
            growing: 0.0,
            growing_d0_sum: 0.0,
            held_d0_sum: 0.0,
            growing_d0_max: 0.0,
            held_d0_max: 0.0,
        };
        for (i, &d0) in start.diameters.iter().enumerate() {
            if held_input[i] {
                h.volume += ball_volume(start.dim, d0);
                h.held_d0_sum += d0;
                h.held_d0_max = h.held_d0_max.max(d0);
            } else {
                h.growing += 1.0;
                h.growing_d0_sum += d0;
                h.growing_d0_max = h.growing_d0_max.max(d0);
            }
        }
        if h.growing == 0.0 {
            return Err(AdamError::Parameter(
                "fixed_diameters holds every diameter: nothing is left to grow".into(),
            ));
        }
        Ok(Some(h))
    }
}

/// A contact's weight (σ/D̄)² under [`OverlapScale::Absolute`].
#[inline(always)]
pub(crate) fn absolute_weight(sigma: f64, mean_diameter: f64) -> f64 {
    let q = sigma / mean_diameter;
    q * q
}

/// Particle indices sorted by the cell (of about one mean diameter) that holds them, so that
/// neighbours sit close in memory.
fn spatial_order(container: &Container, x: &[f64], cell: f64) -> Vec<u32> {
    let d = container.dim();
    let n = x.len() / d;
    let counts: Vec<u64> = container
        .lengths
        .iter()
        .map(|&l| ((l / cell).floor() as u64).clamp(1, 1 << 20))
        .collect();
    let key = |i: usize| -> u64 {
        let mut k = 0u64;
        for a in 0..d {
            let c = ((x[i * d + a] / container.lengths[a]) * counts[a] as f64).floor();
            let c = (c.max(0.0) as u64).min(counts[a] - 1);
            k = k.wrapping_mul(counts[a]).wrapping_add(c);
        }
        k
    };
    let mut keyed: Vec<(u64, u32)> = (0..n).map(|i| (key(i), i as u32)).collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The container's periodic axes as fixed-size arrays, for loops monomorphised on the
/// dimension.
pub(crate) struct Geometry<const D: usize> {
    pub length: [f64; D],
    pub half: [f64; D],
    pub periodic: [bool; D],
}

impl<const D: usize> Geometry<D> {
    #[inline(always)]
    pub fn of(c: &Container) -> Self {
        Geometry {
            length: std::array::from_fn(|k| c.lengths[k]),
            half: std::array::from_fn(|k| 0.5 * c.lengths[k]),
            periodic: std::array::from_fn(|k| c.periodic[k]),
        }
    }

    /// The separation `t` along periodic axis `k` brought to its nearest image, a tie at half
    /// the length kept as it is. Positions are wrapped into the box (at each rebuild, or as
    /// they leave it), so one correction is enough.
    #[inline(always)]
    pub fn nearest_image(&self, t: f64, k: usize) -> f64 {
        if t > self.half[k] {
            t - self.length[k]
        } else if t < -self.half[k] {
            t + self.length[k]
        } else {
            t
        }
    }
}

/// Wraps into the box, along the periodic axes, the particles of `x` (`D` coordinates each)
/// that left it.
#[inline(always)]
fn wrap_escaped_in<const D: usize>(x: &mut [f64], c: &Container) {
    let geo = Geometry::<D>::of(c);
    for xi in x.as_chunks_mut::<D>().0 {
        if (0..D).any(|k| geo.periodic[k] && !(0.0..geo.length[k]).contains(&xi[k])) {
            c.wrap(xi);
        }
    }
}
