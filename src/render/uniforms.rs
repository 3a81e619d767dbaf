//! The GPU structs shared with the WGSL shaders.
//!
//! - Each is `#[repr(C)]` and named beside its WGSL struct in [`SHARED_STRUCTS`], so that a test
//!   compares their sizes with what naga reports.
//! - Buffers hold them in slots [`SLOT`] bytes apart, chosen by dynamic offsets (one per pass).
//! - The organs' data is an array in a storage buffer.

/// Distance between slots of a uniform buffer (the largest alignment a device may require).
pub(super) const SLOT: u64 = 256;

/// Passes a frame may draw with their own frame and screen-door uniforms: one per 4 of the most
/// screen-door sub-samples there are.
pub(super) const MAX_PASSES: u64 = {
    let choices = crate::transparency::SUBSAMPLE_CHOICES;
    choices[choices.len() - 1] as u64 / 4
};

/// Slots of the frame uniform: 0 is the frame as seen, `1 + p` pass `p` of screen-door.
pub(super) const FRAME_SLOTS: u64 = 1 + MAX_PASSES;

/// `Frame` in shaders/organ.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct FrameUniform {
    pub view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    /// NDC x' = x * zw + xy: a sub-pixel shift, or a tile of an atlas ([`UNMOVED`] otherwise).
    pub jitter: [f32; 4],
    /// Clip planes (normal, offset), removing `n . p > d`; unused ones remove nothing.
    pub clip: [[f32; 4]; crate::clip::MAX_PLANES],
    /// Organ space (millimetres) -> the MRI texture's coordinates (0..1 across its voxel centres'
    /// cells).
    pub mri: [[f32; 4]; 4],
    /// What cut faces show: x 0 colour, 1 MRI, 2 MRI tinted (0 where the set has no MRI on the
    /// GPU); y window; z level.
    pub cut_face: [f32; 4],
    /// x: 1 where vertices' territory colours replace their organs' (territory colouring).
    pub colour_by: [u32; 4],
}

/// The frame's `jitter` that leaves the image where it is.
pub(super) const UNMOVED: [f32; 4] = [0.0, 0.0, 1.0, 1.0];

/// A vertex as the organ pipelines read it (`VsIn` in shaders/organ.wgsl, locations 0-3):
/// organ-space position and normal, the organ's index, and its arterial territory's colour (sRGB
/// bytes r, g, b, a from the low byte up; 0 for none).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub organ: u32,
    pub territory: u32,
}

/// `Organ` in shaders/organ.wgsl (an array of them in a storage buffer, one section per use).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct OrganUniform {
    pub model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 4],
    pub colour: [f32; 4],
    /// x: organ index + 1; y: [`CLIPPED`] | [`CAPPED`] | [`CLOSED`].
    pub id: [u32; 4],
}

/// Organ flag: the clip planes cut it.
pub(super) const CLIPPED: u32 = 1;
/// Organ flag: closed and cut, its inside seen through the cut is drawn as a solid face.
pub(super) const CAPPED: u32 = 2;

/// Organ flag: closed (drawn with its back faces culled, which the k-buffer does in its shader).
pub(super) const CLOSED: u32 = 4;

/// `KBuffer` in shaders/organ.wgsl and shaders/kbuffer.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct KBufferUniform {
    pub width: u32,
    pub height: u32,
    pub k: u32,
    pub pad: u32,
}

/// `Screendoor` in shaders/organ.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct ScreendoorUniform {
    pub region_px: u32,
    pub cols: u32,
    pub rows: u32,
    pub organs: u32,
    /// Atlas pixel = screen pixel + offset, for the pass's tile.
    pub offset: [i32; 2],
    pub pass_index: u32,
    pub pad: u32,
}

/// `Gather` in shaders/screendoor.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct GatherUniform {
    pub origin: [i32; 2],
    pub tile: [i32; 2],
    pub tiles_x: u32,
    pub first: u32,
    pub count: u32,
    pub pad: u32,
}

/// (shader file, WGSL struct, size of the Rust struct in bytes) of every struct shared with WGSL.
pub const SHARED_STRUCTS: [(&str, &str, usize); 7] = [
    ("organ.wgsl", "Frame", std::mem::size_of::<FrameUniform>()),
    ("organ.wgsl", "Organ", std::mem::size_of::<OrganUniform>()),
    ("organ.wgsl", "Screendoor", std::mem::size_of::<ScreendoorUniform>()),
    ("screendoor.wgsl", "Screendoor", std::mem::size_of::<ScreendoorUniform>()),
    ("screendoor.wgsl", "Gather", std::mem::size_of::<GatherUniform>()),
    ("organ.wgsl", "KBuffer", std::mem::size_of::<KBufferUniform>()),
    ("kbuffer.wgsl", "KBuffer", std::mem::size_of::<KBufferUniform>()),
];
