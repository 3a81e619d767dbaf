//! Small widgets the viewer's components share: accessible names and a path field with a system
//! file dialog.
//!
//! - Accessible names are AccessKit's, which screen readers and the tests use to find widgets.
//! - The path field's *Browse...* runs the system dialog on a worker thread, so the field works
//!   where no file-dialog service runs; several paths are separated by `;`.

use eframe::egui;
use std::path::{Path, PathBuf};
use std::sync::mpsc;

/// Sets the accessible name of a widget (AccessKit), so screen readers and tests find it.
pub fn accessible(response: &egui::Response, label: impl Into<String>) {
    let label = label.into();
    response.ctx.accesskit_node_builder(response.id, |node| node.set_label(label));
}

/// What a system file dialog should ask for.
#[derive(Clone, Copy)]
pub enum Pick {
    Folder,
    File,
    Files,
    Save,
}

/// A path field with a "Browse..." button backed by a system dialog (rfd) on a worker thread, so
/// it works where no file-dialog service runs (plain X, or Wayland without a portal): the field
/// is filled if the dialog answers. Several paths are separated by `;`.
#[derive(Default)]
pub struct PathField {
    pub text: String,
    pending: Option<mpsc::Receiver<Vec<PathBuf>>>,
}

impl PathField {
    /// The field with its label and *Browse...*; returns whether Enter was pressed in it (the
    /// window's main button then acts, as a click on it would).
    pub fn ui(&mut self, ui: &mut egui::Ui, label: &str, pick: Pick, filters: &[(&str, &[&str])]) -> bool {
        if let Some(rx) = &self.pending {
            if let Ok(paths) = rx.try_recv() {
                self.pending = None;
                if !paths.is_empty() {
                    self.text = paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join("; ");
                }
            }
        }
        let entered = ui
            .horizontal_wrapped(|ui| {
                ui.label(label);
                let width = (ui.available_width() - 90.0).clamp(120.0, 380.0);
                let r = ui.add(egui::TextEdit::singleline(&mut self.text).desired_width(width));
                accessible(&r, label.trim_end_matches(':'));
                let entered = r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                let browse = ui.add_enabled(self.pending.is_none(), egui::Button::new("Browse..."));
                accessible(&browse, format!("Browse {}", label.trim_end_matches(':')));
                if browse.clicked() {
                    self.browse(ui.ctx(), pick, filters);
                }
                entered
            })
            .inner;
        if self.pending.is_some() {
            ui.label("waiting for the file dialog (or type the path)");
        }
        entered
    }

    fn browse(&mut self, ctx: &egui::Context, pick: Pick, filters: &[(&str, &[&str])]) {
        let (tx, rx) = mpsc::channel();
        let filters: Vec<(String, Vec<String>)> =
            filters.iter().map(|(n, e)| (n.to_string(), e.iter().map(|s| s.to_string()).collect())).collect();
        let ctx = ctx.clone();
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

    /// The paths typed or picked.
    pub fn paths(&self) -> Vec<PathBuf> {
        self.text.split(';').map(str::trim).filter(|s| !s.is_empty()).map(PathBuf::from).collect()
    }
}

/// `path` as typed (trimmed), with `.ext` added if it has another extension or none.
pub fn with_extension(path: &str, ext: &str) -> PathBuf {
    let p = PathBuf::from(path.trim());
    if p.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext)) {
        p
    } else {
        let mut s = p.into_os_string();
        s.push(".");
        s.push(ext);
        PathBuf::from(s)
    }
}
