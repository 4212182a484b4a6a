//! The neighbours of one particle at a time, for lists that refresh only the particles that
//! moved (the upkeep of RCPGenerator 1.0).
//!
//! A [`CellList`](super::CellList) finds every pair at once, each by its larger particle; a
//! single small particle asking for all its partners would have to search as far as the
//! largest diameter reaches. Here the particles are split into levels by diameter, each level
//! twice as wide as the one below, with cells as wide as its largest diameter plus the skin
//! (the multilevel grid of Ogarko & Luding 2012). A query searches each level only within its
//! own reach, so a small particle among spheres 15× larger visits a few cells per level.

use crate::container::Container;

/// End of a cell's chain.
const NONE: u32 = u32::MAX;

/// How far a query must look beyond contact.
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    /// Partners are those closer than contact plus `skin`.
    pub skin: f64,
    /// How far a particle may be from where it was last placed ([`NearQuery::place`]).
    pub slack: f64,
    /// How much the diameters may grow, as a factor, before the query is built again.
    pub growth: f64,
}

/// Cells of one level: the particles whose diameters are at most `max_diameter`.
struct Level {
    max_diameter: f64,
    counts: Vec<usize>,
    widths: Vec<f64>,
    /// First particle of each cell's chain.
    head: Vec<u32>,
}

/// Particles binned by size and position, to list the near partners of any one of them. A
/// particle can be placed again as it moves ([`NearQuery::place`]), so the query lives as long
/// as the list it serves.
pub struct NearQuery {
    reach: Reach,
    levels: Vec<Level>,
    /// Per particle: its level, its cell there, and its neighbours in the cell's chain.
    level_of: Vec<u32>,
    cell_of: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    /// A query's cells per axis: (cell index, distance from the particle along the axis).
    axes: Vec<Vec<(usize, f64)>>,
}

impl NearQuery {
    /// Indexes `positions` (row-major, `container.dim()` per particle). The first level holds
    /// diameters up to the 90th percentile; each further level twice the one below.
    pub fn new(container: &Container, positions: &[f64], diameters: &[f64], reach: Reach) -> Self {
        let d = container.dim();
        let n = diameters.len();
        let largest = diameters.iter().fold(0.0f64, |m, &v| m.max(v));
        let mut bounds = Vec::new();
        if n > 0 {
            let mut edge = super::typical_diameter(diameters).max(f64::MIN_POSITIVE);
            bounds.push(edge);
            while edge < largest {
                edge = (2.0 * edge).min(largest);
                bounds.push(edge);
            }
        }
        let level_of: Vec<u32> = diameters
            .iter()
            .map(|&v| bounds.partition_point(|&b| b < v).min(bounds.len() - 1) as u32)
            .collect();
        let mut members = vec![0usize; bounds.len()];
        for &l in &level_of {
            members[l as usize] += 1;
        }
        let levels = bounds
            .iter()
            .zip(&members)
            .map(|(&b, &m)| {
                let b = b * reach.growth;
                Level::new(container, b, b + reach.skin, m)
            })
            .collect();
        let mut query = NearQuery {
            reach,
            levels,
            level_of,
            cell_of: vec![NONE; n],
            next: vec![NONE; n],
            prev: vec![NONE; n],
            axes: vec![Vec::new(); d],
        };
        for i in 0..n {
            query.place(container, i, &positions[i * d..(i + 1) * d]);
        }
        query
    }

    /// Bins particle `i` at `x`, its position from now on up to the slack.
    pub fn place(&mut self, container: &Container, i: usize, x: &[f64]) {
        let level = &mut self.levels[self.level_of[i] as usize];
        let cell = (0..x.len()).fold(0usize, |c, k| {
            let (w, count) = (level.widths[k], level.counts[k]);
            c * count + super::cell_list::axis_cell(x[k], w, count, container.periodic[k])
        }) as u32;
        let old = self.cell_of[i];
        if old == cell {
            return;
        }
        if old != NONE {
            let (p, q) = (self.prev[i], self.next[i]);
            if p == NONE {
                level.head[old as usize] = q;
            } else {
                self.next[p as usize] = q;
            }
            if q != NONE {
                self.prev[q as usize] = p;
            }
        }
        let h = level.head[cell as usize];
        self.next[i] = h;
        self.prev[i] = NONE;
        if h != NONE {
            self.prev[h as usize] = i as u32;
        }
        level.head[cell as usize] = i as u32;
        self.cell_of[i] = cell;
    }

    /// Calls `f(j)` once for every particle `j ≠ i` with |r_ij| < (D_i + D_j)/2 + skin
    /// (minimum image along periodic axes), in no particular order. `positions` are the
    /// current ones, each within the slack of where it was placed; `diameters` within the
    /// growth of those the query was built from.
    pub fn for_each_near(
        &mut self,
        container: &Container,
        positions: &[f64],
        diameters: &[f64],
        i: usize,
        mut f: impl FnMut(usize),
    ) {
        let d = container.dim();
        let xi = &positions[i * d..(i + 1) * d];
        let reach_i = 0.5 * diameters[i] + self.reach.skin;
        for level in &self.levels {
            let reach = reach_i + 0.5 * level.max_diameter + 2.0 * self.reach.slack;
            level.cells_within(container, xi, reach, &mut self.axes);
            let mut pick = [0usize; crate::MAX_DIM];
            'cells: loop {
                let far: f64 = (0..d).map(|k| self.axes[k][pick[k]].1.powi(2)).sum();
                if far < reach * reach {
                    let cell = (0..d).fold(0, |c, k| c * level.counts[k] + self.axes[k][pick[k]].0);
                    let mut j = level.head[cell];
                    while j != NONE {
                        let ju = j as usize;
                        j = self.next[ju];
                        if ju == i {
                            continue;
                        }
                        let xj = &positions[ju * d..(ju + 1) * d];
                        let mut r2 = 0.0;
                        for k in 0..d {
                            let mut t = xj[k] - xi[k];
                            let l = container.lengths[k];
                            if container.periodic[k] && t.abs() > 0.5 * l {
                                t -= l * (t / l).round();
                            }
                            r2 += t * t;
                        }
                        let cut = reach_i + 0.5 * diameters[ju];
                        if r2 < cut * cut {
                            f(ju);
                        }
                    }
                }
                for k in (0..d).rev() {
                    pick[k] += 1;
                    if pick[k] < self.axes[k].len() {
                        continue 'cells;
                    }
                    pick[k] = 0;
                }
                break;
            }
        }
    }
}

impl Level {
    /// Empty cells no narrower than `cell_size` for `members` particles of diameters up to
    /// `max_diameter`.
    fn new(container: &Container, max_diameter: f64, cell_size: f64, members: usize) -> Self {
        let (counts, widths) = super::cell_list::grid(container, cell_size, members);
        let total: usize = counts.iter().product();
        Level {
            max_diameter,
            counts,
            widths,
            head: vec![NONE; total],
        }
    }

    /// Writes into `axes`, per axis, the cells that come within `reach` of `x` with their
    /// distance from it, each cell once (an axis whose cells the reach wraps around is
    /// listed whole).
    fn cells_within(
        &self,
        container: &Container,
        x: &[f64],
        reach: f64,
        axes: &mut [Vec<(usize, f64)>],
    ) {
        for (k, axis) in axes.iter_mut().enumerate() {
            axis.clear();
            let (w, count) = (self.widths[k], self.counts[k] as isize);
            let periodic = container.periodic[k];
            let r = (reach / w).ceil() as isize;
            // Distance along the axis from x to cell c (an index of any image); along a walled
            // axis the edge cells also hold the particles poking through the wall.
            let gap = |c: isize| {
                let lo = if !periodic && c == 0 {
                    f64::NEG_INFINITY
                } else {
                    c as f64 * w
                };
                let hi = if !periodic && c == count - 1 {
                    f64::INFINITY
                } else {
                    (c + 1) as f64 * w
                };
                (lo - x[k]).max(x[k] - hi).max(0.0)
            };
            let home = (x[k] / w).floor() as isize;
            if !periodic {
                let home = home.clamp(0, count - 1);
                axis.extend(
                    ((home - r).max(0)..=(home + r).min(count - 1)).map(|c| (c as usize, gap(c))),
                );
            } else if 2 * r + 1 >= count {
                // Every cell once, at its image nearest x.
                axis.extend((0..count).map(|c| {
                    let near = c + count * ((home - c) as f64 / count as f64).round() as isize;
                    let g = [near - count, near, near + count].map(gap);
                    (c as usize, g.into_iter().fold(f64::INFINITY, f64::min))
                }));
            } else {
                axis.extend((home - r..=home + r).map(|c| (c.rem_euclid(count) as usize, gap(c))));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(c: &Container, x: &[f64], dia: &[f64], skin: f64, i: usize) -> Vec<usize> {
        let d = c.dim();
        let mut dx = vec![0.0; d];
        (0..dia.len())
            .filter(|&j| {
                c.separation(&x[i * d..(i + 1) * d], &x[j * d..(j + 1) * d], &mut dx);
                let cut = 0.5 * (dia[i] + dia[j]) + skin;
                j != i && dx.iter().map(|t| t * t).sum::<f64>() < cut * cut
            })
            .collect()
    }

    fn uniform(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Every query finds exactly the brute-force partners, each once: a power law 1–15 in
    /// periodic and walled boxes, a box too thin for three cells, 2D and 3D, and particles
    /// poking through walls.
    #[test]
    fn every_query_finds_the_brute_force_partners() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let cases: [(&[f64], &[bool]); 5] = [
            (&[30.0, 30.0, 30.0], &[false; 3]),
            (&[30.0, 15.0, 30.0], &[false, true, false]),
            (&[40.0, 40.0, 2.5], &[false; 3]),
            (&[25.0, 25.0], &[false, false]),
            (&[25.0, 25.0], &[true, true]),
        ];
        for (lengths, walls) in cases {
            let c = Container::with_flags(lengths, walls).unwrap();
            let d = lengths.len();
            let n = 400;
            let x: Vec<f64> = (0..n * d)
                .map(|e| lengths[e % d] * (1.1 * uniform(&mut state) - 0.05))
                .collect();
            // D = (1 − u(1 − 15⁻²))^(−1/2): a power law p(D) ∝ D⁻³ on [1, 15], capped below
            // half the thinnest periodic length.
            let thin = (0..d)
                .filter(|&k| !walls[k])
                .map(|k| lengths[k])
                .fold(f64::INFINITY, f64::min);
            let dia: Vec<f64> = (0..n)
                .map(|_| {
                    let u = uniform(&mut state);
                    (1.0 - u * (1.0 - 1.0 / 225.0)).powf(-0.5).min(0.45 * thin)
                })
                .collect();
            let skin = 0.3;
            // Placed where they were, then moved by up to the slack; the diameters grown.
            let reach = Reach {
                skin,
                slack: 0.2,
                growth: 1.05,
            };
            let mut q = NearQuery::new(&c, &x, &dia, reach);
            let x: Vec<f64> = x
                .iter()
                .map(|v| v + 0.2 * (2.0 * uniform(&mut state) - 1.0) / (d as f64).sqrt())
                .collect();
            let dia: Vec<f64> = dia
                .iter()
                .map(|v| v * (1.0 + 0.05 * uniform(&mut state)))
                .collect();
            let check = |q: &mut NearQuery, x: &[f64]| {
                for i in 0..n {
                    let mut found = Vec::new();
                    q.for_each_near(&c, x, &dia, i, |j| found.push(j));
                    found.sort_unstable();
                    assert_eq!(
                        found,
                        brute(&c, x, &dia, skin, i),
                        "{lengths:?} particle {i}"
                    );
                }
            };
            check(&mut q, &x);
            // A third of them placed again far from where they were.
            let mut x = x;
            for i in 0..n / 3 {
                for k in 0..d {
                    x[i * d + k] = lengths[k] * (1.1 * uniform(&mut state) - 0.05);
                }
                q.place(&c, i, &x[i * d..(i + 1) * d]);
            }
            check(&mut q, &x);
        }
    }
}
