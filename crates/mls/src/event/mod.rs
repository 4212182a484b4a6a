//! Events and the event calendar.
//!
//! Every particle owns exactly two predicted events: its next collision (with a particle or a
//! flat wall) and its next neighbour-list renewal (when it may leave its bounding sphere, see
//! [`neighbour_exit`]). The calendar is a complete binary tournament tree
//! over particles, keyed by the earlier of the two, so it always holds N entries, never a stale
//! copy of a particle's own event, and an update costs one walk of log₂ N levels (Rapaport's
//! and Donev–Torquato–Stillinger's event-driven schemes). A collision slot remembers the
//! partner's trajectory version at prediction time; a partner whose version has changed since
//! makes the event stale, and the particle is then predicted afresh (see `System::run_window`).

pub(crate) mod collision;
#[cfg(target_arch = "x86_64")]
pub(crate) mod collision_simd;
pub(crate) mod neighbour_exit;
pub(crate) mod wall;

/// What the collision slot of a particle holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// Collision with particle `j`.
    Pair(usize),
    /// Collision with flat wall `2·axis + side` (side 0 at x = 0, 1 at x = L).
    Wall(usize),
}

/// `other` values from this one up are walls (at most 2·MAX_DIM of them).
const WALL_BASE: u32 = u32::MAX - 64;
/// Particle indices must stay below this.
pub(crate) const MAX_PARTICLES: usize = WALL_BASE as usize;

/// The two predicted events of one particle. Times are relative to the clock origin, ∞ when
/// the event never happens.
#[derive(Clone, Copy, Debug)]
struct Slot {
    collision: f64,
    renewal: f64,
    /// Partner particle, or `WALL_BASE + wall`.
    other: u32,
    /// Trajectory version of the partner particle at prediction time (unused for walls).
    partner_version: u32,
}

const EMPTY: Slot = Slot {
    collision: f64::INFINITY,
    renewal: f64::INFINITY,
    other: 0,
    partner_version: 0,
};

/// The event at the top of the calendar.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Next {
    /// Particle `i` collides with `kind` at time `t`; `partner_version` as predicted.
    Collision {
        t: f64,
        i: usize,
        kind: Kind,
        partner_version: u32,
    },
    /// Particle `i` renews its neighbour list at time `t`.
    Renewal { t: f64, i: usize },
}

/// The event calendar: a tournament tree over the particles' earliest events.
///
/// Node `k` in `1..2m` holds the earliest key of its subtree and the particle it belongs to;
/// the leaves `m..2m` are the particles `0..m` (those ≥ N have key ∞), node 1 is the root.
/// Ties go to the left subtree (the smaller particle index), so the order depends on nothing
/// but the events themselves. Key and winner share one 16-byte node, so the two children
/// of a node share a cache line and one level of a walk touches two lines.
#[derive(Default)]
pub(crate) struct Calendar {
    m: usize,
    node: Vec<Node>,
    slot: Vec<Slot>,
}

/// One node of the tournament tree: the earliest event time of its subtree and its particle.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
struct Node {
    key: f64,
    who: u32,
}

const LEAF_EMPTY: Node = Node {
    key: f64::INFINITY,
    who: 0,
};

impl Calendar {
    /// An empty calendar for `n` particles (every event at ∞); call [`Self::build`] after
    /// filling the slots.
    pub fn reset(&mut self, n: usize) {
        self.m = n.max(1).next_power_of_two();
        self.node.clear();
        self.node.resize(2 * self.m, LEAF_EMPTY);
        self.slot.clear();
        self.slot.resize(n, EMPTY);
        self.build();
    }

    /// Recomputes every node (after slots were filled without walking the tree).
    pub fn build(&mut self) {
        let m = self.m;
        for i in 0..m {
            self.node[m + i] = Node {
                key: self
                    .slot
                    .get(i)
                    .map_or(f64::INFINITY, |s| s.collision.min(s.renewal)),
                who: i as u32,
            };
        }
        for node in (1..m).rev() {
            self.play(node);
        }
    }

    /// Sets node `k` to the winner of its two children; returns whether it changed.
    #[inline(always)]
    fn play(&mut self, k: usize) -> bool {
        // Index arithmetic instead of a branch: which child wins is a coin toss to the branch
        // predictor.
        let l = 2 * k;
        let w = self.node[l + usize::from(self.node[l + 1].key < self.node[l].key)];
        let old = self.node[k];
        self.node[k] = w;
        old.key != w.key || old.who != w.who
    }

    /// Re-keys particle `i` and walks up while the winners change (a node whose key and
    /// winner stay the same leaves everything above it as it was).
    #[inline]
    fn update(&mut self, i: usize) {
        let s = &self.slot[i];
        let mut k = self.m + i;
        self.node[k].key = s.collision.min(s.renewal);
        k >>= 1;
        while k >= 1 && self.play(k) {
            k >>= 1;
        }
    }

    /// Sets the collision of `i` (`t` = ∞: none); takes effect at [`Self::commit`] or
    /// [`Self::build`].
    #[inline]
    pub fn set_collision(&mut self, i: usize, t: f64, kind: Kind, partner_version: u32) {
        let s = &mut self.slot[i];
        s.collision = t;
        s.other = match kind {
            Kind::Pair(j) => j as u32,
            Kind::Wall(w) => WALL_BASE + w as u32,
        };
        s.partner_version = partner_version;
    }

    /// Sets the neighbour-list renewal of `i`; takes effect at [`Self::commit`] or
    /// [`Self::build`].
    #[inline]
    pub fn set_renewal(&mut self, i: usize, t: f64) {
        self.slot[i].renewal = t;
    }

    /// Re-keys particle `i` after its slots changed and walks up to the root.
    #[inline]
    pub fn commit(&mut self, i: usize) {
        self.update(i);
    }

    /// Re-keys particles `i` and `j` after both slots changed (a collision): their two paths are
    /// walked up to the node where they meet, and one path above it, which saves most of a walk
    /// since colliding particles are neighbours in the cell order of the numbering.
    #[inline]
    pub fn commit_pair(&mut self, i: usize, j: usize) {
        let (mut a, mut b) = (self.m + i, self.m + j);
        for (leaf, p) in [(a, i), (b, j)] {
            let s = &self.slot[p];
            self.node[leaf].key = s.collision.min(s.renewal);
        }
        loop {
            a >>= 1;
            b >>= 1;
            if a == b {
                break;
            }
            self.play(a);
            self.play(b);
        }
        while a >= 1 && self.play(a) {
            a >>= 1;
        }
    }

    /// Time of `i`'s predicted neighbour-list renewal.
    #[inline]
    pub fn renewal_time(&self, i: usize) -> f64 {
        self.slot[i].renewal
    }

    /// Time of the earliest event (∞ when there is none).
    #[inline]
    pub fn next_time(&self) -> f64 {
        self.node.get(1).map_or(f64::INFINITY, |n| n.key)
    }

    #[inline]
    fn top(&self) -> usize {
        self.node[1].who as usize
    }

    /// The earliest event (a collision before a renewal of the same particle at the same
    /// time); call only when [`Self::next_time`] is finite. It stays in the calendar: handling it must re-predict the slot it came from.
    #[inline]
    pub fn next(&self) -> Next {
        let i = self.top();
        let s = &self.slot[i];
        if s.collision <= s.renewal {
            let kind = if s.other >= WALL_BASE {
                Kind::Wall((s.other - WALL_BASE) as usize)
            } else {
                Kind::Pair(s.other as usize)
            };
            Next::Collision {
                t: s.collision,
                i,
                kind,
                partner_version: s.partner_version,
            }
        } else {
            Next::Renewal { t: s.renewal, i }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tournament_tree_pops_in_time_order() {
        let mut c = Calendar::default();
        let n = 37;
        c.reset(n);
        for i in 0..n {
            let t = ((i * 7919) % 101) as f64;
            c.set_collision(i, t, Kind::Pair((i + 1) % n), 0);
            c.set_renewal(i, t + 0.5);
        }
        c.build();
        let mut last = f64::NEG_INFINITY;
        for _ in 0..2 * n {
            let (t, i) = match c.next() {
                Next::Collision { t, i, .. } => {
                    c.set_collision(i, f64::INFINITY, Kind::Wall(0), 0);
                    c.commit(i);
                    (t, i)
                }
                Next::Renewal { t, i } => {
                    c.set_renewal(i, f64::INFINITY);
                    c.commit(i);
                    (t, i)
                }
            };
            assert!(t >= last, "{t} after {last} (particle {i})");
            last = t;
        }
        assert_eq!(c.next_time(), f64::INFINITY);
    }

    /// Re-keying two particles at once leaves the tree exactly as two single re-keyings do.
    #[test]
    fn a_pair_commit_equals_two_commits() {
        let n = 45;
        let (mut one, mut two) = (Calendar::default(), Calendar::default());
        for c in [&mut one, &mut two] {
            c.reset(n);
            for i in 0..n {
                c.set_collision(i, ((i * 37) % 11) as f64, Kind::Pair(0), 0);
            }
            c.build();
        }
        for step in 0..2000usize {
            let (i, j) = ((step * 7919) % n, (step * 104_729 + 3) % n);
            if i == j {
                continue;
            }
            let (ti, tj) = (((step * 31) % 17) as f64, ((step * 13) % 17) as f64);
            for c in [&mut one, &mut two] {
                c.set_collision(i, ti, Kind::Pair(j), 0);
                c.set_renewal(j, tj);
            }
            one.commit_pair(i, j);
            two.commit(i);
            two.commit(j);
            for k in 1..2 * one.m {
                assert_eq!(one.node[k].key, two.node[k].key, "node {k} at step {step}");
                assert_eq!(one.node[k].who, two.node[k].who, "node {k} at step {step}");
            }
        }
    }
}
