//! `vbrain render`: one picture of a set through the viewer's renderer, written as PNG.

use super::common::{database, layout, open_reporting};
use super::values::ROUTE_FRAMES;
use super::RenderArgs;
use anyhow::Result;
use serde_json::json;
use vbrain::camera::{Camera, View};
use vbrain::cull::{CullSettings, Culler};
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};
use vbrain::rng::XorShift;
use vbrain::transparency::TransparencySettings;

pub fn run(args: &RenderArgs) -> Result<bool> {
    let (width, height) = (args.size.width, args.size.height);
    let (set, ok) = open_reporting(&args.path)?;
    let layout = layout(&set, &args.layout)?;
    let bounds = layout.bounds(&set);
    let c = &args.camera;
    let camera = match (c.view, c.orbit, c.route) {
        (Some(view), _, _) => Camera::view(&bounds, view),
        (_, Some(o), _) => Camera::orbit(&bounds, o.azimuth, o.elevation),
        (_, _, Some(r)) => r.route.camera(&bounds, r.frame, ROUTE_FRAMES),
        (None, None, None) => Camera::view(&bounds, View::Anterior),
    };
    let started = std::time::Instant::now();
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, &set)?;
    let target = Target::new(&gpu.device, width, height)?;
    let background = if args.transparent { [0.0; 4] } else { crate::BACKGROUND };
    let mode = args.cull;
    let settings = CullSettings { mode, ..Default::default() };
    let (draw, cull) = Culler::new(database(&args.path, &set)).cull(&set, &layout, &camera, target.aspect(), &settings);
    let transparency = TransparencySettings {
        mode: args.transparency,
        subsamples: args.subsamples,
        interactive_subsamples: args.subsamples,
        region_px: args.region,
        k: args.k,
    };
    let order = args.draw_order_seed.map(|seed| XorShift::permutation(set.organs.len(), seed));
    let input = FrameInput {
        draw: Some(&draw),
        background,
        transparency,
        draw_order: order.as_deref(),
        ..FrameInput::new(&set, &camera, &layout)
    };
    let stats = if args.debug_culled {
        renderer.render_cull_debug(&gpu.device, &gpu.queue, &target, &input)?
    } else {
        renderer.render(&gpu.device, &gpu.queue, &target, &input)?
    };
    let image = target.read_color(&gpu.device, &gpu.queue)?;
    vbrain::atomic::write_png(&args.out, &image, true)?;
    if args.json {
        let out = json!({
            "out": args.out, "width": width, "height": height, "organs_drawn": stats.organs_drawn,
            "triangles_drawn": stats.triangles_drawn, "triangles": set.triangle_count(),
            "cull": mode.name(), "culled_percent": cull.culled_percent(), "cull_ms": cull.cull_ms,
            "transparency": transparency.mode.name(), "passes": stats.passes, "mask_ms": stats.mask_ms,
            "mask_configs": stats.mask_configs,
            "adapter": gpu.adapter_description(), "seconds": started.elapsed().as_secs_f64(),
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "{}: {width}x{height}, {} organs, {} triangles drawn ({})",
            args.out.display(),
            stats.organs_drawn,
            stats.triangles_drawn,
            gpu.adapter_description()
        );
    }
    Ok(ok)
}
