//! A mask: a set of sub-samples given by logical index `0..n` (n <= [`MAX_SUBSAMPLES`]).
//!
//! - Indices are logical: where a logical sub-sample lies in the pixel is [`super::layout`]'s
//!   business.
//! - The largest mask is 32x32 sub-samples, the thesis's largest experiment.

/// The largest mask: 32x32 sub-samples, the thesis's largest experiment.
pub const MAX_SUBSAMPLES: usize = 1024;

#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Mask {
    words: [u64; MAX_SUBSAMPLES / 64],
}

impl Default for Mask {
    fn default() -> Self {
        Mask::EMPTY
    }
}

impl std::fmt::Debug for Mask {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_set().entries(self.iter()).finish()
    }
}

impl Mask {
    pub const EMPTY: Mask = Mask { words: [0; MAX_SUBSAMPLES / 64] };

    /// The mask of the first `n` sub-samples.
    pub fn full(n: usize) -> Mask {
        let mut m = Mask::EMPTY;
        for i in 0..n.min(MAX_SUBSAMPLES) {
            m.insert(i);
        }
        m
    }

    pub fn from_indices(indices: impl IntoIterator<Item = usize>) -> Mask {
        let mut m = Mask::EMPTY;
        for i in indices {
            m.insert(i);
        }
        m
    }

    pub fn insert(&mut self, i: usize) {
        self.words[i / 64] |= 1 << (i % 64);
    }

    /// Inserts the sub-samples `range` (a run of consecutive indices).
    pub fn insert_range(&mut self, range: std::ops::Range<usize>) {
        let (mut i, end) = (range.start, range.end.min(MAX_SUBSAMPLES));
        while i < end {
            let (word, bit) = (i / 64, i % 64);
            let n = (64 - bit).min(end - i);
            let ones = if n == 64 { u64::MAX } else { ((1u64 << n) - 1) << bit };
            self.words[word] |= ones;
            i += n;
        }
    }

    pub fn contains(&self, i: usize) -> bool {
        self.words[i / 64] >> (i % 64) & 1 == 1
    }

    pub fn count(&self) -> usize {
        self.words.iter().map(|w| w.count_ones() as usize).sum()
    }

    /// Sub-samples in `self` but not in `other`.
    pub fn minus(&self, other: &Mask) -> Mask {
        let mut m = *self;
        for (a, b) in m.words.iter_mut().zip(&other.words) {
            *a &= !b;
        }
        m
    }

    pub fn union(&self, other: &Mask) -> Mask {
        let mut m = *self;
        for (a, b) in m.words.iter_mut().zip(&other.words) {
            *a |= b;
        }
        m
    }

    /// Sub-samples `64 * i..64 * (i + 1)` as bits.
    pub fn word(&self, i: usize) -> u64 {
        self.words[i]
    }

    /// The first 64 sub-samples as bits (what the renderer uses: masks of at most 64).
    pub fn low_bits(&self) -> u64 {
        self.words[0]
    }

    pub fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        (0..MAX_SUBSAMPLES).filter(|&i| self.contains(i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_match_single_inserts() {
        for (a, b) in [(0, 0), (0, 1), (3, 64), (60, 70), (0, 128), (63, 1024), (100, 900)] {
            let mut m = Mask::EMPTY;
            m.insert_range(a..b);
            assert_eq!(m, Mask::from_indices(a..b), "{a}..{b}");
        }
    }
}
