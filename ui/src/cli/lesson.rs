//! `vbrain lesson render`: a lesson's steps as pictures for slides and worksheets, one PNG per step
//! (`DIR/01.png`, ...) through the viewer's renderer, and `DIR/lesson.md` with each step's title,
//! caption and picture. Steps are drawn with their highlights, sections and labels (or `--labels`
//! for all); `--caption` puts the title and caption in a band below the figure.
//!
//! - A step seen from its angles (no camera of its own) frames the brain whole and centred, with a
//!   margin and, where labels are drawn, room beside it for them ([`FILL`], [`FILL_LABELLED`]).

use super::common::{database, open_set};
use super::LessonRenderArgs;
use crate::annotate::Labels;
use anyhow::{anyhow, Result};
use serde_json::json;
use vbrain::cull::{CullSettings, Culler};
use vbrain::labels::Which;
use vbrain::layout::Layout;
use vbrain::lesson::{Lesson, Step};
use vbrain::navigation::Navigator;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};

/// The share of the half-width and half-height a step's brain fills ([`Navigator::fitting`]).
pub const FILL: [f32; 2] = [0.85, 0.85];
/// The same where labels are drawn: room for their columns beside the brain.
pub const FILL_LABELLED: [f32; 2] = [0.62, 0.85];
/// The most of a picture's height its caption band takes; longer captions end in "…".
const CAPTION_SHARE: f32 = 0.45;

pub fn render(args: &LessonRenderArgs) -> Result<bool> {
    let forced = args.labels.as_deref().map(Which::parse);
    let file = vbrain::data_dir::lesson(&args.lesson)?;
    let lesson = Lesson::load(&file).map_err(|e| anyhow!(e))?;
    let set_path = lesson.set_path(&file);
    let set = open_set(&set_path)?;
    let unknown = lesson.unknown_names(&set);
    if !unknown.is_empty() {
        eprintln!("warning: {}: the set has no organ or group {}", file.display(), unknown.join(", "));
    }
    std::fs::create_dir_all(&args.out).map_err(|e| anyhow!("{}: {e}", args.out.display()))?;
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, &set)?;
    let mut culler = Culler::new(database(&set_path, &set));
    let home = Layout::new(&set).bounds(&set);
    let mut markdown = format!("# {}\n", lesson.title);
    let (mut files, mut labelled) = (Vec::new(), Vec::new());
    let px = crate::annotate::text_px(args.size.height);
    for (k, step) in lesson.steps.iter().enumerate() {
        let view = step.view(&set);
        let which = forced.as_ref().or(view.labels.as_ref());
        let labels = match which {
            // A step's "selected" organs are the ones it highlights.
            Some(Which::Selected) => Labels::Chosen(view.highlight.clone()),
            Some(which) => Labels::of(which, &set, None),
            None => Labels::None,
        };
        let lines = if args.caption {
            caption_lines(step, args.size.width as f32 - 2.0 * px, px, args.size.height)
        } else {
            Vec::new()
        };
        let band = if args.caption { crate::annotate::caption_height(&lines, px) } else { 0 };
        let target = Target::new(&gpu.device, args.size.width, args.size.height.saturating_sub(band).max(1))?;
        let navigator = match step.camera {
            Some(_) => view.navigator,
            None => {
                let fill = if labels == Labels::None { FILL } else { FILL_LABELLED };
                let [az, el] = step.view;
                let fitted = Navigator::fitting(&home, az, el, target.aspect(), fill);
                Navigator { distance: fitted.distance * step.zoom, ..fitted }
            }
        };
        let camera = navigator.camera(&view.layout.bounds(&set).union(home));
        let frame = FrameInput {
            background: crate::background_linear(crate::background_srgb(), false),
            highlight: &view.highlight,
            section: &view.section,
            ..FrameInput::new(&set, &camera, &view.layout)
        };
        let (draw, _) = culler.cull_frame(&renderer.cull_input(&frame, &target), &CullSettings::default());
        let frame = FrameInput { draw: Some(&draw), ..frame };
        renderer.render(&gpu.device, &gpu.queue, &target, &frame)?;
        let mut image = target.read_color(&gpu.device, &gpu.queue)?;
        if labels != Labels::None {
            renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame, crate::annotate::PICK_OPACITY);
            let ids = target.read_ids(&gpu.device, &gpu.queue)?;
            let placed = crate::annotate::draw_sized(&mut image, &ids, &labels, |o| set.organs[o].name.clone(), px);
            labelled.push(placed.len());
        } else {
            labelled.push(0);
        }
        if args.caption {
            image = crate::annotate::caption(&image, &lines, px);
        }
        let name = format!("{:02}.png", k + 1);
        let file = args.out.join(&name);
        vbrain::atomic::write_png(&file, &image, true)?;
        markdown.push_str(&format!(
            "\n## {}. {}\n\n![{}]({name})\n\n{}\n",
            k + 1,
            step.title,
            step.title,
            step.caption
        ));
        files.push(file);
    }
    let md = args.out.join("lesson.md");
    vbrain::atomic::write(&md, |w| w.write_all(markdown.as_bytes())).map_err(|e| anyhow!(e))?;
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

/// A step's title and caption as the lines of its band, cut to [`CAPTION_SHARE`] of a picture
/// `height` pixels high (the last line kept ending in "…").
fn caption_lines(step: &Step, width: f32, px: f32, height: u32) -> Vec<(String, bool)> {
    let mut lines = crate::annotate::caption_lines(&step.title, &step.caption, width, px);
    let most = height as f32 * CAPTION_SHARE;
    let mut cut = false;
    while lines.len() > 1 && crate::annotate::caption_height(&lines, px) as f32 > most {
        lines.pop();
        cut = true;
    }
    if let (true, Some((last, _))) = (cut, lines.last_mut()) {
        last.push('\u{2026}');
    }
    lines
}
