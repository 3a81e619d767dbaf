//! `vbrain lesson render`: a lesson's steps as pictures for slides and worksheets, one PNG per step
//! (`DIR/01.png`, ...) through the viewer's renderer, and `DIR/lesson.md` with each step's title,
//! caption and picture. Steps are drawn with their highlights, sections and labels (or `--labels`
//! for all); `--caption` puts the title and caption in a band below the figure.
//!
//! - Each step is framed, and its caption band cut, as [`crate::studio`] does it.

use super::common::{database, open_set};
use super::{LessonRenderArgs, Report};
use crate::studio::{caption_lines, StepFrame, Studio};
use anyhow::{anyhow, Result};
use serde_json::json;
use std::path::PathBuf;
use vbrain::labels::Which;
use vbrain::lesson::Lesson;

/// A lesson file or name opened with its set: the lesson, its file and the set's path.
pub fn open(name: &std::path::Path) -> Result<(Lesson, std::path::PathBuf, std::path::PathBuf)> {
    let file = vbrain::data_dir::lesson(name)?;
    let lesson = Lesson::load(&file).map_err(|e| anyhow!(e))?;
    let set_path = lesson.set_path(&file);
    Ok((lesson, file, set_path))
}

/// Warns of the names in `lesson` (from `file`) that `set` lacks.
pub fn warn_unknown(lesson: &Lesson, file: &std::path::Path, set: &vbrain::organ_set::OrganSet) {
    let unknown = lesson.unknown_names(set);
    if !unknown.is_empty() {
        eprintln!("warning: {}: the set has no organ or group {}", file.display(), unknown.join(", "));
    }
}

pub fn render(args: &LessonRenderArgs) -> Result<bool> {
    let forced = args.labels.as_deref().map(Which::parse);
    let (lesson, file, set_path) = open(&args.lesson)?;
    super::outputs::folder(&args.out, args.force, &[&file, &set_path])?;
    let set = open_set(&set_path)?;
    warn_unknown(&lesson, &file, &set);
    let mut studio = Studio::new(&set, database(&set_path, &set))?;
    let mut markdown = format!("# {}\n", lesson.title);
    let (mut files, mut labelled) = (Vec::new(), Vec::new());
    vbrain::atomic::write_folder(&args.out, |staging| {
        for (k, step) in lesson.steps.iter().enumerate() {
            let [w, h] = [args.size.width, args.size.height];
            let lines = args.caption.then(|| caption_lines(step, w, h));
            let (image, placed) =
                StepFrame::new(&mut studio, step, forced.as_ref(), [w, h], lines)?.draw(&mut studio, None)?;
            labelled.push(placed);
            let name = format!("{:02}.png", k + 1);
            vbrain::atomic::write_png(&staging.join(&name), &image, false)?;
            markdown.push_str(&format!(
                "\n## {}. {}\n\n![{}]({name})\n\n{}\n",
                k + 1,
                step.title,
                step.title,
                step.caption
            ));
            files.push(args.out.join(name));
        }
        vbrain::atomic::write_new(&staging.join("lesson.md"), |w| w.write_all(markdown.as_bytes()))?;
        anyhow::Ok(())
    })?;
    let md = args.out.join("lesson.md");
    if args.report.json {
        println!(
            "{}",
            serde_json::to_string_pretty(
                &json!({"steps": files.len(), "files": files, "labels": labelled, "markdown": md})
            )?
        );
    } else {
        println!("{}: {} steps rendered into {}", lesson.title, files.len(), args.out.display());
    }
    Ok(true)
}

/// `vbrain lesson pdf`: a handout of the lesson ([`crate::handout::of_lesson`]).
pub fn pdf(args: &LessonPdfArgs) -> Result<bool> {
    let forced = args.labels.as_deref().map(Which::parse);
    let (lesson, file, set_path) = open(&args.lesson)?;
    let out = super::outputs::file(&args.out, super::outputs::Kind::New("pdf"), args.force, &[&file])?;
    let set = open_set(&set_path)?;
    warn_unknown(&lesson, &file, &set);
    let mut studio = Studio::new(&set, database(&set_path, &set))?;
    let bar = super::common::progress_bar(lesson.steps.len() as u64);
    let handout = crate::handout::of_lesson(&mut studio, &lesson, forced.as_ref(), args.paper, &mut |done, _| {
        bar.set_position(done as u64);
        true
    })?;
    bar.finish_and_clear();
    let bytes = crate::handout::pdf(&handout, args.paper)?;
    out.write(|w| w.write_all(&bytes))?;
    if args.report.json {
        println!("{}", serde_json::to_string_pretty(&json!({"out": args.out, "pages": lesson.steps.len() + 1}))?);
    } else {
        println!("{}: {} pages written to {}", lesson.title, lesson.steps.len() + 1, args.out.display());
    }
    Ok(true)
}

/// `vbrain lesson pdf`'s options.
#[derive(clap::Args)]
pub struct LessonPdfArgs {
    /// Lesson file (.vblesson), or the name of one of the default brain's lessons (cortex,
    /// deep-nuclei, ventricles)
    pub lesson: PathBuf,
    /// The PDF file to write
    #[arg(long)]
    pub out: PathBuf,
    /// Replace --out if it exists
    #[arg(long)]
    pub force: bool,
    /// Paper size
    #[arg(long, value_enum, default_value = "a4")]
    pub paper: crate::handout::Paper,
    /// Labels in every figure instead of each step's own: none, selected, all or ids and groups
    /// separated by commas
    #[arg(long)]
    pub labels: Option<String>,
    #[command(flatten)]
    pub report: Report,
}
