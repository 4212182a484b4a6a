//! Sorted rows of particle indices, one per particle, in one vector with room to grow in place:
//! the neighbour list's half rows, and while refreshing the lower partners of each particle.

use std::ops::Range;

pub(crate) struct Rows {
    /// Row `i` is `entries[start[i]..start[i] + len[i]]`, with room for `room[i]` entries.
    /// After [`Rows::lay_out`] (or [`Rows::put_in_order`]) the rows lie in order:
    /// `start[i+1] = start[i] + room[i]`. A row that outgrows its room moves to the end.
    pub start: Vec<u32>,
    len: Vec<u32>,
    room: Vec<u32>,
    pub entries: Vec<u32>,
    in_order: bool,
    /// Entries at the last lay-out (moved rows may at most double them), and values held.
    laid_out: usize,
    held: usize,
}

impl Rows {
    pub fn new() -> Self {
        Rows {
            start: Vec::new(),
            len: Vec::new(),
            room: Vec::new(),
            entries: Vec::new(),
            in_order: true,
            laid_out: 0,
            held: 0,
        }
    }

    /// Lays out `n` rows holding `value` in row `row` for each `(row, value)` of `pairs`, each
    /// row sorted, with room for a quarter more (and two) when `spare`. `fill` is scratch.
    pub fn lay_out(
        &mut self,
        n: usize,
        pairs: impl Iterator<Item = (u32, u32)> + Clone,
        spare: bool,
        fill: &mut Vec<u32>,
    ) {
        self.len.clear();
        self.len.resize(n, 0);
        for (i, _) in pairs.clone() {
            self.len[i as usize] += 1;
        }
        self.room.clear();
        self.room.extend(
            self.len
                .iter()
                .map(|&l| if spare { l + 2 + l / 4 } else { l }),
        );
        self.start.clear();
        self.start.resize(n + 1, 0);
        for i in 0..n {
            self.start[i + 1] = self.start[i] + self.room[i];
        }
        fill.clear();
        fill.extend_from_slice(&self.start[..n]);
        self.entries.clear();
        self.entries.resize(self.start[n] as usize, 0);
        self.held = 0;
        for (i, j) in pairs {
            self.entries[fill[i as usize] as usize] = j;
            fill[i as usize] += 1;
            self.held += 1;
        }
        for i in 0..n {
            let row = self.row(i);
            self.entries[row].sort_unstable();
        }
        self.in_order = true;
        self.laid_out = self.entries.len();
    }

    /// The entries that make row `i`.
    #[inline(always)]
    pub fn row(&self, i: usize) -> Range<usize> {
        let a = self.start[i] as usize;
        a..a + self.len[i] as usize
    }

    /// Row `i`'s values.
    pub fn get(&self, i: usize) -> &[u32] {
        &self.entries[self.row(i)]
    }

    /// Values held in all rows.
    pub fn held(&self) -> usize {
        self.held
    }

    /// Makes row `i` hold `values` (sorted). False when the moved rows would double the entries.
    pub fn replace(&mut self, i: usize, values: &[u32]) -> bool {
        if !self.make_room(i, values.len()) {
            return false;
        }
        let a = self.start[i] as usize;
        self.entries[a..a + values.len()].copy_from_slice(values);
        self.held = self.held + values.len() - self.len[i] as usize;
        self.len[i] = values.len() as u32;
        true
    }

    /// Adds `v` to row `i` in order unless it holds it. False when the moved rows would double
    /// the entries.
    pub fn insert(&mut self, i: usize, v: u32) -> bool {
        let Err(at) = self.get(i).binary_search(&v) else {
            return true;
        };
        let len = self.len[i] as usize;
        if !self.make_room(i, len + 1) {
            return false;
        }
        let a = self.start[i] as usize;
        self.entries.copy_within(a + at..a + len, a + at + 1);
        self.entries[a + at] = v;
        self.len[i] += 1;
        self.held += 1;
        true
    }

    /// Takes `v` out of row `i` if it holds it.
    pub fn remove(&mut self, i: usize, v: u32) {
        if let Ok(at) = self.get(i).binary_search(&v) {
            let row = self.row(i);
            self.entries
                .copy_within(row.start + at + 1..row.end, row.start + at);
            self.len[i] -= 1;
            self.held -= 1;
        }
    }

    /// Gives row `i` room for `need` values, moving it to the end of the entries (with a
    /// quarter more and two) when it has less. False when that would double the entries of
    /// the last lay-out.
    fn make_room(&mut self, i: usize, need: usize) -> bool {
        if need <= self.room[i] as usize {
            return true;
        }
        let room = need + 2 + need / 4;
        let at = self.entries.len();
        if at + room > 2 * self.laid_out + 1024 {
            return false;
        }
        let old = self.row(i);
        self.entries.resize(at + room, 0);
        self.entries.copy_within(old, at);
        self.start[i] = at as u32;
        self.room[i] = room as u32;
        self.in_order = false;
        true
    }

    /// Puts the rows back in order (each keeping its room). Returns whether anything moved.
    pub fn put_in_order(&mut self) -> bool {
        if self.in_order {
            return false;
        }
        let n = self.len.len();
        let mut entries = Vec::with_capacity(self.room.iter().map(|&r| r as usize).sum());
        for i in 0..n {
            let row = self.row(i);
            self.start[i] = entries.len() as u32;
            entries.extend_from_slice(&self.entries[row]);
            entries.resize(self.start[i] as usize + self.room[i] as usize, 0);
        }
        self.start[n] = entries.len() as u32;
        self.entries = entries;
        self.in_order = true;
        true
    }
}
