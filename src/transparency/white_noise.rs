//! White-noise masks: round(alpha * n) sub-samples chosen at random.
//!
//! - Right on their own (first order), but stacked they keep the wrong counts, by chance (thesis
//!   §4.2, Mulder et al. 1998).
//! - Alpha is clamped to 0..=1; the choice draws on the caller's `XorShift`.

use super::Mask;
use crate::rng::XorShift;

pub fn mask(n: usize, alpha: f32, rng: &mut XorShift) -> Mask {
    let mut all: Vec<usize> = (0..n).collect();
    rng.shuffle(&mut all);
    let k = (alpha.clamp(0.0, 1.0) as f64 * n as f64 + 0.5).floor() as usize;
    Mask::from_indices(all.into_iter().take(k.min(n)))
}

#[cfg(test)]
mod tests {
    #[test]
    fn first_order_is_exact() {
        let mut rng = crate::rng::XorShift::seeded(3);
        for n in [16, 64, 256] {
            for a in [0.0, 0.1, 0.25, 0.5, 0.77, 1.0] {
                let m = super::mask(n, a, &mut rng);
                assert_eq!(m.count(), (a as f64 * n as f64 + 0.5).floor() as usize);
                assert!(m.iter().all(|i| i < n));
            }
        }
    }
}
