//! The neighbour lists of all particles in one flat array: the list of particle `i` is a run
//! of `data` with room to grow. The prediction loop reads one list per prediction, so lists
//! laid out in particle order (which is cell order, see `System::rebuild`) are near each other
//! and near the lists of the particles' neighbours, where one heap allocation per list scatters
//! them (one cache miss before the first partner is known).
//!
//! A list that outgrows its room moves to the end of `data` with twice the room; the holes it
//! leaves are reclaimed when the lists are laid out afresh ([`NeighbourLists::begin`]), which
//! `System` does at every grid rebuild.

/// Extra room of a freshly laid-out list: renewals add a partner now and then.
const SLACK: u32 = 4;

#[derive(Default)]
pub(crate) struct NeighbourLists {
    start: Vec<u32>,
    len: Vec<u32>,
    room: Vec<u32>,
    data: Vec<u32>,
}

impl NeighbourLists {
    /// Forgets every list; lists are then laid out in order with [`Self::push_new`] for
    /// particles `0, 1, …, n − 1`.
    pub fn begin(&mut self, n: usize) {
        self.start.clear();
        self.len.clear();
        self.room.clear();
        self.data.clear();
        self.start.reserve(n);
    }

    /// Lays out the list of the next particle (in order from 0).
    pub fn push_new(&mut self, partners: impl Iterator<Item = u32>) {
        let start = self.data.len();
        self.data.extend(partners);
        let len = (self.data.len() - start) as u32;
        self.data.resize(start + (len + SLACK) as usize, 0);
        self.start.push(start as u32);
        self.len.push(len);
        self.room.push(len + SLACK);
    }

    /// The partners of particle `i`.
    #[inline]
    pub fn get(&self, i: usize) -> &[u32] {
        let s = self.start[i] as usize;
        &self.data[s..s + self.len[i] as usize]
    }

    /// Replaces the list of `i`.
    pub fn set(&mut self, i: usize, partners: &[u32]) {
        if partners.len() as u32 > self.room[i] {
            self.relocate(i, 2 * partners.len() as u32);
        }
        let s = self.start[i] as usize;
        self.data[s..s + partners.len()].copy_from_slice(partners);
        self.len[i] = partners.len() as u32;
    }

    /// Adds `j` to the list of `i`.
    pub fn push(&mut self, i: usize, j: u32) {
        if self.len[i] == self.room[i] {
            self.relocate(i, 2 * self.room[i] + SLACK);
        }
        self.data[(self.start[i] + self.len[i]) as usize] = j;
        self.len[i] += 1;
    }

    /// Removes `j` from the list of `i` (the last partner takes its place), if it is there.
    pub fn remove(&mut self, i: usize, j: u32) {
        let s = self.start[i] as usize;
        let len = self.len[i] as usize;
        if let Some(k) = self.data[s..s + len].iter().position(|&m| m == j) {
            self.data[s + k] = self.data[s + len - 1];
            self.len[i] -= 1;
        }
    }

    /// Moves the list of `i` to the end of `data` with room for `room` partners.
    fn relocate(&mut self, i: usize, room: u32) {
        let (s, len) = (self.start[i] as usize, self.len[i] as usize);
        let new = self.data.len();
        self.data.extend_from_within(s..s + len);
        self.data.resize(new + room as usize, 0);
        self.start[i] = new as u32;
        self.room[i] = room;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_grow_shrink_and_move_without_losing_partners() {
        let mut l = NeighbourLists::default();
        l.begin(3);
        l.push_new([1, 2].into_iter());
        l.push_new([0].into_iter());
        l.push_new(std::iter::empty());
        for j in 10..30 {
            l.push(1, j);
        }
        assert_eq!(l.get(0), &[1, 2]);
        assert_eq!(l.get(1).len(), 21);
        assert_eq!(l.get(1)[..3], [0, 10, 11]);
        l.remove(1, 0);
        l.remove(1, 99);
        assert_eq!(l.get(1).len(), 20);
        assert!(!l.get(1).contains(&0));
        l.set(2, &(0..40).collect::<Vec<u32>>());
        assert_eq!(l.get(2).len(), 40);
        l.set(0, &[7]);
        assert_eq!(l.get(0), &[7]);
        assert_eq!(l.get(1).len(), 20);
    }
}
