//! The structure factor S(k) and the spectral density χ(k) of a periodic packing, by a direct
//! sum over wave vectors of the box's reciprocal lattice, radially binned, with the sampling
//! error of each bin.
//!
//! S(k) = |Σ_j e^{ik·r_j}|² / N (the centres). χ(k) of polydisperse packings weighs each
//! particle by its form factor m(k; R) = ∫_{ball of radius R} e^{ik·x} dx (Zachary, Jiao &
//! Torquato, PRL 106, 178001 (2011), eqn 2); reported as χ̃(k) = |Σ_j m_j e^{ik·r_j}|² / (N⟨v²⟩),
//! i.e. χ(k)/(ρ⟨v²⟩), which equals S(k)·m(k)²/v² for equal spheres and tends to S(0) there.
//! A hyperuniform packing has S(k→0) = 0 (Donev, Stillinger & Torquato, PRL 95, 090604
//! (2005)); `s_k0` is the intercept of a straight line fitted to the lowest bins.
//!
//! Which vectors: the allowed wave vectors are k = 2π(n_1/L_1, …, n_d/L_d). A bin is summed
//! whole when it holds at most 1/ε² of them (ε = `relative_error`); a crowded bin is sampled,
//! each vector kept with probability (1/ε²)/M_b by a hash of its indices (uniform over the
//! shell, the same for any thread count). Single-vector values |ρ_k|²/N of a disordered
//! packing scatter about their mean with a standard deviation close to that mean (they are
//! nearly exponentially distributed), so 1/ε² vectors give a bin mean with relative error
//! about ε. The error is not assumed but measured: each bin reports the standard error of
//! its sampled mean, s.d./√n·√(1 − n/M_b), 0 for a bin summed whole.
//!
//! How: the phase e^{ik·r_j} = Π_a (e^{i2π x_{j,a}/L_a})^{n_a} is a product of per-axis powers,
//! tabulated once per block of particles, so the sum costs a few multiplications per vector
//! and particle and no trigonometry. The polydisperse form factor m(k; R_j) is interpolated
//! quadratically in k on sub-bins narrow enough that the error stays below 1e-6 of m.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::form_factor::form_factor;
use crate::MAX_DIM;
use crate::error::CoreError;
use crate::geometry::ball_volume;
use crate::packing::Packing;

/// Largest number of reciprocal-lattice points searched for wave vectors.
const MAX_LATTICE_POINTS: f64 = 5e7;

/// Particles whose per-axis phase tables are held at once (bounds memory at large N).
const BLOCK: usize = 4096;

/// Width of a form-factor interpolation sub-bin times the largest radius, in k·R: quadratic
/// interpolation through three points over a width w errs by at most ~0.064 (w/2)³ max|m'''|,
/// and |m'''| ≤ R³ v, so w·R_max = 0.04 keeps the relative error below 1e-6.
const FORM_FACTOR_WIDTH: f64 = 0.04;

/// Options of [`structure_factor`]; wave numbers are in units of 1/(mean diameter).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct StructureFactorOptions {
    /// Largest wave number k·D̄ (default 12: past the first peak near 7 and the second).
    pub k_max: f64,
    /// Number of equal radial bins over (0, k_max] (default 120).
    pub bins: usize,
    /// Target relative sampling error ε of a bin's mean S (default 0.03): bins with at most
    /// 1/ε² wave vectors are summed whole, crowded bins are sampled to about 1/ε² vectors.
    pub relative_error: f64,
    /// Upper end of the low-k fit window for `s_k0` and `chi_k0` (default k·D̄ = 4).
    pub fit_k_max: f64,
}

impl Default for StructureFactorOptions {
    fn default() -> Self {
        StructureFactorOptions {
            k_max: 12.0,
            bins: 120,
            relative_error: 0.03,
            fit_k_max: 4.0,
        }
    }
}

/// S(k) and χ̃(k), radially binned (bins holding no wave vector are left out).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct StructureFactor {
    /// Mean wave number k·D̄ of each bin's summed vectors.
    pub k: Vec<f64>,
    /// S(k) averaged over the bin's summed wave vectors.
    pub s: Vec<f64>,
    /// Standard error of `s` from sampling the bin (0 where the bin is summed whole).
    pub s_error: Vec<f64>,
    /// χ̃(k) = χ(k)/(ρ⟨v²⟩) averaged over the same wave vectors (2D and 3D only).
    pub chi: Option<Vec<f64>>,
    /// Number of wave vectors summed in each bin.
    pub vectors: Vec<usize>,
    /// Number of wave vectors the box allows in each bin (equal to `vectors` where summed whole).
    pub vectors_in_bin: Vec<usize>,
    /// The target relative error ε the sampling was sized for.
    pub relative_error: f64,
    /// Largest `s_error / s` over the bins (0 when every bin is summed whole).
    pub max_relative_error: f64,
    /// S(k→0): intercept of the straight line a + b·k fitted (weighted by wave-vector counts)
    /// to the bins inside `fit_window`; `None` with fewer than 3 such bins.
    pub s_k0: Option<f64>,
    /// χ̃(k→0) from the same fit to χ̃.
    pub chi_k0: Option<f64>,
    /// The fit window [0, fit_k_max] in k·D̄.
    pub fit_window: [f64; 2],
}

/// One summed wave vector: its bin, its form-factor sub-bin, lattice indices and |k|.
#[derive(Clone, Copy)]
struct WaveVector {
    bin: usize,
    sub: usize,
    n: [i64; MAX_DIM],
    k: f64,
}

/// S(k) and χ̃(k) of a fully periodic packing. Errors when the container is not fully
/// periodic, an option is out of range, or the box allows more than 5·10⁷ lattice points up to
/// `k_max` (lower `k_max`).
// Long because the enumeration of wave vectors, the sampling of crowded bins and the running sums
// of each bin share their state in one pass; a split would pass that state between four functions.
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
    if !(positive(opt.k_max) && positive(opt.fit_k_max) && opt.bins > 0) {
        return Err(CoreError::Parameter(format!(
            "structure-factor options {opt:?}: k_max, fit_k_max and bins must be positive"
        )));
    }
    if !(positive(opt.relative_error) && opt.relative_error < 1.0) {
        return Err(CoreError::Parameter(format!(
            "structure-factor relative error {} must lie in (0, 1)",
            opt.relative_error
        )));
    }
    let d = p.dim;
    let n = p.n();
    if n == 0 {
        return Ok(StructureFactor::default());
    }
    let mean = p.mean_diameter();
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
    let volumes: Vec<f64> = p.diameters.iter().map(|&dd| ball_volume(d, dd)).collect();
    let mean_v2 = volumes.iter().map(|v| v * v).sum::<f64>() / n as f64;
    let equal = p.diameters.iter().all(|&dd| dd == p.diameters[0]);
    let with_chi = d == 2 || d == 3;
    let bin_width = opt.k_max / mean / opt.bins as f64;
    // Polydisperse χ interpolates each m(k; R_j) over sub-bins of width FORM_FACTOR_WIDTH/R_max.
    let subs = if with_chi && !equal {
        let r_max = 0.5 * p.diameters.iter().cloned().fold(0.0, f64::max);
        ((bin_width * r_max / FORM_FACTOR_WIDTH).ceil() as usize).max(1)
    } else {
        1
    };
    let limit = (1.0 / (opt.relative_error * opt.relative_error)).ceil();
    let (vectors, in_bin) = wave_vectors(&n_max, lengths, bin_width, opt.bins, subs, limit);
    // Phases: k·r_j = Σ_a n_a t_{j,a} with t_{j,a} = 2π x_{j,a}/L_a.
    let t: Vec<f64> = (0..n * d)
        .map(|q| two_pi * p.positions[q] / lengths[q % d])
        .collect();
    let form = (with_chi && !equal).then(|| FormFactors {
        d,
        radii: p.diameters.iter().map(|&dd| 0.5 * dd).collect(),
        subs,
        sub_width: bin_width / subs as f64,
    });
    let sums = phase_sums(&t, d, &n_max, &vectors, form.as_ref());

    // Per bin: Σ k, Welford's mean and M2 of S, Σ χ̃, count.
    let mut acc = vec![(0.0, 0.0, 0.0, 0.0, 0usize); opt.bins];
    for (w, sum) in vectors.iter().zip(&sums) {
        let s = (sum[0] * sum[0] + sum[1] * sum[1]) / n as f64;
        let chi = if form.is_some() {
            (sum[2] * sum[2] + sum[3] * sum[3]) / (n as f64 * mean_v2)
        } else if with_chi {
            let m = form_factor(d, w.k, 0.5 * p.diameters[0]);
            m * m * s / mean_v2
        } else {
            0.0
        };
        let a = &mut acc[w.bin];
        a.4 += 1;
        a.0 += w.k * mean;
        let delta = s - a.1;
        a.1 += delta / a.4 as f64;
        a.2 += delta * (s - a.1);
        a.3 += chi;
    }
    let mut out = StructureFactor {
        fit_window: [0.0, opt.fit_k_max],
        chi: with_chi.then(Vec::new),
        relative_error: opt.relative_error,
        ..StructureFactor::default()
    };
    for (&(k, s, m2, chi, c), &total) in acc.iter().zip(&in_bin).filter(|(a, _)| a.4 > 0) {
        let cf = c as f64;
        let error = if c < total && c > 1 {
            (m2 / (cf - 1.0) / cf * (1.0 - cf / total as f64)).sqrt()
        } else {
            0.0
        };
        out.k.push(k / cf);
        out.s.push(s);
        out.s_error.push(error);
        if let Some(v) = out.chi.as_mut() {
            v.push(chi / cf);
        }
        out.vectors.push(c);
        out.vectors_in_bin.push(total);
        if s > 0.0 {
            out.max_relative_error = out.max_relative_error.max(error / s);
        }
    }
    out.s_k0 = intercept(&out.k, &out.s, &out.vectors, opt.fit_k_max);
    out.chi_k0 = out
        .chi
        .as_ref()
        .and_then(|c| intercept(&out.k, c, &out.vectors, opt.fit_k_max));
    Ok(out)
}

/// The polydisperse form factors, interpolated per sub-bin.
struct FormFactors {
    d: usize,
    radii: Vec<f64>,
    /// Sub-bins per bin.
    subs: usize,
    /// Width of a sub-bin in k.
    sub_width: f64,
}

impl FormFactors {
    /// Centre in k of the sub-bin holding `w`.
    fn centre(&self, w: &WaveVector) -> f64 {
        ((w.bin * self.subs + w.sub) as f64 + 0.5) * self.sub_width
    }

    /// Coefficients (m₀, m₁, m₂) per particle of `range` such that m(k_c + δ; R_j) ≈
    /// m₀ + δ(m₁ + δ m₂) over the sub-bin around `kc`: the parabola through its ends and centre.
    fn coefficients(&self, kc: f64, range: std::ops::Range<usize>, c: &mut [Vec<f64>; 3]) {
        let h = 0.5 * self.sub_width;
        for v in c.iter_mut() {
            v.clear();
        }
        for &r in &self.radii[range] {
            let (lo, mid, hi) = (
                form_factor(self.d, kc - h, r),
                form_factor(self.d, kc, r),
                form_factor(self.d, kc + h, r),
            );
            c[0].push(mid);
            c[1].push((hi - lo) / (2.0 * h));
            c[2].push((hi - 2.0 * mid + lo) / (2.0 * h * h));
        }
    }
}

/// Σ_j e^{ik·r_j} (entries 0, 1) and, with `form`, Σ_j m_j(k) e^{ik·r_j} (entries 2, 3) for
/// every vector. Particles go in fixed blocks and each vector's sum runs over them in order, so
/// the result does not depend on the thread count.
fn phase_sums(
    t: &[f64],
    d: usize,
    n_max: &[i64],
    vectors: &[WaveVector],
    form: Option<&FormFactors>,
) -> Vec<[f64; 4]> {
    let n = t.len() / d;
    // Runs of vectors sharing a bin and sub-bin: one set of form-factor coefficients each.
    let mut groups = Vec::new();
    let mut start = 0;
    for i in 1..=vectors.len() {
        if i == vectors.len()
            || (vectors[i].bin, vectors[i].sub) != (vectors[start].bin, vectors[start].sub)
        {
            groups.push(start..i);
            start = i;
        }
    }
    let mut total = vec![[0.0; 4]; vectors.len()];
    for first in (0..n).step_by(BLOCK) {
        let block = first..(first + BLOCK).min(n);
        let table = PhaseTable::new(&t[block.start * d..block.end * d], d, n_max);
        let parts: Vec<Vec<[f64; 4]>> = groups
            .par_iter()
            .map_init(
                || (vec![0.0; 2 * BLOCK], [Vec::new(), Vec::new(), Vec::new()]),
                |(z, coef), g| {
                    let weights = form.map(|f| {
                        let kc = f.centre(&vectors[g.start]);
                        f.coefficients(kc, block.clone(), coef);
                        kc
                    });
                    vectors[g.clone()]
                        .iter()
                        .map(|w| {
                            let (zr, zi) = z.split_at_mut(BLOCK);
                            table.phases(&w.n, zr, zi);
                            let b = table.len;
                            match weights {
                                None => {
                                    let (ar, ai) = (lane_sum(&zr[..b]), lane_sum(&zi[..b]));
                                    [ar, ai, 0.0, 0.0]
                                }
                                Some(kc) => weighted_sums(&zr[..b], &zi[..b], coef, w.k - kc),
                            }
                        })
                        .collect()
                },
            )
            .collect();
        for (g, part) in groups.iter().zip(parts) {
            for (acc, s) in total[g.clone()].iter_mut().zip(part) {
                for q in 0..4 {
                    acc[q] += s[q];
                }
            }
        }
    }
    total
}

/// e^{i m t_{j,a}} for m = 0..=n_max[a] of each axis a and particle j of a block, as rows of
/// real and imaginary parts over the block's particles.
struct PhaseTable {
    len: usize,
    re: Vec<f64>,
    im: Vec<f64>,
    /// Row of (axis a, power 0).
    row0: Vec<usize>,
}

impl PhaseTable {
    fn new(t: &[f64], d: usize, n_max: &[i64]) -> PhaseTable {
        let len = t.len() / d;
        let mut row0 = Vec::with_capacity(d);
        let mut rows = 0;
        for &m in n_max {
            row0.push(rows);
            rows += m as usize + 1;
        }
        let (mut re, mut im) = (vec![0.0; rows * len], vec![0.0; rows * len]);
        for (a, &m) in n_max.iter().enumerate() {
            for j in 0..len {
                let (s, c) = t[j * d + a].sin_cos();
                let (mut x, mut y) = (1.0, 0.0);
                for power in 0..=m as usize {
                    let q = (row0[a] + power) * len + j;
                    re[q] = x;
                    im[q] = y;
                    // Powers by repeated multiplication: the error grows by ~1e-16 a step,
                    // ~1e-13 after the few hundred steps of the largest boxes.
                    (x, y) = (x * c - y * s, x * s + y * c);
                }
            }
        }
        PhaseTable { len, re, im, row0 }
    }

    /// e^{ik·r_j} for the lattice vector `n` into (zr, zi), as the product over the axes of
    /// the tabulated powers (conjugated for negative indices).
    fn phases(&self, n: &[i64; MAX_DIM], zr: &mut [f64], zi: &mut [f64]) {
        let len = self.len;
        let (zr, zi) = (&mut zr[..len], &mut zi[..len]);
        zr.fill(1.0);
        zi.fill(0.0);
        for (a, &row0) in self.row0.iter().enumerate() {
            let m = n[a];
            if m == 0 {
                continue;
            }
            let q = (row0 + m.unsigned_abs() as usize) * len;
            let (re, im) = (&self.re[q..q + len], &self.im[q..q + len]);
            let sign = m.signum() as f64;
            for j in 0..len {
                let (x, y, u, v) = (zr[j], zi[j], re[j], sign * im[j]);
                zr[j] = x * u - y * v;
                zi[j] = x * v + y * u;
            }
        }
    }
}

/// Σ x in four interleaved partial sums (a fixed order the compiler can vectorise).
fn lane_sum(x: &[f64]) -> f64 {
    let mut lanes = [0.0; 4];
    let chunks = x.chunks_exact(4);
    let rest: f64 = chunks.remainder().iter().sum();
    for c in chunks {
        for q in 0..4 {
            lanes[q] += c[q];
        }
    }
    (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]) + rest
}

/// [Σ zr, Σ zi, Σ m zr, Σ m zi] with m_j = c₀ + δ(c₁ + δ c₂) the interpolated form factors.
fn weighted_sums(zr: &[f64], zi: &[f64], c: &[Vec<f64>; 3], delta: f64) -> [f64; 4] {
    let mut s = [0.0; 4];
    for j in 0..zr.len() {
        let m = c[0][j] + delta * (c[1][j] + delta * c[2][j]);
        s[0] += zr[j];
        s[1] += zi[j];
        s[2] += m * zr[j];
        s[3] += m * zi[j];
    }
    s
}

/// The wave vectors summed, sorted by bin and sub-bin, and the number each bin allows: the
/// half of the reciprocal lattice with a positive first non-zero index (S(−k) = S(k)) and
/// 0 < |k| ≤ bins·bin_width. A bin of at most `limit` vectors is taken whole; a larger one
/// keeps each vector with probability limit/M_b by a hash of its indices. Two passes (count,
/// then pick) keep memory at the chosen vectors.
fn wave_vectors(
    n_max: &[i64],
    lengths: &[f64],
    bin_width: f64,
    bins: usize,
    subs: usize,
    limit: f64,
) -> (Vec<WaveVector>, Vec<usize>) {
    let mut count = vec![0usize; bins];
    for_each_wave_vector(n_max, lengths, bin_width, bins, |b, _, _| count[b] += 1);
    let keep: Vec<f64> = count
        .iter()
        .map(|&c| (limit / c.max(1) as f64).min(1.0))
        .collect();
    let mut out = Vec::new();
    for_each_wave_vector(n_max, lengths, bin_width, bins, |bin, nv, k| {
        if keep[bin] >= 1.0 || unit_hash(nv) < keep[bin] {
            let sub = (((k / bin_width - bin as f64) * subs as f64) as usize).min(subs - 1);
            out.push(WaveVector {
                bin,
                sub,
                n: *nv,
                k,
            });
        }
    });
    out.sort_by_key(|w| (w.bin, w.sub));
    (out, count)
}

/// A number in [0, 1) from the lattice indices (SplitMix64 finaliser over each index).
fn unit_hash(n: &[i64; MAX_DIM]) -> f64 {
    let mut h: u64 = 0x9E37_79B9_7F4A_7C15;
    for &v in n {
        h = (h ^ v as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
        h = (h ^ (h >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        h ^= h >> 31;
    }
    (h >> 11) as f64 / (1u64 << 53) as f64
}

/// Calls `f(bin, n, |k|)` for every lattice vector of [`wave_vectors`]' half space, in the
/// order of an odometer over [−n_max, n_max]^d whose first axis turns fastest.
fn for_each_wave_vector(
    n_max: &[i64],
    lengths: &[f64],
    bin_width: f64,
    bins: usize,
    mut f: impl FnMut(usize, &[i64; MAX_DIM], f64),
) {
    let d = n_max.len();
    let two_pi = 2.0 * std::f64::consts::PI;
    let k_max = bin_width * bins as f64;
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
            if k <= k_max {
                f(((k / bin_width) as usize).min(bins - 1), &nv, k);
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

#[cfg(test)]
mod tests {
    use rand::rngs::StdRng;
    use rand::{RngExt, SeedableRng};

    use super::*;
    use crate::container::Container;

    /// `n` random centres with lognormal-like diameters in a periodic box of side `l`.
    fn random_packing(d: usize, n: usize, l: f64, seed: u64) -> Packing {
        let mut rng = StdRng::seed_from_u64(seed);
        let x: Vec<f64> = (0..n * d).map(|_| rng.random_range(0.0..l)).collect();
        let dia: Vec<f64> = (0..n).map(|_| rng.random_range(0.6..1.8)).collect();
        Packing::new(x, dia, Container::periodic_box(&vec![l; d]).unwrap()).unwrap()
    }

    #[test]
    fn tabulated_phases_and_interpolated_form_factors_match_the_direct_sum() {
        for d in [2, 3] {
            let p = random_packing(d, 300, 9.0, 7 + d as u64);
            let two_pi = 2.0 * std::f64::consts::PI;
            let n_max = vec![11i64; d];
            let t: Vec<f64> = p.positions.iter().map(|x| two_pi * x / 9.0).collect();
            let bin_width = 0.1;
            let r_max = 0.9;
            let subs = (bin_width * r_max / FORM_FACTOR_WIDTH).ceil() as usize;
            let (vectors, _) = wave_vectors(&n_max, &[9.0; 3][..d], bin_width, 60, subs, 1e9);
            let form = FormFactors {
                d,
                radii: p.diameters.iter().map(|&x| 0.5 * x).collect(),
                subs,
                sub_width: bin_width / subs as f64,
            };
            let sums = phase_sums(&t, d, &n_max, &vectors, Some(&form));
            let mut worst = [0.0f64; 2];
            for (w, s) in vectors.iter().zip(&sums) {
                let mut exact = [0.0; 4];
                for j in 0..p.n() {
                    let phase: f64 = (0..d).map(|a| w.n[a] as f64 * t[j * d + a]).sum();
                    let m = form_factor(d, w.k, 0.5 * p.diameters[j]);
                    exact[0] += phase.cos();
                    exact[1] += phase.sin();
                    exact[2] += m * phase.cos();
                    exact[3] += m * phase.sin();
                }
                let scale = (p.n() as f64).sqrt();
                let m_scale = scale * form_factor(d, 1e-9, 0.9);
                for q in 0..4 {
                    let (e, i) = if q < 2 { (scale, 0) } else { (m_scale, 1) };
                    worst[i] = worst[i].max((s[q] - exact[q]).abs() / e);
                }
            }
            // Phases to rounding; form factors to the interpolation's 1e-6.
            assert!(worst[0] < 1e-11, "d = {d}: phase error {}", worst[0]);
            assert!(worst[1] < 1e-6, "d = {d}: form-factor error {}", worst[1]);
        }
    }

    #[test]
    fn sampled_bins_agree_with_the_whole_bins_within_their_stated_error() {
        let p = random_packing(3, 2000, 14.0, 3);
        let whole = structure_factor(
            &p,
            &StructureFactorOptions {
                relative_error: 1e-3,
                ..StructureFactorOptions::default()
            },
        )
        .unwrap();
        assert!(whole.s_error.iter().all(|&e| e == 0.0));
        assert_eq!(whole.vectors, whole.vectors_in_bin);
        let eps = 0.1;
        let sampled = structure_factor(
            &p,
            &StructureFactorOptions {
                relative_error: eps,
                ..StructureFactorOptions::default()
            },
        )
        .unwrap();
        assert_eq!(sampled.vectors_in_bin, whole.vectors_in_bin);
        let (mut z2, mut crowded) = (0.0, 0);
        for b in 0..whole.k.len() {
            let (n, m) = (sampled.vectors[b], sampled.vectors_in_bin[b]);
            if n == m {
                // A bin summed whole is the same sum in the same order.
                assert_eq!(sampled.s[b].to_bits(), whole.s[b].to_bits());
                assert_eq!(sampled.s_error[b], 0.0);
                continue;
            }
            crowded += 1;
            // About 1/ε² = 100 vectors kept, and a measured error near that of exponentially
            // scattered values: S/√n, less the finite-population share √(1 − n/M).
            assert!((60..=140).contains(&n), "bin {b}: {n} of {m} kept");
            let rel = sampled.s_error[b] / sampled.s[b];
            let expected = (1.0 - n as f64 / m as f64).sqrt() / (n as f64).sqrt();
            assert!(
                rel > 0.6 * expected && rel < 1.6 * expected,
                "bin {b}: relative error {rel}, expected about {expected}"
            );
            let z = (sampled.s[b] - whole.s[b]) / sampled.s_error[b];
            assert!(
                z.abs() < 5.0,
                "bin {b}: {} against {}, z = {z}",
                sampled.s[b],
                whole.s[b]
            );
            z2 += z * z;
        }
        assert!(crowded > 50, "{crowded} crowded bins");
        // The stated errors are the real ones: the deviations' mean square z is about 1.
        let mean_z2 = z2 / crowded as f64;
        assert!((0.5..2.0).contains(&mean_z2), "mean z² = {mean_z2}");
        assert!(sampled.max_relative_error < 2.0 * eps);
    }
}
