//! `vbrain stand-ins`: occluder stand-ins for a set's closed organs, and for each solid a
//! stand-in and the faces inside it ([`vbrain::organ_set::hidden_faces`]).
//!
//! - An organ's stand-in is a coarse mesh inside it (offset inward, simplified, each triangle
//!   verified inside) that occlusion culling rasterises in the organ's place; kept only with at
//!   most half the organ's triangles.
//! - A solid's stand-in lies inside its organs' union (kept on the same terms); culling leaves
//!   the faces inside it out while the solid is intact.
//! - Offsets are in millimetres. Written into the set's own folder (only the stand-ins and the
//!   manifest), or into `--out`, refusing a folder that already holds files unless `--force`.

use super::common::{open_set, progress_bar};
use super::StandInsArgs;
use anyhow::{bail, Result};
use serde_json::json;
use vbrain::organ_set::{self, stand_in};

/// Builds an inner stand-in for every closed organ of at least `--min-triangles`, keeps those with at
/// most half the organ's triangles, and saves them (in place: only the stand-ins and the manifest).
pub fn run(args: &StandInsArgs) -> Result<bool> {
    let (path, ratio, offset, min_triangles) = (args.path.as_path(), args.ratio, args.offset, args.min_triangles);
    let (out, json) = (args.out.as_deref(), args.report.json);
    if !(ratio > 0.0 && ratio <= 0.5) {
        bail!("--ratio {ratio} outside (0, 0.5]");
    }
    if !(offset > 0.0 && offset.is_finite()) {
        bail!("--offset {offset} must be a positive number of millimetres");
    }
    if !(args.solid_offset > 0.0 && args.solid_offset.is_finite()) {
        bail!("--solid-offset {} must be a positive number of millimetres", args.solid_offset);
    }
    if let Some(out) = out {
        super::outputs::folder(out, args.force, &[path])?;
    }
    if out.is_none() && !path.join(organ_set::MANIFEST_FILE).is_file() {
        bail!("{}: not an organ set folder (no {}); give --out", path.display(), organ_set::MANIFEST_FILE);
    }
    let mut set = open_set(path)?;
    if let Some(id) = args.no_faces_inside.iter().find(|id| !set.solids.iter().any(|s| &s.id == *id)) {
        bail!("--no-faces-inside {id}: the set has no solid of that id");
    }
    let bar = progress_bar(set.organs.len() as u64);
    // Per organ tried: id, triangles, and what became of its stand-in.
    let mut rows: Vec<(String, usize, Outcome)> = Vec::new();
    for organ in &mut set.organs {
        bar.set_message(organ.id.clone());
        bar.inc(1);
        let triangles = organ.mesh().triangle_count();
        if triangles < min_triangles {
            continue;
        }
        let options = stand_in::InnerOptions { triangles: (triangles as f64 * ratio) as usize, offset };
        let built = stand_in::build_inner(organ.mesh(), organ.bvh(), options);
        let outcome = keep_coarse(built, triangles, |s| organ.set_stand_in(Some(s)));
        rows.push((organ.id.clone(), triangles, outcome));
    }
    // Each solid: a stand-in inside the union of its organs.
    for solid in 0..set.solids.len() {
        let members: Vec<&vbrain::mesh::Mesh> =
            set.solids[solid].organs.iter().map(|&o| set.organs[o].mesh()).collect();
        let mut mesh = stand_in::union_surface(&members);
        let triangles = mesh.triangle_count();
        let bvh = vbrain::bvh::Bvh::build(&mut mesh);
        let options = stand_in::InnerOptions { triangles: args.solid_triangles, offset: args.solid_offset };
        let built = stand_in::build_inner(&mesh, &bvh, options);
        let outcome = keep_coarse(built, triangles, |s| set.solids[solid].set_stand_in(Some(s)));
        rows.push((format!("solid {}", set.solids[solid].id), triangles, outcome));
    }
    // Each solid: the faces of its organs no ray from outside reaches while it is intact.
    let mut hidden = organ_set::hidden_faces::find(&set, |s| bar.set_message(format!("faces inside {}", s.id)));
    for (solid, faces) in set.solids.iter().zip(&mut hidden) {
        if args.no_faces_inside.contains(&solid.id) {
            faces.clear();
        }
    }
    let inside: Vec<(String, usize)> = set
        .solids
        .iter()
        .zip(&hidden)
        .map(|(s, faces)| (s.id.clone(), faces.iter().flat_map(|(_, r)| r).map(|r| r.len()).sum()))
        .collect();
    set.set_hidden_faces(hidden);
    bar.finish_and_clear();
    let out = match out {
        Some(out) => {
            set.save(out)?;
            out
        }
        None => {
            set.save_stand_ins(path)?;
            path
        }
    };
    if json {
        let organs: Vec<_> = rows
            .iter()
            .map(|(id, triangles, outcome)| match outcome {
                Outcome::Built { triangles: n, left_out } => {
                    json!({"id": id, "triangles": triangles, "stand_in": n, "left_out": left_out})
                }
                Outcome::Skipped(why) => json!({"id": id, "triangles": triangles, "skipped": why}),
            })
            .collect();
        let hidden: Vec<_> = inside.iter().map(|(id, n)| json!({"solid": id, "hidden_faces": n})).collect();
        println!("{}", serde_json::to_string_pretty(&json!({"out": out, "organs": organs, "hidden_faces": hidden}))?);
    } else {
        for (id, triangles, outcome) in &rows {
            match outcome {
                Outcome::Built { triangles: n, left_out } => {
                    println!("{id:<24} {triangles:>8} triangles -> {n:>6} (left out {left_out})")
                }
                Outcome::Skipped(why) => println!("{id:<24} {triangles:>8} triangles: none ({why})"),
            }
        }
        for (id, n) in &inside {
            println!("solid {id:<18} {n:>8} faces inside it (hidden while it is intact)");
        }
        println!("stand-ins: wrote {}", out.display());
    }
    Ok(true)
}

/// A stand-in built for `triangles` triangles (an organ's, or a solid's organs'), handed to `keep`
/// only with at most half of them: a larger one saves the occluder raster too little work (the
/// cerebellum's halves: 2,343 triangles for 2,624).
fn keep_coarse(
    built: Result<stand_in::Inner, stand_in::StandInError>,
    triangles: usize,
    keep: impl FnOnce(vbrain::organ_set::StandIn),
) -> Outcome {
    match built {
        Ok(built) if 2 * built.stand_in.mesh().triangle_count() > triangles => {
            Outcome::Skipped(format!("{} triangles, not under half", built.stand_in.mesh().triangle_count()))
        }
        Ok(built) => {
            let outcome = Outcome::Built { triangles: built.stand_in.mesh().triangle_count(), left_out: built.dropped };
            keep(built.stand_in);
            outcome
        }
        Err(why) => Outcome::Skipped(why.to_string()),
    }
}

/// What became of one organ's or solid's stand-in.
enum Outcome {
    /// Kept: its triangles, and the simplified triangles that failed verification (left out).
    Built { triangles: usize, left_out: usize },
    /// None, and why.
    Skipped(String),
}
