//! The app's lessons: opening one over its set (loading that first), going to a step with its
//! half-second transition, and authoring: steps made from the current view, new lessons, saving.
//!
//! - Lesson edits are recorded in the scene's history beside layout edits.
//! - A child module of the app, so it reaches its state.

use super::{Action, App, LessonPanel};
use crate::viewer::action::LessonAction;
use crate::viewer::document;
use crate::viewer::settings::LabelMode;
use eframe::egui;
use std::path::Path;
use vbrain::edit::{Edit, Organs};
use vbrain::labels::Which;
use vbrain::lesson::{Lesson, LessonEdit, Step};
use vbrain::scene_file::{CameraMode, CameraState};
use vbrain::transition::Transition;

impl App {
    /// Carries out a lesson action (asking first where unsaved lesson changes would be lost).
    pub(super) fn perform_lesson(&mut self, ctx: &egui::Context, action: LessonAction) {
        match action {
            LessonAction::Open(path) if self.lesson.unsaved() => {
                self.document.confirm = Some(document::Pending::Open(vec![path]));
            }
            LessonAction::Open(path) => self.open_lesson(ctx, &path),
            LessonAction::Step(k) => self.lesson_step(ctx, k),
            LessonAction::Close => self.ask_close_lesson(),
            LessonAction::New if self.lesson.unsaved() => {
                self.document.confirm = Some(document::Pending::CloseLesson);
            }
            LessonAction::New => self.new_lesson(),
            LessonAction::Edit(edit) => self.edit_lesson(&edit),
            LessonAction::AddStep { replace } => self.add_lesson_step(replace),
            LessonAction::Save { as_new } => self.save_lesson(as_new, None),
            LessonAction::SaveTo(path) => self.save_lesson(false, Some(&path)),
        }
    }

    /// Opens a lesson at its first step, over its set (loading that first if another is open).
    pub(super) fn open_lesson(&mut self, ctx: &egui::Context, path: &Path) {
        let lesson = match Lesson::load(path) {
            Ok(l) => l,
            Err(e) => return self.notify(e.to_string(), true),
        };
        if self.has_set_of(&lesson, path) {
            self.start_lesson(ctx, path, lesson);
        } else {
            self.pending_lesson = Some(path.to_path_buf());
            self.perform(ctx, vec![Action::Open(vec![lesson.set_path(path)])]);
        }
    }

    /// The lesson waiting for its set, now that a set is installed.
    pub(super) fn open_pending_lesson(&mut self, ctx: &egui::Context) {
        let Some(path) = self.pending_lesson.take() else { return };
        match Lesson::load(&path) {
            Ok(lesson) if self.has_set_of(&lesson, &path) => self.start_lesson(ctx, &path, lesson),
            Ok(_) => {}
            Err(e) => self.notify(e.to_string(), true),
        }
    }

    /// Is the lesson's set the one open?
    fn has_set_of(&self, lesson: &Lesson, path: &Path) -> bool {
        let set = std::fs::canonicalize(lesson.set_path(path)).ok();
        self.scene.as_ref().is_some_and(|s| matches!(s.source(), [one] if std::fs::canonicalize(one).ok() == set))
    }

    fn start_lesson(&mut self, ctx: &egui::Context, path: &Path, lesson: Lesson) {
        if let Some(scene) = &self.scene {
            let unknown = lesson.unknown_names(scene.set());
            if !unknown.is_empty() {
                self.notify(format!("{}: the set has no organ or group {}", path.display(), unknown.join(", ")), false);
            }
        }
        self.close_lesson();
        self.lesson = LessonPanel::open(lesson, Some(path.to_path_buf()));
        self.lesson_step(ctx, 0);
    }

    /// Shows step `k` of the open lesson: its layout (one undoable step, applied at once) and
    /// camera, eased in from what was on screen over half a second.
    pub(super) fn lesson_step(&mut self, ctx: &egui::Context, k: usize) {
        let (Some(lesson), Some(scene)) = (&self.lesson.lesson, &mut self.scene) else { return };
        let Some(step) = lesson.steps.get(k) else { return };
        let view = step.view(scene.set());
        let fly = view.fly;
        let from = (self.viewport.navigator(), scene.shown().clone());
        let edit = Edit::Restore { organs: Organs::All, states: view.layout.organs };
        scene.apply(&edit, false);
        let to = (view.navigator, scene.layout().clone());
        let transition = Transition { from, to, start: ctx.input(|i| i.time) };
        self.lesson.transition = Some((transition, scene.changes()));
        self.viewport.set_navigator(self.viewport.navigator(), fly);
        self.lesson.step = k;
        let left_out = self.sections.set_section(&view.section);
        match &view.labels {
            // A step's "selected" organs are the ones it highlights.
            Some(Which::Selected) => {
                (self.settings.labels, self.chosen_labels) = (LabelMode::Chosen, view.highlight.clone())
            }
            Some(which) => (self.settings.labels, self.chosen_labels) = LabelMode::of_which(which, scene.set()),
            None => {}
        }
        self.lesson.highlight = view.highlight;
        if left_out > 0 {
            self.notify(format!("step {}: {left_out} clip plane(s) left out", k + 1), false);
        }
        self.ease_lesson_step(ctx);
    }

    /// Draws the step change under way at this frame's time; any other change to the layout ends
    /// it where it is headed.
    pub(super) fn ease_lesson_step(&mut self, ctx: &egui::Context) {
        let (Some((transition, changes)), Some(scene)) = (&self.lesson.transition, &mut self.scene) else {
            return;
        };
        let now = ctx.input(|i| i.time);
        if *changes != scene.changes() || transition.progress(now) >= 1.0 {
            if *changes == scene.changes() {
                self.viewport.set_navigator(transition.to.0, self.viewport.fly());
            }
            scene.show_instead(None);
            self.lesson.transition = None;
            return;
        }
        let (navigator, layout) = transition.at(now);
        self.viewport.set_navigator(navigator, self.viewport.fly());
        scene.show_instead(Some(layout));
        ctx.request_repaint();
    }

    /// Closes the lesson; its edits leave the history.
    pub(super) fn close_lesson(&mut self) {
        if let Some(scene) = &mut self.scene {
            scene.forget_outside();
            scene.show_instead(None);
        }
        self.lesson = LessonPanel::default();
    }

    /// The current view as a step (the selection highlighted).
    fn step_from_view(&self, title: &str) -> Option<Step> {
        let scene = self.scene.as_ref()?;
        let mode = if self.viewport.fly() { CameraMode::Walk } else { CameraMode::Orbit };
        let camera = CameraState::of(&self.viewport.navigator(), mode);
        let highlight: Vec<usize> = self.selected.into_iter().collect();
        let labels = match self.settings.labels {
            // No labels: the step leaves them to whoever follows it.
            LabelMode::None => Which::None,
            mode => mode.which(&self.chosen_labels, scene.set()),
        };
        let section = &self.sections.current;
        Some(Step::capture(scene.set(), scene.layout(), camera, title, &highlight, section, &labels))
    }

    /// Applies a lesson edit as one undoable step.
    pub(super) fn edit_lesson(&mut self, edit: &LessonEdit) {
        if let Some(label) = self.lesson.edit(edit) {
            if let Some(scene) = &mut self.scene {
                scene.record_outside(label);
            }
        }
    }

    /// Adds a step from the current view after the current one, or (`replace`) makes the current
    /// step show the current view, keeping its title and caption.
    pub(super) fn add_lesson_step(&mut self, replace: bool) {
        let Some(lesson) = &self.lesson.lesson else { return };
        let at = self.lesson.step;
        let edit = if replace {
            let Some(old) = lesson.steps.get(at) else { return };
            let Some(mut step) = self.step_from_view(&old.title) else { return };
            step.caption = old.caption.clone();
            LessonEdit::Replace { at, step: Box::new(step) }
        } else {
            let title = format!("Step {}", lesson.steps.len() + 1);
            let Some(step) = self.step_from_view(&title) else { return };
            LessonEdit::Insert { at: at + 1, step: Box::new(step) }
        };
        self.edit_lesson(&edit);
        if let Some(scene) = &self.scene {
            self.lesson.highlight = self
                .lesson
                .lesson
                .as_ref()
                .map_or(Vec::new(), |l| l.steps[self.lesson.step].view(scene.set()).highlight);
        }
    }

    /// A new lesson over the open set, its first step the current view (unsaved until saved).
    pub(super) fn new_lesson(&mut self) {
        let Some(scene) = &self.scene else { return };
        let [set_path] = scene.source() else {
            return self
                .notify("mesh files opened together have no one set for a lesson: save them as a set first", true);
        };
        let set_path = set_path.clone();
        let Some(step) = self.step_from_view("Step 1") else { return };
        let lesson_path = set_path.join("lessons").join("untitled.vblesson");
        let lesson = Lesson::new("Untitled lesson", &set_path, &lesson_path, vec![step]);
        self.close_lesson();
        self.lesson = LessonPanel::open(lesson, None);
    }

    /// Saves the lesson to its file, or asks where (`as_new`, or a new lesson).
    pub(super) fn save_lesson(&mut self, as_new: bool, to: Option<&Path>) {
        let path = match (to, &self.lesson.path, as_new) {
            (Some(p), _, _) => p.to_path_buf(),
            (None, Some(p), false) => p.clone(),
            _ => return self.lesson.ask_where(),
        };
        if self.lesson.path.is_none() {
            // A new lesson's set path was made relative to a guess: make it relative to its file.
            if let (Some(l), Some(scene)) = (&mut self.lesson.lesson, &self.scene) {
                if let [set] = scene.source() {
                    *l = Lesson::new(&l.title, set, &path, l.steps.clone());
                }
            }
        }
        match self.lesson.save(&path) {
            Ok(()) => self.notify(format!("saved {}", path.display()), false),
            Err(e) => self.notify(e.to_string(), true),
        }
    }

    /// Closes the lesson, asking first if it has unsaved changes.
    pub(super) fn ask_close_lesson(&mut self) {
        if self.lesson.unsaved() {
            self.document.confirm = Some(document::Pending::CloseLesson);
        } else {
            self.close_lesson();
        }
    }
}
