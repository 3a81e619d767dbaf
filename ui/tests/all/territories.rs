//! Blood supply and pathways in the viewer and the commands (issue: blood supply and pathways):
//! the search finds territories by abbreviation and by name, and tracts and brainstem parts by
//! their synonyms; choosing a territory colours the brain by territory (one undo step), and a
//! click on the cortex names the artery that supplies the point clicked; glTF carries the
//! territory colours; supply quizzes in the viewer and worksheets.

use crate::viewer::{click, harness_of, organ, point_on, search};
use eframe::egui::{self, Key, Modifiers};
use egui_kittest::kittest::Queryable;
use vbrain::layout::ColourBy;

#[test]
fn search_colour_by_territory_and_click_to_name_the_artery() {
    let mut h = harness_of(egui::Vec2::new(900.0, 560.0));
    let colouring = |h: &egui_kittest::Harness<'static, vbrain_ui::App>| h.state().scene().unwrap().layout().colour_by;
    for query in ["MCA", "middle cerebral artery territory"] {
        if h.query_by_label("Clear search").is_some() {
            h.get_by_label("Clear search").click();
            h.run_steps(2);
        }
        search(&mut h, query);
        for part in ["frontal", "parietal", "temporal", "insular"] {
            let label = format!("Territory Middle cerebral artery, {part} branches");
            assert!(h.query_by_label(&label).is_some(), "search \"{query}\" lists {label}");
        }
        assert!(h.query_by_label("Territory Anterior cerebral artery").is_none(), "\"{query}\" is not the ACA");
    }
    assert_eq!(colouring(&h), ColourBy::Organ);
    h.get_by_label("Territory Middle cerebral artery, frontal branches").click();
    h.run_steps(3);
    assert_eq!(colouring(&h), ColourBy::Territory);

    // The left precentral gyrus, seen from the left, lies in the left MCA's territory.
    let gyrus = organ(&h, "precentral_l");
    h.get_by_label("Clear search").click();
    h.run_steps(2);
    h.key_press(Key::Num3);
    h.run_steps(3);
    let at = point_on(&h, gyrus);
    click(&h, at);
    h.run_steps(3);
    let label = "Supplied here by: Left middle cerebral artery";
    assert!(h.query_by_label_contains(label).is_some(), "the inspector names the artery");

    // Undo puts the organs' own colours back, as one step.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_eq!(colouring(&h), ColourBy::Organ);
}

#[test]
fn territory_colours_reach_gltf_as_vertex_colours_the_validator_passes() {
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("territories.glb");
    let o = crate::cli::vbrain(&[
        "export",
        &crate::cli::brain(),
        "--gltf",
        glb.to_str().unwrap(),
        "--colour-by",
        "territory",
        "--show",
        "skull",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = crate::export::node("validate.mjs", &[&glb]);
    assert_eq!(report["numErrors"], 0, "{report}");
    let bytes = std::fs::read(&glb).unwrap();
    let len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let doc: serde_json::Value = serde_json::from_slice(&bytes[20..20 + len]).unwrap();
    let primitive = |id: &str| {
        let node = doc["nodes"].as_array().unwrap().iter().find(|n| n["extras"]["id"] == id).unwrap().clone();
        doc["meshes"][node["mesh"].as_u64().unwrap() as usize]["primitives"][0].clone()
    };
    // The cortex carries a colour per vertex on a white material; the skull, outside every
    // artery's territory, keeps one colour.
    let gyrus = primitive("precentral_l");
    let colours = &doc["accessors"][gyrus["attributes"]["COLOR_0"].as_u64().expect("COLOR_0") as usize];
    let positions = &doc["accessors"][gyrus["attributes"]["POSITION"].as_u64().unwrap() as usize];
    assert_eq!(colours["count"], positions["count"]);
    let material = &doc["materials"][gyrus["material"].as_u64().unwrap() as usize];
    assert_eq!(material["pbrMetallicRoughness"]["baseColorFactor"], serde_json::json!([1.0, 1.0, 1.0, 1.0]));
    let skull = primitive("skull");
    assert!(skull["attributes"].get("COLOR_0").is_none());
    let material = &doc["materials"][skull["material"].as_u64().unwrap() as usize];
    assert_ne!(material["pbrMetallicRoughness"]["baseColorFactor"], serde_json::json!([1.0, 1.0, 1.0, 1.0]));

    // A set without territories cannot be coloured by them, and says so.
    let obj = dir.path().join("cube.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let png = dir.path().join("cube.png");
    let o = crate::cli::vbrain(&[
        "render",
        obj.to_str().unwrap(),
        "--out",
        png.to_str().unwrap(),
        "--colour-by",
        "territory",
    ]);
    let said = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && said.contains("no arterial territories") && !png.exists(), "{said}");
}

#[test]
fn a_blood_supply_quiz_in_the_viewer_marks_picked_arteries() {
    use vbrain::quiz::{supplier, Kind, Mode};
    use vbrain_ui::viewer::action::{Action, Window};
    let mut h = harness_of(egui::Vec2::new(900.0, 560.0));
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Show(Window::Quiz)]);
    h.run_steps(2);
    let setup = &mut h.state_mut().quiz_mut().setup;
    (setup.group, setup.questions, setup.mode, setup.seed) = ("Frontal lobe".into(), 2, Mode::Supply, 3);
    h.get_by_label("Start quiz").click_accesskit();
    h.run_steps(3);
    let set = h.state().scene().unwrap().set().clone();
    let arteries = &set.territories.as_ref().unwrap().arteries;
    for k in 0..2 {
        let q = h.state().quiz().run.as_ref().unwrap().current().unwrap().clone();
        assert_eq!(q.kind, Kind::Supply);
        assert_eq!(h.state().quiz().outlined, vec![q.organ], "the region asked about is outlined");
        let answer = supplier(&set, q.organ).unwrap();
        let pick = if k == 0 { answer } else { *q.choices.iter().find(|&&c| c != answer).unwrap() };
        let a = &arteries[pick];
        h.get_by_label(&format!("Choice {} ({})", a.name, a.short)).click_accesskit();
        h.run_steps(2);
        let (text, right) = h.state().quiz().run.as_ref().unwrap().feedback.clone().unwrap();
        assert_eq!(right, k == 0, "question {k}: {text}");
        assert!(text.contains(&arteries[answer].name.to_lowercase()), "the feedback names the artery: {text}");
        h.get_by_label(if k == 1 { "Finish" } else { "Next question" }).click_accesskit();
        h.run_steps(2);
    }
    assert_eq!(h.state().quiz().run.as_ref().unwrap().score(), 1);
}

#[test]
fn a_blood_supply_worksheet_lists_arteries_and_its_key_the_supplier() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sheet");
    let o = crate::cli::vbrain(&[
        "quiz",
        &crate::cli::brain(),
        "--mode",
        "supply",
        "--questions",
        "3",
        "--size",
        "200x150",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let listed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let set = vbrain::organ_set::open(std::path::Path::new(&crate::cli::brain())).unwrap().set;
    let keys: Vec<String> = set.territories.as_ref().unwrap().arteries.iter().map(|a| a.key.clone()).collect();
    let answers = std::fs::read_to_string(out.join("answers.md")).unwrap();
    for (k, q) in listed["questions"].as_array().unwrap().iter().enumerate() {
        assert_eq!(q["kind"], "supply");
        let choices: Vec<&str> = q["choices"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
        assert!(choices.len() == 4 && choices.iter().all(|c| keys.iter().any(|k| k == c)), "{choices:?}");
        let organ = set.find(q["organ"].as_str().unwrap()).unwrap();
        let answer = &set.territories.as_ref().unwrap().arteries[vbrain::quiz::supplier(&set, organ).unwrap()];
        let line = answers.lines().find(|l| l.starts_with(&format!("{}. ", k + 1))).unwrap();
        assert!(line.contains(&answer.name) && line.contains(&set.organs[organ].name), "{line}");
    }
    let questions = std::fs::read_to_string(out.join("questions.md")).unwrap();
    assert!(questions.contains("Which artery supplies region A?"), "{questions}");
}

#[test]
fn search_finds_the_pyramidal_tract_and_the_pons() {
    let mut h = harness_of(egui::Vec2::new(760.0, 480.0));
    search(&mut h, "pyramidal tract");
    for name in ["Left corticospinal tract", "Right corticospinal tract"] {
        assert!(h.query_by_label(&format!("Show {name}")).is_some(), "\"pyramidal tract\" finds {name}");
    }
    assert!(h.query_by_label("Show Pons").is_none());
    h.get_by_label("Clear search").click();
    h.run_steps(2);
    search(&mut h, "pons");
    assert!(h.query_by_label("Show Pons").is_some(), "\"pons\" finds the pons");
}
