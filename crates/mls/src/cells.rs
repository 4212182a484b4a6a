//! The cell grid of bounding-sphere centres: each particle's bounding sphere (see
//! `event::neighbour_exit`) has its centre in one cell of a regular grid whose cells are at
//! least as wide as the largest sum of two bounding radii, so two bounding spheres can only
//! overlap when their centres lie in the same or adjacent cells. A centre moves only when its
//! particle renews its neighbour list, so the grid changes one renewal at a time. The core's
//! `CellList` serves static pair lists.
//!
//! Axes with one or two cells make every cell along them adjacent; neighbour coordinates are
//! deduplicated so no pair is visited twice.

const NIL: u32 = u32::MAX;

/// Distinct neighbouring coordinates of one cell coordinate along one axis.
#[derive(Clone, Copy, Debug, Default)]
struct Around {
    c: [u32; 3],
    len: u8,
}

impl Around {
    fn contains(&self, c: u32) -> bool {
        self.c[..self.len as usize].contains(&c)
    }
}

/// A grid of `dims[k]` cells of width `width[k]` per axis with doubly linked cell lists.
pub(crate) struct CellGrid<const D: usize> {
    pub dims: [usize; D],
    pub width: [f64; D],
    stride: [usize; D],
    head: Vec<u32>,
    next: Vec<u32>,
    prev: Vec<u32>,
    /// Cell coordinates of each particle.
    pub coord: Vec<[u32; D]>,
    /// `around[k][c]`: neighbouring coordinates of coordinate `c` along axis `k`.
    around: Vec<Vec<Around>>,
}

impl<const D: usize> CellGrid<D> {
    /// Builds a grid over a box of side `len` with cells about `cell_min` wide, but never fewer
    /// than four per axis while four cells are still wider than `d_max` (four cells keep minimum
    /// images unambiguous, see `System::pair_time_images`), and files every position (which
    /// must lie in the box up to rounding) into its cell.
    pub fn build(
        len: &[f64; D],
        periodic: &[bool; D],
        cell_min: f64,
        d_max: f64,
        n: usize,
        pos: impl Fn(usize) -> [f64; D],
    ) -> Self {
        let mut grid = CellGrid {
            dims: [1; D],
            width: [0.0; D],
            stride: [0; D],
            head: Vec::new(),
            next: Vec::new(),
            prev: Vec::new(),
            coord: Vec::new(),
            around: vec![Vec::new(); D],
        };
        grid.rebuild(len, periodic, cell_min, d_max, n, pos);
        grid
    }

    /// [`Self::build`] in place, reusing this grid's storage: the MLS runs rebuild their grid
    /// every pressure window, and fresh arrays each time fragmented glibc's heap until the
    /// resident memory grew by megabytes per second (1.2 GB after 6 min at N = 2000).
    pub fn rebuild(
        &mut self,
        len: &[f64; D],
        periodic: &[bool; D],
        cell_min: f64,
        d_max: f64,
        n: usize,
        pos: impl Fn(usize) -> [f64; D],
    ) {
        let mut total = 1usize;
        for (k, &len_k) in len.iter().enumerate() {
            // A cap keeps the cell count bounded even for a degenerate `cell_min`.
            let n = (len_k / cell_min).floor();
            self.dims[k] = if n.is_finite() && n >= 1.0 {
                (n as usize).min(1 << 20)
            } else {
                1
            };
            if self.dims[k] < 4 && len_k / 4.0 > d_max {
                self.dims[k] = 4;
            }
            self.width[k] = len_k / self.dims[k] as f64;
            self.stride[k] = total;
            total *= self.dims[k];
        }
        for (k, &periodic_k) in periodic.iter().enumerate() {
            let n = self.dims[k] as i64;
            let around = &mut self.around[k];
            around.clear();
            around.extend((0..n).map(|c| {
                let mut a = Around::default();
                for dc in -1..=1 {
                    let mut m = c + dc;
                    if periodic_k {
                        m = m.rem_euclid(n);
                    } else if !(0..n).contains(&m) {
                        continue;
                    }
                    if !a.contains(m as u32) {
                        a.c[a.len as usize] = m as u32;
                        a.len += 1;
                    }
                }
                a
            }));
        }
        for v in [&mut self.head, &mut self.next, &mut self.prev] {
            v.clear();
        }
        self.head.resize(total, NIL);
        self.next.resize(n, NIL);
        self.prev.resize(n, NIL);
        self.coord.clear();
        self.coord.resize(n, [0; D]);
        for i in 0..n {
            self.coord[i] = self.coord_of(&pos(i));
            self.link(i);
        }
    }

    /// Cell coordinates of a point in the box (clamped into the grid against rounding).
    fn coord_of(&self, x: &[f64; D]) -> [u32; D] {
        std::array::from_fn(|k| {
            let c = (x[k] / self.width[k]).floor();
            (c.max(0.0) as usize).min(self.dims[k] - 1) as u32
        })
    }

    /// The largest distance at which adjacent cells hold every possible partner: the narrowest
    /// width over axes with three or more cells (∞ if every axis has at most two).
    pub fn diameter_limit(&self) -> f64 {
        (0..D)
            .filter(|&k| self.dims[k] >= 3)
            .map(|k| self.width[k])
            .fold(f64::INFINITY, f64::min)
    }

    /// Linear index of the cell of particle `i`.
    pub fn cell_of(&self, i: usize) -> usize {
        self.cell_index(&self.coord[i])
    }

    fn cell_index(&self, c: &[u32; D]) -> usize {
        (0..D).map(|k| c[k] as usize * self.stride[k]).sum()
    }

    fn link(&mut self, i: usize) {
        let cell = self.cell_index(&self.coord[i]);
        let h = self.head[cell];
        self.next[i] = h;
        self.prev[i] = NIL;
        if h != NIL {
            self.prev[h as usize] = i as u32;
        }
        self.head[cell] = i as u32;
    }

    fn unlink(&mut self, i: usize) {
        let (p, n) = (self.prev[i], self.next[i]);
        if p != NIL {
            self.next[p as usize] = n;
        } else {
            let cell = self.cell_index(&self.coord[i]);
            self.head[cell] = n;
        }
        if n != NIL {
            self.prev[n as usize] = p;
        }
    }

    /// Files particle `i` under the cell of point `x` (in the box up to rounding).
    pub fn relocate(&mut self, i: usize, x: &[f64; D]) {
        let c = self.coord_of(x);
        if self.coord[i] != c {
            self.unlink(i);
            self.coord[i] = c;
            self.link(i);
        }
    }

    /// Calls `f` for every particle in the cells adjacent to (and including) cell `c`.
    #[inline]
    pub fn for_each_near(&self, c: &[u32; D], mut f: impl FnMut(usize)) {
        let lists: [Around; D] = std::array::from_fn(|k| self.around[k][c[k] as usize]);
        self.visit(&lists, &mut f);
    }

    /// Odometer over the Cartesian product of per-axis coordinate lists.
    #[inline]
    fn visit(&self, lists: &[Around; D], f: &mut impl FnMut(usize)) {
        if lists.iter().any(|a| a.len == 0) {
            return;
        }
        let mut idx = [0u8; D];
        loop {
            let mut cell = 0;
            for k in 0..D {
                cell += lists[k].c[idx[k] as usize] as usize * self.stride[k];
            }
            let mut p = self.head[cell];
            while p != NIL {
                f(p as usize);
                p = self.next[p as usize];
            }
            let mut k = 0;
            loop {
                if k == D {
                    return;
                }
                idx[k] += 1;
                if idx[k] < lists[k].len {
                    break;
                }
                idx[k] = 0;
                k += 1;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_are_distinct_and_cover_small_periodic_axes() {
        let pos = [[0.1, 0.1], [1.9, 0.1], [0.9, 0.9], [1.5, 1.5]];
        let g = CellGrid::<2>::build(&[2.0, 2.0], &[true, true], 0.6, 0.6, pos.len(), |i| pos[i]);
        assert_eq!(g.dims, [3, 3]);
        let mut seen = Vec::new();
        g.for_each_near(&g.coord[0], |j| seen.push(j));
        seen.sort();
        assert_eq!(seen, vec![0, 1, 2, 3]);
        let g = CellGrid::<2>::build(&[2.0, 2.0], &[true, false], 0.9, 0.9, pos.len(), |i| pos[i]);
        assert_eq!(g.dims, [2, 2]);
        let mut seen = Vec::new();
        g.for_each_near(&g.coord[3], |j| seen.push(j));
        seen.sort();
        assert_eq!(seen, vec![0, 1, 2, 3]);
        assert_eq!(g.diameter_limit(), f64::INFINITY);
    }

    #[test]
    fn relocation_moves_a_particle_between_cell_lists() {
        let pos = [[0.5, 0.5], [3.5, 0.5], [2.5, 0.5]];
        let mut g =
            CellGrid::<2>::build(&[5.0, 1.0], &[false, true], 1.0, 1.0, pos.len(), |i| pos[i]);
        assert_eq!(g.dims, [5, 1]);
        let near = |g: &CellGrid<2>, i: usize| {
            let mut seen = Vec::new();
            g.for_each_near(&g.coord[i], |j| seen.push(j));
            seen.sort();
            seen
        };
        assert_eq!(near(&g, 0), vec![0]);
        g.relocate(0, &[1.5, 0.5]);
        assert_eq!(near(&g, 0), vec![0, 2]);
        g.relocate(0, &[4.9, 0.5]);
        assert_eq!(near(&g, 0), vec![0, 1]);
        assert_eq!(near(&g, 2), vec![1, 2]);
    }
}
