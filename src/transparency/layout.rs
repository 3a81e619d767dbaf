//! Where logical sub-samples lie: the renderer reaches n = 4P sub-samples with P passes of 4x
//! MSAA.
//!
//! - Positions are in pixel units, 0..1 from the pixel's top-left corner, y down.
//! - Bit b of a GPU mask is MSAA sample b % 4 of pass b / 4.
//! - Pass p draws the faded organs shifted by [`pass_offset`], so the P passes sample 4P distinct
//!   positions (at 64, spread over the pixel and at most a sixteenth of a pixel beyond it).
//! - The opaque organs are drawn once, unshifted; their depth and colour serve every pass.
//! - Logical sub-sample i (the masks' index) goes to pass `radical_inverse(i % P)` and sample
//!   `(i / P) % 4`, so that any run of logical sub-samples the mask table hands out is spread
//!   evenly over the passes, and the first k passes alone show each mask's coverage to within one
//!   sub-sample: what progressive refinement shows before the last pass.

use glam::Vec2;

/// Standard 4x MSAA sample positions (Vulkan, D3D), pixel units.
pub const MSAA4: [Vec2; 4] =
    [Vec2::new(0.375, 0.125), Vec2::new(0.875, 0.375), Vec2::new(0.125, 0.625), Vec2::new(0.625, 0.875)];

/// The 4x4 ordered-dither (Bayer) matrix: pass p takes the cell holding p, so the first passes
/// spread over the cell as evenly as any.
const BAYER4: [[usize; 4]; 4] = [[0, 8, 2, 10], [12, 4, 14, 6], [3, 11, 1, 9], [15, 7, 13, 5]];

/// Passes for a mask of `n` sub-samples (4 per pass, at least one).
pub fn passes(n: usize) -> usize {
    n.div_ceil(4).max(1)
}

/// How far pass `p` of `passes` shifts what it draws, in pixels: a point of a 4x4 grid an eighth of
/// a pixel apart, taken in the order of [`BAYER4`], less the mean of the `passes` points used so
/// that they centre on the samples. An eighth of a pixel erred least against the exact reference
/// (docs/benchmarks-log.md, "Pass offsets").
pub fn pass_offset(p: usize, passes: usize) -> Vec2 {
    let cell = |p: usize| -> Vec2 {
        let at = BAYER4.as_flattened().iter().position(|&v| v == p % 16).unwrap_or(0);
        (Vec2::new((at % 4) as f32, (at / 4) as f32) - 1.5) / 8.0
    };
    let used = passes.clamp(1, 16);
    let mean = (0..used).map(cell).sum::<Vec2>() / used as f32;
    cell(p) - mean
}

/// Position of GPU mask bit `b` in a pixel when masks take `passes` passes.
pub fn bit_position(b: usize, passes: usize) -> Vec2 {
    MSAA4[b % 4] + pass_offset(b / 4, passes)
}

/// `i` with its lowest `bits` bits reversed (the base-2 radical inverse scaled to `2^bits`).
fn reversed(i: usize, bits: u32) -> usize {
    if bits == 0 {
        return 0;
    }
    i.reverse_bits() >> (usize::BITS - bits)
}

/// `order[i]` = the GPU bit of logical sub-sample i, for masks of `n` sub-samples (n = 4P).
pub fn logical_to_bit(n: usize) -> Vec<usize> {
    let count = passes(n);
    let bits = count.next_power_of_two().trailing_zeros();
    // Passes in radical-inverse order (for a count that is not a power of two, the reversed
    // indices that fall within it, in order).
    let pass_order: Vec<usize> =
        (0..count.next_power_of_two()).map(|i| reversed(i, bits)).filter(|&p| p < count).collect();
    let mut order: Vec<usize> = (0..count * 4).map(|i| pass_order[i % count] * 4 + (i / count) % 4).collect();
    order.truncate(n.max(1));
    order
}

/// The GPU bits of logical masks for one `order` (`order[i]` = the bit of logical sub-sample i,
/// n <= 64), a byte of the logical mask at a time: eight table lookups instead of one step per
/// sub-sample.
pub struct GpuBits {
    bytes: Box<[[u64; 256]; 8]>,
}

impl GpuBits {
    pub fn new(order: &[usize]) -> GpuBits {
        let mut bytes = Box::new([[0u64; 256]; 8]);
        for (byte, table) in bytes.iter_mut().enumerate() {
            for (value, bits) in table.iter_mut().enumerate() {
                *bits = bit_by_bit((value as u64) << (8 * byte), order);
            }
        }
        GpuBits { bytes }
    }

    /// The GPU bits of a logical mask (its first 64 sub-samples).
    pub fn of(&self, mask: &super::Mask) -> u64 {
        let low = mask.low_bits();
        self.bytes.iter().enumerate().fold(0, |bits, (byte, table)| bits | table[(low >> (8 * byte)) as usize & 0xff])
    }
}

/// The GPU bits of the logical sub-samples set in `low`, one at a time.
fn bit_by_bit(low: u64, order: &[usize]) -> u64 {
    let (mut bits, mut low) = (0u64, low);
    while low != 0 {
        let i = low.trailing_zeros() as usize;
        if let Some(&b) = order.get(i) {
            bits |= 1 << b;
        }
        low &= low - 1;
    }
    bits
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orders_are_permutations_and_spread() {
        for n in [4, 8, 16, 32, 64] {
            let order = logical_to_bit(n);
            let mut sorted = order.clone();
            sorted.sort();
            assert_eq!(sorted, (0..n).collect::<Vec<_>>(), "n = {n}");
            // The first half of the logical sub-samples covers both halves of the pixel.
            let half = &order[..n / 2];
            let left = half.iter().filter(|&&b| bit_position(b, passes(n)).x < 0.5).count();
            assert!(left > 0 && left < half.len(), "n = {n}: {left} of {} on the left", half.len());
        }
    }

    #[test]
    fn the_passes_sample_distinct_positions_spread_over_the_pixel() {
        let at = |n: usize| -> Vec<Vec2> { (0..n).map(|b| bit_position(b, passes(n))).collect() };
        let mut distinct: Vec<[i32; 2]> = at(64).iter().map(|p| (*p * 1024.0).round().as_ivec2().to_array()).collect();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), 64, "64 sub-samples at 64 positions");
        assert!(at(64).iter().all(|p| p.min_element() >= -1.0 / 16.0 && p.max_element() <= 17.0 / 16.0));
        for n in [4, 8, 16, 32, 64] {
            let mean = at(n).iter().sum::<Vec2>() / n as f32;
            assert!((mean - Vec2::splat(0.5)).length() < 1e-5, "n = {n}: centred, {mean}");
        }
    }

    #[test]
    fn the_table_maps_as_the_bits_do() {
        let order = logical_to_bit(64);
        let table = GpuBits::new(&order);
        let mut rng = crate::rng::XorShift::seeded(7);
        for _ in 0..200 {
            let word = rng.next_u64();
            let mask = super::super::Mask::from_indices((0..64).filter(|i| word >> i & 1 == 1));
            assert_eq!(table.of(&mask), bit_by_bit(word, &order));
        }
    }

    #[test]
    fn the_first_passes_hold_their_share_of_any_leading_run() {
        for n in [16, 32, 64] {
            let (order, count) = (logical_to_bit(n), passes(n));
            for run in 1..=n {
                for k in [1, 2, 4, 8].into_iter().filter(|&k| k <= count) {
                    let held = order[..run].iter().filter(|&&b| b / 4 < k).count() as f64;
                    let share = run as f64 * k as f64 / count as f64;
                    assert!((held - share).abs() <= 1.0, "n {n}, run {run}, {k} passes: {held} vs {share}");
                }
            }
        }
    }
}
