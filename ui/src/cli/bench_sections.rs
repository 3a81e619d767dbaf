//! `vbrain bench-sections`: slice panes and MRI cut faces ([`crate::lab::sections_bench`]).
//!
//! - Needs a set with an MRI (default: the default brain); a set without one is refused.
//! - Prints the slice pane's median and slowest redraw, and a coronally cut frame's time with
//!   coloured and with MRI cut faces, in milliseconds; with `--json`, the report as one object.

use super::common::open_set;
use super::{count, values, Report, Size};
use anyhow::Result;
use std::path::PathBuf;

#[derive(clap::Args)]
pub struct BenchSectionsArgs {
    /// Organ set with an MRI [default: the default brain]
    pub path: Option<PathBuf>,
    /// Slice positions, and frames of each kind of cut face, 3..=1000
    #[arg(long, default_value_t = 30, value_parser = count(3, 1000))]
    pub frames: usize,
    /// The 3-D frames' size, WxH
    #[arg(long, default_value = "1024x768", value_parser = values::size)]
    pub size: Size,
    #[command(flatten)]
    pub report: Report,
}
pub fn run(args: &BenchSectionsArgs) -> Result<bool> {
    let path = match &args.path {
        Some(p) => p.clone(),
        None => vbrain::data_dir::default_set()?,
    };
    let set = open_set(&path)?;
    if set.mri.is_none() {
        anyhow::bail!("{}: has no MRI; bench-sections measures MRI cut faces and slices", path.display());
    }
    let r = crate::lab::sections_bench::run(&set, args.frames, [args.size.width, args.size.height])?;
    if args.report.json {
        println!("{}", serde_json::to_string_pretty(&r)?);
    } else {
        println!(
            "slice pane {0}x{0}: {1:.2} ms median, {2:.2} ms slowest; {3}x{4} frame cut coronally: \
             coloured cut faces {5:.2} ms, MRI cut faces {6:.2} ms ({7:.3}x) on {8}",
            r.pane_px,
            r.slice_ms_median,
            r.slice_ms_max,
            r.size[0],
            r.size[1],
            r.colour_faces_ms,
            r.mri_faces_ms,
            r.mri_over_colour,
            r.adapter
        );
    }
    Ok(true)
}
