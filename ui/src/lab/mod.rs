//! The experiments behind the headless commands: each runs its measurement and reports it.
//!
//! - Each prints a summary (or with `--json` one object), and writes a CSV and a PNG plot
//!   ([`plot`]).
//! - They take plain options, never clap types: `cli` parses the arguments, and the checks that
//!   need more than one argument stay here.

pub mod bench;
pub mod k_analysis;
pub mod lod;
pub mod masks;
pub mod occluders;
pub mod plot;
pub mod sections_bench;
pub mod transparency_bench;

use anyhow::{anyhow, Result};
use std::path::Path;

/// The file that marks a folder as written by vbrain's experiments: their later runs write there
/// again without `--force` (`crate::cli::outputs::experiment_folder`).
pub const EXPERIMENT_MARK: &str = ".vbrain-experiments";

/// Makes the output folder `out`, checks that it takes files (a long run must not end on an
/// unwritable folder) and marks it as the experiments' own, before an experiment runs.
pub fn output_folder(out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| anyhow!("{}: {e}", out.display()))?;
    let note = "Results of vbrain's experiments: a later run writes its files here again.\n";
    vbrain::atomic::write(&out.join(EXPERIMENT_MARK), |w| w.write_all(note.as_bytes()))
        .map_err(|e| anyhow!("{}: cannot write there: {e}", out.display()))
}
