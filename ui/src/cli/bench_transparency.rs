//! `vbrain bench-transparency`: the transparency modes against the exact reference (see
//! [`crate::lab::transparency_bench`]).
//!
//! - Only opens the set and passes the size, mask region, output folder and `--json` on; the lab
//!   measures and writes.

use super::common::open_set;
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct BenchTransparencyArgs {
    pub path: PathBuf,
    /// Image size, WxH
    #[arg(long, default_value = "384x384", value_parser = super::values::size)]
    pub size: super::Size,
    /// Screen-door mask region side in pixels
    #[arg(long, default_value_t = vbrain::transparency::TransparencySettings::default().region_px, value_parser = super::region())]
    pub region: u32,
    #[command(flatten)]
    pub results: super::ExperimentOut,
    #[command(flatten)]
    pub report: super::Report,
}

pub fn run(args: &BenchTransparencyArgs) -> Result<bool> {
    args.results.check()?;
    let set = open_set(&args.path)?;
    let size = (args.size.width, args.size.height);
    crate::lab::transparency_bench::run(&set, size, args.region, &args.results.out, args.report.json)?;
    Ok(true)
}
