//! vbrain's headless core: organ sets, their meshes, and the offscreen renderer.
//!
//! - Organ space and world space are both millimetres, RAS; render targets are in screen pixels.
//! - Nothing here panics on bad input: every file error names its file (and line).
//! - A frame flows like this:
//! 1. [`organ_set::open`] reads an organ set (a folder with `organset.json` and `.vbo`/`.obj`
//!    meshes, a folder of meshes, or one mesh file) into an [`organ_set::OrganSet`]: meshes in
//!    organ space, millimetres RAS. [`organ_set::import`] makes sets from label volumes;
//!    [`organ_set::scale`] makes denser copies for benchmarks.
//! 2. The user's changes live in a [`layout::Layout`]: per organ visibility, opacity, colour and a
//!    model transform (organ space -> world space, also millimetres RAS).
//! 3. A [`camera::Camera`] maps world space to clip space.
//! 4. [`cull`] picks what to draw: view-frustum and occlusion culling over each organ's hierarchy
//!    ([`bvh`]) with an opacity map and a sparse depth map.
//! 5. [`transparency`] builds screen-door masks for faded organs, per screen region, with the
//!    tabular pixel mask and neighbourhood error compensation.
//! 6. [`render::Renderer`] draws camera + layout into a [`render::Target`] (screen pixels): opaque
//!    organs with depth and 4x MSAA, faded ones through their masks (or a comparison mode), and on
//!    demand an organ-ID buffer for picking. The viewer paints the target; headless commands read
//!    it back into a PNG.

pub mod atomic;
pub mod bvh;
pub mod camera;
pub mod clip;
pub mod colouring;
pub mod cull;
pub mod cut_mesh;
pub mod data_dir;
pub mod edit;
pub mod error;
pub mod gltf;
pub mod history;
pub mod input;
pub mod json_file;
pub mod lab;
pub mod labels;
pub mod layout;
pub mod lesson;
pub mod lod;
pub mod mesh;
pub mod mos;
pub mod mri;
pub mod multi_surface;
pub mod navigation;
pub mod nifti_file;
pub mod organ_set;
pub mod quiz;
pub mod render;
pub mod rng;
pub mod scene_file;
pub mod scorm;
pub mod surface;
pub mod transition;
pub mod transparency;
pub mod web_page;

pub use error::{Error, Result};
