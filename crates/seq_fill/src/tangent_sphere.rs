//! The centre of a new sphere of radius R touching k parents while its other d − k coordinates
//! are held on brick faces: the exact intersection of the spheres ‖x − x_i‖ = R + R_i
//! (Black & Cheviakov 2022 §2.1, eqn in §2.1), both roots.
//!
//! With the fixed coordinates known, each parent leaves a sphere of radius
//! ρ_i² = (R + R_i)² − Σ_fixed (v_a − x_i,a)² in the k free coordinates. Subtracting the first
//! equation from the others leaves k − 1 linear equations 2 u_i·z = ρ_1² − ρ_i² + |u_i|² with
//! u_i = q_i − q_1 and z = y − q_1; their solutions are the line z = z₀ + t n (z₀ in the span of
//! the u_i, n orthogonal to it), and |z|² = ρ_1² gives t = ±√(ρ_1² − |z₀|²).

/// A parent in a common (unwrapped) frame: its centre and radius.
pub(crate) type Parent<const D: usize> = ([f64; D], f64);

/// Relative size below which parents are taken as degenerate (collinear triples, coincident
/// pairs): no unique pair of roots exists.
const DEGENERATE: f64 = 1e-9;

/// The two centres (the roots `z₀ ± t n`) of a sphere of radius `radius` touching every parent,
/// with coordinates `fixed` = (axis, value) held and the coordinates `free` solved for
/// (`parents.len() == free.len()`). `None` when the parents are degenerate or too far apart
/// for a sphere of this radius to touch them all.
pub(crate) fn tangent_centres<const D: usize>(
    fixed: &[(usize, f64)],
    free: &[usize],
    parents: &[Parent<D>],
    radius: f64,
) -> Option<[[f64; D]; 2]> {
    let k = free.len();
    debug_assert_eq!(parents.len(), k);
    debug_assert!(k >= 1);
    // ρ_i²: the parent's sphere restricted to the free coordinates.
    let mut rho2 = [0.0; D];
    for (i, (c, r)) in parents.iter().enumerate() {
        let s = radius + r;
        rho2[i] = s * s
            - fixed
                .iter()
                .map(|&(a, v)| (v - c[a]) * (v - c[a]))
                .sum::<f64>();
        if rho2[i] < 0.0 {
            return None;
        }
    }
    let q0 = parents[0].0;
    // Orthonormal basis e_j of span(u_i) by Gram–Schmidt; l[i][j] = u_i·e_j (lower triangular).
    let mut e = [[0.0; D]; D];
    let mut z0 = [0.0; D];
    for i in 1..k {
        let mut u = [0.0; D];
        for (m, &a) in free.iter().enumerate() {
            u[m] = parents[i].0[a] - q0[a];
        }
        let uu: f64 = u[..k].iter().map(|v| v * v).sum();
        let b = 0.5 * (rho2[0] - rho2[i] + uu);
        let mut w = u;
        let mut lhs = 0.0;
        for ej in &e[..i - 1] {
            let proj: f64 = (0..k).map(|m| u[m] * ej[m]).sum();
            lhs += proj * (0..k).map(|m| ej[m] * z0[m]).sum::<f64>();
            for m in 0..k {
                w[m] -= proj * ej[m];
            }
        }
        let wn = w[..k].iter().map(|v| v * v).sum::<f64>().sqrt();
        if wn <= DEGENERATE * uu.sqrt().max(f64::MIN_POSITIVE) || wn == 0.0 {
            return None;
        }
        for m in 0..k {
            e[i - 1][m] = w[m] / wn;
        }
        // Forward substitution: u_i·z₀ = b with z₀ = Σ c_j e_j, c_i = (b − Σ_{j<i} l_ij c_j)/l_ii.
        let c = (b - lhs) / wn;
        for m in 0..k {
            z0[m] += c * e[i - 1][m];
        }
    }
    // n: the unit vector orthogonal to every e_j, from the standard basis vector that keeps the
    // most of itself after projection.
    let mut n = [0.0; D];
    let mut best = -1.0;
    for axis in 0..k {
        let mut w = [0.0; D];
        w[axis] = 1.0;
        for ej in &e[..k - 1] {
            let proj = ej[axis];
            for m in 0..k {
                w[m] -= proj * ej[m];
            }
        }
        let wn = w[..k].iter().map(|v| v * v).sum::<f64>().sqrt();
        if wn > best {
            best = wn;
            for m in 0..k {
                n[m] = w[m] / wn;
            }
        }
    }
    let zz: f64 = z0[..k].iter().map(|v| v * v).sum();
    let t2 = rho2[0] - zz;
    if t2 < -1e-12 * rho2[0] {
        return None;
    }
    let t = t2.max(0.0).sqrt();
    let mut roots = [[0.0; D]; 2];
    for (root, sign) in roots.iter_mut().zip([1.0, -1.0]) {
        for &(a, v) in fixed {
            root[a] = v;
        }
        for (m, &a) in free.iter().enumerate() {
            root[a] = q0[a] + z0[m] + sign * t * n[m];
        }
    }
    Some(roots)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dist<const D: usize>(a: &[f64; D], b: &[f64; D]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f64>()
            .sqrt()
    }

    #[test]
    fn both_roots_touch_three_parents_in_3d() {
        let parents = [
            ([0.0, 0.0, 0.0], 1.0),
            ([2.1, 0.0, 0.0], 1.0),
            ([1.0, 1.9, 0.3], 0.8),
        ];
        let r = 0.7;
        let roots = tangent_centres::<3>(&[], &[0, 1, 2], &parents, r).unwrap();
        for x in roots {
            for (c, rp) in &parents {
                assert!((dist(&x, c) - (r + rp)).abs() < 1e-12, "{x:?}");
            }
        }
        assert!(dist(&roots[0], &roots[1]) > 0.1);
    }

    #[test]
    fn fixed_coordinates_are_held_and_parents_touched() {
        // A face z = R of a brick: the new sphere touches the wall and two parents.
        let r = 0.5;
        let parents = [([1.0, 1.0, 1.0], 1.0), ([3.0, 1.2, 0.6], 0.6)];
        let roots = tangent_centres::<3>(&[(2, r)], &[0, 1], &parents, r).unwrap();
        for x in roots {
            assert_eq!(x[2], r);
            for (c, rp) in &parents {
                assert!((dist(&x, c) - (r + rp)).abs() < 1e-12);
            }
        }
        // An edge: one parent, two fixed coordinates.
        let roots =
            tangent_centres::<3>(&[(1, r), (2, r)], &[0], &[([1.0, r, r], 1.0)], r).unwrap();
        assert_eq!(roots[0], [2.5, r, r]);
        assert_eq!(roots[1], [-0.5, r, r]);
    }

    #[test]
    fn out_of_reach_and_degenerate_parents_give_none() {
        let far = [([0.0, 0.0], 1.0), ([10.0, 0.0], 1.0)];
        assert!(tangent_centres::<2>(&[], &[0, 1], &far, 1.0).is_none());
        let same = [([0.0, 0.0], 1.0), ([0.0, 0.0], 1.0)];
        assert!(tangent_centres::<2>(&[], &[0, 1], &same, 1.0).is_none());
        let collinear = [
            ([0.0, 0.0, 0.0], 1.0),
            ([2.0, 0.0, 0.0], 1.0),
            ([4.0, 0.0, 0.0], 1.0),
        ];
        assert!(tangent_centres::<3>(&[], &[0, 1, 2], &collinear, 1.0).is_none());
    }

    #[test]
    fn eight_dimensional_roots_touch_all_parents() {
        let mut parents = Vec::new();
        for i in 0..8 {
            let mut c = [0.0; 8];
            c[i] = 2.0;
            c[(i + 1) % 8] = 0.3 * i as f64;
            parents.push((c, 1.0 + 0.05 * i as f64));
        }
        let free: Vec<usize> = (0..8).collect();
        let roots = tangent_centres::<8>(&[], &free, &parents, 1.5).unwrap();
        for x in roots {
            for (c, rp) in &parents {
                assert!((dist(&x, c) - (1.5 + rp)).abs() < 1e-10);
            }
        }
    }
}
