//! `vbrain stand-ins`: occluder stand-ins for a set's closed organs. Each is a coarse mesh inside
//! its organ (offset inward, simplified, each triangle verified inside) that occlusion culling
//! rasterises in the organ's place; kept only with at most half the organ's triangles.

use super::common::{open_reporting, progress_bar};
use super::StandInsArgs;
use anyhow::{bail, Result};
use serde_json::json;
use vbrain::organ_set::{self, stand_in};

/// Builds an inner stand-in for every closed organ of at least `--min-triangles`, keeps those with at
/// most half the organ's triangles, and saves them (in place: only the stand-ins and the manifest).
pub fn run(args: &StandInsArgs) -> Result<bool> {
    let (path, ratio, offset, min_triangles) = (args.path.as_path(), args.ratio, args.offset, args.min_triangles);
    let (out, json) = (args.out.as_deref(), args.json);
    if !(ratio > 0.0 && ratio <= 0.5) {
        bail!("--ratio {ratio} outside (0, 0.5]");
    }
    if !(offset > 0.0 && offset.is_finite()) {
        bail!("--offset {offset} must be a positive number of millimetres");
    }
    if out.is_none() && !path.join(organ_set::MANIFEST_FILE).is_file() {
        bail!("{}: not an organ set folder (no {}); give --out", path.display(), organ_set::MANIFEST_FILE);
    }
    let (mut set, ok) = open_reporting(path)?;
    let bar = progress_bar(set.organs.len() as u64);
    // Per organ tried: id, triangles, and the stand-in's triangles and those left out, or why none.
    type Row = (String, usize, std::result::Result<(usize, usize), String>);
    let mut rows: Vec<Row> = Vec::new();
    for organ in &mut set.organs {
        bar.set_message(organ.id.clone());
        bar.inc(1);
        let triangles = organ.mesh.triangle_count();
        if triangles < min_triangles {
            continue;
        }
        let options = stand_in::InnerOptions { triangles: (triangles as f64 * ratio) as usize, offset };
        let result = stand_in::build_inner(&organ.mesh, &organ.bvh, options).and_then(|built| {
            let n = built.stand_in.mesh.triangle_count();
            if 2 * n > triangles {
                return Err(format!("{n} triangles, not under half"));
            }
            organ.stand_in = Some(built.stand_in);
            Ok((n, built.dropped))
        });
        rows.push((organ.id.clone(), triangles, result));
    }
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
            .map(|(id, triangles, r)| match r {
                Ok((n, dropped)) => json!({"id": id, "triangles": triangles, "stand_in": n, "left_out": dropped}),
                Err(why) => json!({"id": id, "triangles": triangles, "skipped": why}),
            })
            .collect();
        println!("{}", serde_json::to_string_pretty(&json!({"out": out, "organs": organs}))?);
    } else {
        for (id, triangles, r) in &rows {
            match r {
                Ok((n, dropped)) => println!("{id:<24} {triangles:>8} triangles -> {n:>6} (left out {dropped})"),
                Err(why) => println!("{id:<24} {triangles:>8} triangles: none ({why})"),
            }
        }
        println!("stand-ins: wrote {}", out.display());
    }
    Ok(ok)
}
