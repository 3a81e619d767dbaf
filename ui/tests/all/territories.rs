//! Arterial territories in the viewer (issue: blood supply and pathways): the search finds them
//! by abbreviation and by name, choosing one colours the brain by territory (one undo step), and a
//! click on the cortex names the artery that supplies the point clicked.

use crate::viewer::{click, harness_of, organ, point_on, search};
use eframe::egui::{self, Key, Modifiers};
use egui_kittest::kittest::Queryable;
use vbrain::colouring::ColourBy;

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
