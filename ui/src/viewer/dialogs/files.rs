//! The file windows (open an organ set, open mesh files, import a label volume), files dropped
//! onto the window, and the import job.
//!
//! - Each window has a path field (see [`PathField`]) and returns [`Action`]s; the app runs them.

use crate::viewer::action::{Action, ImportRequest};
use crate::viewer::jobs::Progress;
use crate::viewer::widgets::{accessible, PathField, Pick};
use anyhow::Result;
use eframe::egui;
use std::path::{Path, PathBuf};
use vbrain::organ_set;

/// Is this a NIfTI label volume?
pub fn is_volume(p: &Path) -> bool {
    let name = p.file_name().map(|n| n.to_string_lossy().to_lowercase()).unwrap_or_default();
    name.ends_with(".nii") || name.ends_with(".nii.gz")
}

const MESHES: (&str, &[&str]) = ("Meshes", &["obj", "vbo", "OBJ", "VBO"]);
const VOLUMES: (&str, &[&str]) = ("NIfTI label volume", &["nii", "gz"]);
const TABLES: (&str, &[&str]) = ("Label table", &["csv", "txt", "ctbl", "lut"]);

/// The "Open organ set" and "Open mesh files" windows.
#[derive(Default)]
pub struct OpenWindow {
    pub open: bool,
    pub field: PathField,
}

impl OpenWindow {
    /// "Open organ set": a path, or one of the recent sets.
    pub fn show_set(&mut self, ctx: &egui::Context, recent: &[PathBuf]) -> Vec<Action> {
        let mut open = self.open;
        let mut go = None;
        egui::Window::new("Open organ set or scene").open(&mut open).collapsible(false).show(ctx, |ui| {
            ui.label("A folder with organset.json, a folder of .obj/.vbo files, one mesh file, or a .vbscene file.");
            let entered = self.field.ui(ui, "Path:", Pick::Folder, &[]);
            if ui.button("Open").clicked() || entered {
                go = self.field.paths().into_iter().next();
            }
            if !recent.is_empty() {
                ui.separator();
                ui.label("Recent:");
                for p in recent {
                    if ui.link(p.display().to_string()).clicked() {
                        go = Some(p.clone());
                    }
                }
            }
        });
        self.open = open && go.is_none();
        go.map(|p| vec![Action::Open(vec![p])]).unwrap_or_default()
    }

    /// "Open mesh files": one or more paths.
    pub fn show_meshes(&mut self, ctx: &egui::Context) -> Vec<Action> {
        let mut open = self.open;
        let mut go = None;
        egui::Window::new("Open mesh files").open(&mut open).collapsible(false).show(ctx, |ui| {
            ui.label("One or more .obj/.vbo files (separate paths with ;). Each object becomes an organ.");
            let entered = self.field.ui(ui, "Files:", Pick::Files, &[MESHES]);
            if ui.button("Open").clicked() || entered {
                go = Some(self.field.paths());
            }
        });
        self.open = open && go.is_none();
        match go {
            Some(paths) if !paths.is_empty() => vec![Action::Open(paths)],
            Some(_) => vec![Action::Notify { text: "no file given".into(), error: true }],
            None => Vec::new(),
        }
    }
}

/// The "Import label volume" window.
pub struct ImportWindow {
    pub open: bool,
    volume: PathField,
    labels: PathField,
    out: PathField,
    triangles: usize,
}

impl Default for ImportWindow {
    fn default() -> Self {
        ImportWindow {
            open: false,
            volume: PathField::default(),
            labels: PathField::default(),
            out: PathField::default(),
            triangles: 200_000,
        }
    }
}

impl ImportWindow {
    /// The volume as typed or chosen.
    pub fn volume(&self) -> &str {
        &self.volume.text
    }

    /// Opens the window on this volume.
    pub fn open_on(&mut self, volume: &Path) {
        self.volume.text = volume.display().to_string();
        self.open = true;
    }

    /// The window; `busy` (an import running) disables Import.
    pub fn show(&mut self, ctx: &egui::Context, busy: bool) -> Vec<Action> {
        let mut open = self.open;
        let mut start = false;
        egui::Window::new("Import label volume").open(&mut open).collapsible(false).show(ctx, |ui| {
            ui.label(
                "A label volume (atlas or segmentation, NIfTI) and its label table (CSV index,name or a FreeSurfer LUT).",
            );
            self.volume.ui(ui, "Volume:", Pick::File, &[VOLUMES]);
            self.labels.ui(ui, "Labels:", Pick::File, &[TABLES]);
            self.out.ui(ui, "Output folder:", Pick::Folder, &[]);
            ui.horizontal(|ui| {
                ui.label("Triangle budget:");
                let r = ui.add(egui::DragValue::new(&mut self.triangles).range(1000..=5_000_000).speed(1000));
                accessible(&r, "Triangle budget");
            });
            start = ui.add_enabled(!busy, egui::Button::new("Import")).clicked();
        });
        self.open = open && !start;
        if !start {
            return Vec::new();
        }
        let volume = PathBuf::from(self.volume.text.trim());
        let out = self.out.text.trim();
        let out = if out.is_empty() { volume.with_extension("").with_extension("") } else { PathBuf::from(out) };
        let labels = PathBuf::from(self.labels.text.trim());
        vec![Action::Import(ImportRequest { volume, labels, out, triangles: self.triangles })]
    }
}

/// The import job: reads the table and the volume, builds the set and saves it; gives its folder.
pub fn import(request: &ImportRequest, progress: &Progress) -> Result<PathBuf> {
    use vbrain::organ_set::import;
    let held = vbrain::atomic::folder_entries(&request.out)?;
    if held > 0 {
        anyhow::bail!(
            "{} already holds {held} files or folders; choose a new folder for the set",
            request.out.display()
        );
    }
    let table = import::read_label_table(&request.labels)?;
    progress.set(0, 1, "reading volume");
    let vol = import::read_volume(&request.volume)?;
    let title = request.volume.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let opts = import::ImportOptions { triangles: request.triangles, title, ..Default::default() };
    let (set, _warnings) = import::import(&vol, &table.labels, &opts, &mut |d, t, m| progress.set(d, t, m))?;
    set.save(&request.out)?;
    Ok(request.out.clone())
}

/// Files dropped onto the window: a label volume opens the import window; one path opens as a
/// set; several open their mesh files together.
pub fn dropped(ctx: &egui::Context) -> Vec<Action> {
    let dropped: Vec<PathBuf> = ctx.input(|i| {
        i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).filter(|p| !p.as_os_str().is_empty()).collect()
    });
    if dropped.is_empty() {
        return Vec::new();
    }
    if let Some(v) = dropped.iter().find(|p| is_volume(p)) {
        return vec![Action::ImportVolume(v.clone())];
    }
    if dropped.len() == 1 {
        return vec![Action::Open(dropped)];
    }
    let meshes: Vec<PathBuf> = dropped.into_iter().filter(|p| organ_set::is_mesh_file(p)).collect();
    if meshes.is_empty() {
        vec![Action::Notify {
            text: "dropped files are neither organ sets, meshes nor label volumes".into(),
            error: true,
        }]
    } else {
        vec![Action::Open(meshes)]
    }
}
