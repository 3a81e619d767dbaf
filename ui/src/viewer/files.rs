//! The file windows: open an organ set, open mesh files, import a label volume, export a
//! screenshot. Each has a path field, so it works where no file-dialog service runs (plain X, or
//! Wayland without a portal); "Browse..." asks the system dialog (rfd) on a worker thread and fills
//! the field if it answers.

use super::app::App;
use super::export;
use super::jobs::Job;
use super::settings::ExportSize;
use eframe::egui;
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use vbrain::render::FrameInput;

/// Is this a NIfTI label volume?
pub fn is_volume(p: &Path) -> bool {
    let name = p.file_name().map(|n| n.to_string_lossy().to_lowercase()).unwrap_or_default();
    name.ends_with(".nii") || name.ends_with(".nii.gz")
}

/// What a system file dialog should ask for.
#[derive(Clone, Copy)]
enum Pick {
    Folder,
    File,
    Files,
    Save,
}

/// A path field with a "Browse..." button backed by a system dialog on a worker thread.
#[derive(Default)]
pub struct PathField {
    pub text: String,
    pending: Option<mpsc::Receiver<Vec<PathBuf>>>,
}

impl PathField {
    fn ui(&mut self, ui: &mut egui::Ui, label: &str, pick: Pick, filters: &[(&str, &[&str])]) {
        if let Some(rx) = &self.pending {
            if let Ok(paths) = rx.try_recv() {
                self.pending = None;
                if !paths.is_empty() {
                    self.text = paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join("; ");
                }
            }
        }
        ui.horizontal(|ui| {
            ui.label(label);
            let r = ui.add(egui::TextEdit::singleline(&mut self.text).desired_width(380.0));
            crate::viewer::accessible(&r, label.trim_end_matches(':'));
            let browse = ui.add_enabled(self.pending.is_none(), egui::Button::new("Browse..."));
            crate::viewer::accessible(&browse, format!("Browse {}", label.trim_end_matches(':')));
            if browse.clicked() {
                let (tx, rx) = mpsc::channel();
                let filters: Vec<(String, Vec<String>)> =
                    filters.iter().map(|(n, e)| (n.to_string(), e.iter().map(|s| s.to_string()).collect())).collect();
                let ctx = ui.ctx().clone();
                let start = self.text.clone();
                std::thread::spawn(move || {
                    let mut d = rfd::FileDialog::new();
                    for (name, exts) in &filters {
                        d = d.add_filter(name, exts);
                    }
                    if let Some(dir) = Path::new(&start).parent().filter(|p| p.is_dir()) {
                        d = d.set_directory(dir);
                    }
                    let picked = match pick {
                        Pick::Folder => d.pick_folder().into_iter().collect(),
                        Pick::File => d.pick_file().into_iter().collect(),
                        Pick::Files => d.pick_files().unwrap_or_default(),
                        Pick::Save => d.save_file().into_iter().collect(),
                    };
                    let _ = tx.send(picked);
                    ctx.request_repaint();
                });
                self.pending = Some(rx);
            }
        });
        if self.pending.is_some() {
            ui.label("waiting for the file dialog (or type the path)");
        }
    }

    fn paths(&self) -> Vec<PathBuf> {
        self.text.split(';').map(str::trim).filter(|s| !s.is_empty()).map(PathBuf::from).collect()
    }
}

#[derive(Default)]
pub struct OpenWindow {
    pub open: bool,
    pub field: PathField,
}

#[derive(Default)]
pub struct ImportWindow {
    pub open: bool,
    pub volume: String,
    labels: PathField,
    volume_field: PathField,
    out: PathField,
    triangles: usize,
}

#[derive(Default)]
pub struct ExportWindow {
    pub open: bool,
    pub path: PathField,
    /// The last export's result, shown in the window.
    pub last: Option<String>,
}

#[derive(Default)]
pub struct Dialogs {
    pub open_set: OpenWindow,
    pub open_meshes: OpenWindow,
    pub import: ImportWindow,
    pub export: ExportWindow,
}

const MESHES: (&str, &[&str]) = ("Meshes", &["obj", "vbo", "OBJ", "VBO"]);
const VOLUMES: (&str, &[&str]) = ("NIfTI label volume", &["nii", "gz"]);
const TABLES: (&str, &[&str]) = ("Label table", &["csv", "txt", "ctbl", "lut"]);

pub fn windows(app: &mut App, ctx: &egui::Context) {
    open_set_window(app, ctx);
    open_meshes_window(app, ctx);
    import_window(app, ctx);
    export_window(app, ctx);
}

fn open_set_window(app: &mut App, ctx: &egui::Context) {
    let mut open = app.dialogs.open_set.open;
    let mut go = None;
    egui::Window::new("Open organ set").open(&mut open).collapsible(false).show(ctx, |ui| {
        ui.label("A folder with organset.json, a folder of .obj/.vbo files, or one mesh file.");
        app.dialogs.open_set.field.ui(ui, "Path:", Pick::Folder, &[]);
        if ui.button("Open").clicked() {
            go = app.dialogs.open_set.field.paths().into_iter().next();
        }
        if !app.settings.recent.is_empty() {
            ui.separator();
            ui.label("Recent:");
            for p in &app.settings.recent {
                if ui.link(p.display().to_string()).clicked() {
                    go = Some(p.clone());
                }
            }
        }
    });
    app.dialogs.open_set.open = open && go.is_none();
    if let Some(p) = go {
        app.open(ctx, vec![p]);
    }
}

fn open_meshes_window(app: &mut App, ctx: &egui::Context) {
    let mut open = app.dialogs.open_meshes.open;
    let mut go = None;
    egui::Window::new("Open mesh files").open(&mut open).collapsible(false).show(ctx, |ui| {
        ui.label("One or more .obj/.vbo files (separate paths with ;). Each object becomes an organ.");
        app.dialogs.open_meshes.field.ui(ui, "Files:", Pick::Files, &[MESHES]);
        if ui.button("Open").clicked() {
            go = Some(app.dialogs.open_meshes.field.paths());
        }
    });
    app.dialogs.open_meshes.open = open && go.is_none();
    match go {
        Some(paths) if !paths.is_empty() => app.open(ctx, paths),
        Some(_) => app.notify("no file given", true),
        None => {}
    }
}

fn import_window(app: &mut App, ctx: &egui::Context) {
    let w = &mut app.dialogs.import;
    if !w.volume.is_empty() {
        w.volume_field.text = std::mem::take(&mut w.volume);
    }
    if w.triangles == 0 {
        w.triangles = 200_000;
    }
    let mut open = w.open;
    let mut start = false;
    egui::Window::new("Import label volume").open(&mut open).collapsible(false).show(ctx, |ui| {
        ui.label(
            "A label volume (atlas or segmentation, NIfTI) and its label table (CSV index,name or a FreeSurfer LUT).",
        );
        w.volume_field.ui(ui, "Volume:", Pick::File, &[VOLUMES]);
        w.labels.ui(ui, "Labels:", Pick::File, &[TABLES]);
        w.out.ui(ui, "Output folder:", Pick::Folder, &[]);
        ui.horizontal(|ui| {
            ui.label("Triangle budget:");
            let r = ui.add(egui::DragValue::new(&mut w.triangles).range(1000..=5_000_000).speed(1000));
            crate::viewer::accessible(&r, "Triangle budget");
        });
        start = ui.add_enabled(app.importing.is_none(), egui::Button::new("Import")).clicked();
    });
    app.dialogs.import.open = open && !start;
    if !start {
        return;
    }
    let w = &app.dialogs.import;
    let (volume, labels, out, triangles) = (
        PathBuf::from(w.volume_field.text.trim()),
        PathBuf::from(w.labels.text.trim()),
        w.out.text.trim().to_string(),
        w.triangles,
    );
    let out = if out.is_empty() { volume.with_extension("").with_extension("") } else { PathBuf::from(out) };
    app.importing = Some(Job::spawn(format!("import {}", volume.display()), ctx, move |progress| {
        use vbrain::organ_set::import;
        let table = import::read_label_table(&labels).map_err(|e| e.to_string())?;
        progress.set(0, 1, "reading volume");
        let vol = import::read_volume(&volume).map_err(|e| e.to_string())?;
        let title = volume.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let opts = import::ImportOptions { triangles, title, ..Default::default() };
        let (set, _warnings) =
            import::import(&vol, &table, &opts, &mut |d, t, m| progress.set(d, t, m)).map_err(|e| e.to_string())?;
        set.save(&out).map_err(|e| e.to_string())?;
        Ok(out)
    }));
}

fn export_window(app: &mut App, ctx: &egui::Context) {
    let Some(scene) = &app.scene else { return };
    let viewport = app.viewport.pixel_size().unwrap_or([1280, 800]);
    let w = &mut app.dialogs.export;
    if w.open && w.path.text.is_empty() {
        let name = export::default_file_name(&scene.set.title, std::time::SystemTime::now());
        let folder = app.settings.export.folder.clone().unwrap_or_default();
        w.path.text = folder.join(name).display().to_string();
    }
    let settings = &mut app.settings.export;
    let mut open = w.open;
    let mut save = false;
    egui::Window::new("Export screenshot").open(&mut open).collapsible(false).show(ctx, |ui| {
        let [vw, vh] = viewport;
        let choices = [
            (ExportSize::Viewport, format!("Viewport ({vw}x{vh})")),
            (ExportSize::Double, format!("2x ({}x{})", vw * 2, vh * 2)),
            (ExportSize::Quadruple, format!("4x ({}x{})", vw * 4, vh * 4)),
            (ExportSize::Custom, "Custom".to_string()),
        ];
        for (size, label) in choices {
            ui.radio_value(&mut settings.size, size, label);
        }
        ui.add_enabled_ui(settings.size == ExportSize::Custom, |ui| {
            ui.horizontal(|ui| {
                let r = ui.add(egui::DragValue::new(&mut settings.custom[0]).range(1..=export::MAX_SIDE));
                crate::viewer::accessible(&r, "Custom width");
                ui.label("x");
                let r = ui.add(egui::DragValue::new(&mut settings.custom[1]).range(1..=export::MAX_SIDE));
                crate::viewer::accessible(&r, "Custom height");
            });
        });
        ui.checkbox(&mut settings.transparent, "Transparent background");
        w.path.ui(ui, "File:", Pick::Save, &[("PNG image", &["png"])]);
        save = ui.button("Save").clicked();
        if let Some(last) = &w.last {
            ui.label(last);
        }
    });
    app.dialogs.export.open = open;
    if !save {
        return;
    }
    let [vw, vh] = viewport;
    let size = match app.settings.export.size {
        ExportSize::Viewport => [vw, vh],
        ExportSize::Double => [vw * 2, vh * 2],
        ExportSize::Quadruple => [vw * 4, vh * 4],
        ExportSize::Custom => app.settings.export.custom,
    };
    let result = export_now(app, size);
    let message = match result {
        Ok(path) => {
            app.settings.export.folder = path.parent().map(Path::to_path_buf);
            app.dialogs.export.path.text.clear();
            app.dialogs.export.open = false;
            format!("saved {} ({}x{})", path.display(), size[0], size[1])
        }
        Err(e) => format!("screenshot not saved: {e:#}"),
    };
    let error = message.starts_with("screenshot not saved");
    app.dialogs.export.last = Some(message.clone());
    app.notify(message, error);
}

/// Exports the current view at `size` to the export window's path.
pub fn export_now(app: &App, size: [u32; 2]) -> anyhow::Result<PathBuf> {
    let scene = app.scene.as_ref().ok_or_else(|| anyhow::anyhow!("no organ set"))?;
    let rs = app.gpu.as_ref().ok_or_else(|| anyhow::anyhow!("no GPU"))?;
    let camera = super::viewport::camera(app).ok_or_else(|| anyhow::anyhow!("no camera"))?;
    let mut path = PathBuf::from(app.dialogs.export.path.text.trim());
    if path.as_os_str().is_empty() {
        anyhow::bail!("no file name");
    }
    if path.extension().is_none() {
        path.set_extension("png");
    }
    let background = app.settings.background_linear(app.settings.export.transparent);
    let frame = FrameInput {
        background,
        transparency: app.settings.transparency,
        ..FrameInput::new(&scene.set, &camera, &scene.layout)
    };
    export::export(&rs.device, &rs.queue, &scene.renderer, &frame, size, &path)
}
