//! Chord-length distributions: the lengths of the void and solid segments that lines cut
//! through a packing in a periodic box (Torquato, Random Heterogeneous Materials, §2.2.7).
//!
//! Random lines are isotropic (uniform directions, uniform starting points, fixed seed) and
//! wrap through the periodic box; a line of length T keeps the chords that start in [0, T),
//! followed past T to their end, so long chords are not under-sampled as they would be by
//! dropping the chords cut by the ends. Axial lines run once around the box along an axis and are closed, so none is cut.
//! The number-weighted mean void chord obeys the stereological identity
//! `ℓ_void = c_d (1 − φ)/s` and `ℓ_solid = c_d φ/s` with `s` the surface per volume and
//! `c_d = d κ_d/κ_{d−1}` (4 in 3D, π in 2D; Underwood, Quantitative Stereology, 1970).

use rand::rngs::StdRng;
use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};

use super::check_packing;
use super::sphere_grid::SphereGrid;
use crate::analysis::structure::Histogram;
use crate::error::CoreError;
use crate::geometry::unit_ball_volume;
use crate::packing::Packing;

/// Options of [`chords`].
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct ChordOptions {
    /// Random isotropic lines (default 1000), each four times the longest box side.
    pub lines: usize,
    /// Axial lines per axis (default 200).
    pub axial_lines: usize,
    /// Seed of the line sampler.
    pub seed: u64,
    /// Logarithmic bins of the distributions.
    pub bins: usize,
}

impl Default for ChordOptions {
    fn default() -> Self {
        ChordOptions {
            lines: 1000,
            axial_lines: 200,
            seed: 1,
            bins: 40,
        }
    }
}

/// The chords of one phase.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChordSet {
    /// Number of chords.
    pub count: usize,
    /// Mean chord length (0 when there are none).
    pub mean: f64,
    /// Standard error of the mean, std/√count.
    pub mean_error: f64,
    /// Density of chord lengths on logarithmic bins.
    pub distribution: Histogram,
    /// The chord lengths (not serialised).
    #[serde(skip)]
    pub lengths: Vec<f64>,
}

/// Chord-length distributions and the stereological prediction of their means.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ChordReport {
    /// Void chords along random isotropic lines.
    pub void: ChordSet,
    /// Solid chords along random isotropic lines.
    pub solid: ChordSet,
    /// Void chords along the box axes.
    pub axial_void: ChordSet,
    /// Solid chords along the box axes.
    pub axial_solid: ChordSet,
    /// Specific surface s: sphere surface per container volume (inverse length).
    pub specific_surface: f64,
    /// `c_d (1 − φ)/s`, the mean void chord the identity predicts.
    pub void_mean_predicted: f64,
    /// `c_d φ/s`, the mean solid chord the identity predicts.
    pub solid_mean_predicted: f64,
}

/// Chord-length distributions of `packing` along random and axial lines.
///
/// Errors: those of the void-space checks (2D or 3D, no coincident centres, small overlaps),
/// a container that is not a fully periodic box, or zero lines or bins.
pub fn chords(packing: &Packing, options: &ChordOptions) -> Result<ChordReport, CoreError> {
    check_packing(packing)?;
    let c = &packing.container;
    if !c.is_fully_periodic() {
        return Err(CoreError::Container(
            "chord lengths are measured along lines wrapped through a fully periodic box; this container has walls".into(),
        ));
    }
    if options.lines == 0 || options.bins == 0 {
        return Err(CoreError::Parameter(
            "the chord analysis needs at least one line and one histogram bin".into(),
        ));
    }
    let d = packing.dim;
    let grid = SphereGrid::new(packing, None);
    let mut rng = StdRng::seed_from_u64(options.seed);
    let l_max = c.lengths.iter().cloned().fold(0.0, f64::max);
    let (mut void, mut solid) = (Vec::new(), Vec::new());
    let mut intervals = Vec::new();
    for _ in 0..options.lines {
        let mut x0 = [0.0; 3];
        for k in 0..d {
            x0[k] = rng.random_range(0.0..c.lengths[k]);
        }
        let u = random_direction(&mut rng, d);
        let length = 4.0 * l_max;
        // Scanned past T by a box length, for the chords that start before T.
        let scanned = length + l_max;
        solid_intervals(&grid, &x0, &u, scanned, &mut intervals);
        started_chords(&intervals, length, scanned, &mut void, &mut solid);
    }
    let (mut axial_void, mut axial_solid) = (Vec::new(), Vec::new());
    for axis in 0..d {
        for _ in 0..options.axial_lines {
            let mut x0 = [0.0; 3];
            for k in 0..d {
                x0[k] = rng.random_range(0.0..c.lengths[k]);
            }
            let mut u = [0.0; 3];
            u[axis] = 1.0;
            let length = c.lengths[axis];
            solid_intervals(&grid, &x0, &u, length, &mut intervals);
            // One period of the closed line: intervals wrap around its end.
            let wrapped: Vec<[f64; 2]> = intervals
                .iter()
                .map(|&[a, b]| {
                    let shift = length * (a / length).floor();
                    [a - shift, b - shift]
                })
                .collect();
            closed_chords(wrapped, length, &mut axial_void, &mut axial_solid);
        }
    }
    let volume = c.volume();
    // Surface of a d-ball of radius R: d κ_d R^{d−1}.
    let surface: f64 = packing
        .diameters
        .iter()
        .map(|&dia| d as f64 * unit_ball_volume(d) * (0.5 * dia).powi(d as i32 - 1))
        .sum();
    let s = surface / volume;
    let phi = packing.phi();
    let c_d = d as f64 * unit_ball_volume(d) / unit_ball_volume(d - 1);
    let set = |v: Vec<f64>| chord_set(v, options.bins);
    Ok(ChordReport {
        void: set(void),
        solid: set(solid),
        axial_void: set(axial_void),
        axial_solid: set(axial_solid),
        specific_surface: s,
        void_mean_predicted: c_d * (1.0 - phi) / s,
        solid_mean_predicted: c_d * phi / s,
    })
}

fn random_direction(rng: &mut StdRng, d: usize) -> [f64; 3] {
    if d == 2 {
        let a = rng.random_range(0.0..std::f64::consts::TAU);
        return [a.cos(), a.sin(), 0.0];
    }
    // Uniform on the sphere: z uniform in [−1, 1] (Archimedes), azimuth uniform.
    let z: f64 = rng.random_range(-1.0..1.0);
    let a = rng.random_range(0.0..std::f64::consts::TAU);
    let rho = (1.0 - z * z).sqrt();
    [rho * a.cos(), rho * a.sin(), z]
}

/// The union of the sphere intersections of the segment `x0 + t u`, `t ∈ [0, length]`, as
/// sorted disjoint intervals of `t` (each sphere image near the segment counted).
fn solid_intervals(
    grid: &SphereGrid<'_>,
    x0: &[f64; 3],
    u: &[f64; 3],
    length: f64,
    out: &mut Vec<[f64; 2]>,
) {
    out.clear();
    // A sphere that cuts the line within h/2 of a step's point has its centre within
    // R_max + h/2 of it. Steps of 2(w − R_max) keep that reach within one cell width w, so each
    // step visits 3^d cells rather than 5^d; when the spheres are too large for that, steps of w.
    let w = grid.step();
    let h = if grid.r_max < 0.75 * w {
        // A hair short, so that round-off cannot push the reach past w.
        2.0 * (w - grid.r_max) * (1.0 - 1e-9)
    } else {
        w
    }
    .min(w);
    let steps = (length / h).ceil() as usize;
    let reach = grid.r_max + 0.5 * h;
    for k in 0..steps {
        let t = (k as f64 + 0.5) * h;
        let p = [x0[0] + t * u[0], x0[1] + t * u[1], x0[2] + t * u[2]];
        let p = grid.wrap(p);
        grid.for_each_near(&p, reach, |s, v| {
            let (_, r) = grid.sphere(s);
            let b = v[0] * u[0] + v[1] * u[1] + v[2] * u[2];
            let disc = b * b - (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + r * r;
            if disc > 0.0 {
                // The same sphere met from several steps gives the same interval; the union
                // below merges the copies.
                let root = disc.sqrt();
                out.push([t + b - root, t + b + root]);
            }
        });
    }
    out.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut merged: Vec<[f64; 2]> = Vec::with_capacity(out.len());
    for &iv in out.iter() {
        match merged.last_mut() {
            Some(last) if iv[0] <= last[1] => last[1] = last[1].max(iv[1]),
            _ => merged.push(iv),
        }
    }
    *out = merged;
}

/// Chords that start in `[0, length)` along a line scanned over `[0, scanned]`: solid
/// intervals and the gaps between them, each kept if it starts in the window and ends in the
/// scan.
fn started_chords(
    intervals: &[[f64; 2]],
    length: f64,
    scanned: f64,
    void: &mut Vec<f64>,
    solid: &mut Vec<f64>,
) {
    let starts = |t: f64| (0.0..length).contains(&t);
    for (i, iv) in intervals.iter().enumerate() {
        if starts(iv[0]) && iv[1] < scanned {
            solid.push(iv[1] - iv[0]);
        }
        if let Some(next) = intervals.get(i + 1)
            && starts(iv[1])
            && next[0] < scanned
        {
            void.push(next[0] - iv[1]);
        }
    }
}

/// Chords of a closed line of circumference `length`, intervals given in `[0, length)` plus an
/// overhang past `length` for those that wrap.
fn closed_chords(
    mut intervals: Vec<[f64; 2]>,
    length: f64,
    void: &mut Vec<f64>,
    solid: &mut Vec<f64>,
) {
    if intervals.is_empty() {
        return;
    }
    intervals.sort_by(|a, b| a[0].total_cmp(&b[0]));
    let mut merged: Vec<[f64; 2]> = Vec::with_capacity(intervals.len());
    for iv in intervals {
        match merged.last_mut() {
            Some(last) if iv[0] <= last[1] => last[1] = last[1].max(iv[1]),
            _ => merged.push(iv),
        }
    }
    // The last interval may wrap over the first ones.
    while merged.len() > 1 && merged[merged.len() - 1][1] - length >= merged[0][0] {
        let first = merged.remove(0);
        let last = merged.last_mut().expect("two intervals");
        last[1] = last[1].max(first[1] + length);
    }
    if merged.len() == 1 && merged[0][1] - merged[0][0] >= length {
        return;
    }
    for (i, iv) in merged.iter().enumerate() {
        solid.push(iv[1] - iv[0]);
        let next_start = match merged.get(i + 1) {
            Some(next) => next[0],
            None => merged[0][0] + length,
        };
        void.push(next_start - iv[1]);
    }
}

fn chord_set(mut lengths: Vec<f64>, bins: usize) -> ChordSet {
    lengths.retain(|&l| l > 0.0);
    let (mean, std) = super::mean_std(&lengths);
    let lo = lengths.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = lengths.iter().cloned().fold(0.0, f64::max);
    let distribution = if lengths.is_empty() {
        Histogram::default()
    } else {
        Histogram::logarithmic(&lengths, lo * (1.0 - 1e-9), hi * (1.0 + 1e-9), bins)
    };
    ChordSet {
        count: lengths.len(),
        mean,
        mean_error: if lengths.is_empty() {
            0.0
        } else {
            std / (lengths.len() as f64).sqrt()
        },
        distribution,
        lengths,
    }
}
