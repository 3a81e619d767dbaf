//! `vbrain info`: the organs of a set, their triangles and bounds.
//!
//! - Bounds are in world RAS millimetres.
//! - It checks the set: a broken organ is reported on stderr and makes the exit status 1.
//! - Text from the set is printed terminal-safe (control characters written out, never raw).

use super::common::open_reporting;
use super::InfoArgs;
use anyhow::Result;
use serde_json::json;

pub fn run(args: &InfoArgs) -> Result<bool> {
    let path = vbrain::data_dir::set_or_default(args.path.as_deref())?;
    let (set, ok) = open_reporting(&path)?;
    let bounds = set.bounds();
    if args.report.json {
        let organs: Vec<_> = set
            .organs
            .iter()
            .map(|o| {
                json!({
                    "id": o.id, "name": o.name, "group": o.group, "latin": o.latin, "synonyms": o.synonyms,
                    "info": o.info, "triangles": o.mesh().triangle_count(),
                    "vertices": o.mesh().positions.len(), "bounds": o.mesh().bounds(),
                })
            })
            .collect();
        let out = json!({ "title": set.title, "path": path, "organs": organs, "triangles": set.triangle_count(), "bounds": bounds });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        let shown = super::common::terminal_safe;
        println!("{}: {} organs, {} triangles", shown(&set.title), set.organs.len(), set.triangle_count());
        println!("from {}", path.display());
        println!("bounds (mm, RAS): {:?} .. {:?}", bounds.min, bounds.max);
        for o in &set.organs {
            println!("  {:<28} {:>8} triangles  {}", o.id, o.mesh().triangle_count(), shown(&o.name));
        }
    }
    Ok(ok)
}
