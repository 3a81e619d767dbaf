//! The minimum occluder sets of one occludee (thesis §3.2.1-3.2.2): the cheapest minimal hitting
//! sets of the slots of its combination table, found by backtracking.
//!
//! - On occluder identifiers only (no geometry, no space).
//! - The *occluder stack* of a pixel of the occludee's image is the set of occluders in front of
//!   the occludee that cover the pixel. Pixels with the same stack form one *slot* of the
//!   *combination table*; slots are ordered by how few occluders they hold.
//! - A set of occluders hides the occludee when it *cancels* every slot (holds one of its
//!   occluders): finding a minimum occluder set is finding a minimal hitting set of the slots.
//! - The search runs left to right, backtracking over every occluder of the first slot not yet
//!   cancelled, and prunes a partial set that already costs more than the cheapest sets kept.

/// The combination table of one occludee from the stacks of its pixels (each sorted): its distinct
/// slots, fewest occluders first. A slot holding every occluder of a smaller slot is dropped, as any
/// set that cancels the smaller one cancels it too. `None` if some pixel has an empty stack: then
/// no set of these occluders hides the occludee.
pub fn combination_table<'a>(stacks: impl IntoIterator<Item = &'a [u32]>) -> Option<Vec<Vec<u32>>> {
    let mut distinct: std::collections::HashSet<&[u32]> = Default::default();
    for s in stacks {
        if s.is_empty() {
            return None;
        }
        distinct.insert(s);
    }
    let mut slots: Vec<&[u32]> = distinct.into_iter().collect();
    slots.sort_unstable_by(|a, b| a.len().cmp(&b.len()).then_with(|| a.cmp(b)));
    let mut kept: Vec<(u64, &[u32])> = Vec::new();
    for s in slots {
        let sig = signature(s);
        if !kept.iter().any(|&(ks, k)| ks & !sig == 0 && is_subset(k, s)) {
            kept.push((sig, s));
        }
    }
    Some(kept.into_iter().map(|(_, s)| s.to_vec()).collect())
}

/// A 64-bit summary of a set: a subset's signature has no bit outside its superset's.
pub fn signature(set: &[u32]) -> u64 {
    set.iter().fold(0, |acc, &id| acc | 1u64 << (id.wrapping_mul(0x9E37_79B9) >> 26))
}

/// Is sorted `a` a subset of sorted `b`?
pub fn is_subset(a: &[u32], b: &[u32]) -> bool {
    let mut j = 0;
    for &x in a {
        while j < b.len() && b[j] < x {
            j += 1;
        }
        if j == b.len() || b[j] != x {
            return false;
        }
        j += 1;
    }
    true
}

/// Limits of one search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchLimits {
    /// The cheapest sets kept (the thesis keeps "only the cheapest portion").
    pub keep: usize,
    /// Partial sets tried at most, so a large table cannot run for ever.
    pub steps: usize,
}

/// The cheapest minimum occluder sets of a table (each sorted, cheapest first). `cost` must grow
/// when an occluder is added. Every set returned cancels every slot and is minimal: dropping any
/// of its occluders leaves a slot uncancelled.
pub fn minimum_occluder_sets(table: &[Vec<u32>], cost: &dyn Fn(&[u32]) -> f64, limits: SearchLimits) -> Vec<Vec<u32>> {
    if table.is_empty() || limits.keep == 0 {
        return Vec::new();
    }
    // The slots each occluder cancels.
    let mut slots_of: std::collections::HashMap<u32, Vec<usize>> = Default::default();
    for (s, slot) in table.iter().enumerate() {
        for &id in slot {
            slots_of.entry(id).or_default().push(s);
        }
    }
    // Within a slot, occluders that cancel more slots are tried first: good sets early, so the
    // cost bound prunes sooner.
    let order: Vec<Vec<u32>> = table
        .iter()
        .map(|slot| {
            let mut ids = slot.clone();
            ids.sort_by_key(|id| std::cmp::Reverse(slots_of[id].len()));
            ids
        })
        .collect();
    let mut search = Search {
        table,
        order: &order,
        slots_of: &slots_of,
        cost,
        limits,
        hits: vec![0; table.len()],
        chosen: Vec::new(),
        found: Vec::new(),
        steps: limits.steps,
    };
    search.run(0);
    search.found.into_iter().map(|(_, set)| set).collect()
}

struct Search<'a> {
    table: &'a [Vec<u32>],
    order: &'a [Vec<u32>],
    slots_of: &'a std::collections::HashMap<u32, Vec<usize>>,
    cost: &'a dyn Fn(&[u32]) -> f64,
    limits: SearchLimits,
    /// Per slot, how many chosen occluders cancel it.
    hits: Vec<u32>,
    chosen: Vec<u32>,
    /// (cost, sorted set), cheapest first, at most `limits.keep`.
    found: Vec<(f64, Vec<u32>)>,
    steps: usize,
}

impl Search<'_> {
    fn run(&mut self, from: usize) {
        if self.steps == 0 {
            return;
        }
        self.steps -= 1;
        let Some(s) = (from..self.table.len()).find(|&s| self.hits[s] == 0) else {
            self.record();
            return;
        };
        // Another occluder is needed: prune if the set already costs as much as the worst kept.
        if self.found.len() >= self.limits.keep
            && self.found.last().is_some_and(|(worst, _)| (self.cost)(&self.chosen) >= *worst)
        {
            return;
        }
        for &id in &self.order[s] {
            if self.chosen.contains(&id) {
                continue;
            }
            self.choose(id, 1);
            self.run(s + 1);
            self.choose(id, -1);
            if self.steps == 0 {
                return;
            }
        }
    }

    fn choose(&mut self, id: u32, delta: i32) {
        for &s in &self.slots_of[&id] {
            self.hits[s] = self.hits[s].wrapping_add_signed(delta);
        }
        if delta > 0 {
            self.chosen.push(id);
        } else {
            self.chosen.pop();
        }
    }

    /// Keeps the chosen set, made minimal, if it is new and among the cheapest.
    fn record(&mut self) {
        let mut hits = self.hits.clone();
        let mut set = self.chosen.clone();
        // Drop occluders every slot of which another chosen occluder also cancels, the most
        // recently chosen first.
        let mut i = set.len();
        while i > 0 {
            i -= 1;
            let slots = &self.slots_of[&set[i]];
            if slots.iter().all(|&s| hits[s] >= 2) {
                for &s in slots {
                    hits[s] -= 1;
                }
                set.remove(i);
            }
        }
        set.sort_unstable();
        if self.found.iter().any(|(_, f)| *f == set) {
            return;
        }
        let cost = (self.cost)(&set);
        let at = self.found.partition_point(|(c, _)| *c <= cost);
        if at < self.limits.keep {
            self.found.insert(at, (cost, set));
            self.found.truncate(self.limits.keep);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: u32 = 0;
    const B: u32 = 1;
    const C: u32 = 2;
    const D: u32 = 3;

    fn count(set: &[u32]) -> f64 {
        set.len() as f64
    }

    fn all(table: &[Vec<u32>]) -> Vec<Vec<u32>> {
        minimum_occluder_sets(table, &count, SearchLimits { keep: 100, steps: 100_000 })
    }

    #[test]
    fn thesis_figure_4() {
        // Pixels covered by A only, by C only, by B or D, and by A and B: the last slot holds A's
        // slot, so it is dropped; the minimum occluder sets are ABC and ACD.
        let stacks: Vec<Vec<u32>> = vec![vec![A], vec![C], vec![B, D], vec![A, B], vec![A], vec![B, D]];
        let table = combination_table(stacks.iter().map(|s| s.as_slice())).unwrap_or_default();
        assert_eq!(table, vec![vec![A], vec![C], vec![B, D]]);
        let mut sets = all(&table);
        sets.sort();
        assert_eq!(sets, vec![vec![A, B, C], vec![A, C, D]]);
    }

    #[test]
    fn an_uncovered_pixel_means_visible() {
        let stacks: Vec<Vec<u32>> = vec![vec![A], vec![]];
        assert_eq!(combination_table(stacks.iter().map(|s| s.as_slice())), None);
    }

    #[test]
    fn sets_are_minimal_hitting_sets_and_the_cheapest_come_first() {
        let mut rng = crate::rng::XorShift::seeded(5);
        for _ in 0..200 {
            let ids = 2 + rng.below(8) as u32;
            let slots = 1 + rng.below(7);
            let stacks: Vec<Vec<u32>> = (0..slots)
                .map(|_| {
                    let mut s: Vec<u32> = (0..ids).filter(|_| rng.below(3) == 0).collect();
                    if s.is_empty() {
                        s.push(rng.below(ids as usize) as u32);
                    }
                    s
                })
                .collect();
            let table = combination_table(stacks.iter().map(|s| s.as_slice())).unwrap_or_default();
            let sets = all(&table);
            assert!(!sets.is_empty());
            let hits = |set: &[u32]| stacks.iter().all(|s| s.iter().any(|id| set.contains(id)));
            for set in &sets {
                assert!(hits(set), "{set:?} leaves a pixel of {stacks:?} uncovered");
                for i in 0..set.len() {
                    let mut less = set.clone();
                    less.remove(i);
                    assert!(!hits(&less), "{set:?} is not minimal for {stacks:?}");
                }
            }
            // The cheapest found is a smallest hitting set (brute force over all subsets).
            let best = (0u32..1 << ids)
                .filter(|m| hits(&(0..ids).filter(|i| m >> i & 1 == 1).collect::<Vec<_>>()))
                .map(|m| m.count_ones() as usize)
                .min();
            assert_eq!(Some(sets[0].len()), best);
        }
    }

    #[test]
    fn pruning_keeps_the_cheapest() {
        let table = vec![vec![A, B], vec![B, C], vec![C, D]];
        let sets = minimum_occluder_sets(&table, &count, SearchLimits { keep: 1, steps: 1000 });
        assert_eq!(sets.len(), 1);
        assert_eq!(sets[0].len(), 2);
    }

    #[test]
    fn subsets() {
        assert!(is_subset(&[1, 3], &[0, 1, 2, 3]));
        assert!(!is_subset(&[1, 4], &[0, 1, 2, 3]));
        assert!(is_subset(&[], &[2]));
        assert_eq!(signature(&[1, 3]) & !signature(&[0, 1, 2, 3]), 0);
    }
}
