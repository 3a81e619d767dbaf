//! The viewer's native window: its options and [`run`], which opens the window on an [`App`] with
//! the files [`super::paths`] names.
//!
//! - The options' sizes (default and smallest) are in egui points.

use super::app::{App, AppOptions};
use super::paths::{quiz_history_path, recovery_path};
use anyhow::{anyhow, Result};
use eframe::egui;
use std::path::PathBuf;
use std::sync::Arc;

/// The smallest window, in points: the panels and a usable 3-D view. A stored window geometry
/// (eframe keeps it with the settings) smaller than this, or not a number, opens at this size;
/// eframe itself keeps a window within the largest monitor.
pub const MIN_WINDOW: [f32; 2] = [640.0, 420.0];

/// The window's options: title, default and smallest size, file drops, and the GPU device.
pub fn native_options() -> eframe::NativeOptions {
    eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        wgpu_options: wgpu_options(),
        viewport: egui::ViewportBuilder::default()
            .with_title("vbrain")
            .with_inner_size([1280.0, 820.0])
            .with_min_inner_size(MIN_WINDOW)
            .with_drag_and_drop(true)
            .with_app_id("io.github.vbrain.vbrain")
            .with_icon(Arc::new(icon())),
        ..Default::default()
    }
}

/// The window's icon: the launcher's icon (packaging/icons), 256 pixels square.
pub fn icon() -> egui::IconData {
    const PNG: &[u8] = include_bytes!("../../../packaging/icons/vbrain-256.png");
    match image::load_from_memory_with_format(PNG, image::ImageFormat::Png) {
        Ok(img) => {
            let img = img.into_rgba8();
            egui::IconData { width: img.width(), height: img.height(), rgba: img.into_raw() }
        }
        // The PNG is part of the build; a test decodes it.
        Err(_) => egui::IconData::default(),
    }
}

/// The viewer's GPU device: egui's defaults, and the features the headless renderer asks for where
/// the adapter has them (float blending for dual depth peeling, clip distances for cut sections).
fn wgpu_options() -> egui_wgpu::WgpuConfiguration {
    let mut setup = egui_wgpu::WgpuSetupCreateNew::without_display_handle();
    let defaults = setup.device_descriptor.clone();
    setup.device_descriptor = Arc::new(move |adapter| {
        let mut descriptor = defaults(adapter);
        descriptor.required_features |= adapter.features() & vbrain::render::WANTED_FEATURES;
        descriptor
    });
    egui_wgpu::WgpuConfiguration { wgpu_setup: egui_wgpu::WgpuSetup::CreateNew(setup), ..Default::default() }
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
                AppOptions {
                    path,
                    recovery: recovery_path(),
                    quiz_history: quiz_history_path(),
                    data: vbrain::data_dir::Environment::current(),
                },
            )))
        }),
    )
    .map_err(|e| anyhow!("could not open the viewer window: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_window_has_the_launchers_icon() {
        let icon = icon();
        assert_eq!((icon.width, icon.height), (256, 256));
        assert_eq!(icon.rgba.len(), 256 * 256 * 4);
        // Opaque in the middle, transparent in the corners (the rounded square).
        assert_eq!(icon.rgba[(128 * 256 + 128) * 4 + 3], 255);
        assert_eq!(icon.rgba[3], 0);
    }

    #[test]
    fn the_window_has_a_smallest_size() {
        let options = native_options();
        assert_eq!(options.viewport.min_inner_size, Some(egui::Vec2::from(MIN_WINDOW)));
        let default = options.viewport.inner_size.unwrap_or_default();
        assert!(default.x >= MIN_WINDOW[0] && default.y >= MIN_WINDOW[1]);
        // The smallest window still holds the organ panel, the dock at its narrowest and a 3-D
        // view of 120 points between them.
        let panels = super::super::dock::ORGAN_PANEL_WIDTH + super::super::dock::DOCK_WIDTH[1];
        assert!(MIN_WINDOW[0] >= panels + 120.0, "{MIN_WINDOW:?} leaves no view beside {panels} points of panels");
    }

    #[test]
    fn the_device_has_the_renderers_features_where_the_adapter_can() {
        let egui_wgpu::WgpuSetup::CreateNew(setup) = native_options().wgpu_options.wgpu_setup else {
            panic!("the viewer makes its own device");
        };
        // The adapter the headless renderer opens (it fails saying what to install where none is).
        let gpu = vbrain::render::GpuContext::headless().unwrap();
        let wanted = (setup.device_descriptor)(&gpu.adapter).required_features;
        let can = gpu.adapter.features() & vbrain::render::WANTED_FEATURES;
        assert_eq!(wanted & vbrain::render::WANTED_FEATURES, can);
        let usual = wgpu::Features::FLOAT32_BLENDABLE | wgpu::Features::CLIP_DISTANCES;
        assert!(can.contains(usual), "lavapipe and desktop GPUs blend 32-bit floats and have clip distances");
    }
}
