//! `vbrain export`: a scene or a set as a binary glTF 2.0 file (`--gltf OUT.glb`) for Blender,
//! slides and web viewers: the organs it shows, with their names, colours, opacities, transforms,
//! groups and info texts, cut by its clip planes with solid cut faces ([`vbrain::gltf`]).

use super::common::{apply_layout_args, open_set, section};
use super::ExportArgs;
use anyhow::{anyhow, bail, Result};
use serde_json::json;
use vbrain::layout::Layout;
use vbrain::scene_file::SceneFile;

pub fn run(args: &ExportArgs) -> Result<bool> {
    let out = &args.gltf;
    if out.is_dir() {
        bail!("{}: is a folder; give a file name ending in .glb", out.display());
    }
    if out.exists() && !args.force {
        bail!("{}: already exists; give --force to replace it", out.display());
    }
    let is_scene = args.path.extension().is_some_and(|e| e == vbrain::scene_file::EXTENSION);
    let scene = if is_scene { Some(SceneFile::load(&args.path).map_err(|e| anyhow!(e))?) } else { None };
    let set_path = scene.as_ref().map_or_else(|| args.path.clone(), |s| s.set_path(&args.path));
    if scene.is_some() && !set_path.exists() {
        bail!("{}: the scene's organ set {} is not there", args.path.display(), set_path.display());
    }
    let set = open_set(&set_path)?;
    let mut layout = Layout::new(&set);
    if let Some(s) = &scene {
        let applied = s.apply(&set);
        for w in &applied.warnings {
            eprintln!("warning: {}: {w}", args.path.display());
        }
        layout = applied.layout;
    }
    apply_layout_args(&set, &mut layout, &args.layout)?;
    let (section, _) = section(&set, &args.section, scene.as_ref())?;
    let glb = vbrain::gltf::glb(&set, &layout, &section);
    vbrain::atomic::write(out, |w| w.write_all(&glb.bytes)).map_err(|e| anyhow!(e))?;
    if args.json {
        println!("{}", json!({"out": out, "bytes": glb.bytes.len(), "organs": glb.organs}));
    } else {
        println!("wrote {} ({} organs, {:.1} MB)", out.display(), glb.organs, glb.bytes.len() as f64 / 1e6);
    }
    Ok(true)
}
