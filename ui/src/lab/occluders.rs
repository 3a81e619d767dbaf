//! Behind `vbrain occluders`: the minimum occluder set pre-processing and, with `--experiment`,
//! the occluder-selection experiment of thesis Figure 14.
//!
//! - The pre-processing writes `occluders.json` beside the set, with a progress bar and the time
//!   taken.
//! - The experiment is printed, written as CSV and a PNG plot, and with `--json` as one object
//!   keyed `ps`, `fh`, `mos`.

use anyhow::{bail, Result};
use serde_json::json;
use std::path::Path;
use vbrain::camera::Camera;
use vbrain::lab::bench::Route;
use vbrain::lab::occluder_selection as experiment;
use vbrain::layout::Layout;
use vbrain::mos::{self, Params};
use vbrain::organ_set::{OrganSet, MANIFEST_FILE};

pub struct Options<'a> {
    pub grid: usize,
    pub params: Params,
    pub views: Route,
    pub image: usize,
    pub out: &'a Path,
    pub json: bool,
}

fn check(opts: &Options) -> Result<()> {
    if opts.grid == 0 || opts.params.limit == 0 {
        bail!("--grid and --limit must be at least 1");
    }
    if !(8..=1024).contains(&opts.params.size) || !(8..=4096).contains(&opts.image) {
        bail!("--raster must be in 8..=1024 and --image in 8..=4096");
    }
    Ok(())
}

/// Pre-processes the set and writes its database beside the manifest.
pub fn preprocess(path: &Path, set: &OrganSet, layout: &Layout, opts: &Options) -> Result<()> {
    check(opts)?;
    let dir = if path.is_dir() { path.to_path_buf() } else { path.parent().unwrap_or(Path::new(".")).to_path_buf() };
    if !dir.join(MANIFEST_FILE).is_file() {
        bail!("{}: no {MANIFEST_FILE}; occluder databases live beside an organ set's manifest", dir.display());
    }
    let total = opts.grid * mos::DISTANCES.len();
    let bar = indicatif::ProgressBar::new(total as u64);
    let started = std::time::Instant::now();
    let db = mos::preprocess(set, layout, opts.grid, &opts.params, &|done, _| bar.set_position(done as u64));
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    db.save(&dir)?;
    let file = dir.join(vbrain::cull::database::FILE);
    let counts: Vec<usize> = db.viewpoints.iter().map(|v| v.occluders.len()).collect();
    let mean = counts.iter().sum::<usize>() as f64 / counts.len().max(1) as f64;
    if opts.json {
        let summary = json!({
            "file": file,
            "viewpoints": db.viewpoints.len(),
            "directions": opts.grid,
            "distances": mos::DISTANCES,
            "limit": opts.params.limit,
            "mean_occluders": mean,
            "max_occluders": counts.iter().max(),
            "seconds": seconds,
        });
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!(
            "{} viewpoints ({} directions x {} distances), {:.1} occluders each on average (limit {}), in {:.1} s",
            db.viewpoints.len(),
            opts.grid,
            mos::DISTANCES.len(),
            mean,
            opts.params.limit,
            seconds
        );
        println!("wrote {}", file.display());
    }
    Ok(())
}

/// The experiment's viewpoints: four views around the set, or four frames spread along a route.
pub fn experiment_cameras(set: &OrganSet, layout: &Layout, views: Route) -> Vec<Camera> {
    let home = layout.bounds(set);
    match views {
        Route::Orbit => (0..4).map(|i| Camera::orbit(&home, 90.0 * i as f32 + 30.0, 15.0)).collect(),
        route => (0..4).map(|i| route.camera(&home, 10 + 33 * i, 120)).collect(),
    }
}

pub fn experiment(set: &OrganSet, layout: &Layout, opts: &Options) -> Result<()> {
    check(opts)?;
    super::output_folder(opts.out)?;
    let cameras = experiment_cameras(set, layout, opts.views);
    let counts: Vec<usize> = experiment::COUNTS.iter().copied().filter(|&n| n <= opts.params.limit.max(1)).collect();
    let bar = indicatif::ProgressBar::new(cameras.len() as u64);
    let started = std::time::Instant::now();
    let results = experiment::run(set, layout, &cameras, &counts, opts.image, &opts.params, &mut |d, _| {
        bar.set_position(d as u64)
    });
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    let methods = [
        ("ps", &results.ps, (40, 110, 200)),
        ("fh", &results.fh, (230, 150, 30)),
        ("mos", &results.mos, (200, 40, 40)),
    ];
    let csv = opts.out.join("occluders.csv");
    vbrain::atomic::write(&csv, |w| {
        writeln!(w, "method,occluders,culled_percent")?;
        for (name, curve, _) in &methods {
            for (n, c) in &curve.curve {
                writeln!(w, "{name},{n},{c:.3}")?;
            }
        }
        Ok(())
    })?;
    let plot = opts.out.join("occluders.png");
    let panel = super::plot::Panel {
        title: format!("culled triangles (%) against occluders allowed, mean of {} viewpoints", cameras.len()),
        x_label: "occluders".into(),
        series: methods
            .iter()
            .map(|(name, curve, colour)| super::plot::Series {
                name: name.to_uppercase(),
                colour: *colour,
                points: curve.curve.iter().map(|&(n, c)| (n as f64, c)).collect(),
            })
            .collect(),
    };
    super::plot::write(&plot, 900, 420, &[panel])?;
    if opts.json {
        let mut out = serde_json::Map::new();
        for (name, curve, _) in &methods {
            out.insert((*name).into(), serde_json::to_value(curve)?);
        }
        out.insert("viewpoints".into(), json!(results.viewpoints));
        out.insert("views".into(), json!(opts.views.name()));
        out.insert("raster".into(), json!(opts.params.size));
        out.insert("image".into(), json!(opts.image));
        out.insert("mos_seconds_per_view".into(), json!(results.mos_seconds_per_view));
        out.insert("seconds".into(), json!(seconds));
        out.insert("csv".into(), json!(csv));
        out.insert("plot".into(), json!(plot));
        println!("{}", serde_json::to_string_pretty(&serde_json::Value::Object(out))?);
    } else {
        println!(
            "{} viewpoints ({}), culling raster {}, ID render {}",
            cameras.len(),
            opts.views.name(),
            opts.params.size,
            opts.image
        );
        print!("{:<8}", "method");
        for n in &counts {
            print!("{n:>7}");
        }
        println!("   best  to best");
        for (name, curve, _) in &methods {
            print!("{:<8}", name.to_uppercase());
            for (_, c) in &curve.curve {
                print!("{c:>6.1}%");
            }
            println!("{:>6.1}% {:>8}", curve.best_culled_percent, curve.occluders_to_best);
        }
        println!("minimum occluder sets: {:.2} s per viewpoint; all in {seconds:.1} s", results.mos_seconds_per_view);
        println!("wrote {} and {}", csv.display(), plot.display());
    }
    Ok(())
}
