//! `vbrain render`: one picture of a set through the viewer's renderer, written as PNG.
//!
//! - With `--scene`, of a saved scene (options given override it); with `--save-scene`, the
//!   scene it rendered written out.
//! - Standard views and orbits place the camera as the viewer's navigator does (and over the same
//!   bounds: what is drawn and the set's default layout), so a scene renders alike here and in
//!   the viewer.
//! - Never writes over a file that is not a PNG image (for `--save-scene`, not a vbrain scene)
//!   without `--force`.

use super::common::{apply_colour_by, apply_layout_args, database, open_set, organs, section};
use super::outputs::{self, Kind};
use super::values::ROUTE_FRAMES;
use super::RenderArgs;
use crate::annotate::Labels;
use anyhow::{anyhow, bail, Result};
use serde_json::json;
use std::path::{Path, PathBuf};
use vbrain::camera::View;
use vbrain::cull::{CullMode, CullSettings, Culler};
use vbrain::labels::Which;
use vbrain::layout::Layout;
use vbrain::navigation::Navigator;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};
use vbrain::rng::XorShift;
use vbrain::scene_file::{CameraMode, CameraState, RenderState, SceneFile};
use vbrain::transparency::TransparencySettings;

pub fn run(args: &RenderArgs) -> Result<bool> {
    let force = args.picture.force;
    let inputs: Vec<&Path> = args.path.iter().chain(&args.scene).map(PathBuf::as_path).collect();
    let picture = outputs::file(&args.picture.out, Kind::Png, force, &inputs)?;
    let saved = match &args.save_scene {
        Some(out) if out == &args.picture.out => {
            bail!("{}: is --out too; give --save-scene another file", out.display())
        }
        Some(out) => Some(outputs::file(out, Kind::Scene, force, &inputs)?),
        None => None,
    };
    let (width, height) = (args.picture.size.width, args.picture.size.height);
    let scene = match &args.scene {
        Some(p) => Some((p, SceneFile::load(p).map_err(|e| anyhow!(e))?)),
        None => None,
    };
    let path: PathBuf = match (&args.path, &scene) {
        (Some(p), _) => p.clone(),
        (None, Some((p, s))) => s.set_path(p),
        (None, None) => vbrain::data_dir::default_set()?,
    };
    let set = open_set(&path)?;
    let mut layout = Layout::new(&set);
    let mut selection = None;
    if let Some((p, s)) = &scene {
        let applied = s.apply(&set);
        for w in &applied.warnings {
            eprintln!("warning: {}: {w}", p.display());
        }
        (layout, selection) = (applied.layout, applied.selection);
    }
    apply_layout_args(&set, &mut layout, &args.layout)?;
    apply_colour_by(&set, &path, &mut layout, args.colour_by)?;
    let mut highlight = Vec::new();
    for key in &args.highlight {
        highlight.extend(organs(&set, key)?);
    }

    // The camera: the options' view or orbit, else the scene's, else the anterior view.
    let bounds = layout.bounds(&set).union(Layout::new(&set).bounds(&set));
    let c = &args.camera;
    let (camera, nav) = match c.route {
        // A bench route's camera is not a navigator: it cannot be saved in a scene.
        Some(r) => (r.route.camera(&layout.bounds(&set), r.frame, ROUTE_FRAMES), None),
        None => {
            let orbit = |angles| CameraState::of(&framing(&set, angles), CameraMode::Orbit);
            let nav = match (c.view, c.orbit, &scene) {
                (Some(view), ..) => orbit(view.angles()),
                (_, Some(o), _) => orbit((o.azimuth, o.elevation)),
                (None, None, Some((_, s))) => s.camera,
                (None, None, None) => orbit(View::Anterior.angles()),
            };
            (nav.navigator().camera(&bounds), Some(nav))
        }
    };

    // Render settings: the options given, else the scene's, else the defaults.
    let chosen = scene.as_ref().map(|(_, s)| s.render);
    let base = chosen.map_or_else(TransparencySettings::default, |r| r.transparency);
    let subsamples = args.subsamples.unwrap_or(base.subsamples);
    let transparency = TransparencySettings {
        mode: args.transparency.unwrap_or(base.mode),
        subsamples,
        // A render is a still frame; a scene it saves keeps the viewer's count while moving.
        interactive_subsamples: base.interactive_subsamples,
        region_px: args.region.unwrap_or(base.region_px),
        k: args.k.unwrap_or(base.k),
        peel_layers: args.layers.unwrap_or(base.peel_layers),
        kbuffer: args.kbuffer.unwrap_or(base.kbuffer),
    };
    let mode = args.cull.or(chosen.map(|r| r.cull)).unwrap_or(CullMode::Occlusion);
    let background_srgb = chosen.map_or_else(crate::background_srgb, |r| r.background);
    let background = if args.transparent { [0.0; 4] } else { crate::background_linear(background_srgb, false) };

    // Sections and labels: the options given, else the scene's.
    let from_scene = scene.as_ref().map(|(_, s)| s);
    let (section, saved_section) = section(&set, &args.section, from_scene)?;
    let which = Which::parse(args.labels.as_deref().or(from_scene.and_then(|s| s.labels.as_deref())).unwrap_or(""));

    // The scene is written once the picture is: a render that fails leaves no scene behind.
    let scene_out = match &args.save_scene {
        Some(out) => {
            let Some(nav) = nav else { bail!("--save-scene: a bench route's camera cannot be saved in a scene") };
            let render = RenderState { transparency, cull: mode, background: background_srgb };
            let mut file = SceneFile::capture(&set, &path, out, &layout, nav, render, selection);
            file.set_section(saved_section);
            file.labels = which.key();
            Some((out, file))
        }
        None => None,
    };

    let set_bounds = Layout::new(&set).bounds(&set);
    for p in &section.planes {
        if vbrain::clip::side(std::slice::from_ref(p), &set_bounds) != vbrain::clip::Side::Cut {
            let [x, y, z] = set_bounds.min.map(|v| v.round());
            let [a, b, c] = set_bounds.max.map(|v| v.round());
            bail!("--clip: the plane {:?}, {} lies outside the set ({x}..{a}, {y}..{b}, {z}..{c} mm)", p.normal, p.d);
        }
    }

    let started = std::time::Instant::now();
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, &set)?;
    let mut target = Target::new(&gpu.device, width, height)?;
    let settings = CullSettings { mode, ..Default::default() };
    let mut culler = Culler::new(database(&path, &set));
    let order = args.draw_order_seed.map(|seed| XorShift::permutation(set.organs.len(), seed));
    let input = FrameInput {
        background,
        transparency,
        draw_order: order.as_deref(),
        highlight: &highlight,
        selection,
        section: &section,
        time_gpu: args.report.json,
        ..FrameInput::new(&set, &camera, &layout)
    };
    let (mut draw, cull) = culler.cull_frame(&renderer.cull_input(&input, &target), &settings);
    renderer.coarsen(&mut draw, &vec![args.lod; set.organs.len()]);
    let input = FrameInput { draw: Some(&draw), ..input };
    let stats = if args.debug_culled {
        renderer.render_cull_debug(&gpu.device, &gpu.queue, &mut target, &input)?
    } else {
        renderer.render(&gpu.device, &gpu.queue, &mut target, &input)?
    };
    let mut image = target.read_color(&gpu.device, &gpu.queue)?;
    if let Which::Chosen(names) = &which {
        for key in names {
            organs(&set, key).map_err(|e| anyhow!("--labels: {e}"))?;
        }
    }
    let px = crate::annotate::text_px(height);
    crate::annotate::legend(&mut image, &vbrain::colouring::legend(&set, &layout), px * 0.8);
    let labels = Labels::of(&which, &set, selection);
    if labels != Labels::None {
        // Labels name what is seen, through faded organs as clicks reach through them.
        renderer.render_ids(&gpu.device, &gpu.queue, &target, &input, crate::annotate::PICK_OPACITY);
        let ids = target.read_ids(&gpu.device, &gpu.queue)?;
        crate::annotate::draw(&mut image, &ids, &labels, |o| set.organs[o].name.clone());
    }
    picture.write_png(&image)?;
    if let (Some((out, file)), Some(saved)) = (&scene_out, &saved) {
        let text = vbrain::json_file::to_json(file, out).map_err(|e| anyhow!(e))?;
        saved.write(|w| w.write_all(text.as_bytes()))?;
    }
    if args.report.json {
        let out = json!({
            "out": args.picture.out, "width": width, "height": height, "organs_drawn": stats.organs_drawn,
            "triangles_drawn": stats.triangles_drawn, "triangles": set.triangle_count(),
            "cull": mode.name(), "culled_percent": cull.culled_percent(), "cull_ms": cull.cull_ms,
            "transparency": transparency.mode.name(), "passes": stats.passes, "mask_ms": stats.mask_ms,
            "mask_configs": stats.mask_configs, "gpu_ms": stats.gpu_ms, "scene": args.save_scene,
            "adapter": gpu.adapter_description(), "seconds": started.elapsed().as_secs_f64(),
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "{}: {width}x{height}, {} organs, {} triangles drawn ({})",
            args.picture.out.display(),
            stats.organs_drawn,
            stats.triangles_drawn,
            gpu.adapter_description()
        );
    }
    Ok(true)
}

/// The navigator the viewer's standard views use: framing the set's default layout at these angles.
fn framing(set: &vbrain::organ_set::OrganSet, (azimuth, elevation): (f32, f32)) -> Navigator {
    Navigator::framing(&Layout::new(set).bounds(set), azimuth, elevation)
}
