//! Rectangles of culling pixels: the one rectangle type of the culler, from the projection of a
//! box to the opacity map's look-ups.
//!
//! - Culling pixels, x right, y down.
//! - Inclusive on all four sides (columns `x0..=x1`, rows `y0..=y1`), so never empty.

/// Columns `x0..=x1` and rows `y0..=y1` of a raster (so never empty).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    pub x0: usize,
    pub y0: usize,
    pub x1: usize,
    pub y1: usize,
}

impl PixelRect {
    pub fn new(x0: usize, y0: usize, x1: usize, y1: usize) -> PixelRect {
        debug_assert!(x0 <= x1 && y0 <= y1, "empty rectangle {x0}..={x1} x {y0}..={y1}");
        PixelRect { x0, y0, x1, y1 }
    }

    /// Its pixels.
    pub fn area(&self) -> usize {
        (self.x1 - self.x0 + 1) * (self.y1 - self.y0 + 1)
    }

    /// Its middle pixel (rounded toward the top left).
    pub fn centre(&self) -> (usize, usize) {
        ((self.x0 + self.x1) / 2, (self.y0 + self.y1) / 2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_counts_both_edges() {
        assert_eq!(PixelRect::new(2, 1, 2, 1).area(), 1);
        assert_eq!(PixelRect::new(0, 0, 3, 1).area(), 8);
        assert_eq!(PixelRect::new(1, 2, 4, 6).centre(), (2, 4));
    }
}
