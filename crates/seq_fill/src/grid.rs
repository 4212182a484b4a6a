//! The spatial grid behind every overlap check and parent search, so that the cost of placing
//! a sphere does not grow with the number already placed.
//!
//! Each sphere is entered in every cell its box `[x − R − m, x + R + m]` touches, `m` being
//! the largest gap that still matters (max(ε, δ)·r̄). A query for a ball of radius R at x then
//! visits only the cells of `[x − R, x + R]`, yet finds every sphere whose surface lies within
//! `m` of it, however broad the size distribution (a large sphere sits in many cells instead of
//! forcing every query to search far). Axes wrap for a periodic (Method 2) brick.

/// The grid over a box `[0, L_k)`.
pub(crate) struct Grid<const D: usize> {
    counts: [usize; D],
    widths: [f64; D],
    periodic: bool,
    cells: Vec<Vec<u32>>,
    /// `stamp[i] == query` when sphere `i` was already reported by the current query.
    stamp: Vec<u32>,
    query: u32,
}

/// A run of cells along one axis: `len` cells from `start`, wrapping modulo the count.
#[derive(Clone, Copy, Default)]
struct Span {
    start: usize,
    len: usize,
}

impl<const D: usize> Grid<D> {
    /// A grid over `lengths` with cells no narrower than `cell`, and at most about
    /// `max_cells` cells in all.
    pub(crate) fn new(lengths: &[f64; D], cell: f64, max_cells: usize, periodic: bool) -> Self {
        let mut size = cell.max(f64::MIN_POSITIVE);
        let total = |s: f64| -> f64 { lengths.iter().map(|&l| (l / s).floor().max(1.0)).product() };
        while total(size) > max_cells.max(1) as f64 {
            size *= 1.2;
        }
        let mut counts = [1; D];
        let mut widths = [0.0; D];
        for k in 0..D {
            counts[k] = ((lengths[k] / size).floor() as usize).max(1);
            widths[k] = lengths[k] / counts[k] as f64;
        }
        Grid {
            counts,
            widths,
            periodic,
            cells: vec![Vec::new(); counts.iter().product()],
            stamp: Vec::new(),
            query: 0,
        }
    }

    fn spans(&self, x: &[f64; D], reach: f64) -> [Span; D] {
        let mut spans = [Span::default(); D];
        for k in 0..D {
            let n = self.counts[k];
            let lo = ((x[k] - reach) / self.widths[k]).floor();
            let hi = ((x[k] + reach) / self.widths[k]).floor();
            spans[k] = if self.periodic {
                let len = ((hi - lo) as usize + 1).min(n);
                Span {
                    start: (lo as i64).rem_euclid(n as i64) as usize,
                    len,
                }
            } else {
                let lo = lo.clamp(0.0, (n - 1) as f64) as usize;
                let hi = hi.clamp(0.0, (n - 1) as f64) as usize;
                Span {
                    start: lo,
                    len: hi - lo + 1,
                }
            };
        }
        spans
    }

    /// Calls `f` with the flat index of every cell of the spans.
    fn for_each_cell(counts: &[usize; D], spans: &[Span; D], mut f: impl FnMut(usize)) {
        let mut t = [0usize; D];
        loop {
            let mut c = 0;
            for k in 0..D {
                c = c * counts[k] + (spans[k].start + t[k]) % counts[k];
            }
            f(c);
            let mut k = D;
            loop {
                if k == 0 {
                    return;
                }
                k -= 1;
                t[k] += 1;
                if t[k] < spans[k].len {
                    break;
                }
                t[k] = 0;
            }
        }
    }

    /// Enters sphere `id` at `x` in every cell within `reach` (its radius plus the margin).
    pub(crate) fn insert(&mut self, id: u32, x: &[f64; D], reach: f64) {
        let spans = self.spans(x, reach);
        let cells = &mut self.cells;
        Self::for_each_cell(&self.counts, &spans, |c| cells[c].push(id));
        if self.stamp.len() <= id as usize {
            self.stamp.resize(id as usize + 1, 0);
        }
    }

    /// Calls `f` once for every sphere entered in a cell within `reach` of `x`: a superset of
    /// the spheres whose surface lies within the margin of the ball of radius `reach` at `x`.
    pub(crate) fn for_each_candidate(&mut self, x: &[f64; D], reach: f64, mut f: impl FnMut(u32)) {
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.stamp.fill(0);
            self.query = 1;
        }
        let spans = self.spans(x, reach);
        let (cells, stamp, q) = (&self.cells, &mut self.stamp, self.query);
        Self::for_each_cell(&self.counts, &spans, |c| {
            for &id in &cells[c] {
                if stamp[id as usize] != q {
                    stamp[id as usize] = q;
                    f(id);
                }
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn candidates_include_every_sphere_within_reach_plus_margin_periodic_or_not() {
        for periodic in [false, true] {
            let l = [10.0, 7.0];
            let mut g = Grid::<2>::new(&l, 1.0, 10_000, periodic);
            let pts = [([0.2, 0.3], 0.5), ([9.8, 6.9], 0.4), ([5.0, 3.5], 3.0)];
            let m = 0.25;
            for (i, (x, r)) in pts.iter().enumerate() {
                g.insert(i as u32, x, r + m);
            }
            let mut seen = Vec::new();
            g.for_each_candidate(&[0.1, 6.8], 0.3, |i| seen.push(i));
            // The large sphere at the centre reaches within 1.3 of (0.1, 6.8)? No: 5.9 away.
            assert_eq!(seen.contains(&1), periodic, "{seen:?}");
            assert!(!seen.contains(&2));
            seen.clear();
            g.for_each_candidate(&[5.0, 0.2], 0.1, |i| seen.push(i));
            assert_eq!(seen, vec![2]);
        }
    }
}
