//! `vbrain bench-transparency`: the transparency modes against the exact reference (see
//! [`crate::lab::transparency_bench`]).

use super::common::open_set;
use super::BenchTransparencyArgs;
use anyhow::Result;

pub fn run(args: &BenchTransparencyArgs) -> Result<bool> {
    let set = open_set(&args.path)?;
    let size = (args.size.width, args.size.height);
    crate::lab::transparency_bench::run(&set, size, args.region, &args.out, args.report.json)?;
    Ok(true)
}
