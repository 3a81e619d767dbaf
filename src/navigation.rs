//! Camera navigation: orbit, pan, zoom toward the cursor, framing, and a walk-through (fly) mode,
//! all on one state: a target point, a distance, and the azimuth and elevation of the eye as in
//! [`Camera::orbit`].
//!
//! - World space, millimetres, RAS.
//! - Screen inputs are in pixels of a viewport of known size (y down).
//! - Orbiting turns the eye around the target; flying turns the target around the eye and moves
//!   both.

use crate::camera::{Camera, FOV_Y};
use crate::mesh::Bounds;
use glam::{Vec2, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Navigator {
    pub target: Vec3,
    pub distance: f32,
    pub azimuth: f32,
    pub elevation: f32,
}

impl Navigator {
    /// The view of `vbrain render --orbit AZ,EL` for these bounds.
    pub fn framing(bounds: &Bounds, azimuth: f32, elevation: f32) -> Navigator {
        let c = Camera::orbit(bounds, azimuth, elevation);
        Navigator { target: c.target, distance: (c.eye - c.target).length(), azimuth, elevation }
    }

    /// A figure's view of `bounds` from these angles: the target at the box's centre and the eye as
    /// near as lets the box's eight corners, in perspective, fill at most `fill` of the half-width
    /// and half-height of an image of `aspect` (width / height) with one of them touching. Less than
    /// 1 leaves a margin (and room for labels beside a figure, with a smaller width share).
    pub fn fitting(bounds: &Bounds, azimuth: f32, elevation: f32, aspect: f32, fill: [f32; 2]) -> Navigator {
        let framed = Navigator::framing(bounds, azimuth, elevation);
        if bounds.is_empty() {
            return framed;
        }
        let (forward, right, up) = framed.basis();
        let (half, center) = (bounds.size() * 0.5, bounds.center());
        let tan = (FOV_Y.to_radians() * 0.5).tan();
        let (across, high) = (tan * aspect.max(1e-3) * fill[0].max(1e-3), tan * fill[1].max(1e-3));
        let mut distance: f32 = 0.0;
        for k in 0..8 {
            let sign = |bit: usize| if k & bit == 0 { -1.0 } else { 1.0 };
            let corner = Vec3::new(sign(1) * half.x, sign(2) * half.y, sign(4) * half.z);
            // A corner at depth d + c.forward from the eye shows at c.right / (depth tan) across.
            let behind = corner.dot(forward);
            distance = distance.max(corner.dot(right).abs() / across - behind);
            distance = distance.max(corner.dot(up).abs() / high - behind);
        }
        Navigator { target: center, distance: distance.max(1e-3), ..framed }
    }

    /// The camera, with near and far planes fitted to `scene` (world bounds of what is drawn).
    pub fn camera(&self, scene: &Bounds) -> Camera {
        let radius = scene.size().length().max(1.0);
        let mut c = Camera::looking_at(self.target, self.distance, self.azimuth, self.elevation, radius);
        c.fit_depth(scene);
        c
    }

    fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let c = Camera::looking_at(Vec3::ZERO, 1.0, self.azimuth, self.elevation, 1.0);
        let forward = -c.eye.normalize();
        let right = forward.cross(c.up).normalize();
        (forward, right, c.up)
    }

    pub fn eye(&self) -> Vec3 {
        self.target - self.basis().0 * self.distance
    }

    /// World units per pixel at the target's depth, for a viewport `height` pixels tall.
    fn units_per_pixel(&self, height: f32) -> f32 {
        2.0 * self.distance * (FOV_Y.to_radians() * 0.5).tan() / height.max(1.0)
    }

    /// Turns the eye around the target by a drag of `delta` pixels.
    pub fn orbit(&mut self, delta: Vec2) {
        self.azimuth = (self.azimuth - delta.x * 0.4).rem_euclid(360.0);
        self.elevation = (self.elevation + delta.y * 0.4).clamp(-89.9, 89.9);
    }

    /// Turns the view around the eye (looking around in walk-through mode).
    pub fn look(&mut self, delta: Vec2) {
        let eye = self.eye();
        self.azimuth = (self.azimuth + delta.x * 0.25).rem_euclid(360.0);
        self.elevation = (self.elevation - delta.y * 0.25).clamp(-89.9, 89.9);
        self.target = eye + self.basis().0 * self.distance;
    }

    /// Moves target and eye so the scene follows a drag of `delta` pixels.
    pub fn pan(&mut self, delta: Vec2, viewport_height: f32) {
        let (_, right, up) = self.basis();
        let k = self.units_per_pixel(viewport_height);
        self.target += (-right * delta.x + up * delta.y) * k;
    }

    /// Walks: `forward`, `right`, `up` are signed distances in world units.
    pub fn walk(&mut self, forward: f32, right: f32, up: f32) {
        let (f, r, u) = self.basis();
        self.target += f * forward + r * right + u * up;
    }

    /// Zooms by `factor` (< 1 moves in) keeping the point under the cursor fixed on screen.
    /// `cursor` is in pixels of a `size` viewport.
    pub fn zoom_at(&mut self, factor: f32, cursor: Vec2, size: Vec2) {
        let factor = factor.clamp(0.01, 100.0);
        let (forward, right, up) = self.basis();
        let half = (FOV_Y.to_radians() * 0.5).tan();
        let ndc = Vec2::new(2.0 * cursor.x / size.x.max(1.0) - 1.0, 1.0 - 2.0 * cursor.y / size.y.max(1.0));
        let aspect = size.x / size.y.max(1.0);
        // The cursor's point on the plane through the target facing the camera.
        let p = self.eye() + (forward + right * ndc.x * half * aspect + up * ndc.y * half) * self.distance;
        self.target = p + (self.target - p) * factor;
        self.distance = (self.distance * factor).max(1e-3);
    }

    /// Looks at `bounds` from the current direction, at a distance that frames them.
    pub fn frame(&mut self, bounds: &Bounds) {
        if bounds.is_empty() {
            return;
        }
        *self = Navigator::framing(bounds, self.azimuth, self.elevation);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn project(nav: &Navigator, p: Vec3, aspect: f32) -> Vec2 {
        let scene = Bounds { min: [-500.0; 3], max: [500.0; 3] };
        nav.camera(&scene).view_projection(aspect).project_point3(p).truncate()
    }

    #[test]
    fn framing_matches_render_orbit() {
        let b = Bounds { min: [-70.0, -100.0, -50.0], max: [70.0, 70.0, 80.0] };
        let n = Navigator::framing(&b, 30.0, 10.0);
        let c = Camera::orbit(&b, 30.0, 10.0);
        assert!(n.eye().abs_diff_eq(c.eye, 1e-3));
    }

    #[test]
    fn fitting_fills_the_share_asked_with_a_corner_touching() {
        let b = Bounds { min: [-70.0, -105.0, -50.0], max: [72.0, 70.0, 80.0] };
        for (az, el, aspect, fill) in [(-90.0, 10.0, 4.0 / 3.0, [0.6, 0.85]), (30.0, 25.0, 0.7, [0.9, 0.9])] {
            let n = Navigator::fitting(&b, az, el, aspect, fill);
            let mut most = [0.0f32; 2];
            for k in 0..8 {
                let pick = |bit: usize, axis: usize| if k & bit == 0 { b.min[axis] } else { b.max[axis] };
                let p = project(&n, Vec3::new(pick(1, 0), pick(2, 1), pick(4, 2)), aspect);
                most = [most[0].max(p.x.abs()), most[1].max(p.y.abs())];
            }
            assert!(most[0] <= fill[0] + 1e-4 && most[1] <= fill[1] + 1e-4, "{most:?} beyond {fill:?}");
            assert!((most[0] - fill[0]).abs() < 1e-3 || (most[1] - fill[1]).abs() < 1e-3, "{most:?} short of {fill:?}");
            assert!(n.target.abs_diff_eq(b.center(), 1e-4));
        }
    }

    #[test]
    fn zoom_keeps_the_cursor_point_fixed() {
        let mut n = Navigator { target: Vec3::ZERO, distance: 400.0, azimuth: 20.0, elevation: 10.0 };
        let size = Vec2::new(800.0, 600.0);
        let cursor = Vec2::new(600.0, 150.0);
        // The world point under the cursor on the target plane.
        let (f, r, u) = n.basis();
        let half = (FOV_Y.to_radians() * 0.5).tan();
        let p = n.eye() + (f + r * 0.5 * half * (800.0 / 600.0) + u * 0.5 * half) * n.distance;
        let before = project(&n, p, 800.0 / 600.0);
        n.zoom_at(0.5, cursor, size);
        let after = project(&n, p, 800.0 / 600.0);
        assert!((before - Vec2::new(0.5, 0.5)).length() < 1e-3, "{before}");
        assert!((after - before).length() < 1e-3, "{before} -> {after}");
        assert!((n.distance - 200.0).abs() < 1e-3);
    }

    #[test]
    fn pan_follows_the_drag_and_look_keeps_the_eye() {
        let mut n = Navigator { target: Vec3::ZERO, distance: 300.0, azimuth: 0.0, elevation: 0.0 };
        let before = project(&n, Vec3::ZERO, 1.0);
        n.pan(Vec2::new(100.0, 0.0), 500.0);
        let after = project(&n, Vec3::ZERO, 1.0);
        // 100 of 500 pixels is 0.4 of the 2-unit NDC height, moving right.
        assert!((after.x - before.x - 0.4).abs() < 1e-3, "{before} -> {after}");
        let eye = n.eye();
        n.look(Vec2::new(40.0, -20.0));
        assert!(n.eye().abs_diff_eq(eye, 1e-3));
        n.walk(10.0, 0.0, 0.0);
        assert!((n.eye() - eye).length() > 9.9);
    }
}
