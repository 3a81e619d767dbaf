//! `vbrain video`: a turntable of a set or scene, or a lesson played, as GIF, MP4 or WebM
//! ([`crate::video`]), with a progress bar.
//!
//! - A set turns from the anterior view framed as `vbrain render` frames it, a scene from its
//!   camera; both around the camera's target, elevation kept.

use super::common::{open_set, section};
use super::values::{self, Size};
use super::{Report, SectionArgs};
use crate::annotate::Labels;
use crate::studio::{StepFrame, Studio};
use crate::video::{Plan, Played, Turntable};
use anyhow::{anyhow, bail, Result};
use serde_json::json;
use std::path::{Path, PathBuf};
use vbrain::camera::View;
use vbrain::labels::Which;
use vbrain::layout::Layout;
use vbrain::navigation::Navigator;
use vbrain::scene_file::SceneFile;

pub fn run(args: &VideoArgs) -> Result<bool> {
    let format = crate::video::Format::of(&args.out)?;
    let input = args.path.clone().map_or_else(|| vbrain::data_dir::default_set().map_err(|e| anyhow!(e)), Ok)?;
    let extension = input.extension().and_then(|e| e.to_str()).unwrap_or("");
    let is_lesson = extension == vbrain::lesson::EXTENSION || (!input.exists() && extension.is_empty());
    let size = [args.size.width, args.size.height];
    let forced = args.labels.as_deref().map(Which::parse);

    let (set_path, lesson) = if is_lesson {
        let (lesson, file, set_path) = super::lesson::open(&input)?;
        (set_path, Some((lesson, file)))
    } else if extension == vbrain::scene_file::EXTENSION {
        (SceneFile::load(&input).map_err(|e| anyhow!(e))?.set_path(&input), None)
    } else {
        (input.clone(), None)
    };
    let set = open_set(&set_path)?;
    let mut studio = Studio::new(&set, super::common::database(&set_path, &set))?;
    let plan = match (&lesson, args.turntable) {
        (Some(_), Some(_)) => bail!("--turntable turns a set or a scene; a lesson is played step by step"),
        (None, None) => bail!("give --turntable DEGREES (and --seconds) to turn a set or a scene"),
        (Some((lesson, file)), None) => {
            super::lesson::warn_unknown(lesson, file, &set);
            let mut steps = Vec::new();
            for step in &lesson.steps {
                let lines = args.captions.then(|| crate::studio::caption_lines(step, size[0], size[1]));
                steps.push(StepFrame::new(&mut studio, step, forced.as_ref(), size, lines)?);
            }
            Plan::Lesson(Played { steps, hold: args.hold })
        }
        (None, Some(degrees)) => Plan::Turntable(turntable(&set, &input, extension, forced.as_ref(), degrees, args)?),
    };
    let frames = plan.check(size, args.fps, format)?;
    if args.render_only {
        let seconds = crate::video::render_only(&mut studio, &plan, size, args.fps, format)?;
        let report = json!({"frames": frames, "size": size, "render_s": seconds});
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(true);
    }
    super::outputs::file(&args.out, super::outputs::Kind::New("mp4, .webm or .gif"), args.force, &[&input])?;
    let bar = super::common::progress_bar(frames as u64);
    bar.set_message(format!("frames of {}", args.out.display()));
    let written = crate::video::write(&mut studio, &plan, size, args.fps, &args.out, args.force, &mut |done, _| {
        bar.set_position(done as u64);
        true
    })?;
    bar.finish_and_clear();
    let seconds = written.frames as f64 / args.fps as f64;
    if args.report.json {
        let report = json!({
            "out": args.out, "frames": written.frames, "fps": args.fps, "seconds": seconds,
            "size": size, "render_s": written.render_s, "total_s": written.total_s,
            "total_over_render": written.total_s / written.render_s.max(1e-9),
        });
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "wrote {} frames ({seconds:.1} s at {} fps) to {} in {:.1} s",
            written.frames,
            args.fps,
            args.out.display(),
            written.total_s
        );
    }
    Ok(true)
}

/// The turntable of a set (from the anterior view) or a scene (from its camera, layout, section
/// and labels).
fn turntable(
    set: &vbrain::organ_set::OrganSet,
    input: &Path,
    extension: &str,
    forced: Option<&Which>,
    degrees: f32,
    args: &VideoArgs,
) -> Result<Turntable> {
    let no_section = SectionArgs { clip: Vec::new(), caps: None, cut_face: None, window: None, whole: Vec::new() };
    let (layout, navigator, selection, scene) = if extension == vbrain::scene_file::EXTENSION {
        let scene = SceneFile::load(input).map_err(|e| anyhow!(e))?;
        let applied = scene.apply(set);
        for w in &applied.warnings {
            eprintln!("warning: {}: {w}", input.display());
        }
        (applied.layout, scene.camera.navigator(), applied.selection, Some(scene))
    } else {
        let (az, el) = View::Anterior.angles();
        (Layout::new(set), Navigator::framing(&Layout::new(set).bounds(set), az, el), None, None)
    };
    let (section, _) = section(set, &no_section, scene.as_ref())?;
    let which = forced.cloned().or_else(|| scene.as_ref().and_then(|s| s.labels.as_deref()).map(Which::parse));
    let labels = which.map_or(Labels::None, |w| Labels::of(&w, set, selection));
    Ok(Turntable {
        navigator,
        layout,
        highlight: selection.into_iter().collect(),
        section,
        labels,
        degrees,
        seconds: args.seconds,
    })
}

/// `vbrain video`'s options.
#[derive(clap::Args)]
pub struct VideoArgs {
    /// A scene (.vbscene), a lesson (.vblesson or the name of one of the default brain's lessons)
    /// or an organ set [default: the default brain]
    pub path: Option<PathBuf>,
    /// The video to write: .gif, .mp4 (H.264) or .webm (VP9); MP4 and WebM need ffmpeg
    #[arg(long)]
    pub out: PathBuf,
    /// Replace --out if it exists
    #[arg(long)]
    pub force: bool,
    /// Frame size, WxH (sides 16..=3840; even for MP4 and WebM)
    #[arg(long, default_value = "1280x720", value_parser = values::size)]
    pub size: Size,
    /// Frames a second, 1..=60 (at most 50 for a GIF)
    #[arg(long, default_value_t = 30, value_parser = clap::value_parser!(u32).range(1..=60))]
    pub fps: u32,
    /// Turn a set or scene this many degrees around the camera's target (toward the right when
    /// positive), elevation kept
    #[arg(long, allow_hyphen_values = true, value_parser = values::f32_in(-3600.0, 3600.0))]
    pub turntable: Option<f32>,
    /// The turntable's length in seconds, 0.1..=1200
    #[arg(long, default_value_t = 8.0, value_parser = values::f32_in(0.1, 1200.0))]
    pub seconds: f32,
    /// Seconds a lesson's step is held once it has arrived, 0.1..=600
    #[arg(long, default_value_t = 3.0, value_parser = values::f32_in(0.1, 600.0))]
    pub hold: f32,
    /// Burn each lesson step's title and caption into its frames, in a band below the figure
    #[arg(long)]
    pub captions: bool,
    /// Labels: none, selected, all or ids and groups separated by commas [default: a step's or
    /// scene's own]
    #[arg(long)]
    pub labels: Option<String>,
    /// Render the frames and write nothing; print the seconds it took as JSON (the baseline for
    /// the encoding benchmark)
    #[arg(long, hide = true)]
    pub render_only: bool,
    #[command(flatten)]
    pub report: Report,
}
