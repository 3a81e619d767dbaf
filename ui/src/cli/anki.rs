//! `vbrain anki`: an Anki deck of a set's, a scene's or a lesson's structures ([`crate::anki`]),
//! with a progress bar.
//!
//! - In scope: a set's structures, those a scene shows, or those a lesson's steps highlight (and
//!   its quiz's questions); `--group` narrows them.
//! - Refuses an existing `--out` without `--force`, and an `--out` that is the input.

use super::common::{database, open_set};
use super::AnkiArgs;
use crate::anki::{self, DeckOptions};
use anyhow::{anyhow, bail, Result};
use std::time::Instant;
use vbrain::scene_file::SceneFile;

pub fn run(args: &AnkiArgs) -> Result<bool> {
    let input = args.set.clone().map_or_else(|| vbrain::data_dir::default_set().map_err(|e| anyhow!(e)), Ok)?;
    super::outputs::file(&args.out, super::outputs::Kind::New("apkg"), args.force, &[&input])?;
    let extension = input.extension().and_then(|e| e.to_str()).unwrap_or("");
    let is_lesson = extension == vbrain::lesson::EXTENSION || (!input.exists() && extension.is_empty());
    // The structures in scope: the set's, or those the scene shows, or those the lesson highlights.
    let (path, set, shown, lesson) = if is_lesson {
        let (lesson, file, path) = super::lesson::open(&input)?;
        let set = open_set(&path)?;
        super::lesson::warn_unknown(&lesson, &file, &set);
        let mut shown: Vec<usize> =
            lesson.steps.iter().flat_map(|s| s.highlight.iter().flat_map(|h| set.select(h))).collect();
        shown.sort_unstable();
        shown.dedup();
        (path, set, Some(shown), Some(lesson))
    } else if extension == vbrain::scene_file::EXTENSION {
        let scene = SceneFile::load(&input).map_err(|e| anyhow!(e))?;
        let path = scene.set_path(&input);
        let set = open_set(&path)?;
        let applied = scene.apply(&set);
        for w in &applied.warnings {
            eprintln!("warning: {}: {w}", input.display());
        }
        let shown = (0..set.organs.len()).filter(|&o| applied.layout.organs[o].is_drawn()).collect();
        (path, set, Some(shown), None)
    } else {
        let set = open_set(&input)?;
        (input.clone(), set, None, None)
    };
    let mut scope = match (&shown, args.group.as_deref()) {
        (None, group) => vbrain::quiz::scope(&set, group).map_err(|e| anyhow!(e))?,
        (Some(shown), None) => shown.clone(),
        (Some(shown), Some(group)) => {
            let in_group = set.select(group);
            if in_group.is_empty() {
                bail!("no organ or group \"{group}\" in the set (see `vbrain info`)");
            }
            shown.iter().copied().filter(|o| in_group.contains(o)).collect()
        }
    };
    scope.sort_unstable();
    let questions = match &lesson {
        Some(l) if !l.quiz.is_empty() => Some((l.title.clone(), anki::LessonQuestion::of(l, &set)?)),
        _ => None,
    };
    if scope.is_empty() && questions.is_none() {
        bail!("{}: no structure in scope (a lesson's steps highlight none, or the group has none)", input.display());
    }
    let opts = DeckOptions { scope, size: (args.size.width, args.size.height), views: args.views, lesson: questions };
    let started = Instant::now();
    let bar = indicatif::ProgressBar::new(opts.scope.len() as u64);
    let (bytes, report) =
        anki::build(&set, database(&path, &set), &opts, &mut |done, _| bar.set_position(done as u64))?;
    bar.finish_and_clear();
    anki::write(&args.out, &bytes, args.force)?;
    let seconds = started.elapsed().as_secs_f64();
    if args.report.json {
        let out = serde_json::json!({"deck": args.out, "report": report, "seconds": seconds});
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "{}: {} notes of {} structures, {} pictures ({seconds:.1} s)",
            args.out.display(),
            report.notes,
            report.structures - report.unseen.len(),
            report.media
        );
        if !report.unseen.is_empty() {
            eprintln!("not shown from any view, left out: {}", report.unseen.join(", "));
        }
    }
    Ok(true)
}
