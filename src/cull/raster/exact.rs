//! The raster's exact test, for the pixels where the patch overlaps itself on screen.
//!
//! - Culling pixels; depth = NDC z (larger is farther).
//! - Where the patch overlaps itself (two triangles hold the pixel's centre: the near wall of a
//!   shell joined round its rim to the far wall) the farthest would bound the pixel by the far
//!   layer, and an outline edge of the far layer would cut the near layer's coverage.
//! - Those pixels (overlapping, or touched by an outline edge next to an overlap) go to the exact
//!   test: the triangles' *fragments* there, joined across edges that touch the pixel, form local
//!   components.
//! - A component none of whose touching edges leads to a triangle outside it has no border inside
//!   the pixel, and if it also holds the centre the pixel lies wholly inside its image.
//! - The pixel is then covered as deep as that component's farthest fragment (the nearest such
//!   component counts).

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Fragment {
    /// The pixel's place among those left to the exact test.
    pub slot: u32,
    pub triangle: u32,
    /// Farthest depth of the triangle over the pixel.
    pub z: f32,
    /// The pixel's centre lies inside the triangle.
    pub centre: bool,
    /// Bit k: edge k (corner k to corner k + 1) touches the pixel.
    pub edges: u8,
}

/// Sorts `fragments` by their slot (below `slots`), in place and stably (a counting sort through
/// `spare`): those of one pixel stay in the order of their triangles.
pub(super) fn sort_by_slot(fragments: &mut Vec<Fragment>, slots: usize, spare: &mut Vec<Fragment>) {
    // Per slot, where its fragments start.
    let mut start = vec![0u32; slots + 1];
    for f in fragments.iter() {
        start[f.slot as usize + 1] += 1;
    }
    for i in 1..=slots {
        start[i] += start[i - 1];
    }
    spare.clear();
    spare.resize(fragments.len(), Fragment { slot: 0, triangle: 0, z: 0.0, centre: false, edges: 0 });
    for f in fragments.iter() {
        let at = &mut start[f.slot as usize];
        spare[*at as usize] = *f;
        *at += 1;
    }
    std::mem::swap(fragments, spare);
}

/// Working space of [`pixel_depth`], kept from pixel to pixel.
#[derive(Default)]
pub(super) struct Scratch {
    /// The pixel's fragments that have an edge in it (by triangle, as the pixel's fragments are).
    edged: Vec<Fragment>,
}

/// Most fragments with an edge in one pixel whose components are told apart (as bit sets).
const MAX_EDGED: usize = 64;

/// The depth bound of a pixel from its fragments (sorted by triangle), if they cover it.
pub(super) fn pixel_depth(here: &[Fragment], neighbours: &[[u32; 3]], s: &mut Scratch) -> Option<f32> {
    // A fragment with no edge in the pixel that holds the centre covers it alone. (Were it joined
    // to others, they would only make its component's depth farther.)
    let mut best = f32::INFINITY;
    let mut centre = false;
    s.edged.clear();
    for f in here {
        if f.edges == 0 {
            if f.centre {
                best = best.min(f.z);
            }
        } else {
            s.edged.push(*f);
            centre |= f.centre;
        }
    }
    let found = |best: f32| (best < f32::INFINITY).then_some(best);
    if !centre {
        return found(best);
    }
    // The others form components across their touching edges; one whose edge leads to a fragment
    // not among them (or to none) has a border. Fragments i and j joined: bit j of `joined[i]`.
    let edged = &s.edged[..];
    let m = edged.len();
    // The fragment of a triangle among them (they are few: a short scan beats a binary search);
    // NONE matches none.
    let position = |t: u32| match m {
        0..=16 => edged.iter().position(|g| g.triangle == t),
        _ => edged.binary_search_by_key(&t, |g| g.triangle).ok(),
    };
    if m > MAX_EDGED {
        // Too many to tell apart (degenerate input): taken as one component, which can only
        // make the pixel farther, or uncovered.
        let border = edged
            .iter()
            .any(|f| (0..3).any(|k| f.edges & (1 << k) != 0 && position(neighbours[f.triangle as usize][k]).is_none()));
        return found(if border { best } else { best.min(edged.iter().map(|f| f.z).fold(f32::MIN, f32::max)) });
    }
    let mut joined = [0u64; MAX_EDGED];
    let (mut border, mut centres) = (0u64, 0u64);
    for (i, f) in edged.iter().enumerate() {
        joined[i] |= 1 << i;
        centres |= u64::from(f.centre) << i;
        let mut edges = f.edges;
        while edges != 0 {
            let k = edges.trailing_zeros() as usize;
            edges &= edges - 1;
            match position(neighbours[f.triangle as usize][k]) {
                Some(j) => {
                    joined[i] |= 1 << j;
                    joined[j] |= 1 << i;
                }
                None => border |= 1 << i,
            }
        }
    }
    // Components one by one: grown from their lowest fragment until closed.
    let mut left = if m == 64 { u64::MAX } else { (1u64 << m) - 1 };
    while left != 0 {
        let mut component = left & left.wrapping_neg();
        loop {
            let grown = bits(component).fold(component, |c, j| c | joined[j]);
            if grown == component {
                break;
            }
            component = grown;
        }
        left &= !component;
        if component & border == 0 && component & centres != 0 {
            best = best.min(bits(component).map(|j| edged[j].z).fold(f32::MIN, f32::max));
        }
    }
    found(best)
}

/// The positions of the set bits of `b`, lowest first.
pub(super) fn bits(mut b: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (b != 0).then(|| {
            let j = b.trailing_zeros() as usize;
            b &= b - 1;
            j
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fragments_sorted_by_slot_keep_their_order_within_one() {
        let fragment = |slot, triangle| Fragment { slot, triangle, z: 0.0, centre: false, edges: 0 };
        let mut fragments: Vec<Fragment> =
            [(2, 1), (0, 1), (2, 3), (1, 4), (0, 5), (2, 6)].into_iter().map(|(s, t)| fragment(s, t)).collect();
        sort_by_slot(&mut fragments, 3, &mut Vec::new());
        let order: Vec<(u32, u32)> = fragments.iter().map(|f| (f.slot, f.triangle)).collect();
        assert_eq!(order, [(0, 1), (0, 5), (1, 4), (2, 1), (2, 3), (2, 6)]);
    }
}
