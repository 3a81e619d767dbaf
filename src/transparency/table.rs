//! The tabular pixel mask (thesis §4.3) with neighbourhood error compensation (§4.3.3). Pure
//! functions of opacities and priorities over logical sub-sample indices.
//!
//! The table's rows are sub-sets of the mask's sub-samples. Adding a mask of opacity a splits each
//! row of the last generation (the thesis's rows *start*..*end*) into a filled child of
//! round(a * count + carried error) sub-samples and an empty child of the rest; the rounding error
//! is carried to the next row split, and a child with no sub-sample is abandoned, so a generation
//! never holds more rows than sub-samples. The new mask is the union of the filled children.
//!
//! Every row of the last generation lies wholly inside or wholly outside each earlier mask (rows
//! only ever get split), so the order in which rows are split decides where rounding errors land.
//! Neighbourhood error compensation orders the splits so that the errors cancel inside the filled
//! (and inside the empty) regions of the K highest-priority, i.e. nearest, objects: rows inside the
//! filled regions of all K first, then of the first K-1, ..., then the same for the empty regions.
//! Table order without compensation is the plain tabular mask; a random order is Mulder's pixel
//! tree with the sequential error carry (its empty nodes, which hold no sub-sample, are not kept).

use super::Mask;

/// One row entry: a sub-set of sub-samples and whether it is filled in the mask that made it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Row {
    pub pixels: Vec<u16>,
    pub filled: bool,
}

/// The order in which a new mask splits the last generation's rows.
#[derive(Clone, Copy, Debug)]
pub enum SplitOrder<'a> {
    /// Table order (the plain tabular pixel mask).
    Table,
    /// Neighbourhood error compensation: indices of earlier masks, highest priority (nearest) first.
    Priorities(&'a [usize]),
    /// An explicit permutation of the rows (the pixel tree's random order).
    Given(&'a [usize]),
}

pub struct MaskTable {
    n: usize,
    /// The last generation (the table's rows *start*..*end*); earlier generations are never read
    /// again, so only their count is kept.
    rows: Vec<Row>,
    row_entries: usize,
    masks: Vec<Mask>,
    /// Accumulated error after each row split of the last mask, in split order (for inspection).
    errors: Vec<f64>,
}

impl MaskTable {
    /// A table for masks of `n` sub-samples (1..=1024): one empty row holding all of them.
    pub fn new(n: usize) -> MaskTable {
        let n = n.clamp(1, super::mask::MAX_SUBSAMPLES);
        MaskTable {
            n,
            rows: vec![Row { pixels: (0..n as u16).collect(), filled: false }],
            row_entries: 1,
            masks: Vec::new(),
            errors: Vec::new(),
        }
    }

    pub fn size(&self) -> usize {
        self.n
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
        let order: Vec<usize> = match order {
            SplitOrder::Table => (0..self.rows.len()).collect(),
            SplitOrder::Given(o) if is_permutation(o, self.rows.len()) => o.to_vec(),
            SplitOrder::Given(_) => (0..self.rows.len()).collect(),
            SplitOrder::Priorities(p) => {
                let masks: Vec<&Mask> = p.iter().filter_map(|&i| self.masks.get(i)).collect();
                let first: Vec<usize> = self.rows.iter().map(|r| usize::from(r.pixels[0])).collect();
                compensation_order(&first, &masks)
            }
        };
        let mut take = vec![0usize; self.rows.len()];
        let mut carried = 0.0f64;
        self.errors.clear();
        for &r in &order {
            let count = self.rows[r].pixels.len();
            let want = alpha * count as f64 + carried;
            let k = (want + 0.5).floor().clamp(0.0, count as f64);
            carried = want - k;
            take[r] = k as usize;
            self.errors.push(carried);
        }
        let mut next = Vec::with_capacity(self.rows.len() * 2);
        let mut mask = Mask::EMPTY;
        for (row, k) in self.rows.iter().zip(take) {
            let (filled, empty) = row.pixels.split_at(k);
            for &p in filled {
                mask.insert(usize::from(p));
            }
            for (pixels, filled) in [(filled, true), (empty, false)] {
                if !pixels.is_empty() {
                    next.push(Row { pixels: pixels.to_vec(), filled });
                }
            }
        }
        self.row_entries += next.len();
        self.rows = next;
        self.masks.push(mask);
        mask
    }
}

fn is_permutation(order: &[usize], len: usize) -> bool {
    let mut seen = vec![false; len];
    order.len() == len && order.iter().all(|&i| i < len && !std::mem::replace(&mut seen[i], true))
}

/// Neighbourhood error compensation's split order (thesis §4.3.3, Table 1) for rows represented
/// by one sub-sample each (`first[r]`: rows lie wholly inside or outside each mask) and priority
/// masks, highest first. Rows in the filled region of priorities 0..=i for the largest i come
/// first (F^i before F^(i-1) \ F^i ...), then rows of the empty regions likewise; ties keep table
/// order.
pub fn compensation_order(first: &[usize], priorities: &[&Mask]) -> Vec<usize> {
    let key = |r: usize| {
        let p = first[r];
        let Some(top) = priorities.first() else { return (0, 0) };
        let filled = top.contains(p);
        let run = priorities.iter().take_while(|m| m.contains(p) == filled).count();
        (usize::from(!filled), usize::MAX - run)
    };
    let mut order: Vec<usize> = (0..first.len()).collect();
    order.sort_by_key(|&r| key(r));
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figure_12() {
        let mut t = MaskTable::new(8);
        let m1 = t.add(0.5, SplitOrder::Table);
        assert_eq!(m1, Mask::from_indices(0..4));
        assert_eq!(
            t.rows(),
            &[Row { pixels: vec![0, 1, 2, 3], filled: true }, Row { pixels: vec![4, 5, 6, 7], filled: false }]
        );
        assert_eq!(t.errors(), &[0.0]);
        let m2 = t.add(0.125, SplitOrder::Table);
        assert_eq!(m2, Mask::from_indices([0]));
        // The first row's split leaves -0.5, so the second row's filled child is abandoned.
        assert_eq!(t.errors(), &[-0.5, 0.0]);
        assert_eq!(
            t.rows(),
            &[
                Row { pixels: vec![0], filled: true },
                Row { pixels: vec![1, 2, 3], filled: false },
                Row { pixels: vec![4, 5, 6, 7], filled: false }
            ]
        );
        assert_eq!(t.row_entries(), 1 + 2 + 3);
    }

    #[test]
    fn table_1_split_order() {
        // Sixteen one-sub-sample rows; priorities mask_2, mask_1, mask_4 of thesis Figure 13.
        let rf2 = Mask::from_indices([4, 5, 6, 7, 12, 13, 14, 15]);
        let rf1 = Mask::from_indices(8..16);
        let rf4 = Mask::from_indices((0..16).filter(|i| i % 2 == 1));
        let first: Vec<usize> = (0..16).collect();
        let order = compensation_order(&first, &[&rf2, &rf1, &rf4]);
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
