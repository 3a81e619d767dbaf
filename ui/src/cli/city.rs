//! `vbrain city`: the synthetic city of the occluder experiments, written as an organ set.
//!
//! - Generated from `--seed`; written into `--out`, refusing a folder that already holds files
//!   unless `--force`.

use super::common::summary;
use super::CityArgs;
use anyhow::Result;

pub fn run(args: &CityArgs) -> Result<bool> {
    super::outputs::folder(&args.out.out, args.out.force, &[])?;
    let set = vbrain::lab::city::generate(args.seed);
    set.save(&args.out.out)?;
    summary(args.report.json, "city", &set, &args.out.out)
}
