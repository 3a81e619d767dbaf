//! `vbrain completions SHELL` and `vbrain manual --out DIR`: shell completion scripts and manual
//! pages generated from the clap definitions ([`super::Args`]), so they never drift from the
//! options.
//!
//! - Completion scripts go to standard output; manual pages into `DIR` (created if missing;
//!   existing pages are replaced).
//! - The packages ship both (scripts/package.sh).

use super::{Args, CompletionsArgs, ManualArgs};
use anyhow::{Context, Result};
use clap::CommandFactory;

pub fn completions(args: &CompletionsArgs) -> Result<bool> {
    let mut command = Args::command();
    clap_complete::generate(args.shell, &mut command, "vbrain", &mut std::io::stdout());
    Ok(true)
}

/// `vbrain.1`, and `vbrain-COMMAND.1` for each visible command (`vbrain-lesson-render.1` for
/// nested ones).
pub fn pages(args: &ManualArgs) -> Result<bool> {
    std::fs::create_dir_all(&args.out).with_context(|| format!("{}: cannot create the folder", args.out.display()))?;
    clap_mangen::generate_to(Args::command(), &args.out)
        .with_context(|| format!("{}: cannot write the manual pages", args.out.display()))?;
    println!("wrote the manual pages to {}", args.out.display());
    Ok(true)
}
