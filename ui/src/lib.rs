//! vbrain's desktop viewer (eframe + wgpu) and its command line.
//!
//! The viewer draws through the core's offscreen renderer into a texture that egui paints, so the
//! viewport, exported screenshots and `vbrain render` show the same pixels. Modules: [`viewer`]
//! (the desktop app), [`cli`] (the headless commands) and [`lab`] (the experiments the commands
//! report: benchmarks, mask and occluder experiments, plots).

pub mod cli;
pub mod lab;
pub mod viewer;

pub use viewer::{App, AppOptions};

/// Background of the viewport and of `vbrain render` (linear RGBA).
pub const BACKGROUND: [f32; 4] = [0.012, 0.014, 0.02, 1.0];
