//! Loading organ sets: a folder with `organset.json`, a folder of mesh files, or one mesh file.
//!
//! - A broken organ, stand-in, solid or level file does not stop the rest: the organ is reported
//!   in [`super::Loaded::errors`] and left out, or loads without what was broken, with a warning.
//! - Paths in a manifest stay inside its folder ([`crate::input::inside`]).
//! - Without a manifest, every object (`o`/`g`) of every file is one organ, named after the
//!   object or file, with distinct colours.

use super::manifest::{self, Manifest, OrganEntry};
use super::{
    distinct_colour, hidden_faces, obj, slug, unique_id, Loaded, Organ, OrganSet, Solid, StandIn, MANIFEST_FILE,
};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use std::path::{Path, PathBuf};

/// Opens an organ set folder, a folder of mesh files, or one mesh file.
pub fn open(path: &Path) -> Result<Loaded> {
    let meta = std::fs::metadata(path).map_err(|e| Error::io(path, e))?;
    if meta.is_dir() {
        let manifest = path.join(MANIFEST_FILE);
        // Present in any form (a FIFO, a link to nothing), it is read, and refused with its reason.
        if manifest.symlink_metadata().is_ok() {
            open_manifest(&manifest)
        } else {
            open_files(&mesh_files_in(path)?, &title_of(path))
        }
    } else if path.file_name().is_some_and(|n| n == MANIFEST_FILE) {
        open_manifest(path)
    } else {
        open_files(&[path.to_path_buf()], &title_of(path))
    }
}

fn title_of(path: &Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "organs".into())
}

/// Is this a mesh file vbrain reads (by extension)?
pub fn is_mesh_file(p: &Path) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("obj") || e.eq_ignore_ascii_case("vbo"))
}

fn mesh_files_in(dir: &Path) -> Result<Vec<PathBuf>> {
    let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
    let mut files: Vec<PathBuf> =
        entries.filter_map(|e| e.ok()).map(|e| e.path()).filter(|p| p.is_file() && is_mesh_file(p)).collect();
    files.sort();
    if files.is_empty() {
        return Err(Error::parse(dir, None, format!("no {MANIFEST_FILE} and no .obj or .vbo files in this folder")));
    }
    Ok(files)
}

/// Reads the manifest; a problem with the manifest itself is fatal, a problem with one organ is not.
pub fn open_manifest(path: &Path) -> Result<Loaded> {
    let text = crate::input::read_text(path, crate::input::Kind::Manifest)?;
    let manifest: Manifest =
        serde_json::from_str(&text).map_err(|e| Error::parse(path, Some(e.line()), e.to_string()))?;
    let problems = manifest.validate();
    if !problems.is_empty() {
        return Err(Error::parse(path, None, problems.join("; ")));
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut loaded = Loaded::default();
    let mut seen = std::collections::HashSet::new();
    // On rayon's pool (a thread per core), not a thread per organ.
    let results: Vec<Result<(Organ, Vec<String>)>> = {
        use rayon::prelude::*;
        manifest
            .organs
            .par_iter()
            .map(|entry| {
                std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| load_entry(entry, dir, path)))
                    .unwrap_or_else(|_| Err(Error::LoaderPanicked { path: path.to_path_buf() }))
            })
            .collect()
    };
    for (entry, result) in manifest.organs.iter().zip(results) {
        match result {
            Ok((organ, warnings)) if seen.insert(organ.id.clone()) => {
                loaded.warnings.extend(warnings);
                loaded.set.organs.push(organ);
            }
            Ok(_) => loaded.errors.push(Error::parse(path, None, format!("organ id \"{}\" appears twice", entry.id))),
            Err(e) => loaded.errors.push(e),
        }
    }
    loaded.set.solids = load_solids(&manifest.solids, &loaded.set.organs, dir, &mut loaded.warnings);
    loaded.set.keep_hidden_faces_apart();
    loaded.set.index_hidden_faces();
    if let Some(file) = &manifest.mri {
        let bounds = loaded.set.bounds();
        match manifest::mesh_path_ok(file)
            .map_err(|e| Error::parse(path, None, format!("mri {file}: {e}")))
            .and_then(|_| crate::input::inside(dir, file))
            .and_then(|p| crate::mri::Mri::open(&p, &bounds))
        {
            Ok(mri) => loaded.set.mri = Some(std::sync::Arc::new(mri)),
            Err(e) => loaded.errors.push(e),
        }
    }
    if let Some(file) = &manifest.territories {
        match manifest::mesh_path_ok(file)
            .map_err(|e| Error::parse(path, None, format!("territories {file}: {e}")))
            .and_then(|_| super::territory::Territories::open(dir, file))
        {
            Ok(t) => loaded.set.territories = Some(std::sync::Arc::new(t)),
            Err(e) => loaded.errors.push(e),
        }
    }
    loaded.set.title = manifest.title;
    loaded.set.description = manifest.description;
    loaded.set.sources = manifest.sources;
    Ok(loaded)
}

/// The solids of a manifest over the organs that loaded. A solid naming an organ that is not there,
/// or whose stand-in does not load, costs only speed: it is left out, with a warning.
fn load_solids(
    entries: &[manifest::SolidEntry],
    organs: &[Organ],
    dir: &Path,
    warnings: &mut Vec<String>,
) -> Vec<Solid> {
    let mut solids: Vec<Solid> = Vec::new();
    for entry in entries {
        let ids: Option<Vec<usize>> = entry.organs.iter().map(|id| organs.iter().position(|o| &o.id == id)).collect();
        let problem = if !manifest::id_ok(&entry.id) {
            Some("not a valid id".to_string())
        } else if solids.iter().any(|s| s.id == entry.id) {
            Some("appears twice".to_string())
        } else if ids.is_none() || entry.organs.is_empty() {
            Some("names no organ, or one the set does not have".to_string())
        } else {
            let path_problem = |field: &str, p: &Option<String>| {
                p.as_deref().and_then(|p| manifest::mesh_path_ok(p).err().map(|e| format!("{field} {p}: {e}")))
            };
            path_problem("occluder", &entry.occluder).or_else(|| path_problem("hidden", &entry.hidden))
        };
        if let Some(problem) = problem {
            warnings.push(format!("solid \"{}\" ignored: {problem}", entry.id));
            continue;
        }
        let mut members = ids.unwrap_or_default();
        members.sort_unstable();
        members.dedup();
        let owner = format!("solid \"{}\"", entry.id);
        let stand_in = entry.occluder.as_ref().and_then(|p| read_stand_in(dir, p, &owner, warnings));
        // Broken or stale, they cost only speed.
        let hidden = match &entry.hidden {
            Some(p) => crate::input::inside(dir, p)
                .map_err(|e| e.to_string())
                .and_then(|path| hidden_faces::read(&path, organs, &members))
                .unwrap_or_else(|why| {
                    warnings.push(format!("{owner}: its hidden faces are not used: {why}"));
                    Vec::new()
                }),
            None => Vec::new(),
        };
        solids.push(Solid { id: entry.id.clone(), organs: members, stand_in, hidden });
    }
    solids
}

/// Reads an occluder stand-in (of `owner`, for the warnings), or warns and gives none: a broken
/// stand-in costs only speed.
fn read_stand_in(dir: &Path, path: &str, owner: &str, warnings: &mut Vec<String>) -> Option<StandIn> {
    match crate::input::inside(dir, path).and_then(|p| obj::read(&p)) {
        Ok(f) => {
            warnings.extend(f.warnings);
            let mut mesh = Mesh::default();
            f.objects.iter().for_each(|o| mesh.append(&o.mesh));
            Some(StandIn::new(mesh))
        }
        Err(e) => {
            warnings.push(format!("{owner}: occluder stand-in ignored: {e}"));
            None
        }
    }
}

fn load_entry(entry: &OrganEntry, dir: &Path, manifest_path: &Path) -> Result<(Organ, Vec<String>)> {
    entry.validate().map_err(|m| Error::parse(manifest_path, None, m.to_string()))?;
    let file = obj::read(&crate::input::inside(dir, &entry.mesh)?)?;
    let mut mesh = Mesh::default();
    for o in &file.objects {
        mesh.append(&o.mesh);
    }
    let colour = manifest::parse_colour(&entry.colour).unwrap_or([0.8; 3]);
    let mut warnings = file.warnings;
    // A broken stand-in costs only speed: the organ occludes with its own triangles.
    let owner = format!("organ \"{}\"", entry.id);
    let stand_in = entry.occluder.as_ref().and_then(|p| read_stand_in(dir, p, &owner, &mut warnings));
    // Broken or stale levels cost only speed while moving: the organ is drawn whole.
    let (vertices, indices) = (mesh.positions.len(), mesh.indices.len());
    let lods = match entry
        .lod
        .as_ref()
        .map(|p| crate::input::inside(dir, p).and_then(|p| crate::lod::read(&p, vertices, indices)))
    {
        Some(Ok(levels)) => levels,
        Some(Err(e)) => {
            warnings.push(format!("{owner}: levels of detail ignored: {e}"));
            Vec::new()
        }
        None => Vec::new(),
    };
    let organ = Organ {
        stand_in,
        lods,
        group: entry.group.clone(),
        opacity: entry.opacity,
        visible: entry.visible,
        latin: entry.latin.clone(),
        synonyms: entry.synonyms.clone(),
        info: entry.info.clone(),
        ..Organ::new(entry.id.clone(), entry.name.clone(), colour, mesh)
    };
    Ok((organ, warnings))
}

/// One organ per object of each file; a broken file is reported and skipped.
pub fn open_files(files: &[PathBuf], title: &str) -> Result<Loaded> {
    let mut loaded = Loaded { set: OrganSet { title: title.into(), ..Default::default() }, ..Default::default() };
    let mut ids = std::collections::HashSet::new();
    for f in files {
        match obj::read(f) {
            Ok(file) => {
                loaded.warnings.extend(file.warnings);
                let group = if files.len() > 1 { title_of(f) } else { String::new() };
                for o in file.objects {
                    let id = unique_id(&slug(&o.name), &mut ids);
                    let colour = distinct_colour(loaded.set.organs.len());
                    loaded.set.organs.push(Organ { group: group.clone(), ..Organ::new(id, o.name, colour, o.mesh) });
                }
            }
            Err(e) => loaded.errors.push(e),
        }
    }
    Ok(loaded)
}
