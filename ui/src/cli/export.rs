//! `vbrain export`: a set, a scene or a lesson as a binary glTF 2.0 file (`--gltf OUT.glb`) for
//! Blender, slides and web viewers ([`vbrain::gltf`]: the organs shown, with their names, colours,
//! opacities, transforms, groups and info texts, cut by the clip planes with solid cut faces), and
//! as a self-contained web page (`--web DIR`, [`vbrain::web_page`]); a lesson's glTF file is its
//! first step, its page every step. Cameras are framed as `vbrain render` frames them.
//!
//! - A page asks a quiz ([`crate::page_quiz`]): a lesson's own, or `--quiz N` questions drawn
//!   from a set with `--seed`.
//! - `--scorm OUT.zip` packages that page for a learning platform ([`vbrain::scorm`]).

use super::common::{apply_colour_by, apply_layout_args, open_set, section};
use super::outputs::{self, Kind};
use super::ExportArgs;
use anyhow::{anyhow, bail, Result};
use serde_json::json;
use std::path::Path;
use vbrain::camera::View as Standard;
use vbrain::clip::Section;
use vbrain::labels::Which;
use vbrain::layout::Layout;
use vbrain::lesson::Lesson;
use vbrain::organ_set::OrganSet;
use vbrain::scene_file::SceneFile;
use vbrain::web_page::{camera, labelled, Page, PageQuiz, View};

pub fn run(args: &ExportArgs) -> Result<bool> {
    let path = vbrain::data_dir::set_or_default(args.path.as_deref())?;
    let (source, set_path) = open_source(&path)?;
    let inputs = [path.as_path(), set_path.as_path()];
    let gltf = args.gltf.as_ref().map(|o| outputs::file(o, Kind::New("glb"), args.force, &inputs)).transpose()?;
    let scorm = args.scorm.as_ref().map(|o| outputs::file(o, Kind::New("zip"), args.force, &inputs)).transpose()?;
    if let Some(dir) = &args.web {
        outputs::folder(dir, args.force, &inputs)?;
    }
    let files: Vec<&Path> = [&args.gltf, &args.scorm].into_iter().flatten().map(|p| p.as_path()).collect();
    outputs::apart(&files, &args.web.iter().map(|p| p.as_path()).collect::<Vec<_>>())?;
    let set = open_set(&set_path)?;
    let (mut page, lesson) = match source {
        Source::Set => (scene_page(&set, None, &path, args)?, None),
        Source::Scene(scene) => (scene_page(&set, Some(&scene), &path, args)?, None),
        Source::Lesson(lesson) => (lesson_page(&set, &lesson, &path, args)?, Some(lesson)),
    };
    page.quiz = page_quiz(&set, lesson.as_ref(), &path, args)?;
    if args.scorm.is_some() && page.quiz.is_none() {
        bail!("{}: has no quiz to grade; --scorm needs a lesson with a quiz, or --quiz N", path.display());
    }
    let mut summary = json!({});
    if let Some(out) = &gltf {
        // A lesson's file is its first step; a scene's or set's is what the page shows.
        let (layout, section) = match page.lesson {
            true => (&page.views[0].layout, &page.views[0].section),
            false => (&page.layout, &page.section),
        };
        let glb = vbrain::gltf::glb(&set, layout, section, vbrain::gltf::Encoding::Float);
        out.write(|w| w.write_all(&glb.bytes))?;
        let out = out.path();
        if !args.report.json {
            println!("wrote {} ({} organs, {:.1} MB)", out.display(), glb.organs, glb.bytes.len() as f64 / 1e6);
        }
        summary["gltf"] = json!({"out": out, "bytes": glb.bytes.len(), "organs": glb.organs});
    }
    if let Some(dir) = &args.web {
        let bytes = vbrain::web_page::write(dir, &page).map_err(|e| anyhow!(e))?;
        let steps = if page.lesson { format!("{} steps, ", page.views.len()) } else { String::new() };
        if !args.report.json {
            println!("wrote {} ({steps}{:.1} MB in all)", dir.join("index.html").display(), bytes as f64 / 1e6);
        }
        summary["web"] = json!({"out": dir, "bytes": bytes, "steps": page.views.len()});
    }
    if let Some(out) = &scorm {
        let package = vbrain::scorm::package(&page).map_err(|e| anyhow!("{}: {e}", out.path().display()))?;
        out.write(|w| w.write_all(&package))?;
        let (out, bytes) = (out.path(), package.len());
        let quiz = page.quiz.as_ref().map(|q| (q.questions.len(), q.pass_mark)).unwrap_or_default();
        if !args.report.json {
            println!(
                "wrote {} (SCORM 1.2, {} questions, pass mark {} %, {:.1} MB)",
                out.display(),
                quiz.0,
                quiz.1,
                bytes as f64 / 1e6
            );
        }
        summary["scorm"] = json!({"out": out, "bytes": bytes, "questions": quiz.0, "pass_mark": quiz.1});
    }
    if args.report.json {
        println!("{summary}");
    }
    Ok(true)
}

/// The page's quiz: a lesson's own (none where it has none), or `--quiz N` questions drawn from
/// the set's shown organs.
fn page_quiz(set: &OrganSet, lesson: Option<&Lesson>, path: &Path, args: &ExportArgs) -> Result<Option<PageQuiz>> {
    let built = match (lesson, args.quiz) {
        (Some(_), Some(_)) => bail!("{}: a lesson asks its own quiz; --quiz is for sets and scenes", path.display()),
        (Some(l), None) => {
            crate::page_quiz::of_lesson(set, l, args.pass_mark).map_err(|e| anyhow!("{}: {e:#}", path.display()))?
        }
        (None, Some(n)) => Some(crate::page_quiz::drawn(set, n, args.seed, args.pass_mark)?),
        (None, None) => None,
    };
    let Some(built) = built else { return Ok(None) };
    for note in &built.notes {
        eprintln!("note: {}: {note}", path.display());
    }
    Ok(Some(built.quiz))
}

/// What `vbrain export` was given.
enum Source {
    Set,
    Scene(SceneFile),
    Lesson(Lesson),
}

/// The file `path` names, and its set's path: a scene's or a lesson's set (which must be there),
/// else the path itself.
fn open_source(path: &Path) -> Result<(Source, std::path::PathBuf)> {
    let extension = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let (source, set) = if extension == vbrain::scene_file::EXTENSION {
        let scene = SceneFile::load(path).map_err(|e| anyhow!(e))?;
        let set = scene.set_path(path);
        (Source::Scene(scene), set)
    } else if extension == vbrain::lesson::EXTENSION {
        let lesson = Lesson::load(path).map_err(|e| anyhow!(e))?;
        let set = lesson.set_path(path);
        (Source::Lesson(lesson), set)
    } else {
        return Ok((Source::Set, path.to_path_buf()));
    };
    if !set.exists() {
        bail!("{}: its organ set {} is not there", path.display(), set.display());
    }
    Ok((source, set))
}

/// A set or a scene (with the options' changes) as one view, its cut in the model.
fn scene_page<'a>(set: &'a OrganSet, scene: Option<&SceneFile>, path: &Path, args: &ExportArgs) -> Result<Page<'a>> {
    let (mut layout, mut selection) = (Layout::new(set), None);
    if let Some(s) = scene {
        let applied = s.apply(set);
        for w in &applied.warnings {
            eprintln!("warning: {}: {w}", path.display());
        }
        (layout, selection) = (applied.layout, applied.selection);
    }
    apply_layout_args(set, &mut layout, &args.layout)?;
    apply_colour_by(set, path, &mut layout, args.colour_by)?;
    let (section, _) = section(set, &args.section, scene)?;
    let nav = match scene {
        Some(s) => s.camera.navigator(),
        None => {
            let (azimuth, elevation) = Standard::Anterior.angles();
            vbrain::navigation::Navigator::framing(&Layout::new(set).bounds(set), azimuth, elevation)
        }
    };
    let which = Which::parse(scene.and_then(|s| s.labels.as_deref()).unwrap_or(""));
    let view = View {
        title: set.title.clone(),
        caption: String::new(),
        labels: labelled(set, &layout, &which, selection),
        camera: camera(set, &layout, &nav),
        layout: layout.clone(),
        highlight: Vec::new(),
        selection,
        section: Section::default(),
    };
    Ok(Page { set, title: set.title.clone(), layout, section, views: vec![view], lesson: false, quiz: None })
}

/// A lesson: every organ in the model, uncut; each step shows, fades, colours, places and cuts
/// them (without cut faces) in the page.
fn lesson_page<'a>(set: &'a OrganSet, lesson: &Lesson, path: &Path, args: &ExportArgs) -> Result<Page<'a>> {
    let (l, c) = (&args.layout, &args.section);
    let changes = !(l.show.is_empty() && l.hide.is_empty() && l.opacity.is_empty() && args.colour_by.is_none());
    if changes || !c.clip.is_empty() || c.caps.is_some() || !c.whole.is_empty() {
        bail!("{}: a lesson's steps set the organs and planes; --show, --hide, --opacity, --colour-by, --clip, --caps and --whole are for sets and scenes", path.display());
    }
    for name in lesson.unknown_names(set) {
        eprintln!("warning: {}: the set has no organ or group \"{name}\"; left out", path.display());
    }
    Ok(Page::lesson(set, lesson))
}
