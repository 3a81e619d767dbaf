//! The quiz of an exported page ([`vbrain::web_page::PageQuiz`]), for `vbrain export` and the
//! viewer's exports alike: a lesson's own questions, or questions drawn from a set. Each
//! question's view fades what hides its structure, as the viewer's quiz does; a headless render's
//! organ-ID buffer decides, so this needs a GPU adapter.
//!
//! - A question whose structure does not show in its view is left out, with a note naming it.
//! - Pass marks are per cent: the one given, else the lesson's, else
//!   [`vbrain::lesson::DEFAULT_PASS_MARK`].

use anyhow::{anyhow, bail, Result};
use vbrain::clip::Section;
use vbrain::layout::Layout;
use vbrain::lesson::{Lesson, StepView};
use vbrain::organ_set::OrganSet;
use vbrain::quiz::{self, Question};
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};
use vbrain::web_page::{camera, PageQuestion, PageQuiz, View};

/// A built quiz and what it had to say (questions left out, fewer questions than asked).
pub struct Built {
    pub quiz: PageQuiz,
    pub notes: Vec<String>,
}

/// The side of the square picture that decides what a question's view fades, in pixels.
const SCOUT: u32 = 256;

/// A lesson's quiz, or `None` where the lesson has none.
pub fn of_lesson(set: &OrganSet, lesson: &Lesson, pass_mark: Option<f32>) -> Result<Option<Built>> {
    if lesson.quiz.is_empty() {
        return Ok(None);
    }
    let questions = lesson.questions(set).map_err(|e| anyhow!(e))?;
    let views = (0..questions.len()).map(|k| lesson.question_view(k, set)).collect();
    build(set, questions, views, pass_mark.or(lesson.pass_mark)).map(Some)
}

/// `n` questions (locate and name in turn) over the organs the set shows, drawn with `seed`.
pub fn drawn(set: &OrganSet, n: usize, seed: u64, pass_mark: Option<f32>) -> Result<Built> {
    let scope = quiz::scope(set, None).map_err(|e| anyhow!(e))?;
    let spec = quiz::Spec { scope, questions: n, mode: quiz::Mode::Mixed, seed };
    let generated = quiz::generate(set, &spec).map_err(|e| anyhow!(e))?;
    let views = vec![None; generated.questions.len()];
    let mut built = build(set, generated.questions, views, pass_mark)?;
    built.notes.extend(generated.note);
    Ok(built)
}

/// The questions with their views: a step's layout, camera and cut where one is given, else the
/// default layout seen from the structure's side; what hides the structure faded.
fn build(
    set: &OrganSet,
    questions: Vec<Question>,
    views: Vec<Option<StepView>>,
    pass_mark: Option<f32>,
) -> Result<Built> {
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, set)?;
    let scout = Target::new(&gpu.device, SCOUT, SCOUT)?;
    let ids = |camera: &vbrain::camera::Camera, layout: &Layout| {
        let frame = FrameInput::new(set, camera, layout);
        renderer.render_ids(&gpu.device, &gpu.queue, &scout, &frame, crate::annotate::PICK_OPACITY);
        scout.read_ids(&gpu.device, &gpu.queue).unwrap_or_default()
    };
    let (mut asked, mut notes) = (Vec::new(), Vec::new());
    for (k, (q, from)) in questions.into_iter().zip(views).enumerate() {
        let (base, nav, section) = match from {
            Some(step) => (step.layout, step.navigator, step.section),
            None => {
                let (base, nav) = quiz::side_view(set, q.organ);
                (base, nav, Section::default())
            }
        };
        let cam = camera(set, &base, &nav);
        let (layout, _) = quiz::reveal(q.organ, &base, |l| ids(&cam, l));
        if !ids(&cam, &layout).contains(&(q.organ as u32 + 1)) {
            notes.push(format!("question {}: {} does not show in its view; left out", k + 1, set.organs[q.organ].name));
            continue;
        }
        let highlight = if q.kind == quiz::Kind::Name { vec![q.organ] } else { Vec::new() };
        let view = View {
            title: String::new(),
            caption: String::new(),
            camera: camera(set, &layout, &nav),
            layout,
            highlight,
            labels: Vec::new(),
            selection: None,
            section,
        };
        asked.push(PageQuestion { kind: q.kind, organ: q.organ, choices: q.choices, view });
    }
    if asked.is_empty() {
        bail!("no question of the quiz shows its structure");
    }
    let pass_mark = pass_mark.unwrap_or(vbrain::lesson::DEFAULT_PASS_MARK);
    Ok(Built { quiz: PageQuiz { questions: asked, pass_mark }, notes })
}
