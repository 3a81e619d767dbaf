//! The desktop viewer (eframe + wgpu). The viewport is drawn by the core's offscreen renderer into a
//! texture that egui paints, so it shows exactly what `vbrain render` writes.
//! Camera state is an orbit around the set's centre in world space (millimetres, RAS).

use anyhow::{anyhow, Result};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use vbrain::camera::{Camera, View};
use vbrain::layout::Layout;
use vbrain::organ_set::{self, OrganSet};
use vbrain::render::{FrameInput, Renderer, Target};

/// Background of the viewport and of `vbrain render` (linear RGBA).
pub const BACKGROUND: [f32; 4] = [0.012, 0.014, 0.02, 1.0];

/// The default organ set: `organs/brain` under the working directory, else beside the sources.
pub fn default_set_path() -> PathBuf {
    let here = PathBuf::from("organs/brain");
    if here.is_dir() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../organs/brain")
}

pub fn run(path: Option<PathBuf>) -> Result<()> {
    let path = path.unwrap_or_else(default_set_path);
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: eframe::egui::ViewportBuilder::default().with_title("vbrain").with_inner_size([1280.0, 820.0]),
        ..Default::default()
    };
    eframe::run_native("vbrain", options, Box::new(move |cc| Ok(Box::new(Viewer::new(cc, path)))))
        .map_err(|e| anyhow!("could not open the viewer window: {e}"))
}

/// The loaded scene with its GPU resources.
struct Scene {
    set: OrganSet,
    layout: Layout,
    renderer: Renderer,
    /// What the camera frames: the organs shown when the set was opened (world space).
    home: vbrain::mesh::Bounds,
}

/// A set loaded off the UI thread, with its problems as messages; or why it could not load.
type LoadResult = Result<(OrganSet, Vec<String>), String>;

pub struct Viewer {
    scene: Option<Scene>,
    loading: Option<mpsc::Receiver<LoadResult>>,
    messages: Vec<String>,
    target: Option<(Target, eframe::egui::TextureId)>,
    azimuth: f32,
    elevation: f32,
    zoom: f32,
    title: String,
}

impl Viewer {
    fn new(_cc: &eframe::CreationContext, path: PathBuf) -> Viewer {
        let mut v = Viewer {
            scene: None,
            loading: None,
            messages: Vec::new(),
            target: None,
            azimuth: 0.0,
            elevation: 0.0,
            zoom: 1.0,
            title: path.display().to_string(),
        };
        v.open(path);
        v
    }

    /// Loads a set on a worker thread; the UI keeps running.
    fn open(&mut self, path: PathBuf) {
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let result = organ_set::open(&path).map_err(|e| e.to_string()).map(|l| {
                let problems = l.errors.iter().map(|e| e.to_string()).chain(l.warnings).collect();
                (l.set, problems)
            });
            let _ = tx.send(result);
        });
        self.loading = Some(rx);
    }

    fn poll_loading(&mut self, frame: &eframe::Frame) {
        let Some(rx) = &self.loading else { return };
        let Ok(result) = rx.try_recv() else { return };
        self.loading = None;
        match result {
            Ok((set, problems)) => {
                self.messages.extend(problems);
                let Some(rs) = frame.wgpu_render_state() else {
                    self.messages.push("no wgpu render state".into());
                    return;
                };
                match Renderer::new(&rs.device, &set) {
                    Ok(renderer) => {
                        self.title = set.title.clone();
                        let layout = Layout::new(&set);
                        let home = layout.bounds(&set);
                        self.scene = Some(Scene { layout, set, renderer, home });
                    }
                    Err(e) => self.messages.push(e.to_string()),
                }
            }
            Err(e) => self.messages.push(e),
        }
    }

    /// The orbit camera around the home bounds; at zoom 1 exactly `vbrain render --orbit AZ,EL`.
    fn camera(&self, scene: &Scene) -> Camera {
        let mut camera = Camera::orbit(&scene.home, self.azimuth, self.elevation).zoomed(self.zoom);
        camera.fit_depth(&scene.layout.bounds(&scene.set).union(scene.home));
        camera
    }

    fn organ_panel(&mut self, ui: &mut eframe::egui::Ui) {
        let Some(scene) = &mut self.scene else { return };
        ui.heading(&scene.set.title);
        ui.label(format!("{} organs, {} triangles", scene.set.organs.len(), scene.set.triangle_count()));
        ui.separator();
        eframe::egui::ScrollArea::vertical().show(ui, |ui| {
            for (organ, state) in scene.set.organs.iter().zip(scene.layout.organs.iter_mut()) {
                ui.horizontal(|ui| {
                    ui.checkbox(&mut state.visible, "").on_hover_text("Show or hide");
                    ui.add(eframe::egui::Slider::new(&mut state.opacity, 0.0..=1.0).show_value(false));
                    ui.label(&organ.name);
                });
            }
        });
    }

    fn viewport(&mut self, ui: &mut eframe::egui::Ui, frame: &eframe::Frame) {
        let size = ui.available_size();
        let (rect, response) = ui.allocate_exact_size(size, eframe::egui::Sense::click_and_drag());
        if response.dragged() {
            let d = response.drag_delta();
            self.azimuth -= d.x * 0.4;
            self.elevation = (self.elevation + d.y * 0.4).clamp(-89.0, 89.0);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            self.zoom = (self.zoom * (-scroll * 0.002).exp()).clamp(0.05, 5.0);
        }
        let Some(scene) = &self.scene else { return };
        let Some(rs) = frame.wgpu_render_state() else {
            return;
        };
        let ppp = ui.ctx().pixels_per_point();
        let (w, h) = (((rect.width() * ppp) as u32).max(1), ((rect.height() * ppp) as u32).max(1));
        let needs_new = self.target.as_ref().is_none_or(|(t, _)| t.width != w || t.height != h);
        if needs_new {
            match Target::new(&rs.device, w, h) {
                Ok(t) => {
                    let mut egui_renderer = rs.renderer.write();
                    let id = match self.target.take() {
                        Some((_, id)) => {
                            egui_renderer.update_egui_texture_from_wgpu_texture(
                                &rs.device,
                                &t.display_view,
                                wgpu::FilterMode::Linear,
                                id,
                            );
                            id
                        }
                        None => {
                            egui_renderer.register_native_texture(&rs.device, &t.display_view, wgpu::FilterMode::Linear)
                        }
                    };
                    self.target = Some((t, id));
                }
                Err(e) => {
                    self.messages.push(e.to_string());
                    return;
                }
            }
        }
        let Some((target, id)) = &self.target else {
            return;
        };
        let camera = self.camera(scene);
        scene.renderer.render(
            &rs.device,
            &rs.queue,
            target,
            &FrameInput { camera: &camera, layout: &scene.layout, background: BACKGROUND },
        );
        let uv = eframe::egui::Rect::from_min_max(eframe::egui::pos2(0.0, 0.0), eframe::egui::pos2(1.0, 1.0));
        ui.painter().image(*id, rect, uv, eframe::egui::Color32::WHITE);
    }
}

impl eframe::App for Viewer {
    fn ui(&mut self, ui: &mut eframe::egui::Ui, frame: &mut eframe::Frame) {
        use eframe::egui::{CentralPanel, Panel};
        self.poll_loading(frame);
        Panel::top("menu").show(ui, |ui| {
            ui.horizontal(|ui| {
                for v in View::ALL {
                    if ui.button(v.name()).clicked() {
                        (self.azimuth, self.elevation) = v.angles();
                        self.elevation = self.elevation.clamp(-89.0, 89.0);
                    }
                }
                if self.loading.is_some() {
                    ui.spinner();
                    ui.label(format!("loading {}", self.title));
                }
            });
        });
        if !self.messages.is_empty() {
            Panel::bottom("messages").show(ui, |ui| {
                for m in &self.messages {
                    ui.colored_label(eframe::egui::Color32::LIGHT_RED, m);
                }
                if ui.button("Dismiss").clicked() {
                    self.messages.clear();
                }
            });
        }
        Panel::left("organs").default_size(300.0).show(ui, |ui| self.organ_panel(ui));
        CentralPanel::no_frame().show(ui, |ui| self.viewport(ui, frame));
        if self.loading.is_some() {
            ui.ctx().request_repaint_after(std::time::Duration::from_millis(50));
        }
    }
}
