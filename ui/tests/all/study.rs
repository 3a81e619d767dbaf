//! Study material read by the programs students use: an Anki deck imported with Anki's own
//! collection library (`scripts/anki_import.py`, PyPI package `anki`), as File > Import does;
//! a SCORM package unpacked and read by Python, and played in Chromium inside a platform's page
//! that records its SCORM 1.2 API calls (`scripts/web/scorm-test.mjs`).

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

/// A shipped lesson's deck: the structures its steps highlight, and a note per question of its
/// quiz (name it, or find it), in a deck of the lesson's own.
#[test]
fn a_lessons_deck_holds_its_structures_and_its_quiz() {
    let dir = tempfile::tempdir().unwrap();
    let deck = dir.path().join("ventricles.apkg");
    let lesson = Path::new(&brain()).join("lessons/ventricles.vblesson");
    let args = [
        "anki",
        lesson.to_str().unwrap(),
        "--views",
        "1",
        "--size",
        "160x160",
        "--out",
        deck.to_str().unwrap(),
        "--json",
    ];
    let report = json(&vbrain(&args))["report"].clone();
    let structures = report["structures"].as_u64().unwrap();
    assert!((6..=8).contains(&structures), "the Ventricles group and the steps' highlights: {report}");
    assert_eq!(report["questions"], 4, "{report}");
    assert!(report["unseen"].as_array().unwrap().is_empty(), "{report}");
    let v = anki_import(&[&deck]);
    assert_eq!(v["note_count"].as_u64(), Some(3 * structures + 4), "{v}");
    assert_eq!(v["missing_media"].as_array().unwrap().len(), 0, "{}", v["missing_media"]);
    let all = v["notes"].as_array().unwrap();
    let types = |t: &str| all.iter().filter(|n| n["type"] == t).count() as u64;
    // Two locate questions become find-it notes, two name questions name-it notes.
    assert_eq!((types("vbrain find it"), types("vbrain name it")), (2, structures + 2));
    let find = all.iter().find(|n| n["type"] == "vbrain find it").unwrap();
    assert!(find["fields"]["Plain"].as_str().unwrap().contains("-q1-plain.png"), "{find}");
    let decks: Vec<&str> = v["decks"].as_array().unwrap().iter().filter_map(|d| d.as_str()).collect();
    assert!(decks.iter().any(|d| d.contains("::Lessons::")), "{decks:?}");

    // A scene's deck holds what the scene shows: its six ventricles less the one it hides.
    let (scene, png) = (dir.path().join("s.vbscene"), dir.path().join("s.png"));
    let p = |p: &Path| p.to_str().unwrap().to_string();
    let args = ["render", &brain(), "--hide", "lateral_ventricle_l", "--save-scene", &p(&scene), "--out", &p(&png)];
    assert!(vbrain(&[&args[..], &["--size", "32x32"]].concat()).status.success());
    let deck = dir.path().join("scene.apkg");
    let args = ["anki", &p(&scene), "--group", "Ventricles", "--views", "1", "--size", "96x96", "--out", &p(&deck)];
    let report = json(&vbrain(&[&args[..], &["--json"]].concat()))["report"].clone();
    assert_eq!(report["structures"], 5, "{report}");
}

/// Unpacks a zip with Python's zipfile into `dir`, and reads its manifest with Python's XML
/// parser: (the manifest's title, its files' hrefs, the zip's entries, the mastery score).
fn unpack_scorm(zip: &Path, dir: &Path) -> serde_json::Value {
    let script = r#"
import json, sys, zipfile, xml.etree.ElementTree as ET
z = zipfile.ZipFile(sys.argv[1])
z.extractall(sys.argv[2])
root = ET.fromstring(z.read("imsmanifest.xml"))
ns = {"cp": "http://www.imsproject.org/xsd/imscp_rootv1p1p2", "adlcp": "http://www.adlnet.org/xsd/adlcp_rootv1p2"}
print(json.dumps({
    "title": root.find("cp:organizations/cp:organization/cp:title", ns).text,
    "files": sorted(f.get("href") for f in root.iter("{%s}file" % ns["cp"])),
    "entries": sorted(n for n in z.namelist() if n != "imsmanifest.xml"),
    "launch": root.find("cp:resources/cp:resource", ns).get("href"),
    "mastery": root.find(".//adlcp:masteryscore", ns).text,
}))
"#;
    let out = Command::new("python3").args(["-c", script]).arg(zip).arg(dir).output().unwrap();
    assert!(out.status.success(), "the package or its manifest is broken: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// A shipped lesson as a SCORM package: its manifest is well-formed and names every file; a
/// platform's page hosting it sees the quiz played with clicks reported as initialise, score,
/// status and finish, in that order.
#[test]
fn a_lesson_as_a_scorm_package_reports_its_quiz_to_the_platform() {
    let dir = tempfile::tempdir().unwrap();
    let zip = dir.path().join("cortex.zip");
    let lesson = Path::new(&brain()).join("lessons/cortex.vblesson");
    let args = ["export", lesson.to_str().unwrap(), "--scorm", zip.to_str().unwrap(), "--pass-mark", "60", "--json"];
    let summary = json(&vbrain(&args));
    assert_eq!(summary["scorm"]["questions"], 6, "{summary}");
    // Written once; not replaced without --force.
    let again = vbrain(&args);
    assert_eq!(again.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&again.stderr).contains("--force"));

    let unpacked = dir.path().join("sco");
    let manifest = unpack_scorm(&zip, &unpacked);
    assert_eq!(manifest["files"], manifest["entries"], "{manifest}");
    assert_eq!(manifest["launch"], "index.html");
    assert_eq!(manifest["mastery"], "60");
    assert!(manifest["files"].as_array().unwrap().len() >= 7, "{manifest}");

    // Two questions answered wrongly, four rightly: 67 %, passed against 60 %.
    let shot = dir.path().join("quiz.png");
    let seen = crate::export::node("scorm-test.mjs", &[&unpacked, Path::new("2"), &shot]);
    assert_eq!(seen["errors"], serde_json::json!([]), "{seen}");
    let answers = seen["answers"].as_array().unwrap();
    assert_eq!(answers.len(), 6, "{seen}");
    assert!(answers[0]["feedback"].as_str().unwrap().starts_with("No: "), "{seen}");
    assert!(answers[5]["feedback"].as_str().unwrap().starts_with("Right: "), "{seen}");
    assert_eq!(seen["missed"].as_array().unwrap().len(), 2, "{seen}");
    assert!(seen["score_line"].as_str().unwrap().starts_with("Score: 4 of 6 (67 %), passed"), "{seen}");
    let calls: Vec<Vec<String>> = serde_json::from_value(seen["calls"].clone()).unwrap();
    let at =
        |call: &[&str]| calls.iter().position(|c| c == call).unwrap_or_else(|| panic!("no call {call:?} in {calls:?}"));
    let init = at(&["LMSInitialize", ""]);
    let raw = at(&["LMSSetValue", "cmi.core.score.raw", "67"]);
    at(&["LMSSetValue", "cmi.core.score.min", "0"]);
    at(&["LMSSetValue", "cmi.core.score.max", "100"]);
    let status = at(&["LMSSetValue", "cmi.core.lesson_status", "passed"]);
    let finish = at(&["LMSFinish", ""]);
    assert!(init == 0 && init < raw && raw < status && status < finish && finish == calls.len() - 1, "{calls:?}");
}

/// Names with markup stay text in the manifest; a page without a quiz is no SCORM package.
#[test]
fn a_scorm_manifest_keeps_names_as_text_and_needs_a_quiz() {
    let dir = tempfile::tempdir().unwrap();
    let set = dir.path().join("set");
    std::fs::create_dir(&set).unwrap();
    let cube = "v 0 0 0\nv 30 0 0\nv 0 30 0\nv 0 0 30\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    std::fs::write(set.join("a.obj"), cube).unwrap();
    std::fs::write(set.join("b.obj"), cube.replace("v 0 0 0", "v 60 0 0")).unwrap();
    let title = "<script>alert(\"x\")</script> & ]]> done";
    let manifest = serde_json::json!({"format": "vbrain-organ-set/1", "title": title, "organs": [
        {"id": "a", "name": "A <b>", "mesh": "a.obj", "colour": "#c08080"},
        {"id": "b", "name": "B ]]>", "mesh": "b.obj", "colour": "#80c080"}]});
    std::fs::write(set.join("organset.json"), manifest.to_string()).unwrap();
    let zip = dir.path().join("p.zip");
    let s = set.to_str().unwrap();
    let refused = vbrain(&["export", s, "--scorm", zip.to_str().unwrap()]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("no quiz") && !zip.exists());
    let o = vbrain(&["export", s, "--scorm", zip.to_str().unwrap(), "--quiz", "2"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let seen = unpack_scorm(&zip, &dir.path().join("sco"));
    assert_eq!(seen["title"], title);
    assert_eq!(seen["mastery"], "70");
    let page = std::fs::read_to_string(dir.path().join("sco/index.html")).unwrap();
    assert!(!page.contains("<script>alert"), "names stay data, never markup");
}
