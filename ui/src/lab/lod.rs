//! `vbrain bench --lod`: level of detail (Callahan 2005, ch. 5, Fig. 5.6) over the bench's camera
//! path. Each frame is drawn as the viewer draws a moving frame (interactive sub-samples, culled):
//! at full detail, then by each strategy: `area` (each organ at the level its projected size calls
//! for), `level-1` and `level-2` (every organ at that level; both culling-aware, an organ keeping
//! its culled full mesh where that has fewer triangles), each of the viewer's smaller render
//! scales, and as the viewer chooses (`auto`: each frame's level and scale, and its sub-samples or
//! one weighted blended pass for faded organs, from the last one's time, as [`MotionQuality`]
//! decides in the viewer). Times are the render and the
//! wait for the GPU, not the read-back; errors are RMSE over 8-bit RGB against the full-size frame,
//! after scaling up with a bilinear filter as the viewer's texture does.
//! - Pixels: top left origin; the smaller images keep the view's aspect.

use crate::viewer::viewport::motion::{MotionQuality, SCALES};
use anyhow::{anyhow, Result};
use image::imageops::{resize, FilterType};
use image::RgbaImage;
use serde::Serialize;
use std::time::{Duration, Instant};
use vbrain::cull::{CullSettings, Culler};
use vbrain::layout::Layout;
use vbrain::organ_set::OrganSet;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};

/// What `bench --lod` runs.
pub struct LodOptions {
    pub frames: usize,
    pub size: (u32, u32),
    pub route: vbrain::lab::bench::Route,
    pub transparency: vbrain::transparency::TransparencySettings,
    pub section: vbrain::clip::Section,
    pub database: Option<vbrain::cull::database::Database>,
}

/// One way of drawing moving frames: its median time and its error against full size.
#[derive(Clone, Debug, Serialize)]
pub struct Strategy {
    pub strategy: String,
    pub moving_median_ms: f64,
    pub rmse: f64,
}

/// The run: full-size moving frames' median time, then each strategy.
#[derive(Clone, Debug, Serialize)]
pub struct LodReport {
    pub full_median_ms: f64,
    pub strategies: Vec<Strategy>,
}

/// RMSE of `a` against `b` (the same size) over their 8-bit RGB channels.
pub fn rmse(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let pairs = a.pixels().zip(b.pixels());
    let sum: f64 = pairs.map(|(p, q)| (0..3).map(|k| (f64::from(p[k]) - f64::from(q[k])).powi(2)).sum::<f64>()).sum();
    (sum / (3 * a.width() as usize * a.height() as usize).max(1) as f64).sqrt()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// Pixels a triangle should cover at least: finer detail than this is not seen.
pub const PIXELS_PER_TRIANGLE: f32 = 4.0;

/// Per organ of `set` drawn by `layout` through `camera` into `size` pixels, the level its
/// projected size calls for (area-based): the finest whose triangles each cover at least
/// [`PIXELS_PER_TRIANGLE`] pixels of the organ's projected bounds (its coarsest where none does);
/// 0 for organs without levels, hidden, or reaching behind the eye.
pub fn levels_by_area(set: &OrganSet, layout: &Layout, camera: &vbrain::camera::Camera, size: [u32; 2]) -> Vec<u8> {
    let view_projection = camera.view_projection(size[0] as f32 / size[1].max(1) as f32);
    let screen = (size[0] * size[1]) as f32;
    set.organs
        .iter()
        .zip(&layout.organs)
        .map(|(o, state)| {
            if o.lods().is_empty() || !state.is_drawn() {
                return 0;
            }
            let model = state.transform.matrix();
            let (mut lo, mut hi) = (glam::Vec2::splat(f32::MAX), glam::Vec2::splat(f32::MIN));
            for corner in o.bounds().corners() {
                let clip = view_projection * model.transform_point3(corner).extend(1.0);
                if clip.w <= 1e-6 {
                    return 0;
                }
                let ndc = glam::Vec2::new(clip.x, clip.y) / clip.w;
                (lo, hi) = (lo.min(ndc), hi.max(ndc));
            }
            let (lo, hi) = (lo.max(glam::Vec2::splat(-1.0)), hi.min(glam::Vec2::splat(1.0)));
            let share = ((hi.x - lo.x).max(0.0) * (hi.y - lo.y).max(0.0)) / 4.0;
            let most = share * screen / PIXELS_PER_TRIANGLE;
            let triangles = std::iter::once(o.mesh().triangle_count()).chain(o.lods().iter().map(|l| l.len() / 3));
            let fitting = triangles.enumerate().find(|&(_, t)| t as f32 <= most).map(|(k, _)| k);
            fitting.unwrap_or(o.lods().len()) as u8
        })
        .collect()
}

/// How a strategy coarsens a moving frame's organs.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Levels {
    /// Their full meshes.
    Full,
    /// Every organ at this level, where it has fewer triangles than culling keeps.
    Uniform(u8),
    /// Each organ at the level its projected size calls for ([`levels_by_area`]).
    Area,
}

/// Runs the comparison; `progress(done, total)` hears of every frame.
pub fn run(set: &OrganSet, layout: &Layout, opts: &LodOptions, progress: &mut dyn FnMut(usize)) -> Result<LodReport> {
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, set)?;
    let (w, h) = opts.size;
    let side = |v: u32, s: f32| ((v as f32 * s).round() as u32).max(1);
    let mut targets = Vec::new();
    for &s in &SCALES {
        targets.push(Target::new(&gpu.device, side(w, s), side(h, s))?);
    }
    let home = layout.bounds(set);
    let mut culler = Culler::new(opts.database.clone());
    let wait = || gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| anyhow!("waiting for the GPU: {e}"));
    // Draws frame `camera` into `target` with `transparency`, its organs as `levels` says: its
    // time, and the image at full size.
    let mut draw = |camera: &vbrain::camera::Camera,
                    target: &mut Target,
                    transparency: vbrain::transparency::TransparencySettings,
                    levels: Levels|
     -> Result<(f64, RgbaImage)> {
        let frame =
            FrameInput { transparency, moving: true, section: &opts.section, ..FrameInput::new(set, camera, layout) };
        let started = Instant::now();
        let (mut list, _) = culler.cull_frame(&renderer.cull_input(&frame, target), &CullSettings::default());
        match levels {
            Levels::Full => {}
            Levels::Uniform(k) => renderer.coarsen(&mut list, &vec![k; set.organs.len()]),
            Levels::Area => {
                renderer.coarsen(&mut list, &levels_by_area(set, layout, camera, [target.width, target.height]))
            }
        }
        renderer.render(&gpu.device, &gpu.queue, target, &FrameInput { draw: Some(&list), ..frame })?;
        wait()?;
        let ms = started.elapsed().as_secs_f64() * 1000.0;
        let image = target.read_color(&gpu.device, &gpu.queue)?;
        let image = if image.width() == w { image } else { resize(&image, w, h, FilterType::Triangle) };
        Ok((ms, image))
    };
    // The fixed strategies: (name, levels, index into SCALES).
    let mut fixed: Vec<(String, Levels, usize)> = vec![
        ("area".into(), Levels::Area, 0),
        ("level-1".into(), Levels::Uniform(1), 0),
        ("level-2".into(), Levels::Uniform(2), 0),
    ];
    fixed.extend(SCALES.iter().enumerate().skip(1).map(|(k, s)| (format!("scale-{:.0}", s * 100.0), Levels::Full, k)));
    let names: Vec<String> = fixed.iter().map(|f| f.0.clone()).chain(["auto".into()]).collect();
    let (mut full_ms, mut times, mut errors) =
        (Vec::new(), vec![Vec::new(); names.len()], vec![Vec::new(); names.len()]);
    let mut auto = MotionQuality::default();
    // As in the viewer, only frames whose faded organs screen-door draws tell how it fares.
    let faded = layout.organs.iter().any(|s| s.is_drawn() && !s.is_opaque());
    let screendoor_faded = faded && opts.transparency.mode.mask_method().is_some();
    for i in 0..opts.frames {
        let camera = opts.route.camera(&home, i, opts.frames);
        let (ms, full) = draw(&camera, &mut targets[0], opts.transparency, Levels::Full)?;
        // The first frame warms pipelines and caches: not counted.
        let counted = i > 0 || opts.frames == 1;
        for (k, (_, levels, scale)) in fixed.iter().enumerate() {
            let (ms, image) = draw(&camera, &mut targets[*scale], opts.transparency, *levels)?;
            if counted {
                times[k].push(ms);
                errors[k].push(rmse(&image, &full));
            }
        }
        // The viewer's choice: its level of detail and render scale, and its sub-samples (or one
        // weighted blended pass) for the faded organs, each from the frame before.
        let chosen = SCALES.iter().position(|&s| s == auto.scale()).unwrap_or(0);
        let levels = match auto.level() {
            0 => Levels::Full,
            k => Levels::Uniform(k),
        };
        let (auto_ms, image) = draw(&camera, &mut targets[chosen], auto.frame(opts.transparency, true), levels)?;
        let took = Duration::from_secs_f64(auto_ms / 1000.0);
        if screendoor_faded {
            let setting = opts.transparency.interactive_subsamples;
            auto.observe(setting, auto.moving(setting), took);
        }
        auto.observe_detail(took);
        if counted {
            full_ms.push(ms);
            times[names.len() - 1].push(auto_ms);
            errors[names.len() - 1].push(rmse(&image, &full));
        }
        progress(i + 1);
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let strategies = names
        .into_iter()
        .zip(times.into_iter().zip(&errors))
        .map(|(strategy, (t, e))| Strategy { strategy, moving_median_ms: median(t), rmse: mean(e) })
        .collect();
    Ok(LodReport { full_median_ms: median(full_ms), strategies })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rmse_is_zero_for_the_same_image_and_grows_with_the_difference() {
        let a = RgbaImage::from_pixel(4, 4, image::Rgba([10, 20, 30, 255]));
        let mut b = a.clone();
        assert_eq!(rmse(&a, &b), 0.0);
        b.put_pixel(0, 0, image::Rgba([10 + 48, 20, 30, 0]));
        // One channel of 48 (alpha is not counted) over 48 channel values: sqrt(48^2 / 48).
        assert!((rmse(&a, &b) - 48f64.sqrt()).abs() < 1e-9, "{}", rmse(&a, &b));
    }
}
