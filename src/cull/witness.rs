//! Frame-to-frame witnesses of visibility: per part of an organ's hierarchy
//! ([`crate::bvh::Part`]), the place among the part's vertices of one that was seen the last frame
//! the part was tested.
//!
//! - No coordinate space: places only.
//! - A vertex seen where it lies (uncovered, or in front of the occluders there:
//!   [`super::Occluders::sees`]) shows that no test of its part could pass, so the part is drawn.
//! - Most parts that are visible in one frame are so in the next, and often through the same
//!   vertex: the next frame looks that one vertex up first, and where it is seen again, the part is
//!   drawn without its tests.
//! - What is culled does not depend on the witnesses: any vertex of the part would show the same,
//!   so a stale witness (or one kept for another set) only costs its look-up.

use std::sync::atomic::{AtomicU8, Ordering::Relaxed};

/// No witness.
const NO_WITNESS: u8 = u8::MAX;

/// One organ's witnesses, one per part. Shared by the threads of a traversal, each recording those
/// of the parts it tests (a part is tested by one thread a frame).
#[derive(Debug, Default)]
pub struct Witnesses(Vec<AtomicU8>);

impl Clone for Witnesses {
    fn clone(&self) -> Self {
        Witnesses(self.0.iter().map(|w| AtomicU8::new(w.load(Relaxed))).collect())
    }
}

impl Witnesses {
    /// Fits the list to `parts` parts, forgetting every witness where the count differs.
    pub fn fit(&mut self, parts: usize) {
        if self.0.len() != parts {
            self.0 = (0..parts).map(|_| AtomicU8::new(NO_WITNESS)).collect();
        }
    }

    /// Part `part`'s witness: a place among its vertices.
    pub fn get(&self, part: usize) -> Option<usize> {
        self.0.get(part).map(|w| w.load(Relaxed)).filter(|&w| w != NO_WITNESS).map(usize::from)
    }

    /// Records part `part`'s witness (`None`: it has none).
    pub fn set(&self, part: usize, witness: Option<usize>) {
        let w = witness.and_then(|w| u8::try_from(w).ok()).unwrap_or(NO_WITNESS);
        if let Some(at) = self.0.get(part).filter(|at| at.load(Relaxed) != w) {
            at.store(w, Relaxed);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn witnesses_are_kept_per_part_and_forgotten_when_the_parts_change() {
        let mut w = Witnesses::default();
        w.fit(3);
        assert_eq!((w.get(0), w.get(2), w.get(3)), (None, None, None));
        w.set(1, Some(7));
        w.set(2, Some(300)); // no place that large: none kept
        w.set(5, Some(1)); // no such part: ignored
        assert_eq!((w.get(1), w.get(2)), (Some(7), None));
        w.fit(3);
        assert_eq!(w.clone().get(1), Some(7));
        w.set(1, None);
        assert_eq!(w.get(1), None);
        w.set(1, Some(4));
        w.fit(4);
        assert_eq!(w.get(1), None);
    }
}
