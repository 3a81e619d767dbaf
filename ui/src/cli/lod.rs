//! `vbrain lod`: each organ's levels of detail ([`vbrain::lod`]), built with meshopt and written
//! into the set's own folder, for the viewer to draw while the view moves.
//!
//! - Written as `meshes/ID.lod` beside the meshes, and named in the manifest (only the organs'
//!   `lod` fields change); built over the meshes as this run loads them, so after a mesh changes
//!   the command runs again (a stale file is refused at load with that advice).
//! - Organs of fewer than [`vbrain::lod::MIN_TRIANGLES`] triangles get none.

use super::common::open_set;
use anyhow::{bail, Result};
use serde_json::json;
use std::path::PathBuf;
use vbrain::organ_set;

#[derive(clap::Args)]
pub struct LodArgs {
    /// The organ set's folder (its levels are written there)
    pub path: PathBuf,
    #[command(flatten)]
    pub report: super::Report,
}

pub fn run(args: &LodArgs) -> Result<bool> {
    let path = args.path.as_path();
    if !path.join(organ_set::MANIFEST_FILE).is_file() {
        bail!("{}: not an organ set folder (no {})", path.display(), organ_set::MANIFEST_FILE);
    }
    let mut set = open_set(path)?;
    set.build_lods();
    set.save_lods(path)?;
    let rows: Vec<_> = set
        .organs
        .iter()
        .map(|o| (o.id.as_str(), o.mesh().triangle_count(), o.lods().iter().map(|l| l.len() / 3).collect::<Vec<_>>()))
        .collect();
    let full: usize = rows.iter().map(|r| r.1).sum();
    // The set's triangles with every organ at level k, or its coarsest where it has fewer.
    let per_level: Vec<usize> = (1..=vbrain::lod::RATIOS.len())
        .map(|k| rows.iter().map(|(_, t, levels)| levels.get(k - 1).or(levels.last()).copied().unwrap_or(*t)).sum())
        .collect();
    if args.report.json {
        let organs: Vec<_> =
            rows.iter().map(|(id, t, levels)| json!({"id": id, "triangles": t, "levels": levels})).collect();
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({"organs": organs, "triangles": full, "levels": per_level}))?
        );
    } else {
        let with = rows.iter().filter(|r| !r.2.is_empty()).count();
        let levels: Vec<String> = per_level.iter().map(|t| t.to_string()).collect();
        println!(
            "{}: levels for {with} of {} organs; {full} triangles in all, {} at each level",
            path.display(),
            rows.len(),
            levels.join(" and ")
        );
    }
    Ok(true)
}
