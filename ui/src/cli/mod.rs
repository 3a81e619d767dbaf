//! The headless commands of `vbrain`. Each prints a human summary, or with `--json` one JSON object
//! on stdout; errors go to stderr and make the exit status non-zero.

use anyhow::{anyhow, bail, Context, Result};
use clap::{Parser, Subcommand};
use serde_json::json;
use std::path::{Path, PathBuf};
use vbrain::camera::{Camera, View};
use vbrain::cull::{self, CullMode, CullSettings};
use vbrain::layout::Layout;
use vbrain::organ_set::{self, import, scale, stand_in, Loaded, OrganSet};
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};
use vbrain::transparency::{TransparencyMode, TransparencySettings};

#[derive(Parser)]
#[command(name = "vbrain", version, about = "Explore the brain as a set of organs: viewer and headless tools")]
pub struct Args {
    /// Organ set folder, .obj/.vbo file or folder of them to open in the viewer (default: organs/brain)
    pub path: Option<PathBuf>,
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand)]
pub enum Command {
    /// List the organs of a set: triangles per organ and bounds
    Info {
        path: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Render a set to a PNG through the viewer's renderer
    Render(RenderArgs),
    /// Turn a label volume (NIfTI) and its label table into an organ set
    Import {
        /// Label volume, .nii or .nii.gz
        volume: PathBuf,
        /// Label table: CSV `index,name` or a FreeSurfer colour look-up table
        #[arg(long)]
        labels: PathBuf,
        /// Output folder for the organ set
        #[arg(long)]
        out: PathBuf,
        /// Triangle budget for the whole set
        #[arg(long, default_value_t = 200_000)]
        triangles: usize,
        /// Smoothing iterations (Taubin)
        #[arg(long, default_value_t = 10)]
        smooth: usize,
        /// Title of the new set (default: the volume's file name)
        #[arg(long)]
        title: Option<String>,
        #[arg(long)]
        json: bool,
    },
    /// Benchmark culling: the camera orbits the set; each mode runs over the same frames
    Bench {
        path: PathBuf,
        /// Frames of the orbit (the thesis: 475)
        #[arg(long, default_value_t = 475)]
        frames: usize,
        /// Image size, WxH
        #[arg(long, default_value = "512x512")]
        size: String,
        /// Culling modes to compare, comma-separated
        #[arg(long, default_value = "none,frustum,occlusion")]
        cull: String,
        /// Show organs hidden by default (e.g. skull), by id
        #[arg(long, num_args = 1..)]
        show: Vec<String>,
        /// Hide organs by id
        #[arg(long, num_args = 1..)]
        hide: Vec<String>,
        /// Set opacity, ID=A or all=A
        #[arg(long, num_args = 1..)]
        opacity: Vec<String>,
        /// Occluder triangle budget per frame (triangles facing the eye)
        #[arg(long, default_value_t = CullSettings::default().occluder_triangles)]
        occluder_triangles: usize,
        /// Culling raster size, WxH
        #[arg(long, default_value = "128x128")]
        raster: String,
        /// Camera path: orbit (the Virtual Brain run) or a city walkthrough route: best, average, worst
        #[arg(long, default_value = "orbit")]
        route: String,
        /// Occluder selection: auto (pre-computed sets while the layout is unchanged), ps or mos
        #[arg(long, default_value = "auto")]
        selection: String,
        /// Most occluder leaves per frame (the thesis's city runs: 64)
        #[arg(long)]
        occluders: Option<usize>,
        /// Folder for bench.csv and bench.png
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// The mask experiment of thesis Figures 19/20: faulty pixels per stacking level per mask method
    Masks {
        /// Mask size, WxH sub-samples (the thesis: 16x16 and 32x32)
        #[arg(long, default_value = "16x16")]
        mask: String,
        /// Transparent objects stacked per trial
        #[arg(long, default_value_t = 16)]
        objects: usize,
        #[arg(long, default_value_t = 1000)]
        trials: usize,
        /// One opacity for every object (default: random per object)
        #[arg(long)]
        alpha: Option<f32>,
        /// Objects that neighbourhood error compensation favours
        #[arg(long, default_value_t = 6)]
        k: usize,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Folder for masks.csv and masks.png
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Compare the transparency modes against the exact reference on views with 4 to 39
    /// transparent organs; also time mask regeneration at 1920x1080
    BenchTransparency {
        path: PathBuf,
        /// Image size, WxH
        #[arg(long, default_value = "384x384")]
        size: String,
        /// Screen-door mask region side in pixels
        #[arg(long, default_value_t = vbrain::transparency::TransparencySettings::default().region_px)]
        region: u32,
        /// Folder for transparency.csv, transparency.png and transparency-sheet.png
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Minimum occluder sets (thesis §3.2): pre-compute occluders per viewpoint for the set's
    /// layout into occluders.json beside it, or with --experiment compare occluder selections
    Occluders {
        path: PathBuf,
        /// Directions of the viewpoint grid on a sphere around the set (each at two distances)
        #[arg(long, default_value_t = 32)]
        grid: usize,
        /// Most occluders kept per viewpoint
        #[arg(long, default_value_t = 128)]
        limit: usize,
        /// Culling raster side, pixels
        #[arg(long, default_value_t = 128)]
        raster: usize,
        /// Show organs hidden by default (e.g. skull), by id
        #[arg(long, num_args = 1..)]
        show: Vec<String>,
        /// Hide organs by id
        #[arg(long, num_args = 1..)]
        hide: Vec<String>,
        /// Run the occluder-selection experiment (thesis Figure 14) instead: culled % against the
        /// number of occluders for projected size, first hit and minimum occluder sets
        #[arg(long)]
        experiment: bool,
        /// Experiment viewpoints: orbit (four views around the set) or frames of a city route (best,
        /// average, worst)
        #[arg(long, default_value = "orbit")]
        views: String,
        /// Experiment ID-render size (square), for first hit and projected size
        #[arg(long, default_value_t = 512)]
        image: usize,
        /// Folder for occluders.csv and occluders.png (experiment)
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Generate the synthetic city of the occluder experiments (about 300,000 triangles)
    City {
        /// Output folder for the organ set
        #[arg(long)]
        out: PathBuf,
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[arg(long)]
        json: bool,
    },
    /// Write a denser copy of a set (each triangle subdivided), for benchmarks
    Scale {
        set: PathBuf,
        /// Density factor K: each triangle becomes n*n with n = round(sqrt(K))
        #[arg(long)]
        factor: f64,
        #[arg(long)]
        out: PathBuf,
        #[arg(long)]
        json: bool,
    },
    /// Build occluder stand-ins: for each closed organ, a coarse mesh verified to lie inside it,
    /// which occlusion culling rasterises in its place (written as meshes/ID.occluder.vbo)
    StandIns {
        path: PathBuf,
        /// Stand-in triangles as a share of the organ's
        #[arg(long, default_value_t = 0.0625)]
        ratio: f64,
        /// Most inward offset of the stand-in from the surface, millimetres
        #[arg(long, default_value_t = 2.0)]
        offset: f32,
        /// Organs with fewer triangles get none
        #[arg(long, default_value_t = 2048)]
        min_triangles: usize,
        /// Output folder (default: the set's own folder)
        #[arg(long)]
        out: Option<PathBuf>,
        #[arg(long)]
        json: bool,
    },
}

#[derive(clap::Args)]
pub struct RenderArgs {
    pub path: PathBuf,
    /// Output PNG file
    #[arg(long)]
    pub out: PathBuf,
    /// Image size, WxH
    #[arg(long, default_value = "1024x1024")]
    pub size: String,
    /// Standard view: anterior, posterior, left, right, superior, inferior
    #[arg(long)]
    pub view: Option<String>,
    /// Orbit AZ,EL in degrees from the anterior view (azimuth toward the right, elevation upward)
    #[arg(long, allow_hyphen_values = true)]
    pub orbit: Option<String>,
    /// Camera of a bench route instead, ROUTE:FRAME of 120 (e.g. best:0; routes: orbit, best,
    /// average, worst)
    #[arg(long)]
    pub route: Option<String>,
    /// Show organs hidden by default (e.g. skull), by id
    #[arg(long, num_args = 1..)]
    pub show: Vec<String>,
    /// Hide organs by id (repeatable)
    #[arg(long, num_args = 1..)]
    pub hide: Vec<String>,
    /// Set opacity, ID=A or all=A with A in 0..1 (repeatable)
    #[arg(long, num_args = 1..)]
    pub opacity: Vec<String>,
    /// Transparent background instead of the viewer's dark grey
    #[arg(long)]
    pub transparent: bool,
    /// Culling: none, frustum or occlusion (the image is the same; only the work differs)
    #[arg(long, default_value = "occlusion")]
    pub cull: String,
    /// Show what culling removed in colour through a translucent grey model (thesis Figure 21)
    #[arg(long)]
    pub debug_culled: bool,
    /// Transparency: screendoor, screendoor-whitenoise, screendoor-pixeltree, alpha-unsorted,
    /// alpha-sorted, weighted-blended or exact
    #[arg(long, default_value = "screendoor")]
    pub transparency: String,
    /// Screen-door sub-samples per pixel: 4, 8, 16, 32 or 64
    #[arg(long, default_value_t = 64)]
    pub subsamples: usize,
    /// Screen-door mask region side in pixels
    #[arg(long, default_value_t = vbrain::transparency::TransparencySettings::default().region_px)]
    pub region: u32,
    /// Nearest organs that the masks' error compensation favours
    #[arg(long, default_value_t = 6)]
    pub k: usize,
    /// Draw the organs in an order shuffled by this seed (screen-door gives the same image)
    #[arg(long)]
    pub draw_order_seed: Option<u64>,
    #[arg(long)]
    pub json: bool,
}

pub fn run(command: Command) -> std::process::ExitCode {
    match run_command(command) {
        Ok(true) => std::process::ExitCode::SUCCESS,
        Ok(false) => std::process::ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Runs one command; `Ok(false)` means it finished but reported errors (e.g. broken organs).
fn run_command(command: Command) -> Result<bool> {
    match command {
        Command::Info { path, json } => info(&path, json),
        Command::Render(args) => render(&args),
        Command::Import { volume, labels, out, triangles, smooth, title, json } => {
            import_cmd(&volume, &labels, &out, triangles, smooth, title, json)
        }
        Command::Scale { set, factor, out, json } => scale_cmd(&set, factor, &out, json),
        Command::StandIns { path, ratio, offset, min_triangles, out, json } => {
            stand_ins_cmd(&path, ratio, offset, min_triangles, out.as_deref(), json)
        }
        Command::Occluders { path, grid, limit, raster, show, hide, experiment, views, image, out, json } => {
            let (set, ok) = open_reporting(&path)?;
            let mut layout = Layout::new(&set);
            apply_overrides(&set, &mut layout, &show, &hide, &[])?;
            let opts = crate::lab::occluders::Options {
                grid,
                params: vbrain::mos::Params { size: raster, limit, ..Default::default() },
                views: parse_route(&views)?,
                image,
                out: &out,
                json,
            };
            if experiment {
                crate::lab::occluders::experiment(&set, &layout, &opts)?;
            } else {
                crate::lab::occluders::preprocess(&path, &set, &layout, &opts)?;
            }
            Ok(ok)
        }
        Command::City { out, seed, json } => {
            let set = vbrain::city::generate(seed);
            set.save(&out)?;
            summary(json, "city", &set, &out)
        }
        Command::BenchTransparency { path, size, region, out, json } => {
            let (set, ok) = open_reporting(&path)?;
            if !(1..=256).contains(&region) {
                bail!("--region {region} outside 1..256 pixels");
            }
            crate::lab::transparency_bench::run(&set, parse_size(&size)?, region, &out, json)?;
            Ok(ok)
        }
        Command::Masks { mask, objects, trials, alpha, k, seed, out, json } => {
            let n = crate::lab::masks::parse_mask(&mask)?;
            let experiment = vbrain::transparency::experiment::Experiment { n, objects, trials, alpha, k, seed };
            crate::lab::masks::run(&crate::lab::masks::MasksOptions { experiment, out: &out, json })?;
            Ok(true)
        }
        Command::Bench {
            path,
            frames,
            size,
            cull,
            show,
            hide,
            opacity,
            occluder_triangles,
            raster,
            route,
            selection,
            occluders,
            out,
            json,
        } => {
            let (set, ok) = open_reporting(&path)?;
            let mut layout = Layout::new(&set);
            apply_overrides(&set, &mut layout, &show, &hide, &opacity)?;
            let (rw, rh) = parse_size(&raster)?;
            let selection = cull::Selection::parse(&selection)
                .ok_or_else(|| anyhow!("unknown occluder selection \"{selection}\" (auto, ps, mos)"))?;
            let settings = CullSettings {
                width: rw as usize,
                height: rh as usize,
                occluder_triangles,
                occluder_leaves: occluders,
                selection,
                ..Default::default()
            };
            let opts = crate::lab::bench::BenchOptions {
                frames,
                size: parse_size(&size)?,
                modes: &cull,
                route: parse_route(&route)?,
                json,
                out: &out,
                settings,
            };
            crate::lab::bench::run(&set, &layout, &opts)?;
            Ok(ok)
        }
    }
}

pub fn parse_route(s: &str) -> Result<vbrain::bench::Route> {
    vbrain::bench::Route::parse(s).ok_or_else(|| anyhow!("unknown route \"{s}\" (orbit, best, average, worst)"))
}

/// Opens a set and reports its warnings and broken organs on stderr; true if nothing broke.
pub fn open_reporting(path: &Path) -> Result<(OrganSet, bool)> {
    let Loaded { set, errors, warnings } = organ_set::open(path).map_err(|e| anyhow!(e))?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    for e in &errors {
        eprintln!("error: {e}");
    }
    if set.organs.is_empty() {
        bail!("{}: no organ could be loaded", path.display());
    }
    Ok((set, errors.is_empty()))
}

fn info(path: &Path, json: bool) -> Result<bool> {
    let (set, ok) = open_reporting(path)?;
    let bounds = set.bounds();
    if json {
        let organs: Vec<_> = set
            .organs
            .iter()
            .map(|o| {
                json!({
                    "id": o.id, "name": o.name, "group": o.group, "triangles": o.mesh.triangle_count(),
                    "vertices": o.mesh.positions.len(), "bounds": o.mesh.bounds(),
                })
            })
            .collect();
        let out = json!({ "title": set.title, "organs": organs, "triangles": set.triangle_count(), "bounds": bounds });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!("{}: {} organs, {} triangles", set.title, set.organs.len(), set.triangle_count());
        println!("bounds (mm, RAS): {:?} .. {:?}", bounds.min, bounds.max);
        for o in &set.organs {
            println!("  {:<28} {:>8} triangles  {}", o.id, o.mesh.triangle_count(), o.name);
        }
    }
    Ok(ok)
}

pub fn parse_size(s: &str) -> Result<(u32, u32)> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| anyhow!("size \"{s}\" is not WxH"))?;
    let w: u32 = w.trim().parse().with_context(|| format!("width in \"{s}\""))?;
    let h: u32 = h.trim().parse().with_context(|| format!("height in \"{s}\""))?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        bail!("size {w}x{h} outside 1..16384");
    }
    Ok((w, h))
}

/// Applies `--show`, `--hide` and `--opacity` to a layout.
fn apply_overrides(
    set: &OrganSet,
    layout: &mut Layout,
    show: &[String],
    hide: &[String],
    opacity: &[String],
) -> Result<()> {
    let index = |id: &str| set.find(id).ok_or_else(|| anyhow!("no organ with id \"{id}\" (see `vbrain info`)"));
    for id in show {
        layout.organs[index(id)?].visible = true;
    }
    for id in hide {
        layout.organs[index(id)?].visible = false;
    }
    for spec in opacity {
        let (id, a) = spec.split_once('=').ok_or_else(|| anyhow!("opacity \"{spec}\" is not ID=A"))?;
        let a: f32 = a.parse().with_context(|| format!("opacity in \"{spec}\""))?;
        if !(0.0..=1.0).contains(&a) {
            bail!("opacity {a} in \"{spec}\" outside 0..1");
        }
        if id == "all" {
            layout.organs.iter_mut().for_each(|s| s.opacity = a);
        } else {
            layout.organs[index(id)?].opacity = a;
        }
    }
    Ok(())
}

fn render(args: &RenderArgs) -> Result<bool> {
    let (width, height) = parse_size(&args.size)?;
    let (set, ok) = open_reporting(&args.path)?;
    let mut layout = Layout::new(&set);
    apply_overrides(&set, &mut layout, &args.show, &args.hide, &args.opacity)?;
    let bounds = layout.bounds(&set);
    let camera = match (&args.view, &args.orbit, &args.route) {
        (Some(v), None, None) => Camera::view(&bounds, View::parse(v).ok_or_else(|| anyhow!("unknown view \"{v}\""))?),
        (None, Some(o), None) => {
            let (az, el) = o.split_once(',').ok_or_else(|| anyhow!("orbit \"{o}\" is not AZ,EL"))?;
            let az: f32 = az.trim().parse().with_context(|| format!("azimuth in \"{o}\""))?;
            let el: f32 = el.trim().parse().with_context(|| format!("elevation in \"{o}\""))?;
            Camera::orbit(&bounds, az, el)
        }
        (None, None, Some(spec)) => {
            let (route, frame) = spec.split_once(':').unwrap_or((spec, "0"));
            let frame: usize = frame.trim().parse().with_context(|| format!("frame in \"{spec}\""))?;
            if frame >= 120 {
                bail!("frame {frame} outside 0..120");
            }
            parse_route(route)?.camera(&bounds, frame, 120)
        }
        (None, None, None) => Camera::view(&bounds, View::Anterior),
        _ => bail!("give one of --view, --orbit and --route"),
    };
    let started = std::time::Instant::now();
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, &set)?;
    let target = Target::new(&gpu.device, width, height)?;
    let background = if args.transparent { [0.0; 4] } else { crate::BACKGROUND };
    let mode = CullMode::parse(&args.cull)
        .ok_or_else(|| anyhow!("unknown culling \"{}\" (none, frustum, occlusion)", args.cull))?;
    let (draw, cull) =
        cull::cull(&set, &layout, &camera, target.aspect(), &CullSettings { mode, ..Default::default() });
    let transparency = transparency_settings(&args.transparency, args.subsamples, args.region, args.k)?;
    let order = args.draw_order_seed.map(|seed| shuffled(set.organs.len(), seed));
    let input = FrameInput {
        draw: Some(&draw),
        background,
        transparency,
        draw_order: order.as_deref(),
        ..FrameInput::new(&set, &camera, &layout)
    };
    let stats = if args.debug_culled {
        renderer.render_cull_debug(&gpu.device, &gpu.queue, &target, &input);
        let organs_drawn = draw.ranges.iter().filter(|r| !r.is_empty()).count();
        vbrain::render::RenderStats { triangles_drawn: cull.drawn, organs_drawn, ..Default::default() }
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

/// Transparency settings from the command line's values, checked.
pub fn transparency_settings(mode: &str, subsamples: usize, region: u32, k: usize) -> Result<TransparencySettings> {
    let names: Vec<&str> = TransparencyMode::ALL.iter().map(|m| m.name()).collect();
    let mode = TransparencyMode::parse(mode)
        .ok_or_else(|| anyhow!("unknown transparency \"{mode}\" ({})", names.join(", ")))?;
    if !vbrain::transparency::SUBSAMPLE_CHOICES.contains(&subsamples) {
        bail!("--subsamples {subsamples}: use 4, 8, 16, 32 or 64");
    }
    if !(1..=256).contains(&region) {
        bail!("--region {region} outside 1..256 pixels");
    }
    if k == 0 {
        bail!("--k must be at least 1");
    }
    Ok(TransparencySettings { mode, subsamples, interactive_subsamples: subsamples, region_px: region, k })
}

/// A permutation of `0..n` shuffled by `seed`.
pub fn shuffled(n: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    vbrain::rng::XorShift::seeded(seed).shuffle(&mut order);
    order
}

fn progress_bar(len: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) = indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}") {
        bar.set_style(style);
    }
    bar
}

fn import_cmd(
    volume: &Path,
    labels: &Path,
    out: &Path,
    triangles: usize,
    smooth: usize,
    title: Option<String>,
    json: bool,
) -> Result<bool> {
    let table = import::read_label_table(labels)?;
    let vol = import::read_volume(volume)?;
    let title = title.unwrap_or_else(|| {
        let name = volume.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        name.trim_end_matches(".gz").trim_end_matches(".nii").to_string()
    });
    let opts = import::ImportOptions { triangles, smoothing: smooth, title };
    let bar = progress_bar(1);
    let (set, warnings) = import::import(&vol, &table, &opts, &mut |done, total, what| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    })?;
    bar.finish_and_clear();
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    set.save(out)?;
    summary(json, "import", &set, out)
}

fn summary(json: bool, what: &str, set: &OrganSet, out: &Path) -> Result<bool> {
    if json {
        let organs: Vec<_> = set
            .organs
            .iter()
            .map(|o| json!({"id": o.id, "name": o.name, "triangles": o.mesh.triangle_count()}))
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({"out": out, "organs": organs, "triangles": set.triangle_count()}))?
        );
    } else {
        println!("{what}: wrote {} organs, {} triangles to {}", set.organs.len(), set.triangle_count(), out.display());
    }
    Ok(true)
}

fn scale_cmd(path: &Path, factor: f64, out: &Path, json: bool) -> Result<bool> {
    if !(1.0..=10_000.0).contains(&factor) {
        bail!("factor {factor} outside 1..10000");
    }
    let (set, ok) = open_reporting(path)?;
    let n = scale::level_for_factor(factor);
    let bar = progress_bar(set.organs.len() as u64);
    let scaled = scale::scale_set(&set, n, &mut |done, _, what| {
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    });
    bar.finish_and_clear();
    scaled.save(out)?;
    Ok(summary(json, "scale", &scaled, out)? && ok)
}

/// Builds an inner stand-in for every closed organ of at least `min_triangles`, keeps those with at
/// most half the organ's triangles, and saves them (in place: only the stand-ins and the manifest).
fn stand_ins_cmd(
    path: &Path,
    ratio: f64,
    offset: f32,
    min_triangles: usize,
    out: Option<&Path>,
    json: bool,
) -> Result<bool> {
    if !(ratio > 0.0 && ratio <= 0.5) {
        bail!("--ratio {ratio} outside (0, 0.5]");
    }
    if !(offset > 0.0 && offset.is_finite()) {
        bail!("--offset {offset} must be a positive number of millimetres");
    }
    if out.is_none() && !path.join(organ_set::MANIFEST_FILE).is_file() {
        bail!("{}: not an organ set folder (no {}); give --out", path.display(), organ_set::MANIFEST_FILE);
    }
    let (mut set, ok) = open_reporting(path)?;
    let bar = progress_bar(set.organs.len() as u64);
    // Per organ tried: id, triangles, and the stand-in's triangles and those left out, or why none.
    type Row = (String, usize, std::result::Result<(usize, usize), String>);
    let mut rows: Vec<Row> = Vec::new();
    for organ in &mut set.organs {
        bar.set_message(organ.id.clone());
        bar.inc(1);
        let triangles = organ.mesh.triangle_count();
        if triangles < min_triangles {
            continue;
        }
        let options = stand_in::InnerOptions { triangles: (triangles as f64 * ratio) as usize, offset };
        let result = stand_in::build_inner(&organ.mesh, &organ.bvh, options).and_then(|built| {
            let n = built.stand_in.mesh.triangle_count();
            if 2 * n > triangles {
                return Err(format!("{n} triangles, not under half"));
            }
            organ.stand_in = Some(built.stand_in);
            Ok((n, built.dropped))
        });
        rows.push((organ.id.clone(), triangles, result));
    }
    bar.finish_and_clear();
    let out = match out {
        Some(out) => {
            set.save(out)?;
            out
        }
        None => {
            set.save_stand_ins(path)?;
            path
        }
    };
    if json {
        let organs: Vec<_> = rows
            .iter()
            .map(|(id, triangles, r)| match r {
                Ok((n, dropped)) => json!({"id": id, "triangles": triangles, "stand_in": n, "left_out": dropped}),
                Err(why) => json!({"id": id, "triangles": triangles, "skipped": why}),
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&json!({"out": out, "organs": organs}))?);
    } else {
        for (id, triangles, r) in &rows {
            match r {
                Ok((n, dropped)) => println!("{id:<24} {triangles:>8} triangles -> {n:>6} (left out {dropped})"),
                Err(why) => println!("{id:<24} {triangles:>8} triangles: none ({why})"),
            }
        }
        println!("stand-ins: wrote {}", out.display());
    }
    Ok(ok)
}
