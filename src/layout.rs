//! The layout: what the user changed about each organ (visibility, opacity, colour and the model
//! transform from organ space to world space), and what colours the organs (the colours
//! themselves are [`crate::colouring`]'s).
//!
//! - Both spaces are millimetres, RAS.
//! - A transform scales and rotates about its pivot (the organ's centre in organ space), then
//!   translates; rotations are Euler angles in degrees about x, y, z, applied in that order.
//! - Colours are sRGB components in 0..=1.

use crate::mesh::Bounds;
use crate::organ_set::OrganSet;
use glam::{EulerRot, Mat4, Quat, Vec3};
use serde::{Deserialize, Serialize};

/// A model transform: scale and rotate about `pivot` (the organ's centre in organ space), then
/// translate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub translation: Vec3,
    /// Rotation as Euler angles in degrees about x, y, z (applied in that order).
    pub rotation_deg: Vec3,
    pub scale: f32,
    pub pivot: Vec3,
}

impl Transform {
    pub fn identity(pivot: Vec3) -> Self {
        Transform { translation: Vec3::ZERO, rotation_deg: Vec3::ZERO, scale: 1.0, pivot }
    }

    /// Largest translation per axis a file may give, millimetres (100 m).
    pub const MAX_TRANSLATION: f32 = 1e5;
    /// Scales a file may give.
    pub const SCALES: std::ops::RangeInclusive<f32> = 1e-3..=1e3;

    /// A transform from a file's numbers (translation mm, rotation degrees, scale), or what is
    /// wrong with them: not finite, a translation beyond [`Self::MAX_TRANSLATION`], a rotation
    /// beyond +-1e6 degrees, a scale outside [`Self::SCALES`].
    pub fn from_parts(translation: [f32; 3], rotation: [f32; 3], scale: f32, pivot: Vec3) -> Result<Transform, String> {
        if !translation.iter().all(|v| v.is_finite() && v.abs() <= Self::MAX_TRANSLATION) {
            return Err(format!("translation {translation:?} is not within +-{} mm", Self::MAX_TRANSLATION));
        }
        if !rotation.iter().all(|v| v.is_finite() && v.abs() <= 1e6) {
            return Err(format!("rotation {rotation:?} is not degrees within +-1000000"));
        }
        if !Self::SCALES.contains(&scale) {
            return Err(format!("scale {scale} is not in {}..={}", Self::SCALES.start(), Self::SCALES.end()));
        }
        Ok(Transform { translation: translation.into(), rotation_deg: rotation.into(), scale, pivot })
    }

    pub fn is_identity(&self) -> bool {
        self.translation == Vec3::ZERO && self.rotation_deg == Vec3::ZERO && self.scale == 1.0
    }

    pub fn rotation(&self) -> Quat {
        let r = self.rotation_deg * (std::f32::consts::PI / 180.0);
        Quat::from_euler(EulerRot::XYZ, r.x, r.y, r.z)
    }

    /// Organ space to world space.
    pub fn matrix(&self) -> Mat4 {
        Mat4::from_translation(self.translation + self.pivot)
            * Mat4::from_quat(self.rotation())
            * Mat4::from_scale(Vec3::splat(self.scale))
            * Mat4::from_translation(-self.pivot)
    }
}

/// What colours the organs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ColourBy {
    /// Each organ its own colour (the layout's).
    #[default]
    Organ,
    /// Each organ its lobe's (or other group's) colour.
    Lobe,
    /// The arterial territory at each point, where the set has territories.
    Territory,
}

impl ColourBy {
    pub const ALL: [ColourBy; 3] = [ColourBy::Organ, ColourBy::Lobe, ColourBy::Territory];

    /// As menus show it.
    pub fn label(self) -> &'static str {
        match self {
            ColourBy::Organ => "Organ",
            ColourBy::Lobe => "Lobe",
            ColourBy::Territory => "Arterial territory",
        }
    }

    /// As files and the command line write it: `organ`, `lobe` or `territory`.
    pub fn name(self) -> &'static str {
        match self {
            ColourBy::Organ => "organ",
            ColourBy::Lobe => "lobe",
            ColourBy::Territory => "territory",
        }
    }

    /// From [`Self::name`].
    pub fn parse(s: &str) -> Option<ColourBy> {
        ColourBy::ALL.into_iter().find(|c| c.name() == s)
    }

    pub fn is_default(&self) -> bool {
        *self == ColourBy::Organ
    }
}

/// The state of one organ that the user may change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrganState {
    pub visible: bool,
    pub opacity: f32,
    /// sRGB components in 0..=1.
    pub colour: [f32; 3],
    pub transform: Transform,
}

impl OrganState {
    /// Drawn at all: visible and not fully faded.
    pub fn is_drawn(&self) -> bool {
        self.visible && self.opacity > 0.0
    }

    /// Drawn and fully opaque: the only organs that may hide others.
    pub fn is_opaque(&self) -> bool {
        self.visible && self.opacity >= 1.0
    }
}

/// Per-organ state, index-aligned with the set's organs, and what colours them.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    pub organs: Vec<OrganState>,
    pub colour_by: ColourBy,
}

impl Layout {
    /// The set's defaults: its visibility, opacity and colours, no transform.
    pub fn new(set: &OrganSet) -> Layout {
        Layout {
            organs: set
                .organs
                .iter()
                .map(|o| OrganState {
                    visible: o.visible,
                    opacity: o.opacity,
                    colour: o.colour,
                    transform: Transform::identity(o.mesh.bounds().center()),
                })
                .collect(),
            colour_by: Default::default(),
        }
    }

    /// World-space bounds of the drawn organs (all organs if none is drawn).
    pub fn bounds(&self, set: &OrganSet) -> Bounds {
        let drawn = |all: bool| {
            set.organs
                .iter()
                .zip(&self.organs)
                .filter(|(_, s)| all || s.is_drawn())
                .fold(Bounds::EMPTY, |b, (o, s)| b.union(o.mesh.bounds().transformed(&s.transform.matrix())))
        };
        let b = drawn(false);
        if b.is_empty() {
            drawn(true)
        } else {
            b
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transform_pivots_about_the_centre() {
        let mut t = Transform::identity(Vec3::new(10.0, 0.0, 0.0));
        t.rotation_deg = Vec3::new(0.0, 0.0, 90.0);
        t.scale = 2.0;
        // The pivot stays put; a point 1 mm right of it goes 2 mm anterior.
        assert!(t.matrix().transform_point3(Vec3::new(10.0, 0.0, 0.0)).abs_diff_eq(Vec3::new(10.0, 0.0, 0.0), 1e-5));
        assert!(t.matrix().transform_point3(Vec3::new(11.0, 0.0, 0.0)).abs_diff_eq(Vec3::new(10.0, 2.0, 0.0), 1e-5));
        t.translation = Vec3::Z;
        assert!(t.matrix().transform_point3(Vec3::new(10.0, 0.0, 0.0)).abs_diff_eq(Vec3::new(10.0, 0.0, 1.0), 1e-5));
    }
}
