//! Fill-reducing orderings of the sparse symmetric matrices packbench factorises: calippso's
//! interior point (its normal equations), closest-jammed's minimum-norm solves (A Aᵀ over
//! bonds) and the force balance's projection (G Gᵀ over contacts).

use std::sync::Mutex;

use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::SymmetricOrdering;

/// The ordering a symbolic Cholesky factorisation uses.
pub enum FillOrdering {
    /// faer's approximate minimum degree.
    Amd,
    /// METIS's nested dissection: the permutation and its inverse.
    NestedDissection { fwd: Vec<usize>, inv: Vec<usize> },
}

impl FillOrdering {
    /// As faer takes it, for a matrix of order `n`.
    pub fn as_faer(&self, n: usize) -> SymmetricOrdering<'_, usize> {
        match self {
            FillOrdering::Amd => SymmetricOrdering::Amd,
            FillOrdering::NestedDissection { fwd, inv } => {
                SymmetricOrdering::Custom(PermRef::new_checked(fwd, inv, n))
            }
        }
    }
}

/// METIS's nested-dissection ordering of the pattern (lower triangle, column-compressed), with
/// the columns coupled to more than half of the others (Γ's) ordered last; AMD for small
/// patterns or if METIS fails. On the 3D contact graphs of the CALiPPSO LPs it halves
/// the fill of AMD's ordering (nnz(L) 25.7M against 53.0M at N = 10⁴) and the factorisation
/// takes a third of the time; on closest-jammed's A Aᵀ the gain grows with the bonds (a
/// quarter of the time per step at 16 000–20 000 bonds, N = 10⁴).
pub fn nested_dissection(n: usize, col_ptr: &[usize], row_idx: &[usize]) -> FillOrdering {
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); n];
    for c in 0..n {
        for &r in &row_idx[col_ptr[c]..col_ptr[c + 1]] {
            if r != c {
                adj[c].push(r);
                adj[r].push(c);
            }
        }
    }
    let dense: Vec<bool> = adj.iter().map(|a| a.len() > n / 2).collect();
    let sparse: Vec<usize> = (0..n).filter(|&v| !dense[v]).collect();
    // METIS takes i32 indices; its adjacency lists every off-diagonal entry twice.
    if sparse.len() < ND_MIN_COLUMNS || i32::try_from(2 * row_idx.len()).is_err() {
        return FillOrdering::Amd;
    }
    let mut local = vec![0i32; n];
    for (k, &v) in sparse.iter().enumerate() {
        local[v] = k as i32;
    }
    let mut xadj = vec![0i32];
    let mut adjncy = Vec::new();
    for &v in &sparse {
        adjncy.extend(adj[v].iter().filter(|&&u| !dense[u]).map(|&u| local[u]));
        xadj.push(adjncy.len() as i32);
    }
    let mut nv = sparse.len() as i32;
    let mut perm = vec![0i32; sparse.len()];
    let mut iperm = vec![0i32; sparse.len()];
    // METIS draws from one random generator for the whole process (GKlib's Mersenne twister in
    // static storage, reseeded with 4321 at the start of every call): two calls on two threads
    // (parallel runs of `compare`, parallel tests) interleave its draws, and each may get
    // another ordering, hence other rounding in every factor and another path. That made a
    // 6D closest-jammed run return a packing with an overlap of 0.76 in one run out of seven.
    // One call at a time makes the ordering a function of the pattern alone.
    let _only_caller = METIS_CALL
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    // SAFETY: METIS_NodeND reads nv + 1 entries of xadj and xadj[nv] of adjncy, writes nv
    // entries of perm and iperm (all allocated here); null weights and options are allowed.
    // The lock above keeps its process-global state to one caller.
    let status = unsafe {
        metis_sys::METIS_NodeND(
            &mut nv,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return FillOrdering::Amd;
    }
    let mut fwd: Vec<usize> = perm.iter().map(|&p| sparse[p as usize]).collect();
    fwd.extend((0..n).filter(|&v| dense[v]));
    let mut inv = vec![0usize; n];
    for (k, &v) in fwd.iter().enumerate() {
        inv[v] = k;
    }
    FillOrdering::NestedDissection { fwd, inv }
}

/// Held for the duration of each METIS call (see [`nested_dissection`]).
static METIS_CALL: Mutex<()> = Mutex::new(());

/// Patterns with fewer free columns are ordered by AMD (METIS's separators do not pay).
const ND_MIN_COLUMNS: usize = 200;

#[cfg(test)]
mod tests {
    use super::*;

    /// The lower triangle of a 12 × 12 × 12 grid graph's Laplacian pattern (1728 columns).
    fn grid_pattern() -> (usize, Vec<usize>, Vec<usize>) {
        let m = 12;
        let n = m * m * m;
        let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
        for c in 0..n {
            row_idx.push(c);
            let (x, y, z) = (c % m, (c / m) % m, c / (m * m));
            for (ok, r) in [
                (x + 1 < m, c + 1),
                (y + 1 < m, c + m),
                (z + 1 < m, c + m * m),
            ] {
                if ok {
                    row_idx.push(r);
                }
            }
            col_ptr.push(row_idx.len());
        }
        (n, col_ptr, row_idx)
    }

    fn permutation(o: FillOrdering) -> Vec<usize> {
        match o {
            FillOrdering::NestedDissection { fwd, .. } => fwd,
            FillOrdering::Amd => panic!("a grid of 1728 columns is ordered by METIS"),
        }
    }

    /// Orderings made on two threads at once equal the one made alone: METIS's process-wide
    /// random generator is never shared between two calls.
    #[test]
    fn concurrent_orderings_equal_the_ordering_made_alone() {
        let (n, col_ptr, row_idx) = grid_pattern();
        let alone = permutation(nested_dissection(n, &col_ptr, &row_idx));
        let mut sorted = alone.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        std::thread::scope(|s| {
            let workers: Vec<_> = (0..2)
                .map(|_| {
                    s.spawn(|| {
                        (0..20)
                            .map(|_| permutation(nested_dissection(n, &col_ptr, &row_idx)))
                            .collect::<Vec<_>>()
                    })
                })
                .collect();
            for w in workers {
                for p in w.join().unwrap() {
                    assert_eq!(p, alone);
                }
            }
        });
    }
}
