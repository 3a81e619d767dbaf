//! The app's scene files: opening a scene (over the set it names, loading that first), applying
//! it, saving it, and what happens to unsaved changes (the question before they are lost, the
//! recovery file kept and offered back). A child module of the app, so it reaches its state.

use super::{Action, App, LessonPanel, Notification};
use crate::viewer::document;
use eframe::egui;
use std::path::Path;
use vbrain::edit::{Edit, Organs};

impl App {
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
    }

    /// Saves the scene to `path` (atomically); it becomes the document.
    pub(super) fn save_scene(&mut self, path: &Path) {
        let Some(scene) = &self.scene else { return };
        let Some(file) = document::capture(scene, &self.viewport, &self.settings, self.selected, path) else {
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
            if self.document.unsaved(self.scene.as_ref()) {
                ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
                self.document.confirm = Some(document::Pending::Quit);
            } else {
                self.document.remove_recovery();
            }
        }
        if let Some(pending) = self.document.confirm.clone() {
            let name = self.document.title(None);
            match document::confirm_window(ctx, &pending, &name) {
                Some(document::Answer::Save) => {
                    self.document.confirm = None;
                    self.perform(ctx, vec![Action::SaveScene { as_new: false }]);
                    // Saved to its file: go on; asked where (a new scene): the user goes on after.
                    if !self.document.unsaved(self.scene.as_ref()) {
                        self.go_on(ctx, pending);
                    }
                }
                Some(document::Answer::Discard) => {
                    self.document.confirm = None;
                    self.document.remove_recovery();
                    if let Some(scene) = &self.scene {
                        self.document.mark_saved(scene, self.document.path.clone());
                    }
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
            let (viewport, settings, selected) = (&self.viewport, &self.settings, self.selected);
            let capture = |p: &Path| document::capture(scene, viewport, settings, selected, p);
            if let Some(problem) = self.document.keep_recovery(now, scene, capture) {
                self.notifications.push(Notification { text: problem, error: true });
            }
        }
    }

    /// Carries out what waited for the answer.
    pub(super) fn go_on(&mut self, ctx: &egui::Context, pending: document::Pending) {
        match pending {
            document::Pending::Quit => self.perform(ctx, vec![Action::Quit]),
            document::Pending::Open(paths) => self.perform(ctx, vec![Action::Open(paths)]),
        }
    }

    /// Opens a lesson at its first step, over its set (loading that first if another is open).
    pub(super) fn open_lesson(&mut self, ctx: &egui::Context, path: &Path) {
        let lesson = match vbrain::lesson::Lesson::load(path) {
            Ok(l) => l,
            Err(e) => return self.notify(e.to_string(), true),
        };
        if self.has_set_of(&lesson, path) {
            self.start_lesson(path, lesson);
        } else {
            self.pending_lesson = Some(path.to_path_buf());
            self.perform(ctx, vec![Action::Open(vec![lesson.set_path(path)])]);
        }
    }

    /// The lesson waiting for its set, now that a set is installed.
    pub(super) fn open_pending_lesson(&mut self) {
        let Some(path) = self.pending_lesson.take() else { return };
        match vbrain::lesson::Lesson::load(&path) {
            Ok(lesson) if self.has_set_of(&lesson, &path) => self.start_lesson(&path, lesson),
            Ok(_) => {}
            Err(e) => self.notify(e.to_string(), true),
        }
    }

    /// Is the lesson's set the one open?
    fn has_set_of(&self, lesson: &vbrain::lesson::Lesson, path: &Path) -> bool {
        let set = std::fs::canonicalize(lesson.set_path(path)).ok();
        self.scene.as_ref().is_some_and(|s| matches!(s.source(), [one] if std::fs::canonicalize(one).ok() == set))
    }

    fn start_lesson(&mut self, path: &Path, lesson: vbrain::lesson::Lesson) {
        if let Some(scene) = &self.scene {
            let unknown = lesson.unknown_names(scene.set());
            if !unknown.is_empty() {
                self.notify(format!("{}: the set has no organ or group {}", path.display(), unknown.join(", ")), false);
            }
        }
        self.lesson = LessonPanel { lesson: Some((path.to_path_buf(), lesson)), step: 0 };
        self.lesson_step(0);
    }

    /// Shows step `k` of the open lesson: its layout (one undoable step) and camera.
    pub(super) fn lesson_step(&mut self, k: usize) {
        let (Some((_, lesson)), Some(scene)) = (&self.lesson.lesson, &mut self.scene) else { return };
        let Some(step) = lesson.steps.get(k) else { return };
        let view = step.view(scene.set());
        let edit = Edit::Restore { organs: Organs::All, states: view.layout.organs };
        scene.apply(&edit, false);
        self.viewport.set_navigator(view.navigator, false);
        self.lesson.step = k;
    }
}
