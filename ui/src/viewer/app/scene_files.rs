//! The app's scene files: opening a scene (over the set it names, loading that first), applying
//! it, saving it, and what happens to unsaved changes.
//!
//! - Unsaved changes: the question before they are lost, the recovery file kept and offered back.
//! - A child module of the app, so it reaches its state.

use super::{Action, App, Notification};
use crate::viewer::action::DocumentAction;
use crate::viewer::action::LessonAction;
use crate::viewer::document;
use crate::viewer::settings::LabelMode;
use eframe::egui;
use std::path::Path;

impl App {
    /// Carries out a scene-file action.
    pub(super) fn perform_document(&mut self, action: DocumentAction) {
        match action {
            DocumentAction::Save { as_new } => match (&self.document.path, as_new) {
                (Some(p), false) => {
                    let p = p.clone();
                    self.save_scene(&p);
                }
                _ => self.document.save_window.open = true,
            },
            DocumentAction::SaveTo(path) => self.save_scene(&path),
        }
    }

    /// Opens a scene file: applied at once over the set it names if that is open, else once that
    /// set has loaded.
    pub(super) fn open_scene(&mut self, ctx: &egui::Context, path: &Path) {
        let file = match vbrain::scene_file::SceneFile::load(path) {
            Ok(f) => f,
            Err(e) => return self.notify(e.to_string(), true),
        };
        let set_path = file.set_path(path);
        let same = |a: &Path| std::fs::canonicalize(a).ok() == std::fs::canonicalize(&set_path).ok();
        let open_already = self.scene.as_ref().is_some_and(|s| matches!(s.source(), [one] if same(one)));
        if open_already {
            self.apply_scene(path, &file);
        } else if !set_path.exists() {
            self.notify(format!("{}: its organ set {} is missing", path.display(), set_path.display()), true);
        } else {
            self.open(ctx, vec![set_path]);
            self.document.pending = Some((path.to_path_buf(), file));
        }
    }

    /// Shows a scene: layout, selection, camera and render settings; it becomes the document.
    pub(super) fn apply_scene(&mut self, path: &Path, file: &vbrain::scene_file::SceneFile) {
        let Some(scene) = &mut self.scene else { return };
        let applied = file.apply(scene.set());
        scene.set_layout(applied.layout);
        self.selected = applied.selection;
        let fly = file.camera.mode == vbrain::scene_file::CameraMode::Walk;
        self.viewport.set_navigator(file.camera.navigator(), fly);
        self.settings.transparency = file.render.transparency;
        self.settings.cull.mode = file.render.cull;
        self.settings.background = file.render.background;
        let which = vbrain::labels::Which::parse(file.labels.as_deref().unwrap_or(""));
        (self.settings.labels, self.chosen_labels) = LabelMode::of_which(&which, scene.set());
        let (section, unknown) = file.section().resolve(scene.set());
        for name in unknown {
            self.notifications.push(Notification {
                text: format!("{}: \"whole\" names no organ or group {name}", path.display()),
                error: false,
            });
        }
        let left_out = self.sections.set_section(&section);
        if self.document.restoring.as_deref() == Some(path) {
            // Recovered changes are saved nowhere yet.
            self.document.restoring = None;
            self.document.mark_unsaved();
            let _ = std::fs::remove_file(path);
        } else {
            self.document.mark_saved(scene, Some(path.to_path_buf()));
            self.settings.remember(path);
        }
        for w in applied.warnings {
            self.notify(format!("{}: {w}", path.display()), false);
        }
        if left_out > 0 {
            let text = format!(
                "{}: {left_out} clip plane(s) left out: the viewer cuts with one plane per anatomical axis and one oblique",
                path.display()
            );
            self.notify(text, false);
        }
    }

    /// Saves the scene to `path` (atomically); it becomes the document.
    pub(super) fn save_scene(&mut self, path: &Path) {
        let Some(scene) = &self.scene else { return };
        let which = self.settings.labels.which(&self.chosen_labels, scene.set());
        let marks = (&self.settings, &which);
        let Some(file) =
            document::capture(scene, self.viewport.camera_state(), &self.sections.current, marks, self.selected, path)
        else {
            return self
                .notify("mesh files opened together cannot be saved as a scene: save them as a set first", true);
        };
        match file.save(path) {
            Ok(()) => {
                self.document.mark_saved(scene, Some(path.to_path_buf()));
                self.settings.remember(path);
                self.notify(format!("saved {}", path.display()), false);
            }
            Err(e) => self.notify(e.to_string(), true),
        }
    }

    /// The question before unsaved changes are lost, the window closing, the recovery file kept
    /// and a recovery file offered back.
    pub(super) fn unsaved_changes(&mut self, ctx: &egui::Context) {
        if ctx.input(|i| i.viewport().close_requested()) && !self.closing {
            if self.unsaved(&document::Pending::Quit) {
                ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
                self.document.confirm = Some(document::Pending::Quit);
            } else {
                self.document.remove_recovery();
            }
        }
        if let Some(pending) = self.document.confirm.clone() {
            let scene_too = pending != document::Pending::CloseLesson && self.document.unsaved(self.scene.as_ref());
            let mut names = Vec::new();
            if scene_too {
                names.push(self.document.title(None));
            }
            if self.lesson.unsaved() {
                names.push(format!("the lesson {}", self.lesson.name().trim_end_matches(" *")));
            }
            match document::confirm_window(ctx, &pending, &names.join(" and ")) {
                Some(document::Answer::Save) => {
                    self.document.confirm = None;
                    if scene_too {
                        self.perform(ctx, vec![Action::Document(DocumentAction::Save { as_new: false })]);
                    }
                    if self.lesson.unsaved() {
                        self.perform(ctx, vec![Action::Lesson(LessonAction::Save { as_new: false })]);
                    }
                    // Saved to their files: go on; asked where (a new one): the user goes on after.
                    if !self.unsaved(&pending) {
                        self.go_on(ctx, pending);
                    }
                }
                Some(document::Answer::Discard) => {
                    self.document.confirm = None;
                    if scene_too {
                        self.document.remove_recovery();
                        if let Some(scene) = &self.scene {
                            self.document.mark_saved(scene, self.document.path.clone());
                        }
                    }
                    self.lesson.discard_changes();
                    self.go_on(ctx, pending);
                }
                Some(document::Answer::Cancel) => self.document.confirm = None,
                None => {}
            }
        }
        if self.document.offer_recovery && self.scene.is_some() && self.loading.is_none() {
            if let Some(restore) = document::recovery_window(ctx) {
                self.document.offer_recovery = false;
                match (restore, self.document.recovery.clone()) {
                    (true, Some(p)) => {
                        let restored = p.with_extension("restored.vbscene");
                        if std::fs::rename(&p, &restored).is_ok() {
                            self.document.restoring = Some(restored.clone());
                            self.open_scene(ctx, &restored);
                        }
                    }
                    _ => self.document.remove_recovery(),
                }
            }
        }
        if let Some(scene) = &self.scene {
            let now = ctx.input(|i| i.time);
            let which = self.settings.labels.which(&self.chosen_labels, scene.set());
            let (viewport, section, selected) = (&self.viewport, &self.sections.current, self.selected);
            let marks = (&self.settings, &which);
            let capture = |p: &Path| document::capture(scene, viewport.camera_state(), section, marks, selected, p);
            if let Some(problem) = self.document.keep_recovery(now, scene, capture) {
                self.notifications.push(Notification { text: problem, error: true });
            }
        }
    }

    /// Is anything unsaved that `pending` would lose: the scene (unless only the lesson closes)
    /// or the lesson?
    pub(super) fn unsaved(&self, pending: &document::Pending) -> bool {
        let scene = *pending != document::Pending::CloseLesson && self.document.unsaved(self.scene.as_ref());
        scene || self.lesson.unsaved()
    }

    /// Carries out what waited for the answer.
    pub(super) fn go_on(&mut self, ctx: &egui::Context, pending: document::Pending) {
        let action = match pending {
            document::Pending::Quit => Action::Quit,
            document::Pending::Open(paths) => Action::Open(paths),
            document::Pending::CloseLesson => Action::Lesson(LessonAction::Close),
        };
        self.perform(ctx, vec![action]);
    }
}
