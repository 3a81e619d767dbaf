//! Centre-sampled software rasterisation of hierarchy leaves, for choosing occluders (never for
//! deciding what is culled: that is the conservative rasteriser in [`crate::cull::raster`]).
//!
//! - Pixels of a `width` x `height` image: x right, y down, pixel (i, j) sampled at its centre
//!   (i + 0.5, j + 0.5).
//! - Depth = NDC z, larger is farther.

use crate::cull::project::project_triangle;
use crate::cull::LeafRef;
use crate::layout::Layout;
use crate::organ_set::OrganSet;
use glam::{Mat4, Vec3};
use rayon::prelude::*;

/// One leaf's image: the nearest depth of its triangles at each covered pixel centre.
#[derive(Clone, Debug, PartialEq)]
pub struct LeafImage {
    pub x0: usize,
    pub y0: usize,
    pub w: usize,
    pub h: usize,
    /// Row-major over the rectangle; +inf where the leaf does not cover the centre.
    pub depth: Vec<f32>,
    /// Pixels covered (its projected size).
    pub pixels: u32,
}

impl LeafImage {
    /// Covered pixels as (image x, image y, depth).
    pub fn covered(&self) -> impl Iterator<Item = (usize, usize, f32)> + '_ {
        self.depth
            .iter()
            .enumerate()
            .filter(|(_, d)| d.is_finite())
            .map(|(i, &d)| (self.x0 + i % self.w, self.y0 + i / self.w, d))
    }
}

/// Rasterises one leaf (both windings; triangles reaching nearer than the near plane are skipped,
/// as in the run-time rasteriser).
pub fn rasterise_leaf(
    set: &OrganSet,
    layout: &Layout,
    view_proj: &Mat4,
    r: LeafRef,
    w: usize,
    h: usize,
) -> Option<LeafImage> {
    let organ = &set.organs[r.organ as usize];
    let node = &organ.bvh.nodes[organ.bvh.leaves[r.leaf as usize] as usize];
    let mvp = *view_proj * layout.organs[r.organ as usize].transform.matrix();
    let mut tris = Vec::with_capacity(node.count as usize);
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for t in node.first..node.first + node.count {
        if let Some(tri) = project_triangle(&organ.mesh, t, &mvp, w, h) {
            for p in tri {
                (lo, hi) = (lo.min(p), hi.max(p));
            }
            tris.push(tri);
        }
    }
    if tris.is_empty() || hi.x < 0.5 || hi.y < 0.5 || lo.x > w as f32 - 0.5 || lo.y > h as f32 - 0.5 {
        return None;
    }
    // Pixels whose centres the bounds can hold.
    let first = |v: f32, n: usize| ((v - 0.5).ceil().max(0.0) as usize).min(n - 1);
    let last = |v: f32, n: usize| ((v - 0.5).floor().max(0.0) as usize).min(n - 1);
    let (x0, x1, y0, y1) = (first(lo.x, w), last(hi.x, w), first(lo.y, h), last(hi.y, h));
    if x1 < x0 || y1 < y0 {
        return None;
    }
    let (iw, ih) = (x1 - x0 + 1, y1 - y0 + 1);
    let mut depth = vec![f32::INFINITY; iw * ih];
    for t in &tris {
        draw_triangle(t, x0, y0, iw, ih, &mut depth);
    }
    let pixels = depth.iter().filter(|d| d.is_finite()).count() as u32;
    (pixels > 0).then_some(LeafImage { x0, y0, w: iw, h: ih, depth, pixels })
}

/// Writes the triangle's depth at the pixel centres it covers (top-left rule not needed: shared
/// edges may be sampled by both triangles, which only matters for depth, the nearest kept).
fn draw_triangle(t: &[Vec3; 3], x0: usize, y0: usize, w: usize, h: usize, depth: &mut [f32]) {
    let area = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
    if area == 0.0 || !area.is_finite() {
        return;
    }
    let lo = t[0].min(t[1]).min(t[2]);
    let hi = t[0].max(t[1]).max(t[2]);
    let span = |a: f32, b: f32, origin: usize, n: usize| {
        let s = ((a - 0.5).ceil() - origin as f32).max(0.0) as usize;
        let e = ((b - 0.5).floor() - origin as f32).min(n as f32 - 1.0);
        (s, e)
    };
    let (xs, xe) = span(lo.x, hi.x, x0, w);
    let (ys, ye) = span(lo.y, hi.y, y0, h);
    if xe < 0.0 || ye < 0.0 {
        return;
    }
    for y in ys..=ye as usize {
        for x in xs..=xe as usize {
            let (px, py) = ((x0 + x) as f32 + 0.5, (y0 + y) as f32 + 0.5);
            let e = |a: Vec3, b: Vec3| ((b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)) / area;
            let (w0, w1, w2) = (e(t[1], t[2]), e(t[2], t[0]), e(t[0], t[1]));
            if w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 {
                let z = w0 * t[0].z + w1 * t[1].z + w2 * t[2].z;
                let d = &mut depth[y * w + x];
                *d = d.min(z);
            }
        }
    }
}

/// The images cut down to the pixels the run-time rasteriser can count as wholly covered: a
/// pixel stays if each of its four neighbours is covered by some image of the same organ (or lies
/// off screen). The run-time rasteriser fuses an organ's leaves into patches and drops the pixels
/// their outline touches; this is its centre-sampled likeness, so a selection made on these images
/// also covers what lies just inside another occluder's outline.
pub fn interior(images: &[Option<LeafImage>], organs: &[u32], w: usize, h: usize) -> Vec<Option<LeafImage>> {
    let mut union: std::collections::HashMap<u32, Vec<bool>> = Default::default();
    for (image, &o) in images.iter().zip(organs) {
        let mask = union.entry(o).or_insert_with(|| vec![false; w * h]);
        for (x, y, _) in image.iter().flat_map(|im| im.covered()) {
            mask[y * w + x] = true;
        }
    }
    images
        .iter()
        .zip(organs)
        .map(|(image, o)| {
            let image = image.as_ref()?;
            let mask = &union[o];
            let covered = |x: isize, y: isize| {
                x < 0 || y < 0 || x >= w as isize || y >= h as isize || mask[y as usize * w + x as usize]
            };
            let mut out = image.clone();
            for (i, d) in out.depth.iter_mut().enumerate() {
                let (x, y) = ((image.x0 + i % image.w) as isize, (image.y0 + i / image.w) as isize);
                if d.is_finite() && !(covered(x - 1, y) && covered(x + 1, y) && covered(x, y - 1) && covered(x, y + 1))
                {
                    *d = f32::INFINITY;
                }
            }
            out.pixels = out.depth.iter().filter(|d| d.is_finite()).count() as u32;
            (out.pixels > 0).then_some(out)
        })
        .collect()
}

/// Every candidate's image, in parallel.
pub fn leaf_images(
    set: &OrganSet,
    layout: &Layout,
    view_proj: &Mat4,
    candidates: &[LeafRef],
    w: usize,
    h: usize,
) -> Vec<Option<LeafImage>> {
    candidates.par_iter().map(|&r| rasterise_leaf(set, layout, view_proj, r, w, h)).collect()
}

/// The ID buffer of the images: per pixel, the index of the nearest image there (`None` where none).
pub fn id_buffer(images: &[Option<LeafImage>], w: usize, h: usize) -> Vec<Option<u32>> {
    let mut nearest = vec![(f32::INFINITY, None); w * h];
    for (i, image) in images.iter().enumerate() {
        for (x, y, d) in image.iter().flat_map(|im| im.covered()) {
            let p = &mut nearest[y * w + x];
            if d < p.0 {
                *p = (d, Some(i as u32));
            }
        }
    }
    nearest.into_iter().map(|(_, id)| id).collect()
}

/// Per image, how many pixels of the ID buffer it holds (its visible, "first-hit" pixels).
pub fn visible_pixels(images: &[Option<LeafImage>], w: usize, h: usize) -> Vec<u32> {
    let mut count = vec![0; images.len()];
    for id in id_buffer(images, w, h).into_iter().flatten() {
        count[id as usize] += 1;
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_covers_the_centres_inside_it() {
        let t = [Vec3::new(0.0, 0.0, 0.5), Vec3::new(8.0, 0.0, 0.5), Vec3::new(0.0, 8.0, 0.5)];
        let mut depth = vec![f32::INFINITY; 64];
        draw_triangle(&t, 0, 0, 8, 8, &mut depth);
        // Centre (x + 0.5, y + 0.5) is inside when x + y + 1 <= 8, that is x + y < 8.
        for y in 0..8 {
            for x in 0..8 {
                assert_eq!(depth[y * 8 + x].is_finite(), x + y < 8, "pixel {x},{y}");
            }
        }
    }
}
