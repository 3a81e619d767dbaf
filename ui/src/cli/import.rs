//! `vbrain import`: a label volume (NIfTI) and its label table become an organ set.
//!
//! - Written into `--out`, refusing a folder that already holds files unless `--force`.
//! - The label table's and the import's warnings go to stderr.

use super::common::{progress_bar, summary};
use super::ImportArgs;
use anyhow::Result;
use vbrain::organ_set::import;

pub fn run(args: &ImportArgs) -> Result<bool> {
    super::outputs::folder(&args.out.out, args.out.force, &[&args.volume, &args.labels])?;
    let table = import::read_label_table(&args.labels)?;
    let vol = import::read_volume(&args.volume)?;
    let title = args.title.clone().unwrap_or_else(|| {
        let name = args.volume.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        name.trim_end_matches(".gz").trim_end_matches(".nii").to_string()
    });
    let opts = import::ImportOptions { triangles: args.triangles, smoothing: args.smooth, title };
    let bar = progress_bar(1);
    let mut progress = |done: usize, total: usize, what: &str| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
        bar.set_message(what.to_string());
    };
    let import = if args.seamless { import::import_seamless } else { import::import };
    let (set, warnings) = import(&vol, &table.labels, &opts, &mut progress)?;
    bar.finish_and_clear();
    for w in table.warnings.iter().chain(&warnings) {
        eprintln!("warning: {w}");
    }
    set.save(&args.out.out)?;
    summary(args.report.json, "import", &set, &args.out.out)
}
