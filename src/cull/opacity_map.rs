//! The opacity map (thesis §3.3.1-3.3.2): a summed-area table of the occluders' coverage bitmap,
//! so the covered pixels of any rectangle take four look-ups.
//!
//! - Culling pixels; the table has the extra zero row and column.
//! - Rows here run top to bottom (the thesis counts from the lower left; the counts are the same).

use super::rect::PixelRect;

/// `Op(x, y)` = covered pixels in columns `1..=x`, rows `1..=y` (1-based; row and column 0 are 0).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OpacityMap {
    pub width: usize,
    pub height: usize,
    op: Vec<u32>,
}

impl OpacityMap {
    /// Builds the table from a `width x height` bitmap (non-zero = covered), row-major.
    pub fn new(bitmap: &[u8], width: usize, height: usize) -> OpacityMap {
        let stride = width + 1;
        let mut op = vec![0u32; stride * (height + 1)];
        for y in 0..height {
            let mut row = 0u32;
            for x in 0..width {
                row += u32::from(bitmap[y * width + x] != 0);
                op[(y + 1) * stride + x + 1] = op[y * stride + x + 1] + row;
            }
        }
        OpacityMap { width, height, op }
    }

    /// `Op(x, y)`.
    pub fn op(&self, x: usize, y: usize) -> u32 {
        self.op[y * (self.width + 1) + x]
    }

    /// Covered pixels in `r`: the thesis's opacity function OPF(x1, x2, y1, y2) over
    /// `x1 < x <= x2`, `y1 < y <= y2` in its 1-based pixels is `covered` of the 0-based
    /// `PixelRect { x0: x1, y0: y1, x1: x2 - 1, y1: y2 - 1 }`.
    pub fn covered(&self, r: PixelRect) -> u32 {
        let (x1, x2, y1, y2) = (r.x0, r.x1 + 1, r.y0, r.y1 + 1);
        (self.op(x1, y1) + self.op(x2, y2)) - (self.op(x1, y2) + self.op(x2, y1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The thesis's OPF(2, 5, 1, 5): 1-based columns 3..=5, rows 2..=5.
    const OPF_2_5_1_5: PixelRect = PixelRect { x0: 2, y0: 1, x1: 4, y1: 4 };

    /// A bitmap whose opacity values match the thesis's Figure 5 worked example (lower-left origin
    /// there; here row index 0 is the thesis's row 1).
    #[test]
    fn thesis_figure_5() {
        #[rustfmt::skip]
        let bitmap: [u8; 25] = [
            1, 1, 1, 1, 1, // row 1
            0, 1, 1, 0, 1, // row 2
            1, 0, 0, 1, 0, // row 3
            1, 1, 0, 0, 1, // row 4
            0, 1, 0, 1, 1, // row 5
        ];
        let m = OpacityMap::new(&bitmap, 5, 5);
        // The thesis's region 2 < x <= 5, 1 < y <= 5 (12 pixels) is not wholly covered.
        let brute: u32 = (1..5).flat_map(|y| (2..5).map(move |x| u32::from(bitmap[y * 5 + x]))).sum();
        assert_eq!(m.covered(OPF_2_5_1_5), brute);
        assert!(m.covered(OPF_2_5_1_5) < 12);
    }

    #[test]
    fn thesis_figure_5_values() {
        // Op values of the thesis's example give OPF(2, 5, 1, 5) = 2 - 9 - 5 + 18 = 6.
        let (op21, op25, op51, op55) = (2i64, 9, 5, 18);
        assert_eq!(op21 - op25 - op51 + op55, 6);
        // A bitmap with exactly those values: 6 of the 12 pixels covered.
        #[rustfmt::skip]
        let bitmap: [u8; 25] = [
            1, 1, 1, 1, 1,
            1, 1, 1, 1, 0,
            1, 1, 0, 1, 0,
            1, 0, 1, 0, 1,
            1, 1, 0, 0, 1,
        ];
        let m = OpacityMap::new(&bitmap, 5, 5);
        assert_eq!(
            (m.op(2, 1) as i64, m.op(2, 5) as i64, m.op(5, 1) as i64, m.op(5, 5) as i64),
            (op21, op25, op51, op55)
        );
        assert_eq!(m.covered(OPF_2_5_1_5), 6);
    }

    #[test]
    fn matches_brute_force_on_random_bitmaps() {
        let mut rng = crate::rng::XorShift(12345);
        let mut rand = || rng.next_u64();
        for _ in 0..50 {
            let (w, h) = (1 + rand() as usize % 40, 1 + rand() as usize % 40);
            let bitmap: Vec<u8> = (0..w * h).map(|_| (rand() % 3 == 0) as u8).collect();
            let m = OpacityMap::new(&bitmap, w, h);
            for _ in 0..50 {
                let (mut x0, mut x1) = (rand() as usize % w, rand() as usize % w);
                let (mut y0, mut y1) = (rand() as usize % h, rand() as usize % h);
                if x0 > x1 {
                    std::mem::swap(&mut x0, &mut x1);
                }
                if y0 > y1 {
                    std::mem::swap(&mut y0, &mut y1);
                }
                let brute: u32 = (y0..=y1)
                    .flat_map(|y| (x0..=x1).map(move |x| (y, x)))
                    .map(|(y, x)| u32::from(bitmap[y * w + x]))
                    .sum();
                assert_eq!(m.covered(PixelRect::new(x0, y0, x1, y1)), brute);
            }
        }
    }
}
