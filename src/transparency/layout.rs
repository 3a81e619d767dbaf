//! Where logical sub-samples lie in a pixel. The renderer reaches n = 4P sub-samples with P passes
//! of 4x MSAA: pass p shifts the image by a sub-pixel jitter, and bit b of a GPU mask is MSAA sample
//! b % 4 of pass b / 4. Logical sub-sample i (the masks' index) goes to bit `order[i]`, an order in
//! which every prefix is spread over the pixel (greedy farthest point), so that the contiguous
//! runs of sub-samples the mask table hands out do not gather in one corner: no pattern at edges.
//! Positions are in pixel units, 0..1 from the pixel's top-left corner.

use glam::Vec2;

/// Standard 4x MSAA sample positions (Vulkan, D3D), pixel units.
pub const MSAA4: [Vec2; 4] =
    [Vec2::new(0.375, 0.125), Vec2::new(0.875, 0.375), Vec2::new(0.125, 0.625), Vec2::new(0.625, 0.875)];

/// Passes for a mask of `n` sub-samples (4 per pass, at least one).
pub fn passes(n: usize) -> usize {
    n.div_ceil(4).max(1)
}

/// Sub-pixel shift of pass `p` of `count`: a stratified pattern within a quarter pixel of the
/// centre (pass 0 unshifted), in pixels.
pub fn jitter(p: usize, count: usize) -> Vec2 {
    if count <= 1 || p == 0 {
        return Vec2::ZERO;
    }
    let halton = |mut i: usize, base: usize| {
        let (mut f, mut r) = (1.0f32, 0.0f32);
        while i > 0 {
            f /= base as f32;
            r += f * (i % base) as f32;
            i /= base;
        }
        r
    };
    Vec2::new(halton(p, 2), halton(p, 3)) * 0.5 - Vec2::splat(0.25)
}

/// Position of GPU mask bit `b` with `count` passes.
pub fn bit_position(b: usize, count: usize) -> Vec2 {
    let p = MSAA4[b % 4] + jitter(b / 4, count);
    Vec2::new(p.x.rem_euclid(1.0), p.y.rem_euclid(1.0))
}

/// `order[i]` = the GPU bit of logical sub-sample i, for masks of `n` sub-samples (n = 4P).
pub fn logical_to_bit(n: usize) -> Vec<usize> {
    let count = passes(n);
    let bits = count * 4;
    let pos: Vec<Vec2> = (0..bits).map(|b| bit_position(b, count)).collect();
    // Toroidal distance, so that the pattern tiles across pixels without clumps at the borders.
    let dist = |a: Vec2, b: Vec2| {
        let d = (a - b).abs();
        Vec2::new(d.x.min(1.0 - d.x), d.y.min(1.0 - d.y)).length_squared()
    };
    let mut order = vec![0usize];
    let mut nearest: Vec<f32> = pos.iter().map(|&p| dist(p, pos[0])).collect();
    while order.len() < bits {
        let mut best = None;
        for b in 0..bits {
            if order.contains(&b) {
                continue;
            }
            if best.is_none_or(|(_, d)| nearest[b] > d) {
                best = Some((b, nearest[b]));
            }
        }
        let Some((b, _)) = best else { break };
        order.push(b);
        for (o, &p) in nearest.iter_mut().zip(&pos) {
            *o = o.min(dist(p, pos[b]));
        }
    }
    order.truncate(n.max(1));
    order
}

/// Maps a logical mask (n <= 64 sub-samples) to GPU bits.
pub fn to_gpu_bits(mask: &super::Mask, order: &[usize]) -> u64 {
    let (mut bits, mut low) = (0u64, mask.low_bits());
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
    fn jitter_stays_near_the_centre() {
        for p in 0..16 {
            let j = jitter(p, 16);
            assert!(j.x.abs() <= 0.25 && j.y.abs() <= 0.25);
        }
        assert_eq!(jitter(0, 16), Vec2::ZERO);
    }
}
