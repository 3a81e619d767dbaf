//! Cameras and their view and projection matrices.
//!
//! - World space: millimetres, RAS (+x right, +y anterior, +z superior).
//! - View space is right-handed; projection is into wgpu clip space, depth 0..1.
//! - Orbit angles are degrees: azimuth from the anterior view toward the subject's right, elevation
//!   toward superior ([`Camera::orbit`]).

use crate::mesh::Bounds;
use glam::{Mat4, Vec3};

/// The six standard anatomical views: the camera looks at the named side of the subject.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    Anterior,
    Posterior,
    Left,
    Right,
    Superior,
    Inferior,
}

impl View {
    pub const ALL: [View; 6] =
        [View::Anterior, View::Posterior, View::Left, View::Right, View::Superior, View::Inferior];

    pub fn name(self) -> &'static str {
        match self {
            View::Anterior => "anterior",
            View::Posterior => "posterior",
            View::Left => "left",
            View::Right => "right",
            View::Superior => "superior",
            View::Inferior => "inferior",
        }
    }

    pub fn parse(s: &str) -> Option<View> {
        View::ALL.into_iter().find(|v| v.name().eq_ignore_ascii_case(s))
    }

    /// Azimuth and elevation (degrees) of this view, as in [`Camera::orbit`].
    pub fn angles(self) -> (f32, f32) {
        match self {
            View::Anterior => (0.0, 0.0),
            View::Right => (90.0, 0.0),
            View::Posterior => (180.0, 0.0),
            View::Left => (-90.0, 0.0),
            View::Superior => (0.0, 90.0),
            View::Inferior => (0.0, -90.0),
        }
    }
}

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub target: Vec3,
    pub up: Vec3,
    /// Vertical field of view, degrees.
    pub fov_y: f32,
    pub near: f32,
    pub far: f32,
}

/// The default vertical field of view, degrees.
pub const FOV_Y: f32 = 30.0;

impl Camera {
    /// A camera on a sphere around the centre of `bounds`, far enough to frame all of it.
    /// Azimuth turns from the anterior view toward the subject's right (90 = right view); elevation
    /// lifts toward superior (90 = superior view, anterior at the top of the image).
    /// The distance fits the box's extent across and along the view direction into the vertical
    /// field of view (and so into any image at least as wide as it is tall).
    pub fn orbit(bounds: &Bounds, azimuth_deg: f32, elevation_deg: f32) -> Camera {
        if bounds.is_empty() {
            return Camera::looking_at(Vec3::ZERO, 4.0, azimuth_deg, elevation_deg, 1.0);
        }
        let probe = Camera::looking_at(Vec3::ZERO, 1.0, azimuth_deg, elevation_deg, 1.0);
        let forward = -probe.eye.normalize();
        let right = forward.cross(probe.up).normalize();
        let half = bounds.size() * 0.5;
        let extent = |axis: Vec3| half.x * axis.x.abs() + half.y * axis.y.abs() + half.z * axis.z.abs();
        let across = extent(right).max(extent(probe.up));
        let depth = extent(forward);
        let distance = across / (FOV_Y.to_radians() * 0.5).tan() * 1.05 + depth;
        let mut camera = Camera::looking_at(bounds.center(), distance, azimuth_deg, elevation_deg, 1.0);
        camera.fit_depth(bounds);
        camera
    }

    /// A camera at `distance` from `center` in the direction given by azimuth and elevation (as in
    /// [`Camera::orbit`]); `radius` bounds the scene for the depth range.
    pub fn looking_at(center: Vec3, distance: f32, azimuth_deg: f32, elevation_deg: f32, radius: f32) -> Camera {
        let (az, el) = (azimuth_deg.to_radians(), elevation_deg.clamp(-90.0, 90.0).to_radians());
        let dir = Vec3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin());
        // Up is superior, tilted toward posterior as the camera rises, so the poles stay defined.
        let up = Vec3::new(-az.sin() * el.sin(), -az.cos() * el.sin(), el.cos()).normalize();
        let near = (distance - radius * 1.5).max(distance * 0.01).max(0.1);
        Camera { eye: center + dir * distance, target: center, up, fov_y: FOV_Y, near, far: distance + radius * 1.5 }
    }

    pub fn view(bounds: &Bounds, view: View) -> Camera {
        let (az, el) = view.angles();
        Camera::orbit(bounds, az, el)
    }

    pub fn view_matrix(&self) -> Mat4 {
        Mat4::look_at_rh(self.eye, self.target, self.up)
    }

    pub fn projection(&self, aspect: f32) -> Mat4 {
        Mat4::perspective_rh(self.fov_y.to_radians(), aspect.max(1e-6), self.near, self.far)
    }

    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.projection(aspect) * self.view_matrix()
    }

    /// The ray through a point of the image: `ndc` from -1 to 1, x right, y up. Returns the
    /// point on the near plane and the unit direction away from the eye (world space).
    pub fn ray(&self, aspect: f32, ndc: glam::Vec2) -> (Vec3, Vec3) {
        let inverse = self.view_projection(aspect).inverse();
        let near = inverse.project_point3(ndc.extend(0.0));
        let far = inverse.project_point3(ndc.extend(1.0));
        (near, (far - near).normalize_or_zero())
    }

    /// The same camera moved along its line of sight to `factor` times its distance from the target.
    pub fn zoomed(&self, factor: f32) -> Camera {
        Camera { eye: self.target + (self.eye - self.target) * factor, ..*self }
    }

    /// Adjusts near and far planes to enclose a scene of these bounds (world space).
    pub fn fit_depth(&mut self, bounds: &Bounds) {
        if bounds.is_empty() {
            return;
        }
        let d = (bounds.center() - self.eye).length();
        let r = bounds.size().length() * 0.5;
        self.far = (d + r) * 1.01 + 1.0;
        self.near = (d - r).max(self.far * 1e-4).max(0.05);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit() -> Bounds {
        Bounds { min: [-10.0; 3], max: [10.0; 3] }
    }

    #[test]
    fn views_look_from_the_named_side() {
        assert!(Camera::view(&unit(), View::Anterior).eye.y > 40.0);
        assert!(Camera::view(&unit(), View::Right).eye.x > 40.0);
        assert!(Camera::view(&unit(), View::Left).eye.x < -40.0);
        assert!(Camera::view(&unit(), View::Superior).eye.z > 40.0);
        let inf = Camera::view(&unit(), View::Inferior);
        assert!(inf.eye.z < -40.0 && inf.up.y.abs() > 0.99);
    }

    #[test]
    fn orbit_frames_the_bounds() {
        let cam = Camera::orbit(&unit(), 30.0, 20.0);
        let vp = cam.view_projection(1.0);
        for c in unit().corners() {
            let p = vp.project_point3(c);
            assert!(p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z), "{c} -> {p}");
        }
    }
}
