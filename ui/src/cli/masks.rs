//! `vbrain masks`: the mask experiment of thesis Figures 19/20 (see [`crate::lab::masks`]).
//!
//! - `--mask WxH` counts sub-samples (W x H of them); the arguments become the core's experiment,
//!   which the lab runs and writes into `--out`.

use super::MasksArgs;
use crate::lab::masks::{self, MasksOptions};
use anyhow::Result;
use vbrain::lab::masks::Experiment;

pub fn run(args: &MasksArgs) -> Result<bool> {
    super::outputs::experiment_folder(&args.out, args.force)?;
    let n = args.mask.width as usize * args.mask.height as usize;
    let experiment =
        Experiment { n, objects: args.objects, trials: args.trials, alpha: args.alpha, k: args.k, seed: args.seed };
    masks::run(&MasksOptions { experiment, out: &args.out, json: args.report.json })?;
    Ok(true)
}
