//! The strata of a unit brick filled in turn (Black & Cheviakov 2022 §2.1, §3): corners, then edges, faces
//! and the volume. A stratum holds some coordinates on brick faces and leaves k free; a new
//! sphere in it touches k parents that belong to the same stratum, mutually within δ·r̄
//! ("parents", §2.3): one parent on an edge, two on a face, three in the volume of a 3D brick
//! (two in the area of a 2D one).

use crate::bed::{Bed, OBSTACLE_BASE};
use crate::params::Variant;

/// Parent tuples generated per new sphere at most (bounds the clique search in high d).
const MAX_TUPLES_PER_SPHERE: usize = 256;

/// Tolerance, relative to r̄, of "this sphere touches that face" for stratum membership: the
/// fill sets held coordinates exactly, so only rounding separates members from the face.
const MEMBER_TOL: f64 = 1e-9;

/// When the fill of a stratum stops besides "nothing fits".
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Goal {
    /// Edges (and in d ≥ 4 the other faces of dimension below d − 1): fill until full.
    Full,
    /// A face: FaceGoal of the wall with this core wall id.
    Face(usize),
    /// The volume: BodyGoal.
    Body,
}

/// One edge, face or the volume of the unit brick.
#[derive(Clone, Debug)]
pub(crate) struct Stratum {
    /// Held coordinates: (axis, on the high face).
    pub fixed: Vec<(usize, bool)>,
    /// Free coordinates, solved for from the parents.
    pub free: Vec<usize>,
    pub goal: Goal,
}

impl Stratum {
    /// Every stratum of dimension ≥ 1 of a d-dimensional brick, lowest dimension first
    /// (edges, then faces, then the volume). Method 1 fills every face of each kind;
    /// Method 2 fills only those at the low end of each held axis (the others are copies).
    pub(crate) fn all(d: usize, variant: Variant) -> Vec<Stratum> {
        let mut out = Vec::new();
        for k in 1..=d {
            for mask in 0u32..(1 << d) {
                if mask.count_ones() as usize != k {
                    continue;
                }
                let free: Vec<usize> = (0..d).filter(|a| mask & (1 << a) != 0).collect();
                let held: Vec<usize> = (0..d).filter(|a| mask & (1 << a) == 0).collect();
                let sides = match variant {
                    Variant::Method1 => 1u32 << held.len(),
                    Variant::Method2 => 1,
                };
                for side in 0..sides {
                    let fixed: Vec<(usize, bool)> = held
                        .iter()
                        .enumerate()
                        .map(|(m, &a)| (a, side & (1 << m) != 0))
                        .collect();
                    let goal = if k == d {
                        Goal::Body
                    } else if k == d - 1 {
                        Goal::Face(2 * fixed[0].0 + fixed[0].1 as usize)
                    } else {
                        Goal::Full
                    };
                    out.push(Stratum {
                        fixed,
                        free: free.clone(),
                        goal,
                    });
                }
            }
        }
        out
    }

    /// Number of parents of a new sphere in this stratum.
    pub(crate) fn parents(&self) -> usize {
        self.free.len()
    }

    /// The held coordinates of a sphere of radius `r`: Method 1 spheres lie inside and touch the
    /// face (x_a = r or L_a − r), Method 2 centres lie on it (x_a = 0).
    pub(crate) fn held_values<const D: usize>(
        &self,
        variant: Variant,
        lengths: &[f64; D],
        r: f64,
    ) -> ([(usize, f64); D], usize) {
        let mut out = [(0, 0.0); D];
        for (m, &(a, hi)) in self.fixed.iter().enumerate() {
            out[m] = match (variant, hi) {
                (Variant::Method1, false) => (a, r),
                (Variant::Method1, true) => (a, lengths[a] - r),
                (Variant::Method2, _) => (a, 0.0),
            };
        }
        (out, self.fixed.len())
    }

    /// Whether sphere or obstacle `id` lies on every held face of this stratum. An obstacle
    /// (a hemisphere centred on an x face) belongs to the volume and to its own x face.
    pub(crate) fn contains<const D: usize>(
        &self,
        bed: &Bed<D>,
        variant: Variant,
        id: u32,
        mean_radius: f64,
    ) -> bool {
        if id >= OBSTACLE_BASE {
            let o = &bed.obstacles[(id - OBSTACLE_BASE) as usize];
            let side_hi = o.wall % 2 == 1;
            return self.fixed.is_empty() || self.fixed == [(0, side_hi)];
        }
        let tol = MEMBER_TOL * mean_radius;
        self.fixed.iter().all(|&(a, hi)| match variant {
            Variant::Method1 => bed.wall_gap(id as usize, a, hi).abs() <= tol,
            Variant::Method2 => bed.centres[id as usize][a] == 0.0,
        })
    }

    /// Appends to `out` every tuple of `parents()` mutually near members that contains sphere
    /// `s` and otherwise only obstacles or spheres placed before `s`, so that each tuple is
    /// produced once, by its last-placed sphere.
    pub(crate) fn tuples_closing_at<const D: usize>(
        &self,
        bed: &Bed<D>,
        variant: Variant,
        s: u32,
        mean_radius: f64,
        out: &mut Vec<[u32; D]>,
    ) {
        let k = self.parents();
        let candidates: Vec<u32> = bed
            .near_of(s)
            .iter()
            .copied()
            .filter(|&j| {
                (j >= OBSTACLE_BASE || j < s) && self.contains(bed, variant, j, mean_radius)
            })
            .collect();
        let mut tuple = [0u32; D];
        tuple[0] = s;
        let mut budget = MAX_TUPLES_PER_SPHERE;
        extend_clique(bed, &candidates, 0, &mut tuple, 1, k, &mut budget, out);
    }
}

/// Depth-first search for cliques of the near graph: extends `tuple[..len]` with candidates
/// from index `from` on, each near every member already chosen.
#[allow(clippy::too_many_arguments)]
fn extend_clique<const D: usize>(
    bed: &Bed<D>,
    candidates: &[u32],
    from: usize,
    tuple: &mut [u32; D],
    len: usize,
    k: usize,
    budget: &mut usize,
    out: &mut Vec<[u32; D]>,
) {
    if len == k {
        if *budget > 0 {
            *budget -= 1;
            out.push(*tuple);
        }
        return;
    }
    for (m, &c) in candidates.iter().enumerate().skip(from) {
        if *budget == 0 {
            return;
        }
        // tuple[0] is the new sphere, near every candidate by construction.
        if tuple[1..len].iter().all(|&t| bed.are_near(t, c)) {
            tuple[len] = c;
            extend_clique(bed, candidates, m + 1, tuple, len + 1, k, budget, out);
        }
    }
}
