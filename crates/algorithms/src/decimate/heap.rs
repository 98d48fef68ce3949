//! The indexed priority queue of the collapse loop.

/// A binary min-heap of halfedges keyed by their collapse priority, with each halfedge's
/// place in the heap, so that a key is changed or removed in place (pmp-library's
/// `HeapInterface`): the heap never holds more than one entry per halfedge. Ties go to
/// the smaller halfedge id, so the order is a deterministic function of the keys.
///
/// Keys are non-negative (quadric errors and their penalised values), so their bit
/// patterns order as the values do (`f64::total_cmp`); the heap compares those as
/// integers.
pub(super) struct Heap {
    /// `(key bits, halfedge)`, a min-heap in `(key, halfedge)` order.
    entries: Vec<(u64, u32)>,
    /// Per halfedge: its index in `entries`, or `u32::MAX` when it is not queued.
    place: Vec<u32>,
}

/// The bits of a non-negative key, `-0` as `+0`: ordered as the keys are.
fn bits(key: f64) -> u64 {
    debug_assert!(key >= 0.0 || key.is_nan(), "a negative heap key: {key}");
    (key + 0.0).to_bits()
}

impl Heap {
    const ABSENT: u32 = u32::MAX;

    /// An empty heap for halfedge ids below `capacity`.
    pub(super) fn with_capacity(capacity: usize) -> Self {
        Self {
            entries: Vec::new(),
            place: vec![Self::ABSENT; capacity],
        }
    }

    /// Replaces the content of an empty heap by the given `(key, halfedge)` entries, at
    /// most one per halfedge: Floyd's heap construction, O(n). The order of the entries
    /// taken out is the strict `(key, halfedge)` order whatever the layout.
    pub(super) fn fill(&mut self, entries: &[(f64, u32)]) {
        debug_assert!(self.entries.is_empty());
        self.entries = entries.iter().map(|&(key, h)| (bits(key), h)).collect();
        for (i, &(_, h)) in self.entries.iter().enumerate() {
            // Fewer entries than `u32::MAX`: one per halfedge id at most.
            self.place[h as usize] = i as u32;
        }
        for i in (0..self.entries.len() / 2).rev() {
            self.down(i);
        }
    }

    /// Empties the heap and returns its entries as `(key, halfedge)`, in no particular
    /// order (to be keyed again and put back with [`Heap::fill`]).
    pub(super) fn drain(&mut self) -> Vec<(f64, u32)> {
        for &(_, h) in &self.entries {
            self.place[h as usize] = Self::ABSENT;
        }
        std::mem::take(&mut self.entries)
            .into_iter()
            .map(|(key, h)| (f64::from_bits(key), h))
            .collect()
    }

    /// Moves the entry at `i` towards the root to its place; each entry it passes moves
    /// down one level (one write of each place, not a swap per level).
    fn up(&mut self, mut i: usize) {
        let moving = self.entries[i];
        while i > 0 {
            let parent = (i - 1) / 2;
            let above = self.entries[parent];
            if moving >= above {
                break;
            }
            self.entries[i] = above;
            self.place[above.1 as usize] = i as u32;
            i = parent;
        }
        self.entries[i] = moving;
        self.place[moving.1 as usize] = i as u32;
    }

    /// Moves the entry at `i` towards the leaves to its place (as [`Heap::up`]).
    fn down(&mut self, mut i: usize) {
        let n = self.entries.len();
        let moving = self.entries[i];
        loop {
            let l = 2 * i + 1;
            if l >= n {
                break;
            }
            let r = l + 1;
            let c = if r < n && self.entries[r] < self.entries[l] {
                r
            } else {
                l
            };
            let child = self.entries[c];
            if child >= moving {
                break;
            }
            self.entries[i] = child;
            self.place[child.1 as usize] = i as u32;
            i = c;
        }
        self.entries[i] = moving;
        self.place[moving.1 as usize] = i as u32;
    }

    /// Queues `h` with `key` (non-negative), or changes its key.
    pub(super) fn set(&mut self, h: u32, key: f64) {
        let key = bits(key);
        let at = self.place[h as usize];
        if at == Self::ABSENT {
            self.entries.push((key, h));
            let i = self.entries.len() - 1;
            self.place[h as usize] = i as u32;
            self.up(i);
        } else {
            let i = at as usize;
            let old = self.entries[i].0;
            self.entries[i].0 = key;
            if key < old {
                self.up(i);
            } else {
                self.down(i);
            }
        }
    }

    /// Removes `h` if it is queued.
    #[inline]
    pub(super) fn remove(&mut self, h: u32) {
        // Most calls find nothing queued (the collapse loop removes every halfedge of a
        // removed edge): that test is inlined, the removal is not.
        let at = self.place[h as usize];
        if at != Self::ABSENT {
            self.remove_at(h, at as usize);
        }
    }

    /// Removes `h`, queued at `i`.
    fn remove_at(&mut self, h: u32, i: usize) {
        self.place[h as usize] = Self::ABSENT;
        let last = self.entries.pop().expect("a queued entry");
        if i < self.entries.len() {
            // The last entry takes the removed one's place and moves to its own.
            let old = self.entries[i];
            self.entries[i] = last;
            if last < old {
                self.up(i);
            } else {
                self.sink(i);
            }
        }
    }

    /// Moves the entry at `i`, which belongs far below (the last leaf, moved into a
    /// removed entry's place), to its place: the hole goes down to a leaf along the
    /// smaller children (one comparison per level instead of two) and the entry rises
    /// from there (Floyd's bottom-up sift).
    fn sink(&mut self, mut i: usize) {
        let n = self.entries.len();
        let moving = self.entries[i];
        loop {
            let l = 2 * i + 1;
            if l >= n {
                break;
            }
            let r = l + 1;
            let c = if r < n && self.entries[r] < self.entries[l] {
                r
            } else {
                l
            };
            let child = self.entries[c];
            self.entries[i] = child;
            self.place[child.1 as usize] = i as u32;
            i = c;
        }
        self.entries[i] = moving;
        self.up(i);
    }

    /// Whether `h` is queued.
    pub(super) fn contains(&self, h: u32) -> bool {
        self.place[h as usize] != Self::ABSENT
    }

    /// The smallest entry, without removing it.
    pub(super) fn peek(&self) -> Option<(f64, u32)> {
        self.entries
            .first()
            .map(|&(key, h)| (f64::from_bits(key), h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decimate::test_rng::Lcg;

    #[test]
    fn the_heap_gives_the_entries_in_key_then_id_order() {
        let mut rng = Lcg(7);
        let n = 500u32;
        // Few distinct keys, so that ties (broken by the id) are common.
        let mut initial: Vec<(f64, u32)> = Vec::new();
        for h in 0..n {
            if !rng.next().is_multiple_of(3) {
                initial.push(((rng.next() % 20) as f64, h));
            }
        }
        let mut want: std::collections::BTreeMap<u32, f64> =
            initial.iter().map(|&(k, h)| (h, k)).collect();
        let mut heap = Heap::with_capacity(n as usize);
        heap.fill(&initial);
        for _ in 0..2000 {
            let h = (rng.next() % u64::from(n)) as u32;
            if rng.next().is_multiple_of(4) {
                heap.remove(h);
                want.remove(&h);
            } else {
                let key = (rng.next() % 20) as f64 + 0.5 * rng.unit();
                heap.set(h, key);
                want.insert(h, key);
            }
            assert_eq!(heap.contains(h), want.contains_key(&h));
        }
        let mut expected: Vec<(f64, u32)> = want.into_iter().map(|(h, k)| (k, h)).collect();
        expected.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // Drained and filled again (as the collapse loop does when it keys the whole
        // queue), the heap holds the same entries and gives them in the same order.
        let mut drained = heap.drain();
        assert!((0..n).all(|h| !heap.contains(h)));
        assert!(heap.peek().is_none());
        drained.sort_by_key(|&(_, h)| h);
        heap.fill(&drained);
        let mut got = Vec::new();
        while let Some((key, h)) = heap.peek() {
            heap.remove(h);
            got.push((key, h));
        }
        assert_eq!(got, expected);
    }
}
