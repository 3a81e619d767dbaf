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
    /// Folder for transparency.csv, transparency.png and transparency-sheet.png
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Write into --out even where it holds files no vbrain experiment wrote (only the
    /// experiment's own files are replaced)
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub report: super::Report,
}

pub fn run(args: &BenchTransparencyArgs) -> Result<bool> {
    super::outputs::experiment_folder(&args.out, args.force)?;
    let set = open_set(&args.path)?;
    let size = (args.size.width, args.size.height);
    crate::lab::transparency_bench::run(&set, size, args.region, &args.out, args.report.json)?;
    Ok(true)
}
