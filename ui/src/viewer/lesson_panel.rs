//! The Lesson panel: a lesson's title, its steps (a list to jump to any), Previous and Next
//! (buttons, Page Up and Page Down), and the current step's caption, whose simple markup
//! (`**bold**`, `*italics*`, lines starting `- `) is drawn as such. The panel holds the lesson and
//! the step shown; going to a step is an [`Action::LessonStep`] the app carries out.

use super::action::Action;
use eframe::egui::{self, RichText};
use std::path::{Path, PathBuf};
use vbrain::lesson::{Lesson, EXTENSION};

#[derive(Default)]
pub struct LessonPanel {
    /// The lesson open, from this file.
    pub lesson: Option<(PathBuf, Lesson)>,
    /// The step shown (0-based).
    pub step: usize,
}

/// The lessons in the `lessons` folder beside a set, by file name.
pub fn lessons_beside(set: &Path) -> Vec<PathBuf> {
    let mut found: Vec<PathBuf> = std::fs::read_dir(set.join("lessons"))
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    found.retain(|p| p.extension().is_some_and(|e| e == EXTENSION));
    found.sort();
    found
}

impl LessonPanel {
    pub fn is_open(&self) -> bool {
        self.lesson.is_some()
    }

    /// The step `delta` away from the current one, if there is one.
    pub fn step_by(&self, delta: isize) -> Option<usize> {
        let (_, lesson) = self.lesson.as_ref()?;
        let next = self.step.checked_add_signed(delta)?;
        (next < lesson.steps.len()).then_some(next)
    }

    pub fn show(&self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut out = Vec::new();
        let Some((_, lesson)) = &self.lesson else { return out };
        ui.horizontal(|ui| {
            ui.heading(&lesson.title);
            if ui.small_button("×").on_hover_text("Close the lesson").clicked() {
                out.push(Action::CloseLesson);
            }
        });
        ui.horizontal(|ui| {
            let previous = ui.add_enabled(self.step > 0, egui::Button::new("< Previous"));
            if previous.on_hover_text("Previous step (Page Up)").clicked() {
                out.extend(self.step_by(-1).map(Action::LessonStep));
            }
            ui.label(format!("step {} of {}", self.step + 1, lesson.steps.len()));
            let next = ui.add_enabled(self.step + 1 < lesson.steps.len(), egui::Button::new("Next >"));
            if next.on_hover_text("Next step (Page Down)").clicked() {
                out.extend(self.step_by(1).map(Action::LessonStep));
            }
        });
        ui.separator();
        for (k, step) in lesson.steps.iter().enumerate() {
            if ui.selectable_label(k == self.step, format!("{}. {}", k + 1, step.title)).clicked() && k != self.step {
                out.push(Action::LessonStep(k));
            }
        }
        ui.separator();
        if let Some(step) = lesson.steps.get(self.step) {
            ui.label(RichText::new(&step.title).strong());
            egui::ScrollArea::vertical().id_salt("caption").show(ui, |ui| caption(ui, &step.caption));
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
