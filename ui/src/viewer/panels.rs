//! The organ panel (the set's group tree with a search filter, per organ and per group: show,
//! transparency toggle, opacity, colour, isolate) and the inspector of the selected organ (name,
//! info, triangles, opacity, colour, and its transform in world millimetres and degrees).

use super::app::{App, Scene};
use crate::viewer::accessible;
use eframe::egui::{self, RichText};

/// A node of the group tree: its organs (indices) and sub-groups, in the set's order.
#[derive(Default)]
struct Group {
    name: String,
    organs: Vec<usize>,
    children: Vec<Group>,
}

impl Group {
    fn insert(&mut self, path: &[&str], organ: usize) {
        match path.split_first() {
            None => self.organs.push(organ),
            Some((first, rest)) => {
                let i = match self.children.iter().position(|c| c.name == *first) {
                    Some(i) => i,
                    None => {
                        self.children.push(Group { name: first.to_string(), ..Default::default() });
                        self.children.len() - 1
                    }
                };
                self.children[i].insert(rest, organ);
            }
        }
    }

    /// Every organ in this group and below.
    fn all(&self) -> Vec<usize> {
        let mut v = self.organs.clone();
        for c in &self.children {
            v.extend(c.all());
        }
        v
    }
}

/// The tree of the organs matching `filter` (case-insensitive, on name, id or group).
fn tree(scene: &Scene, filter: &str) -> Group {
    let filter = filter.to_lowercase();
    let mut root = Group::default();
    for (i, o) in scene.set.organs.iter().enumerate() {
        let hay = format!("{} {} {}", o.name, o.id, o.group).to_lowercase();
        if filter.is_empty() || hay.contains(&filter) {
            let path: Vec<&str> = o.group.split('/').filter(|s| !s.is_empty()).collect();
            root.insert(&path, i);
        }
    }
    root
}

pub fn organ_panel(app: &mut App, ui: &mut egui::Ui) {
    let Some(scene) = &mut app.scene else {
        ui.label("No organ set loaded.");
        return;
    };
    ui.heading(&scene.set.title);
    ui.label(format!("{} organs, {} triangles", scene.set.organs.len(), scene.set.triangle_count()));
    ui.horizontal(|ui| {
        let r = ui.add(egui::TextEdit::singleline(&mut app.filter).hint_text("search organs").desired_width(200.0));
        accessible(&r, "Search organs");
        if ui.button("Show all").clicked() {
            scene.show_all();
        }
    });
    ui.separator();
    let root = tree(scene, &app.filter);
    let mut select = None;
    egui::ScrollArea::vertical().auto_shrink([false; 2]).show(ui, |ui| {
        group_contents(ui, scene, &root, app.selected, &mut select);
        if root.organs.is_empty() && root.children.is_empty() {
            ui.label("No organ matches.");
        }
    });
    if let Some(s) = select {
        app.selected = Some(s);
    }
}

fn group_contents(
    ui: &mut egui::Ui,
    scene: &mut Scene,
    group: &Group,
    selected: Option<usize>,
    select: &mut Option<usize>,
) {
    for child in &group.children {
        let id = ui.make_persistent_id(("group", &child.name, child.all().first().copied()));
        egui::collapsing_header::CollapsingState::load_with_default_open(ui.ctx(), id, true)
            .show_header(ui, |ui| group_header(ui, scene, child))
            .body(|ui| group_contents(ui, scene, child, selected, select));
    }
    for &i in &group.organs {
        organ_row(ui, scene, i, selected == Some(i), select);
    }
}

/// Group row: name, then show/hide, transparency and isolate for all its organs.
fn group_header(ui: &mut egui::Ui, scene: &mut Scene, group: &Group) {
    let organs = group.all();
    let all_visible = organs.iter().all(|&i| scene.layout.organs[i].visible);
    let mut visible = all_visible;
    let r = ui.checkbox(&mut visible, "");
    accessible(&r, format!("Show group {}", group.name));
    if r.changed() {
        organs.iter().for_each(|&i| scene.layout.organs[i].visible = visible);
    }
    ui.label(RichText::new(&group.name).strong());
    let all_opaque = organs.iter().all(|&i| scene.layout.organs[i].opacity >= 1.0);
    let r = ui.selectable_label(!all_opaque, "T").on_hover_text("Transparency of the whole group");
    accessible(&r, format!("Transparency of group {}", group.name));
    if r.clicked() {
        for &i in &organs {
            let next = if all_opaque { scene.last_translucent[i] } else { 1.0 };
            scene.set_opacity(i, next);
        }
    }
    let mut opacity = organs.iter().map(|&i| scene.layout.organs[i].opacity).sum::<f32>() / organs.len().max(1) as f32;
    let r = ui
        .add(egui::Slider::new(&mut opacity, 0.0..=1.0).show_value(false))
        .on_hover_text("Opacity of the whole group");
    accessible(&r, format!("Opacity of group {}", group.name));
    if r.changed() {
        organs.iter().for_each(|&i| scene.set_opacity(i, opacity));
    }
    let r = ui.small_button("isolate").on_hover_text("Show only this group");
    accessible(&r, format!("Isolate group {}", group.name));
    if r.clicked() {
        scene.isolate(&organs);
    }
}

fn organ_row(ui: &mut egui::Ui, scene: &mut Scene, i: usize, is_selected: bool, select: &mut Option<usize>) {
    let name = scene.set.organs[i].name.clone();
    ui.horizontal(|ui| {
        let state = &mut scene.layout.organs[i];
        let r = ui.checkbox(&mut state.visible, "").on_hover_text("Show or hide");
        accessible(&r, format!("Show {name}"));
        let translucent = state.opacity < 1.0;
        let r = ui.selectable_label(translucent, "T").on_hover_text("Toggle transparency (T)");
        accessible(&r, format!("Transparency of {name}"));
        if r.clicked() {
            scene.toggle_transparency(i);
        }
        let r = ui.color_edit_button_rgb(&mut scene.layout.organs[i].colour);
        accessible(&r, format!("Colour of {name}"));
        let mut opacity = scene.layout.organs[i].opacity;
        let r = ui.add(egui::Slider::new(&mut opacity, 0.0..=1.0).show_value(false)).on_hover_text("Opacity");
        accessible(&r, format!("Opacity of {name}"));
        if r.changed() {
            scene.set_opacity(i, opacity);
        }
        let r = ui.selectable_label(is_selected, &name);
        accessible(&r, format!("Select {name}"));
        if r.clicked() {
            *select = Some(i);
        }
        r.context_menu(|ui| {
            if ui.button("Isolate").clicked() {
                scene.isolate(&[i]);
                ui.close();
            }
            if ui.button("Reset transform").clicked() {
                scene.reset_transform(i);
                ui.close();
            }
        });
    });
}

pub fn inspector(app: &mut App, ui: &mut egui::Ui) {
    let (Some(scene), Some(sel)) = (&mut app.scene, app.selected) else { return };
    let organ = &scene.set.organs[sel];
    let name = organ.name.clone();
    ui.heading(&name);
    if !organ.group.is_empty() {
        ui.label(RichText::new(&organ.group).weak());
    }
    ui.label(format!("{} triangles, id {}", organ.mesh.triangle_count(), organ.id));
    ui.separator();
    egui::ScrollArea::vertical().max_height(220.0).show(ui, |ui| {
        ui.label(if organ.info.is_empty() { "No description." } else { organ.info.as_str() });
    });
    ui.separator();
    let mut opacity = scene.layout.organs[sel].opacity;
    let r = ui.add(egui::Slider::new(&mut opacity, 0.0..=1.0).text("opacity"));
    accessible(&r, format!("Inspector opacity of {name}"));
    if r.changed() {
        scene.set_opacity(sel, opacity);
    }
    ui.horizontal(|ui| {
        let s = &mut scene.layout.organs[sel];
        let r = ui.checkbox(&mut s.visible, "visible");
        accessible(&r, format!("Inspector visibility of {name}"));
        let r = ui.color_edit_button_rgb(&mut s.colour);
        accessible(&r, format!("Inspector colour of {name}"));
        ui.label("colour");
    });
    ui.separator();
    ui.label(RichText::new("Transform").strong());
    let t = &mut scene.layout.organs[sel].transform;
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
    ui.horizontal(|ui| {
        if ui.button("Reset transform").clicked() {
            scene.reset_transform(sel);
        }
        if ui.button("Isolate").clicked() {
            scene.isolate(&[sel]);
        }
        if ui.button("Frame").clicked() {
            let b = scene.organ_bounds(sel);
            app.viewport.nav.frame(&b);
        }
    });
}
