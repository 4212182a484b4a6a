//! Iterative rattler removal: a particle with fewer than d+1 contacts cannot be held in place;
//! removing it can leave neighbours with too few contacts, so repeat until none is left.

use super::ContactNetwork;

/// Flags every rattler of `net` (N particles, dimension `d`). Wall contacts count.
pub fn rattlers(net: &ContactNetwork, n: usize, d: usize) -> Vec<bool> {
    let mut count = vec![0usize; n];
    let mut partners: Vec<Vec<usize>> = vec![Vec::new(); n];
    for c in &net.contacts {
        count[c.i] += 1;
        if let Some(j) = c.j {
            count[j] += 1;
            partners[c.i].push(j);
            partners[j].push(c.i);
        }
    }
    let mut rattler = vec![false; n];
    let mut stack: Vec<usize> = (0..n).filter(|&i| count[i] < d + 1).collect();
    while let Some(i) = stack.pop() {
        if rattler[i] {
            continue;
        }
        rattler[i] = true;
        for &j in &partners[i] {
            if !rattler[j] {
                count[j] -= 1;
                if count[j] < d + 1 {
                    stack.push(j);
                }
            }
        }
    }
    rattler
}
