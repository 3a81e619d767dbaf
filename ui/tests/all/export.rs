//! `vbrain export --gltf`: the default brain, cut, as a glTF file the Khronos validator passes
//! (run under Node.js from `scripts/gltf`, installed by `scripts/test.sh`), its organs, groups and
//! texts in the file, and a refusal for what it must not write over or cannot find.

use super::cli::{brain, vbrain};
use serde_json::Value;
use std::path::Path;
use std::process::Command;

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The JSON chunk of a GLB file.
fn gltf_json(glb: &[u8]) -> Value {
    assert_eq!(&glb[0..4], b"glTF");
    let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&glb[20..20 + len]).unwrap()
}

/// The Khronos validator's report on `file`; fails saying what to install where Node.js or the
/// validator is missing.
fn validate(file: &Path) -> Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/gltf/validate.mjs");
    let out = Command::new("node").arg(&script).arg(file).output().unwrap_or_else(|e| {
        panic!("could not run node ({e}): install Node.js (Debian: nodejs npm), then run scripts/test.sh")
    });
    assert!(
        !stderr(&out).contains("ERR_MODULE_NOT_FOUND"),
        "the glTF validator is not installed: run `npm ci --prefix scripts/gltf` (scripts/test.sh does)"
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("validator said: {e}: {}", stderr(&out)))
}

#[test]
fn the_default_brain_cut_coronally_exports_as_valid_gltf() {
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("brain.glb");
    let g = glb.to_str().unwrap();
    let o =
        vbrain(&["export", &brain(), "--gltf", g, "--clip", "coronal=-20", "--opacity", "precuneus_l=0.4", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let report = validate(&glb);
    assert_eq!(report["numErrors"], 0, "{report}");
    let bytes = std::fs::read(&glb).unwrap();
    let doc = gltf_json(&bytes);
    let nodes = doc["nodes"].as_array().unwrap();
    // Organs carry their ids and texts; the lobes are group nodes under the hemispheres.
    let organ = |id: &str| nodes.iter().find(|n| n["extras"]["id"] == id).unwrap_or_else(|| panic!("no {id}"));
    assert!(organ("thalamus_l")["extras"]["info"].as_str().is_some_and(|t| t.len() > 40));
    assert!(nodes.iter().any(|n| n["name"] == "Left hemisphere" && n.get("mesh").is_none()));
    // Skull and scalp are hidden by default: not exported.
    assert!(!nodes.iter().any(|n| n["extras"]["id"] == "skull"));
    // The summary counts the organs in the file: those the cut left something of.
    let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
    let with_mesh = nodes.iter().filter(|n| n.get("mesh").is_some()).count();
    assert_eq!(summary["organs"].as_u64(), Some(with_mesh as u64));
    assert!(with_mesh > 40 && with_mesh < 99, "{with_mesh} organs: those anterior of the plane are gone");
    // The cut: nothing of an organ lies anterior of y = -20 mm (organ space is world space here).
    let meshes = doc["meshes"].as_array().unwrap();
    for n in nodes.iter().filter(|n| n.get("mesh").is_some()) {
        let prim = &meshes[n["mesh"].as_u64().unwrap() as usize]["primitives"][0];
        let acc = &doc["accessors"][prim["attributes"]["POSITION"].as_u64().unwrap() as usize];
        assert!(acc["max"][1].as_f64().unwrap() <= -20.0 + 1e-3, "{} reaches {}", n["name"], acc["max"][1]);
    }
    // The faded gyrus is translucent, the rest opaque.
    let material = |id: &str| {
        let prim = &meshes[organ(id)["mesh"].as_u64().unwrap() as usize]["primitives"][0];
        doc["materials"][prim["material"].as_u64().unwrap() as usize].clone()
    };
    assert_eq!(material("precuneus_l")["alphaMode"], "BLEND");
    let alpha = material("precuneus_l")["pbrMetallicRoughness"]["baseColorFactor"][3].as_f64().unwrap();
    assert!((alpha - 0.4).abs() < 1e-6, "{alpha}");
    assert!(material("thalamus_l").get("alphaMode").is_none());
}

#[test]
fn export_refuses_to_overwrite_and_names_a_missing_set() {
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("brain.glb");
    std::fs::write(&glb, "mine").unwrap();
    let o = vbrain(&["export", &brain(), "--gltf", glb.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&glb).unwrap(), b"mine");
    // A scene whose set is gone.
    let scene = dir.path().join("s.vbscene");
    let png = dir.path().join("s.png");
    let saved = vbrain(&[
        "render",
        &brain(),
        "--size",
        "16x16",
        "--out",
        png.to_str().unwrap(),
        "--save-scene",
        scene.to_str().unwrap(),
    ]);
    assert!(saved.status.success(), "{}", stderr(&saved));
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    v["set"]["path"] = "no/such/set".into();
    std::fs::write(&scene, v.to_string()).unwrap();
    let out = dir.path().join("new.glb");
    let o = vbrain(&["export", scene.to_str().unwrap(), "--gltf", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("no/such/set"), "{}", stderr(&o));
    assert!(!out.exists());
}
