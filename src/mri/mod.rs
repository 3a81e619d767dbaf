//! An organ set's MRI: one 3-D intensity volume registered to the set's organs (issue: sectional
//! anatomy), read once when the set opens.
//!
//! - World space is the set's organ space: millimetres, RAS (+x right, +y anterior, +z superior).
//! - Intensities are normalised to 0..=1 (the volume's minimum to its 99.5th percentile, above
//!   that clamped) and kept as 8-bit steps; [`Mri::sample`] is trilinear between voxel centres.
//! - A volume that cannot serve the set is refused with a message naming its file: not 3-D, over
//!   [`MAX_VOXELS`], non-finite values, constant, or no overlap with the set's bounds. The set then
//!   loads without it.
//! - [`mod@slice`]: the set's organs and the MRI on an axis-aligned plane, in a pane's pixels.

pub mod slice;

use crate::error::{Error, Result};
use crate::mesh::Bounds;
use glam::{Mat4, Vec3};
use std::path::Path;

/// The most voxels an MRI may have (2^26, e.g. 400^3 at one byte each).
pub const MAX_VOXELS: usize = 1 << 26;

/// A normalised intensity volume and where it lies.
#[derive(Clone)]
pub struct Mri {
    dims: [usize; 3],
    /// Voxel indices -> world millimetres.
    to_world: Mat4,
    to_voxel: Mat4,
    /// 0..=255 for 0..=1, x fastest.
    values: Vec<u8>,
}

impl std::fmt::Debug for Mri {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Mri({}x{}x{})", self.dims[0], self.dims[1], self.dims[2])
    }
}

impl Mri {
    /// Reads the volume at `path` for a set whose organs span `set_bounds`.
    pub fn open(path: &Path, set_bounds: &Bounds) -> Result<Mri> {
        let raw = crate::nifti_file::read(path, "MRI volume", MAX_VOXELS)?;
        let bad = |m: String| Error::parse(path, None, m);
        let values: Vec<f32> = (0..raw.len()).map(|i| raw.value(i) as f32).collect();
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(bad(format!("voxel {i} is not a finite number: an MRI volume needs intensities")));
        }
        let mri = Mri::from_values(raw.dims, raw.affine, &values).map_err(bad)?;
        let b = mri.bounds();
        let overlaps = (0..3).all(|a| b.min[a] <= set_bounds.max[a] && b.max[a] >= set_bounds.min[a]);
        if !overlaps {
            return Err(bad(format!(
                "the volume spans {:?} to {:?} mm, which misses the set's organs ({:?} to {:?} mm): \
                 is its affine in the set's space?",
                b.min, b.max, set_bounds.min, set_bounds.max
            )));
        }
        Ok(mri)
    }

    /// A volume of `values` (x fastest) on a grid of `dims` placed by `to_world` (voxel indices ->
    /// millimetres), normalised.
    pub fn from_values(dims: [usize; 3], to_world: Mat4, values: &[f32]) -> std::result::Result<Mri, String> {
        let count = dims[0] * dims[1] * dims[2];
        if count == 0 || count > MAX_VOXELS || values.len() != count {
            return Err(format!("{}x{}x{} voxels is not an MRI vbrain reads", dims[0], dims[1], dims[2]));
        }
        if !(to_world.is_finite() && to_world.determinant().abs() > 1e-12) {
            return Err("the voxel-to-world transform is singular".into());
        }
        let mut sorted: Vec<f32> = values.iter().copied().filter(|v| v.is_finite()).collect();
        if sorted.len() != count {
            return Err("the volume holds values that are not finite numbers".into());
        }
        sorted.sort_unstable_by(f32::total_cmp);
        let lo = sorted[0];
        // The 99.5th percentile, or the maximum where that is still the minimum (a sparse volume).
        let p995 = sorted[((count - 1) as f64 * 0.995) as usize];
        let hi = if p995 > lo { p995 } else { sorted[count - 1] };
        if hi <= lo {
            return Err(format!("every voxel holds {lo}: the volume shows nothing"));
        }
        let values = values.iter().map(|&v| ((v - lo) / (hi - lo) * 255.0).round().clamp(0.0, 255.0) as u8).collect();
        Ok(Mri { dims, to_world, to_voxel: to_world.inverse(), values })
    }

    pub fn dims(&self) -> [usize; 3] {
        self.dims
    }

    /// Voxel indices -> world millimetres.
    pub fn to_world(&self) -> Mat4 {
        self.to_world
    }

    /// The normalised intensities, 0..=255, x fastest (for a 3-D texture).
    pub fn voxels(&self) -> &[u8] {
        &self.values
    }

    /// The world box the voxel centres span.
    pub fn bounds(&self) -> Bounds {
        let [x, y, z] = self.dims.map(|d| d.saturating_sub(1) as f32);
        let box_ = Bounds { min: [0.0; 3], max: [x, y, z] };
        box_.transformed(&self.to_world)
    }

    /// The intensity (0..=1) at world point `p`, trilinear; `None` outside the voxel centres' box.
    pub fn sample(&self, p: Vec3) -> Option<f32> {
        self.sample_voxel(self.to_voxel.transform_point3(p))
    }

    /// World -> voxel coordinates (voxel centres at whole numbers).
    pub fn to_voxel(&self) -> Mat4 {
        self.to_voxel
    }

    /// [`Mri::sample`] at voxel coordinates `v`.
    pub fn sample_voxel(&self, v: Vec3) -> Option<f32> {
        let [nx, ny, nz] = self.dims;
        let max = Vec3::new((nx - 1) as f32, (ny - 1) as f32, (nz - 1) as f32);
        if !(v.cmpge(Vec3::ZERO).all() && v.cmple(max).all()) {
            return None;
        }
        let i = v.floor().min(max);
        let f = v - i;
        let (x, y, z) = (i.x as usize, i.y as usize, i.z as usize);
        // The next voxel along each axis, or this one at the far face.
        let (sx, sy, sz) = (usize::from(x + 1 < nx), nx * usize::from(y + 1 < ny), nx * ny * usize::from(z + 1 < nz));
        let base = x + nx * (y + ny * z);
        let at = |o: usize| self.values[base + o] as f32;
        let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
        let c00 = lerp(at(0), at(sx), f.x);
        let c10 = lerp(at(sy), at(sy + sx), f.x);
        let c01 = lerp(at(sz), at(sz + sx), f.x);
        let c11 = lerp(at(sz + sy), at(sz + sy + sx), f.x);
        Some(lerp(lerp(c00, c10, f.y), lerp(c01, c11, f.y), f.z) / 255.0)
    }
}

/// Window and level: the intensities `level ± window / 2` (normalised, 0..=1) span black to white.
/// The default, 0.9 and 0.6, shows a T1 template's grey and white matter apart.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(try_from = "WindowFields")]
pub struct Window {
    pub window: f32,
    pub level: f32,
}

impl Default for Window {
    fn default() -> Self {
        Window { window: 0.9, level: 0.6 }
    }
}

/// A window as files hold it, checked by [`Window::new`] as it is read.
#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct WindowFields {
    window: f32,
    level: f32,
}

impl TryFrom<WindowFields> for Window {
    type Error = String;
    fn try_from(f: WindowFields) -> std::result::Result<Window, String> {
        Window::new(f.window, f.level)
    }
}

impl Window {
    /// The grey (0..=1) of intensity `v`.
    pub fn grey(&self, v: f32) -> f32 {
        ((v - self.level) / self.window.max(1e-3) + 0.5).clamp(0.0, 1.0)
    }

    /// Checks a window given by a user: both finite, the window above 0.
    pub fn new(window: f32, level: f32) -> std::result::Result<Window, String> {
        if !(window.is_finite() && window > 0.0 && window <= 2.0 && level.is_finite() && (-1.0..=2.0).contains(&level))
        {
            return Err(format!(
                "window {window} and level {level}: the window must be in (0, 2] and the level in [-1, 2]"
            ));
        }
        Ok(Window { window, level })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampling_is_trilinear_between_voxel_centres() {
        let dims = [2, 2, 2];
        let values: Vec<f32> = (0..8).map(|i| if i % 2 == 1 { 10.0 } else { 0.0 }).collect();
        let mri = Mri::from_values(dims, Mat4::from_translation(Vec3::new(-1.0, 0.0, 0.0)), &values).unwrap();
        assert_eq!(mri.sample(Vec3::new(-1.0, 0.0, 0.0)), Some(0.0));
        assert_eq!(mri.sample(Vec3::new(0.0, 1.0, 1.0)), Some(1.0));
        let mid = mri.sample(Vec3::new(-0.5, 0.5, 0.5)).unwrap();
        assert!((mid - 0.5).abs() < 0.01, "{mid}");
        assert_eq!(mri.sample(Vec3::new(0.5, 0.0, 0.0)), None);
    }

    #[test]
    fn a_constant_or_singular_volume_is_refused() {
        assert!(Mri::from_values([2, 1, 1], Mat4::IDENTITY, &[3.0, 3.0]).is_err());
        assert!(Mri::from_values([2, 1, 1], Mat4::ZERO, &[0.0, 3.0]).is_err());
        assert!(Mri::from_values([2, 1, 1], Mat4::IDENTITY, &[0.0, f32::NAN]).is_err());
    }

    #[test]
    fn window_maps_level_to_middle_grey() {
        let w = Window::new(0.5, 0.4).unwrap();
        assert_eq!(w.grey(0.4), 0.5);
        assert_eq!(w.grey(0.0), 0.0);
        assert_eq!(w.grey(0.9), 1.0);
        assert!(Window::new(0.0, 0.5).is_err());
        assert!(Window::new(f32::NAN, 0.5).is_err());
    }
}
