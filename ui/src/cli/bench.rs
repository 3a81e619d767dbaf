//! `vbrain bench`: culling modes compared over the same camera path (see [`crate::lab::bench`]).
//!
//! - The arguments become plain options for the lab; with `--lod`, moving frames are timed by
//!   level of detail and render scale instead, printed as text or as `{"lod": ...}`.
//! - Refuses more than [`vbrain::clip::MAX_PLANES`] `--clip` planes.

use super::common::{database, layout, open_set};
use super::BenchArgs;
use crate::lab::bench::{self, BenchOptions};
use crate::lab::lod::LodOptions;
use anyhow::Result;
use vbrain::cull::CullSettings;
use vbrain::transparency::TransparencySettings;

pub fn run(args: &BenchArgs) -> Result<bool> {
    args.results.check()?;
    let set = open_set(&args.path)?;
    let layout = layout(&set, &args.layout)?;
    let settings = CullSettings {
        width: args.raster.width as usize,
        height: args.raster.height as usize,
        occluder_triangles: args.occluder_triangles,
        occluder_leaves: args.occluders,
        selection: args.selection,
        ..Default::default()
    };
    let base = TransparencySettings::default();
    let transparency = TransparencySettings {
        mode: args.transparency.unwrap_or(base.mode),
        subsamples: args.subsamples.unwrap_or(base.subsamples),
        kbuffer: args.kbuffer.unwrap_or(base.kbuffer),
        ..base
    };
    let opts = BenchOptions {
        frames: args.frames,
        size: (args.size.width, args.size.height),
        modes: &args.cull,
        route: args.route,
        json: args.report.json,
        out: &args.results.out,
        settings,
        transparency,
        database: database(&args.path, &set),
        section: vbrain::clip::Section { planes: args.clip.clone(), ..Default::default() },
    };
    if args.clip.len() > vbrain::clip::MAX_PLANES {
        anyhow::bail!("--clip: at most {} planes", vbrain::clip::MAX_PLANES);
    }
    if args.lod {
        return lod(&set, &layout, opts);
    }
    bench::run(&set, &layout, &opts)?;
    Ok(true)
}

/// `--lod`: moving frames by render scale, printed as text or as `{"lod": ...}`.
fn lod(set: &vbrain::organ_set::OrganSet, layout: &vbrain::layout::Layout, opts: BenchOptions) -> Result<bool> {
    let lod_opts = LodOptions {
        frames: opts.frames,
        size: opts.size,
        route: opts.route,
        transparency: opts.transparency,
        section: opts.section,
        database: opts.database,
    };
    let bar = indicatif::ProgressBar::new(opts.frames as u64);
    let report = crate::lab::lod::run(set, layout, &lod_opts, &mut |d| bar.set_position(d as u64))?;
    bar.finish_and_clear();
    if opts.json {
        let mut lod = serde_json::json!({ "full_median_ms": report.full_median_ms });
        for s in &report.strategies {
            lod[&s.strategy] = serde_json::json!({ "moving_median_ms": s.moving_median_ms, "rmse": s.rmse });
        }
        let (w, h) = opts.size;
        let out = serde_json::json!({ "lod": lod, "frames": opts.frames, "size": [w, h], "route": opts.route.name() });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "moving frames at {}x{}: full size {:.1} ms (median)",
            opts.size.0, opts.size.1, report.full_median_ms
        );
        for s in &report.strategies {
            let ratio = s.moving_median_ms / report.full_median_ms.max(1e-9);
            println!("{:<10} {:>8.1} ms ({ratio:.2}x)  RMSE {:.2}", s.strategy, s.moving_median_ms, s.rmse);
        }
    }
    Ok(true)
}
