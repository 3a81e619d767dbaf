//! The viewer's window and where it keeps its files: the native options (default and smallest
//! size, in egui points), the default organ set, the recovery and quiz-history files beside
//! eframe's settings, and [`run`], which opens the window on an [`App`].

use super::app::{App, AppOptions};
use anyhow::{anyhow, Result};
use eframe::egui;
use std::path::{Path, PathBuf};

/// Where the viewer keeps its recovery file: beside its settings.
pub fn recovery_path() -> Option<PathBuf> {
    eframe::storage_dir("vbrain").map(|d| d.join("recovery.vbscene"))
}

/// Where the viewer keeps quiz results: beside its settings.
pub fn quiz_history_path() -> Option<PathBuf> {
    eframe::storage_dir("vbrain").map(|d| d.join("quiz-history.csv"))
}

/// The default organ set: `organs/brain` under the working directory, else beside the sources.
pub fn default_set_path() -> PathBuf {
    let here = PathBuf::from("organs/brain");
    if here.is_dir() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../organs/brain")
}

/// The smallest window, in points: the panels and a usable 3-D view. A stored window geometry
/// (eframe keeps it with the settings) smaller than this, or not a number, opens at this size;
/// eframe itself keeps a window within the largest monitor.
pub const MIN_WINDOW: [f32; 2] = [640.0, 420.0];

/// The window's options: title, default and smallest size, file drops.
pub fn native_options() -> eframe::NativeOptions {
    eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default()
            .with_title("vbrain")
            .with_inner_size([1280.0, 820.0])
            .with_min_inner_size(MIN_WINDOW)
            .with_drag_and_drop(true),
        ..Default::default()
    }
}

/// Opens the viewer window.
pub fn run(path: Option<PathBuf>) -> Result<()> {
    let options = native_options();
    eframe::run_native(
        "vbrain",
        options,
        Box::new(move |cc| {
            Ok(Box::new(App::new(
                cc,
                AppOptions { path, recovery: recovery_path(), quiz_history: quiz_history_path() },
            )))
        }),
    )
    .map_err(|e| anyhow!("could not open the viewer window: {e}"))
}
