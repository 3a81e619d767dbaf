//! Smooth changes between two views, as a lesson goes from step to step: the camera (navigator)
//! and the layout (opacity, colour, transform) are eased from one to the other over [`DURATION`]
//! seconds.
//!
//! - World space is millimetres RAS; angles are degrees.
//! - An organ that appears fades in from nothing, one that goes fades out and is hidden at the end.
//! - Pure functions: the viewer asks for the state at a time and draws it; the edit itself is
//!   applied at once.

use crate::layout::{Layout, OrganState};
use crate::navigation::Navigator;

/// Seconds a step change takes.
pub const DURATION: f64 = 0.5;

/// A change under way from one view to another, started at `start` (seconds, any clock).
#[derive(Clone, Debug)]
pub struct Transition {
    pub from: (Navigator, Layout),
    pub to: (Navigator, Layout),
    pub start: f64,
}

impl Transition {
    /// How far it has gone at `now`: 0 at the start, 1 once [`DURATION`] has passed.
    pub fn progress(&self, now: f64) -> f32 {
        ((now - self.start) / DURATION).clamp(0.0, 1.0) as f32
    }

    /// The camera and layout at `now`, eased.
    pub fn at(&self, now: f64) -> (Navigator, Layout) {
        let t = ease(self.progress(now));
        (navigator(&self.from.0, &self.to.0, t), layout(&self.from.1, &self.to.1, t))
    }
}

/// Smoothstep: slow at both ends.
pub fn ease(t: f32) -> f32 {
    let t = t.clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// The camera a fraction `t` of the way: target and distance straight, the azimuth the short way
/// round.
pub fn navigator(from: &Navigator, to: &Navigator, t: f32) -> Navigator {
    let turn = (to.azimuth - from.azimuth + 180.0).rem_euclid(360.0) - 180.0;
    Navigator {
        target: from.target.lerp(to.target, t),
        distance: lerp(from.distance, to.distance, t),
        azimuth: from.azimuth + turn * t,
        elevation: lerp(from.elevation, to.elevation, t),
    }
}

/// The layout a fraction `t` of the way. Organs of layouts of different sizes take `to`'s state.
pub fn layout(from: &Layout, to: &Layout, t: f32) -> Layout {
    if t >= 1.0 || from.organs.len() != to.organs.len() {
        return to.clone();
    }
    let organs = from.organs.iter().zip(&to.organs).map(|(a, b)| organ(a, b, t)).collect();
    Layout { organs, colour_by: to.colour_by }
}

fn organ(a: &OrganState, b: &OrganState, t: f32) -> OrganState {
    let shown = |s: &OrganState| if s.visible { s.opacity } else { 0.0 };
    let mut s = *b;
    s.visible = a.visible || b.visible;
    s.opacity = lerp(shown(a), shown(b), t);
    s.colour = std::array::from_fn(|k| lerp(a.colour[k], b.colour[k], t));
    s.transform.translation = a.transform.translation.lerp(b.transform.translation, t);
    s.transform.rotation_deg = a.transform.rotation_deg.lerp(b.transform.rotation_deg, t);
    s.transform.scale = lerp(a.transform.scale, b.transform.scale, t);
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn nav(azimuth: f32) -> Navigator {
        Navigator { target: Vec3::ZERO, distance: 100.0, azimuth, elevation: 0.0 }
    }

    #[test]
    fn the_camera_turns_the_short_way_and_ends_where_it_should() {
        let mid = navigator(&nav(170.0), &nav(-170.0), 0.5);
        assert!((mid.azimuth - 180.0).abs() < 1e-4, "{}", mid.azimuth);
        let end = navigator(&nav(170.0), &nav(-170.0), 1.0);
        assert!((end.azimuth.rem_euclid(360.0) - 190.0).abs() < 1e-3);
        assert_eq!(ease(0.0), 0.0);
        assert_eq!(ease(1.0), 1.0);
        assert!(ease(0.25) < 0.25 && ease(0.75) > 0.75);
    }

    #[test]
    fn organs_fade_in_and_out_and_end_in_the_target_state() {
        let base = OrganState {
            visible: true,
            opacity: 1.0,
            colour: [1.0, 0.0, 0.0],
            transform: crate::layout::Transform::identity(Vec3::ZERO),
        };
        let gone = OrganState { visible: false, ..base };
        let faded = OrganState { opacity: 0.2, colour: [0.0, 0.0, 1.0], ..base };
        let from = Layout { organs: vec![base, gone, base], colour_by: Default::default() };
        let to = Layout { organs: vec![gone, base, faded], colour_by: Default::default() };
        let mid = layout(&from, &to, 0.5);
        assert!(mid.organs.iter().all(|s| s.visible));
        assert_eq!([mid.organs[0].opacity, mid.organs[1].opacity, mid.organs[2].opacity], [0.5, 0.5, 0.6]);
        assert_eq!(mid.organs[2].colour, [0.5, 0.0, 0.5]);
        let transition = Transition { from: (nav(0.0), from), to: (nav(90.0), to.clone()), start: 10.0 };
        let (n, end) = transition.at(10.0 + DURATION);
        assert_eq!(end, to);
        assert_eq!(n.azimuth, 90.0);
        assert_eq!(transition.progress(10.0 + DURATION / 2.0), 0.5);
    }
}
