//! Quizzes on the default brain: every structure a quiz may ask about, deep ones included, is
//! visible from the question's camera once the organs hiding it are faded.

use crate::common::{default_set, gpu};
use vbrain::layout::Layout;
use vbrain::quiz;
use vbrain::render::{FrameInput, Renderer, Target};

#[test]
fn every_target_shows_from_its_questions_camera() {
    let (set, gpu) = (default_set(), gpu());
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let target = Target::new(&gpu.device, 192, 144).unwrap();
    let base = Layout::new(set);
    let home = base.bounds(set);
    let scope = quiz::scope(set, None).unwrap();
    let mut hidden = 0;
    for &organ in &scope {
        let camera = quiz::camera(set, &base, organ).camera(&home);
        let ids = |l: &Layout| {
            renderer.render_ids(&gpu.device, &gpu.queue, &target, &FrameInput::new(set, &camera, l), 0.5);
            target.read_ids(&gpu.device, &gpu.queue).unwrap()
        };
        let before = ids(&base).iter().filter(|&&i| i as usize == organ + 1).count();
        let (layout, share) = quiz::reveal(organ, &base, ids);
        let seen = ids(&layout).iter().filter(|&&i| i as usize == organ + 1).count();
        hidden += usize::from(before == 0);
        assert!(share >= 0.05 && seen > 0, "{}: {:.0} % of it seen", set.organs[organ].id, share * 100.0);
    }
    assert!(hidden > 5, "deep structures are among them ({hidden} hidden before fading)");
}

#[test]
fn every_shipped_lesson_has_a_quiz_over_real_organs() {
    let set = default_set();
    let dir = crate::common::brain_dir().join("lessons");
    let mut lessons = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let lesson = vbrain::lesson::Lesson::load(&path).unwrap();
        let questions = lesson.questions(set).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(questions.len() >= 4, "{}", path.display());
        assert!(questions.iter().all(|q| q.choices.len() == quiz::CHOICES && q.choices.contains(&q.organ)));
        lessons += 1;
    }
    assert_eq!(lessons, 5);
}

/// An MRI quiz over every structure: seeded, each question on a slice through its structure where
/// the structure shows (so it is outlined and can be clicked), one right answer among distinct
/// choices.
#[test]
fn an_mri_quiz_asks_every_structure_on_a_slice_that_shows_it() {
    use vbrain::mri::slice::{organ_ids, Pane};
    let set = default_set();
    let scope = quiz::scope(set, None).unwrap();
    let spec = quiz::Spec { scope: scope.clone(), questions: scope.len(), mode: quiz::Mode::Mri, seed: 11 };
    let q = quiz::generate(set, &spec).unwrap();
    assert_eq!(q, quiz::generate(set, &spec).unwrap(), "the same seed asks the same quiz");
    assert_ne!(q, quiz::generate(set, &quiz::Spec { seed: 12, ..spec.clone() }).unwrap());
    assert!(q.questions.len() * 10 >= scope.len() * 9, "{} of {} structures asked", q.questions.len(), scope.len());
    let shown: Vec<usize> = (0..set.organs.len()).filter(|&o| set.organs[o].visible).collect();
    let home = shown.iter().fold(vbrain::mesh::Bounds::EMPTY, |b, &o| b.union(set.organs[o].mesh().bounds()));
    let mut kinds = [0, 0];
    for question in &q.questions {
        let plane = question.slice.expect("an MRI question has its slice");
        let ids = organ_ids(set, &shown, &Pane::fit(plane, &home, 160, 160, true));
        let own = ids.iter().filter(|&&id| id as usize == question.organ + 1).count();
        assert!(own >= quiz::SLICE_PIXELS, "{} shows {own} pixels on its slice", set.organs[question.organ].id);
        let right = question.choices.iter().filter(|&&c| c == question.organ).count();
        let mut distinct = question.choices.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert!(right == 1 && distinct.len() == question.choices.len(), "{:?}", question);
        kinds[usize::from(question.kind == quiz::Kind::Name)] += 1;
    }
    assert!(kinds[0] > 0 && kinds[1] > 0, "locate and name by turns: {kinds:?}");
}
