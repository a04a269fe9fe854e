//! Input: a 64-bit seed. Output: a deterministic stream of integers
//! (SplitMix64, Steele, Lea and Flood, "Fast splittable pseudorandom
//! number generators", OOPSLA 2014), and the few draws the families use.
//!
//! Integer arithmetic only (wrapping `u64` operations and an unbiased
//! rejection for ranges), so a seed gives the same stream on every
//! machine, compiler and thread count. Written here rather than taken
//! from a crate so that the stream can never change under a version bump:
//! the generated meshes' bytes depend on it.

/// A SplitMix64 generator.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    /// The generator whose first output is `SplitMix64(seed)`'s.
    pub fn new(seed: u64) -> Self {
        Rng { state: seed }
    }

    /// The stream of a family: the seed mixed with the family name
    /// (FNV-1a), so that two families never share a stream.
    pub fn for_family(name: &str, seed: u64) -> Self {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in name.bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        let mut r = Rng::new(h);
        let mixed = r.next_u64() ^ seed;
        Rng::new(mixed)
    }

    /// The next 64 bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n` (`n > 0`), without modulo bias: draws below the
    /// largest multiple of `n` are kept.
    pub fn below(&mut self, n: u64) -> u64 {
        assert!(n > 0, "below(0)");
        let zone = u64::MAX - (u64::MAX % n + 1) % n;
        loop {
            let x = self.next_u64();
            if x <= zone {
                return x % n;
            }
        }
    }

    /// Uniform in `lo..=hi` (`lo <= hi`).
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        assert!(lo <= hi, "empty range {lo}..={hi}");
        let span = (hi - lo) as u64 + 1;
        lo + self.below(span) as i64
    }

    /// Uniform in `lo..=hi` as a `usize`.
    pub fn size(&mut self, lo: usize, hi: usize) -> usize {
        self.range(lo as i64, hi as i64) as usize
    }

    /// True with probability `num / den`.
    pub fn chance(&mut self, num: u64, den: u64) -> bool {
        self.below(den) < num
    }

    /// A uniformly chosen element.
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len() as u64) as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference outputs of SplitMix64 from seed 0 (Vigna's
    /// `splitmix64.c`, the generator that seeds xoshiro): a change of the
    /// stream would change every generated mesh.
    #[test]
    fn splitmix64_matches_the_reference_stream() {
        let mut r = Rng::new(0);
        assert_eq!(r.next_u64(), 0xe220_a839_7b1d_cdaf);
        assert_eq!(r.next_u64(), 0x6e78_9e6a_a1b9_65f4);
        assert_eq!(r.next_u64(), 0x06c4_5d18_8009_454f);
    }

    #[test]
    fn below_stays_in_range_and_hits_every_value() {
        let mut r = Rng::new(7);
        let mut seen = [0u32; 7];
        for _ in 0..7000 {
            seen[r.below(7) as usize] += 1;
        }
        assert!(seen.iter().all(|&c| c > 800 && c < 1200), "{seen:?}");
        assert_eq!(r.range(-3, -3), -3);
        assert!((0..100).all(|_| (-2..=2).contains(&r.range(-2, 2))));
    }

    #[test]
    fn family_streams_differ() {
        let a = Rng::for_family("polycube", 1).next_u64();
        let b = Rng::for_family("terraced", 1).next_u64();
        let c = Rng::for_family("polycube", 2).next_u64();
        assert!(a != b && a != c);
    }
}
