//! Contact candidates and their geometry.
//!
//! A candidate is a particle pair together with the periodic image of the second particle,
//! `r_ij = x_j + Σ_k n_k L_k e_k − x_i` (Baranau & Tallarek 2014 App. C: "x_ii may be non-zero", so a
//! particle may touch its own image in a small box), or a particle and a wall. Positions are
//! never wrapped during a run, so a candidate's image shift stays valid between rebuilds.
//! When every periodic side exceeds twice the interaction reach the core's cell list finds the
//! pairs (minimum image); in smaller boxes every image within reach is enumerated.

use packbench_core::neighbor::{CellList, for_each_image_pair, needs_images};
use packbench_core::{Container, MAX_DIM};

/// Identity of a contact candidate: stable across steps and candidate rebuilds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum Key {
    /// Particle `i` and the image of particle `j` shifted by `shift[k]` box lengths on axis k.
    Pair {
        i: u32,
        j: u32,
        shift: [i8; MAX_DIM],
    },
    /// Particle `i` and wall `id` of the container.
    Wall { i: u32, id: u32 },
}

/// A candidate evaluated at a configuration: the constraint `dist ≥ size · t`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Link {
    /// First particle.
    pub i: usize,
    /// Second particle (may equal `i` for a self-image), `None` for a wall.
    pub j: Option<usize>,
    /// Unit vector from `i` to `j` (to the wall, out of the container).
    pub normal: [f64; MAX_DIM],
    /// Centre distance |r_ij|, or the wall distance h.
    pub dist: f64,
    /// Nominal contact distance: D_ij = (D_i + D_j)/2 for pairs, D_i/2 for walls.
    pub size: f64,
}

impl Link {
    /// Gap at growth factor `t`: `dist − size·t` (length units).
    #[inline]
    pub fn gap(&self, t: f64) -> f64 {
        self.dist - self.size * t
    }

    /// Relative gap `dist/(size·t) − 1`.
    #[inline]
    pub fn rel_gap(&self, t: f64) -> f64 {
        self.dist / (self.size * t) - 1.0
    }

    /// The particle pair whose relative velocity this constraint couples, if it is a true pair
    /// (a self-image or a wall acts on one particle's coordinates only, or on none).
    #[inline]
    pub fn other(&self) -> Option<usize> {
        self.j.filter(|&j| j != self.i)
    }

    /// `a·y`: the rate of change of `dist` under velocities `y` (row of the bond matrix A,
    /// eqn 1 of Baranau & Tallarek 2014 divided by |x_ij|: n·(y_j − y_i); walls: −n·y_i).
    #[inline]
    pub fn rate(&self, y: &[f64], d: usize) -> f64 {
        let n = &self.normal[..d];
        let yi = &y[self.i * d..(self.i + 1) * d];
        match self.j {
            Some(j) if j == self.i => 0.0,
            Some(j) => {
                let yj = &y[j * d..(j + 1) * d];
                (0..d).map(|k| n[k] * (yj[k] - yi[k])).sum()
            }
            None => -(0..d).map(|k| n[k] * yi[k]).sum::<f64>(),
        }
    }

    /// The row's non-zero coefficients `(coordinate, a_k)`, so that `a·y` is [`Link::rate`]:
    /// `±n` on both particles of a pair (j first), `−n` on a wall's particle, none for a
    /// particle's own image. For assembling programs; the hot paths use `rate` and
    /// `add_transposed`.
    pub fn terms(&self, d: usize) -> Vec<(usize, f64)> {
        let n = &self.normal[..d];
        match self.j {
            Some(j) if j == self.i => Vec::new(),
            Some(j) => (0..d)
                .flat_map(|k| [(j * d + k, n[k]), (self.i * d + k, -n[k])])
                .collect(),
            None => (0..d).map(|k| (self.i * d + k, -n[k])).collect(),
        }
    }

    /// Adds `c · aᵀ` (this row transposed, times `c`) to the coordinate vector `out`.
    #[inline]
    pub fn add_transposed(&self, c: f64, out: &mut [f64], d: usize) {
        let n = &self.normal[..d];
        match self.j {
            Some(j) if j == self.i => {}
            Some(j) => {
                for k in 0..d {
                    out[j * d + k] += c * n[k];
                    out[self.i * d + k] -= c * n[k];
                }
            }
            None => {
                for k in 0..d {
                    out[self.i * d + k] -= c * n[k];
                }
            }
        }
    }
}

/// The candidates near a configuration, and what they were built for.
pub(crate) struct Candidates {
    /// Every candidate whose gap was below the skin at the last build.
    pub keys: Vec<Key>,
    /// Their gaps `dist − size·t` (length units) at the build.
    pub gaps: Vec<f64>,
    /// The skin (length units) the list was built with.
    pub skin: f64,
    /// Upper bound on how much any gap can have shrunk since the build (length units).
    pub consumed: f64,
}

impl Candidates {
    /// Candidates of the configuration `x` with actual diameters `t·D`, within `skin` of contact.
    pub fn build(container: &Container, x: &[f64], diameters: &[f64], t: f64, skin: f64) -> Self {
        let d = container.dim();
        let n = diameters.len();
        let actual: Vec<f64> = diameters.iter().map(|&v| v * t).collect();
        let d_max = actual.iter().fold(0.0f64, |m, &v| m.max(v));
        let mut keys = Vec::new();
        if needs_images(container, d_max + skin) {
            for_each_image_pair(container, x, &actual, skin, |i, j, shift| {
                let mut s8 = [0i8; MAX_DIM];
                for (s, &v) in s8.iter_mut().zip(shift) {
                    *s = v as i8;
                }
                keys.push(Key::Pair {
                    i: i as u32,
                    j: j as u32,
                    shift: s8,
                });
            });
        } else {
            let mut wrapped = x.to_vec();
            for p in wrapped.chunks_exact_mut(d) {
                container.wrap(p);
            }
            let mut delta = [0.0; MAX_DIM];
            CellList::for_each_near_pair(container, &wrapped, &actual, skin, |a, b| {
                let (i, j) = (a.min(b), a.max(b));
                container.separation(
                    &wrapped[i * d..(i + 1) * d],
                    &wrapped[j * d..(j + 1) * d],
                    &mut delta[..d],
                );
                let mut shift = [0i8; MAX_DIM];
                for k in 0..d {
                    if container.periodic[k] {
                        let raw = x[j * d + k] - x[i * d + k];
                        shift[k] = ((delta[k] - raw) / container.lengths[k]).round() as i8;
                    }
                }
                keys.push(Key::Pair {
                    i: i as u32,
                    j: j as u32,
                    shift,
                });
            });
        }
        if container.has_walls() {
            for i in 0..n {
                container.for_each_wall(&x[i * d..(i + 1) * d], 0.5 * actual[i] + skin, |w| {
                    keys.push(Key::Wall {
                        i: i as u32,
                        id: w.id as u32,
                    })
                });
            }
        }
        keys.sort_unstable();
        keys.dedup();
        let gaps = keys
            .iter()
            .map(|k| link(container, x, diameters, k).gap(t))
            .collect();
        Candidates {
            keys,
            gaps,
            skin,
            consumed: 0.0,
        }
    }

    /// The candidates (with their index) whose gap may now be `reach` or less: a gap shrank by
    /// at most `consumed` since the build. Scans of the whole list evaluate only these.
    pub fn within(&self, reach: f64) -> impl Iterator<Item = (usize, &Key)> {
        let limit = reach + self.consumed;
        self.gaps
            .iter()
            .zip(&self.keys)
            .enumerate()
            .filter(move |(_, (gap, _))| **gap <= limit)
            .map(|(i, (_, key))| (i, key))
    }

    /// True when a gap may have shrunk by the skin since the build, so a pair may be missing.
    pub fn is_stale(&self) -> bool {
        self.consumed >= 0.5 * self.skin
    }
}

/// Evaluates candidate `key` at positions `x` (nominal diameters `diameters`).
pub(crate) fn link(container: &Container, x: &[f64], diameters: &[f64], key: &Key) -> Link {
    let d = container.dim();
    let mut normal = [0.0; MAX_DIM];
    match *key {
        Key::Pair { i, j, shift } => {
            let (i, j) = (i as usize, j as usize);
            for k in 0..d {
                normal[k] = x[j * d + k] - x[i * d + k] + shift[k] as f64 * container.lengths[k];
            }
            let dist = normal[..d].iter().map(|v| v * v).sum::<f64>().sqrt();
            if dist > 0.0 {
                normal[..d].iter_mut().for_each(|v| *v /= dist);
            } else {
                // Coincident centres have no direction; any unit vector keeps the row finite.
                normal[0] = 1.0;
            }
            Link {
                i,
                j: Some(j),
                normal,
                dist,
                size: 0.5 * (diameters[i] + diameters[j]),
            }
        }
        Key::Wall { i, id } => {
            let i = i as usize;
            let mut dist = f64::INFINITY;
            container.for_each_wall(&x[i * d..(i + 1) * d], f64::INFINITY, |w| {
                if w.id == id as usize {
                    dist = w.distance;
                    normal[..d].copy_from_slice(w.normal);
                }
            });
            Link {
                i,
                j: None,
                normal,
                dist,
                size: 0.5 * diameters[i],
            }
        }
    }
}

/// The largest relative overlap `1 − dist/(size·t)` over `keys`, with the offending particles.
pub(crate) fn worst_overlap(
    container: &Container,
    x: &[f64],
    diameters: &[f64],
    t: f64,
    keys: &[Key],
) -> (f64, usize, usize) {
    let mut worst = (0.0, 0, 0);
    for key in keys {
        let l = link(container, x, diameters, key);
        let ov = -l.rel_gap(t);
        if ov > worst.0 {
            worst = (ov, l.i, l.j.unwrap_or(l.i));
        }
    }
    worst
}
