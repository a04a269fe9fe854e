//! The weld's table of kept vertices: open addressing with linear probing,
//! one 8-byte slot per entry (a vertex id and 32 bits of its hash), so that
//! a slot can be fetched from memory before it is needed
//! ([`Table::prefetch`]).
//!
//! Why not `hashbrown`: welding a million-triangle soup looks up three
//! million corners, each at a random slot of a table larger than the
//! caches; one lookup at a time, each waits for memory. Here the weld asks
//! for the slot of the corner a few places ahead while it works on this
//! one, which no map API offers (loading a 1 M-triangle binary STL, one
//! thread: 0.165 s with `hashbrown::HashTable`, 0.090 s with this table). Equality is always decided on the kept coordinates
//! (the hash bits only skip slots that cannot match), so the weld stays
//! exact whatever the hash does.

/// The hash bits kept in a slot beside the id.
fn tag(hash: u64) -> u32 {
    (hash >> 32) as u32
}

/// A set of vertex ids keyed by their positions' hashes. Slot value 0 is
/// empty; else `tag << 32 | (id + 1)`.
pub(super) struct Table {
    slots: Vec<u64>,
    len: usize,
}

impl Table {
    /// A table that holds `n` entries without growing.
    pub(super) fn with_capacity(n: usize) -> Self {
        Table {
            slots: vec![0; slots_for(n)],
            len: 0,
        }
    }

    fn mask(&self) -> usize {
        self.slots.len() - 1
    }

    /// Asks for the slot where a lookup of `hash` starts to be brought into
    /// the cache (a hint; it changes no result).
    #[inline]
    pub(super) fn prefetch(&self, hash: u64) {
        #[cfg(target_arch = "x86_64")]
        {
            let slot = &self.slots[hash as usize & self.mask()];
            // SAFETY: SSE is part of x86-64, so `_mm_prefetch` is available.
            // It only hints the cache and never faults, whatever the
            // address; this one is a live element of `slots`.
            unsafe {
                core::arch::x86_64::_mm_prefetch::<{ core::arch::x86_64::_MM_HINT_T0 }>(
                    (slot as *const u64).cast(),
                )
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = hash;
    }

    /// The id stored under `hash` for which `same(id)` holds, if any.
    #[inline]
    pub(super) fn find(&self, hash: u64, mut same: impl FnMut(u32) -> bool) -> Option<u32> {
        let mask = self.mask();
        let want = tag(hash);
        let mut i = hash as usize & mask;
        loop {
            let s = self.slots[i];
            if s == 0 {
                return None;
            }
            let id = (s as u32).wrapping_sub(1);
            if (s >> 32) as u32 == want && same(id) {
                return Some(id);
            }
            i = (i + 1) & mask;
        }
    }

    /// Stores `id` under `hash` (the caller has checked it is not there).
    /// `rehash(id)` gives the hash of a stored id, to grow the table.
    /// `id` must be below `u32::MAX`.
    #[inline]
    pub(super) fn insert(&mut self, hash: u64, id: u32, rehash: impl Fn(u32) -> u64) {
        if 2 * (self.len + 1) > self.slots.len() {
            self.grow(&rehash);
        }
        self.place(hash, id);
        self.len += 1;
    }

    fn place(&mut self, hash: u64, id: u32) {
        let mask = self.mask();
        let mut i = hash as usize & mask;
        while self.slots[i] != 0 {
            i = (i + 1) & mask;
        }
        self.slots[i] = u64::from(tag(hash)) << 32 | u64::from(id + 1);
    }

    #[cold]
    fn grow(&mut self, rehash: &impl Fn(u32) -> u64) {
        let doubled = vec![0; 2 * self.slots.len()];
        let old = std::mem::replace(&mut self.slots, doubled);
        for s in old.into_iter().filter(|&s| s != 0) {
            let id = (s as u32) - 1;
            self.place(rehash(id), id);
        }
    }
}

/// Slots for `n` entries at a load of at most one half (a power of two).
fn slots_for(n: usize) -> usize {
    (2 * n.max(4)).next_power_of_two()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hashes that share their start slot and their tag still keep their
    /// ids apart (the caller's `same` decides), through growing.
    #[test]
    fn colliding_hashes_are_told_apart_by_the_caller() {
        let mut t = Table::with_capacity(1);
        let hash = |_: u32| 0x1234_5678_0000_0003u64;
        for id in 0..100u32 {
            assert_eq!(t.find(hash(id), |k| k == id), None);
            t.insert(hash(id), id, hash);
        }
        for id in 0..100u32 {
            assert_eq!(t.find(hash(id), |k| k == id), Some(id));
        }
        assert_eq!(t.find(hash(0), |k| k == 100), None);
        // A different tag never reaches `same`.
        assert_eq!(t.find(0x9999_0000_0000_0003, |_| true), None);
    }

    /// Ids 0 and u32::MAX - 2 round-trip through a slot.
    #[test]
    fn ends_of_the_id_range_round_trip() {
        let mut t = Table::with_capacity(2);
        t.insert(7, 0, |_| 7);
        t.insert(9, u32::MAX - 2, |_| 9);
        assert_eq!(t.find(7, |k| k == 0), Some(0));
        assert_eq!(t.find(9, |k| k == u32::MAX - 2), Some(u32::MAX - 2));
    }
}
