//! `vbrain bench`: culling modes compared over the same camera path (see [`crate::lab::bench`]).

use super::common::{database, layout, open_set};
use super::BenchArgs;
use crate::lab::bench::{self, BenchOptions};
use anyhow::Result;
use vbrain::cull::CullSettings;
use vbrain::transparency::TransparencySettings;

pub fn run(args: &BenchArgs) -> Result<bool> {
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
        ..base
    };
    let opts = BenchOptions {
        frames: args.frames,
        size: (args.size.width, args.size.height),
        modes: &args.cull,
        route: args.route,
        json: args.report.json,
        out: &args.out,
        settings,
        transparency,
        database: database(&args.path, &set),
        section: vbrain::clip::Section { planes: args.clip.clone(), ..Default::default() },
    };
    if args.clip.len() > vbrain::clip::MAX_PLANES {
        anyhow::bail!("--clip: at most {} planes", vbrain::clip::MAX_PLANES);
    }
    bench::run(&set, &layout, &opts)?;
    Ok(true)
}
