//! The open scene file (`.vbscene`): where it lives, whether the organs changed since it was
//! saved, the Save Scene window, the question before unsaved changes would be lost, the recovery
//! file, and turning the viewer's state into a [`SceneFile`].
//!
//! - The app owns one [`Document`]; saving and opening go through
//!   [`crate::viewer::App::perform`].
//! - While there are unsaved changes, the scene is written (atomically) to a recovery file at
//!   most every [`RECOVERY_SECONDS`]; a clean exit, a save or a discard removes it.
//! - A recovery file found at start is offered back.

use super::action::Action;
use super::scene::Scene;
use super::settings::Settings;
use super::widgets::{PathField, Pick};
use crate::viewer::action::DocumentAction;
use eframe::egui;
use std::path::{Path, PathBuf};
use vbrain::scene_file::{CameraState, RenderState, SceneFile, EXTENSION};

/// Is this a scene file (by its extension)?
pub fn is_scene(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case(EXTENSION))
}

/// Seconds between writes of the recovery file while changes go on.
pub const RECOVERY_SECONDS: f64 = 3.0;

/// What waits for an answer about unsaved changes.
#[derive(Clone, Debug, PartialEq)]
pub enum Pending {
    Quit,
    Open(Vec<PathBuf>),
    /// Close the lesson (only the lesson's changes matter).
    CloseLesson,
}

#[derive(Default)]
pub struct Document {
    /// The scene file last saved or opened.
    pub path: Option<PathBuf>,
    /// The scene's change count when it was last saved or opened (see [`Scene::changes`]).
    saved: u64,
    /// A scene whose set is loading: applied once the set is installed.
    pub pending: Option<(PathBuf, SceneFile)>,
    pub save_window: SaveWindow,
    /// Asking whether to save before this happens.
    pub confirm: Option<Pending>,
    /// Where the recovery file goes (`None`: none is written).
    pub recovery: Option<PathBuf>,
    /// When the recovery file was last written, and the change count it holds.
    recovered: Option<(f64, u64)>,
    /// A recovery file was found at start: offer it.
    pub offer_recovery: bool,
    /// The recovery file being restored (renamed aside): applied as unsaved changes.
    pub restoring: Option<PathBuf>,
}

impl Document {
    /// The organs changed since the scene was saved or opened (or since the set was opened).
    pub fn unsaved(&self, scene: Option<&Scene>) -> bool {
        scene.is_some_and(|s| s.changes() != self.saved)
    }

    /// What is on screen now is what the file holds; the recovery file is no longer needed.
    pub fn mark_saved(&mut self, scene: &Scene, path: Option<PathBuf>) {
        self.saved = scene.changes();
        self.path = path;
        self.remove_recovery();
    }

    /// A set was opened: nothing to save yet (a recovery file from before stays, to be offered).
    pub fn opened_set(&mut self, scene: &Scene) {
        self.saved = scene.changes();
        self.path = None;
    }

    /// What is on screen is not saved anywhere (a recovered scene).
    pub fn mark_unsaved(&mut self) {
        self.saved = u64::MAX;
        self.path = None;
    }

    /// Writes the recovery file (what `capture` makes of the scene for that path) if there are
    /// unsaved changes it does not hold yet and its last write is [`RECOVERY_SECONDS`] old; `now`
    /// in seconds. Returns a problem to show.
    pub fn keep_recovery(
        &mut self,
        now: f64,
        scene: &Scene,
        capture: impl FnOnce(&Path) -> Option<SceneFile>,
    ) -> Option<String> {
        let path = self.recovery.clone()?;
        if !self.unsaved(Some(scene)) {
            return None;
        }
        let changes = scene.changes();
        if let Some((at, held)) = self.recovered {
            if held == changes || now - at < RECOVERY_SECONDS {
                return None;
            }
        }
        let file = capture(&path)?;
        self.recovered = Some((now, changes));
        // The settings' folder is made by eframe only when it first saves them: on a first run the
        // recovery file may come first.
        let dir = path.parent().unwrap_or(Path::new("."));
        let made = std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()));
        let saved = made.and_then(|()| file.save(&path).map_err(|e| e.to_string()));
        saved.err().map(|e| format!("could not write the recovery file: {e}"))
    }

    /// Removes the recovery file (after a save, a discard or a clean exit).
    pub fn remove_recovery(&mut self) {
        if let Some(p) = &self.recovery {
            let _ = std::fs::remove_file(p);
        }
        self.recovered = None;
    }

    /// The window title's name for it: the file's name, with `*` while unsaved.
    pub fn title(&self, scene: Option<&Scene>) -> String {
        let name = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map_or("untitled scene".into(), |n| n.to_string_lossy().into_owned());
        format!("{name}{}", if self.unsaved(scene) { " *" } else { "" })
    }
}

/// The viewer's state as a scene file to be written at `path`; `None` where the scene cannot be
/// saved (several mesh files opened together have no one path to refer to).
pub fn capture(
    scene: &Scene,
    camera: CameraState,
    section: &vbrain::clip::Section,
    (settings, labels): (&Settings, &vbrain::labels::Which),
    selected: Option<usize>,
    path: &Path,
) -> Option<SceneFile> {
    let [set_path] = scene.source() else { return None };
    let render =
        RenderState { transparency: settings.transparency, cull: settings.cull.mode, background: settings.background };
    let mut file = SceneFile::capture(scene.set(), set_path, path, scene.layout(), camera, render, selected);
    file.set_section(vbrain::clip::SavedSection::of(section, scene.set()));
    file.labels = labels.key();
    Some(file)
}

/// "Save scene as": a path field.
#[derive(Default)]
pub struct SaveWindow {
    pub open: bool,
    pub field: PathField,
}

impl SaveWindow {
    pub fn show(&mut self, ctx: &egui::Context) -> Vec<Action> {
        let mut open = self.open;
        let mut go = None;
        egui::Window::new("Save scene").open(&mut open).collapsible(false).show(ctx, |ui| {
            ui.label("The organs, the camera and the render settings, as a .vbscene file (JSON).");
            let entered = self.field.ui(ui, "File:", Pick::Save, &[("vbrain scene", &[EXTENSION])]);
            if (ui.button("Save").clicked() || entered) && !self.field.text.trim().is_empty() {
                go = Some(super::widgets::with_extension(&self.field.text, EXTENSION));
            }
        });
        self.open = open && go.is_none();
        go.map(|p| vec![Action::Document(DocumentAction::SaveTo(p))]).unwrap_or_default()
    }
}

/// The question before unsaved changes would be lost: Save, Don't save or Cancel. Returns the
/// answer once given.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Answer {
    Save,
    Discard,
    Cancel,
}

pub fn confirm_window(ctx: &egui::Context, pending: &Pending, name: &str) -> Option<Answer> {
    let mut answer = None;
    let what = match pending {
        Pending::Quit => "before quitting",
        Pending::Open(_) => "before opening another",
        Pending::CloseLesson => "before closing it",
    };
    egui::Modal::new(egui::Id::unique("unsaved changes")).show(ctx, |ui| {
        ui.heading("Save changes?");
        ui.label(format!("Unsaved changes in {name}. Save them {what}?"));
        ui.horizontal(|ui| {
            if ui.button("Save").clicked() {
                answer = Some(Answer::Save);
            }
            if ui.button("Don't save").clicked() {
                answer = Some(Answer::Discard);
            }
            if ui.button("Cancel").clicked() || ui.input(|i| i.key_pressed(egui::Key::Escape)) {
                answer = Some(Answer::Cancel);
            }
        });
    });
    answer
}

/// The offer of a recovery file found at start: Restore or Discard.
pub fn recovery_window(ctx: &egui::Context) -> Option<bool> {
    let mut answer = None;
    egui::Modal::new(egui::Id::unique("recovery")).show(ctx, |ui| {
        ui.heading("Restore unsaved changes?");
        ui.label("vbrain closed while a scene had changes that were not saved. Restore them?");
        ui.horizontal(|ui| {
            if ui.button("Restore").clicked() {
                answer = Some(true);
            }
            if ui.button("Discard").clicked() {
                answer = Some(false);
            }
        });
    });
    answer
}
