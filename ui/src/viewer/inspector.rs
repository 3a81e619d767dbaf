//! The inspector of the selected organ: name, group, info text, the arterial territory where it
//! was clicked (with the artery's teaching text), triangles, opacity, colour,
//! visibility, "Do not cut" and "Label", and its transform, with Reset transform, Isolate and
//! Frame.
//!
//! - The transform translates in world millimetres, rotates in degrees and scales.
//! - It reads the scene and returns [`Action`]s.

use super::action::Action;
use super::scene::Scene;
use super::widgets::accessible;
use crate::viewer::action::SectionAction;
use eframe::egui::{self, RichText};
use vbrain::edit::{Edit, Organs};

/// What the inspector shows beside the layout: whether the organ is kept whole where planes cut,
/// whether it is labelled, and the arterial territory where it was clicked.
#[derive(Clone, Copy, Debug, Default)]
pub struct Marks {
    pub whole: bool,
    pub labelled: bool,
    pub supply: Option<u8>,
}

pub fn inspector(ui: &mut egui::Ui, scene: &Scene, sel: usize, marks: Marks) -> Vec<Action> {
    let mut out = Vec::new();
    let organ = &scene.set().organs[sel];
    let state = scene.layout().organs[sel];
    let name = &organ.name;
    ui.heading(name);
    if let Some(latin) = &organ.latin {
        ui.label(RichText::new(latin).italics());
    }
    if !organ.synonyms.is_empty() {
        ui.label(format!("Also: {}", organ.synonyms.join(", ")));
    }
    if !organ.group.is_empty() {
        ui.label(RichText::new(&organ.group).weak());
    }
    ui.label(format!("{} triangles, id {}", organ.mesh().triangle_count(), organ.id));
    ui.separator();
    egui::ScrollArea::vertical().max_height(220.0).show(ui, |ui| {
        ui.label(if organ.info.is_empty() { "No description." } else { organ.info.as_str() });
    });
    if let Some((artery, side)) = scene.set().territories.as_ref().zip(marks.supply).and_then(|(t, id)| t.artery(id)) {
        ui.separator();
        let name = vbrain::organ_set::territory::sided(side, &artery.name);
        ui.label(RichText::new(format!("Supplied here by: {name} ({})", artery.short)).strong())
            .on_hover_text("The arterial territory at the point you clicked (Liu et al. 2023 atlas)");
        egui::CollapsingHeader::new("About this territory").id_salt("territory").show(ui, |ui| {
            if !artery.latin.is_empty() {
                ui.label(RichText::new(&artery.latin).italics());
            }
            ui.label(&artery.info);
        });
    }
    ui.separator();
    let one = || Organs::One(sel);
    let mut opacity = state.opacity;
    let r = ui.add(egui::Slider::new(&mut opacity, 0.0..=1.0).text("opacity"));
    accessible(&r, format!("Inspector opacity of {name}"));
    if r.changed() {
        out.push(Action::Edit(Edit::Opacity { organs: one(), opacity }));
    }
    ui.horizontal(|ui| {
        let mut visible = state.visible;
        let r = ui.checkbox(&mut visible, "visible");
        accessible(&r, format!("Inspector visibility of {name}"));
        if r.changed() {
            out.push(Action::Edit(Edit::Visible { organs: one(), visible }));
        }
        let mut colour = state.colour;
        let r = ui.color_edit_button_rgb(&mut colour);
        accessible(&r, format!("Inspector colour of {name}"));
        if r.changed() {
            out.push(Action::Edit(Edit::Colour { organs: one(), colour }));
        }
        ui.label("colour");
    });
    ui.horizontal(|ui| {
        let mut whole = marks.whole;
        let r = ui.checkbox(&mut whole, "Do not cut").on_hover_text("Keep it whole where clip planes cut the set");
        accessible(&r, format!("Do not cut {name}"));
        if r.changed() {
            out.push(Action::Section(SectionAction::KeepWhole { organ: sel, whole }));
        }
        let mut on = marks.labelled;
        let r = ui.checkbox(&mut on, "Label").on_hover_text("Name it with a label (View > Labels: chosen organs)");
        accessible(&r, format!("Label {name}"));
        if r.changed() {
            out.push(Action::Label { organ: sel, on });
        }
    });
    ui.separator();
    ui.label(RichText::new("Transform").strong());
    let mut t = state.transform;
    egui::Grid::new("transform").num_columns(4).show(ui, |ui| {
        let row = |ui: &mut egui::Ui, label: &str, v: &mut glam::Vec3, speed: f32, unit: &str| {
            ui.label(label);
            for (axis, c) in ["x", "y", "z"].iter().zip([&mut v.x, &mut v.y, &mut v.z]) {
                let r = ui.add(egui::DragValue::new(c).speed(speed).suffix(unit));
                accessible(&r, format!("{label} {axis}"));
            }
            ui.end_row();
        };
        row(ui, "Translate", &mut t.translation, 0.5, " mm");
        row(ui, "Rotate", &mut t.rotation_deg, 1.0, "°");
        ui.label("Scale");
        let r = ui.add(egui::DragValue::new(&mut t.scale).speed(0.01).range(0.05..=20.0));
        accessible(&r, "Scale");
        ui.end_row();
    });
    if t != state.transform {
        out.push(Action::Edit(Edit::Transform { organ: sel, transform: t }));
    }
    ui.horizontal(|ui| {
        if ui.button("Reset transform").clicked() {
            out.push(Action::Edit(Edit::ResetTransform { organs: one() }));
        }
        if ui.button("Isolate").clicked() {
            out.push(Action::Edit(Edit::Isolate { organs: one() }));
        }
        if ui.button("Frame").clicked() {
            out.push(Action::Frame(sel));
        }
    });
    out
}
