//! Events and the event calendar.
//!
//! One binary heap holds every predicted event. An event remembers the version counters of
//! the particles it involves at prediction time; a particle's counter changes whenever its
//! trajectory does, so an event whose counters no longer match is stale and is dropped when
//! it reaches the top (lazy invalidation). Each particle pushes only its earliest collision,
//! so the heap stays O(N); see `System::process` for how a stale partner is handled.

pub(crate) mod cell_crossing;
pub(crate) mod collision;
pub(crate) mod wall;

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// What an event does, encoded in [`Event::other`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// Collision of `i` with particle `j`.
    Pair(usize),
    /// Collision of `i` with flat wall `2·axis + side` (side 0 at x = 0, 1 at x = L).
    Wall(usize),
    /// `i` leaves its cell.
    Crossing,
}

/// `other` values from this one up are walls (at most 2·MAX_DIM of them).
const WALL_BASE: u32 = u32::MAX - 64;
const CROSSING: u32 = u32::MAX;
/// Particle indices must stay below this.
pub(crate) const MAX_PARTICLES: usize = WALL_BASE as usize;

/// One predicted event at time `t` (relative to the current clock origin).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Event {
    pub t: f64,
    pub i: u32,
    other: u32,
    /// Version of `i` (trajectory version, or crossing version for a crossing).
    pub vi: u32,
    /// Trajectory version of the partner particle for a pair; for a crossing, the face it
    /// leaves through, `2·axis + 1` upwards or `2·axis` downwards; unused for walls.
    pub vj: u32,
}

impl Event {
    pub fn new(t: f64, i: usize, kind: Kind, vi: u32, vj: u32) -> Self {
        let other = match kind {
            Kind::Pair(j) => j as u32,
            Kind::Wall(w) => WALL_BASE + w as u32,
            Kind::Crossing => CROSSING,
        };
        Event {
            t,
            i: i as u32,
            other,
            vi,
            vj,
        }
    }

    pub fn kind(&self) -> Kind {
        match self.other {
            CROSSING => Kind::Crossing,
            o if o >= WALL_BASE => Kind::Wall((o - WALL_BASE) as usize),
            j => Kind::Pair(j as usize),
        }
    }
}

impl PartialEq for Event {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Event {}
impl PartialOrd for Event {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Event {
    /// Reversed on time so that `BinaryHeap` pops the earliest event; ties are broken by the
    /// particle indices so the order never depends on anything but the events themselves.
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .t
            .total_cmp(&self.t)
            .then_with(|| other.i.cmp(&self.i))
            .then_with(|| other.other.cmp(&self.other))
    }
}

/// The event calendar: a min-heap on time.
#[derive(Default)]
pub(crate) struct Calendar {
    heap: BinaryHeap<Event>,
}

impl Calendar {
    pub fn clear(&mut self) {
        self.heap.clear();
    }
    /// Schedules `e` unless it never happens.
    #[inline]
    pub fn push(&mut self, e: Event) {
        if e.t.is_finite() {
            self.heap.push(e);
        }
    }
    /// Time of the earliest event (∞ when empty).
    #[inline]
    pub fn next_time(&self) -> f64 {
        self.heap.peek().map_or(f64::INFINITY, |e| e.t)
    }
    #[inline]
    pub fn pop(&mut self) -> Option<Event> {
        self.heap.pop()
    }
}
