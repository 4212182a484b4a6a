//! The structure factor S(k) and the spectral density χ(k) of a periodic packing, by a direct
//! sum over a bounded set of wave vectors of the box's reciprocal lattice, radially binned.
//!
//! S(k) = |Σ_j e^{ik·r_j}|² / N (the centres). χ(k) of polydisperse packings weighs each
//! particle by its form factor m(k; R) = ∫_{ball of radius R} e^{ik·x} dx (Zachary, Jiao &
//! Torquato, PRL 106, 178001 (2011), eqn 2); reported as χ̃(k) = |Σ_j m_j e^{ik·r_j}|² / (N⟨v²⟩),
//! i.e. χ(k)/(ρ⟨v²⟩), which equals S(k)·m(k)²/v² for equal spheres and tends to S(0) there.
//! A hyperuniform packing has S(k→0) = 0 (Donev, Stillinger & Torquato, PRL 95, 090604
//! (2005)); `s_k0` is the intercept of a straight line fitted to the lowest bins.
//!
//! Why a direct sum: the wave vectors allowed by the box are k = 2π(n_1/L_1, …, n_d/L_d); at
//! most a fixed number per radial bin, chosen evenly through the bin, bound the cost to
//! bins × that number × N phase evaluations (the low-k bins that decide `s_k0` hold only a few
//! vectors each, all of them used), exact for every k summed, with no grid assignment or
//! aliasing corrections that a density-grid FFT would need.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::form_factor::form_factor;
use crate::MAX_DIM;
use crate::error::CoreError;
use crate::geometry::ball_volume;
use crate::packing::Packing;

/// Largest number of reciprocal-lattice points searched for wave vectors.
const MAX_LATTICE_POINTS: f64 = 5e7;

/// Options of [`structure_factor`]; wave numbers are in units of 1/(mean diameter).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct StructureFactorOptions {
    /// Largest wave number k·D̄ (default 12: past the first peak near 7 and the second).
    pub k_max: f64,
    /// Number of equal radial bins over (0, k_max] (default 120).
    pub bins: usize,
    /// Largest number of wave vectors summed per bin (default 100); the lowest bins hold fewer
    /// and are summed whole.
    pub vectors_per_bin: usize,
    /// Upper end of the low-k fit window for `s_k0` and `chi_k0` (default k·D̄ = 4).
    pub fit_k_max: f64,
}

impl Default for StructureFactorOptions {
    fn default() -> Self {
        StructureFactorOptions {
            k_max: 12.0,
            bins: 120,
            vectors_per_bin: 100,
            fit_k_max: 4.0,
        }
    }
}

/// S(k) and χ̃(k), radially binned (bins holding no wave vector are left out).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StructureFactor {
    /// Mean wave number k·D̄ of each bin.
    pub k: Vec<f64>,
    /// S(k) averaged over the bin's wave vectors.
    pub s: Vec<f64>,
    /// χ̃(k) = χ(k)/(ρ⟨v²⟩) averaged over the bin's wave vectors (2D and 3D only).
    pub chi: Option<Vec<f64>>,
    /// Number of wave vectors summed in each bin.
    pub vectors: Vec<usize>,
    /// S(k→0): intercept of the straight line a + b·k fitted (weighted by wave-vector counts)
    /// to the bins inside `fit_window`; `None` with fewer than 3 such bins.
    pub s_k0: Option<f64>,
    /// χ̃(k→0) from the same fit to χ̃.
    pub chi_k0: Option<f64>,
    /// The fit window [0, fit_k_max] in k·D̄.
    pub fit_window: [f64; 2],
}

/// S(k) and χ̃(k) of a fully periodic packing. Errors when the container is not fully
/// periodic, an option is out of range, or the box allows more than 5·10⁷ lattice points up to
/// `k_max` (lower `k_max`).
pub fn structure_factor(
    p: &Packing,
    opt: &StructureFactorOptions,
) -> Result<StructureFactor, CoreError> {
    if !p.container.is_fully_periodic() {
        return Err(CoreError::Parameter(
            "the structure factor needs a fully periodic box".into(),
        ));
    }
    let positive = |v: f64| v.is_finite() && v > 0.0;
    if !(positive(opt.k_max) && positive(opt.fit_k_max) && opt.bins > 0 && opt.vectors_per_bin > 0)
    {
        return Err(CoreError::Parameter(format!(
            "structure-factor options {opt:?}: k_max, fit_k_max, bins and vectors_per_bin must be positive"
        )));
    }
    let d = p.dim;
    let n = p.n();
    if n == 0 {
        return Ok(StructureFactor::default());
    }
    let mean = p.diameters.iter().sum::<f64>() / n as f64;
    let lengths = &p.container.lengths;
    let two_pi = 2.0 * std::f64::consts::PI;
    let n_max: Vec<i64> = lengths
        .iter()
        .map(|&l| (opt.k_max / mean * l / two_pi).floor() as i64)
        .collect();
    let points: f64 = n_max.iter().map(|&m| (2 * m + 1) as f64).product();
    if points > MAX_LATTICE_POINTS {
        return Err(CoreError::Parameter(format!(
            "k_max = {} spans {points:.3e} reciprocal-lattice points in this box (at most {MAX_LATTICE_POINTS:e}); lower k_max",
            opt.k_max
        )));
    }
    let chosen = wave_vectors(&n_max, lengths, mean, opt);
    // Phases: k·r_j = Σ_a n_a t_{j,a} with t_{j,a} = 2π x_{j,a}/L_a.
    let t: Vec<f64> = (0..n * d)
        .map(|q| two_pi * p.positions[q] / lengths[q % d])
        .collect();
    let volumes: Vec<f64> = p.diameters.iter().map(|&dd| ball_volume(d, dd)).collect();
    let mean_v2 = volumes.iter().map(|v| v * v).sum::<f64>() / n as f64;
    let equal = p.diameters.iter().all(|&dd| dd == p.diameters[0]);
    let with_chi = d == 2 || d == 3;
    let sums: Vec<(f64, f64)> = chosen
        .par_iter()
        .map(|(_, nv, kk)| {
            let (mut ar, mut ai, mut br, mut bi) = (0.0, 0.0, 0.0, 0.0);
            for j in 0..n {
                let phase: f64 = (0..d).map(|a| nv[a] as f64 * t[j * d + a]).sum();
                let (s, c) = phase.sin_cos();
                ar += c;
                ai += s;
                if with_chi && !equal {
                    let m = form_factor(d, *kk, 0.5 * p.diameters[j]);
                    br += m * c;
                    bi += m * s;
                }
            }
            if with_chi && equal {
                let m = form_factor(d, *kk, 0.5 * p.diameters[0]);
                (br, bi) = (m * ar, m * ai);
            }
            (
                (ar * ar + ai * ai) / n as f64,
                (br * br + bi * bi) / (n as f64 * mean_v2),
            )
        })
        .collect();
    let mut acc = vec![(0.0, 0.0, 0.0, 0usize); opt.bins];
    for ((b, _, kk), (s, chi)) in chosen.iter().zip(&sums) {
        let a = &mut acc[*b];
        a.0 += kk * mean;
        a.1 += s;
        a.2 += chi;
        a.3 += 1;
    }
    let mut out = StructureFactor {
        fit_window: [0.0, opt.fit_k_max],
        chi: with_chi.then(Vec::new),
        ..StructureFactor::default()
    };
    for &(k, s, chi, c) in acc.iter().filter(|a| a.3 > 0) {
        out.k.push(k / c as f64);
        out.s.push(s / c as f64);
        if let Some(v) = out.chi.as_mut() {
            v.push(chi / c as f64);
        }
        out.vectors.push(c);
    }
    out.s_k0 = intercept(&out.k, &out.s, &out.vectors, opt.fit_k_max);
    out.chi_k0 = out
        .chi
        .as_ref()
        .and_then(|c| intercept(&out.k, c, &out.vectors, opt.fit_k_max));
    Ok(out)
}

/// The wave vectors summed, as (bin, lattice indices n, |k|): the half of the reciprocal
/// lattice with a positive first non-zero index (S(−k) = S(k)) and 0 < |k|·D̄ ≤ k_max, at most
/// `vectors_per_bin` per bin, evenly strided through the bin in lattice order. Two passes
/// (count, then pick) keep memory at the chosen vectors.
fn wave_vectors(
    n_max: &[i64],
    lengths: &[f64],
    mean: f64,
    opt: &StructureFactorOptions,
) -> Vec<(usize, [i64; MAX_DIM], f64)> {
    let mut count = vec![0usize; opt.bins];
    for_each_wave_vector(n_max, lengths, mean, opt.k_max, opt.bins, |b, _, _| {
        count[b] += 1
    });
    let stride: Vec<usize> = count
        .iter()
        .map(|&c| c.div_ceil(opt.vectors_per_bin).max(1))
        .collect();
    let mut seen = vec![0usize; opt.bins];
    let mut out = Vec::new();
    for_each_wave_vector(n_max, lengths, mean, opt.k_max, opt.bins, |b, nv, k| {
        if seen[b].is_multiple_of(stride[b]) {
            out.push((b, *nv, k));
        }
        seen[b] += 1;
    });
    out
}

/// Calls `f(bin, n, |k|)` for every lattice vector of [`wave_vectors`]' half space, in the
/// order of an odometer over [−n_max, n_max]^d whose first axis turns fastest.
fn for_each_wave_vector(
    n_max: &[i64],
    lengths: &[f64],
    mean: f64,
    k_max: f64,
    bins: usize,
    mut f: impl FnMut(usize, &[i64; MAX_DIM], f64),
) {
    let d = n_max.len();
    let two_pi = 2.0 * std::f64::consts::PI;
    let bin_width = k_max / bins as f64;
    let mut nv = [0i64; MAX_DIM];
    for a in 0..d {
        nv[a] = -n_max[a];
    }
    loop {
        if nv[..d].iter().find(|&&v| v != 0).is_some_and(|&v| v > 0) {
            let k = (0..d)
                .map(|a| (two_pi * nv[a] as f64 / lengths[a]).powi(2))
                .sum::<f64>()
                .sqrt();
            if k * mean <= k_max {
                f(((k * mean / bin_width) as usize).min(bins - 1), &nv, k);
            }
        }
        let mut a = 0;
        loop {
            if a == d {
                return;
            }
            if nv[a] < n_max[a] {
                nv[a] += 1;
                break;
            }
            nv[a] = -n_max[a];
            a += 1;
        }
    }
}

/// Intercept of the weighted least-squares line through the points with 0 < x ≤ x_max.
fn intercept(x: &[f64], y: &[f64], w: &[usize], x_max: f64) -> Option<f64> {
    let (mut sw, mut sx, mut sy, mut sxx, mut sxy, mut pts) = (0.0, 0.0, 0.0, 0.0, 0.0, 0);
    for ((&xi, &yi), &wi) in x.iter().zip(y).zip(w) {
        if xi > 0.0 && xi <= x_max {
            let wi = wi as f64;
            sw += wi;
            sx += wi * xi;
            sy += wi * yi;
            sxx += wi * xi * xi;
            sxy += wi * xi * yi;
            pts += 1;
        }
    }
    if pts < 3 {
        return None;
    }
    let det = sw * sxx - sx * sx;
    if det <= 1e-12 * sw * sxx {
        return None;
    }
    Some((sxx * sy - sx * sxy) / det)
}
