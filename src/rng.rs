//! A tiny deterministic xorshift generator: the same numbers on every machine, for tests, the mask
//! experiments and the reference mask generators (white noise, pixel tree).
//!
//! - `xorshift64`; any seed, 0 included, is scrambled (splitmix64) into a state, so nearby seeds
//!   differ.

/// `xorshift64`. Build it with [`XorShift::seeded`] (any seed, 0 included) or directly with a
/// non-zero state.
pub struct XorShift(pub u64);

impl XorShift {
    /// A generator from any seed: the seed is scrambled (splitmix64) so nearby seeds differ.
    pub fn seeded(seed: u64) -> XorShift {
        let mut z = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        XorShift((z ^ (z >> 31)) | 1)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in 0..1, in steps of 1e-4.
    pub fn unit(&mut self) -> f32 {
        (self.next_u64() % 10_000) as f32 / 10_000.0
    }

    /// Uniform in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }

    /// A permutation of `0..n` shuffled by a generator from `seed`.
    pub fn permutation(n: usize, seed: u64) -> Vec<usize> {
        let mut order: Vec<usize> = (0..n).collect();
        XorShift::seeded(seed).shuffle(&mut order);
        order
    }

    /// Shuffles `items` in place (Fisher-Yates).
    pub fn shuffle<T>(&mut self, items: &mut [T]) {
        for i in (1..items.len()).rev() {
            let j = self.below(i + 1);
            items.swap(i, j);
        }
    }
}
