//! The software occluder rasteriser, in culling pixels (x right, y down, pixel (i, j) covers
//! [i, i+1) x [j, j+1); depth = NDC z, larger is farther). It is conservative by construction.
//!
//! Occluders come as *patches*: connected sets of triangles that all project with the same winding
//! (the front side of an organ's surface, say). The outline of a patch's image lies on its outline
//! edges, the edges whose neighbour across is not in the patch. Per patch:
//!
//! * a pixel is **covered** if its centre is inside a triangle of the patch and no outline edge of
//!   the patch touches it: a square that holds a point of the image and meets none of its outline
//!   lies wholly inside it;
//! * its **depth** is the farthest the patch's triangles reach over that pixel (each triangle's
//!   depth plane at the pixel's corners, capped by its vertices), so every point of the patch seen
//!   in the pixel is at least that near.
//!
//! Patches merge by union: a pixel is covered if some patch covers it, with the nearest such bound.

use glam::Vec3;

/// A projected occluder triangle: x, y in culling pixels, z = NDC depth.
pub type Triangle = [Vec3; 3];

/// Coverage and depth of occluders at low resolution, built patch by patch.
#[derive(Clone, Debug, PartialEq)]
pub struct OccluderRaster {
    pub width: usize,
    pub height: usize,
    covered: Vec<u8>,
    depth: Vec<f32>,
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

/// Margin (pixels) by which outline edges are widened against rounding.
const EPS: f32 = 1e-3;

/// One patch rasterised over its bounding rectangle of pixels.
struct Patch {
    x0: usize,
    y0: usize,
    w: usize,
    h: usize,
    centre: Vec<bool>,
    outline: Vec<bool>,
    depth: Vec<f32>,
}

impl Patch {
    fn triangle(&mut self, t: &Triangle) {
        let min = t[0].min(t[1]).min(t[2]);
        let max = t[0].max(t[1]).max(t[2]);
        let area = (t[1].x - t[0].x) * (t[2].y - t[0].y) - (t[2].x - t[0].x) * (t[1].y - t[0].y);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        // Edge functions, positive inside whatever the winding.
        let s = area.signum();
        let edge = |a: Vec3, b: Vec3| {
            let (ea, eb) = ((a.y - b.y) * s, (b.x - a.x) * s);
            (ea, eb, -(ea * a.x + eb * a.y))
        };
        let edges = [edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])];
        // Depth plane z = z0 + dzdx (x - x0) + dzdy (y - y0).
        let dzdx = ((t[1].z - t[0].z) * (t[2].y - t[0].y) - (t[2].z - t[0].z) * (t[1].y - t[0].y)) / area;
        let dzdy = ((t[2].z - t[0].z) * (t[1].x - t[0].x) - (t[1].z - t[0].z) * (t[2].x - t[0].x)) / area;
        let zmax = t[0].z.max(t[1].z).max(t[2].z);
        let clamp_x = |v: f32| (v.max(self.x0 as f32) as usize).clamp(self.x0, self.x0 + self.w - 1);
        let clamp_y = |v: f32| (v.max(self.y0 as f32) as usize).clamp(self.y0, self.y0 + self.h - 1);
        let (x0, x1) = (clamp_x(min.x.floor()), clamp_x(max.x.ceil() - 1.0));
        let (y0, y1) = (clamp_y(min.y.floor()), clamp_y(max.y.ceil() - 1.0));
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
                // Touches the square: no edge has the whole square outside.
                if !edges.iter().all(|&(a, b, c)| a * cx + b * cy + c + 0.5 * (a.abs() + b.abs()) >= 0.0) {
                    continue;
                }
                let i = (y - self.y0) * self.w + (x - self.x0);
                if edges.iter().all(|&(a, b, c)| a * cx + b * cy + c >= 0.0) {
                    self.centre[i] = true;
                }
                let z = t[0].z + dzdx * (cx - t[0].x) + dzdy * (cy - t[0].y) + 0.5 * (dzdx.abs() + dzdy.abs());
                let z = if z.is_finite() { z.min(zmax) } else { zmax };
                if z > self.depth[i] {
                    self.depth[i] = z;
                }
            }
        }
    }

    /// Marks every pixel the segment a-b touches (widened by a small margin) as on the outline.
    fn outline_edge(&mut self, a: Vec3, b: Vec3) {
        let (xs, ys) = (self.x0 as f32, self.y0 as f32);
        let (xe, ye) = (xs + self.w as f32, ys + self.h as f32);
        let (ymin, ymax) = (a.y.min(b.y) - EPS, a.y.max(b.y) + EPS);
        if ymax < ys || ymin >= ye || a.x.max(b.x) + EPS < xs || a.x.min(b.x) - EPS >= xe {
            return;
        }
        let (r0, r1) = (ymin.floor().max(ys) as usize, ymax.floor().min(ye - 1.0) as usize);
        for row in r0..=r1 {
            let (lo, hi) = (row as f32 - EPS, row as f32 + 1.0 + EPS);
            // The part of the segment inside this row band.
            let (xa, xb) = if (b.y - a.y).abs() < 1e-12 {
                (a.x, b.x)
            } else {
                let ta = ((lo - a.y) / (b.y - a.y)).clamp(0.0, 1.0);
                let tb = ((hi - a.y) / (b.y - a.y)).clamp(0.0, 1.0);
                (a.x + (b.x - a.x) * ta, a.x + (b.x - a.x) * tb)
            };
            let (xl, xr) = (xa.min(xb) - EPS, xa.max(xb) + EPS);
            if xr < xs || xl >= xe {
                continue;
            }
            let (c0, c1) = (xl.floor().max(xs) as usize - self.x0, xr.floor().min(xe - 1.0) as usize - self.x0);
            let at = (row - self.y0) * self.w;
            self.outline[at + c0..=at + c1].fill(true);
        }
    }
}

impl OccluderRaster {
    pub fn new(width: usize, height: usize) -> OccluderRaster {
        let n = width * height;
        OccluderRaster { width, height, covered: vec![0; n], depth: vec![f32::INFINITY; n] }
    }

    /// Adds one patch: its triangles (one winding) and its outline edges.
    pub fn patch(&mut self, triangles: &[Triangle], outline: &[[Vec3; 2]]) {
        let (w, h) = (self.width as f32, self.height as f32);
        let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for t in triangles {
            for p in t {
                (min, max) = (min.min(*p), max.max(*p));
            }
        }
        if !(min.is_finite() && max.is_finite()) || max.x <= 0.0 || max.y <= 0.0 || min.x >= w || min.y >= h {
            return;
        }
        let (x0, y0) = (min.x.floor().max(0.0) as usize, min.y.floor().max(0.0) as usize);
        let (x1, y1) = ((max.x.ceil().min(w) as usize).max(x0 + 1), (max.y.ceil().min(h) as usize).max(y0 + 1));
        let (pw, ph) = (x1 - x0, y1 - y0);
        let mut p = Patch {
            x0,
            y0,
            w: pw,
            h: ph,
            centre: vec![false; pw * ph],
            outline: vec![false; pw * ph],
            depth: vec![f32::NEG_INFINITY; pw * ph],
        };
        for t in triangles {
            p.triangle(t);
        }
        for [a, b] in outline {
            p.outline_edge(*a, *b);
        }
        for y in 0..ph {
            for x in 0..pw {
                let i = y * pw + x;
                if p.centre[i] && !p.outline[i] {
                    let j = (y0 + y) * self.width + x0 + x;
                    self.covered[j] = 1;
                    self.depth[j] = self.depth[j].min(p.depth[i]);
                }
            }
        }
    }

    pub fn finish(self) -> OccluderMaps {
        OccluderMaps { width: self.width, height: self.height, covered: self.covered, depth: self.depth }
    }
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

    /// A fan of triangles around a centre (a closed polygon of one winding): its rim is the outline.
    fn fan(cx: f32, cy: f32, r: f32, k: usize, z: f32) -> (Vec<Triangle>, Vec<[Vec3; 2]>) {
        let p = |i: usize| {
            let a = i as f32 / k as f32 * std::f32::consts::TAU;
            Vec3::new(cx + r * a.cos(), cy + r * a.sin(), z + 0.01 * a.sin())
        };
        let c = Vec3::new(cx, cy, z);
        let tris = (0..k).map(|i| [c, p(i), p(i + 1)]).collect();
        let rim = (0..k).map(|i| [p(i), p(i + 1)]).collect();
        (tris, rim)
    }

    #[test]
    fn coverage_never_exceeds_a_fine_reference() {
        let mut rng = crate::rng::XorShift(7);
        let mut rand = || rng.unit();
        for _ in 0..30 {
            let (tris, rim) =
                fan(4.0 + 24.0 * rand(), 4.0 + 24.0 * rand(), 2.0 + 12.0 * rand(), 5 + (rand() * 20.0) as usize, 0.5);
            let mut r = OccluderRaster::new(32, 32);
            r.patch(&tris, &rim);
            let maps = r.finish();
            let mut covered = 0;
            for y in 0..32 {
                for x in 0..32 {
                    if maps.covered[y * 32 + x] == 1 {
                        covered += 1;
                        assert_eq!(coverage(&tris, x, y, 16), 1.0, "pixel {x},{y} counted covered but is not");
                        // Depth is at least the farthest triangle vertex nearby... and never nearer
                        // than the surface: the fan's depth varies in 0.49..=0.51.
                        assert!(maps.depth[y * 32 + x] >= 0.49 && maps.depth[y * 32 + x] <= 0.5101);
                    }
                }
            }
            let _ = covered;
        }
    }

    #[test]
    fn inner_edges_do_not_cut_coverage() {
        // A square of two triangles: only its four sides are outline.
        let q = [
            Vec3::new(2.0, 2.0, 0.3),
            Vec3::new(10.0, 2.0, 0.3),
            Vec3::new(10.0, 10.0, 0.3),
            Vec3::new(2.0, 10.0, 0.3),
        ];
        let mut r = OccluderRaster::new(12, 12);
        let sides: Vec<[Vec3; 2]> = (0..4).map(|i| [q[i], q[(i + 1) % 4]]).collect();
        r.patch(&[[q[0], q[1], q[2]], [q[0], q[2], q[3]]], &sides);
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
}

#[cfg(test)]
mod patch_tests {
    use super::*;

    #[test]
    fn a_hidden_patch_neither_cuts_coverage_nor_pushes_depth() {
        let sq = |x0: f32, x1: f32, z: f32| {
            let q = [Vec3::new(x0, x0, z), Vec3::new(x1, x0, z), Vec3::new(x1, x1, z), Vec3::new(x0, x1, z)];
            let sides: Vec<[Vec3; 2]> = (0..4).map(|i| [q[i], q[(i + 1) % 4]]).collect();
            (vec![[q[0], q[1], q[2]], [q[0], q[2], q[3]]], sides)
        };
        let mut r = OccluderRaster::new(16, 16);
        let (near, near_rim) = sq(1.0, 15.0, 0.2);
        let (far, far_rim) = sq(5.0, 9.0, 0.9);
        r.patch(&near, &near_rim);
        r.patch(&far, &far_rim);
        let maps = r.finish();
        // The far square's sides lie over the near square: they cut nothing, and depth stays near.
        assert_eq!(maps.covered.iter().map(|&c| c as usize).sum::<usize>(), 12 * 12);
        assert!(maps.depth.iter().zip(&maps.covered).all(|(&d, &c)| c == 0 || (d - 0.2).abs() < 1e-6));
    }
}
