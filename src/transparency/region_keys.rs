//! Which transparent organs each screen region holds, and its K nearest (thesis §4.3.4, the
//! first two steps of [`super::regions`]). Spaces: organ meshes in organ space, moved into world
//! space by the layout and projected by the camera; regions are squares of `region_px` screen
//! pixels (x right, y down), numbered row-major; depth is NDC z (larger is farther).
//! - A pixel takes the masks of the region under it moved by up to [`reach`] in each axis
//!   ([`region_of`]), so that neighbouring regions' configurations blend over a region's width
//!   instead of meeting at straight edges that show as tiles; leaf rectangles grow by as much.

use crate::camera::Camera;
use crate::layout::Layout;
use crate::organ_set::OrganSet;
use rayon::prelude::*;

/// The image's pixels and its regions: `cols` x `rows` squares of `region_px`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Grid {
    pub width: u32,
    pub height: u32,
    pub region_px: u32,
    pub cols: u32,
    pub rows: u32,
}

/// How far a pixel's region lookup moves in each axis: half a region.
pub(super) fn reach(region_px: u32) -> u32 {
    region_px / 2
}

/// A well-mixed hash of a pixel's position (mirrored in shaders/organ.wgsl).
fn pixel_hash(x: u32, y: u32) -> u32 {
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^ (h >> 16)
}

/// The region (column, row) whose masks pixel (x, y) takes: the one under the pixel moved by a
/// hash of its position, at most [`reach`] in each axis, clamped to the grid. Mirrored by
/// `region_of` in shaders/organ.wgsl.
pub(super) fn region_of(x: u32, y: u32, region_px: u32, cols: u32, rows: u32) -> (u32, u32) {
    let (region_px, reach) = (region_px.max(1), reach(region_px) as i64);
    let h = pixel_hash(x, y);
    let span = 2 * reach + 1;
    let moved = |v: u32, bits: u32, n: u32| {
        let v = (v as i64 + (bits as i64 % span) - reach).max(0) as u32;
        (v / region_px).min(n.max(1) - 1)
    };
    (moved(x, h & 0xffff, cols), moved(y, h >> 16, rows))
}

/// A hierarchy leaf of a transparent organ on screen: the regions its rectangle touches (columns
/// `c0..=c1`, rows `r0..=r1`) and the nearest NDC depth of its box.
#[derive(Clone, Copy, Debug)]
pub(super) struct LeafRect {
    organ: u32,
    c0: u32,
    c1: u32,
    r0: u32,
    r1: u32,
    z: f32,
}

/// The screen rectangles of the hierarchy leaves of every drawn transparent organ (the first
/// `organs`), an organ at a time in parallel.
pub(super) fn leaf_rects(
    (set, layout, organs): (&OrganSet, &Layout, usize),
    camera: &Camera,
    grid: &Grid,
) -> Vec<LeafRect> {
    let (cols, rows) = (grid.cols, grid.rows);
    let vp = camera.view_projection(grid.width as f32 / grid.height as f32);
    let (w, h) = (grid.width as f32, grid.height as f32);
    let scale = 1.0 / grid.region_px as f32;
    let organ_rects = |(o, (organ, state)): (usize, (&crate::organ_set::Organ, &crate::layout::OrganState))| {
        let mut rects = Vec::new();
        if !state.is_drawn() || state.is_opaque() {
            return rects;
        }
        let m = vp * state.transform.matrix();
        for &leaf in &organ.bvh.leaves {
            let Some(node) = organ.bvh.nodes.get(leaf as usize) else { continue };
            let v = node.bounds.corners().map(|c| m * c.extend(1.0));
            let outside = |f: &dyn Fn(&glam::Vec4) -> bool| v.iter().all(f);
            if outside(&|c| c.x > c.w) || outside(&|c| c.x < -c.w) || outside(&|c| c.y > c.w) {
                continue;
            }
            if outside(&|c| c.y < -c.w) || outside(&|c| c.z > c.w) {
                continue;
            }
            let (x0, x1, y0, y1, z) = if v.iter().any(|c| c.w <= 1e-6) {
                // Crosses the eye plane: present everywhere, as near as can be.
                (0.0, w, 0.0, h, 0.0)
            } else {
                let (mut x0, mut x1, mut y0, mut y1, mut z) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN, f32::MAX);
                for c in &v {
                    let (x, y) = ((c.x / c.w * 0.5 + 0.5) * w, (0.5 - c.y / c.w * 0.5) * h);
                    (x0, x1, y0, y1, z) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y), z.min(c.z / c.w));
                }
                let grow = 1.0 + reach(grid.region_px) as f32;
                (x0 - grow, x1 + grow, y0 - grow, y1 + grow, z.max(0.0))
            };
            let cell = |v: f32, n: u32| ((v * scale).floor().max(0.0) as u32).min(n - 1);
            let (c0, c1, r0, r1) = (cell(x0, cols), cell(x1, cols), cell(y0, rows), cell(y1, rows));
            rects.push(LeafRect { organ: o as u32, c0, c1, r0, r1, z });
        }
        rects
    };
    let drawn = set.organs.par_iter().zip(&layout.organs).enumerate().take(organs);
    drawn.flat_map_iter(organ_rects).collect()
}

/// The pixel rectangle `[x, y, width, height]` of the regions the leaves touch.
pub(super) fn covered_pixels(rects: &[LeafRect], grid: &Grid) -> [u32; 4] {
    let Some(first) = rects.first() else { return [0; 4] };
    let (mut c0, mut c1, mut r0, mut r1) = (first.c0, first.c1, first.r0, first.r1);
    for r in rects {
        (c0, c1, r0, r1) = (c0.min(r.c0), c1.max(r.c1), r0.min(r.r0), r1.max(r.r1));
    }
    let s = grid.region_px;
    let (x, y) = (c0 * s, r0 * s);
    [x, y, ((c1 + 1) * s).min(grid.width) - x, ((r1 + 1) * s).min(grid.height) - y]
}

/// The key of every region in row-major order, `stride` = `words + k` u64 a region: its organs as
/// bits (`words` u64), then its K nearest by the nearest depth of their leaves there, nearest
/// first (ties by index), padded with `u64::MAX`. A row of regions at a time, in parallel.
pub(super) fn region_keys(rects: &[LeafRect], organs: usize, k: usize, grid: &Grid) -> Vec<u64> {
    let words = organs.div_ceil(64);
    let stride = words + k;
    let (cols, rows) = (grid.cols as usize, grid.rows);
    // Per row: the nearest depth of each organ in each region of the row, and which are present.
    let scratch = || (vec![f32::INFINITY; cols * organs], vec![0u64; cols * words], Vec::new());
    let row_keys = |(depths, present, nearest): &mut (Vec<f32>, Vec<u64>, Vec<usize>), r: u32| {
        depths.fill(f32::INFINITY);
        present.fill(0);
        for rect in rects.iter().filter(|x| x.r0 <= r && r <= x.r1) {
            let o = rect.organ as usize;
            for c in rect.c0 as usize..=rect.c1 as usize {
                let d = &mut depths[c * organs + o];
                *d = d.min(rect.z);
                present[c * words + o / 64] |= 1 << (o % 64);
            }
        }
        let mut keys = vec![u64::MAX; stride * cols];
        for ((key, bits), depth) in keys
            .chunks_exact_mut(stride)
            .zip(present.chunks_exact(words.max(1)))
            .zip(depths.chunks_exact(organs.max(1)))
        {
            key[..words].copy_from_slice(bits);
            nearest.clear();
            for (w, &word) in bits.iter().enumerate() {
                let mut word = word;
                while word != 0 {
                    nearest.push(w * 64 + word.trailing_zeros() as usize);
                    word &= word - 1;
                }
            }
            nearest.sort_by(|&a, &b| depth[a].total_cmp(&depth[b]).then(a.cmp(&b)));
            for (k, &o) in key[words..].iter_mut().zip(nearest.iter()) {
                *k = o as u64;
            }
        }
        keys
    };
    let rows: Vec<Vec<u64>> = (0..rows).into_par_iter().map_init(scratch, row_keys).collect();
    rows.concat()
}

#[cfg(test)]
mod tests {
    use super::region_of;

    /// Pixels take a neighbouring region's masks near its edges, never one farther, and at a
    /// region's centre nearly always its own; so edges blend and no tile edge is straight.
    #[test]
    fn pixels_near_an_edge_mix_the_regions_on_both_sides() {
        let (side, cols, rows) = (32u32, 8u32, 8u32);
        let (mut moved, mut centres_moved) = (0, 0);
        for y in 0..rows * side {
            for x in 0..cols * side {
                let (c, r) = region_of(x, y, side, cols, rows);
                let (c0, r0) = (x / side, y / side);
                assert!(c.abs_diff(c0) <= 1 && r.abs_diff(r0) <= 1, "({x}, {y}) took region ({c}, {r})");
                moved += usize::from((c, r) != (c0, r0));
                let centre = x % side == side / 2 && y % side == side / 2;
                centres_moved += usize::from(centre && (c, r) != (c0, r0));
            }
        }
        let share = moved as f64 / f64::from(cols * rows * side * side);
        assert!((0.3..0.7).contains(&share), "{share} of pixels take a neighbour's masks");
        // Only the hash's extreme moves reach from the centre to the next region (1 in 33 per axis).
        assert!(centres_moved <= 8, "{centres_moved} of 64 region centres take a neighbour's masks");
    }
}
