//! The Quiz panel: a student tests themself. Set up a quiz (a group to ask about, how many
//! questions, locate / name / mixed, an optional time limit, a seed for a repeatable quiz), then
//! answer.
//!
//! - "Click the left caudate nucleus" is answered by clicking it in the view; "Name the outlined
//!   structure" by typing its name or picking one of four.
//! - Each answer is marked at once (a wrong click names what was clicked and outlines the right
//!   one); score, streak and time are shown.
//! - At the end a review flies to each missed structure with its label and info text.
//! - The panel holds the quiz's state; the app shows each question's view (see `app/quiz.rs`).

use super::action::Action;
use super::widgets::accessible;
use crate::viewer::action::QuizAction;
use eframe::egui::{self, RichText};
use vbrain::quiz::{Kind, Mode, Question};

/// What the student sets before starting.
#[derive(Clone, Debug, PartialEq)]
pub struct Setup {
    /// A group path or id; empty for every organ shown by default.
    pub group: String,
    pub questions: usize,
    pub mode: Mode,
    /// Minutes for the whole quiz; 0 for no limit.
    pub minutes: u32,
    pub seed: u64,
}

impl Default for Setup {
    fn default() -> Self {
        Setup { group: String::new(), questions: 10, mode: Mode::Mixed, minutes: 0, seed: 1 }
    }
}

/// One answered question.
#[derive(Clone, Debug, PartialEq)]
pub struct Answered {
    pub correct: bool,
    /// What was given: the organ clicked or picked, or the text typed.
    pub given: String,
    /// Seconds since the question was asked.
    pub seconds: f64,
}

/// Per question, the layout and camera it starts from (a lesson's step), if not the default.
pub type Views = Vec<Option<(vbrain::layout::Layout, vbrain::navigation::Navigator)>>;

/// A quiz under way or finished.
#[derive(Clone, Debug, PartialEq)]
pub struct Run {
    /// What it is over, for the history ("Basal ganglia", or the lesson's title).
    pub title: String,
    pub questions: Vec<Question>,
    /// The question asked (== questions.len() once finished).
    pub k: usize,
    pub answers: Vec<Answered>,
    /// When the quiz and the current question started (seconds, the UI's clock).
    pub started: f64,
    pub asked: f64,
    /// The time limit's end, if any.
    pub ends: Option<f64>,
    /// The text typed for a name question.
    pub typed: String,
    /// The mark of the current question, shown until Next: text and whether right.
    pub feedback: Option<(String, bool)>,
    pub streak: usize,
    pub best_streak: usize,
    /// Seconds the quiz took, once finished.
    pub took: Option<f64>,
    /// The missed question being reviewed.
    pub reviewing: Option<usize>,
    /// Per question, the layout and camera it starts from (a lesson's step), if not the default.
    pub views: Views,
}

impl Run {
    pub fn new(title: String, questions: Vec<Question>, now: f64, minutes: u32) -> Run {
        Run {
            title,
            questions,
            k: 0,
            answers: Vec::new(),
            started: now,
            asked: now,
            ends: (minutes > 0).then(|| now + f64::from(minutes) * 60.0),
            typed: String::new(),
            feedback: None,
            streak: 0,
            best_streak: 0,
            took: None,
            reviewing: None,
            views: Vec::new(),
        }
    }

    pub fn finished(&self) -> bool {
        self.took.is_some()
    }

    pub fn current(&self) -> Option<&Question> {
        self.questions.get(self.k).filter(|_| !self.finished())
    }

    pub fn score(&self) -> usize {
        self.answers.iter().filter(|a| a.correct).count()
    }

    /// Marks the current question; returns false if it was marked already.
    pub fn mark(&mut self, correct: bool, given: String, feedback: String, now: f64) -> bool {
        if self.feedback.is_some() || self.current().is_none() {
            return false;
        }
        self.answers.push(Answered { correct, given, seconds: now - self.asked });
        self.streak = if correct { self.streak + 1 } else { 0 };
        self.best_streak = self.best_streak.max(self.streak);
        self.feedback = Some((feedback, correct));
        true
    }

    /// The questions answered wrongly or left unanswered.
    pub fn missed(&self) -> Vec<usize> {
        (0..self.questions.len()).filter(|&k| !self.answers.get(k).is_some_and(|a| a.correct)).collect()
    }
}

#[derive(Default)]
pub struct QuizPanel {
    pub open: bool,
    pub setup: Setup,
    pub run: Option<Run>,
    /// Where "Export results" writes.
    pub export_path: String,
    /// Lines of past results for this set, newest last.
    pub history: Vec<String>,
    /// [`QuizPanel::highlight`] as of the last action.
    pub outlined: Vec<usize>,
}

impl QuizPanel {
    /// The organs the viewport outlines now: the target of a name question, the right answer
    /// after a wrong click, the structure reviewed.
    pub fn highlight(&self) -> Vec<usize> {
        let Some(run) = &self.run else { return Vec::new() };
        if let Some(k) = run.reviewing {
            return run.questions.get(k).map(|q| vec![q.organ]).unwrap_or_default();
        }
        match run.current() {
            Some(q) if q.kind != Kind::Locate || run.feedback.is_some() => vec![q.organ],
            _ => Vec::new(),
        }
    }

    /// Brings [`QuizPanel::outlined`] up to date.
    pub fn refresh(&mut self) {
        self.outlined = self.highlight();
    }

    /// Is a quiz being answered (so clicks answer and labels would give answers away)?
    pub fn answering(&self) -> bool {
        self.run.as_ref().is_some_and(|r| !r.finished())
    }

    /// The panel; `name` names organs and `artery` the set's arteries (by index), `info` gives
    /// the organs' texts, `groups` are the set's group paths to choose from, `now` the UI's clock.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        (name, artery): (&dyn Fn(usize) -> String, &dyn Fn(usize) -> String),
        info: &dyn Fn(usize) -> String,
        groups: &[String],
        now: f64,
    ) -> Vec<Action> {
        let mut out = Vec::new();
        ui.horizontal(|ui| {
            ui.heading("Quiz");
            if ui.small_button("Close").on_hover_text("Leave the quiz").clicked() {
                out.push(Action::Quiz(QuizAction::Close));
            }
        });
        match &mut self.run {
            None => setup(ui, &mut self.setup, groups, &self.history, &mut out),
            Some(run) if !run.finished() => answering(ui, run, (name, artery), now, &mut out),
            Some(run) => review(ui, run, name, info, &mut self.export_path, &mut out),
        }
        out
    }
}

/// The group choice's text for "every organ shown by default".
const ALL_SHOWN: &str = "All structures shown";

fn setup(ui: &mut egui::Ui, s: &mut Setup, groups: &[String], history: &[String], out: &mut Vec<Action>) {
    ui.label("Test yourself on the structures of this set.");
    ui.horizontal(|ui| {
        ui.label("Group");
        let selected = if s.group.is_empty() { ALL_SHOWN } else { s.group.as_str() };
        let r = egui::ComboBox::from_id_salt("quiz group")
            .selected_text(selected)
            .width(200.0)
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut s.group, String::new(), ALL_SHOWN);
                // Nested groups indented under their parents, named by their last part.
                for path in groups {
                    let depth = path.matches('/').count();
                    let name = path.rsplit('/').next().unwrap_or(path);
                    ui.horizontal(|ui| {
                        ui.add_space(14.0 * depth as f32);
                        ui.selectable_value(&mut s.group, path.clone(), name).on_hover_text(path);
                    });
                }
            })
            .response;
        accessible(&r, "Quiz group");
        r.on_hover_text("The structures to be asked about: a group of the set, or all shown");
    });
    ui.horizontal(|ui| {
        ui.label("Questions");
        let r = ui.add(egui::DragValue::new(&mut s.questions).range(1..=200));
        accessible(&r, "Quiz questions");
        ui.label("Seed");
        let r = ui.add(egui::DragValue::new(&mut s.seed));
        accessible(&r, "Quiz seed");
        r.on_hover_text("The same seed asks the same questions");
    });
    ui.horizontal(|ui| {
        for (mode, text) in [
            (Mode::Locate, "Locate"),
            (Mode::Name, "Name"),
            (Mode::Mixed, "Mixed"),
            (Mode::Mri, "MRI slices"),
            (Mode::Supply, "Blood supply"),
        ] {
            let r = ui.radio_value(&mut s.mode, mode, text);
            if mode == Mode::Mri {
                r.on_hover_text("Name and locate by turns on axial, coronal and sagittal slices of the MRI");
            } else if mode == Mode::Supply {
                r.on_hover_text("Which artery supplies the outlined region? (sets with arterial territories)");
            }
        }
    });
    ui.horizontal(|ui| {
        ui.label("Time limit");
        let r = ui.add(egui::DragValue::new(&mut s.minutes).range(0..=120).suffix(" min"));
        accessible(&r, "Quiz time limit");
        r.on_hover_text("0: no limit");
    });
    if ui.button("Start quiz").clicked() {
        out.push(Action::Quiz(QuizAction::Start));
    }
    if !history.is_empty() {
        ui.separator();
        ui.label(RichText::new("Your last results").strong());
        for line in history.iter().rev().take(5) {
            ui.label(RichText::new(line).weak());
        }
    }
}

/// The question being asked; `name` names organs, `artery` arteries (a supply question's choices).
fn answering(
    ui: &mut egui::Ui,
    run: &mut Run,
    (name, artery): (&dyn Fn(usize) -> String, &dyn Fn(usize) -> String),
    now: f64,
    out: &mut Vec<Action>,
) {
    let Some(q) = run.current().cloned() else { return };
    let elapsed = now - run.started;
    let time = match run.ends {
        Some(end) => format!("{:.0} s left", (end - now).max(0.0)),
        None => format!("{elapsed:.0} s"),
    };
    ui.label(format!(
        "Question {} of {}   score {}   streak {}   {time}",
        run.k + 1,
        run.questions.len(),
        run.score(),
        run.streak
    ));
    ui.separator();
    match q.kind {
        Kind::Locate => {
            ui.label(RichText::new(format!("Click the {}", vbrain::quiz::lower_first(&name(q.organ)))).heading());
            ui.label(RichText::new("Click it in the view; you can still turn the brain.").weak());
        }
        Kind::Supply => {
            ui.label(RichText::new(vbrain::quiz::supply_prompt(run.k)).heading());
            if run.feedback.is_none() {
                for &c in &q.choices {
                    let r = ui.button(artery(c));
                    accessible(&r, format!("Choice {}", artery(c)));
                    if r.clicked() {
                        out.push(Action::Quiz(QuizAction::Pick(c)));
                    }
                }
            }
        }
        Kind::Name => {
            ui.label(RichText::new("Name the outlined structure").heading());
            if run.feedback.is_none() {
                let r = ui.add(egui::TextEdit::singleline(&mut run.typed).hint_text("type its name"));
                accessible(&r, "Quiz answer");
                let entered = r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                if ui.button("Check").clicked() || entered {
                    out.push(Action::Quiz(QuizAction::Answer(run.typed.clone())));
                }
                ui.label(RichText::new("or pick one:").weak());
                for &c in &q.choices {
                    let r = ui.button(name(c));
                    accessible(&r, format!("Choice {}", name(c)));
                    if r.clicked() {
                        out.push(Action::Quiz(QuizAction::Pick(c)));
                    }
                }
            }
        }
    }
    if let Some((text, right)) = &run.feedback {
        ui.separator();
        let colour =
            if *right { egui::Color32::from_rgb(120, 210, 120) } else { egui::Color32::from_rgb(240, 130, 110) };
        ui.label(RichText::new(text).color(colour).strong());
        let last = run.k + 1 == run.questions.len();
        if ui.button(if last { "Finish" } else { "Next question" }).clicked() {
            out.push(Action::Quiz(QuizAction::Next));
        }
    }
}

fn review(
    ui: &mut egui::Ui,
    run: &Run,
    name: &dyn Fn(usize) -> String,
    info: &dyn Fn(usize) -> String,
    export: &mut String,
    out: &mut Vec<Action>,
) {
    let n = run.questions.len();
    ui.label(RichText::new(format!("Score {} of {n}", run.score())).heading());
    ui.label(format!("Best streak {}, {:.0} s", run.best_streak, run.took.unwrap_or(0.0)));
    let missed = run.missed();
    ui.separator();
    if missed.is_empty() {
        ui.label("No structure missed.");
    } else {
        ui.label(RichText::new("Review what you missed").strong());
    }
    for k in missed {
        let organ = run.questions[k].organ;
        ui.horizontal(|ui| {
            let given = run.answers.get(k).map_or("no answer".to_string(), |a| a.given.clone());
            ui.label(format!("{}. {} (you: {given})", k + 1, name(organ)));
            let r = ui.small_button("Show");
            accessible(&r, format!("Review {}", name(organ)));
            if r.clicked() {
                out.push(Action::Quiz(QuizAction::Review(k)));
            }
        });
    }
    if let Some(k) = run.reviewing {
        ui.separator();
        let organ = run.questions[k].organ;
        ui.label(RichText::new(name(organ)).strong());
        egui::ScrollArea::vertical().max_height(200.0).show(ui, |ui| ui.label(info(organ)));
    }
    ui.separator();
    ui.horizontal(|ui| {
        let r = ui.add(egui::TextEdit::singleline(export).hint_text("results.csv").desired_width(160.0));
        accessible(&r, "Quiz results file");
        if ui.button("Export CSV").on_hover_text("Each question, your answer and the time it took").clicked() {
            out.push(Action::Quiz(QuizAction::Export(export.clone())));
        }
    });
    if ui.button("New quiz").clicked() {
        out.push(Action::Quiz(QuizAction::Again));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marks_keep_score_streak_and_the_missed() {
        let q = |organ| Question { kind: Kind::Locate, organ, choices: vec![organ], slice: None };
        let mut run = Run::new("t".into(), vec![q(1), q(2), q(3)], 0.0, 1);
        assert!(run.mark(true, "a".into(), "ok".into(), 2.0));
        assert!(!run.mark(false, "b".into(), "no".into(), 3.0), "one mark per question");
        run.feedback = None;
        run.k = 1;
        run.mark(false, "b".into(), "no".into(), 4.0);
        assert_eq!((run.score(), run.streak, run.best_streak), (1, 0, 1));
        assert_eq!(run.missed(), vec![1, 2]);
        assert_eq!(run.ends, Some(60.0));
    }
}
