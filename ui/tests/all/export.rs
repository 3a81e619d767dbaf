//! `vbrain export`: the default brain, cut, as a glTF file the Khronos validator passes, its
//! organs, groups and texts in the file; the default brain and a shipped lesson as web pages that
//! headless Chromium opens from their files and a student uses (click, hide, next, previous); names
//! that HTML must escape staying text; and refusals for what must not be written over or cannot be
//! found. The checkers run under Node.js from `scripts/web` (`scripts/test.sh` installs them).

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
    node("validate.mjs", &[file])
}

/// What `scripts/web/page-test.mjs` saw of the page in `dir` (and a screenshot beside it).
fn open_page(dir: &Path) -> Value {
    open_page_at(dir, None)
}

/// [`open_page`], also measuring at a lesson's step what its cut faces draw.
fn open_page_at(dir: &Path, step: Option<usize>) -> Value {
    let shot = dir.with_extension("png");
    let step = step.map(|k| std::path::PathBuf::from(k.to_string()));
    let mut args = vec![dir, shot.as_path()];
    args.extend(step.as_deref());
    let seen = node("page-test.mjs", &args);
    assert_eq!(seen["errors"], serde_json::json!([]), "{seen}");
    seen
}

/// One checker at a time: several headless Chromiums at once on a small machine run past the
/// pages' timeouts.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Runs a checker of `scripts/web` under Node.js and reads the JSON it prints.
pub(crate) fn node(script: &str, args: &[&Path]) -> Value {
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/web").join(script);
    let out = Command::new("node").arg(&script).args(args).output().unwrap_or_else(|e| {
        panic!("could not run node ({e}): install Node.js (Debian: nodejs npm), then run scripts/test.sh")
    });
    assert!(
        !stderr(&out).contains("ERR_MODULE_NOT_FOUND"),
        "the checkers are not installed: run `npm ci --prefix scripts/web` (scripts/test.sh does)"
    );
    assert!(
        !stderr(&out).contains("Failed to launch"),
        "Chromium did not start: install Debian's chromium or set CHROMIUM (scripts/test.sh does): {}",
        stderr(&out)
    );
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{} said: {e}: {}", script.display(), stderr(&out)))
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
    assert_eq!(summary["gltf"]["organs"].as_u64(), Some(with_mesh as u64));
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

#[test]
fn the_default_brain_and_a_lesson_open_as_web_pages() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("brain");
    let o = vbrain(&["export", &brain(), "--web", page.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: Value = serde_json::from_slice(&o.stdout).unwrap();
    let bytes = summary["web"]["bytes"].as_u64().unwrap();
    assert!(bytes < 15_000_000, "the page is {bytes} bytes");
    for file in ["index.html", "scene.glb", "vendor/three/LICENSE", "vendor/three/three.module.min.js"] {
        assert!(page.join(file).is_file(), "{file}");
    }
    // The page's model stores its normals in bytes (KHR_mesh_quantization); it is valid too.
    let report = validate(&page.join("scene.glb"));
    assert_eq!(report["numErrors"], 0, "{report}");
    let seen = open_page(&page);
    let shown = seen["pixels"].as_u64().unwrap();
    assert!(shown > 40_000, "the brain is drawn: {seen}");
    assert!(seen["clicked_name"].as_str().is_some_and(|n| n.contains("gyrus")), "a click names the gyrus: {seen}");
    assert!(seen["clicked_info"].as_str().is_some_and(|t| t.len() > 40), "{seen}");
    let hidden = seen["pixels_without_cerebrum"].as_u64().unwrap();
    assert!(hidden * 2 < shown, "hiding the cerebrum removes its pixels: {hidden} of {shown}");

    let lesson = dir.path().join("lesson");
    let cortex = Path::new(&brain()).join("lessons/cortex.vblesson");
    let o = vbrain(&["export", cortex.to_str().unwrap(), "--web", lesson.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A lesson's steps set the organs: options that would change them are refused.
    let unused = dir.path().join("unused");
    let refused =
        vbrain(&["export", cortex.to_str().unwrap(), "--web", unused.to_str().unwrap(), "--hide", "thalamus_l"]);
    assert_eq!(refused.status.code(), Some(1), "{}", stderr(&refused));
    assert!(stderr(&refused).contains("are for sets and scenes") && !unused.exists(), "{}", stderr(&refused));
    let seen = open_page(&lesson);
    let captions: Vec<&str> = seen["captions"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
    assert!(captions[0].contains("Seen from the left"), "step 1's caption: {}", captions[0]);
    assert!(!captions[0].contains('*'), "the caption's marks are gone: {}", captions[0]);
    // Its Markdown as the viewer draws it: paragraphs, a two-item list, bold and italic runs.
    let markup = &seen["caption_markup"];
    assert!(markup["p"].as_u64() >= Some(2) && markup["li"] == 2, "{markup}");
    assert!(markup["strong"].as_u64() >= Some(4) && markup["em"].as_u64() >= Some(1), "{markup}");
    assert!(captions[1] != captions[0] && captions[2] == captions[0], "Next and Previous: {captions:?}");
    assert!(seen["pixels_step_2"].as_u64().unwrap() > 10_000, "{seen}");
}

#[test]
fn names_html_would_read_stay_text_and_a_folder_with_files_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let set = dir.path().join("set");
    std::fs::create_dir(&set).unwrap();
    std::fs::write(set.join("a.obj"), "v 0 0 0\nv 30 0 0\nv 0 30 0\nv 0 0 30\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n")
        .unwrap();
    let name = "<script>alert('x')</script> & <b>bold</b>";
    let manifest = serde_json::json!({"format": "vbrain-organ-set/1", "title": "A & B <i>",
        "organs": [{"id": "a", "name": name, "mesh": "a.obj", "colour": "#c08080", "group": "<img src=x onerror=alert(1)>"}]});
    std::fs::write(set.join("organset.json"), manifest.to_string()).unwrap();
    let page = dir.path().join("page");
    let o = vbrain(&["export", set.to_str().unwrap(), "--web", page.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let seen = open_page(&page);
    assert!(seen["tree_text"].as_str().unwrap().contains(name), "{seen}");
    assert!(seen["title"].as_str().unwrap().starts_with("A & B <i>"), "{seen}");
    // The page's folder now holds files: writing it again is refused unless --force.
    let o = vbrain(&["export", set.to_str().unwrap(), "--web", page.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("--force"), "{}", stderr(&o));
    let o = vbrain(&["export", set.to_str().unwrap(), "--web", page.to_str().unwrap(), "--force"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A lesson step's section shows solid cut faces in the page, as in the viewer.
#[test]
fn a_lesson_steps_section_has_cut_faces_in_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("deep-nuclei");
    let lesson = Path::new(&brain()).join("lessons/deep-nuclei.vblesson");
    let o = vbrain(&["export", lesson.to_str().unwrap(), "--web", page.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Step 3 is a coronal section through the basal ganglia.
    let seen = open_page_at(&page, Some(3));
    let changed = seen["cap_pixels"].as_u64().unwrap();
    assert!(changed > 5_000, "the cut faces change only {changed} pixels: {seen}");
}
