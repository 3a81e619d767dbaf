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

/// Makes the output folder `out` and checks that it takes files, before an experiment runs (a
/// long run must not end on an unwritable folder).
pub fn output_folder(out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).map_err(|e| anyhow!("{}: {e}", out.display()))?;
    let probe = out.join(format!(".vbrain-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| anyhow!("{}: cannot write there: {e}", out.display()))?;
    std::fs::remove_file(&probe).map_err(|e| anyhow!("{}: {e}", probe.display()))
}
