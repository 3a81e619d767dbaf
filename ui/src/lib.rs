//! vbrain's desktop viewer (eframe + wgpu) and its command line.
//!
//! The viewer draws through the core's offscreen renderer into a texture that egui paints, so the
//! viewport, exported screenshots and `vbrain render` show the same pixels. Modules:
//! [`app`] (state, menus, keys), `panels` (organ tree, inspector), `viewport` (drawing, camera and
//! organ manipulation by mouse), `files` (open, import, recent, drag and drop), `export`
//! (screenshots), `jobs` (work off the UI thread), `settings` (what persists), [`cli`] (headless), with `bench`, `masks` and `occluders` (experiments) and `plot`.

pub mod app;
pub mod bench;
pub mod cli;
pub mod export;
pub mod files;
pub mod jobs;
pub mod masks;
pub mod occluders;
mod panels;
pub mod plot;
pub mod settings;
pub mod transparency_bench;
pub mod viewport;

pub use app::{App, AppOptions};

/// Background of the viewport and of `vbrain render` (linear RGBA).
pub const BACKGROUND: [f32; 4] = [0.012, 0.014, 0.02, 1.0];

/// Sets the accessible name of a widget (AccessKit), so screen readers and tests find it.
pub fn accessible(response: &eframe::egui::Response, label: impl Into<String>) {
    let label = label.into();
    response.ctx.accesskit_node_builder(response.id, |node| node.set_label(label));
}
