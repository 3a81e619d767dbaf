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
    assert_eq!(lessons, 3);
}
