use super::dense_pseudoinverse::gram_pseudoinverse;
use super::*;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use packbench_core::MAX_DIM;

/// The fallback agrees with the SVD's pseudoinverse on a rank-deficient bond-like matrix
/// (the third row is the sum of the first two).
#[test]
fn gram_pseudoinverse_matches_the_svd() {
    let rows = [
        [1.0, -0.5, 0.0, 2.0, 0.3],
        [0.0, 1.5, -1.0, 0.5, 0.0],
        [1.0, 1.0, -1.0, 2.5, 0.3],
    ];
    let a = Mat::<f64>::from_fn(3, 5, |r, c| rows[r][c]);
    let by_svd = a.thin_svd().unwrap().pseudoinverse();
    let by_gram = gram_pseudoinverse(a.as_ref()).unwrap();
    let err = (&by_svd - &by_gram).norm_max();
    assert!(err < 1e-10, "{err}");
}

/// A bond network of `m³` particles on a periodic cubic grid with pseudo-random normals:
/// bonds to the +x and +y neighbours, and to the +z one for every third particle (about 2.3
/// per particle, fewer than the 3 coordinates, so the rows are independent), plus unbonded
/// slots to the other +z neighbours. Its Gram matrix fills in like a 3D packing's.
fn network(m: usize) -> (Vec<Key>, Vec<Link>, Vec<Key>) {
    let n = m * m * m;
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut uniform = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let key = |i: usize, j: usize| Key::Pair {
        i: i as u32,
        j: j as u32,
        shift: [0; MAX_DIM],
    };
    let neighbour = |i: usize, axis: usize| {
        let stride = m.pow(axis as u32);
        let c = (i / stride) % m;
        i - c * stride + ((c + 1) % m) * stride
    };
    let (mut keys, mut links, mut spare) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..n {
        for axis in 0..3 {
            let j = neighbour(i, axis);
            if axis == 2 && i % 3 != 0 {
                spare.push(key(i, j));
                continue;
            }
            let v = [uniform(), uniform(), uniform()];
            let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            let mut normal = [0.0; MAX_DIM];
            (0..3).for_each(|q| normal[q] = v[q] / norm);
            keys.push(key(i, j));
            links.push(Link {
                i,
                j: Some(j),
                normal,
                dist: 1.0,
                size: 1.0,
            });
        }
    }
    (keys, links, spare)
}

/// The batched path-restricted forward solves and the selected inversion give the diagonal
/// of `(A Aᵀ)⁻¹` of full solves, and with caps the solves stop at partial sums between the
/// cap and the exact value.
#[test]
fn inverse_diagonals_match_full_solves() {
    let m = 9;
    let n = m * m * m;
    let (keys, links, spare) = network(m);
    let all: Vec<Key> = keys.iter().chain(&spare).copied().collect();
    let pattern = Rc::new(GramPattern::new(&all, n).unwrap());
    assert!(
        matches!(pattern.symbolic().raw(), SymbolicCholeskyRaw::Supernodal(_)),
        "the test should exercise the supernodal path"
    );
    let mn = pattern.factor(&keys, &links, 3).unwrap().unwrap();
    // More bonds than one batch, so that batches and their work matrices are reused.
    let ks: Vec<usize> = (0..keys.len()).step_by(7).collect();
    assert!(ks.len() > DIAGONAL_BATCH);
    let exact: Vec<f64> = ks
        .iter()
        .map(|&k| {
            let mut e = vec![0.0; keys.len()];
            e[k] = 1.0;
            mn.gram_solve(&e)[k]
        })
        .collect();
    let uncapped = vec![f64::INFINITY; ks.len()];
    let fast = mn.inverse_diagonals(&ks, &uncapped).unwrap();
    let halves: Vec<f64> = exact.iter().map(|e| 0.5 * e).collect();
    let capped = mn.inverse_diagonals(&ks, &halves).unwrap();
    // The first supernode alone is a lower bound.
    let first = mn
        .inverse_diagonals(&ks, &vec![f64::NEG_INFINITY; ks.len()])
        .unwrap();
    assert!(pattern.work.borrow().iter().all(|&v| v == 0.0));
    let MinNorm::Slotted { values, slots, .. } = &mn else {
        panic!("a slotted factor")
    };
    let ks_slots: Vec<usize> = ks.iter().map(|&k| slots[k]).collect();
    let selected = pattern
        .selected_inverse_diagonal(values, &ks_slots)
        .unwrap();
    for (j, &e) in exact.iter().enumerate() {
        let by_selection = selected[j];
        assert!(
            (by_selection - e).abs() <= 1e-10 * e,
            "{}: {by_selection} vs {e}",
            ks[j]
        );
        assert!(
            (fast[j] - e).abs() <= 1e-10 * e,
            "{}: {} vs {e}",
            ks[j],
            fast[j]
        );
        assert!(
            capped[j] > 0.5 * e && capped[j] <= e * (1.0 + 1e-12),
            "{}",
            ks[j]
        );
        assert!(first[j] > 0.0 && first[j] <= e * (1.0 + 1e-12), "{}", ks[j]);
    }
    assert!(
        first.iter().zip(&exact).any(|(f, e)| f < &(0.99 * e)),
        "the bound should stop early somewhere"
    );
}

/// A factor of all but the last bonds, bordered with those bonds one at a time and with two
/// base bonds and one added bond released, solves the changed Gram system at once:
/// bordering is exact while the particles stay put, so conjugate gradients converge in one
/// iteration to the exact factor's solution.
#[test]
fn a_bordered_factor_solves_the_changed_basis() {
    let m = 6;
    let n = m * m * m;
    let (keys, links, spare) = network(m);
    let all: Vec<Key> = keys.iter().chain(&spare).copied().collect();
    let pattern = Rc::new(GramPattern::new(&all, n).unwrap());
    let k0 = keys.len() - 5;
    let base = Rc::new(
        pattern
            .factor(&keys[..k0], &links[..k0], 3)
            .unwrap()
            .unwrap(),
    );
    let mut pre = Preconditioner::new(&base).unwrap();
    let (mut basis, mut rows) = (keys[..k0].to_vec(), links[..k0].to_vec());
    for k in k0..keys.len() {
        basis.push(keys[k]);
        rows.push(links[k]);
        pre = pre.extend(&basis, &rows, n, 3).unwrap();
    }
    for gone in [0, 7, k0 + 1] {
        pre = pre.release(&keys[gone]).unwrap();
        let at = basis.iter().position(|k| *k == keys[gone]).unwrap();
        basis.remove(at);
        rows.remove(at);
    }
    let stats = Rc::new(CgStats::default());
    let pre = Rc::new(pre);
    let bordered = MinNorm::iterative(&pre, &basis, &rows, n, 3, &stats).unwrap();
    let exact = GramPattern::new(&basis, n)
        .map(Rc::new)
        .unwrap()
        .factor(&basis, &rows, 3)
        .unwrap()
        .unwrap();
    let rhs: Vec<f64> = (0..basis.len()).map(|k| 1.0 + (k % 7) as f64).collect();
    let (x, y) = (bordered.gram_solve(&rhs), exact.gram_solve(&rhs));
    let err = x
        .iter()
        .zip(&y)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(err <= 1e-10 * scale, "{err} vs {scale}");
    assert!(
        stats.failures.get() == 0 && stats.worst.get() <= 1,
        "{}",
        stats.worst.get()
    );
    // A basis missing a bond the preconditioner holds gets no iterative form.
    assert!(MinNorm::iterative(&pre, &basis[1..], &rows[1..], n, 3, &stats).is_none());
}

/// A square with both diagonals braced (4 particles in a plane, 6 bonds, 5 independent)
/// is a fold in miniature: `A Aᵀ` is singular and its null vector is the self-stress,
/// sides `+1` and diagonals `−√2`. The fold multipliers are that self-stress, balanced
/// (`Aᵀλ = 0`), with the sign of `G⁻¹b` approached from outside the fold (`λᵀb > 0`).
#[test]
fn fold_multipliers_are_the_self_stress_of_a_singular_basis() {
    let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let pairs = [(0, 1), (1, 2), (3, 2), (0, 3), (0, 2), (1, 3)];
    let (mut keys, mut links) = (Vec::new(), Vec::new());
    for &(i, j) in &pairs {
        let (a, b): ([f64; 2], [f64; 2]) = (corners[i], corners[j]);
        let dist = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let mut normal = [0.0; MAX_DIM];
        normal[0] = (b[0] - a[0]) / dist;
        normal[1] = (b[1] - a[1]) / dist;
        keys.push(Key::Pair {
            i: i as u32,
            j: j as u32,
            shift: [0; MAX_DIM],
        });
        links.push(Link {
            i,
            j: Some(j),
            normal,
            dist,
            size: 1.0,
        });
    }
    let lambda = Solver::new(0)
        .fold_multipliers(&keys, &links, 4, 3)
        .unwrap();
    let mut net = vec![0.0; 12];
    for (l, &f) in links.iter().zip(&lambda) {
        l.add_transposed(f, &mut net, 3);
    }
    let scale = lambda.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let unbalanced = net.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(unbalanced <= 1e-6 * scale, "{unbalanced} vs {scale}");
    for k in 0..6 {
        let expected = if k < 4 { 1.0 } else { -2f64.sqrt() };
        assert!(
            (lambda[k] / lambda[0] - expected).abs() < 1e-6,
            "{lambda:?}"
        );
    }
    assert!(lambda[0] > 0.0, "{lambda:?}");
}
