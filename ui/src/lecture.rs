//! The viewer's lecture exports, *File > Export video...* and *File > Export PDF handout...*: the
//! current view (turned around once, or as one labelled figure) or the open lesson, written as
//! `vbrain video` and `vbrain lesson pdf` write them.
//!
//! - Run off the UI thread; `progress(done, total)` returning false cancels, leaving no file.

use crate::annotate::Labels;
use crate::handout::{Handout, Paper, Sheet};
use crate::studio::{Shot, StepFrame, Studio};
use crate::video::{Plan, Played, Turntable};
use anyhow::{anyhow, Result};
use std::path::Path;
use vbrain::clip::Section;
use vbrain::layout::Layout;
use vbrain::lesson::Lesson;
use vbrain::navigation::Navigator;
use vbrain::organ_set::OrganSet;

/// A video's frame size and rate.
pub const VIDEO_SIZE: [u32; 2] = [1280, 720];
pub const VIDEO_FPS: u32 = 30;
/// A turntable's length, and how long each lesson step is held, in seconds.
pub const TURN_SECONDS: f32 = 8.0;
pub const HOLD_SECONDS: f32 = 3.0;

/// The viewer's current view.
pub struct View {
    pub navigator: Navigator,
    pub layout: Layout,
    pub highlight: Vec<usize>,
    pub section: Section,
    pub labels: Labels,
    pub selected: Option<usize>,
}

/// Writes a video of `lesson` played (captions burned in) or of `view` turned once around, to
/// the new file `path`; says what it wrote.
pub fn video(
    set: &OrganSet,
    lesson: Option<&Lesson>,
    view: &View,
    path: &Path,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<String> {
    let mut studio = Studio::new(set, None)?;
    let [w, h] = VIDEO_SIZE;
    let plan = match lesson {
        Some(lesson) => {
            let mut steps = Vec::new();
            for step in &lesson.steps {
                let lines = crate::studio::caption_lines(step, w, h);
                steps.push(StepFrame::new(&mut studio, step, None, VIDEO_SIZE, Some(lines))?);
            }
            Plan::Lesson(Played { steps, hold: HOLD_SECONDS })
        }
        None => Plan::Turntable(Turntable {
            navigator: view.navigator,
            layout: view.layout.clone(),
            highlight: view.highlight.clone(),
            section: view.section.clone(),
            labels: view.labels.clone(),
            degrees: 360.0,
            seconds: TURN_SECONDS,
        }),
    };
    let written = crate::video::write(&mut studio, &plan, VIDEO_SIZE, VIDEO_FPS, path, false, progress)?;
    Ok(format!(
        "saved {} ({} frames, {:.0} s)",
        path.display(),
        written.frames,
        written.frames as f32 / VIDEO_FPS as f32
    ))
}

/// Writes a PDF handout of `lesson`, or of `view` as one labelled figure with the selected
/// structure's text, to the new file `path`; says what it wrote.
pub fn handout(
    set: &OrganSet,
    lesson: Option<&Lesson>,
    view: &View,
    path: &Path,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<String> {
    let mut studio = Studio::new(set, None)?;
    let paper = Paper::A4;
    let handout = match lesson {
        Some(lesson) => crate::handout::of_lesson(&mut studio, lesson, None, paper, progress)?,
        None => {
            let [w, h] = crate::handout::figure_pixels(paper, 4.0 / 3.0);
            let shot = Shot {
                navigator: view.navigator,
                layout: &view.layout,
                highlight: &view.highlight,
                section: &view.section,
                labels: &view.labels,
                px: crate::annotate::text_px(h),
            };
            let (figure, _) = studio.shoot([w, h], &shot)?;
            let (heading, text) = match view.selected.and_then(|o| set.organs.get(o)) {
                Some(o) => (o.name.clone(), o.info.clone()),
                None => (set.title.clone(), String::new()),
            };
            let sheets = vec![Sheet { heading, figure: Some(figure), text }];
            Handout { title: set.title.clone(), subtitle: crate::handout::attribution(set), sheets }
        }
    };
    let bytes = crate::handout::pdf(&handout, paper)?;
    vbrain::atomic::write_new(path, |w| std::io::Write::write_all(w, &bytes)).map_err(|e| anyhow!(e))?;
    Ok(format!("saved {} ({} pages)", path.display(), handout.sheets.len() + 1))
}
