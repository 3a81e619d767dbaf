//! Projection into the culling raster: boxes, triangles and points from organ space through a
//! model-view-projection matrix into culling pixels.
//!
//! - Culling pixels: x right, y down; depth = NDC z, larger is farther, 0 at the near plane.
//! - Rectangles are rounded outward (thesis §3.3's conservative rounding).

use super::rect::PixelRect;
use crate::bvh::Bvh;
use crate::mesh::{Bounds, Mesh};
use glam::{Mat4, Vec3, Vec4};

/// Where a box lies on the screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum ScreenBox {
    /// Wholly outside one frustum plane.
    Outside,
    /// Reaches behind the eye: cannot be placed on screen.
    Straddles,
    /// Inclusive pixel rectangle (rounded outward, clamped), nearest and farthest NDC depth;
    /// `inside`: wholly inside the frustum.
    Rect { rect: PixelRect, z: f32, far: f32, inside: bool },
}

pub(crate) fn project_box(mvp: &Mat4, b: &Bounds, w: usize, h: usize) -> ScreenBox {
    // The eight corners in clip space, four at a time: lane i of `near` is corner i (offset along
    // the box's x if i & 1, along y if i & 2), and `far` is the same four offset along z.
    let min = Vec3::from(b.min);
    let size = Vec3::from(b.max) - min;
    let base = *mvp * min.extend(1.0);
    let (dx, dy, dz) = (mvp.x_axis * size.x, mvp.y_axis * size.y, mvp.z_axis * size.z);
    let lanes = |k: usize| Vec4::new(base[k], base[k] + dx[k], base[k] + dy[k], base[k] + dx[k] + dy[k]);
    let near = [lanes(0), lanes(1), lanes(2), lanes(3)];
    let far = [near[0] + dz.x, near[1] + dz.y, near[2] + dz.z, near[3] + dz.w];
    // Per frustum plane, a bit per corner outside it.
    let outside = |[x, y, z, cw]: [Vec4; 4]| {
        [x.cmplt(-cw), x.cmpgt(cw), y.cmplt(-cw), y.cmpgt(cw), z.cmplt(Vec4::ZERO), z.cmpgt(cw)].map(|m| m.bitmask())
    };
    let (a, c) = (outside(near), outside(far));
    if (0..6).any(|k| a[k] & c[k] == 0b1111) {
        return ScreenBox::Outside;
    }
    let inside = (0..6).all(|k| a[k] | c[k] == 0);
    let eps = Vec4::splat(1e-5);
    if near[3].cmple(eps).any() || far[3].cmple(eps).any() {
        return ScreenBox::Straddles;
    }
    let ndc = |k: usize| (near[k] / near[3], far[k] / far[3]);
    let range = |(n, f): (Vec4, Vec4)| (n.min(f).min_element(), n.max(f).max_element());
    let ((x_lo, x_hi), (y_lo, y_hi), (z_lo, z_hi)) = (range(ndc(0)), range(ndc(1)), range(ndc(2)));
    if ![x_lo, x_hi, y_lo, y_hi, z_lo, z_hi].iter().all(|v| v.is_finite()) {
        return ScreenBox::Straddles;
    }
    let (wf, hf) = (w as f32, h as f32);
    let (px0, px1) = ((x_lo + 1.0) * 0.5 * wf, (x_hi + 1.0) * 0.5 * wf);
    let (py0, py1) = ((1.0 - y_hi) * 0.5 * hf, (1.0 - y_lo) * 0.5 * hf);
    // A box flat in screen space (a plane seen edge-on) still covers the pixel its span lies in.
    let (x0, y0) = (first_pixel(px0, wf), first_pixel(py0, hf));
    let (x1, y1) = (last_pixel(px1, wf).max(x0), last_pixel(py1, hf).max(y0));
    ScreenBox::Rect { rect: PixelRect { x0, y0, x1, y1 }, z: z_lo, far: z_hi, inside }
}

/// The first of `n` pixels that a span starting at `v` (in pixels) reaches, clamped (without a
/// call to floor).
pub(super) fn first_pixel(v: f32, n: f32) -> usize {
    v.clamp(0.0, n - 1.0) as usize
}

/// The last of `n` pixels that a span ending at `v` (in pixels) reaches, clamped (without a call
/// to ceil).
pub(super) fn last_pixel(v: f32, n: f32) -> usize {
    let v = v.clamp(0.0, n);
    let t = v as usize;
    (t + usize::from((t as f32) < v)).saturating_sub(1).min(n as usize - 1)
}

/// Does the box lie wholly beyond the near plane (so the eye is outside it)?
pub(crate) fn wholly_ahead(mvp: &Mat4, b: &Bounds) -> bool {
    b.corners().iter().all(|c| {
        let p = *mvp * c.extend(1.0);
        p.w > 1e-5 && p.z >= 0.0
    })
}

/// Triangle `t` of `mesh` in the pixels of a `w` x `h` image (x right, y down, z = NDC depth), if
/// it lies wholly beyond the near plane: the part of a triangle nearer than that is clipped when
/// drawn and hides nothing.
pub(crate) fn project_triangle(mesh: &Mesh, t: u32, mvp: &Mat4, w: usize, h: usize) -> Option<[Vec3; 3]> {
    let corner = |k: usize| project_point(mesh.positions[mesh.indices[3 * t as usize + k] as usize], mvp, w, h);
    Some([corner(0)?, corner(1)?, corner(2)?])
}

/// A point in the pixels of a `w` x `h` image, as [`project_triangle`]: `None` before the near plane.
pub(super) fn project_point(p: [f32; 3], mvp: &Mat4, w: usize, h: usize) -> Option<Vec3> {
    let (sx, sy) = (0.5 * w as f32, 0.5 * h as f32);
    let c = *mvp * Vec3::from(p).extend(1.0);
    (c.w > 1e-5 && c.z >= 0.0).then(|| Vec3::new((c.x / c.w + 1.0) * sx, (1.0 - c.y / c.w) * sy, c.z / c.w))
}

/// The vertices of some leaves of a mesh in pixels, as [`project_point`], each projected once:
/// those in the range of vertex numbers the leaves use (compact where the leaves lie together in
/// the hierarchy, vertices being numbered in leaf order). Where the range is wider than the
/// leaves have corners, none are kept, and each triangle's corners are projected as asked for.
pub(super) struct ProjectedVertices {
    first: u32,
    points: Vec<Option<Vec3>>,
    mvp: Mat4,
    size: (usize, usize),
}

impl ProjectedVertices {
    pub(super) fn of_leaves(mesh: &Mesh, bvh: &Bvh, leaves: &[u32], mvp: &Mat4, w: usize, h: usize) -> Self {
        let (mut lo, mut hi, mut corners) = (u32::MAX, 0, 0);
        for &l in leaves {
            let range = bvh.leaf_range(l);
            corners += range.len();
            for &v in &mesh.indices[range.start as usize..range.end as usize] {
                (lo, hi) = (lo.min(v), hi.max(v));
            }
        }
        let points = if lo <= hi && ((hi - lo) as usize) < corners {
            (lo..=hi).map(|v| project_point(mesh.positions[v as usize], mvp, w, h)).collect()
        } else {
            Vec::new()
        };
        ProjectedVertices { first: lo, points, mvp: *mvp, size: (w, h) }
    }

    /// Triangle `t` of the leaves, as [`project_triangle`].
    pub(super) fn triangle(&self, mesh: &Mesh, t: u32) -> Option<[Vec3; 3]> {
        if self.points.is_empty() {
            return project_triangle(mesh, t, &self.mvp, self.size.0, self.size.1);
        }
        let corner = |k: usize| self.points[(mesh.indices[3 * t as usize + k] - self.first) as usize];
        Some([corner(0)?, corner(1)?, corner(2)?])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;

    #[test]
    fn vertices_projected_once_give_the_triangles_projected_corner_by_corner() {
        // An octahedron subdivided (12,800 triangles, over 50 leaves), seen from outside.
        let mut mesh = crate::organ_set::scale::subdivide(&Mesh::octahedron(), 40);
        let bvh = Bvh::build(&mut mesh);
        assert!(bvh.leaves.len() >= 50);
        let camera = Camera {
            eye: Vec3::new(0.3, -3.0, 0.5),
            target: Vec3::ZERO,
            up: Vec3::Z,
            fov_y: 45.0,
            near: 0.1,
            far: 10.0,
        };
        let mvp = camera.view_projection(1.0);
        let last = bvh.leaves.len() as u32 - 1;
        // Neighbouring leaves (their vertices kept) and the first with the last (each corner projected).
        for (leaves, kept) in [(vec![0, 1], true), (vec![0, last], false), ((0..=last).collect(), true)] {
            let projected = ProjectedVertices::of_leaves(&mesh, &bvh, &leaves, &mvp, 128, 96);
            assert_eq!(projected.points.is_empty(), !kept, "leaves {leaves:?}");
            for &l in &leaves {
                for t in bvh.leaf_range(l).step_by(3).map(|i| i / 3) {
                    assert_eq!(projected.triangle(&mesh, t), project_triangle(&mesh, t, &mvp, 128, 96));
                }
            }
        }
    }
}
