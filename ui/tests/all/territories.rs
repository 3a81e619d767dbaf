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
