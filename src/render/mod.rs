//! The offscreen renderer (wgpu). One renderer serves the viewer's viewport and every headless
//! command, so a screenshot is exactly what the viewer shows.
//!
//! Spaces: meshes are uploaded in organ space; the vertex shader applies each organ's model matrix
//! (organ -> world, millimetres RAS) and the camera's view-projection (world -> wgpu clip space,
//! depth 0..1). Targets are in screen pixels, origin top left.

mod context;
mod oit;
mod renderer;
mod target;

pub use context::{GpuContext, NO_ADAPTER_HELP};
pub use renderer::{FrameInput, RenderStats, Renderer, SAMPLE_COUNT};
pub use target::{Target, COLOR_FORMAT};

/// An sRGB colour component (0..1) to linear light.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear-light component (0..1) to sRGB.
pub fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The WGSL sources, by file name, for validation and pipeline creation.
pub const SHADERS: &[(&str, &str)] = &[
    ("organ.wgsl", include_str!("../../shaders/organ.wgsl")),
    ("composite.wgsl", include_str!("../../shaders/composite.wgsl")),
];
