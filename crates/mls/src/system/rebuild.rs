//! The cell-grid rebuild: cells sized for the largest diameter plus twice the neighbour-list
//! skin (the skin chosen from the packing fraction and the last pressure), particles renumbered
//! in cell order, every neighbour list renewed and every event predicted afresh, and the times
//! at which the grid or the box stops holding the growing spheres.

use super::{CELL_MARGIN, System};

/// Neighbour-list skin, as a fraction of the largest diameter: bounding spheres reach this
/// much beyond each sphere's surface. Smaller gives shorter lists, larger fewer renewals; the
/// best trade depends on how far spheres travel between collisions, so the skin goes from
/// `SKIN_FLUID` at φ ≤ 0.5 down to `SKIN_DENSE` at φ ≥ 0.6 (measured at N = 10⁴ in 3D: 0.2
/// beats 0.1 by ~20 % at φ = 0.55, 0.1 beats 0.2 by ~15 % at φ ≈ 0.63), and below that with
/// the reduced pressure `p` of the last window: spheres rattle in cages about `d·σ/p` wide
/// (free-volume theory, `p ≈ d/δ` for relative gaps `δ`), so a skin of `SKIN_GAPS` cage widths
/// keeps renewals rare while the lists shrink to the first shell (~10 partners at skin 0.1,
/// ~7 at 0.02 in a 3D packing near jamming), down to `SKIN_JAMMED`.
const SKIN_FLUID: f64 = 0.2;
const SKIN_DENSE: f64 = 0.1;
const SKIN_GAPS: f64 = 3.0;
const SKIN_JAMMED: f64 = 0.005;

impl<const D: usize, const P: bool> System<D, P> {
    /// Rebuilds the grid for the current largest diameter, renews every neighbour list and
    /// re-predicts every event. Particles are renumbered in cell order first, so that
    /// neighbours lie close in memory (the calendar is rebuilt, so no event refers to an old
    /// number). Positions must be wrapped into the box (`move_origin`).
    pub(super) fn rebuild(&mut self) {
        let d_max = self.ratio_max * self.scale0;
        // Cells at least (d_max + 2·skin)(1 + margin) wide; a skin that widens to fill cells the
        // floor keeps wider (dilute systems), so renewals stay rare there.
        let cell = (d_max
            * (1.0 + 2.0 * skin_fraction(self.phi(), self.pressure, D))
            * (1.0 + CELL_MARGIN))
            .max(self.cell_floor);
        self.skin = 0.5 * (cell / (1.0 + CELL_MARGIN) - d_max);
        let range = d_max + 2.0 * self.skin;
        // Every buffer here is reused from the last rebuild (see `CellGrid::rebuild`).
        let parts = &self.p;
        self.grid
            .rebuild(&self.len, &self.periodic, cell, range, parts.len(), |i| {
                parts[i].x
            });
        self.order.clear();
        self.order.extend(0..self.p.len());
        let grid = &self.grid;
        self.order.sort_by_key(|&i| grid.cell_of(i));
        self.p_spare.clear();
        self.p_spare.extend(self.order.iter().map(|&i| self.p[i]));
        std::mem::swap(&mut self.p, &mut self.p_spare);
        self.id_spare.clear();
        self.id_spare.extend(self.order.iter().map(|&i| self.id[i]));
        std::mem::swap(&mut self.id, &mut self.id_spare);
        self.version.fill(0);
        let parts = &self.p;
        self.grid
            .rebuild(&self.len, &self.periodic, cell, range, parts.len(), |i| {
                parts[i].x
            });
        let short = |k: usize| (P || self.periodic[k]) && self.grid.dims[k] < 4;
        let single = (0..D).any(|k| short(k) && self.grid.dims[k] < 2);
        self.small = std::array::from_fn(|k| single && short(k));
        self.anchored = !single && (0..D).any(short);
        // Anchored imaging needs every bounding-sphere pair narrower than half of each short
        // axis (its cell width when it has two cells): rebuild before the spheres grow past it.
        let grid_limit = (0..D)
            .filter(|&k| self.anchored && short(k))
            .map(|k| self.grid.width[k])
            .fold(self.grid.diameter_limit(), f64::min);
        self.rebuilds += 1;
        let scale = self.scale(self.now);
        for i in 0..self.n() {
            self.centre[i] = self.p[i].x;
            self.bound[i] = 0.5 * self.p[i].ratio * scale + self.skin;
        }
        self.lists.begin(self.n());
        let mut list = std::mem::take(&mut self.spare);
        for i in 0..self.n() {
            list.clear();
            self.grid.for_each_near(&self.grid.coord[i], |j| {
                if j != i && self.listed(i, j) {
                    list.push(j as u32);
                }
            });
            self.lists.push_new(list.iter().copied());
        }
        self.spare = list;
        self.calendar.reset(self.n());
        for i in 0..self.n() {
            self.predict_renewal(i);
            self.predict_collisions(i);
        }
        self.calendar.build();
        let reach = |d: f64| {
            if self.growth > 0.0 && self.ratio_max > 0.0 {
                ((d / self.ratio_max - self.scale0) / self.growth).max(0.0)
            } else {
                f64::INFINITY
            }
        };
        self.t_grid = reach(grid_limit - 2.0 * self.skin);
        let min_periodic = (0..D)
            .filter(|&k| P || self.periodic[k])
            .map(|k| self.len[k])
            .fold(f64::INFINITY, f64::min);
        self.t_box = reach(0.5 * min_periodic);
    }
}

/// Neighbour-list skin as a fraction of the largest diameter at packing fraction `phi` and
/// reduced pressure `pressure` in dimension `d` (NaN before the first window).
fn skin_fraction(phi: f64, pressure: f64, d: usize) -> f64 {
    let s = ((phi - 0.5) / 0.1).clamp(0.0, 1.0);
    let by_phi = SKIN_FLUID + (SKIN_DENSE - SKIN_FLUID) * s;
    let by_cage = SKIN_GAPS * d as f64 / pressure;
    if by_cage.is_nan() {
        by_phi
    } else {
        by_phi.min(by_cage.max(SKIN_JAMMED))
    }
}
