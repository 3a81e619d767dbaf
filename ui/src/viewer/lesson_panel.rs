//! The Lesson panel: a lesson's title, its steps (a list to jump to any), Previous and Next
//! (buttons, Page Up and Page Down), and the current step's caption. With "Edit lesson" on, the
//! same panel authors it.
//!
//! - A caption's simple markup (`**bold**`, `*italics*`, lines starting `- `) is drawn as such.
//! - Authoring: add a step from the current view (or update the current step from it), edit
//!   titles and captions, move and delete steps, save the lesson.
//! - The panel holds the lesson, the step shown and its own undo snapshots; every change is a
//!   [`LessonEdit`] that the app records in the scene's history beside layout edits, so Ctrl+Z
//!   undoes them in the order made.

use super::action::Action;
use super::widgets::{accessible, PathField, Pick};
use crate::viewer::action::{LessonAction, QuizAction};
use eframe::egui::{self, RichText};
use std::path::{Path, PathBuf};
use vbrain::lesson::{Lesson, LessonEdit, EXTENSION};
use vbrain::transition::Transition;

/// Snapshots kept for undo (as many as the scene's history keeps steps).
const UNDO_LIMIT: usize = vbrain::history::DEFAULT_LIMIT;

#[derive(Default)]
pub struct LessonPanel {
    /// The lesson open.
    pub lesson: Option<Lesson>,
    /// Its file; `None` for a new lesson not saved yet.
    pub path: Option<PathBuf>,
    /// The lesson as last opened or saved.
    saved: Option<Lesson>,
    /// The step shown (0-based).
    pub step: usize,
    /// The organs its step highlights, outlined in the viewport.
    pub highlight: Vec<usize>,
    /// The change to this step under way, and the scene's change count it was made at (any
    /// later change ends it).
    pub transition: Option<(Transition, u64)>,
    /// Authoring controls shown.
    pub editing: bool,
    undo: Vec<Lesson>,
    redo: Vec<Lesson>,
    /// What the text fields hold while being typed in, and the step and texts they were filled
    /// from (refilled when those change and nobody is typing).
    texts: Texts,
    save_as: Option<PathField>,
}

#[derive(Default)]
struct Texts {
    lesson_title: String,
    title: String,
    caption: String,
    from: Option<(usize, String, String, String)>,
    typing: bool,
}

impl LessonPanel {
    /// A panel showing `lesson` (from `path`, or new) at its first step.
    pub fn open(lesson: Lesson, path: Option<PathBuf>) -> LessonPanel {
        let saved = path.is_some().then(|| lesson.clone());
        LessonPanel { editing: path.is_none(), lesson: Some(lesson), path, saved, ..Default::default() }
    }

    pub fn is_open(&self) -> bool {
        self.lesson.is_some()
    }

    /// The lesson has changes not saved to its file (or was never saved).
    pub fn unsaved(&self) -> bool {
        self.lesson.is_some() && self.lesson != self.saved
    }

    /// Forgets the changes since the lesson was saved (the user chose not to keep them).
    pub fn discard_changes(&mut self) {
        self.saved = self.lesson.clone();
    }

    /// Its name for people: the file's name or "new lesson", with `*` while unsaved.
    pub fn name(&self) -> String {
        let name = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map_or("new lesson".into(), |n| n.to_string_lossy().into_owned());
        format!("{name}{}", if self.unsaved() { " *" } else { "" })
    }

    /// The step `delta` away from the current one, if there is one.
    pub fn step_by(&self, delta: isize) -> Option<usize> {
        let lesson = self.lesson.as_ref()?;
        let next = self.step.checked_add_signed(delta)?;
        (next < lesson.steps.len()).then_some(next)
    }

    /// Applies an edit, keeping what was before for undo; returns its label if it changed
    /// anything. The current step follows the step it moved or added.
    pub fn edit(&mut self, edit: &LessonEdit) -> Option<String> {
        let lesson = self.lesson.as_mut()?;
        let before = lesson.clone();
        let label = lesson.edit(edit)?;
        self.undo.push(before);
        if self.undo.len() > UNDO_LIMIT {
            self.undo.remove(0);
        }
        self.redo.clear();
        self.step = match *edit {
            LessonEdit::Insert { at, .. } => at.min(lesson.steps.len() - 1),
            LessonEdit::Move { to, .. } => to,
            _ => self.step.min(lesson.steps.len() - 1),
        };
        Some(label)
    }

    /// Undoes (or with `redo`, redoes) the last lesson edit.
    pub fn undo(&mut self, redo: bool) {
        let (from, to) = if redo { (&mut self.redo, &mut self.undo) } else { (&mut self.undo, &mut self.redo) };
        if let (Some(back), Some(now)) = (from.pop(), self.lesson.as_mut()) {
            to.push(std::mem::replace(now, back));
            self.step = self.step.min(now.steps.len().saturating_sub(1));
        }
    }

    /// Writes the lesson to `path` (atomically); it becomes the lesson's file.
    pub fn save(&mut self, path: &Path) -> vbrain::Result<()> {
        let Some(lesson) = &mut self.lesson else { return Ok(()) };
        if let Some(from) = &self.path {
            if from != path {
                *lesson = lesson.moved(from, path);
            }
        }
        lesson.save(path)?;
        self.path = Some(path.to_path_buf());
        self.saved = Some(lesson.clone());
        self.save_as = None;
        Ok(())
    }

    /// Asks where to save (the panel's Save as field).
    pub fn ask_where(&mut self) {
        let mut field = PathField::default();
        field.text = self.path.as_ref().map(|p| p.display().to_string()).unwrap_or_default();
        self.save_as = Some(field);
    }

    /// Fills the text fields from the lesson unless someone is typing in them.
    fn refill_texts(&mut self) {
        let Some(lesson) = &self.lesson else { return };
        let Some(step) = lesson.steps.get(self.step) else { return };
        let from = Some((self.step, lesson.title.clone(), step.title.clone(), step.caption.clone()));
        if self.texts.from != from && !self.texts.typing {
            self.texts.lesson_title = lesson.title.clone();
            self.texts.title = step.title.clone();
            self.texts.caption = step.caption.clone();
            self.texts.from = from;
        }
    }

    pub fn show(&mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut out = Vec::new();
        self.refill_texts();
        let Some(lesson) = self.lesson.clone() else { return out };
        ui.horizontal(|ui| {
            ui.heading(&lesson.title);
            if ui.small_button("×").on_hover_text("Close the lesson").clicked() {
                out.push(Action::Lesson(LessonAction::Close));
            }
        });
        ui.horizontal(|ui| {
            let previous = ui.add_enabled(self.step > 0, egui::Button::new("< Previous"));
            if previous.on_hover_text("Previous step (Page Up)").clicked() {
                out.extend(self.step_by(-1).map(|k| Action::Lesson(LessonAction::Step(k))));
            }
            ui.label(format!("step {} of {}", self.step + 1, lesson.steps.len()));
            let next = ui.add_enabled(self.step + 1 < lesson.steps.len(), egui::Button::new("Next >"));
            if next.on_hover_text("Next step (Page Down)").clicked() {
                out.extend(self.step_by(1).map(|k| Action::Lesson(LessonAction::Step(k))));
            }
            ui.toggle_value(&mut self.editing, "Edit lesson").on_hover_text("Add, change, move and delete steps");
        });
        if !lesson.quiz.is_empty()
            && ui.button(format!("Take the lesson's quiz ({} questions)", lesson.quiz.len())).clicked()
        {
            out.push(Action::Quiz(QuizAction::Lesson));
        }
        ui.separator();
        let editing = self.editing;
        let n = lesson.steps.len();
        for (k, step) in lesson.steps.iter().enumerate() {
            ui.horizontal(|ui| {
                if ui.selectable_label(k == self.step, format!("{}. {}", k + 1, step.title)).clicked() && k != self.step
                {
                    out.push(Action::Lesson(LessonAction::Step(k)));
                }
                if editing {
                    let up = ui.add_enabled(k > 0, egui::Button::new("Up").small()).on_hover_text("Move up");
                    accessible(&up, format!("Move step {} up", k + 1));
                    if up.clicked() {
                        out.push(Action::Lesson(LessonAction::Edit(LessonEdit::Move { from: k, to: k - 1 })));
                    }
                    let down = ui.add_enabled(k + 1 < n, egui::Button::new("Down").small()).on_hover_text("Move down");
                    accessible(&down, format!("Move step {} down", k + 1));
                    if down.clicked() {
                        out.push(Action::Lesson(LessonAction::Edit(LessonEdit::Move { from: k, to: k + 1 })));
                    }
                    let delete =
                        ui.add_enabled(n > 1, egui::Button::new("Delete").small()).on_hover_text("Delete the step");
                    accessible(&delete, format!("Delete step {}", k + 1));
                    if delete.clicked() {
                        out.push(Action::Lesson(LessonAction::Edit(LessonEdit::Remove(k))));
                    }
                }
            });
        }
        if editing {
            out.extend(self.authoring(ui));
        }
        ui.separator();
        if let Some(step) = lesson.steps.get(self.step) {
            ui.label(RichText::new(&step.title).strong());
            egui::ScrollArea::vertical().id_salt("caption").show(ui, |ui| caption(ui, &step.caption));
        }
        out
    }

    /// The authoring controls: add or update a step from the view, the current step's title and
    /// caption, the lesson's title, Save and Save as.
    fn authoring(&mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut out = Vec::new();
        let Some(lesson) = &self.lesson else { return out };
        ui.horizontal(|ui| {
            let add = ui
                .button("+ Add step from view")
                .on_hover_text("A new step after this one: the organs and camera as they are now");
            if add.clicked() {
                out.push(Action::Lesson(LessonAction::AddStep { replace: false }));
            }
            let update = ui
                .button("Update step from view")
                .on_hover_text("This step shows the organs and camera as they are now");
            if update.clicked() {
                out.push(Action::Lesson(LessonAction::AddStep { replace: true }));
            }
        });
        let step = self.step;
        let commit = |texts: &Texts| {
            let mut s = lesson.steps.get(step)?.clone();
            s.title = texts.title.trim().to_string();
            s.caption = texts.caption.clone();
            Some(Action::Lesson(LessonAction::Edit(LessonEdit::Replace { at: step, step: Box::new(s) })))
        };
        let mut typing = false;
        let mut done = false;
        ui.horizontal(|ui| {
            ui.label("Step title:");
            let r = ui.text_edit_singleline(&mut self.texts.title);
            accessible(&r, "Step title");
            typing |= r.has_focus();
            done |= r.lost_focus();
        });
        ui.label("Caption (**bold**, *italics*, lines starting \"- \" for a list):");
        let r = ui.add(
            egui::TextEdit::multiline(&mut self.texts.caption).desired_rows(5).desired_width(ui.available_width()),
        );
        accessible(&r, "Caption");
        typing |= r.has_focus();
        done |= r.lost_focus();
        if done {
            out.extend(commit(&self.texts));
        }
        ui.horizontal(|ui| {
            ui.label("Lesson title:");
            let r = ui.text_edit_singleline(&mut self.texts.lesson_title);
            accessible(&r, "Lesson title");
            typing |= r.has_focus();
            if r.lost_focus() && !self.texts.lesson_title.trim().is_empty() {
                out.push(Action::Lesson(LessonAction::Edit(LessonEdit::Retitle(
                    self.texts.lesson_title.trim().to_string(),
                ))));
            }
        });
        self.texts.typing = typing;
        ui.horizontal(|ui| {
            let save = ui.add_enabled(self.unsaved(), egui::Button::new("Save lesson"));
            if save.on_hover_text("Write the lesson to its file").clicked() {
                out.push(Action::Lesson(LessonAction::Save { as_new: false }));
            }
            if ui.button("Save lesson as...").clicked() {
                out.push(Action::Lesson(LessonAction::Save { as_new: true }));
            }
        });
        if let Some(field) = &mut self.save_as {
            let entered = field.ui(ui, "Lesson file:", Pick::Save, &[("vbrain lesson", &[EXTENSION])]);
            let mut cancel = false;
            ui.horizontal(|ui| {
                if (ui.button("Save").clicked() || entered) && !field.text.trim().is_empty() {
                    out.push(Action::Lesson(LessonAction::SaveTo(super::widgets::with_extension(
                        &field.text,
                        EXTENSION,
                    ))));
                }
                cancel = ui.button("Cancel").clicked();
            });
            if cancel {
                self.save_as = None;
            }
        }
        out
    }
}

/// Draws a caption: paragraphs, `- ` list items, `**bold**` and `*italics*` runs.
fn caption(ui: &mut egui::Ui, text: &str) {
    for line in text.lines() {
        if line.trim().is_empty() {
            ui.add_space(4.0);
            continue;
        }
        let (bullet, body) = match line.strip_prefix("- ") {
            Some(rest) => ("•  ", rest),
            None => ("", line),
        };
        ui.horizontal_wrapped(|ui| {
            ui.spacing_mut().item_spacing.x = 0.0;
            if !bullet.is_empty() {
                ui.label(bullet);
            }
            for (text, bold, italic) in runs(body) {
                let mut t = RichText::new(text);
                if bold {
                    t = t.strong();
                }
                if italic {
                    t = t.italics();
                }
                ui.label(t);
            }
        });
    }
}

/// A line split into runs of (text, bold, italic) at `**` and `*` marks.
fn runs(line: &str) -> Vec<(String, bool, bool)> {
    let (mut out, mut current, mut bold, mut italic) = (Vec::new(), String::new(), false, false);
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '*' {
            if !current.is_empty() {
                out.push((std::mem::take(&mut current), bold, italic));
            }
            if chars.peek() == Some(&'*') {
                chars.next();
                bold = !bold;
            } else {
                italic = !italic;
            }
        } else {
            current.push(c);
        }
    }
    if !current.is_empty() {
        out.push((current, bold, italic));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::runs;

    #[test]
    fn markup_runs() {
        let r = runs("a **bold** and *it* end");
        let expect = [
            ("a ", false, false),
            ("bold", true, false),
            (" and ", false, false),
            ("it", false, true),
            (" end", false, false),
        ];
        assert_eq!(r, expect.map(|(t, b, i)| (t.to_string(), b, i)).to_vec());
    }
}
