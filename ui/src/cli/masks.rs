//! `vbrain masks`: the mask experiment of thesis Figures 19/20 (see [`crate::lab::masks`]).
//!
//! - `--mask WxH` counts sub-samples (W x H of them); the arguments become the core's experiment,
//!   which the lab runs and writes into `--out`.

use crate::lab::masks::{self, MasksOptions};
use anyhow::Result;
use vbrain::lab::masks::Experiment;

#[derive(clap::Args)]
pub struct MasksArgs {
    /// Mask size, WxH sub-samples (the thesis: 16x16 and 32x32)
    #[arg(long, default_value = "16x16", value_parser = super::values::size)]
    pub mask: super::Size,
    /// Transparent objects stacked per trial, 1..=256
    #[arg(long, default_value_t = 16, value_parser = super::count(1, 256))]
    pub objects: usize,
    /// Trials, 1..=1000000
    #[arg(long, default_value_t = 1000, value_parser = super::count(1, 1_000_000))]
    pub trials: usize,
    /// One opacity for every object, 0..=1 (default: random per object)
    #[arg(long, value_parser = super::values::unit)]
    pub alpha: Option<f32>,
    /// Farther objects a new mask's error compensation weighs (the nearer ones all count, merged
    /// into one), 1..=64
    #[arg(long, default_value_t = vbrain::transparency::DEFAULT_K, value_parser = super::k())]
    pub k: usize,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub results: super::ExperimentOut,
    #[command(flatten)]
    pub report: super::Report,
}

pub fn run(args: &MasksArgs) -> Result<bool> {
    args.results.check()?;
    let n = args.mask.width as usize * args.mask.height as usize;
    let experiment =
        Experiment { n, objects: args.objects, trials: args.trials, alpha: args.alpha, k: args.k, seed: args.seed };
    masks::run(&MasksOptions { experiment, out: &args.results.out, json: args.report.json })?;
    Ok(true)
}
