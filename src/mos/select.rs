//! Scoring and selecting minimum occluder sets (thesis §3.2.3).
//!
//! - On occluder indices and their centre-sampled images (image pixels, depth = NDC z).
//! - Identical sets found for different occludees are grouped, their gains added; a set inherits
//!   the gain of every set it contains (occlusion fusion: rendering ABC also hides what AB hides).
//! - Sets are ranked by gain over cost, and taken in that order, each overlaid on an ID buffer of
//!   the occluders taken so far: an occluder that holds no pixel of the buffer (redundant, or
//!   hidden behind nearer ones) is dropped, until the limit is reached.

use super::coverage::LeafImage;
use super::search::{is_subset, signature};
use std::collections::HashMap;

/// Groups identical sets and lets each inherit the gains of its subsets. Input: (sorted set, gain
/// of one occludee); output: distinct sets with their total gain.
pub fn gains(found: impl IntoIterator<Item = (Vec<u32>, f64)>) -> Vec<(Vec<u32>, f64)> {
    let mut own: HashMap<Vec<u32>, f64> = HashMap::new();
    for (set, gain) in found {
        *own.entry(set).or_default() += gain;
    }
    let sets: Vec<(Vec<u32>, f64, u64)> = own.into_iter().map(|(s, g)| (s.clone(), g, signature(&s))).collect();
    // Sets by their smallest occluder: a subset of S starts with one of S's occluders.
    let mut by_first: HashMap<u32, Vec<usize>> = HashMap::new();
    for (i, (s, _, _)) in sets.iter().enumerate() {
        if let Some(&first) = s.first() {
            by_first.entry(first).or_default().push(i);
        }
    }
    let mut out: Vec<(Vec<u32>, f64)> = sets
        .iter()
        .map(|(s, _, sig)| {
            let total: f64 = s
                .iter()
                .flat_map(|id| by_first.get(id).into_iter().flatten())
                .map(|&j| &sets[j])
                .filter(|(t, _, tsig)| t.len() <= s.len() && tsig & !sig == 0 && is_subset(t, s))
                .map(|(_, g, _)| g)
                .sum();
            (s.clone(), total)
        })
        .collect();
    out.sort_by(|a, b| a.0.cmp(&b.0));
    out
}

/// Ranks sets by score = gain / cost, best first (ties: fewer occluders, then the set itself).
pub fn rank(sets: Vec<(Vec<u32>, f64)>, cost: &dyn Fn(&[u32]) -> f64) -> Vec<Vec<u32>> {
    let mut scored: Vec<(f64, Vec<u32>)> = sets.into_iter().map(|(s, g)| (g / cost(&s).max(1e-9), s)).collect();
    scored.sort_by(|a, b| b.0.total_cmp(&a.0).then_with(|| a.1.len().cmp(&b.1.len())).then_with(|| a.1.cmp(&b.1)));
    scored.into_iter().map(|(_, s)| s).collect()
}

/// Takes ranked sets in order, overlaying each on the ID buffer of those taken before; returns
/// the occluders holding pixels of the buffer, in the order they were first taken, at most `limit`.
pub fn select(ranked: &[Vec<u32>], images: &[Option<LeafImage>], w: usize, h: usize, limit: usize) -> Vec<u32> {
    let mut nearest: Vec<(f32, u32)> = vec![(f32::INFINITY, u32::MAX); w * h];
    let mut held: HashMap<u32, u32> = HashMap::new(); // occluder -> pixels held
    let mut order: Vec<u32> = Vec::new();
    let mut present = 0usize;
    for set in ranked {
        for &id in set {
            if held.contains_key(&id) {
                continue;
            }
            held.insert(id, 0);
            order.push(id);
            for (x, y, d) in images[id as usize].iter().flat_map(|im| im.covered()) {
                let p = &mut nearest[y * w + x];
                if d < p.0 {
                    if p.1 != u32::MAX {
                        let old = held.entry(p.1).or_default();
                        *old -= 1;
                        if *old == 0 {
                            present -= 1;
                        }
                    }
                    let new = held.entry(id).or_default();
                    *new += 1;
                    if *new == 1 {
                        present += 1;
                    }
                    *p = (d, id);
                }
            }
        }
        if present >= limit {
            break;
        }
    }
    order.into_iter().filter(|id| held.get(id).is_some_and(|&n| n > 0)).take(limit).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn supersets_inherit_gains() {
        let g = gains(vec![(vec![1], 2.0), (vec![1, 2], 3.0), (vec![1, 2], 1.0), (vec![2, 3], 5.0)]);
        assert_eq!(g, vec![(vec![1], 2.0), (vec![1, 2], 6.0), (vec![2, 3], 5.0)]);
    }

    fn square(x0: usize, y0: usize, n: usize, z: f32) -> Option<LeafImage> {
        Some(LeafImage { x0, y0, w: n, h: n, depth: vec![z; n * n], pixels: (n * n) as u32 })
    }

    #[test]
    fn hidden_and_redundant_occluders_are_dropped() {
        // 0: a near square; 1: a far square behind it; 2: a square beside them.
        let images = vec![square(0, 0, 4, 0.2), square(1, 1, 2, 0.8), square(5, 0, 2, 0.5)];
        let ranked = vec![vec![0, 1], vec![2]];
        assert_eq!(select(&ranked, &images, 8, 8, 10), vec![0, 2]);
        assert_eq!(select(&ranked, &images, 8, 8, 1), vec![0]);
        // Ranked scores: gain 6 over 2 occluders beats gain 2 over 1.
        let cost = |s: &[u32]| s.len() as f64;
        assert_eq!(rank(vec![(vec![2], 2.0), (vec![0, 1], 6.0)], &cost), vec![vec![0, 1], vec![2]]);
    }
}
