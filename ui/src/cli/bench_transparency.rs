//! `vbrain bench-transparency`: the transparency modes against the exact reference (see
//! [`crate::lab::transparency_bench`]).
//!
//! - Only opens the set and passes the size, mask region, output folder and `--json` on; the lab
//!   measures and writes.

use super::common::open_set;
use super::BenchTransparencyArgs;
use anyhow::Result;

pub fn run(args: &BenchTransparencyArgs) -> Result<bool> {
    super::outputs::experiment_folder(&args.out, args.force)?;
    let set = open_set(&args.path)?;
    let size = (args.size.width, args.size.height);
    crate::lab::transparency_bench::run(&set, size, args.region, &args.out, args.report.json)?;
    Ok(true)
}
