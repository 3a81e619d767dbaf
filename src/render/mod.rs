//! The offscreen renderer (wgpu). One renderer serves the viewer's viewport and every headless
//! command, so a screenshot is exactly what the viewer shows.
//!
//! - Meshes are uploaded in organ space; the vertex shader applies each organ's model matrix
//!   (organ -> world, millimetres RAS) and the camera's view-projection (world -> wgpu clip space,
//!   depth 0..1).
//! - Targets are in screen pixels, origin top left.
//! - [`Renderer`] holds the set on the GPU (`scene`) and one technique per way of drawing a frame,
//!   each its own module with its pipelines and per-frame data, called through one interface
//!   (`frame::Technique`).
//! - The techniques: `blend` (opaque, and sorted or unsorted alpha blending), `screendoor` (thesis
//!   chapter 4), `weighted` (weighted blended OIT), `peel` (depth peeling and dual depth peeling),
//!   `kbuffer` (the k-buffer, Callahan 2005), `exact` (the reference), `debug` (the culling view,
//!   thesis Figure 21), `ids` (picking and leaf visibility) and `outline` (highlighted and selected
//!   organs, over the finished frame).
//! - `uniforms` holds the structs shared with WGSL, `pipelines` what the techniques build them
//!   with, `passes` the one builder their render passes begin with.
//! - [`guard`] turns GPU errors (out of memory above all) into errors and checks a target's size
//!   before it is made; `timer` measures a frame's GPU time where the adapter has timestamp
//!   queries.

mod blend;
mod context;
mod debug;
mod exact;
mod frame;
pub mod guard;
mod ids;
mod kbuffer;
mod outline;
mod passes;
mod peel;
mod pipelines;
mod renderer;
mod scene;
mod screendoor;
mod target;
mod tiles;
mod timer;
pub mod uniforms;
mod weighted;

pub use context::{GpuContext, NO_ADAPTER_HELP};
pub use frame::{FrameInput, RenderStats};
pub use outline::WIDTH as OUTLINE_WIDTH;
pub use pipelines::SAMPLE_COUNT;
pub use renderer::Renderer;
pub use target::{Target, COLOR_FORMAT};
pub use timer::FEATURES as GPU_TIMER_FEATURES;

/// Device features the renderer uses where the adapter has them: 32-bit float blending (dual depth
/// peeling), clip distances (triangles cut at the clip planes) and timestamp queries (GPU time).
pub const WANTED_FEATURES: wgpu::Features =
    wgpu::Features::FLOAT32_BLENDABLE.union(wgpu::Features::CLIP_DISTANCES).union(timer::FEATURES);

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

/// A WGSL source by its file name in `shaders/`.
pub struct Shader {
    pub name: &'static str,
    pub source: &'static str,
}

/// Organ shading, picking, screen-door and weighted sums.
pub const ORGAN_SHADER: Shader = Shader { name: "organ.wgsl", source: include_str!("../../shaders/organ.wgsl") };
/// The vertex stage that cuts triangles at the clip planes, appended to [`ORGAN_SHADER`] where the
/// device has clip distances ([`organ_source`]).
pub const ORGAN_CLIP_SHADER: Shader =
    Shader { name: "organ_clip.wgsl", source: include_str!("../../shaders/organ_clip.wgsl") };
/// Full-screen passes: accumulation, presentation, the weighted resolve.
pub const COMPOSITE_SHADER: Shader =
    Shader { name: "composite.wgsl", source: include_str!("../../shaders/composite.wgsl") };
/// Screen-door's tiles: restoring the opaque image into them, gathering them into the image.
pub const SCREENDOOR_SHADER: Shader =
    Shader { name: "screendoor.wgsl", source: include_str!("../../shaders/screendoor.wgsl") };
/// The depth-peeling modes' per-sample compositing.
pub const PEEL_SHADER: Shader = Shader { name: "peel.wgsl", source: include_str!("../../shaders/peel.wgsl") };
/// The k-buffer's resolve.
pub const KBUFFER_SHADER: Shader = Shader { name: "kbuffer.wgsl", source: include_str!("../../shaders/kbuffer.wgsl") };
/// Every shader, for validation.
pub const SHADERS: [&Shader; 6] =
    [&ORGAN_SHADER, &ORGAN_CLIP_SHADER, &COMPOSITE_SHADER, &SCREENDOOR_SHADER, &PEEL_SHADER, &KBUFFER_SHADER];

/// The organ pipelines' WGSL: organ.wgsl, and where the device has clip distances, organ_clip.wgsl
/// after it (`vs_clipped`).
pub fn organ_source(clip_distances: bool) -> String {
    match clip_distances {
        true => format!("enable clip_distances;\n{}\n{}", ORGAN_SHADER.source, ORGAN_CLIP_SHADER.source),
        false => ORGAN_SHADER.source.to_string(),
    }
}
