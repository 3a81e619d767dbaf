//! What the culler is asked to do: the mode and the raster, budget and test settings.
//!
//! - The raster size is in culling pixels (a low-resolution grid over the viewport).
//! - The adaptive stop's coverage ratio is the thesis's 0.2 by default (0 disables it); a hole
//!   tolerance makes the overlap test approximate, no longer conservative.

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CullMode {
    /// Draw every drawn organ whole.
    None,
    /// View-frustum culling of the hierarchy only.
    Frustum,
    /// Frustum and occlusion culling.
    Occlusion,
}

impl CullMode {
    pub const ALL: [CullMode; 3] = [CullMode::None, CullMode::Frustum, CullMode::Occlusion];

    pub fn name(self) -> &'static str {
        match self {
            CullMode::None => "none",
            CullMode::Frustum => "frustum",
            CullMode::Occlusion => "occlusion",
        }
    }

    pub fn parse(s: &str) -> Option<CullMode> {
        CullMode::ALL.into_iter().find(|m| m.name() == s)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct CullSettings {
    pub mode: CullMode,
    /// Culling raster size in pixels.
    pub width: usize,
    pub height: usize,
    /// Most occluder triangles rasterised per frame (those facing the eye).
    pub occluder_triangles: usize,
    /// Stop descending below this coverage ratio (thesis: 0.2); 0 disables the adaptive stop.
    pub adaptive_ratio: f32,
    /// Approximate overlap test: tolerate this fraction of uncovered pixels. Not conservative;
    /// `None` (the default) keeps culling exact.
    pub hole_tolerance: Option<f32>,
    /// Most occluder leaves per frame (`None`: only the triangle budget limits them).
    pub occluder_leaves: Option<usize>,
    /// Where the occluders come from.
    pub selection: Selection,
}

impl Default for CullSettings {
    fn default() -> Self {
        CullSettings {
            mode: CullMode::Occlusion,
            width: 128,
            height: 128,
            occluder_triangles: 1280,
            adaptive_ratio: 0.2,
            hole_tolerance: None,
            occluder_leaves: None,
            selection: Selection::Auto,
        }
    }
}

/// How occluders are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Selection {
    /// The pre-computed minimum occluder sets while the set has a fresh database that serves the
    /// layout (nothing moved; organs faded since left out, and the largest occluders by projected
    /// size added, on the budget plus the triangles left out) and the camera is near one of its
    /// viewpoints; projected size otherwise.
    #[default]
    Auto,
    /// Projected size every frame.
    ProjectedSize,
    /// The pre-computed minimum occluder sets of the nearest viewpoint, even after organs moved
    /// (still conservative: occluders are rasterised where they are now; faded ones are skipped).
    Mos,
}

impl Selection {
    pub const ALL: [Selection; 3] = [Selection::Auto, Selection::ProjectedSize, Selection::Mos];

    pub fn name(self) -> &'static str {
        match self {
            Selection::Auto => "auto",
            Selection::ProjectedSize => "projected-size",
            Selection::Mos => "mos",
        }
    }

    pub fn parse(s: &str) -> Option<Selection> {
        match s {
            "ps" => Some(Selection::ProjectedSize),
            _ => Selection::ALL.into_iter().find(|m| m.name() == s),
        }
    }
}
