//! `vbrain occluders`: minimum occluder sets pre-computed beside a set, or with `--experiment`
//! the occluder-selection experiment (see [`crate::lab::occluders`]).
//!
//! - The layout is the set's default with `--show` and `--hide` applied.
//! - The pre-computed sets are written beside the set (`occluders.json`).

use super::common::{apply_visibility, open_set};
use super::OccludersArgs;
use crate::lab::occluders::{self, Options};
use anyhow::Result;
use vbrain::layout::Layout;

pub fn run(args: &OccludersArgs) -> Result<bool> {
    let set = open_set(&args.path)?;
    let mut layout = Layout::new(&set);
    apply_visibility(&set, &mut layout, &args.show, &args.hide)?;
    let opts = Options {
        grid: args.grid,
        params: vbrain::mos::Params { size: args.raster, limit: args.limit, ..Default::default() },
        views: args.views,
        image: args.image,
        out: &args.results.out,
        json: args.report.json,
    };
    if args.experiment {
        args.results.check()?;
        occluders::experiment(&set, &layout, &opts)?;
    } else {
        occluders::preprocess(&args.path, &set, &layout, &opts)?;
    }
    Ok(true)
}
