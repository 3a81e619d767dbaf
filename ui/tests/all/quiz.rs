//! Quizzes in the real viewer under egui_kittest: a locate and a name quiz played to the end by
//! clicking, typing and picking (right and wrong answers), the review and the CSV export; a
//! lesson's quiz taken from its steps.

use crate::viewer::{brain, click, harness_of, organ, pixels_of, point_on};
use eframe::egui;
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use vbrain_ui::viewer::action::{LessonAction, QuizAction};
use vbrain_ui::App;

/// An organ drawn at some pixel that is not `organ`.
fn other_than(h: &Harness<'static, App>, organ: usize) -> usize {
    let (ids, _) = h.state().read_ids().unwrap();
    ids.iter().find(|&&i| i != 0 && i != organ as u32 + 1).map(|&i| i as usize - 1).unwrap()
}

#[test]
fn play_a_locate_and_a_name_quiz_to_the_end() {
    use vbrain::quiz::{Kind, Mode};
    use vbrain_ui::viewer::action::{Action, Window};
    let mut h = harness_of(egui::Vec2::new(900.0, 560.0));
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Show(Window::Quiz)]);
    h.run_steps(2);
    let setup = &mut h.state_mut().quiz_mut().setup;
    (setup.group, setup.questions, setup.mode, setup.seed) = ("Basal ganglia".into(), 3, Mode::Locate, 2);
    h.get_by_label("Start quiz").click_accesskit();
    h.run_steps(3);

    // Locate: right, wrong, right. Each target is seen from the quiz's camera.
    for k in 0..3 {
        let q = h.state().quiz().run.as_ref().unwrap().current().unwrap().clone();
        assert_eq!(q.kind, Kind::Locate);
        assert!(pixels_of(&h, q.organ) > 20, "question {k}: the target shows");
        let at = if k == 1 { point_on(&h, other_than(&h, q.organ)) } else { point_on(&h, q.organ) };
        click(&h, at);
        h.run_steps(3);
        let run = h.state().quiz().run.as_ref().unwrap();
        let (text, right) = run.feedback.clone().unwrap();
        assert_eq!(right, k != 1, "question {k}: {text}");
        if k == 1 {
            assert!(text.starts_with("That is the"), "a wrong click names what was clicked: {text}");
            assert_eq!(h.state().quiz().outlined, vec![q.organ], "then the right one is outlined");
        }
        assert_eq!(h.state().selected(), None, "clicks answer, they do not select");
        h.get_by_label(if k == 2 { "Finish" } else { "Next question" }).click_accesskit();
        h.run_steps(3);
    }
    let run = h.state().quiz().run.clone().unwrap();
    assert!(run.finished());
    assert_eq!((run.score(), run.best_streak, run.missed()), (2, 1, vec![1]));
    assert!(h.state().quiz().history.last().unwrap().contains("2 of 3"));
    let missed = h.state().scene().unwrap().set().organs[run.questions[1].organ].name.clone();
    h.get_by_label(&format!("Review {missed}")).click_accesskit();
    h.run_steps(3);
    assert_eq!(h.state().quiz().outlined, vec![run.questions[1].organ], "the review shows the missed structure");
    assert!(pixels_of(&h, run.questions[1].organ) > 20);
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("results.csv");
    h.state_mut().perform(&ctx, vec![Action::Quiz(QuizAction::Export(csv.display().to_string()))]);
    assert_eq!(std::fs::read_to_string(&csv).unwrap().lines().count(), 4, "a header and three questions");

    // Name: type the right name, pick a wrong choice, pick the right one.
    h.get_by_label("New quiz").click_accesskit();
    h.run_steps(2);
    h.state_mut().quiz_mut().setup.mode = Mode::Name;
    h.get_by_label("Start quiz").click_accesskit();
    h.run_steps(3);
    let set = h.state().scene().unwrap().set().clone();
    for k in 0..3 {
        let q = h.state().quiz().run.as_ref().unwrap().current().unwrap().clone();
        assert_eq!(h.state().quiz().outlined, vec![q.organ], "the structure to name is outlined");
        if k == 0 {
            h.get_by_label("Quiz answer").focus();
            h.run_steps(1);
            h.get_by_label("Quiz answer").type_text(&set.organs[q.organ].name.to_lowercase());
            h.run_steps(1);
            h.get_by_label("Check").click_accesskit();
        } else {
            let pick = if k == 1 { *q.choices.iter().find(|&&c| c != q.organ).unwrap() } else { q.organ };
            h.get_by_label(&format!("Choice {}", set.organs[pick].name)).click_accesskit();
        }
        h.run_steps(2);
        let (text, right) = h.state().quiz().run.as_ref().unwrap().feedback.clone().unwrap();
        assert_eq!(right, k != 1, "question {k}: {text}");
        h.get_by_label(if k == 2 { "Finish" } else { "Next question" }).click_accesskit();
        h.run_steps(2);
    }
    assert_eq!(h.state().quiz().run.as_ref().unwrap().score(), 2);
    h.get_by_label("Close").click_accesskit();
    h.run_steps(2);
    assert!(h.state().quiz().run.is_none());
    assert!(
        h.state().scene().unwrap().shown() == h.state().scene().unwrap().layout(),
        "the scene's own layout is back"
    );
}

#[test]
fn take_a_lessons_quiz_from_its_steps() {
    use vbrain_ui::viewer::action::Action;
    let mut h = harness_of(egui::Vec2::new(900.0, 560.0));
    let ctx = h.ctx.clone();
    let path = brain().join("lessons/deep-nuclei.vblesson");
    h.state_mut().perform(&ctx, vec![Action::Lesson(LessonAction::Open(path))]);
    h.run_steps(3);
    h.get_by_label("Take the lesson's quiz (6 questions)").click_accesskit();
    h.run_steps(3);
    let run = h.state().quiz().run.clone().expect("the quiz starts");
    assert_eq!((run.questions.len(), run.title.as_str()), (6, "The basal ganglia and thalamus"));
    assert_eq!(run.views.iter().filter(|v| v.is_some()).count(), 1, "one question starts from a step");
    let caudate = organ(&h, "caudate_l");
    assert_eq!(run.questions[0].organ, caudate, "in the lesson's order");
    click(&h, point_on(&h, caudate));
    h.run_steps(2);
    h.get_by_label("Next question").click_accesskit();
    h.run_steps(3);
    let shown = h.state().scene().unwrap().shown().clone();
    let white = organ(&h, "white_matter_l");
    assert!(!shown.organs[white].visible, "question 2 starts from step 2, the cerebrum hidden");
}

/// The MRI quiz in the viewer: the slice panes come up through the question's structure, and a
/// click on it in its pane answers right.
#[test]
fn an_mri_question_is_answered_by_clicking_its_slice() {
    use vbrain::mri::slice::{organ_ids, Axis};
    use vbrain::quiz::{Kind, Mode};
    use vbrain_ui::viewer::action::{Action, Window};
    use vbrain_ui::viewer::settings::ViewLayout;
    let mut h = harness_of(egui::Vec2::new(1000.0, 640.0));
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Show(Window::Quiz)]);
    h.run_steps(2);
    let setup = &mut h.state_mut().quiz_mut().setup;
    (setup.group, setup.questions, setup.mode, setup.seed) = ("Basal ganglia".into(), 2, Mode::Mri, 4);
    h.get_by_label("Start quiz").click_accesskit();
    h.run_steps(4);
    assert_eq!(h.state().settings().view_layout, ViewLayout::ThreeDWithSlices);
    let q = h.state().quiz().run.as_ref().unwrap().current().unwrap().clone();
    assert_eq!(q.kind, Kind::Locate);
    let plane = q.slice.unwrap();
    let k = Axis::ALL.iter().position(|&a| a == plane.axis).unwrap();
    let (rect, pane) = h.state().slices().shown(Axis::ALL[k]).unwrap();
    assert_eq!(pane.plane, plane, "the pane shows the question's slice");
    // A pixel deep inside the structure on that pane.
    let set = h.state().scene().unwrap().set();
    let shown: Vec<usize> = (0..set.organs.len()).filter(|&o| set.organs[o].visible).collect();
    let ids = organ_ids(set, &shown, &pane);
    let w = pane.width as usize;
    let own = |i: usize| ids.get(i) == Some(&(q.organ as u32 + 1));
    let deep = (w..ids.len() - w).find(|&i| own(i) && own(i - 1) && own(i + 1) && own(i - w) && own(i + w)).unwrap();
    let ppp = ctx.pixels_per_point();
    let at = rect.min + egui::vec2((deep % w) as f32 + 0.5, (deep / w) as f32 + 0.5) / ppp;
    click(&h, at);
    h.run_steps(3);
    let (text, right) = h.state().quiz().run.as_ref().unwrap().feedback.clone().unwrap();
    assert!(right, "a click on the structure in its slice is right: {text}");
}
