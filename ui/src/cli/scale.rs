//! `vbrain scale`: a denser copy of a set (each triangle subdivided n x n), for benchmarks.
//!
//! - Refused before any subdividing: a set with organs that did not load, and a factor whose copy
//!   would need more than 80 % of the memory available or an organ past 2^32 vertices.
//! - Written into `--out`, refusing a folder that already holds files unless `--force`, and one
//!   that holds the set it scales even then.

use super::common::{open_reporting, progress_bar, summary};
use super::ScaleArgs;
use anyhow::{bail, Result};
use vbrain::organ_set::scale;

pub fn run(args: &ScaleArgs) -> Result<bool> {
    super::outputs::folder(&args.out.out, args.out.force, &[&args.set])?;
    let (set, ok) = open_reporting(&args.set)?;
    if !ok {
        bail!("{}: some organs did not load (above); a scaled copy would leave them out", args.set.display());
    }
    let n = scale::level_for_factor(args.factor);
    let e = scale::estimate(&set, n);
    let gib = |b: u64| b as f64 / (1u64 << 30) as f64;
    eprintln!("scale: level {n} makes about {} triangles in {:.2} GiB of memory", e.triangles, gib(e.memory_bytes));
    if e.largest_organ_vertices > u64::from(u32::MAX) {
        bail!(
            "factor {}: an organ would have {} vertices, more than a mesh indexes (2^32)",
            args.factor,
            e.largest_organ_vertices
        );
    }
    if let Some(available) = vbrain::input::available_memory() {
        if e.memory_bytes > available / 10 * 8 {
            bail!(
                "factor {}: the copy needs about {:.2} GiB and {:.2} GiB of memory is available; give a smaller --factor",
                args.factor,
                gib(e.memory_bytes),
                gib(available)
            );
        }
    }
    let bar = progress_bar(set.organs.len() as u64);
    let scaled = scale::scale_set(&set, n, &mut |done, _, what| {
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    });
    bar.finish_and_clear();
    scaled.save(&args.out.out)?;
    summary(args.report.json, "scale", &scaled, &args.out.out)
}
