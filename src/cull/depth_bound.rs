//! Depth bounds per culling pixel: a lower bound of a box's or a triangle's depth, for the depth
//! test of a node whose nearest depth alone is in front of some occluder depth over its rectangle,
//! and an upper bound of a box's ([`FarBound`]), to find a node in front of the occluders.
//!
//! - Boxes in organ space; pixels of the culling raster (x right, y down, pixel (i, j) covers
//!   [i, i+1) x [j, j+1)); depth = NDC z (larger is farther).
//! - The lower bound serves a tilted box over a tilted occluder surface; below a node in front of
//!   the occluders nothing can be hidden.
//! - A triangle's NDC depth is linear in screen position, so over a pixel's square its least value
//!   is at a corner.
//! - A ray from the eye enters a convex box where it crosses the last of the box's faces that face
//!   the eye (Cyrus-Beck), so along any ray that meets the box its depth is at least each such
//!   face's plane depth on that ray, also linear in screen position (projection maps planes to
//!   planes).
//! - The same holds for the intersection of the box with a slab holding the same triangles
//!   ([`Slab`], two parallel planes across their mean normal): the slab's face toward the eye is
//!   one more such plane.
//! - The bound at a pixel is the largest of these over the (at most four) front faces, and never
//!   less than the box's nearest corner depth.
//! - The upper bound is the mirror image: the smallest over the far faces, where rays leave.

use super::raster::Triangle;
use super::rect::PixelRect;
use crate::bvh::Slab;
use crate::mesh::Bounds;
use glam::{DMat4, DVec3, DVec4, Vec3, Vec4};

/// Planes steeper than this (NDC depth per culling pixel) are left out: nearly edge-on, they
/// bound nothing and their coefficients lose precision.
const MAX_SLOPE: f64 = 1.0;

/// Subtracted from every bound against rounding (NDC depth; depth maps hold f32 values near 1).
const EPS: f32 = 1e-6;

/// The depth bound of one box or triangle over the pixels of a `width` x `height` raster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthBound {
    /// Per plane (a box's and its slab's front faces, or a triangle's own), lane by lane: its
    /// least value over pixel (x, y) is c + a x + b y. Lanes without a plane hold the nearest
    /// corner depth (a = b = 0).
    planes: Planes,
    /// The nearest corner depth.
    nearest: f32,
}

/// Up to four planes z = c + a x + b y over the culling pixels, one per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Planes {
    c: Vec4,
    a: Vec4,
    b: Vec4,
    count: usize,
}

impl Planes {
    /// No plane: every lane the constant `z`.
    fn constant(z: f32) -> Planes {
        Planes { c: Vec4::splat(z), a: Vec4::ZERO, b: Vec4::ZERO, count: 0 }
    }

    fn push(&mut self, [c, a, b]: [f32; 3]) {
        (self.c[self.count], self.a[self.count], self.b[self.count]) = (c, a, b);
        self.count += 1;
    }

    /// Each plane's value at pixel (x, y).
    fn at(&self, x: usize, y: usize) -> Vec4 {
        self.c + self.a * x as f32 + self.b * y as f32
    }
}

impl DepthBound {
    /// The bound for box `b` (and, where given, a slab holding the same triangles) seen through
    /// `inverse` (of its model-view-projection matrix) from `eye` (in organ space), with nearest
    /// corner depth `nearest`.
    pub fn of_box(
        inverse: &Unprojection,
        eye: Vec3,
        b: &Bounds,
        slab: Option<&Slab>,
        nearest: f32,
        width: usize,
        height: usize,
    ) -> DepthBound {
        let mut bound = DepthBound { planes: Planes::constant(nearest), nearest };
        for (normal, d) in faces(eye, b, slab, Side::Near).into_iter().flatten() {
            if let Some([c, a, b]) = screen_plane(inverse, normal, d, width, height) {
                bound.add_plane(c, a, b);
            }
        }
        bound
    }

    /// The bound for a projected triangle.
    pub fn of_triangle(t: &Triangle) -> DepthBound {
        let nearest = t[0].z.min(t[1].z).min(t[2].z);
        let mut bound = DepthBound { planes: Planes::constant(nearest), nearest };
        let (e1, e2) = ((t[1] - t[0]).as_dvec3(), (t[2] - t[0]).as_dvec3());
        let area = e1.x * e2.y - e2.x * e1.y;
        // z = z0 + a (x - x0) + b (y - y0).
        let a = (e1.z * e2.y - e2.z * e1.y) / area;
        let b = (e2.z * e1.x - e1.z * e2.x) / area;
        let o = t[0].as_dvec3();
        bound.add_plane(o.z - a * o.x - b * o.y, a, b);
        bound
    }

    /// Adds the plane z = c + a x + b y (x, y at any point of the raster), as its least value over
    /// each pixel, unless it is too steep to bound anything.
    fn add_plane(&mut self, c: f64, a: f64, b: f64) {
        if let Some(plane) = over_pixel([c, a, b], -1.0) {
            self.planes.push(plane);
        }
    }

    /// The least depth of the box or triangle on any ray through pixel (x, y) that meets it.
    pub fn at(&self, x: usize, y: usize) -> f32 {
        self.planes.at(x, y).max_element().max(self.nearest) - EPS
    }

    /// Whether every pixel of the inclusive rectangle holds an occluder depth in front of this.
    pub fn behind(&self, depth: &[f32], width: usize, r: PixelRect) -> bool {
        let PixelRect { x0, y0, x1, y1 } = r;
        (y0..=y1).all(|y| (x0..=x1).all(|x| depth[y * width + x] < self.at(x, y)))
    }
}

/// Which faces of a box (and slab) [`faces`] lists.
#[derive(Clone, Copy, PartialEq)]
enum Side {
    /// Those facing the eye, where rays enter.
    Near,
    /// Those facing away, where rays leave.
    Far,
}

/// The planes `normal . p = d` (organ space) of the faces of box `b` and `slab` on `side` as seen
/// from `eye`: on each axis (and across the slab) where the eye lies outside their extent.
fn faces(eye: Vec3, b: &Bounds, slab: Option<&Slab>, side: Side) -> [Option<(DVec3, f32)>; 4] {
    // Of the extent lo..hi along `normal`, the face on `side`, if the eye at `e` lies outside it.
    let face = |normal: DVec3, e: f32, lo: f32, hi: f32| {
        let (toward, away) = if e < lo {
            (lo, hi)
        } else if e > hi {
            (hi, lo)
        } else {
            return None;
        };
        Some((normal, if side == Side::Near { toward } else { away }))
    };
    let axis = |k: usize| face(DVec3::AXES[k], eye[k], b.min[k], b.max[k]);
    let slab = slab.and_then(|s| face(s.normal.as_dvec3(), s.normal.dot(eye), s.min, s.max));
    [axis(0), axis(1), axis(2), slab]
}

/// The inverse of a model-view-projection matrix, kept by rows (in double precision): it takes a
/// plane of organ space to NDC.
#[derive(Clone, Copy, Debug)]
pub struct Unprojection {
    /// The inverse's rows, as columns.
    rows: DMat4,
}

impl Unprojection {
    pub fn of(mvp: &glam::Mat4) -> Unprojection {
        Unprojection { rows: mvp.as_dmat4().inverse().transpose() }
    }
}

/// The NDC depth of the plane `normal . p = d` of organ space (seen through `inverse`) as
/// `[c, a, b]`: depth c + a x + b y at culling pixel position (x, y).
fn screen_plane(inverse: &Unprojection, normal: DVec3, d: f32, width: usize, height: usize) -> Option<[f64; 3]> {
    let (w, h) = (width as f64, height as f64);
    // Points (X, Y, Z) in NDC on the plane satisfy q . (X, Y, Z, 1) = 0.
    let r = &inverse.rows;
    let q: DVec4 = normal.x * r.x_axis + normal.y * r.y_axis + normal.z * r.z_axis - d as f64 * r.w_axis;
    if q.z == 0.0 {
        return None;
    }
    // Z = -(q.x X + q.y Y + q.w) / q.z with X = 2 x / w - 1 and Y = 1 - 2 y / h.
    Some([(q.x - q.y - q.w) / q.z, -2.0 * q.x / (w * q.z), 2.0 * q.y / (h * q.z)])
}

/// The plane z = c + a x + b y as its least (`side` -1) or greatest (`side` +1) value over each
/// pixel's square: at its centre, less or plus half the slope across it; `None` where it is too
/// steep to bound anything.
fn over_pixel([c, a, b]: [f64; 3], side: f64) -> Option<[f32; 3]> {
    if !(a.is_finite() && b.is_finite() && c.is_finite()) || a.abs() + b.abs() > MAX_SLOPE {
        return None;
    }
    let c = c + 0.5 * (a + b) + side * 0.5 * (a.abs() + b.abs());
    Some([c as f32, a as f32, b as f32])
}

/// An upper bound of the depth of a box's triangles at each culling pixel: along a ray that meets
/// the box and its slab, where it leaves them. On an axis where the eye lies outside the box's
/// extent, the ray crosses the box's far face there after leaving, so each such far face's plane
/// bounds it from above; so does the slab's far face where the eye lies outside the slab, and the
/// farthest corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarBound {
    /// Per far face, lane by lane: its greatest value over pixel (x, y) is c + a x + b y. Lanes
    /// without a face hold the farthest corner depth.
    planes: Planes,
    farthest: f32,
}

impl FarBound {
    /// The bound for box `b` and `slab` seen through `inverse` from `eye` (in organ space), with
    /// farthest corner depth `farthest`.
    pub fn of_box(
        inverse: &Unprojection,
        eye: Vec3,
        b: &Bounds,
        slab: &Slab,
        farthest: f32,
        width: usize,
        height: usize,
    ) -> FarBound {
        let mut bound = FarBound { planes: Planes::constant(farthest), farthest };
        for (normal, d) in faces(eye, b, Some(slab), Side::Far).into_iter().flatten() {
            if let Some(plane) = screen_plane(inverse, normal, d, width, height).and_then(|p| over_pixel(p, 1.0)) {
                bound.planes.push(plane);
            }
        }
        bound
    }

    /// The greatest depth of the box on any ray through pixel (x, y) that meets it.
    pub fn at(&self, x: usize, y: usize) -> f32 {
        self.planes.at(x, y).min_element().min(self.farthest) + EPS
    }

    /// Whether the box lies in front of the occluders wherever they cover the inclusive rectangle:
    /// then nothing inside it can be hidden.
    pub fn in_front(&self, depth: &[f32], width: usize, r: PixelRect) -> bool {
        let PixelRect { x0, y0, x1, y1 } = r;
        (y0..=y1).all(|y| (x0..=x1).all(|x| self.at(x, y) < depth[y * width + x]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::XorShift;
    use glam::Mat4;

    /// Where the ray from `eye` along `dir` enters the box and the slab, if it meets both (slab
    /// tests: the entry is the last of the entries into each pair of planes).
    fn entry(eye: Vec3, dir: Vec3, b: &Bounds, slab: &Slab) -> Option<Vec3> {
        let (mut t0, mut t1) = (0.0f32, f32::INFINITY);
        let mut clip = |lo: f32, hi: f32| {
            t0 = t0.max(lo.min(hi));
            t1 = t1.min(lo.max(hi));
        };
        for k in 0..3 {
            clip((b.min[k] - eye[k]) / dir[k], (b.max[k] - eye[k]) / dir[k]);
        }
        let (e, d) = (slab.normal.dot(eye), slab.normal.dot(dir));
        clip((slab.min - e) / d, (slab.max - e) / d);
        (t0 <= t1).then(|| eye + dir * t0)
    }

    #[test]
    fn bounds_hold_the_depths_of_every_point_of_box_and_slab() {
        let mut rng = XorShift(5);
        let mut rand = || rng.unit();
        let (w, h) = (64, 48);
        let (mut hits, mut useful, mut tighter, mut below_far) = (0, 0, 0, 0);
        for _ in 0..200 {
            let eye = Vec3::new(rand() - 0.5, rand() - 0.5, 0.5 + rand()) * 40.0;
            let centre = Vec3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5) * 10.0;
            let half = Vec3::new(0.5 + rand() * 4.0, 0.5 + rand() * 4.0, 0.2 + rand() * 4.0);
            let b = Bounds { min: (centre - half).into(), max: (centre + half).into() };
            let model = Mat4::from_rotation_z(rand() * 6.0) * Mat4::from_rotation_x(rand() - 0.5);
            let world_eye = model.transform_point3(eye);
            let view = Mat4::look_at_rh(world_eye, model.transform_point3(centre), Vec3::Y);
            let mvp = Mat4::perspective_rh(0.8, w as f32 / h as f32, 5.0, 120.0) * view * model;
            let nearest = b.corners().iter().map(|&c| mvp.project_point3(c).z).fold(f32::INFINITY, f32::min);
            // A thin slab across the box, tilted at random, through a random point of it.
            let normal = Vec3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5).normalize();
            let through = normal.dot(centre + Vec3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5) * half);
            let slab = Slab { normal, min: through - 0.3 * rand(), max: through + 0.3 * rand() };
            let inverse = Unprojection::of(&mvp);
            let box_only = DepthBound::of_box(&inverse, eye, &b, None, nearest, w, h);
            let bound = DepthBound::of_box(&inverse, eye, &b, Some(&slab), nearest, w, h);
            let farthest = b.corners().iter().map(|&c| mvp.project_point3(c).z).fold(f32::NEG_INFINITY, f32::max);
            let far = FarBound::of_box(&inverse, eye, &b, &slab, farthest, w, h);
            // Rays through random points of the box and the slab, seen in whatever pixel they fall.
            for _ in 0..400 {
                let inner = Vec3::from(b.min) + Vec3::new(rand(), rand(), rand()) * 2.0 * half;
                if !(slab.min..=slab.max).contains(&normal.dot(inner)) {
                    continue;
                }
                let s = mvp.project_point3(inner);
                let (sx, sy) = ((s.x + 1.0) * 0.5 * w as f32, (1.0 - s.y) * 0.5 * h as f32);
                if !(0.0..w as f32).contains(&sx) || !(0.0..h as f32).contains(&sy) {
                    continue;
                }
                let (x, y) = (sx as usize, sy as usize);
                // Every point of the box and slab lies no farther than the far bound.
                assert!(far.at(x, y) >= s.z - 1e-6, "pixel {x},{y}: far bound {} before depth {}", far.at(x, y), s.z);
                below_far += usize::from(far.at(x, y) < farthest - 1e-4);
                let dir = (inner - eye).normalize();
                if let Some(p) = entry(eye, dir, &b, &slab) {
                    hits += 1;
                    let z = mvp.project_point3(p).z;
                    assert!(bound.at(x, y) <= z + 1e-6, "pixel {x},{y}: bound {} over entry depth {z}", bound.at(x, y));
                    useful += usize::from(box_only.at(x, y) > nearest + 1e-4);
                    tighter += usize::from(bound.at(x, y) > box_only.at(x, y) + 1e-4);
                }
            }
        }
        assert!(hits > 4000, "only {hits} rays met their boxes");
        // Tilted boxes: the box's bound is often well behind the nearest corner, and the slab's
        // often behind that.
        assert!(useful > hits / 4, "box bound beyond the nearest corner on only {useful} of {hits} rays");
        assert!(tighter > hits / 4, "slab bound beyond the box's on only {tighter} of {hits} rays");
        assert!(below_far > hits / 4, "far bound before the farthest corner on only {below_far} of {hits} rays");
    }

    #[test]
    fn triangle_bound_never_exceeds_its_depth() {
        let mut rng = XorShift(11);
        let mut rand = || rng.unit();
        let mut tight = 0;
        for _ in 0..500 {
            let corner = |r: &mut dyn FnMut() -> f32| Vec3::new(r() * 32.0, r() * 32.0, 0.9 + 0.1 * r());
            let t = [corner(&mut rand), corner(&mut rand), corner(&mut rand)];
            let bound = DepthBound::of_triangle(&t);
            for _ in 0..20 {
                // A point of the triangle, by barycentric coordinates.
                let (u, v) = (rand(), rand());
                let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
                let p = t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
                let b = bound.at(p.x as usize, p.y as usize);
                assert!(b <= p.z + 1e-6, "bound {b} over depth {} at {p}", p.z);
                tight += usize::from(b > bound.nearest + 1e-3);
            }
        }
        assert!(tight > 1000, "the plane raised the bound above the nearest corner only {tight} times");
    }
}
