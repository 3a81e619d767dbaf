//! `vbrain anki`: an Anki deck of a set's structures ([`crate::anki`]), with a progress bar.

use super::common::{database, open_set};
use super::AnkiArgs;
use crate::anki::{self, DeckOptions};
use anyhow::{anyhow, bail, Result};
use std::time::Instant;

pub fn run(args: &AnkiArgs) -> Result<bool> {
    if args.out.exists() && !args.force {
        bail!("{}: exists (use --force to replace it)", args.out.display());
    }
    let path = vbrain::data_dir::set_or_default(args.set.as_deref())?;
    let set = open_set(&path)?;
    let scope = vbrain::quiz::scope(&set, args.group.as_deref()).map_err(|e| anyhow!(e))?;
    let opts = DeckOptions { scope, size: (args.size.width, args.size.height), views: args.views };
    let started = Instant::now();
    let bar = indicatif::ProgressBar::new(opts.scope.len() as u64);
    let (bytes, report) =
        anki::build(&set, database(&path, &set), &opts, &mut |done, _| bar.set_position(done as u64))?;
    bar.finish_and_clear();
    anki::write(&args.out, &bytes, args.force)?;
    let seconds = started.elapsed().as_secs_f64();
    if args.report.json {
        let out = serde_json::json!({"deck": args.out, "report": report, "seconds": seconds});
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "{}: {} notes of {} structures, {} pictures ({seconds:.1} s)",
            args.out.display(),
            report.notes,
            report.structures - report.unseen.len(),
            report.media
        );
        if !report.unseen.is_empty() {
            eprintln!("not shown from any view, left out: {}", report.unseen.join(", "));
        }
    }
    Ok(true)
}
