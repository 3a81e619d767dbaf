//! A tiny deterministic xorshift generator for unit tests: the same numbers on every machine.

/// `xorshift64`; the seed must not be 0.
pub struct XorShift(pub u64);

impl XorShift {
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
}
