//! What the commands share: opening a set with its problems reported on stderr, applying
//! `--show`/`--hide`/`--opacity`, the summary of a written set, and progress bars.
//!
//! - Organs are named by organ id or group; a name the set has neither of is refused.
//! - A command that writes from a set leaves a broken organ out with a warning and exits 0;
//!   `info`, which checks a set, exits 1 for it.
//! - Text from a file is made safe to print on a terminal (`terminal_safe`): control characters
//!   written out, never sent raw.

use super::{LayoutArgs, SectionArgs};
use anyhow::{anyhow, bail, Result};
use serde_json::json;
use std::path::Path;
use vbrain::clip::{SavedSection, Section};
use vbrain::cull::database::Database;
use vbrain::layout::Layout;
use vbrain::organ_set::{self, Loaded, OrganSet};
use vbrain::scene_file::SceneFile;

/// Opens a set and reports its warnings and broken organs on stderr; true if nothing broke.
/// For `info`, which checks a set: a broken organ makes its exit status 1.
pub fn open_reporting(path: &Path) -> Result<(OrganSet, bool)> {
    open_labelled(path, "error: ", "")
}

/// Opens a set for a command that writes something from it (an image, a benchmark): a broken
/// organ is a warning and is left out, and the command goes on to exit 0, so that it never both
/// writes its output and reports failure.
pub fn open_set(path: &Path) -> Result<OrganSet> {
    Ok(open_labelled(path, "warning: ", " (left out)")?.0)
}

fn open_labelled(path: &Path, label: &str, left_out: &str) -> Result<(OrganSet, bool)> {
    let Loaded { set, errors, warnings } = organ_set::open(path).map_err(|e| anyhow!(e))?;
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    for e in &errors {
        eprintln!("{label}{e}{left_out}");
    }
    if set.organs.is_empty() {
        bail!("{}: no organ could be loaded", path.display());
    }
    Ok((set, errors.is_empty()))
}

/// The occluder database beside the set opened from `path`, if one fits it; a file there that
/// does not is a warning (culling then chooses occluders by projected size).
pub fn database(path: &Path, set: &OrganSet) -> Option<Database> {
    Database::load_for(path, set).unwrap_or_else(|e| {
        eprintln!("warning: {e}; occluders by projected size only");
        None
    })
}

/// The set's default layout with `--show`, `--hide` and `--opacity` applied, in that order.
pub fn layout(set: &OrganSet, args: &LayoutArgs) -> Result<Layout> {
    let mut layout = Layout::new(set);
    apply_layout_args(set, &mut layout, args)?;
    Ok(layout)
}

/// Applies `--show`, `--hide` and `--opacity` to a layout, in that order.
pub fn apply_layout_args(set: &OrganSet, layout: &mut Layout, args: &LayoutArgs) -> Result<()> {
    apply_visibility(set, layout, &args.show, &args.hide)?;
    for o in &args.opacity {
        if o.id == "all" {
            layout.organs.iter_mut().for_each(|s| s.opacity = o.opacity);
        } else {
            for i in organs(set, &o.id)? {
                layout.organs[i].opacity = o.opacity;
            }
        }
    }
    Ok(())
}

/// Applies `--colour-by` to a layout (of the set at `path`); territory colouring needs a set with
/// arterial territories.
pub fn apply_colour_by(
    set: &OrganSet,
    path: &std::path::Path,
    layout: &mut Layout,
    by: Option<vbrain::layout::ColourBy>,
) -> Result<()> {
    layout.colour_by = by.unwrap_or(layout.colour_by);
    if layout.colour_by == vbrain::layout::ColourBy::Territory && set.territories.is_none() {
        anyhow::bail!("{}: the set has no arterial territories to colour by", path.display());
    }
    Ok(())
}

/// Applies `--show` then `--hide` to a layout.
pub fn apply_visibility(set: &OrganSet, layout: &mut Layout, show: &[String], hide: &[String]) -> Result<()> {
    for (keys, visible) in [(show, true), (hide, false)] {
        for key in keys {
            for i in organs(set, key)? {
                layout.organs[i].visible = visible;
            }
        }
    }
    Ok(())
}

/// The cross-section `--clip`, `--caps`, `--cut-face`, `--window` and `--whole` give, each else
/// the scene's (caps default on), with at most [`vbrain::clip::MAX_PLANES`] planes: in the set, and as a scene file keeps it.
pub fn section(set: &OrganSet, args: &SectionArgs, scene: Option<&SceneFile>) -> Result<(Section, SavedSection)> {
    let saved = scene.map(SceneFile::section).unwrap_or(SavedSection { caps: true, ..Default::default() });
    let saved = SavedSection {
        planes: if args.clip.is_empty() { saved.planes } else { args.clip.clone() },
        caps: args.caps.unwrap_or(saved.caps),
        faces: vbrain::clip::CutFace {
            show: args.cut_face.unwrap_or(saved.faces.show),
            window: args.window.unwrap_or(saved.faces.window),
        },
        whole: if args.whole.is_empty() { saved.whole } else { args.whole.clone() },
    };
    if saved.planes.len() > vbrain::clip::MAX_PLANES {
        bail!("--clip: at most {} planes at once", vbrain::clip::MAX_PLANES);
    }
    let (section, unknown) = saved.resolve(set);
    if let Some(key) = unknown.first() {
        // The user's option is an error; a scene's stale name only a warning, as for its organs.
        if !args.whole.is_empty() {
            bail!("--whole: no organ with id \"{key}\" and no group of that name (see `vbrain info`)");
        }
        eprintln!("warning: the scene keeps \"{key}\" whole, which the set has no organ or group of; left out");
    }
    Ok((section, saved))
}

/// The organs `key` names: an id or a group ([`OrganSet::select`]).
pub fn organs(set: &OrganSet, key: &str) -> Result<Vec<usize>> {
    let found = set.select(key);
    if found.is_empty() {
        bail!("no organ with id \"{key}\" and no group of that name (see `vbrain info`)");
    }
    Ok(found)
}

/// Text from a file as a terminal may show it: control characters (escape sequences that would
/// recolour or clear the terminal, say) written out as `\u{1b}`, never sent raw.
pub fn terminal_safe(text: &str) -> String {
    text.chars().map(|c| if c.is_control() { c.escape_unicode().to_string() } else { c.to_string() }).collect()
}

/// Prints what a command wrote: organs and triangles (with `json`, as one object).
pub fn summary(json: bool, what: &str, set: &OrganSet, out: &Path) -> Result<bool> {
    if json {
        let organs: Vec<_> = set
            .organs
            .iter()
            .map(|o| json!({"id": o.id, "name": o.name, "triangles": o.mesh().triangle_count()}))
            .collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({"out": out, "organs": organs, "triangles": set.triangle_count()}))?
        );
    } else {
        println!("{what}: wrote {} organs, {} triangles to {}", set.organs.len(), set.triangle_count(), out.display());
    }
    Ok(true)
}

/// A progress bar on stderr: `{bar} {pos}/{len} {msg}`.
pub fn progress_bar(len: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) = indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}") {
        bar.set_style(style);
    }
    bar
}
