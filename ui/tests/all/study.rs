//! Study material read by the programs students use: an Anki deck imported with Anki's own
//! collection library (`scripts/anki_import.py`, PyPI package `anki`), as File > Import does.

use crate::cli::{brain, json, vbrain};
use std::path::Path;
use std::process::Command;

/// A copy of the default brain's manifest and meshes, to edit.
fn brain_copy(dir: &Path) {
    let from = std::path::PathBuf::from(brain());
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::copy(from.join("organset.json"), dir.join("organset.json")).unwrap();
    for entry in std::fs::read_dir(from.join("meshes")).unwrap() {
        let entry = entry.unwrap();
        std::fs::copy(entry.path(), dir.join("meshes").join(entry.file_name())).unwrap();
    }
}

fn anki_import(decks: &[&Path]) -> serde_json::Value {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/anki_import.py");
    let out = Command::new("python3").arg(script).args(decks).output().unwrap();
    assert!(
        out.status.success(),
        "Anki's library (pip install anki) could not import the deck: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn an_anki_deck_imports_into_anki_and_updates_without_duplicates() {
    let dir = tempfile::tempdir().unwrap();
    let set = dir.path().join("set");
    brain_copy(&set);
    let (first, second) = (dir.path().join("first.apkg"), dir.path().join("second.apkg"));
    let export = |out: &Path| {
        let args = ["anki", set.to_str().unwrap(), "--group", "Basal ganglia", "--views", "1", "--size", "160x160"];
        json(&vbrain(&[&args[..], &["--out", out.to_str().unwrap(), "--json"]].concat()))
    };
    let report = export(&first)["report"].clone();
    let structures = report["structures"].as_u64().unwrap();
    assert!(structures >= 8, "{report}");
    assert!(report["unseen"].as_array().unwrap().is_empty(), "{report}");
    let notes = report["notes"].as_u64().unwrap();
    assert_eq!(notes, 3 * structures, "a name-it and two occlusion notes per structure and view");
    // Never replaced without --force.
    let again = vbrain(&["anki", set.to_str().unwrap(), "--out", first.to_str().unwrap()]);
    assert!(!again.status.success() && String::from_utf8_lossy(&again.stderr).contains("--force"));

    // The set changes: a text, and a name that must stay text.
    let manifest = set.join("organset.json");
    let mut m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&manifest).unwrap()).unwrap();
    let hostile = "<script>alert(1)</script> & \"x\" ]]>";
    for o in m["organs"].as_array_mut().unwrap() {
        match o["id"].as_str() {
            Some("caudate_l") => o["info"] = format!("{} Revised.", o["info"].as_str().unwrap()).into(),
            Some("putamen_l") => o["name"] = hostile.into(),
            _ => {}
        }
    }
    std::fs::write(&manifest, serde_json::to_string(&m).unwrap()).unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1100));
    export(&second);

    let v = anki_import(&[&first, &second]);
    assert_eq!(v["imports"][0]["new"].as_u64(), Some(notes), "{}", v["imports"]);
    // The second export updates the changed notes (3 each) and adds none.
    assert_eq!(v["imports"][1]["new"].as_u64(), Some(0), "{}", v["imports"]);
    assert!(v["imports"][1]["updated"].as_u64().unwrap() >= 6, "{}", v["imports"]);
    assert_eq!((v["note_count"].as_u64(), v["card_count"].as_u64()), (Some(notes), Some(notes)));
    assert_eq!(v["missing_media"].as_array().unwrap().len(), 0, "{}", v["missing_media"]);
    let decks: Vec<&str> = v["decks"].as_array().unwrap().iter().filter_map(|d| d.as_str()).collect();
    assert!(decks.iter().any(|d| d.ends_with("::Basal ganglia::Left")), "{decks:?}");
    let all = v["notes"].as_array().unwrap();
    let types = |t: &str| all.iter().filter(|n| n["type"] == t).count() as u64;
    assert_eq!((types("vbrain name it"), types("vbrain image occlusion")), (structures, 2 * structures));
    let caudate = all.iter().find(|n| n["fields"]["Name"] == "Left caudate nucleus").expect("the caudate's note");
    assert!(caudate["fields"]["Latin"].as_str().is_some_and(|l| !l.is_empty()));
    assert!(caudate["fields"]["Info"].as_str().unwrap().ends_with("Revised."));
    assert!(caudate["fields"]["Masked"].as_str().is_none_or(|f| f.contains("<img src=")));
    // The hostile name arrives as text, escaped, in every field it reaches.
    assert!(all.iter().any(|n| n["fields"]["Name"].as_str().is_some_and(|s| s.starts_with("&lt;script&gt;"))));
    assert!(!v["notes"].to_string().contains("<script"), "markup from a name reached a card");
}
