//! The app's quizzes: starting one (from the Quiz panel's setup or a lesson's quiz), showing each
//! question's view, marking clicks, typed names and picks, the time limit, the review, the
//! history of results per set and the CSV export.
//!
//! - A question's view is the default layout with the organs hiding the target faded (found from
//!   the viewport's organ-ID buffer) and a camera from the target's side.
//! - It is shown in place of the scene's layout, which the quiz never changes.
//! - A question on a slice also brings up the slice panes through its structure.
//! - A child module of the app, so it reaches its state.

use super::App;
use crate::viewer::action::QuizAction;
use crate::viewer::quiz_panel::{Run, Views};
use eframe::egui;
use vbrain::quiz::{self, Kind, Question, Spec};

impl App {
    /// Carries out a quiz action; answers are timed by the frame's clock.
    pub(super) fn perform_quiz(&mut self, ctx: &egui::Context, action: QuizAction) {
        let now = ctx.input(|i| i.time);
        match action {
            QuizAction::Start => self.start_quiz(ctx, None),
            QuizAction::Lesson => self.start_lesson_quiz(ctx),
            QuizAction::Answer(text) => self.quiz_name(Some(text), None, now),
            QuizAction::Pick(organ) => self.quiz_name(None, Some(organ), now),
            QuizAction::Next => self.quiz_next(now),
            QuizAction::Review(k) => self.quiz_review(k),
            QuizAction::Export(path) => self.export_quiz(&path),
            QuizAction::Again => self.close_quiz(true),
            QuizAction::Close => self.close_quiz(false),
        }
    }

    /// Starts a quiz: `given` questions (a lesson's, with its title and each question's view),
    /// else the panel's setup.
    pub(super) fn start_quiz(&mut self, ctx: &egui::Context, given: Option<(String, Vec<Question>, Views)>) {
        let Some(scene) = &self.scene else { return };
        let set = scene.set();
        let (title, questions, views) = match given {
            Some(q) => q,
            None => {
                let s = &self.quiz.setup;
                let group = Some(s.group.trim()).filter(|g| !g.is_empty());
                let made = quiz::scope(set, group).and_then(|scope| {
                    quiz::generate(set, &Spec { scope, questions: s.questions, mode: s.mode, seed: s.seed })
                });
                let title = group.unwrap_or("all structures").to_string();
                match made {
                    Ok(made) => {
                        if let Some(note) = made.note {
                            self.notify(note, false);
                        }
                        (title, made.questions, Vec::new())
                    }
                    Err(e) => return self.notify(e, true),
                }
            }
        };
        if questions.is_empty() {
            return self.notify("the quiz has no questions", true);
        }
        let now = ctx.input(|i| i.time);
        self.quiz.run = Some(Run { views, ..Run::new(title, questions, now, self.quiz.setup.minutes) });
        self.quiz.open = true;
        self.selected = None;
        // A lesson step still easing in would put its own layout back over the question's.
        self.lesson.transition = None;
        self.ask_question(now);
    }

    /// Starts the open lesson's quiz.
    pub(super) fn start_lesson_quiz(&mut self, ctx: &egui::Context) {
        let (Some(lesson), Some(scene)) = (&self.lesson.lesson, &self.scene) else { return };
        match lesson.questions(scene.set()) {
            Ok(q) => {
                let title = lesson.title.clone();
                let views = (0..q.len())
                    .map(|k| lesson.question_view(k, scene.set()).map(|v| (v.layout, v.navigator)))
                    .collect();
                self.start_quiz(ctx, Some((title, q, views)));
            }
            Err(e) => self.notify(e, true),
        }
    }

    /// Shows the view of question `k`: what hides its structure faded, the camera on its side
    /// (or the lesson step's layout and camera the question names).
    fn show_question_view(&mut self, k: usize) {
        let (Some(scene), Some(run)) = (&self.scene, &self.quiz.run) else { return };
        let Some(organ) = run.questions.get(k).map(|q| q.organ) else { return };
        // A question on a slice: the slice panes come up, through the structure on its plane.
        if let Some(plane) = run.questions.get(k).and_then(|q| q.slice) {
            use crate::viewer::settings::ViewLayout;
            if self.settings.view_layout == ViewLayout::ThreeD {
                self.settings.view_layout = ViewLayout::ThreeDWithSlices;
            }
            let mut point = scene.set().organs[organ].mesh().bounds().center();
            point[plane.axis.normal()] = plane.at;
            self.slices.point = Some(point);
        }
        let (base, nav) = run.views.get(k).cloned().flatten().unwrap_or_else(|| quiz::side_view(scene.set(), organ));
        let input = self.viewport_input();
        let (layout, _) = quiz::reveal(organ, &base, |l| self.viewport.ids_of(&input, l, nav).unwrap_or_default());
        if let Some(scene) = &mut self.scene {
            scene.show_instead(Some(layout));
        }
        self.viewport.set_navigator(nav, false);
    }

    fn ask_question(&mut self, now: f64) {
        let Some(run) = &mut self.quiz.run else { return };
        (run.asked, run.feedback, run.typed) = (now, None, String::new());
        if !run.finished() {
            let k = run.k;
            self.show_question_view(k);
        }
    }

    fn organ_name(&self, organ: usize) -> String {
        self.scene.as_ref().and_then(|s| s.set().organs.get(organ)).map_or(String::new(), |o| o.name.clone())
    }

    /// A click in the view while a quiz is answered: a locate question's answer.
    pub(super) fn quiz_click(&mut self, clicked: Option<usize>, now: f64) {
        let Some(q) = self.quiz.run.as_ref().and_then(Run::current).cloned() else { return };
        let Some(clicked) = clicked.filter(|_| q.kind == Kind::Locate) else { return };
        let (target, got) = (self.organ_name(q.organ), self.organ_name(clicked));
        let right = clicked == q.organ;
        let text = if right {
            format!("Right: the {}", quiz::lower_first(&target))
        } else {
            format!("That is the {}. The {} is outlined.", quiz::lower_first(&got), quiz::lower_first(&target))
        };
        if let Some(run) = &mut self.quiz.run {
            run.mark(right, got, text, now);
        }
    }

    /// A name question answered by typing (`typed`) or picking (`picked`).
    pub(super) fn quiz_name(&mut self, typed: Option<String>, picked: Option<usize>, now: f64) {
        let Some(q) = self.quiz.run.as_ref().and_then(Run::current).cloned() else { return };
        let Some(scene) = &self.scene else { return };
        if q.kind == Kind::Supply {
            return self.quiz_supply(&q, picked, now);
        }
        let (right, given) = match (typed, picked) {
            (Some(t), _) => (quiz::accepts(scene.set(), q.organ, &t), t),
            (None, Some(p)) => (p == q.organ, self.organ_name(p)),
            (None, None) => return,
        };
        if given.trim().is_empty() {
            return self.notify("type a name, or pick one of the four", false);
        }
        let target = self.organ_name(q.organ);
        let text = if right {
            format!("Right: {target}")
        } else {
            format!("Not quite: it is the {}", quiz::lower_first(&target))
        };
        if let Some(run) = &mut self.quiz.run {
            run.mark(right, given, text, now);
        }
    }

    /// A supply question answered by picking artery `picked` (an index into the set's arteries).
    fn quiz_supply(&mut self, q: &Question, picked: Option<usize>, now: f64) {
        let (Some(scene), Some(picked)) = (&self.scene, picked) else { return };
        let set = scene.set();
        let Some(arteries) = set.territories.as_ref().map(|t| &t.arteries) else { return };
        let name = |k: usize| arteries.get(k).map_or(String::new(), |a| a.name.clone());
        let answer = quiz::supplier(set, q.organ);
        let right = answer == Some(picked);
        let region = quiz::lower_first(&self.organ_name(q.organ));
        let target = answer.map(name).unwrap_or_default();
        let text = if right {
            format!("Right: the {} supplies the {region}", quiz::lower_first(&target))
        } else {
            format!("Not quite: the {region} lies in the territory of the {}", quiz::lower_first(&target))
        };
        if let Some(run) = &mut self.quiz.run {
            run.mark(right, name(picked), text, now);
        }
    }

    /// The next question, or the end.
    pub(super) fn quiz_next(&mut self, now: f64) {
        let Some(run) = &mut self.quiz.run else { return };
        if run.feedback.is_none() {
            return;
        }
        run.k += 1;
        if run.k >= run.questions.len() {
            self.finish_quiz(now);
        } else {
            self.ask_question(now);
        }
    }

    /// Ends the quiz (the last answer, or the time limit) and keeps the result in the history.
    fn finish_quiz(&mut self, now: f64) {
        let Some(run) = &mut self.quiz.run else { return };
        run.k = run.questions.len();
        run.feedback = None;
        run.took = Some(now - run.started);
        let line = format!("{}: {} of {} in {:.0} s", run.title, run.score(), run.questions.len(), now - run.started);
        let set = self.scene.as_ref().map_or(String::new(), |s| s.set().title.clone());
        let when = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
        let csv = format!(
            "{when},{},{},{},{},{:.1}\n",
            vbrain::lab::csv_field(&set),
            vbrain::lab::csv_field(&run.title),
            run.questions.len(),
            run.score(),
            now - run.started
        );
        self.quiz.history.push(line);
        if let Some(path) = &self.quiz_history {
            if let Err(e) = append(path, &csv) {
                self.notify(format!("{}: the quiz result was not kept: {e}", path.display()), true);
            }
        }
        if let Some(scene) = &mut self.scene {
            scene.show_instead(None);
        }
    }

    /// Each frame: the time limit, and a repaint each second for the clock.
    pub(super) fn quiz_tick(&mut self, ctx: &egui::Context) {
        let Some(run) = &self.quiz.run else { return };
        if run.finished() {
            return;
        }
        let now = ctx.input(|i| i.time);
        if run.ends.is_some_and(|end| now >= end) {
            self.notify("time is up", false);
            return self.finish_quiz(now);
        }
        ctx.request_repaint_after(std::time::Duration::from_millis(500));
    }

    /// Flies to missed question `k`'s structure, labelled, with its info text in the panel.
    pub(super) fn quiz_review(&mut self, k: usize) {
        let Some(run) = &mut self.quiz.run else { return };
        run.reviewing = Some(k);
        self.show_question_view(k);
    }

    /// Leaves the quiz: the scene's own layout is shown again.
    pub(super) fn close_quiz(&mut self, setup_again: bool) {
        self.quiz.run = None;
        self.quiz.open = setup_again;
        if let Some(scene) = &mut self.scene {
            scene.show_instead(None);
        }
    }

    /// Writes the quiz's questions and answers as CSV (atomically).
    pub(super) fn export_quiz(&mut self, path: &str) {
        let (Some(run), Some(scene)) = (&self.quiz.run, &self.scene) else { return };
        let path = if path.trim().is_empty() { "quiz-results.csv" } else { path.trim() };
        let path = crate::viewer::widgets::with_extension(path, "csv");
        let mut text = String::from("question,kind,organ_id,organ,answer,correct,seconds\n");
        for (k, q) in run.questions.iter().enumerate() {
            let o = &scene.set().organs[q.organ];
            let a = run.answers.get(k);
            text.push_str(&format!(
                "{},{},{},{},{},{},{}\n",
                k + 1,
                match q.kind {
                    Kind::Locate => "locate",
                    Kind::Name => "name",
                    Kind::Supply => "supply",
                },
                vbrain::lab::csv_field(&o.id),
                vbrain::lab::csv_field(&o.name),
                vbrain::lab::csv_field(a.map_or("", |a| a.given.as_str())),
                a.is_some_and(|a| a.correct),
                a.map_or(String::new(), |a| format!("{:.1}", a.seconds)),
            ));
        }
        match vbrain::atomic::write(&path, |w| w.write_all(text.as_bytes())) {
            Ok(()) => self.notify(format!("quiz results written to {}", path.display()), false),
            Err(e) => self.notify(format!("quiz results not written: {e}"), true),
        }
    }

    /// The results kept for this set, as the panel lists them.
    pub(super) fn load_quiz_history(&mut self) {
        let (Some(path), Some(scene)) = (&self.quiz_history, &self.scene) else { return };
        let title = vbrain::lab::csv_field(&scene.set().title);
        let text = vbrain::input::read_text(path, vbrain::input::Kind::Document).unwrap_or_default();
        self.quiz.history = text
            .lines()
            .filter_map(|l| {
                let rest = l.split_once(',')?.1.strip_prefix(&format!("{title},"))?;
                let fields: Vec<&str> = rest.rsplitn(4, ',').collect();
                let [seconds, correct, questions, quiz] = fields[..] else { return None };
                Some(format!("{}: {correct} of {questions} in {seconds} s", quiz.trim_matches('"')))
            })
            .collect();
    }
}

/// Appends a line to a file, creating it (and its folder) if needed.
fn append(path: &std::path::Path, line: &str) -> std::io::Result<()> {
    use std::io::Write;
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::OpenOptions::new().create(true).append(true).open(path)?.write_all(line.as_bytes())
}
