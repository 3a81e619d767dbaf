//! `vbrain city`: the synthetic city of the occluder experiments, written as an organ set.

use super::common::{summary, writable_folder};
use super::CityArgs;
use anyhow::Result;

pub fn run(args: &CityArgs) -> Result<bool> {
    writable_folder(&args.out.out, args.out.force)?;
    let set = vbrain::lab::city::generate(args.seed);
    set.save(&args.out.out)?;
    summary(args.report.json, "city", &set, &args.out.out)
}
