//! The viewer's state and its frame: menus, keyboard shortcuts, panels, viewport, dialogs, status
//! bar and notifications. Organ state lives in the core's [`Layout`] (world space, millimetres RAS).

use super::files::Dialogs;
use super::jobs::Job;
use super::settings::Settings;
use super::viewport::Viewport;
use anyhow::{anyhow, Result};
use eframe::egui::{self, Key, KeyboardShortcut, Modifiers};
use std::path::{Path, PathBuf};
use vbrain::camera::View;
use vbrain::layout::{Layout, Transform};
use vbrain::mesh::Bounds;
use vbrain::organ_set::{self, Loaded, OrganSet};
use vbrain::render::Renderer;

/// How the viewer starts.
#[derive(Clone, Debug, Default)]
pub struct AppOptions {
    /// What to open; `None` opens the default brain (or the last set, if the settings say so).
    pub path: Option<PathBuf>,
}

/// The default organ set: `organs/brain` under the working directory, else beside the sources.
pub fn default_set_path() -> PathBuf {
    let here = PathBuf::from("organs/brain");
    if here.is_dir() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../organs/brain")
}

/// Opens the viewer window.
pub fn run(path: Option<PathBuf>) -> Result<()> {
    let options = eframe::NativeOptions {
        renderer: eframe::Renderer::Wgpu,
        viewport: egui::ViewportBuilder::default()
            .with_title("vbrain")
            .with_inner_size([1280.0, 820.0])
            .with_drag_and_drop(true),
        ..Default::default()
    };
    eframe::run_native("vbrain", options, Box::new(move |cc| Ok(Box::new(App::new(cc, AppOptions { path })))))
        .map_err(|e| anyhow!("could not open the viewer window: {e}"))
}

/// A loaded set with its GPU resources and the user's changes.
pub struct Scene {
    pub set: OrganSet,
    /// Where it was opened from (a folder, a file, or several files joined by the title).
    pub source: Vec<PathBuf>,
    pub layout: Layout,
    pub renderer: Renderer,
    /// What the camera frames on reset: the organs shown when the set was opened (world space).
    pub home: Bounds,
    /// Per organ, the opacity the transparency toggle returns to.
    pub last_translucent: Vec<f32>,
    /// Culls frame after frame, keeping where each organ's last traversal stopped.
    pub culler: vbrain::cull::Culler,
}

impl Scene {
    /// Sets an organ's opacity, remembering translucent values for the toggle.
    pub fn set_opacity(&mut self, organ: usize, opacity: f32) {
        let opacity = opacity.clamp(0.0, 1.0);
        self.layout.organs[organ].opacity = opacity;
        if opacity < 1.0 && opacity > 0.0 {
            self.last_translucent[organ] = opacity;
        }
    }

    /// Opaque <-> the organ's last translucent opacity.
    pub fn toggle_transparency(&mut self, organ: usize) {
        let s = &self.layout.organs[organ];
        let next = if s.opacity >= 1.0 { self.last_translucent[organ] } else { 1.0 };
        self.set_opacity(organ, next);
    }

    /// Shows only these organs.
    pub fn isolate(&mut self, organs: &[usize]) {
        for (i, s) in self.layout.organs.iter_mut().enumerate() {
            s.visible = organs.contains(&i);
        }
    }

    pub fn show_all(&mut self) {
        self.layout.organs.iter_mut().for_each(|s| s.visible = true);
    }

    /// Back to the set's defaults: visibility, opacity, colour, no transforms.
    pub fn reset_layout(&mut self) {
        self.layout = Layout::new(&self.set);
    }

    pub fn reset_transform(&mut self, organ: usize) {
        let t = &mut self.layout.organs[organ].transform;
        *t = Transform::identity(t.pivot);
    }

    /// World bounds of one organ as placed now.
    pub fn organ_bounds(&self, organ: usize) -> Bounds {
        self.set.organs[organ].mesh.bounds().transformed(&self.layout.organs[organ].transform.matrix())
    }
}

/// A message for the user; errors name the file that failed.
pub struct Notification {
    pub text: String,
    pub error: bool,
}

type LoadResult = Result<(Loaded, Vec<PathBuf>), String>;

pub struct App {
    /// The device eframe renders with; the scene draws with it too.
    pub gpu: Option<egui_wgpu::RenderState>,
    pub scene: Option<Scene>,
    pub selected: Option<usize>,
    pub settings: Settings,
    pub notifications: Vec<Notification>,
    pub viewport: Viewport,
    pub dialogs: Dialogs,
    pub(crate) filter: String,
    loading: Option<Job<LoadResult>>,
    pub(crate) importing: Option<Job<Result<PathBuf, String>>>,
}

/// Keyboard shortcuts, also shown in the menus.
pub mod keys {
    use super::*;
    pub const EXPORT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::S);
    pub const OPEN: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::O);
    pub const RESET_LAYOUT: KeyboardShortcut = KeyboardShortcut::new(Modifiers::COMMAND, Key::R);
    pub const VIEWS: [(Key, View); 6] = [
        (Key::Num1, View::Anterior),
        (Key::Num2, View::Posterior),
        (Key::Num3, View::Left),
        (Key::Num4, View::Right),
        (Key::Num5, View::Superior),
        (Key::Num6, View::Inferior),
    ];
}

impl App {
    pub fn new(cc: &eframe::CreationContext, options: AppOptions) -> App {
        let settings = Settings::load(cc.storage);
        let mut app = App {
            gpu: cc.wgpu_render_state.clone(),
            scene: None,
            selected: None,
            notifications: Vec::new(),
            viewport: Viewport::default(),
            dialogs: Dialogs::default(),
            filter: String::new(),
            loading: None,
            importing: None,
            settings,
        };
        let path = match options.path {
            Some(p) => p,
            None => match &app.settings.last_set {
                Some(last) if app.settings.reopen_last && last.exists() => last.clone(),
                _ => default_set_path(),
            },
        };
        app.open(&cc.egui_ctx, vec![path]);
        app
    }

    /// Loads a set (one folder or file) or several mesh files, off the UI thread.
    pub fn open(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        let title = match paths.as_slice() {
            [one] => one.display().to_string(),
            many => format!("{} files", many.len()),
        };
        self.loading = Some(Job::spawn(title, ctx, move |progress| {
            progress.set(0, 1, "reading meshes");
            let result = match paths.as_slice() {
                [one] => organ_set::open(one),
                many => organ_set::open_files(many, "Mesh files"),
            };
            progress.set(1, 1, "uploading");
            result.map(|l| (l, paths)).map_err(|e| e.to_string())
        }));
    }

    pub fn is_loading(&self) -> bool {
        self.loading.is_some() || self.importing.is_some()
    }

    /// The running job: title, progress (if known) and message.
    pub fn loading_job(&self) -> Option<(String, Option<f32>, String)> {
        let (title, p) = match (&self.loading, &self.importing) {
            (Some(j), _) => (&j.title, &j.progress),
            (None, Some(j)) => (&j.title, &j.progress),
            _ => return None,
        };
        Some((title.clone(), p.fraction(), p.message()))
    }

    pub fn notify(&mut self, text: impl Into<String>, error: bool) {
        self.notifications.push(Notification { text: text.into(), error });
    }

    fn poll_jobs(&mut self, ctx: &egui::Context) {
        if let Some(result) = self.importing.as_ref().and_then(|j| j.poll()) {
            self.importing = None;
            match result {
                Ok(dir) => {
                    self.notify(format!("imported into {}", dir.display()), false);
                    self.open(ctx, vec![dir]);
                }
                Err(e) => self.notify(e, true),
            }
        }
        let Some(result) = self.loading.as_ref().and_then(|j| j.poll()) else { return };
        self.loading = None;
        match result {
            Ok((loaded, paths)) => self.install(loaded, paths),
            Err(e) => self.notify(e, true),
        }
    }

    /// Makes a loaded set the scene (the previous one stays if this one has no organs).
    fn install(&mut self, loaded: Loaded, paths: Vec<PathBuf>) {
        for w in loaded.warnings {
            self.notify(w, false);
        }
        for e in loaded.errors {
            self.notify(e.to_string(), true);
        }
        if loaded.set.organs.is_empty() {
            self.notify(format!("{}: no organ could be loaded", paths_label(&paths)), true);
            return;
        }
        let Some(rs) = &self.gpu else {
            self.notify("the viewer needs the wgpu renderer", true);
            return;
        };
        match Renderer::new(&rs.device, &loaded.set) {
            Ok(renderer) => {
                let set = loaded.set;
                let layout = Layout::new(&set);
                let home = layout.bounds(&set);
                let last_translucent =
                    set.organs.iter().map(|o| if o.opacity < 1.0 { o.opacity } else { 0.4 }).collect();
                if let [one] = paths.as_slice() {
                    self.settings.remember(one);
                }
                self.viewport.reset_camera(&home);
                self.selected = None;
                self.scene = Some(Scene {
                    set,
                    source: paths,
                    layout,
                    renderer,
                    home,
                    last_translucent,
                    culler: Default::default(),
                });
            }
            Err(e) => self.notify(e.to_string(), true),
        }
    }

    /// Keyboard shortcuts that act when no text field has the keyboard.
    fn handle_keys(&mut self, ctx: &egui::Context) {
        if ctx.input_mut(|i| i.consume_shortcut(&keys::EXPORT)) {
            self.dialogs.export.open = true;
        }
        if ctx.input_mut(|i| i.consume_shortcut(&keys::OPEN)) {
            self.dialogs.open_set.open = true;
        }
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        if ctx.input_mut(|i| i.consume_shortcut(&keys::RESET_LAYOUT)) {
            if let Some(s) = &mut self.scene {
                s.reset_layout();
            }
        }
        let pressed = |key| ctx.input(|i| i.key_pressed(key) && i.modifiers.is_none());
        for (key, view) in keys::VIEWS {
            if pressed(key) {
                self.viewport.set_view(view, self.scene.as_ref().map(|s| s.home));
            }
        }
        if pressed(Key::Home) || pressed(Key::R) {
            if let Some(s) = &self.scene {
                self.viewport.reset_camera(&s.home);
            }
        }
        if pressed(Key::G) {
            self.viewport.fly = !self.viewport.fly;
        }
        if pressed(Key::Escape) {
            self.selected = None;
        }
        let (Some(scene), Some(sel)) = (&mut self.scene, self.selected) else { return };
        if pressed(Key::T) {
            scene.toggle_transparency(sel);
        }
        if pressed(Key::H) {
            scene.layout.organs[sel].visible = !scene.layout.organs[sel].visible;
        }
        if pressed(Key::I) {
            scene.isolate(&[sel]);
        }
        if pressed(Key::F) {
            let b = scene.organ_bounds(sel);
            self.viewport.nav.frame(&b);
        }
    }

    fn menu_bar(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui
                    .add(egui::Button::new("Open organ set...").shortcut_text(ui.ctx().format_shortcut(&keys::OPEN)))
                    .clicked()
                {
                    self.dialogs.open_set.open = true;
                }
                if ui.button("Open mesh files...").clicked() {
                    self.dialogs.open_meshes.open = true;
                }
                if ui.button("Import label volume...").clicked() {
                    self.dialogs.import.open = true;
                }
                ui.menu_button("Recent sets", |ui| {
                    if self.settings.recent.is_empty() {
                        ui.label("none yet");
                    }
                    for p in self.settings.recent.clone() {
                        if ui.button(p.display().to_string()).clicked() {
                            self.open(ui.ctx(), vec![p]);
                        }
                    }
                });
                ui.separator();
                let export =
                    egui::Button::new("Export screenshot...").shortcut_text(ui.ctx().format_shortcut(&keys::EXPORT));
                if ui.add_enabled(self.scene.is_some(), export).clicked() {
                    self.dialogs.export.open = true;
                }
                ui.separator();
                if ui.button("Quit").clicked() {
                    ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
                }
            });
            ui.menu_button("View", |ui| {
                for (key, view) in keys::VIEWS {
                    let label = format!("{}{}", view.name()[..1].to_uppercase(), &view.name()[1..]);
                    if ui
                        .add(egui::Button::new(label).shortcut_text(format!("{key:?}").trim_start_matches("Num")))
                        .clicked()
                    {
                        self.viewport.set_view(view, self.scene.as_ref().map(|s| s.home));
                    }
                }
                ui.separator();
                if ui.add(egui::Button::new("Reset camera").shortcut_text("R")).clicked() {
                    if let Some(s) = &self.scene {
                        self.viewport.reset_camera(&s.home);
                    }
                }
                ui.checkbox(&mut self.viewport.fly, "Walk-through camera (G)");
                ui.separator();
                ui.menu_button("Culling of hidden tissue", |ui| {
                    let c = &mut self.settings.cull;
                    for mode in vbrain::cull::CullMode::ALL {
                        ui.radio_value(&mut c.mode, mode, mode.name());
                    }
                    ui.separator();
                    ui.label("Occluders");
                    let has_db = self.scene.as_ref().is_some_and(|s| s.set.occluders.is_some());
                    let choices = [
                        (vbrain::cull::Selection::Auto, "automatic: pre-computed while nothing moved"),
                        (vbrain::cull::Selection::ProjectedSize, "projected size (every frame)"),
                        (vbrain::cull::Selection::Mos, "pre-computed minimum occluder sets"),
                    ];
                    for (selection, label) in choices {
                        let r = ui.radio_value(&mut c.selection, selection, label);
                        crate::viewer::accessible(&r, format!("Occluders: {}", selection.name()));
                    }
                    if !has_db {
                        ui.weak("This set has no occluder database (vbrain occluders PATH).");
                    }
                    ui.separator();
                    let r = ui.add(egui::Slider::new(&mut c.width, 32..=512).text("culling raster (pixels)"));
                    crate::viewer::accessible(&r, "Culling raster size");
                    c.height = c.width;
                    let r = ui.add(
                        egui::Slider::new(&mut c.occluder_triangles, 128..=131_072)
                            .logarithmic(true)
                            .text("occluder triangles"),
                    );
                    crate::viewer::accessible(&r, "Occluder triangle budget");
                    let r = ui
                        .add(egui::Slider::new(&mut c.adaptive_ratio, 0.0..=1.0).text("adaptive stop below coverage"));
                    crate::viewer::accessible(&r, "Adaptive stop ratio");
                    let mut approximate = c.hole_tolerance.is_some();
                    if ui.checkbox(&mut approximate, "approximate overlap test (not exact)").changed() {
                        c.hole_tolerance = approximate.then_some(0.05);
                    }
                    if let Some(t) = &mut c.hole_tolerance {
                        ui.add(egui::Slider::new(t, 0.0..=0.5).text("hole tolerance"));
                    }
                    if ui.button("Defaults").clicked() {
                        *c = vbrain::cull::CullSettings::default();
                    }
                    ui.separator();
                    ui.checkbox(&mut self.settings.cull_debug, "Debug view: culled triangles in colour");
                });
                ui.menu_button("Transparency of faded organs", |ui| {
                    let t = &mut self.settings.transparency;
                    for mode in vbrain::transparency::TransparencyMode::ALL {
                        ui.radio_value(&mut t.mode, mode, mode.name());
                    }
                    ui.separator();
                    ui.label("Screen-door masks");
                    for (label, value) in [
                        ("sub-samples, still", &mut t.subsamples),
                        ("sub-samples, moving", &mut t.interactive_subsamples),
                    ] {
                        egui::ComboBox::from_label(label).selected_text(value.to_string()).show_ui(ui, |ui| {
                            for n in vbrain::transparency::SUBSAMPLE_CHOICES {
                                ui.selectable_value(value, n, n.to_string());
                            }
                        });
                    }
                    let r = ui.add(egui::Slider::new(&mut t.region_px, 4..=128).text("region (pixels)"));
                    crate::viewer::accessible(&r, "Mask region size");
                    let r = ui.add(egui::Slider::new(&mut t.k, 1..=16).text("K nearest organs compensated"));
                    crate::viewer::accessible(&r, "Neighbourhood error compensation K");
                    if ui.button("Defaults").clicked() {
                        *t = vbrain::transparency::TransparencySettings::default();
                    }
                });
                ui.separator();
                ui.checkbox(&mut self.settings.show_inspector, "Inspector");
                ui.checkbox(&mut self.settings.show_stats, "Statistics (fps, culling and mask overlay)");
                ui.horizontal(|ui| {
                    ui.label("Background");
                    let r = ui.color_edit_button_rgb(&mut self.settings.background);
                    crate::viewer::accessible(&r, "Background colour");
                });
            });
            ui.menu_button("Organs", |ui| {
                let has = self.scene.is_some();
                if ui.add_enabled(has, egui::Button::new("Show all")).clicked() {
                    if let Some(s) = &mut self.scene {
                        s.show_all();
                    }
                }
                let reset = egui::Button::new("Reset organ layout")
                    .shortcut_text(ui.ctx().format_shortcut(&keys::RESET_LAYOUT));
                if ui.add_enabled(has, reset).clicked() {
                    if let Some(s) = &mut self.scene {
                        s.reset_layout();
                    }
                }
                ui.add(
                    egui::Slider::new(&mut self.settings.pick_min_opacity, 0.0..=1.0)
                        .text("click through below opacity"),
                );
            });
            ui.menu_button("Help", |ui| {
                ui.label(CONTROLS);
            });
            if let Some((title, fraction, message)) = self.loading_job() {
                ui.separator();
                ui.label(format!("loading {title}"));
                match fraction {
                    Some(f) => {
                        ui.add(egui::ProgressBar::new(f).desired_width(160.0).text(message));
                    }
                    None => {
                        ui.spinner();
                    }
                }
            }
        });
    }

    fn status_bar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let Some(scene) = &self.scene else {
                ui.label(if self.is_loading() { "loading..." } else { "no organ set: File > Open organ set..." });
                return;
            };
            let stats = self.viewport.stats;
            if self.settings.show_stats {
                ui.label(format!("{:.0} fps", self.viewport.fps()));
                ui.separator();
            }
            ui.label(format!("{} / {} triangles drawn", stats.triangles_drawn, scene.set.triangle_count()));
            ui.separator();
            ui.label(format!("{} organs drawn", stats.organs_drawn));
            ui.separator();
            ui.label(if self.viewport.fly { "walk-through camera" } else { "orbit camera" });
            ui.separator();
            ui.label(format!("transparency: {}", self.settings.transparency.mode.name()));
            ui.separator();
            let occluders = match self.viewport.cull.source {
                Some(vbrain::cull::OccluderSource::Mos) => ", pre-computed occluders",
                Some(vbrain::cull::OccluderSource::ProjectedSize) => ", occluders by projected size",
                None => "",
            };
            ui.label(format!("culling: {}{occluders}", self.settings.cull.mode.name()));
            if let Some(sel) = self.selected {
                ui.separator();
                ui.label(format!("selected: {}", scene.set.organs[sel].name));
            }
        });
    }

    fn notifications(&mut self, ctx: &egui::Context) {
        if self.notifications.is_empty() {
            return;
        }
        let mut dismiss = None;
        egui::Area::new(egui::Id::unique("notifications")).anchor(egui::Align2::RIGHT_BOTTOM, [-12.0, -36.0]).show(
            ctx,
            |ui| {
                egui::Frame::popup(ui.style()).show(ui, |ui| {
                    ui.set_max_width(520.0);
                    for (i, n) in self.notifications.iter().enumerate().rev().take(8) {
                        ui.horizontal(|ui| {
                            let colour = if n.error { egui::Color32::LIGHT_RED } else { ui.visuals().text_color() };
                            if ui.small_button("x").on_hover_text("Dismiss").clicked() {
                                dismiss = Some(i);
                            }
                            ui.add(egui::Label::new(egui::RichText::new(&n.text).color(colour)).wrap());
                        });
                    }
                    if self.notifications.len() > 1 && ui.button("Dismiss all").clicked() {
                        dismiss = Some(usize::MAX);
                    }
                });
            },
        );
        match dismiss {
            Some(usize::MAX) => self.notifications.clear(),
            Some(i) => {
                self.notifications.remove(i);
            }
            None => {}
        }
    }

    fn dropped_files(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).filter(|p| !p.as_os_str().is_empty()).collect()
        });
        if dropped.is_empty() {
            return;
        }
        let volume = dropped.iter().find(|p| super::files::is_volume(p));
        if let Some(v) = volume {
            self.dialogs.import.volume = v.display().to_string();
            self.dialogs.import.open = true;
        } else if dropped.len() == 1 {
            self.open(ctx, dropped);
        } else {
            let meshes: Vec<PathBuf> = dropped.into_iter().filter(|p| organ_set::is_mesh_file(p)).collect();
            if meshes.is_empty() {
                self.notify("dropped files are neither organ sets, meshes nor label volumes", true);
            } else {
                self.open(ctx, meshes);
            }
        }
    }
}

fn paths_label(paths: &[PathBuf]) -> String {
    paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
}

pub const CONTROLS: &str = "Mouse: drag to orbit, right or middle drag to pan, wheel to zoom toward the cursor, \
click to select an organ, double-click to frame it.\n\
With an organ selected: Ctrl+drag moves it, Shift+drag rotates it, Ctrl+wheel resizes it.\n\
Keys: 1-6 anterior, posterior, left, right, superior, inferior view; R or Home reset camera; \
G walk-through camera (W/A/S/D/Q/E move, drag to look); F frame selected; T toggle its transparency; \
H hide or show it; I isolate it; Esc deselect; Ctrl+R reset organ layout; Ctrl+O open; Ctrl+S export screenshot.";

impl eframe::App for App {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        use egui::{CentralPanel, Panel};
        let ctx = ui.ctx().clone();
        self.poll_jobs(&ctx);
        self.dropped_files(&ctx);
        self.handle_keys(&ctx);
        Panel::top("menu").show(ui, |ui| self.menu_bar(ui));
        Panel::bottom("status").show(ui, |ui| self.status_bar(ui));
        Panel::left("organs").default_size(330.0).resizable(true).show(ui, |ui| super::panels::organ_panel(self, ui));
        if self.settings.show_inspector && self.selected.is_some() {
            Panel::right("inspector")
                .default_size(300.0)
                .resizable(true)
                .show(ui, |ui| super::panels::inspector(self, ui));
        }
        CentralPanel::no_frame().show(ui, |ui| super::viewport::show(self, ui));
        super::files::windows(self, &ctx);
        self.notifications(&ctx);
        if self.is_loading() {
            ctx.request_repaint_after(std::time::Duration::from_millis(100));
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        self.settings.save(storage);
    }
}
