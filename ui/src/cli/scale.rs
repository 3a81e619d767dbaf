//! `vbrain scale`: a denser copy of a set (each triangle subdivided n x n), for benchmarks.

use super::common::{open_reporting, progress_bar, summary, writable_folder};
use super::ScaleArgs;
use anyhow::{bail, Result};
use vbrain::organ_set::scale;

pub fn run(args: &ScaleArgs) -> Result<bool> {
    let factor = args.factor;
    if !(1.0..=10_000.0).contains(&factor) {
        bail!("factor {factor} outside 1..10000");
    }
    writable_folder(&args.out, args.force)?;
    let (set, ok) = open_reporting(&args.set)?;
    let n = scale::level_for_factor(factor);
    let bar = progress_bar(set.organs.len() as u64);
    let scaled = scale::scale_set(&set, n, &mut |done, _, what| {
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    });
    bar.finish_and_clear();
    scaled.save(&args.out)?;
    Ok(summary(args.json, "scale", &scaled, &args.out)? && ok)
}
