//! The organ panel: the set's group tree with a search filter (which also finds arterial
//! territories); per organ and per group: show,
//! transparency toggle, opacity, colour; isolate on right-click of a name.
//!
//! - It reads the scene and returns [`Action`]s (edits, selection); its own state is the filter.

use super::action::Action;
use super::scene::Scene;
use super::widgets::accessible;
use eframe::egui::{self, RichText};
use vbrain::edit::{Edit, Organs};
use vbrain::organ_set::names;

/// A node of the group tree: its organs (indices) and sub-groups, in the set's order.
#[derive(Default)]
struct Group {
    /// The last part of the group path (what the tree shows).
    name: String,
    /// The whole `/`-separated path (what edits are named after).
    path: String,
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
                        let path =
                            if self.path.is_empty() { first.to_string() } else { format!("{}/{first}", self.path) };
                        self.children.push(Group { name: first.to_string(), path, ..Default::default() });
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

    fn organs(&self) -> Organs {
        Organs::Group { name: self.path.clone(), organs: self.all() }
    }

    /// The group at `path` in this tree.
    fn find(&self, path: &str) -> Option<&Group> {
        if self.path == path {
            return Some(self);
        }
        self.children.iter().find_map(|c| c.find(path))
    }
}

/// The most characters of a name a row shows: longer names end in "…".
pub const MAX_ROW_NAME: usize = 64;

/// `name`, cut to [`MAX_ROW_NAME`] characters.
fn short(name: &str) -> std::borrow::Cow<'_, str> {
    match name.char_indices().nth(MAX_ROW_NAME) {
        Some((at, _)) => format!("{}…", &name[..at]).into(),
        None => name.into(),
    }
}

/// The deepest group the tree shows: deeper parts of a group path are shown joined in one row,
/// so a hand-made set nested thousands deep costs neither stack nor width.
pub const MAX_TREE_DEPTH: usize = 8;

/// The tree of the organs matching `filter`: any of their names (name, id, Latin name, synonyms)
/// or their group, case- and accent-insensitively.
fn tree(scene: &Scene, filter: &str) -> Group {
    let folded = names::fold(filter);
    let mut root = Group::default();
    for (i, o) in scene.set().organs.iter().enumerate() {
        if names::matches_folded(o, &folded) || names::fold(&o.group).contains(&folded) {
            let parts: Vec<&str> = o.group.split('/').filter(|s| !s.is_empty()).collect();
            let mut path: Vec<String> = parts.iter().take(MAX_TREE_DEPTH - 1).map(|s| s.to_string()).collect();
            if parts.len() >= MAX_TREE_DEPTH {
                path.push(parts[MAX_TREE_DEPTH - 1..].join("/"));
            }
            let path: Vec<&str> = path.iter().map(String::as_str).collect();
            root.insert(&path, i);
        }
    }
    root
}

/// The organ panel and its search filter.
#[derive(Default)]
pub struct OrganPanel {
    filter: String,
}

impl OrganPanel {
    /// The panel; `quiz` says a quiz is being answered: the rows then show what the quiz shows and
    /// take no edits (the quiz decides what is shown until it ends).
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        scene: Option<&Scene>,
        selected: Option<usize>,
        quiz: bool,
    ) -> Vec<Action> {
        let mut out = Vec::new();
        // The panel keeps its width whatever the rows show (a search's few rows do not narrow it
        // and move the 3-D view).
        ui.set_min_width(ui.available_width());
        let Some(scene) = scene else {
            ui.label("No organ set loaded.");
            return out;
        };
        ui.add(egui::Label::new(RichText::new(&scene.set().title).heading()).truncate());
        ui.label(format!("{} organs, {} triangles", scene.set().organs.len(), scene.set().triangle_count()));
        ui.horizontal(|ui| {
            let r =
                ui.add(egui::TextEdit::singleline(&mut self.filter).hint_text("search organs").desired_width(200.0));
            accessible(&r, "Search organs");
            r.on_hover_text("Any name: English, Latin, a synonym (\"Broca\"), an id or a group");
            if !self.filter.is_empty() {
                let r = ui.small_button("×").on_hover_text("Clear the search");
                accessible(&r, "Clear search");
                if r.clicked() {
                    self.filter.clear();
                }
            }
            if ui.button("Show all").clicked() {
                out.push(Action::Edit(Edit::show_all()));
            }
        });
        ui.separator();
        territories(ui, scene, &self.filter, &mut out);
        let root = tree(scene, &self.filter);
        let filtering = !self.filter.trim().is_empty();
        // A group's row acts on the whole group its name says, whatever the search shows of it.
        let unfiltered;
        let whole = if filtering {
            unfiltered = tree(scene, "");
            &unfiltered
        } else {
            &root
        };
        if quiz {
            ui.label(
                RichText::new("The quiz shows the organs it asks about; the tree is yours again when it ends.").weak(),
            );
        }
        egui::ScrollArea::vertical().auto_shrink([false; 2]).show(ui, |ui| {
            // Compact rows, so that a name keeps room in a panel of 300 points.
            ui.spacing_mut().slider_width = 64.0;
            ui.spacing_mut().interact_size.x = 28.0;
            if quiz {
                ui.disable();
            }
            let mut rows = Rows { scene, selected, filtering, whole, out: &mut out };
            rows.group_contents(ui, &root);
            if root.organs.is_empty() && root.children.is_empty() {
                ui.label("No organ matches.");
            }
        });
        out
    }
}

/// The arterial territories a search names ("MCA", "middle cerebral artery territory"): a row
/// each, which colours the organs by territory; the teaching text on hover.
fn territories(ui: &mut egui::Ui, scene: &Scene, filter: &str, out: &mut Vec<Action>) {
    let Some(t) = &scene.set().territories else { return };
    let found = t.find(filter);
    if found.is_empty() {
        return;
    }
    ui.label(RichText::new("Arterial territories").strong());
    for a in found {
        let [r, g, b] = a.colour.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
        ui.horizontal(|ui| {
            let (swatch, _) = ui.allocate_exact_size(egui::vec2(12.0, 12.0), egui::Sense::hover());
            ui.painter().rect_filled(swatch, 2.0, egui::Color32::from_rgb(r, g, b));
            let row = ui.selectable_label(false, format!("{} ({})", a.name, a.short)).on_hover_text(&a.info);
            accessible(&row, format!("Territory {}", a.name));
            if row.clicked() {
                out.push(Action::Edit(Edit::ColourBy(vbrain::layout::ColourBy::Territory)));
            }
        });
    }
    ui.separator();
}

/// The tree's rows: what they read and the actions they return.
struct Rows<'a> {
    scene: &'a Scene,
    selected: Option<usize>,
    /// A search is on: every group of the matches opens (its own open state, apart from the
    /// unfiltered tree's).
    filtering: bool,
    /// The unfiltered tree, whose groups the group rows act on.
    whole: &'a Group,
    out: &'a mut Vec<Action>,
}

impl Rows<'_> {
    fn edit(&mut self, edit: Edit) {
        self.out.push(Action::Edit(edit));
    }

    fn group_contents(&mut self, ui: &mut egui::Ui, group: &Group) {
        for child in &group.children {
            let id = ui.make_persistent_id(("group", &child.name, child.all().first().copied(), self.filtering));
            // Groups three deep (a hemisphere's lobes) start closed: 68 gyri are too many rows.
            let open = self.filtering || child.path.matches('/').count() < 2;
            egui::collapsing_header::CollapsingState::load_with_default_open(ui.ctx(), id, open)
                .show_header(ui, |ui| self.group_header(ui, child))
                .body(|ui| self.group_contents(ui, child));
        }
        for &i in &group.organs {
            self.organ_row(ui, i);
        }
    }

    /// Group row: name, then show/hide, transparency and isolate for all its organs (also those a
    /// search leaves out of the tree).
    fn group_header(&mut self, ui: &mut egui::Ui, shown: &Group) {
        let whole = self.whole;
        let group = whole.find(&shown.path).unwrap_or(shown);
        let scene = self.scene;
        let layout = scene.shown();
        let organs = group.all();
        let mut visible = organs.iter().all(|&i| layout.organs[i].visible);
        let r = ui.checkbox(&mut visible, "");
        accessible(&r, format!("Show group {}", group.name));
        if r.changed() {
            self.edit(Edit::Visible { organs: group.organs(), visible });
        }
        // Long names are cut short (hover shows them whole); the panel's width is capped too.
        // The name, with *Isolate* on right-click as an organ's name has it (rows stay narrow).
        let r = ui.add(egui::Label::new(RichText::new(short(&group.name)).strong()).sense(egui::Sense::click()));
        let mut isolate = false;
        r.on_hover_text(format!("{} (right-click: isolate)", group.name)).context_menu(|ui| {
            let r = ui.button("Isolate").on_hover_text("Show only this group");
            accessible(&r, format!("Isolate group {}", group.name));
            isolate = r.clicked();
            if isolate {
                ui.close();
            }
        });
        if isolate {
            self.edit(Edit::Isolate { organs: group.organs() });
        }
        let all_opaque = organs.iter().all(|&i| layout.organs[i].opacity >= 1.0);
        let r = ui.selectable_label(!all_opaque, "T").on_hover_text("Transparency of the whole group");
        accessible(&r, format!("Transparency of group {}", group.name));
        if r.clicked() {
            self.edit(scene.toggle_group_transparency(&group.path, &organs));
        }
        let mut opacity = organs.iter().map(|&i| layout.organs[i].opacity).sum::<f32>() / organs.len().max(1) as f32;
        let r = ui
            .add(egui::Slider::new(&mut opacity, 0.0..=1.0).show_value(false))
            .on_hover_text("Opacity of the whole group");
        accessible(&r, format!("Opacity of group {}", group.name));
        if r.changed() {
            self.edit(Edit::Opacity { organs: group.organs(), opacity });
        }
    }

    fn organ_row(&mut self, ui: &mut egui::Ui, i: usize) {
        let scene = self.scene;
        let name = &scene.set().organs[i].name;
        let state = scene.shown().organs[i];
        ui.horizontal(|ui| {
            let mut visible = state.visible;
            let r = ui.checkbox(&mut visible, "").on_hover_text("Show or hide");
            accessible(&r, format!("Show {name}"));
            if r.changed() {
                self.edit(Edit::Visible { organs: Organs::One(i), visible });
            }
            let r = ui.selectable_label(state.opacity < 1.0, "T").on_hover_text("Toggle transparency (T)");
            accessible(&r, format!("Transparency of {name}"));
            if r.clicked() {
                self.edit(scene.toggle_transparency(i));
            }
            let mut colour = state.colour;
            let r = ui.color_edit_button_rgb(&mut colour);
            accessible(&r, format!("Colour of {name}"));
            if r.changed() {
                self.edit(Edit::Colour { organs: Organs::One(i), colour });
            }
            let mut opacity = state.opacity;
            let r = ui.add(egui::Slider::new(&mut opacity, 0.0..=1.0).show_value(false)).on_hover_text("Opacity");
            accessible(&r, format!("Opacity of {name}"));
            if r.changed() {
                self.edit(Edit::Opacity { organs: Organs::One(i), opacity });
            }
            // The name takes what the row leaves and ends in "…" there; hover shows it whole.
            let r = ui.add(egui::Button::selectable(self.selected == Some(i), short(name)).truncate());
            let r = r.on_hover_text(name.as_str());
            accessible(&r, format!("Select {name}"));
            if r.clicked() {
                self.out.push(Action::Select(Some(i)));
            }
            r.context_menu(|ui| {
                if ui.button("Isolate").clicked() {
                    self.edit(Edit::Isolate { organs: Organs::One(i) });
                    ui.close();
                }
                if ui.button("Reset transform").clicked() {
                    self.edit(Edit::ResetTransform { organs: Organs::One(i) });
                    ui.close();
                }
            });
        });
    }
}
