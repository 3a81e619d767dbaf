//! The open scene file (`.vbscene`): where it lives, whether the organs changed since it was saved,
//! the Save Scene window, and turning the viewer's state into a [`SceneFile`] and back. The app
//! owns one [`Document`]; saving and opening go through [`crate::viewer::App::perform`].

use super::action::Action;
use super::scene::Scene;
use super::settings::Settings;
use super::viewport::Viewport;
use super::widgets::{PathField, Pick};
use eframe::egui;
use std::path::{Path, PathBuf};
use vbrain::scene_file::{CameraMode, CameraState, RenderState, SceneFile, EXTENSION};

/// Is this a scene file (by its extension)?
pub fn is_scene(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case(EXTENSION))
}

/// `path` as typed, with `.vbscene` added if it has another extension or none.
pub fn with_extension(path: &str) -> PathBuf {
    let p = PathBuf::from(path.trim());
    if is_scene(&p) {
        p
    } else {
        let mut s = p.into_os_string();
        s.push(".");
        s.push(EXTENSION);
        PathBuf::from(s)
    }
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
}

impl Document {
    /// The organs changed since the scene was saved or opened (or since the set was opened).
    pub fn unsaved(&self, scene: Option<&Scene>) -> bool {
        scene.is_some_and(|s| s.changes() != self.saved)
    }

    /// What is on screen now is what the file holds.
    pub fn mark_saved(&mut self, scene: &Scene, path: Option<PathBuf>) {
        self.saved = scene.changes();
        self.path = path;
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
    viewport: &Viewport,
    settings: &Settings,
    selected: Option<usize>,
    path: &Path,
) -> Option<SceneFile> {
    let [set_path] = scene.source() else { return None };
    let mode = if viewport.fly() { CameraMode::Walk } else { CameraMode::Orbit };
    let render =
        RenderState { transparency: settings.transparency, cull: settings.cull.mode, background: settings.background };
    Some(SceneFile::capture(
        scene.set(),
        set_path,
        path,
        scene.layout(),
        CameraState::of(&viewport.navigator(), mode),
        render,
        selected,
    ))
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
            self.field.ui(ui, "File:", Pick::Save, &[("vbrain scene", &[EXTENSION])]);
            if ui.button("Save").clicked() && !self.field.text.trim().is_empty() {
                go = Some(with_extension(&self.field.text));
            }
        });
        self.open = open && go.is_none();
        go.map(|p| vec![Action::SaveSceneTo(p)]).unwrap_or_default()
    }
}
