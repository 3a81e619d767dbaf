//! vbrain's desktop viewer (eframe + wgpu) and its command line.
//!
//! - The viewer draws through the core's offscreen renderer into a texture that egui paints, so
//!   the viewport, exported screenshots and `vbrain render` show the same pixels.
//! - Modules: [`viewer`] (the desktop app), [`cli`] (the headless commands), [`lab`] (the
//!   experiments the commands report: benchmarks, mask and occluder experiments, plots),
//!   [`annotate`] (labels on figures) and [`anki`] (Anki decks of a set's structures).

pub mod anki;
pub mod annotate;
pub mod cli;
pub mod handout;
pub mod lab;
pub mod lecture;
pub mod page_quiz;
pub mod slice_figure;
pub mod studio;
pub mod video;
pub mod viewer;

pub use viewer::{App, AppOptions};

/// The version and the commit it was built from, as `vbrain --version` and Help > About show them.
pub const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), " (commit ", env!("VBRAIN_COMMIT"), ")");

/// Background of the viewport and of `vbrain render` (linear RGBA).
pub const BACKGROUND: [f32; 4] = [0.012, 0.014, 0.02, 1.0];

/// [`BACKGROUND`] as sRGB, as the viewer's settings and scene files hold backgrounds.
pub fn background_srgb() -> [f32; 3] {
    [BACKGROUND[0], BACKGROUND[1], BACKGROUND[2]].map(vbrain::render::linear_to_srgb)
}

/// An sRGB background as the renderer's linear RGBA: opaque, or with alpha 0 if `transparent`.
pub fn background_linear(srgb: [f32; 3], transparent: bool) -> [f32; 4] {
    let [r, g, b] = srgb.map(vbrain::render::srgb_to_linear);
    [r, g, b, if transparent { 0.0 } else { 1.0 }]
}
