//! A cell list with a size-aware stencil.
//!
//! Cells are sized for a typical (90th-percentile) diameter, not the largest, and every pair
//! is found by its larger particle, which searches the cells within its own reach `2r_i + skin`.
//! Small particles therefore scan 3^d cells while the rare large ones scan more, so broad size
//! distributions (a power law from 1 to 15) need no tuning and no neighbour cap.

use rayon::prelude::*;

use crate::container::Container;

/// Cell index of a set of particles; built once per configuration.
pub struct CellList {
    dim: usize,
    /// Cells per axis.
    counts: Vec<usize>,
    /// Cell width per axis (≥ the nominal cell size).
    widths: Vec<f64>,
    /// `start[c]..start[c+1]` indexes `order` for the particles of cell `c`.
    start: Vec<u32>,
    /// Particle indices sorted by cell.
    order: Vec<u32>,
}

/// Particles from which [`CellList::near_pairs`] scans ranges of cells on rayon's threads (when
/// it has more than one): the same pairs in the same order as one thread, since each range's
/// pairs are kept in order and joined in the order of the ranges.
const PARALLEL_MIN_PARTICLES: usize = 8192;

/// Upper bound on cells per particle, to bound memory for sparse or thin systems.
const MAX_CELLS_PER_PARTICLE: f64 = 4.0;

impl CellList {
    /// Indexes `positions` (row-major, `container.dim()` per particle) with cells no narrower
    /// than `cell_size`.
    pub fn new(container: &Container, positions: &[f64], cell_size: f64) -> Self {
        let d = container.dim();
        let n = positions.len() / d;
        let (counts, widths) = grid(container, cell_size, n.max(1));
        let total: usize = counts.iter().product();
        let mut cell_of = vec![0u32; n];
        let mut start = vec![0u32; total + 1];
        for i in 0..n {
            let mut c = 0usize;
            for k in 0..d {
                c = c * counts[k]
                    + axis_cell(
                        positions[i * d + k],
                        widths[k],
                        counts[k],
                        container.periodic[k],
                    );
            }
            cell_of[i] = c as u32;
            start[c + 1] += 1;
        }
        for c in 0..total {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut order = vec![0u32; n];
        for i in 0..n {
            let c = cell_of[i] as usize;
            order[fill[c] as usize] = i as u32;
            fill[c] += 1;
        }
        CellList {
            dim: d,
            counts,
            widths,
            start,
            order,
        }
    }

    /// Every pair `(i, j)` with `|r_ij| < (D_i + D_j)/2 + skin`, each pair once, the larger
    /// particle first (either order among equal diameters). Distances use the minimum image.
    pub fn near_pairs(
        container: &Container,
        positions: &[f64],
        diameters: &[f64],
        skin: f64,
    ) -> Vec<(u32, u32)> {
        let mut pairs = Vec::new();
        Self::near_pairs_into(container, positions, diameters, skin, &mut pairs);
        pairs
    }

    /// [`CellList::near_pairs`] written into `pairs` (cleared first): a caller that builds its
    /// list again and again keeps the memory, which at N = 10⁶ is hundreds of MB per build
    /// and otherwise is mapped afresh each time.
    pub fn near_pairs_into(
        container: &Container,
        positions: &[f64],
        diameters: &[f64],
        skin: f64,
        pairs: &mut Vec<(u32, u32)>,
    ) {
        pairs.clear();
        if diameters.len() >= PARALLEL_MIN_PARTICLES && rayon::current_num_threads() > 1 {
            let cell_size = typical_diameter(diameters) + skin;
            let cl = CellList::new(container, positions, cell_size);
            return crate::dispatch_dim!(
                container.dim(),
                D => cl.scan::<D>(container, positions, diameters, skin).pairs_in_parallel(pairs),
                _ => unreachable!("dimension checked by Container::validate"),
            );
        }
        // Dense packings list a few pairs per particle; reserving that avoids most regrowth.
        pairs.reserve(4 * diameters.len());
        Self::for_each_near_pair(container, positions, diameters, skin, |i, j| {
            pairs.push((i as u32, j as u32))
        });
    }

    /// Calls `f(i, j)` for every pair of [`CellList::near_pairs`], in a deterministic order.
    pub fn for_each_near_pair(
        container: &Container,
        positions: &[f64],
        diameters: &[f64],
        skin: f64,
        f: impl FnMut(usize, usize),
    ) {
        if diameters.len() < 2 {
            return;
        }
        let cell_size = typical_diameter(diameters) + skin;
        let cl = CellList::new(container, positions, cell_size);
        crate::dispatch_dim!(
            container.dim(),
            D => crate::widest_simd::with_avx2(#[inline(always)] || {
                cl.scan::<D>(container, positions, diameters, skin).all_pairs(f)
            }),
            _ => unreachable!("dimension checked by Container::validate"),
        )
    }

    /// The scan, monomorphised over the dimension, ready to pair ranges of cells.
    ///
    /// Particles are copied into cell order, the small ones first within each cell, so the
    /// inner loops read contiguous memory. A particle whose reach is one cell on every axis is
    /// "small". Two small particles are paired cell pair by cell pair through a half stencil
    /// (the home cell and its lexicographically later neighbours), which visits each cell pair
    /// once with a branch-light inner loop; any pair with a larger particle is found by that
    /// particle through its full stencil. The half stencil needs distinct neighbour cells, i.e.
    /// at least three cells along every periodic axis.
    fn scan<'a, const D: usize>(
        &'a self,
        container: &Container,
        positions: &[f64],
        diameters: &[f64],
        skin: f64,
    ) -> Scan<'a, D> {
        debug_assert_eq!(self.dim, D);
        let geometry = StencilGeometry::<D> {
            counts: std::array::from_fn(|k| self.counts[k]),
            widths: std::array::from_fn(|k| self.widths[k]),
            lengths: std::array::from_fn(|k| container.lengths[k]),
            periodic: std::array::from_fn(|k| container.periodic[k]),
        };
        let total: usize = geometry.counts.iter().product();
        let half = (0..D).all(|k| !geometry.periodic[k] || geometry.counts[k] >= 3);
        let min_width = self.widths.iter().fold(f64::INFINITY, |m, &w| m.min(w));
        let is_small = |i: u32| half && diameters[i as usize] + skin <= min_width;
        // Cell order with each cell's small particles first; `small_end[c]` ends them.
        let mut order: Vec<u32> = Vec::with_capacity(self.order.len());
        let mut small_end = vec![0u32; total];
        for (cell, end) in small_end.iter_mut().enumerate() {
            let members = &self.order[self.start[cell] as usize..self.start[cell + 1] as usize];
            order.extend(members.iter().filter(|&&i| is_small(i)));
            *end = order.len() as u32;
            order.extend(members.iter().filter(|&&i| !is_small(i)));
        }
        let xs: Vec<[f64; D]> = order
            .iter()
            .map(|&i| std::array::from_fn(|k| positions[i as usize * D + k]))
            .collect();
        let ds: Vec<f64> = order.iter().map(|&i| diameters[i as usize]).collect();
        let interior = InteriorStencil::new(&geometry);
        Scan {
            cells: self,
            geometry,
            total,
            half,
            skin,
            order,
            small_end,
            xs,
            ds,
            interior,
        }
    }
}

/// A scan's particles in cell order with its grid, ready to pair any range of cells: the
/// pairs of all cells are those of the small particles' half stencils, cell by cell, then
/// those of the larger particles, cell by cell ([`Scan::small_pairs`], [`Scan::large_pairs`]).
struct Scan<'a, const D: usize> {
    cells: &'a CellList,
    geometry: StencilGeometry<D>,
    total: usize,
    half: bool,
    skin: f64,
    /// Particle indices in cell order, each cell's small particles first (`small_end[c]` ends
    /// them); their positions and diameters in that order.
    order: Vec<u32>,
    small_end: Vec<u32>,
    xs: Vec<[f64; D]>,
    ds: Vec<f64>,
    interior: InteriorStencil<D>,
}

impl<const D: usize> Scan<'_, D> {
    /// Every pair, the small particles' first, in the order of the cells.
    #[inline(always)]
    fn all_pairs(&self, mut f: impl FnMut(usize, usize)) {
        self.small_pairs(0..self.total, &mut f);
        self.large_pairs(0..self.total, &mut f);
    }

    /// [`Scan::all_pairs`] as `(i, j)` appended to `pairs`, ranges of cells scanned on rayon's
    /// threads and their pairs joined in the order of the ranges: the same list as one thread
    /// makes.
    fn pairs_in_parallel(&self, pairs: &mut Vec<(u32, u32)>) {
        let chunk = self.total.div_ceil(4 * rayon::current_num_threads()).max(1);
        let ranges: Vec<std::ops::Range<usize>> = (0..self.total)
            .step_by(chunk)
            .map(|a| a..(a + chunk).min(self.total))
            .collect();
        let scan = |large: bool| -> Vec<Vec<(u32, u32)>> {
            ranges
                .par_iter()
                .map(|cells| {
                    let mut v = Vec::new();
                    let mut push = |i: usize, j: usize| v.push((i as u32, j as u32));
                    if large {
                        self.large_pairs(cells.clone(), &mut push);
                    } else {
                        self.small_pairs(cells.clone(), &mut push);
                    }
                    v
                })
                .collect()
        };
        let (small, large) = (scan(false), scan(true));
        pairs.reserve(small.iter().chain(&large).map(Vec::len).sum());
        small.into_iter().chain(large).for_each(|v| pairs.extend(v));
    }

    /// The pairs of two small particles whose first lies in `cells`, found through the half
    /// stencils.
    #[inline(always)]
    fn small_pairs(&self, cells: std::ops::Range<usize>, f: &mut impl FnMut(usize, usize)) {
        let (geometry, interior, skin) = (&self.geometry, &self.interior, self.skin);
        let (start, small_end, xs, ds) = (&self.cells.start, &self.small_end, &self.xs, &self.ds);
        let mut emit = |a: usize, b: usize| f(self.order[a] as usize, self.order[b] as usize);
        let one: [isize; D] = [1; D];
        let mut common = Stencil::<D>::default();
        if self.half {
            // The small particles of a cell's forward neighbours, shifted next to it and
            // gathered into one run, so each home particle tests them in one long loop.
            let mut near = Gathered::<D>::default();
            for cell in cells {
                let (a0, a1) = (start[cell] as usize, small_end[cell] as usize);
                if a0 == a1 {
                    continue;
                }
                near.clear();
                let range = |c: usize| start[c] as usize..small_end[c] as usize;
                let mut round = false;
                if interior.fits(&geometry.coords(cell)) {
                    for &o in &interior.forward {
                        near.extend(xs, ds, range((cell as isize + o) as usize), &[0.0; D]);
                    }
                } else {
                    geometry.build(&geometry.coords(cell), &one, f64::INFINITY, &mut common);
                    // With three cells along a periodic axis the stencil covers it whole and
                    // takes the minimum image along it.
                    round = common.round.contains(&true);
                    for ((&c, shift), _) in common
                        .cells
                        .iter()
                        .zip(&common.shifts)
                        .zip(&common.forward)
                        .filter(|e| *e.1)
                    {
                        near.extend(xs, ds, range(c as usize), shift);
                    }
                }
                let min_image = if round { common.round } else { [false; D] };
                for i in a0..a1 {
                    let (xi, reach) = (xs[i], 0.5 * ds[i] + skin);
                    let mut test = |xj: &[f64; D], dj: f64, j: usize| {
                        let cut = reach + 0.5 * dj;
                        let r2 = separation2(&xi, xj, &[0.0; D], &min_image, &geometry.lengths);
                        if r2 < cut * cut {
                            emit(i, j);
                        }
                    };
                    for j in i + 1..a1 {
                        test(&xs[j], ds[j], j);
                    }
                    for ((xj, &dj), &j) in near.x.iter().zip(&near.d).zip(&near.index) {
                        test(xj, dj, j as usize);
                    }
                }
            }
        }
    }

    /// The pairs of each particle in `cells` that is not small with the particles no larger
    /// than it, found through its full stencil.
    #[inline(always)]
    fn large_pairs(&self, cells: std::ops::Range<usize>, f: &mut impl FnMut(usize, usize)) {
        let (geometry, interior, skin) = (&self.geometry, &self.interior, self.skin);
        let (start, small_end, xs, ds) = (&self.cells.start, &self.small_end, &self.xs, &self.ds);
        let widths = &self.cells.widths;
        let mut emit = |a: usize, b: usize| f(self.order[a] as usize, self.order[b] as usize);
        let one: [isize; D] = [1; D];
        let mut common = Stencil::<D>::default();
        let mut own = Stencil::<D>::default();
        for cell in cells {
            let (a0, a1) = (small_end[cell] as usize, start[cell + 1] as usize);
            if a0 == a1 {
                continue;
            }
            let home = geometry.coords(cell);
            let mut common_built = false;
            for a in a0..a1 {
                let da = ds[a];
                // Partners are no larger than a, so they lie within D_a + skin.
                let reach: [isize; D] =
                    std::array::from_fn(|k| ((da + skin) / widths[k]).ceil() as isize);
                let stencil = if reach == one {
                    if !common_built {
                        if interior.fits(&home) {
                            interior.translate(cell, &mut common);
                        } else {
                            geometry.build(&home, &one, f64::INFINITY, &mut common);
                        }
                        common_built = true;
                    }
                    &common
                } else {
                    geometry.build(&home, &reach, da + skin, &mut own);
                    &own
                };
                for (c, shift) in stencil.cells.iter().zip(&stencil.shifts) {
                    for b in start[*c as usize] as usize..start[*c as usize + 1] as usize {
                        let db = ds[b];
                        // Each pair once: the larger particle, or the earlier one among equals.
                        if db > da || (db == da && b <= a) {
                            continue;
                        }
                        let cut = 0.5 * (da + db) + skin;
                        let r2 =
                            separation2(&xs[a], &xs[b], shift, &stencil.round, &geometry.lengths);
                        if r2 < cut * cut {
                            emit(a, b);
                        }
                    }
                }
            }
        }
    }
}

/// Squared length of `xj + shift − xi`, with the minimum image along the `round` axes.
#[inline(always)]
fn separation2<const D: usize>(
    xi: &[f64; D],
    xj: &[f64; D],
    shift: &[f64; D],
    round: &[bool; D],
    lengths: &[f64; D],
) -> f64 {
    let mut r2 = 0.0;
    for k in 0..D {
        let mut dx = xj[k] + shift[k] - xi[k];
        if round[k] {
            dx -= lengths[k] * (dx / lengths[k]).round();
        }
        r2 += dx * dx;
    }
    r2
}

/// Particles gathered from several cells: positions (shifted), diameters and indices.
struct Gathered<const D: usize> {
    x: Vec<[f64; D]>,
    d: Vec<f64>,
    index: Vec<u32>,
}

impl<const D: usize> Default for Gathered<D> {
    fn default() -> Self {
        Gathered {
            x: Vec::new(),
            d: Vec::new(),
            index: Vec::new(),
        }
    }
}

impl<const D: usize> Gathered<D> {
    fn clear(&mut self) {
        self.x.clear();
        self.d.clear();
        self.index.clear();
    }

    /// Appends the particles `range` of `xs`/`ds`, displaced by `shift`.
    fn extend(
        &mut self,
        xs: &[[f64; D]],
        ds: &[f64],
        range: std::ops::Range<usize>,
        shift: &[f64; D],
    ) {
        self.x.extend(
            xs[range.clone()]
                .iter()
                .map(|x| std::array::from_fn(|k| x[k] + shift[k])),
        );
        self.d.extend_from_slice(&ds[range.clone()]);
        self.index.extend(range.map(|j| j as u32));
    }
}

/// The grid as the scan sees it.
struct StencilGeometry<const D: usize> {
    counts: [usize; D],
    widths: [f64; D],
    lengths: [f64; D],
    periodic: [bool; D],
}

/// Neighbour cells of one home cell, each with the periodic shift that brings its particles
/// next to the home cell; axes where the stencil wraps onto itself use the minimum image.
struct Stencil<const D: usize> {
    cells: Vec<u32>,
    shifts: Vec<[f64; D]>,
    /// Whether the cell's offset from home is lexicographically positive (half stencil).
    forward: Vec<bool>,
    round: [bool; D],
    /// Scratch of [`StencilGeometry::build`]: the offsets along each axis.
    axes: [Vec<AxisCell>; D],
}

/// One offset along one axis of a stencil.
struct AxisCell {
    /// Its term of the linear cell index (wrapped coordinate × stride).
    index: usize,
    shift: f64,
    /// Squared gap between the home cell and this one along the axis.
    gap2: f64,
    /// Sign of the offset from home.
    side: i8,
}

impl<const D: usize> Default for Stencil<D> {
    fn default() -> Self {
        Stencil {
            cells: Vec::new(),
            shifts: Vec::new(),
            forward: Vec::new(),
            round: [false; D],
            axes: std::array::from_fn(|_| Vec::new()),
        }
    }
}

/// The reach-one stencil of a cell away from every box face, as offsets of the linear cell
/// index: no wrapping, no shifts, so it is translated rather than rebuilt.
struct InteriorStencil<const D: usize> {
    offsets: Vec<isize>,
    /// The lexicographically later offsets (the half stencil).
    forward: Vec<isize>,
    counts: [usize; D],
}

impl<const D: usize> InteriorStencil<D> {
    fn new(g: &StencilGeometry<D>) -> Self {
        let mut offsets = Vec::with_capacity(3usize.pow(D as u32));
        let mut off = [-1isize; D];
        'all: loop {
            let mut lin = 0isize;
            for k in 0..D {
                lin = lin * g.counts[k] as isize + off[k];
            }
            offsets.push(lin);
            let mut k = D;
            loop {
                if k == 0 {
                    break 'all;
                }
                k -= 1;
                if off[k] < 1 {
                    off[k] += 1;
                    break;
                }
                off[k] = -1;
            }
        }
        InteriorStencil {
            forward: offsets.iter().copied().filter(|&o| o > 0).collect(),
            offsets,
            counts: g.counts,
        }
    }

    /// True when every neighbour of `home` lies inside the grid without wrapping.
    fn fits(&self, home: &[isize; D]) -> bool {
        (0..D).all(|k| self.counts[k] >= 3 && home[k] >= 1 && home[k] + 1 < self.counts[k] as isize)
    }

    fn translate(&self, cell: usize, out: &mut Stencil<D>) {
        out.cells.clear();
        out.cells
            .extend(self.offsets.iter().map(|&o| (cell as isize + o) as u32));
        out.shifts.clear();
        out.shifts.resize(self.offsets.len(), [0.0; D]);
        out.forward.clear();
        out.round = [false; D];
    }
}

impl<const D: usize> StencilGeometry<D> {
    fn coords(&self, mut cell: usize) -> [isize; D] {
        let mut home = [0isize; D];
        for k in (0..D).rev() {
            home[k] = (cell % self.counts[k]) as isize;
            cell /= self.counts[k];
        }
        home
    }

    /// Fills `out` with the cells within `reach[k]` cells of `home` along each axis whose
    /// nearest point can lie within `cut` of a point of the home cell: a large particle's
    /// reach is a ball, and the corners of its cube of cells (half of it in 3D) hold no
    /// partner. Each axis's offsets are tabulated first (cell index term, periodic shift,
    /// squared gap, side of home), so the cells of the cube cost only sums.
    fn build(&self, home: &[isize; D], reach: &[isize; D], cut: f64, out: &mut Stencil<D>) {
        out.cells.clear();
        out.shifts.clear();
        out.forward.clear();
        let mut stride = 1usize;
        for k in (0..D).rev() {
            let m = self.counts[k] as isize;
            out.round[k] = self.periodic[k] && 2 * reach[k] + 1 >= m;
            let (lo, hi) = if out.round[k] {
                (0, m - 1)
            } else if self.periodic[k] {
                (home[k] - reach[k], home[k] + reach[k])
            } else {
                ((home[k] - reach[k]).max(0), (home[k] + reach[k]).min(m - 1))
            };
            let axis = &mut out.axes[k];
            axis.clear();
            for off in lo..=hi {
                let wrapped = off.rem_euclid(m);
                // A cell reached by wrapping holds particles one box length away; along an
                // axis taken whole the minimum image replaces the shift and the gap.
                let shift = ((off - wrapped) / m) as f64 * self.lengths[k];
                let gap = if out.round[k] {
                    0.0
                } else {
                    ((off - home[k]).abs() - 1).max(0) as f64 * self.widths[k]
                };
                axis.push(AxisCell {
                    index: wrapped as usize * stride,
                    shift,
                    gap2: gap * gap,
                    side: (off - home[k]).signum() as i8,
                });
            }
            stride *= self.counts[k];
        }
        let cut2 = cut * cut;
        let mut pick = [0usize; D];
        loop {
            let mut gap2 = 0.0;
            for k in 0..D {
                gap2 += out.axes[k][pick[k]].gap2;
            }
            if gap2 < cut2 {
                let mut c = 0usize;
                let mut shift = [0.0; D];
                let mut side = 0i8;
                for k in 0..D {
                    let e = &out.axes[k][pick[k]];
                    c += e.index;
                    shift[k] = e.shift;
                    if side == 0 {
                        side = e.side;
                    }
                }
                out.cells.push(c as u32);
                out.shifts.push(shift);
                // Lexicographically later than home: the first differing axis is ahead.
                out.forward.push(side > 0);
            }
            let mut k = D;
            loop {
                if k == 0 {
                    return;
                }
                k -= 1;
                if pick[k] + 1 < out.axes[k].len() {
                    pick[k] += 1;
                    break;
                }
                pick[k] = 0;
            }
        }
    }
}

/// Cells per axis and their widths for cells no narrower than `cell_size`, widened until there
/// are at most a few per particle (of `particles`), which bounds memory for sparse or thin
/// systems.
pub(super) fn grid(
    container: &Container,
    cell_size: f64,
    particles: usize,
) -> (Vec<usize>, Vec<f64>) {
    let mut size = cell_size.max(f64::MIN_POSITIVE);
    let cells_for = |s: f64| {
        container
            .lengths
            .iter()
            .map(|&l| (l / s).floor().max(1.0))
            .product::<f64>()
    };
    while cells_for(size) > MAX_CELLS_PER_PARTICLE * particles as f64 + 27.0 {
        size *= 1.25;
    }
    let counts: Vec<usize> = container
        .lengths
        .iter()
        .map(|&l| ((l / size).floor() as usize).max(1))
        .collect();
    let widths = container
        .lengths
        .iter()
        .zip(&counts)
        .map(|(&l, &c)| l / c as f64)
        .collect();
    (counts, widths)
}

/// Cell coordinate along one axis; walled axes clamp particles that poke through a wall.
#[inline]
pub(super) fn axis_cell(x: f64, width: f64, count: usize, periodic: bool) -> usize {
    let c = (x / width).floor();
    if periodic {
        (c as isize).rem_euclid(count as isize) as usize
    } else {
        c.clamp(0.0, (count - 1) as f64) as usize
    }
}

/// The 90th-percentile diameter: cells are sized for it so that rare large particles do not
/// make the cells of a broad distribution huge.
pub fn typical_diameter(diameters: &[f64]) -> f64 {
    let mut sorted: Vec<f64> = diameters.to_vec();
    let k = ((0.9 * (sorted.len() - 1) as f64).round() as usize).min(sorted.len() - 1);
    let (_, v, _) = sorted.select_nth_unstable_by(k, |a, b| a.total_cmp(b));
    *v
}

#[cfg(test)]
mod tests;
