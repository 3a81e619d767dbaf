//! The sparse depth map (thesis §3.3.3-3.3.4) over the occluder depth map: a depth comparison over
//! a row visits only the row's local peaks instead of every pixel.
//!
//! - Culling pixels; depth = NDC z, 0 near .. 1 far, larger is farther.
//! - Per row, each pixel stores how far to step right to the next local peak, so a comparison
//!   visits the peaks (and the row's ends) and still sees the row's farthest occluder depth.

use super::rect::PixelRect;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct SparseDepth {
    pub width: usize,
    pub height: usize,
    /// `step[i]`: distance from pixel `i` to the first peak at or right of it in its row, where a
    /// peak is a pixel deeper than its right neighbour, or the last pixel of the row. Between a pixel
    /// and that peak the depth never decreases, so the peak holds their maximum.
    step: Vec<u16>,
}

impl SparseDepth {
    pub fn new(depth: &[f32], width: usize, height: usize) -> SparseDepth {
        let mut step = vec![0u16; width * height];
        for y in 0..height {
            let row = &depth[y * width..(y + 1) * width];
            let out = &mut step[y * width..(y + 1) * width];
            // Right to left: the distance to the next peak grows by one until a peak resets it.
            let mut next = 0u16;
            for x in (0..width).rev() {
                let peak = x + 1 == width || row[x] > row[x + 1];
                next = if peak { 0 } else { next.saturating_add(1) };
                out[x] = next;
            }
        }
        SparseDepth { width, height, step }
    }

    /// The farthest depth in row `y`, columns `x0..=x1`, visiting only the peaks in between.
    #[cfg(test)]
    pub fn row_max(&self, depth: &[f32], y: usize, x0: usize, x1: usize) -> f32 {
        let row = y * self.width;
        let mut best = f32::NEG_INFINITY;
        let mut x = x0;
        loop {
            let peak = x + self.step[row + x] as usize;
            if peak >= x1 {
                // Non-decreasing from x to beyond x1: x1 holds the rest's maximum.
                return best.max(depth[row + x1]);
            }
            best = best.max(depth[row + peak]);
            x = peak + 1;
        }
    }

    /// Is `z` behind every depth in the inclusive rectangle? Stops at the first depth not in front.
    pub fn all_in_front_of(&self, depth: &[f32], r: PixelRect, z: f32) -> bool {
        let PixelRect { x0, y0, x1, y1 } = r;
        (y0..=y1).all(|y| {
            let row = y * self.width;
            let mut x = x0;
            loop {
                let peak = x + self.step[row + x] as usize;
                if peak >= x1 {
                    return depth[row + x1] < z;
                }
                if depth[row + peak] >= z {
                    return false;
                }
                x = peak + 1;
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn row_maxima_match_brute_force() {
        let mut rng = crate::rng::XorShift(99);
        let mut rand = || rng.next_u64();
        for _ in 0..100 {
            let (w, h) = (1 + rand() as usize % 50, 1 + rand() as usize % 6);
            // Smooth runs with plateaus and jumps, like occluder depths.
            let mut depth = Vec::with_capacity(w * h);
            for _ in 0..h {
                let mut d = (rand() % 100) as f32 / 100.0;
                for _ in 0..w {
                    match rand() % 4 {
                        0 => {}
                        1 => d += 0.01,
                        2 => d -= 0.01,
                        _ => d = (rand() % 100) as f32 / 100.0,
                    }
                    depth.push(d);
                }
            }
            let s = SparseDepth::new(&depth, w, h);
            for _ in 0..40 {
                let y = rand() as usize % h;
                let (mut x0, mut x1) = (rand() as usize % w, rand() as usize % w);
                if x0 > x1 {
                    std::mem::swap(&mut x0, &mut x1);
                }
                let brute = depth[y * w + x0..=y * w + x1].iter().copied().fold(f32::NEG_INFINITY, f32::max);
                assert_eq!(s.row_max(&depth, y, x0, x1), brute);
                let z = (rand() % 110) as f32 / 100.0;
                assert_eq!(s.all_in_front_of(&depth, PixelRect::new(x0, y, x1, y), z), brute < z);
            }
        }
    }

    #[test]
    fn steps_reach_the_peaks() {
        // Rising to a peak at 3, falling, rising to the end.
        let d = [0.1, 0.2, 0.2, 0.5, 0.3, 0.4, 0.6];
        let s = SparseDepth::new(&d, 7, 1);
        assert_eq!(s.step, [3, 2, 1, 0, 2, 1, 0]);
        assert_eq!(s.row_max(&d, 0, 4, 5), 0.4);
    }
}
