//! `vbrain city`: the synthetic city of the occluder experiments, written as an organ set.

use super::common::{summary, writable_folder};
use super::CityArgs;
use anyhow::Result;

pub fn run(args: &CityArgs) -> Result<bool> {
    writable_folder(&args.out, args.force)?;
    let set = vbrain::lab::city::generate(args.seed);
    set.save(&args.out)?;
    summary(args.json, "city", &set, &args.out)
}
