//! The software occluder rasteriser, in culling pixels (x right, y down, pixel (i, j) covers
//! [i, i+1) x [j, j+1); depth = NDC z, larger is farther). It is conservative by construction.
//!
//! Occluders come as triangles that all project with the same winding (the camera-facing side of
//! organ surfaces), each with its neighbours across its three edges that are occluders too. Each
//! triangle leaves a *fragment* in every pixel it touches: its farthest depth over the pixel (its
//! depth plane at the pixel's corners, capped by its vertices), whether it holds the pixel's centre,
//! and which of its edges touch the pixel.
//!
//! Per pixel, fragments joined across edges that touch the pixel form local components. A
//! component none of whose touching edges leads to a triangle outside it (an outline edge, or a
//! neighbour that does not reach the pixel) has no border inside the pixel; if it also holds the
//! centre, the square holds a point of its image and meets none of its outline, so it lies wholly
//! inside that image. The pixel is then **covered**, and its **depth** is the farthest depth of the
//! component; of several such components the nearest counts. Components are local, so a surface
//! that overlaps itself on screen (the near wall of a shell joined round its rim to the far wall)
//! bounds a pixel by its near layer alone.

use crate::bvh::NONE;
use glam::Vec3;

/// A projected occluder triangle: x, y in culling pixels, z = NDC depth.
pub type Triangle = [Vec3; 3];

/// Coverage and depth of occluders at low resolution, collected triangle by triangle.
#[derive(Clone, Debug, PartialEq)]
pub struct OccluderRaster {
    pub width: usize,
    pub height: usize,
    triangles: Vec<Triangle>,
    /// Per triangle added, its occluder neighbours (indices among all triangles added, or NONE).
    neighbours: Vec<[u32; 3]>,
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

/// Margin (in pixel widths) by which triangles and edges are widened against rounding.
const EPS: f32 = 1e-3;

/// One edge of a triangle: its edge function a x + b y + c (positive inside), how far from its
/// line a widened pixel square may reach, and its box widened by [`EPS`].
#[derive(Clone, Copy, Debug)]
struct Edge {
    a: f32,
    b: f32,
    c: f32,
    reach: f32,
    x_lo: f32,
    x_hi: f32,
    y_lo: f32,
    y_hi: f32,
}

impl Edge {
    /// The edge from `p` to `q` of a triangle whose signed area has sign `s`.
    fn new(p: Vec3, q: Vec3, s: f32) -> Edge {
        let (a, b) = ((p.y - q.y) * s, (q.x - p.x) * s);
        Edge {
            a,
            b,
            c: -(a * p.x + b * p.y),
            reach: (0.5 + EPS) * (a.abs() + b.abs()),
            x_lo: p.x.min(q.x) - EPS,
            x_hi: p.x.max(q.x) + EPS,
            y_lo: p.y.min(q.y) - EPS,
            y_hi: p.y.max(q.y) + EPS,
        }
    }
}

/// One triangle over one pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Fragment {
    pixel: u32,
    triangle: u32,
    /// Farthest depth of the triangle over the pixel.
    z: f32,
    /// The pixel's centre lies inside the triangle.
    centre: bool,
    /// Bit k: edge k (corner k to corner k + 1) touches the pixel.
    edges: u8,
}

impl OccluderRaster {
    pub fn new(width: usize, height: usize) -> OccluderRaster {
        OccluderRaster { width, height, triangles: Vec::new(), neighbours: Vec::new() }
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

    /// Appends the fragments of triangle `id` to `out`, in row order.
    fn fragments_of(&self, out: &mut Vec<Fragment>, id: u32, t: &Triangle) {
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
            return;
        }
        // Edge functions, positive inside whatever the winding; `reach` is how far from the line
        // (in edge-function units) a widened square centred at a point may still meet it.
        let s = area.signum();
        let edges = [0, 1, 2].map(|k| Edge::new(t[k], t[(k + 1) % 3], s));
        // Depth plane z = z0 + dzdx (x - x0) + dzdy (y - y0).
        let dzdx = ((t[1].z - t[0].z) * (t[2].y - t[0].y) - (t[2].z - t[0].z) * (t[1].y - t[0].y)) / area;
        let dzdy = ((t[2].z - t[0].z) * (t[1].x - t[0].x) - (t[1].z - t[0].z) * (t[2].x - t[0].x)) / area;
        let slope = 0.5 * (dzdx.abs() + dzdy.abs());
        let zmax = max.z;
        let span =
            |lo: f32, hi: f32, n: f32| ((lo - EPS).floor().max(0.0) as usize, (hi + EPS).floor().min(n - 1.0) as usize);
        let (x0, x1) = span(min.x, max.x, w);
        let (y0, y1) = span(min.y, max.y, h);
        for y in y0..=y1 {
            let cy = y as f32 + 0.5;
            // The pixels whose widened square an edge's line leaves wholly outside lie beyond a
            // point on the row; the exact test below runs only between those points (less a pixel).
            let (mut lo, mut hi) = (x0 as f32, x1 as f32);
            for e in &edges {
                // a (x + 0.5) + b cy + c + reach >= 0.
                let at = -(e.b * cy + e.c + e.reach) / e.a - 0.5;
                if e.a > 0.0 {
                    lo = lo.max(at.floor() - 1.0);
                } else if e.a < 0.0 {
                    hi = hi.min(at.ceil() + 1.0);
                }
            }
            if lo.partial_cmp(&hi).is_none_or(|o| o.is_gt()) {
                continue;
            }
            // Per edge: b cy, and whether its box reaches this row (bit k).
            let by = edges.map(|e| e.b * cy);
            let row_mask =
                (0..3).fold(0u8, |m, k| m | (u8::from(edges[k].y_lo <= cy + 0.5 && edges[k].y_hi >= cy - 0.5) << k));
            let dz_row = dzdy * (cy - t[0].y);
            for x in lo as usize..=hi as usize {
                let cx = x as f32 + 0.5;
                let f = [0, 1, 2].map(|k| edges[k].a * cx + by[k] + edges[k].c);
                // Touches the (widened) square: no edge has the whole square outside.
                if (f[0] + edges[0].reach < 0.0) | (f[1] + edges[1].reach < 0.0) | (f[2] + edges[2].reach < 0.0) {
                    continue;
                }
                // An edge touches the square where its line passes within reach of the centre and
                // its box meets the square (none does for a square wholly inside).
                let near = |k: usize| {
                    let e = &edges[k];
                    u8::from(f[k] <= e.reach && e.x_lo <= cx + 0.5 && e.x_hi >= cx - 0.5) << k
                };
                let touching = row_mask & (near(0) | near(1) | near(2));
                let z = t[0].z + dzdx * (cx - t[0].x) + dz_row + slope;
                out.push(Fragment {
                    pixel: (y * self.width + x) as u32,
                    triangle: id,
                    z: if z.is_finite() { z.min(zmax) } else { zmax },
                    centre: (f[0] >= 0.0) & (f[1] >= 0.0) & (f[2] >= 0.0),
                    edges: touching,
                });
            }
        }
    }

    /// Coverage and depth of every pixel (triangles and pixel rows shared among threads).
    pub fn finish(self) -> OccluderMaps {
        use rayon::prelude::*;
        const CHUNK: usize = 128;
        let chunks: Vec<Vec<Fragment>> = self
            .triangles
            .par_chunks(CHUNK)
            .enumerate()
            .map(|(c, tris)| {
                let mut out = Vec::with_capacity(4 * tris.len());
                for (k, t) in tris.iter().enumerate() {
                    self.fragments_of(&mut out, (c * CHUNK + k) as u32, t);
                }
                out
            })
            .collect();
        let n = self.width * self.height;
        // Fragments by pixel (a stable counting sort: by triangle within a pixel).
        let mut start = vec![0u32; n + 1];
        for f in chunks.iter().flatten() {
            start[f.pixel as usize + 1] += 1;
        }
        for p in 0..n {
            start[p + 1] += start[p];
        }
        let mut next = start.clone();
        let mut sorted = vec![EMPTY; start[n] as usize];
        for f in chunks.iter().flatten() {
            sorted[next[f.pixel as usize] as usize] = *f;
            next[f.pixel as usize] += 1;
        }
        let mut covered = vec![0u8; n];
        let mut depth = vec![f32::INFINITY; n];
        // Bands of pixels in parallel; a pixel no fragment reaches stays uncovered.
        const BAND: usize = 2048;
        covered.par_chunks_mut(BAND).zip(depth.par_chunks_mut(BAND)).enumerate().for_each(|(b, (covered, depth))| {
            let mut scratch = Scratch::default();
            for i in 0..covered.len() {
                let p = b * BAND + i;
                let (first, end) = (start[p] as usize, start[p + 1] as usize);
                if first == end {
                    continue;
                }
                if let Some(z) = pixel_depth(&sorted[first..end], &self.neighbours, &mut scratch) {
                    covered[i] = 1;
                    depth[i] = z;
                }
            }
        });
        OccluderMaps { width: self.width, height: self.height, covered, depth }
    }
}

const EMPTY: Fragment = Fragment { pixel: 0, triangle: 0, z: 0.0, centre: false, edges: 0 };

/// Working space of [`pixel_depth`], kept from pixel to pixel.
#[derive(Default)]
struct Scratch {
    /// The pixel's fragments that have an edge in it (by triangle, as the pixel's fragments are).
    edged: Vec<Fragment>,
}

/// Most fragments with an edge in one pixel whose components are told apart (as bit sets).
const MAX_EDGED: usize = 64;

/// The depth bound of a pixel from its fragments (sorted by triangle), if they cover it.
fn pixel_depth(here: &[Fragment], neighbours: &[[u32; 3]], s: &mut Scratch) -> Option<f32> {
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
fn bits(mut b: u64) -> impl Iterator<Item = usize> {
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
        // A ramp winding 1.5 times round a ring, one connected surface: its first half turn
        // (near, z about 0.2) lies over its last (far, z about 0.8) on screen.
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
        let mut r = OccluderRaster::new(32, 32);
        r.add(&tris, &neighbours);
        let maps = r.finish();
        // Over the overlap (angles 90..180 degrees, away from the ramp's ends and rims) every covered
        // pixel takes the near layer's depth.
        let mut overlap = 0;
        for y in 0..32 {
            for x in 0..32 {
                let (dx, dy) = (x as f32 + 0.5 - 16.0, y as f32 + 0.5 - 16.0);
                let (r, a) = (dx.hypot(dy), dy.atan2(dx).to_degrees());
                if maps.covered[y * 32 + x] == 1 {
                    assert_eq!(coverage(&tris, x, y, 16), 1.0);
                }
                if (8.0..12.0).contains(&r) && (100.0..170.0).contains(&a) {
                    assert_eq!(maps.covered[y * 32 + x], 1, "pixel {x},{y}");
                    assert!(maps.depth[y * 32 + x] < 0.5, "pixel {x},{y}: depth {}", maps.depth[y * 32 + x]);
                    overlap += 1;
                }
            }
        }
        assert!(overlap > 10);
    }
}
