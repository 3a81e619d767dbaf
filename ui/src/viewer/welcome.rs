//! The view the viewer opens on when no set was given and the default set is nowhere it looked:
//! the places, in order ([`vbrain::data_dir`]), and *Open*.
//!
//! - It only reads; *Open* returns an action that shows the window to open a set or scene.

use super::action::{Action, Window};
use eframe::egui;

/// The view shown when no set was given and none was found: where the viewer looked, and *Open*.
pub fn view(ui: &mut egui::Ui, not_found: &vbrain::data_dir::NotFound) -> Vec<Action> {
    let mut out = Vec::new();
    ui.vertical_centered(|ui| {
        ui.add_space(ui.available_height() * 0.2);
        ui.heading("Welcome to vbrain");
        ui.add_space(8.0);
        ui.label("The default brain was not found. vbrain looked in:");
        for place in &not_found.looked {
            ui.monospace(place.display().to_string());
        }
        ui.add_space(8.0);
        ui.label(format!(
            "Reinstall vbrain, set {} to the folder that holds `{}/`, or open an organ set.",
            vbrain::data_dir::ENV,
            vbrain::data_dir::DEFAULT_SET
        ));
        ui.add_space(8.0);
        if ui.button("Open organ set or scene...").clicked() {
            out.push(Action::Show(Window::OpenSet));
        }
    });
    out
}
