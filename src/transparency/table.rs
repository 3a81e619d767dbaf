//! The tabular pixel mask (thesis §4.3) with neighbourhood error compensation (§4.3.3).
//!
//! - Pure functions of opacities and priorities over logical sub-sample indices.
//! - The table's rows are sub-sets of the mask's sub-samples. Adding a mask of opacity a splits
//!   each row of the last generation (the thesis's rows *start*..*end*) into a filled child of
//!   round(a * count + carried error) sub-samples and an empty child of the rest; the rounding
//!   error is carried to the next row split, and a child with no sub-sample is abandoned, so a
//!   generation never holds more rows than sub-samples. The new mask is the union of the filled
//!   children.
//! - Every row of the last generation lies wholly inside or wholly outside each earlier mask
//!   (rows only ever get split), so the order in which rows are split decides where rounding
//!   errors land.
//! - Neighbourhood error compensation orders the splits so that the errors cancel inside the
//!   filled (and inside the empty) regions of the K highest-priority, i.e. nearest, objects: rows
//!   inside the filled regions of all K first, then of the first K-1, ..., then the same for the
//!   empty regions.
//! - With the priorities in depth order, each group of empty rows is what one earlier mask shows
//!   (its *owner*), so the new mask's rounding error stays within a sub-sample for each level.
//! - Masks made out of depth order ([`SplitOrder::Neighbours`]) get the same from the union of the
//!   nearer masks as the top priority, followed by the K nearest farther masks.
//! - Table order without compensation is the plain tabular mask; a random order is Mulder's pixel
//!   tree with the sequential error carry (its empty nodes, which hold no sub-sample, are not
//!   kept).

use super::Mask;

/// One row entry: a sub-set of sub-samples and whether it is filled in the mask that made it.
/// A row's filled child takes the first sub-samples of its list and the empty child the rest, and
/// the first row lists `0..n` in order, so every row's list is a run of consecutive indices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Row {
    pub start: u16,
    pub count: u16,
    pub filled: bool,
}

impl Row {
    /// The row's sub-samples.
    pub fn pixels(&self) -> std::ops::Range<usize> {
        usize::from(self.start)..usize::from(self.start) + usize::from(self.count)
    }
}

/// The order in which a new mask splits the last generation's rows.
#[derive(Clone, Copy, Debug)]
pub enum SplitOrder<'a> {
    /// Table order (the plain tabular pixel mask).
    Table,
    /// Neighbourhood error compensation: indices of earlier masks, highest priority (nearest) first.
    Priorities(&'a [usize]),
    /// Compensation as `Priorities`, with the rows of equal rank split in an order shuffled by
    /// `seed`: for masks after the K nearest, which all share those priorities and would otherwise
    /// split in one order, and so come out identical at equal opacities (and hide each other).
    Shuffled { priorities: &'a [usize], seed: u64 },
    /// Compensation around the new mask's depth, for masks generated out of depth order: the
    /// union of every earlier mask `nearer` than the new one counts as the highest priority (its
    /// empty rows are what the new mask shows), then the earlier masks just `farther` than it,
    /// nearest first (whose visible rows it covers). The rows each stacking level shows are then
    /// split in one run, so every level's rounding error stays within a sub-sample per mask.
    Neighbours { nearer: &'a [usize], farther: &'a [usize] },
    /// An explicit permutation of the rows (the pixel tree's random order).
    Given(&'a [usize]),
}

#[derive(Debug)]
pub struct MaskTable {
    n: usize,
    /// The last generation (the table's rows *start*..*end*); earlier generations are never read
    /// again, so only their count is kept.
    rows: Vec<Row>,
    row_entries: usize,
    masks: Vec<Mask>,
    /// Accumulated error after each row split of the last mask, in split order (for inspection).
    errors: Vec<f64>,
    /// Scratch buffers reused by every mask: split order, the compensation ranks' word sets, row
    /// by start and where each rank ends, priority masks, filled counts, the next generation.
    order: Vec<usize>,
    words: Vec<u64>,
    row_at: Vec<u16>,
    ends: Vec<usize>,
    priority: Vec<Mask>,
    take: Vec<u16>,
    next: Vec<Row>,
}

/// Clones the table, not its scratch buffers; `clone_from` reuses the target's allocations.
impl Clone for MaskTable {
    fn clone(&self) -> MaskTable {
        let mut table = MaskTable::new(self.n);
        table.clone_from(self);
        table
    }

    fn clone_from(&mut self, source: &MaskTable) {
        self.n = source.n;
        self.rows.clone_from(&source.rows);
        self.row_entries = source.row_entries;
        self.masks.clone_from(&source.masks);
        self.errors.clone_from(&source.errors);
    }
}

impl MaskTable {
    /// A table for masks of `n` sub-samples (1..=1024): one empty row holding all of them.
    pub fn new(n: usize) -> MaskTable {
        let n = n.clamp(1, super::mask::MAX_SUBSAMPLES);
        MaskTable {
            n,
            rows: vec![Row { start: 0, count: n as u16, filled: false }],
            row_entries: 1,
            masks: Vec::new(),
            errors: Vec::new(),
            order: Vec::new(),
            words: Vec::new(),
            row_at: Vec::new(),
            ends: Vec::new(),
            priority: Vec::new(),
            take: Vec::new(),
            next: Vec::new(),
        }
    }

    pub fn size(&self) -> usize {
        self.n
    }

    /// Whether every row holds a single sub-sample. From then on the rows stay as they are (in
    /// sub-sample order), so a new mask depends on its opacity, split order and priorities only,
    /// not on the masks added before it other than those priorities.
    pub fn is_saturated(&self) -> bool {
        self.rows.len() == self.n
    }

    /// The last generation of rows.
    pub fn rows(&self) -> &[Row] {
        &self.rows
    }

    /// Row entries the table has held, the first one included (thesis Table 2).
    pub fn row_entries(&self) -> usize {
        self.row_entries
    }

    pub fn masks(&self) -> &[Mask] {
        &self.masks
    }

    pub fn into_masks(self) -> Vec<Mask> {
        self.masks
    }

    /// The accumulated error after each row split of the last mask, in split order.
    pub fn errors(&self) -> &[f64] {
        &self.errors
    }

    /// Adds a mask of opacity `alpha` and returns it.
    pub fn add(&mut self, alpha: f32, order: SplitOrder) -> Mask {
        let alpha = f64::from(alpha.clamp(0.0, 1.0));
        self.split_order(order);
        let rows = self.rows.len();
        self.take.clear();
        self.take.resize(rows, 0);
        let mut carried = 0.0f64;
        self.errors.clear();
        for &r in &self.order {
            let count = self.rows[r].count;
            let want = alpha * f64::from(count) + carried;
            let k = (want + 0.5).floor().clamp(0.0, f64::from(count));
            carried = want - k;
            self.take[r] = k as u16;
            self.errors.push(carried);
        }
        self.next.clear();
        let mut mask = Mask::EMPTY;
        for (row, &k) in self.rows.iter().zip(&self.take) {
            mask.insert_range(usize::from(row.start)..usize::from(row.start + k));
            for (start, count, filled) in [(row.start, k, true), (row.start + k, row.count - k, false)] {
                if count > 0 {
                    self.next.push(Row { start, count, filled });
                }
            }
        }
        self.row_entries += self.next.len();
        std::mem::swap(&mut self.rows, &mut self.next);
        self.masks.push(mask);
        mask
    }

    /// The mask [`add`](Self::add) would make on this saturated table (every row one sub-sample;
    /// see [`is_saturated`](Self::is_saturated)), without adding it: the table is left as it was.
    pub fn saturated_mask(&mut self, alpha: f32, order: SplitOrder) -> Mask {
        debug_assert!(self.is_saturated());
        let alpha = f64::from(alpha.clamp(0.0, 1.0));
        self.split_order(order);
        let (mut carried, mut mask) = (0.0f64, Mask::EMPTY);
        for &r in &self.order {
            let want = alpha + carried;
            let k = (want + 0.5).floor().clamp(0.0, 1.0);
            carried = want - k;
            if k > 0.0 {
                mask.insert(usize::from(self.rows[r].start));
            }
        }
        mask
    }

    /// The order in which the next mask splits the rows, into `self.order`.
    fn split_order<'a>(&mut self, order: SplitOrder<'a>) {
        let rows = self.rows.len();
        self.priority.clear();
        let masks = &self.masks;
        let pick = |ids: &'a [usize]| ids.iter().filter_map(move |&i| masks.get(i).copied());
        match order {
            SplitOrder::Priorities(p) | SplitOrder::Shuffled { priorities: p, .. } => self.priority.extend(pick(p)),
            SplitOrder::Neighbours { nearer, farther } => {
                self.priority.push(pick(nearer).fold(Mask::EMPTY, |u, m| u.union(&m)));
                self.priority.extend(pick(farther));
            }
            SplitOrder::Table | SplitOrder::Given(_) => {}
        }
        let seed = match order {
            SplitOrder::Shuffled { seed, .. } => Some(seed),
            _ => None,
        };
        self.order.clear();
        match order {
            SplitOrder::Given(o) if is_permutation(o, rows) => self.order.extend_from_slice(o),
            _ if !self.priority.is_empty() => {
                let scratch = (&mut self.order, &mut self.ends, &mut self.words, &mut self.row_at);
                compensation_ranks(&self.rows, &self.priority, self.n, scratch);
                if let Some(seed) = seed {
                    let mut rng = crate::rng::XorShift::seeded(seed);
                    let mut from = 0;
                    for &end in &self.ends {
                        rng.shuffle(&mut self.order[from..end]);
                        from = end;
                    }
                }
            }
            _ => self.order.extend(0..rows),
        }
    }
}

/// `rows` (sorted by start, each wholly inside or outside every priority mask) into `order` by
/// neighbourhood error compensation's rank among the priority masks, highest first: rows in the
/// filled region of priorities 0..=i for the largest i come first (F^i before F^(i-1) \ F^i ...),
/// then rows of the empty regions likewise (thesis §4.3.3, Table 1); ties in table order, with
/// `ends[k]` where rank k ends. The sets of sub-samples of each rank are found a word at a time,
/// and each set's row starts listed in order.
/// `words` and `row_at` are scratch: the agreement sets and row starts, and the row at a start.
fn compensation_ranks(
    rows: &[Row],
    priorities: &[Mask],
    n: usize,
    (order, ends, words, row_at): (&mut Vec<usize>, &mut Vec<usize>, &mut Vec<u64>, &mut Vec<u16>),
) {
    let (len, nw) = (priorities.len(), n.div_ceil(64));
    // agree[i]: sub-samples where priorities 0..=i all match the first (in or out); row starts.
    words.clear();
    words.resize((len + 1) * nw, 0);
    let (agree, starts) = words.split_at_mut(len * nw);
    let top = &priorities[0];
    for w in 0..nw {
        let mut same = u64::MAX;
        for (i, m) in priorities.iter().enumerate() {
            same &= !(m.word(w) ^ top.word(w));
            agree[i * nw + w] = same;
        }
    }
    row_at.resize(n, 0);
    for (r, row) in rows.iter().enumerate() {
        starts[usize::from(row.start) / 64] |= 1 << (row.start % 64);
        row_at[usize::from(row.start)] = r as u16;
    }
    order.clear();
    ends.clear();
    for filled in [true, false] {
        // Rank len - run on each side: the longest runs of agreement first.
        for run in (0..=len).rev() {
            for w in (0..nw).filter(|_| run > 0) {
                let side = if filled { top.word(w) } else { !top.word(w) };
                let longer = if run < len { agree[run * nw + w] } else { 0 };
                let mut set = side & agree[(run - 1) * nw + w] & !longer & starts[w];
                while set != 0 {
                    order.push(usize::from(row_at[w * 64 + set.trailing_zeros() as usize]));
                    set &= set - 1;
                }
            }
            ends.push(order.len());
        }
    }
}

fn is_permutation(order: &[usize], len: usize) -> bool {
    let mut seen = vec![false; len];
    order.len() == len && order.iter().all(|&i| i < len && !std::mem::replace(&mut seen[i], true))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference for [`compensation_ranks`], one row at a time: the rank of a row represented
    /// by its sub-sample `p` among priority masks, highest first.
    fn split_key(p: usize, priorities: &[Mask]) -> usize {
        let Some(top) = priorities.first() else { return 0 };
        let filled = top.contains(p);
        let run = priorities.iter().take_while(|m| m.contains(p) == filled).count();
        usize::from(!filled) * (priorities.len() + 1) + priorities.len() - run
    }

    /// The split order of rows represented by one sub-sample each (`first[r]`), for priority masks
    /// highest first; ties keep table order.
    fn compensation_order(first: &[usize], priorities: &[Mask]) -> Vec<usize> {
        let mut keyed: Vec<(usize, usize)> =
            first.iter().enumerate().map(|(r, &p)| (split_key(p, priorities), r)).collect();
        keyed.sort_unstable();
        keyed.into_iter().map(|(_, r)| r).collect()
    }

    #[test]
    fn figure_12() {
        let mut t = MaskTable::new(8);
        let m1 = t.add(0.5, SplitOrder::Table);
        assert_eq!(m1, Mask::from_indices(0..4));
        assert_eq!(t.rows(), &[Row { start: 0, count: 4, filled: true }, Row { start: 4, count: 4, filled: false }]);
        assert_eq!(t.errors(), &[0.0]);
        let m2 = t.add(0.125, SplitOrder::Table);
        assert_eq!(m2, Mask::from_indices([0]));
        // The first row's split leaves -0.5, so the second row's filled child is abandoned.
        assert_eq!(t.errors(), &[-0.5, 0.0]);
        assert_eq!(
            t.rows(),
            &[
                Row { start: 0, count: 1, filled: true },
                Row { start: 1, count: 3, filled: false },
                Row { start: 4, count: 4, filled: false }
            ]
        );
        assert_eq!(t.rows()[1].pixels(), 1..4);
        assert_eq!(t.row_entries(), 1 + 2 + 3);
    }

    #[test]
    fn table_1_split_order() {
        // Sixteen one-sub-sample rows; priorities mask_2, mask_1, mask_4 of thesis Figure 13.
        let rf2 = Mask::from_indices([4, 5, 6, 7, 12, 13, 14, 15]);
        let rf1 = Mask::from_indices(8..16);
        let rf4 = Mask::from_indices((0..16).filter(|i| i % 2 == 1));
        let first: Vec<usize> = (0..16).collect();
        let order = compensation_order(&first, &[rf2, rf1, rf4]);
        assert_eq!(order, vec![13, 15, 12, 14, 4, 5, 6, 7, 0, 2, 1, 3, 8, 9, 10, 11]);
        // No priorities: table order.
        assert_eq!(compensation_order(&first, &[]), first);
    }

    #[test]
    fn table_2_row_entries() {
        for (n, m, entries) in [(64, 16, 767), (1024, 24, 16383), (1024, 10, 2047), (64, 6, 127)] {
            let mut t = MaskTable::new(n);
            for _ in 0..m {
                t.add(0.5, SplitOrder::Table);
            }
            assert_eq!(t.row_entries(), entries, "n = {n}, m = {m}");
        }
    }

    #[test]
    fn first_order_exact_for_every_alpha() {
        let mut rng = crate::rng::XorShift::seeded(11);
        for n in [8, 64, 256] {
            let mut t = MaskTable::new(n);
            for step in 0..=200 {
                let alpha = step as f32 / 200.0;
                let prior: Vec<usize> = (0..t.masks().len().min(6)).collect();
                let order = match rng.below(3) {
                    0 => SplitOrder::Table,
                    1 => SplitOrder::Priorities(&prior),
                    _ => SplitOrder::Table,
                };
                let m = t.add(alpha, order);
                let exact = alpha as f64 * n as f64;
                assert!(
                    (m.count() as f64 - exact).abs() <= 0.5 + 1e-9,
                    "n {n} alpha {alpha}: {} sub-samples",
                    m.count()
                );
                assert!(t.rows().len() <= n);
            }
        }
    }

    #[test]
    fn neighbours_keep_every_level_within_a_sub_sample_per_mask() {
        // Masks made in random depth order: each new one must take round(alpha * count) of what
        // each level shows, within one sub-sample, for its own level and every farther neighbour's.
        let mut rng = crate::rng::XorShift::seeded(3);
        for _ in 0..200 {
            let n = [16, 64, 256][rng.below(3)];
            let mut t = MaskTable::new(n);
            let mut depths: Vec<f32> = Vec::new();
            for _ in 0..10 {
                let (alpha, depth) = (rng.unit(), rng.unit());
                let mut farther: Vec<usize> = (0..depths.len()).filter(|&i| depths[i] > depth).collect();
                farther.sort_by(|&a, &b| depths[a].total_cmp(&depths[b]));
                let nearer: Vec<usize> = (0..depths.len()).filter(|&i| depths[i] <= depth).collect();
                // What each level shows before the new mask: j's free sub-samples, then each farther one's.
                let cover = |ids: &[usize]| ids.iter().fold(Mask::EMPTY, |u, &i| u.union(&t.masks()[i]));
                let mut shows = vec![Mask::full(n).minus(&cover(&nearer))];
                for (x, &f) in farther.iter().enumerate() {
                    let front = cover(&nearer).union(&cover(&farther[..x]));
                    shows.push(t.masks()[f].minus(&front));
                }
                let m = t.add(alpha, SplitOrder::Neighbours { nearer: &nearer, farther: &farther });
                for (x, show) in shows.iter().enumerate() {
                    let taken = show.count() - show.minus(&m).count();
                    let want = f64::from(alpha) * show.count() as f64;
                    assert!(
                        (taken as f64 - want).abs() <= 1.0 + 1e-9,
                        "level {x}: took {taken} of {}, alpha {alpha}",
                        show.count()
                    );
                }
                depths.push(depth);
            }
        }
    }

    #[test]
    fn ranks_found_a_word_at_a_time_sort_as_the_keys_do() {
        let mut rng = crate::rng::XorShift::seeded(3);
        for n in [16, 64, 100, 1024] {
            let mut t = MaskTable::new(n);
            for _ in 0..6 {
                let alpha = rng.unit();
                t.add(alpha, SplitOrder::Table);
                let priorities: Vec<Mask> = t.masks().iter().rev().copied().collect();
                let first: Vec<usize> = t.rows().iter().map(|r| usize::from(r.start)).collect();
                let (mut order, mut ends, mut words, mut row_at) = Default::default();
                compensation_ranks(t.rows(), &priorities, n, (&mut order, &mut ends, &mut words, &mut row_at));
                assert_eq!(order, compensation_order(&first, &priorities), "n = {n}");
                let keys: Vec<usize> = order.iter().map(|&r| split_key(first[r], &priorities)).collect();
                for (rank, w) in ends.windows(2).enumerate() {
                    assert!(keys[w[0]..w[1]].iter().all(|&k| k == rank + 1), "n = {n}: rank {}", rank + 1);
                }
            }
        }
    }

    #[test]
    fn saturated_mask_is_the_mask_add_would_make() {
        let mut rng = crate::rng::XorShift::seeded(5);
        for n in [16, 64] {
            let mut t = MaskTable::new(n);
            while !t.is_saturated() {
                t.add(0.5, SplitOrder::Table);
            }
            let priorities: Vec<usize> = (0..t.masks().len().min(5)).collect();
            for seed in 0..20 {
                let (alpha, order) = (rng.unit(), SplitOrder::Shuffled { priorities: &priorities, seed });
                let (rows, masks) = (t.rows().to_vec(), t.masks().len());
                let mask = t.saturated_mask(alpha, order);
                assert_eq!((t.rows(), t.masks().len()), (rows.as_slice(), masks), "the table is left as it was");
                let mut added = t.clone();
                assert_eq!(mask, added.add(alpha, order), "n = {n}, alpha {alpha}");
            }
        }
    }

    #[test]
    fn within_capacity_stacking_is_exact() {
        // Up to log2(n) masks of opacity 1/2 are exact binary partitions: every stacking level right.
        let mut t = MaskTable::new(64);
        for _ in 0..6 {
            t.add(0.5, SplitOrder::Table);
        }
        let mut covered = Mask::EMPTY;
        for (i, m) in t.masks().iter().enumerate() {
            assert_eq!(m.minus(&covered).count(), 64 >> (i + 1));
            covered = covered.union(m);
        }
    }
}
