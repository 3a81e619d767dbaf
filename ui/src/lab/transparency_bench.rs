//! Behind `vbrain bench-transparency`: every transparency mode against the exact reference on
//! views of the set with 1 to 99 transparent organs, all in one run.
//!
//! - Per mode: mean absolute and 99th-percentile per-pixel error (8-bit sRGB units, the largest
//!   of the three channels), frame time and, where the adapter has timestamp queries, GPU time.
//! - Per view: the same view with nothing faded (`opaque_frame_ms`, the base of the cost ratios),
//!   screen-door's frame while moving (its interactive sub-samples; the viewer's cheapest moving
//!   frame is the weighted blended one), and an error-against-time curve (screen-door at 4..64
//!   sub-samples, the peeling modes at 1..8 layers).
//! - Writes a CSV, a PNG plot and a contact sheet (one row per view, one column per mode in the
//!   order printed).
//! - Also times mask regeneration at 1920x1080 with every organ at 50 % opacity, and per view
//!   counts the k-buffer slots each pixel needs ([`super::k_analysis`]).

use anyhow::{bail, Result};
use serde_json::json;
use std::path::Path;
use std::time::Instant;
use vbrain::camera::Camera;
use vbrain::layout::Layout;
use vbrain::organ_set::OrganSet;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};
use vbrain::transparency::{regions, TransparencyMode, TransparencySettings, SUBSAMPLE_CHOICES};

/// A bench view: organs made transparent (the rest of `opaque` drawn opaque, all others hidden,
/// unless `opaque` is [`WITH_THE_REST`]), and the orbit angles. An empty `transparent` list means
/// every organ shown by default.
struct ViewSpec {
    name: &'static str,
    transparent: &'static [&'static str],
    opaque: &'static [&'static str],
    orbit: (f32, f32),
    /// Camera distance relative to the fitted one.
    distance: f32,
    /// The transparent organs' opacity; `None` draws each in 0.2..0.8 from a fixed seed.
    opacity: Option<f32>,
}

/// `opaque` of a view that shows every organ shown by default, opaque but for `transparent`.
const WITH_THE_REST: &[&str] = &["*"];

const VIEWS: [ViewSpec; 6] = [
    ViewSpec {
        name: "one faded gyrus",
        transparent: &["superiorfrontal_l"],
        opaque: WITH_THE_REST,
        orbit: (-30.0, 20.0),
        distance: 1.0,
        opacity: Some(0.4),
    },
    ViewSpec {
        name: "left deep nuclei",
        transparent: &["caudate_l", "putamen_l", "pallidum_l", "thalamus_l"],
        opaque: &["hippocampus_l", "amygdala_l"],
        orbit: (-70.0, 10.0),
        distance: 1.0,
        opacity: None,
    },
    ViewSpec {
        name: "basal ganglia, ventricles, hippocampi",
        transparent: &[
            "caudate_l",
            "putamen_l",
            "pallidum_l",
            "thalamus_l",
            "lateral_ventricle_l",
            "hippocampus_l",
            "caudate_r",
            "putamen_r",
            "pallidum_r",
            "thalamus_r",
            "lateral_ventricle_r",
            "hippocampus_r",
        ],
        opaque: &["Brainstem"],
        orbit: (30.0, 20.0),
        distance: 0.6,
        opacity: None,
    },
    ViewSpec {
        name: "left hemisphere",
        transparent: &[
            "Left hemisphere",
            "lateral_ventricle_l",
            "Basal ganglia/Left",
            "Diencephalon/Left",
            "Limbic system/Left",
            "Cerebellum/Left",
        ],
        opaque: &["Brainstem"],
        orbit: (-90.0, 5.0),
        distance: 1.0,
        opacity: None,
    },
    ViewSpec { name: "whole brain", transparent: &[], opaque: &[], orbit: (35.0, 15.0), distance: 0.75, opacity: None },
    ViewSpec {
        name: "whole brain at 50 %",
        transparent: &[],
        opaque: &[],
        orbit: (35.0, 15.0),
        distance: 0.75,
        opacity: Some(0.5),
    },
];

/// The modes compared with the exact reference: all the others.
pub fn modes() -> impl Iterator<Item = TransparencyMode> + Clone {
    TransparencyMode::ALL.into_iter().filter(|&m| m != TransparencyMode::Exact)
}

/// Modes of the error-against-time curve, and the most layers the peeling modes get in it.
const CURVE_MODES: [TransparencyMode; 3] =
    [TransparencyMode::Screendoor, TransparencyMode::Peel, TransparencyMode::DualPeel];
const CURVE_LAYERS: usize = 8;

struct Row {
    view: String,
    transparent: usize,
    mode: TransparencyMode,
    mae: f64,
    p99: f64,
    frame_ms: f64,
    /// Median GPU time of the timed frames, where the adapter has timestamp queries.
    gpu_ms: Option<f64>,
    passes: usize,
}

/// One shot of a view: its image, median wall-clock and GPU times, and passes.
struct Shot {
    image: image::RgbaImage,
    frame_ms: f64,
    gpu_ms: Option<f64>,
    passes: usize,
}

/// A point of the error-against-time curve: sub-samples (screen-door) or layers (peeling).
struct CurvePoint {
    mode: TransparencyMode,
    setting: usize,
    mae: f64,
    frame_ms: f64,
}

/// Against each peeling mode at its most layers: the cheapest screen-door point of `curve` with no
/// more error, and its frame time over the peeling frame's (the target, with every organ at 50 %:
/// at most 0.5 against dual peeling). Null where no screen-door point gets there.
fn at_equal_error(curve: &[CurvePoint]) -> serde_json::Value {
    let peeled = CURVE_MODES.iter().filter(|&&m| m != TransparencyMode::Screendoor).filter_map(|&m| {
        let deepest = curve.iter().filter(|p| p.mode == m).max_by_key(|p| p.setting)?;
        let cheapest = curve
            .iter()
            .filter(|p| p.mode == TransparencyMode::Screendoor && p.mae <= deepest.mae)
            .min_by(|a, b| a.frame_ms.total_cmp(&b.frame_ms));
        let figures = cheapest.map(|sd| {
            json!({"layers": deepest.setting, "mean_abs_error": deepest.mae, "frame_ms": deepest.frame_ms,
                "screendoor_subsamples": sd.setting, "screendoor_mean_abs_error": sd.mae,
                "screendoor_frame_ms": sd.frame_ms, "time_ratio": sd.frame_ms / deepest.frame_ms})
        });
        Some((m.name().to_string(), figures.unwrap_or(serde_json::Value::Null)))
    });
    serde_json::Value::Object(peeled.collect())
}

/// A view's weighted blended frame: what the viewer draws while moving where one screen-door pass
/// is too slow (`viewer::viewport::motion`).
fn blended_ms(rows: &[Row], view: &str) -> f64 {
    rows.iter().find(|r| r.view == view && r.mode == TransparencyMode::WeightedBlended).map_or(f64::NAN, |r| r.frame_ms)
}

/// One view's figures besides the rows.
struct ViewFigures {
    opaque_frame_ms: f64,
    opaque_gpu_ms: Option<f64>,
    moving_frame_ms: f64,
    curve: Vec<CurvePoint>,
}

/// The layout of a view; opacities as the spec says.
fn view_layout(set: &OrganSet, spec: &ViewSpec, seed: u64) -> Result<(Layout, usize)> {
    let mut layout = Layout::new(set);
    let mut rng = vbrain::rng::XorShift::seeded(seed);
    let select = |keys: &[&str]| -> Result<Vec<usize>> {
        let mut found = Vec::new();
        for key in keys {
            let organs = set.select(key);
            if organs.is_empty() {
                bail!("the set has no organ or group \"{key}\" for view \"{}\"", spec.name);
            }
            found.extend(organs);
        }
        Ok(found)
    };
    let chosen: Vec<usize> = if spec.transparent.is_empty() {
        (0..set.organs.len()).filter(|&i| layout.organs[i].visible).collect()
    } else {
        if !std::ptr::eq(spec.opaque, WITH_THE_REST) {
            layout.organs.iter_mut().for_each(|s| s.visible = false);
            for i in select(spec.opaque)? {
                layout.organs[i].visible = true;
            }
        }
        let chosen = select(spec.transparent)?;
        for &i in &chosen {
            layout.organs[i].visible = true;
        }
        chosen
    };
    for &i in &chosen {
        layout.organs[i].opacity = spec.opacity.unwrap_or_else(|| 0.2 + 0.6 * rng.unit());
    }
    Ok((layout, chosen.len()))
}

/// Mean and 99th percentile of the per-pixel error (largest channel difference, 8-bit units).
fn errors(image: &image::RgbaImage, exact: &image::RgbaImage) -> (f64, f64) {
    let mut e: Vec<u8> = image
        .pixels()
        .zip(exact.pixels())
        .map(|(a, b)| (0..3).map(|k| a[k].abs_diff(b[k])).max().unwrap_or(0))
        .collect();
    let mean = e.iter().map(|&v| f64::from(v)).sum::<f64>() / e.len().max(1) as f64;
    e.sort_unstable();
    let p99 = e.get((e.len() * 99 / 100).min(e.len().saturating_sub(1))).copied().unwrap_or(0);
    (mean, f64::from(p99))
}

/// Renders views for the bench: each frame drawn once to warm up, then timed [`TIMED`] times with
/// the queue finished (the read-back waits for it); the median counts.
const TIMED: usize = 3;

struct Shooter<'a> {
    gpu: &'a GpuContext,
    renderer: &'a Renderer,
    target: Target,
    set: &'a OrganSet,
    region_px: u32,
}

impl Shooter<'_> {
    fn shot(
        &mut self,
        camera: &Camera,
        layout: &Layout,
        transparency: TransparencySettings,
        moving: bool,
    ) -> Result<Shot> {
        let transparency = TransparencySettings { region_px: self.region_px, ..transparency };
        let frame = FrameInput {
            background: crate::BACKGROUND,
            transparency,
            moving,
            ..FrameInput::new(self.set, camera, layout)
        };
        let timed = FrameInput { time_gpu: true, ..frame };
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let mut stats = self.renderer.render(device, queue, &mut self.target, &frame)?;
        let mut image = self.target.read_color(device, queue)?;
        // The reference is not timed (slow by design).
        let runs = if transparency.mode == TransparencyMode::Exact { 0 } else { TIMED };
        let (mut times, mut gpu_times) = (Vec::with_capacity(runs), Vec::with_capacity(runs));
        for _ in 0..runs {
            // Reading the GPU time waits for the frame, as reading its image does anyway.
            let started = Instant::now();
            stats = self.renderer.render(device, queue, &mut self.target, &timed)?;
            image = self.target.read_color(device, queue)?;
            times.push(started.elapsed().as_secs_f64() * 1000.0);
            gpu_times.extend(stats.gpu_ms);
        }
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied()
        };
        Ok(Shot { image, frame_ms: median(times).unwrap_or(0.0), gpu_ms: median(gpu_times), passes: stats.passes })
    }

    fn mode(&mut self, camera: &Camera, layout: &Layout, mode: TransparencyMode) -> Result<Shot> {
        self.shot(camera, layout, TransparencySettings { mode, ..Default::default() }, false)
    }
}

/// The error-against-time curve of one view.
fn curve(s: &mut Shooter, camera: &Camera, layout: &Layout, exact: &image::RgbaImage) -> Result<Vec<CurvePoint>> {
    let mut points = Vec::new();
    for mode in CURVE_MODES {
        let settings: Vec<(usize, TransparencySettings)> = if mode == TransparencyMode::Screendoor {
            SUBSAMPLE_CHOICES
                .iter()
                .map(|&n| (n, TransparencySettings { mode, subsamples: n, ..Default::default() }))
                .collect()
        } else {
            (1..=CURVE_LAYERS)
                .map(|n| (n, TransparencySettings { mode, peel_layers: n, ..Default::default() }))
                .collect()
        };
        for (setting, t) in settings {
            let shot = s.shot(camera, layout, t, false)?;
            points.push(CurvePoint { mode, setting, mae: errors(&shot.image, exact).0, frame_ms: shot.frame_ms });
        }
    }
    Ok(points)
}

pub fn run(set: &OrganSet, size: (u32, u32), region_px: u32, out: &Path, json_out: bool) -> Result<()> {
    super::output_folder(out)?;
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, set)?;
    let target = Target::new(&gpu.device, size.0, size.1)?;
    let mut shooter = Shooter { gpu: &gpu, renderer: &renderer, target, set, region_px };
    let mut rows = Vec::new();
    let mut figures = Vec::new();
    let mut sheet_rows = Vec::new();
    let mut k_rows = Vec::new();
    let bar = indicatif::ProgressBar::new(VIEWS.len() as u64);
    for (v, spec) in VIEWS.iter().enumerate() {
        let (layout, transparent) = view_layout(set, spec, v as u64 + 1)?;
        let bounds = layout.bounds(set);
        let mut camera = Camera::orbit(&bounds, spec.orbit.0, spec.orbit.1).zoomed(spec.distance);
        camera.fit_depth(&bounds);
        let exact = shooter.mode(&camera, &layout, TransparencyMode::Exact)?.image;
        let mut opaque_layout = layout.clone();
        opaque_layout.organs.iter_mut().filter(|s| s.is_drawn()).for_each(|s| s.opacity = 1.0);
        let opaque = shooter.mode(&camera, &opaque_layout, TransparencyMode::Screendoor)?;
        let mut images = vec![exact.clone()];
        for mode in modes() {
            let Shot { image, frame_ms, gpu_ms, passes } = shooter.mode(&camera, &layout, mode)?;
            let (mae, p99) = errors(&image, &exact);
            if mode == TransparencyMode::KBuffer {
                if let Some(counts) = renderer.fragment_counts(&gpu.device, &gpu.queue, &shooter.target)? {
                    k_rows.push(super::k_analysis::shares(spec.name, transparent, &counts));
                }
            }
            rows.push(Row { view: spec.name.into(), transparent, mode, mae, p99, frame_ms, gpu_ms, passes });
            images.push(image);
        }
        let moving = shooter.shot(&camera, &layout, TransparencySettings::default(), true)?;
        let curve = curve(&mut shooter, &camera, &layout, &exact)?;
        figures.push(ViewFigures {
            opaque_frame_ms: opaque.frame_ms,
            opaque_gpu_ms: opaque.gpu_ms,
            moving_frame_ms: moving.frame_ms,
            curve,
        });
        sheet_rows.push(images);
        bar.inc(1);
    }
    bar.finish_and_clear();
    let regen = mask_regeneration(set, region_px)?;
    let (k_csv, k_plot) = super::k_analysis::write(out, &k_rows)?;
    let csv = out.join("transparency.csv");
    vbrain::atomic::write(&csv, |w| {
        writeln!(w, "view,transparent_organs,mode,mean_abs_error,p99_error,frame_ms,passes,gpu_ms")?;
        for r in &rows {
            let (v, n, m) = (vbrain::lab::csv_field(&r.view), r.transparent, r.mode.name());
            let gpu = r.gpu_ms.map(|g| format!("{g:.2}")).unwrap_or_default();
            writeln!(w, "{v},{n},{m},{:.4},{:.1},{:.2},{},{gpu}", r.mae, r.p99, r.frame_ms, r.passes)?;
        }
        Ok(())
    })?;
    let plot = out.join("transparency.png");
    write_plot(&plot, &rows, &figures)?;
    let sheet = out.join("transparency-sheet.png");
    write_sheet(&sheet, &sheet_rows, size)?;
    let mean = |m: TransparencyMode| {
        let v: Vec<f64> = rows.iter().filter(|r| r.mode == m).map(|r| r.mae).collect();
        v.iter().sum::<f64>() / v.len().max(1) as f64
    };
    if json_out {
        let views: Vec<_> = VIEWS
            .iter()
            .zip(&figures)
            .map(|(spec, fig)| {
                let modes: serde_json::Map<_, _> = rows
                    .iter()
                    .filter(|r| r.view == spec.name)
                    .map(|r| {
                        let gpu_over_opaque = r.gpu_ms.zip(fig.opaque_gpu_ms).map(|(g, o)| g / o);
                        let figures = json!({"mean_abs_error": r.mae, "p99_error": r.p99, "frame_ms": r.frame_ms,
                            "passes": r.passes, "cost_over_opaque": r.frame_ms / fig.opaque_frame_ms,
                            "gpu_ms": r.gpu_ms, "gpu_cost_over_opaque": gpu_over_opaque});
                        (r.mode.name().to_string(), figures)
                    })
                    .collect();
                let transparent = rows.iter().find(|r| r.view == spec.name).map(|r| r.transparent);
                let curve: serde_json::Map<_, _> = CURVE_MODES
                    .iter()
                    .map(|&m| {
                        let key = if m == TransparencyMode::Screendoor { "subsamples" } else { "layers" };
                        let points: Vec<_> = fig
                            .curve
                            .iter()
                            .filter(|p| p.mode == m)
                            .map(|p| json!({key: p.setting, "mean_abs_error": p.mae, "frame_ms": p.frame_ms}))
                            .collect();
                        (m.name().to_string(), json!(points))
                    })
                    .collect();
                json!({"view": spec.name, "transparent_organs": transparent, "opaque_frame_ms": fig.opaque_frame_ms,
                    "opaque_gpu_ms": fig.opaque_gpu_ms, "screendoor_moving_frame_ms": fig.moving_frame_ms,
                    "blended_moving_frame_ms": blended_ms(&rows, spec.name),
                    "modes": modes, "curve": curve, "screendoor_at_equal_error": at_equal_error(&fig.curve)})
            })
            .collect();
        let means: serde_json::Map<_, _> = modes().map(|m| (m.name().to_string(), json!(mean(m)))).collect();
        let out = json!({
            "size": [size.0, size.1], "region_px": region_px, "views": views, "mean_abs_error": means,
            "mask_regeneration": regen, "adapter": gpu.adapter_description(),
            "k_analysis": k_rows, "k_csv": k_csv, "k_plot": k_plot,
            "csv": csv, "plot": plot, "sheet": sheet,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        let adapter = gpu.adapter_description();
        println!("{} views at {}x{} on {adapter}; errors against exact, 8-bit units", VIEWS.len(), size.0, size.1);
        println!(
            "{:<40} {:>6} {:<22} {:>9} {:>6} {:>10} {:>9}",
            "view", "organs", "mode", "mean err", "p99", "frame ms", "x opaque"
        );
        for (r, fig) in rows.iter().zip(figures.iter().flat_map(|f| std::iter::repeat_n(f, modes().count()))) {
            let (v, n, m) = (&r.view, r.transparent, r.mode.name());
            let ratio = r.frame_ms / fig.opaque_frame_ms;
            println!("{v:<40} {n:>6} {m:<22} {:>9.3} {:>6.0} {:>10.1} {ratio:>9.2}", r.mae, r.p99, r.frame_ms);
        }
        for (spec, fig) in VIEWS.iter().zip(&figures) {
            let (o, m, b) = (fig.opaque_frame_ms, fig.moving_frame_ms, blended_ms(&rows, spec.name));
            println!(
                "{:<40} opaque {o:.1} ms, moving: screen-door {m:.1} ms ({:.2}x), blended {b:.1} ms ({:.2}x)",
                spec.name,
                m / o,
                b / o
            );
        }
        if let (Some(spec), Some(fig)) = (VIEWS.last(), figures.last()) {
            println!(
                "{}: screen-door at the error of peeling's most layers: {}",
                spec.name,
                at_equal_error(&fig.curve)
            );
        }
        for m in modes() {
            println!("mean over views  {:<22} {:.3}", m.name(), mean(m));
        }
        println!("mask regeneration at 1920x1080, every organ at 50 %: {regen}");
        for r in &k_rows {
            println!(
                "{:<40} k-buffer slots needed: k <= 2 {:.1} %, 3-6 {:.1} %, > 6 {:.1} % (most {})",
                r.view, r.k_at_most_2, r.k_3_to_6, r.k_over_6, r.most
            );
        }
        println!("contact sheet columns: exact, {}", modes().map(|m| m.name()).collect::<Vec<_>>().join(", "));
        println!(
            "wrote {}, {}, {}, {} and {}",
            csv.display(),
            plot.display(),
            sheet.display(),
            k_csv.display(),
            k_plot.display()
        );
    }
    Ok(())
}

/// Error and frame time per view, and the error-against-time curve of the view with every organ
/// at 50 %.
fn write_plot(path: &Path, rows: &[Row], figures: &[ViewFigures]) -> Result<()> {
    use super::plot::{Panel, Series};
    let series = |value: fn(&Row) -> f64| {
        modes()
            .map(|m| Series {
                name: m.name().into(),
                colour: colour(m),
                points: rows.iter().filter(|r| r.mode == m).map(|r| (r.transparent as f64, value(r))).collect(),
            })
            .collect()
    };
    let last = figures.last().map(|f| f.curve.as_slice()).unwrap_or_default();
    let curve = CURVE_MODES
        .iter()
        .map(|&m| Series {
            name: m.name().into(),
            colour: colour(m),
            points: last.iter().filter(|p| p.mode == m).map(|p| (p.frame_ms, p.mae)).collect(),
        })
        .collect();
    super::plot::write(
        path,
        1000,
        340,
        &[
            Panel {
                title: "mean absolute error against exact (8-bit units)".into(),
                x_label: "transparent organs in the view".into(),
                series: series(|r| r.mae),
            },
            Panel {
                title: "frame time (ms)".into(),
                x_label: "transparent organs in the view".into(),
                series: series(|r| r.frame_ms),
            },
            Panel {
                title: format!(
                    "{}: error against frame time (screen-door 4..64 sub-samples, peeling 1..{CURVE_LAYERS} layers)",
                    VIEWS[VIEWS.len() - 1].name
                ),
                x_label: "frame time (ms)".into(),
                series: curve,
            },
        ],
    )
}

fn colour(m: TransparencyMode) -> (u8, u8, u8) {
    match m {
        TransparencyMode::Screendoor => (200, 40, 40),
        TransparencyMode::ScreendoorWhitenoise => (120, 120, 120),
        TransparencyMode::ScreendoorPixeltree => (40, 110, 200),
        TransparencyMode::AlphaUnsorted => (230, 150, 30),
        TransparencyMode::AlphaSorted => (40, 160, 80),
        TransparencyMode::WeightedBlended => (140, 60, 170),
        TransparencyMode::Peel => (20, 170, 190),
        TransparencyMode::DualPeel => (90, 90, 30),
        TransparencyMode::KBuffer => (230, 90, 150),
        TransparencyMode::Exact => (0, 0, 0),
    }
}

/// The widest contact sheet, in pixels: larger images are scaled down to fit, so that the sheet
/// of a full-size run stays small enough to keep beside the results (about 1 MB).
const MAX_SHEET_WIDTH: u32 = 1800;

/// Images side by side, one row per view, with a 4-pixel white gap; each image scaled down (never
/// up) so that the sheet is at most [`MAX_SHEET_WIDTH`] wide.
fn write_sheet(path: &Path, rows: &[Vec<image::RgbaImage>], size: (u32, u32)) -> Result<()> {
    let gap = 4;
    let cols = rows.iter().map(|r| r.len()).max().unwrap_or(0) as u32;
    let room = MAX_SHEET_WIDTH.saturating_sub(gap * (cols + 1)) as f32 / (cols.max(1) * size.0.max(1)) as f32;
    let scale = room.min(1.0);
    let tile = (((size.0 as f32 * scale) as u32).max(1), ((size.1 as f32 * scale) as u32).max(1));
    let (w, h) = (cols * (tile.0 + gap) + gap, rows.len() as u32 * (tile.1 + gap) + gap);
    let mut sheet = image::RgbaImage::from_pixel(w, h, image::Rgba([255, 255, 255, 255]));
    for (r, images) in rows.iter().enumerate() {
        for (c, img) in images.iter().enumerate() {
            let (x, y) = (gap + c as u32 * (tile.0 + gap), gap + r as u32 * (tile.1 + gap));
            if scale < 1.0 {
                let small = image::imageops::resize(img, tile.0, tile.1, image::imageops::FilterType::Triangle);
                image::imageops::overlay(&mut sheet, &small, x.into(), y.into());
            } else {
                image::imageops::overlay(&mut sheet, img, x.into(), y.into());
            }
        }
    }
    Ok(vbrain::atomic::write_png(path, &sheet, true)?)
}

/// Mask regeneration at 1920x1080 with every shown organ at 50 %: over 24 orbit frames, after
/// two warm-up frames, the median and largest times and the distinct configurations, all generated
/// anew; then, as the renderer does, keeping the last frame's configurations, on the same orbit
/// (15 degrees a frame) and on one of small moves (1 degree a frame, as a drag turns the view);
/// and at a still view with the largest organ's opacity changing every frame (a slider dragged).
fn mask_regeneration(set: &OrganSet, region_px: u32) -> Result<serde_json::Value> {
    let mut layout = Layout::new(set);
    layout.organs.iter_mut().for_each(|s| s.opacity = 0.5);
    if !layout.organs.iter().any(|s| s.is_drawn()) {
        bail!("no organ is shown");
    }
    let s = TransparencySettings::default();
    let p = regions::RegionParams {
        width: 1920,
        height: 1080,
        region_px,
        subsamples: s.subsamples,
        k: s.k,
        method: vbrain::transparency::MaskMethod::TabularNec,
    };
    let bounds = layout.bounds(set);
    let frames = 24;
    let orbit = |step_deg: f32, keep: bool| {
        let mut cache = regions::MaskCache::default();
        regeneration_times(frames, |i| {
            let camera = Camera::orbit(&bounds, i as f32 * step_deg, 15.0);
            match keep {
                true => regions::region_masks_kept(set, &layout, &camera, &p, &mut cache),
                false => regions::region_masks(set, &layout, &camera, &p),
            }
        })
    };
    let (median_ms, max_ms, median_configs, _) = orbit(360.0 / frames as f32, false);
    let (kept_ms, kept_max_ms, _, kept_configs) = orbit(360.0 / frames as f32, true);
    let (small_ms, small_max_ms, small_configs, small_kept) = orbit(1.0, true);
    // An opacity slider dragged at a still view: the largest shown organ's opacity changes every
    // frame, so only the configurations it is in are made again.
    let largest = (0..set.organs.len().min(layout.organs.len()))
        .filter(|&o| layout.organs[o].is_drawn())
        .max_by_key(|&o| set.organs[o].mesh().triangle_count());
    let slider = largest.map(|organ| {
        let (mut layout, mut cache) = (layout.clone(), regions::MaskCache::default());
        let camera = Camera::orbit(&bounds, 30.0, 15.0);
        let (ms, max_ms, configs, kept) = regeneration_times(frames, |i| {
            layout.organs[organ].opacity = 0.3 + 0.01 * i as f32;
            regions::region_masks_kept(set, &layout, &camera, &p, &mut cache)
        });
        json!({"organ": set.organs[organ].id, "median_ms": ms, "max_ms": max_ms, "configs": configs,
            "median_configs_kept": kept})
    });
    Ok(json!({
        "width": 1920, "height": 1080, "region_px": region_px, "subsamples": s.subsamples, "k": s.k,
        "frames": frames, "median_ms": median_ms, "max_ms": max_ms, "median_configs": median_configs,
        "kept": {"median_ms": kept_ms, "max_ms": kept_max_ms, "median_configs_kept": kept_configs},
        "small_moves": {"step_deg": 1.0, "median_ms": small_ms, "max_ms": small_max_ms,
            "median_configs": small_configs, "median_configs_kept": small_kept},
        "opacity_slider": slider,
    }))
}

/// Over `frames` frames made by `frame` (given the frame's number), after two warm-up frames: the
/// median and largest times, the median distinct configurations and the median kept.
fn regeneration_times(frames: usize, mut frame: impl FnMut(usize) -> regions::RegionMasks) -> (f64, f64, usize, usize) {
    let (mut times, mut configs, mut kept) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..frames + 2 {
        let m = frame(i);
        if i >= 2 {
            times.push(m.ms);
            configs.push(m.configs);
            kept.push(m.kept);
        }
    }
    times.sort_by(f64::total_cmp);
    configs.sort_unstable();
    kept.sort_unstable();
    let mid = times.len() / 2;
    (times[mid], times.last().copied().unwrap_or(0.0), configs[mid], kept[mid])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screen_door_is_compared_where_its_error_is_no_higher() {
        let point = |mode, setting, mae, frame_ms| CurvePoint { mode, setting, mae, frame_ms };
        let (sd, dual) = (TransparencyMode::Screendoor, TransparencyMode::DualPeel);
        let curve = [
            point(sd, 8, 2.7, 270.0),
            point(sd, 16, 1.5, 475.0),
            point(sd, 64, 0.9, 1700.0),
            point(dual, 4, 3.8, 580.0),
            point(dual, 8, 2.0, 1000.0),
            point(TransparencyMode::Peel, 8, 0.5, 1300.0),
        ];
        let v = at_equal_error(&curve);
        assert_eq!(v["dual-peel"]["layers"], 8);
        assert_eq!(v["dual-peel"]["screendoor_subsamples"], 16);
        assert!((v["dual-peel"]["time_ratio"].as_f64().unwrap() - 0.475).abs() < 1e-9);
        assert!(v["peel"].is_null(), "no screen-door point is as close as peeling there");
    }

    #[test]
    fn a_contact_sheet_is_scaled_down_to_fit_and_never_up() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sheet.png");
        let tile = |w, h| image::RgbaImage::from_pixel(w, h, image::Rgba([200, 10, 10, 255]));
        write_sheet(&path, &[vec![tile(800, 600); 4], vec![tile(800, 600); 4]], (800, 600)).unwrap();
        let big = image::open(&path).unwrap();
        assert!(big.width() <= MAX_SHEET_WIDTH && big.width() > MAX_SHEET_WIDTH - 8, "{}", big.width());
        write_sheet(&path, &[vec![tile(64, 64); 3]], (64, 64)).unwrap();
        assert_eq!(image::open(&path).unwrap().width(), 3 * 68 + 4, "small images keep their size");
    }
}
