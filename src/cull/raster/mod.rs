//! The software occluder rasteriser: occluder triangles into coverage and depth, conservative by
//! construction.
//!
//! - Culling pixels: x right, y down, pixel (i, j) covers [i, i+1) x [j, j+1); depth = NDC z,
//!   larger is farther.
//! - Occluders come as triangles that all project with the same winding (the camera-facing side of
//!   organ surfaces), each with its neighbours across its three edges that are occluders too.
//! - Joined across those edges, they form connected **patches**, each rasterised on its own and
//!   then merged (a pixel covered by several patches takes the nearest's depth).
//! - Within a patch, an edge with no neighbour is an *outline* edge, and the union of the patch's
//!   triangles on screen has its boundary on outline edges only (across any other edge the two
//!   triangles lie side by side, so the points of the edge are inside).
//! - So a pixel that no outline edge touches and whose centre a triangle holds lies wholly inside
//!   the union: it is **covered**.
//! - Its **depth** is the farthest over the pixel of the triangles that reach it (each triangle's
//!   depth plane at the pixel's farthest corner, capped by its vertices); a triangle reaching the
//!   pixel without holding its centre would have an edge in it, one leading to an outline edge
//!   there, so where only one triangle holds the centre they all form one surface in the pixel.
//! - Where the patch overlaps itself on screen, pixels go to the [`exact`] test.
//! - Leaving any pixel uncovered is always safe; the exact test only wins back coverage.
//! - Pixels are evaluated four of a row at a time ([`lanes`]), in SIMD or scalar code alike.

mod exact;
mod lanes;
mod patch;

use super::rect::PixelRect;
use super::share::{Phase, Tasks};
use crate::bvh::NONE;
use exact::{pixel_depth, sort_by_slot, Fragment, Scratch};
use lanes::{max_ps, Lanes, Setup, EPS};
pub use lanes::{Path, Triangle};
use patch::{Patch, Window, BORDER, CENTRE, SECOND};
use std::ops::Range;

/// Coverage and depth of occluders at low resolution, collected triangle by triangle.
#[derive(Clone, Debug, PartialEq)]
pub struct OccluderRaster {
    pub width: usize,
    pub height: usize,
    triangles: Vec<Triangle>,
    /// Per triangle added, its occluder neighbours (indices among all triangles added, or NONE).
    neighbours: Vec<[u32; 3]>,
    path: Path,
}

/// The result: a coverage bitmap (1 = wholly covered) and the farthest occluder depth of each
/// covered pixel (+inf elsewhere, so nothing is ever behind an uncovered pixel).
#[derive(Clone, Debug, PartialEq)]
pub struct OccluderMaps {
    pub width: usize,
    pub height: usize,
    pub covered: Vec<u8>,
    pub depth: Vec<f32>,
}

/// The raster's patches (largest first) as tasks to share, with each triangle's reach.
pub(crate) struct Patches {
    raster: OccluderRaster,
    reach: Vec<Option<PixelRect>>,
    /// All triangles, patch by patch ([`OccluderRaster::patches`]), and where each patch lies.
    triangles: Vec<u32>,
    patches: Vec<Range<usize>>,
}

impl Tasks for Patches {
    type State = Rasterising;
    fn count(&self) -> usize {
        self.patches.len()
    }
    fn state(&self) -> Rasterising {
        Rasterising::new(self.raster.width, self.raster.height)
    }
    fn run(&self, r: &mut Rasterising, i: usize) {
        self.raster.rasterise(r, &self.triangles[self.patches[i].clone()], &self.reach);
    }
}

/// One thread's share of the rasterisation: its maps, and working space kept from patch to patch.
pub(crate) struct Rasterising {
    maps: OccluderMaps,
    patch: Patch,
    /// Per pixel of the patch left to the exact test, its index in the image.
    exact: Vec<usize>,
    fragments: Vec<Fragment>,
    /// Room to sort the fragments into.
    spare: Vec<Fragment>,
    scratch: Scratch,
}

impl Rasterising {
    fn new(width: usize, height: usize) -> Rasterising {
        Rasterising {
            maps: OccluderMaps::empty(width, height),
            patch: Patch::default(),
            exact: Vec::new(),
            fragments: Vec::new(),
            spare: Vec::new(),
            scratch: Scratch::default(),
        }
    }
}

/// Bits 0..4 of `m` moved to bits 0, 8, 16 and 24: a 0 or 1 in each of four bytes.
fn bytes(m: u32) -> u32 {
    (m & 1) | ((m & 2) << 7) | ((m & 4) << 14) | ((m & 8) << 21)
}

impl OccluderRaster {
    pub fn new(width: usize, height: usize) -> OccluderRaster {
        OccluderRaster { width, height, triangles: Vec::new(), neighbours: Vec::new(), path: Path::native() }
    }

    /// The same, its pixels evaluated by `path`.
    #[cfg(test)]
    pub fn with_path(self, path: Path) -> OccluderRaster {
        OccluderRaster { path, ..self }
    }

    /// Adds triangles of one winding; `neighbours[i][k]` is the index in `triangles` of the
    /// triangle across edge k of triangle i (corner k to corner k + 1), or `NONE` where that
    /// triangle is not an occluder.
    pub fn add(&mut self, triangles: &[Triangle], neighbours: &[[u32; 3]]) {
        debug_assert_eq!(triangles.len(), neighbours.len());
        let base = self.neighbours.len() as u32;
        self.triangles.extend_from_slice(triangles);
        self.neighbours.extend(neighbours.iter().map(|n| n.map(|j| if j == NONE { NONE } else { base + j })));
    }

    /// Adds the triangles of `other` (of the same size), linked among themselves as there.
    pub fn append(&mut self, other: &OccluderRaster) {
        self.add(&other.triangles, &other.neighbours);
    }

    /// How many triangles were added.
    pub fn len(&self) -> usize {
        self.triangles.len()
    }

    /// The pixels that triangle `t` may touch, if it has area and reaches the image.
    fn reach(&self, t: &Triangle) -> Option<PixelRect> {
        let min = t[0].min(t[1]).min(t[2]);
        let max = t[0].max(t[1]).max(t[2]);
        let area = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
        let (w, h) = (self.width as f32, self.height as f32);
        if area == 0.0
            || !area.is_finite()
            || max.x + EPS < 0.0
            || max.y + EPS < 0.0
            || min.x - EPS >= w
            || min.y - EPS >= h
        {
            return None;
        }
        // Both ends reach the image: clamped to it, truncation is floor.
        let span = |lo: f32, hi: f32, n: f32| ((lo - EPS).max(0.0) as usize, (hi + EPS).clamp(0.0, n - 1.0) as usize);
        let (x0, x1) = span(min.x, max.x, w);
        let (y0, y1) = span(min.y, max.y, h);
        Some(PixelRect { x0, y0, x1, y1 })
    }

    /// Visits the pixels of a patch (at `at`) in `t`'s reach (from [`OccluderRaster::reach`]),
    /// four of a row at a time, with the triangle's centre and edge masks and depth there: of each
    /// row `y`, those of the fours that meet columns `span(y)` (inclusive), if any. (The fours
    /// start at the reach's first column, whatever the span.)
    fn lanes(
        &self,
        at: Window,
        t: &Triangle,
        PixelRect { x0, y0, y1, .. }: PixelRect,
        span: impl Fn(usize) -> Option<(usize, usize)>,
        mut visit: impl FnMut(Lanes),
    ) {
        let setup = Setup::new(t);
        for y in y0..=y1 {
            let Some((from, to)) = span(y) else { continue };
            let row = setup.row(y);
            let start = (y - at.y0) * at.stride;
            let mut x = x0 + (from - x0) / 4 * 4;
            while x <= to {
                if let Some(l) = setup.four(self.path, &row, x) {
                    visit(Lanes { i: start + x - at.x0, ..l });
                }
                x += 4;
            }
        }
    }

    /// The connected patches of the triangles added, largest first: all triangles, patch by patch
    /// (each patch's in increasing order), and where each patch lies among them.
    fn patches(&self) -> (Vec<u32>, Vec<Range<usize>>) {
        let n = self.triangles.len();
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn root(parent: &mut [u32], mut i: u32) -> u32 {
            while parent[i as usize] != i {
                let up = parent[parent[i as usize] as usize];
                parent[i as usize] = up;
                i = up;
            }
            i
        }
        for (i, ns) in self.neighbours.iter().enumerate() {
            for &j in ns {
                if j != NONE {
                    let (a, b) = (root(&mut parent, i as u32), root(&mut parent, j));
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
        // Grouped by a counting sort: per root (a patch's first triangle), its patch's size, then
        // where its next triangle goes.
        let roots: Vec<u32> = (0..n as u32).map(|i| root(&mut parent, i)).collect();
        let mut next = vec![0usize; n];
        for &r in &roots {
            next[r as usize] += 1;
        }
        let mut firsts: Vec<usize> = (0..n).filter(|&r| next[r] > 0).collect();
        firsts.sort_by_key(|&r| std::cmp::Reverse(next[r]));
        let mut patches = Vec::with_capacity(firsts.len());
        for r in firsts {
            let start = patches.last().map_or(0, |p: &Range<usize>| p.end);
            patches.push(start..start + next[r]);
            next[r] = start;
        }
        let mut triangles = vec![0u32; n];
        for (i, &r) in roots.iter().enumerate() {
            triangles[next[r as usize]] = i as u32;
            next[r as usize] += 1;
        }
        (triangles, patches)
    }

    /// Coverage and depth of every pixel, patch by patch, on the calling thread alone.
    #[cfg(test)]
    pub fn finish(self) -> OccluderMaps {
        self.finish_on(&Phase::default())
    }

    /// [`OccluderRaster::finish`] with the patches shared among the threads helping `phase` (each
    /// patch is rasterised on its own, so the result does not depend on how).
    pub(crate) fn finish_on(self, phase: &Phase<Patches>) -> OccluderMaps {
        let (w, h) = (self.width, self.height);
        let reach: Vec<Option<PixelRect>> = self.triangles.iter().map(|t| self.reach(t)).collect();
        let (triangles, patches) = self.patches();
        let done = phase.run(Patches { raster: self, reach, triangles, patches });
        done.into_iter().map(|r| r.maps).reduce(OccluderMaps::merge).unwrap_or_else(|| OccluderMaps::empty(w, h))
    }

    /// Adds the coverage and depth of one patch's pixels to `r`'s maps (`reach`: per triangle, from
    /// [`OccluderRaster::reach`]).
    fn rasterise(&self, r: &mut Rasterising, tris: &[u32], reach: &[Option<PixelRect>]) {
        let w = self.width;
        let Rasterising { maps, patch, exact, fragments, spare, scratch } = r;
        let Some(PixelRect { x0, y0, x1, y1 }) = tris.iter().filter_map(|&t| reach[t as usize]).reduce(|a, b| {
            PixelRect { x0: a.x0.min(b.x0), y0: a.y0.min(b.y0), x1: a.x1.max(b.x1), y1: a.y1.max(b.y1) }
        }) else {
            return;
        };
        patch.reset(x0, y0, x1 - x0 + 1, y1 - y0 + 1);
        self.fill(patch, tris, reach);
        exact.clear();
        for y in 0..patch.h {
            let (at, out) = (y * patch.at.stride, (y0 + y) * w + x0);
            for x in 0..patch.w {
                let flags = patch.flags[at + x];
                if flags == CENTRE {
                    maps.cover(out + x, patch.far[at + x]);
                } else if flags & CENTRE != 0 && (flags & SECOND != 0 || patch.overlaps_near(x, y)) {
                    patch.leave_to_exact(x, y, exact.len() as u32);
                    exact.push(out + x);
                }
            }
        }
        if exact.is_empty() {
            return;
        }
        self.exact_fragments(patch, tris, reach, fragments);
        sort_by_slot(fragments, exact.len(), spare);
        for here in fragments.chunk_by(|f, g| f.slot == g.slot) {
            if let Some(z) = pixel_depth(here, &self.neighbours, scratch) {
                maps.cover(exact[here[0].slot as usize], z);
            }
        }
    }

    /// The first pass over a patch: per pixel, the farthest depth of the triangles that touch it,
    /// and its flags. Where one triangle holds the centre and no outline edge touches the pixel,
    /// the patch's triangles there form a single component with no border in the pixel (one not
    /// holding the centre would have a border): the pixel is covered, as deep as the farthest.
    fn fill(&self, patch: &mut Patch, tris: &[u32], reach: &[Option<PixelRect>]) {
        for &t in tris {
            let Some(rect) = reach[t as usize] else { continue };
            let outline = self.neighbours[t as usize].map(|n| n == NONE);
            let all = |_| Some((rect.x0, rect.x1));
            self.lanes(patch.at, &self.triangles[t as usize], rect, all, |l| {
                let border = (0..3).filter(|&k| outline[k]).fold(0, |m, k| m | l.edges[k]);
                let reached = l.reached();
                for (j, far) in patch.far[l.i..l.i + 4].iter_mut().enumerate() {
                    if reached & (1 << j) != 0 {
                        *far = max_ps(*far, l.z[j]);
                    }
                }
                let flags = &mut patch.flags[l.i..l.i + 4];
                let old = u32::from_le_bytes([flags[0], flags[1], flags[2], flags[3]]);
                let centre = bytes(l.centre);
                let new = old
                    | (centre * u32::from(CENTRE))
                    | ((centre & old) * u32::from(SECOND))
                    | (bytes(border) * u32::from(BORDER));
                flags.copy_from_slice(&new.to_le_bytes());
            });
        }
    }

    /// The second pass, over the triangles that reach pixels left to the exact test (where the
    /// patch overlaps itself, or an outline edge passes): their fragments there, triangle by
    /// triangle (in the order of `tris`).
    fn exact_fragments(&self, patch: &Patch, tris: &[u32], reach: &[Option<PixelRect>], out: &mut Vec<Fragment>) {
        out.clear();
        for &t in tris {
            let tri = &self.triangles[t as usize];
            let Some(rect @ PixelRect { x0, y0, x1, y1 }) = reach[t as usize] else { continue };
            let at = patch.at;
            if !patch.any_exact(PixelRect { x0: x0 - at.x0, y0: y0 - at.y0, x1: x1 - at.x0, y1: y1 - at.y0 }) {
                continue;
            }
            // Only the fours that hold such pixels.
            let span = |y| patch.exact_span(y - at.y0, x0 - at.x0, x1 - at.x0).map(|(a, b)| (a + at.x0, b + at.x0));
            self.lanes(at, tri, rect, span, |l| {
                let reached = l.reached();
                for j in (0..4).filter(|j| reached & (1 << j) != 0) {
                    let slot = patch.slot[l.i + j];
                    if slot != NONE {
                        let edges = (0..3).fold(0u8, |m, k| m | (((l.edges[k] >> j) & 1) as u8) << k);
                        let centre = (l.centre >> j) & 1 != 0;
                        out.push(Fragment { slot, triangle: t, z: l.z[j], centre, edges });
                    }
                }
            });
        }
    }
}

impl OccluderMaps {
    /// No pixel covered.
    fn empty(width: usize, height: usize) -> OccluderMaps {
        OccluderMaps { width, height, covered: vec![0; width * height], depth: vec![f32::INFINITY; width * height] }
    }

    /// The maps of two sets of patches together: covered where either covers, as deep as the
    /// nearer.
    pub(crate) fn merge(mut self, other: OccluderMaps) -> OccluderMaps {
        for (c, o) in self.covered.iter_mut().zip(&other.covered) {
            *c |= o;
        }
        for (d, o) in self.depth.iter_mut().zip(&other.depth) {
            *d = d.min(*o);
        }
        self
    }

    /// Marks pixel `i` covered, as deep as `z` (or nearer where it already was).
    fn cover(&mut self, i: usize, z: f32) {
        self.covered[i] = 1;
        self.depth[i] = self.depth[i].min(z);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Fraction of a pixel covered by the union of triangles, by dense point sampling.
    fn coverage(tris: &[Triangle], x: usize, y: usize, n: usize) -> f32 {
        let inside = |t: &Triangle, px: f32, py: f32| {
            let s = |a: Vec3, b: Vec3| (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
            let (d0, d1, d2) = (s(t[0], t[1]), s(t[1], t[2]), s(t[2], t[0]));
            (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0)
        };
        let mut hit = 0;
        for j in 0..n {
            for i in 0..n {
                let (px, py) = (x as f32 + (i as f32 + 0.5) / n as f32, y as f32 + (j as f32 + 0.5) / n as f32);
                hit += usize::from(tris.iter().any(|t| inside(t, px, py)));
            }
        }
        hit as f32 / (n * n) as f32
    }

    /// A fan of k triangles around a centre (a closed polygon of one winding): its rim has no
    /// neighbours.
    fn fan(cx: f32, cy: f32, r: f32, k: usize, z: f32) -> (Vec<Triangle>, Vec<[u32; 3]>) {
        let p = |i: usize| {
            let a = i as f32 / k as f32 * std::f32::consts::TAU;
            Vec3::new(cx + r * a.cos(), cy + r * a.sin(), z + 0.01 * a.sin())
        };
        let c = Vec3::new(cx, cy, z);
        let tris = (0..k).map(|i| [c, p(i), p(i + 1)]).collect();
        let neighbours = (0..k).map(|i| [((i + k - 1) % k) as u32, NONE, ((i + 1) % k) as u32]).collect();
        (tris, neighbours)
    }

    /// A ramp winding 1.5 times round a ring, one connected surface: its first half turn (near,
    /// z about 0.2) lies over its last (far, z about 0.8) on screen.
    fn ramp() -> (Vec<Triangle>, Vec<[u32; 3]>) {
        let steps = 90;
        let turn = 1.5 * std::f32::consts::TAU;
        let at = |i: usize, r: f32| {
            let a = turn * i as f32 / steps as f32;
            Vec3::new(16.0 + r * a.cos(), 16.0 + r * a.sin(), 0.2 + 0.6 * i as f32 / steps as f32)
        };
        let (mut tris, mut neighbours) = (Vec::new(), Vec::new());
        for i in 0..steps {
            let (a, b, c, d) = (at(i, 6.0), at(i, 14.0), at(i + 1, 14.0), at(i + 1, 6.0));
            let (t0, t1) = (2 * i as u32, 2 * i as u32 + 1);
            tris.push([a, b, c]);
            neighbours.push([if i == 0 { NONE } else { t0 - 1 }, NONE, t1]);
            tris.push([a, c, d]);
            neighbours.push([t0, if i + 1 == steps { NONE } else { t1 + 1 }, NONE]);
        }
        (tris, neighbours)
    }

    /// Two triangles making the square [a, b]^2 at depth z; only its four sides are outline.
    fn square(a: f32, b: f32, z: f32) -> (Vec<Triangle>, Vec<[u32; 3]>) {
        let q = [Vec3::new(a, a, z), Vec3::new(b, a, z), Vec3::new(b, b, z), Vec3::new(a, b, z)];
        (vec![[q[0], q[1], q[2]], [q[0], q[2], q[3]]], vec![[NONE, NONE, 1], [0, NONE, NONE]])
    }

    #[test]
    fn coverage_never_exceeds_a_fine_reference() {
        let mut rng = crate::rng::XorShift(7);
        let mut rand = || rng.unit();
        let mut total = 0;
        for _ in 0..30 {
            let (tris, neighbours) =
                fan(4.0 + 24.0 * rand(), 4.0 + 24.0 * rand(), 2.0 + 12.0 * rand(), 5 + (rand() * 20.0) as usize, 0.5);
            let mut r = OccluderRaster::new(32, 32);
            r.add(&tris, &neighbours);
            let maps = r.finish();
            for y in 0..32 {
                for x in 0..32 {
                    if maps.covered[y * 32 + x] == 1 {
                        total += 1;
                        assert_eq!(coverage(&tris, x, y, 16), 1.0, "pixel {x},{y} counted covered but is not");
                        // Never nearer than the surface: the fan's depth varies in 0.49..=0.51.
                        assert!(maps.depth[y * 32 + x] >= 0.49 && maps.depth[y * 32 + x] <= 0.5101);
                    }
                }
            }
        }
        assert!(total > 1000, "only {total} pixels covered in 30 fans");
    }

    /// The maps with depth as bits, to compare paths bit for bit.
    fn bits(m: &OccluderMaps) -> (Vec<u8>, Vec<u32>) {
        (m.covered.clone(), m.depth.iter().map(|d| d.to_bits()).collect())
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]

        /// Random fans, squares and a ramp overlapping itself, some tilted steeply in depth.
        #[test]
        fn simd_and_scalar_rasters_agree_bit_for_bit(seed in 1u64..u64::MAX, tilt in 0.0f32..50.0) {
            let mut rng = crate::rng::XorShift(seed);
            let mut rand = || rng.unit();
            let mut r = OccluderRaster::new(40, 36);
            for _ in 0..6 {
                let (mut tris, neighbours) = match (rand() * 3.0) as u32 {
                    0 => fan(40.0 * rand(), 36.0 * rand(), 1.0 + 14.0 * rand(), 3 + (rand() * 30.0) as usize, rand()),
                    1 => square(40.0 * rand(), 40.0 * rand(), rand()),
                    _ => ramp(),
                };
                for t in &mut tris {
                    t.iter_mut().for_each(|v| v.z += tilt * 1e-3 * v.x * v.y.sin());
                }
                r.add(&tris, &neighbours);
            }
            let simd = r.clone().with_path(Path::Simd).finish();
            let scalar = r.with_path(Path::Scalar).finish();
            proptest::prop_assert_eq!(bits(&simd), bits(&scalar));
        }
    }

    #[test]
    fn a_pixel_where_many_edges_meet_is_covered() {
        // Fans centred on pixel (8, 8): every spoke crosses it; above MAX_EDGED the pixel's
        // fragments are taken as one component.
        for k in [40, 100] {
            let (tris, neighbours) = fan(8.5, 8.5, 6.0, k, 0.5);
            let mut r = OccluderRaster::new(16, 16);
            r.add(&tris, &neighbours);
            let maps = r.finish();
            assert_eq!(maps.covered[8 * 16 + 8], 1, "{k} spokes");
            let z = maps.depth[8 * 16 + 8];
            // The fan's farthest depth over the pixel, never nearer.
            assert!((0.5..=0.5101).contains(&z), "{k} spokes: depth {z}");
        }
    }

    #[test]
    fn inner_edges_do_not_cut_coverage() {
        let (tris, neighbours) = square(2.0, 10.0, 0.3);
        let mut r = OccluderRaster::new(12, 12);
        r.add(&tris, &neighbours);
        let maps = r.finish();
        let count: usize = maps.covered.iter().map(|&c| c as usize).sum();
        // Pixels 2..10 are inside, but the ones the sides touch (2 and 9, widened) are not counted.
        assert_eq!(count, 6 * 6);
        assert!(maps.depth.iter().zip(&maps.covered).all(|(&d, &c)| if c == 1 {
            (d - 0.3).abs() < 1e-6
        } else {
            d.is_infinite()
        }));
    }

    #[test]
    fn a_hidden_square_neither_cuts_coverage_nor_pushes_depth() {
        let mut r = OccluderRaster::new(16, 16);
        let (near, near_n) = square(1.0, 15.0, 0.2);
        let (far, far_n) = square(5.0, 9.0, 0.9);
        r.add(&near, &near_n);
        r.add(&far, &far_n);
        let maps = r.finish();
        // The far square's sides lie over the near square: they cut nothing, and depth stays near.
        assert_eq!(maps.covered.iter().map(|&c| c as usize).sum::<usize>(), 12 * 12);
        assert!(maps.depth.iter().zip(&maps.covered).all(|(&d, &c)| c == 0 || (d - 0.2).abs() < 1e-6));
    }

    #[test]
    fn a_surface_overlapping_itself_is_bounded_by_its_near_layer() {
        let (tris, neighbours) = ramp();
        let mut r = OccluderRaster::new(32, 32);
        r.add(&tris, &neighbours);
        let maps = r.finish();
        // Over the overlap (angles 100..180 degrees, away from the rims), and across the far layer's
        // end at 180 degrees (an outline edge under the near layer, which goes on to 210 and
        // beyond), every pixel is covered, at the near layer's depth.
        let mut overlap = 0;
        for y in 0..32 {
            for x in 0..32 {
                let (dx, dy) = (x as f32 + 0.5 - 16.0, y as f32 + 0.5 - 16.0);
                let (r, a) = (dx.hypot(dy), dy.atan2(dx).to_degrees());
                if maps.covered[y * 32 + x] == 1 {
                    assert_eq!(coverage(&tris, x, y, 16), 1.0);
                }
                if (8.0..12.0).contains(&r) && ((100.0..=180.0).contains(&a) || (-180.0..-150.0).contains(&a)) {
                    assert_eq!(maps.covered[y * 32 + x], 1, "pixel {x},{y}");
                    assert!(maps.depth[y * 32 + x] < 0.5, "pixel {x},{y}: depth {}", maps.depth[y * 32 + x]);
                    overlap += 1;
                }
            }
        }
        assert!(overlap > 10);
    }

    #[test]
    fn pixels_left_to_the_exact_test_are_found_in_any_rectangle() {
        let mut rng = crate::rng::XorShift(7);
        for w in [1, 5, 63, 64, 65, 130] {
            let mut patch = Patch::default();
            patch.reset(0, 0, w, 4);
            let mut set = vec![false; w * 4];
            for slot in 0..(w as u32 / 3).max(1) {
                let (x, y) = (rng.next_u64() as usize % w, rng.next_u64() as usize % 4);
                patch.leave_to_exact(x, y, slot);
                set[y * w + x] = true;
            }
            for _ in 0..200 {
                let (mut x0, mut x1) = (rng.next_u64() as usize % w, rng.next_u64() as usize % w);
                let (mut y0, mut y1) = (rng.next_u64() as usize % 4, rng.next_u64() as usize % 4);
                (x0, x1, y0, y1) = (x0.min(x1), x0.max(x1), y0.min(y1), y0.max(y1));
                let brute = (y0..=y1).any(|y| (x0..=x1).any(|x| set[y * w + x]));
                assert_eq!(patch.any_exact(PixelRect { x0, y0, x1, y1 }), brute, "{w} wide: {x0}..={x1} x {y0}..={y1}");
                let row: Vec<usize> = (x0..=x1).filter(|&x| set[y0 * w + x]).collect();
                let span = row.first().zip(row.last()).map(|(&a, &b)| (a, b));
                assert_eq!(patch.exact_span(y0, x0, x1), span, "{w} wide: {x0}..={x1} in row {y0}");
            }
        }
    }

    #[test]
    fn patches_are_the_connected_triangles_largest_first() {
        // Triangles 0-1-4 joined in a chain, 2 alone, 3-5 joined; a triangle's neighbour names it
        // back.
        let mut raster = OccluderRaster::new(8, 8);
        let t = [Vec3::ZERO, Vec3::X, Vec3::Y];
        raster.add(
            &[t; 6],
            &[[1, NONE, NONE], [0, 4, NONE], [NONE; 3], [5, NONE, NONE], [1, NONE, NONE], [3, NONE, NONE]],
        );
        let (triangles, patches) = raster.patches();
        let groups: Vec<&[u32]> = patches.into_iter().map(|p| &triangles[p]).collect();
        assert_eq!(groups, [&[0, 1, 4][..], &[3, 5], &[2]]);
    }
}
