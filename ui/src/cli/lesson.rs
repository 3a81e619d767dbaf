//! `vbrain lesson render`: a lesson's steps as pictures for slides and worksheets, one PNG per step
//! (`DIR/01.png`, ...) through the viewer's renderer, and `DIR/lesson.md` with each step's title,
//! caption and picture. Steps are drawn with their highlights, sections and labels.

use super::common::{database, open_set};
use super::LessonRenderArgs;
use crate::annotate::Labels;
use anyhow::{anyhow, Result};
use serde_json::json;
use vbrain::cull::{CullSettings, Culler};
use vbrain::labels::Which;
use vbrain::layout::Layout;
use vbrain::lesson::Lesson;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};

pub fn render(args: &LessonRenderArgs) -> Result<bool> {
    let lesson = Lesson::load(&args.lesson).map_err(|e| anyhow!(e))?;
    let set_path = lesson.set_path(&args.lesson);
    let set = open_set(&set_path)?;
    let unknown = lesson.unknown_names(&set);
    if !unknown.is_empty() {
        eprintln!("warning: {}: the set has no organ or group {}", args.lesson.display(), unknown.join(", "));
    }
    std::fs::create_dir_all(&args.out).map_err(|e| anyhow!("{}: {e}", args.out.display()))?;
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, &set)?;
    let target = Target::new(&gpu.device, args.size.width, args.size.height)?;
    let mut culler = Culler::new(database(&set_path, &set));
    let home = Layout::new(&set).bounds(&set);
    let mut markdown = format!("# {}\n", lesson.title);
    let mut files = Vec::new();
    for (k, step) in lesson.steps.iter().enumerate() {
        let view = step.view(&set);
        let camera = view.navigator.camera(&view.layout.bounds(&set).union(home));
        let section = &view.section;
        let clip = vbrain::cull::Clip::of(section, renderer.cuts_geometry());
        let settings = CullSettings::default();
        let (draw, _) = culler.cull_clipped(&set, &view.layout, &camera, target.aspect(), &settings, clip);
        let frame = FrameInput {
            draw: Some(&draw),
            background: crate::background_linear(crate::background_srgb(), false),
            highlight: &view.highlight,
            clip: &section.planes,
            caps: section.caps,
            whole: &section.whole,
            ..FrameInput::new(&set, &camera, &view.layout)
        };
        renderer.render(&gpu.device, &gpu.queue, &target, &frame)?;
        let mut image = target.read_color(&gpu.device, &gpu.queue)?;
        let labels = match &view.labels {
            // A step's "selected" organs are the ones it highlights.
            Some(Which::Selected) => Labels::Chosen(view.highlight.clone()),
            Some(which) => Labels::of(which, &set, None),
            None => Labels::None,
        };
        if labels != Labels::None {
            renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame, crate::annotate::PICK_OPACITY);
            let ids = target.read_ids(&gpu.device, &gpu.queue)?;
            crate::annotate::draw(&mut image, &ids, &labels, |o| set.organs[o].name.clone());
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
    if args.json {
        println!("{}", serde_json::to_string_pretty(&json!({"steps": files.len(), "files": files, "markdown": md}))?);
    } else {
        println!("{}: {} steps rendered into {}", lesson.title, files.len(), args.out.display());
    }
    Ok(true)
}
