//! The Sections panel (a tab of the dock): the three anatomical planes (axial, coronal, sagittal)
//! and one oblique plane, solid cut faces on or off, and the organs kept whole (set from the
//! inspector).
//!
//! - Each plane is on or off, at a position in millimetres (world RAS, kept within the set's
//!   bounds), cutting away the superior, anterior or right side or (flipped) the other one.
//! - The oblique plane's normal is set by "Align to view": it then faces the camera and cuts away
//!   what lies nearer the eye.
//! - Buttons step a plane 1 mm or 5 mm at a time; while the panel is open each plane has a handle
//!   in the viewport to drag it along its normal.
//! - What the panel sets is one [`vbrain::clip::Section`], drawn, picked, exported and saved in
//!   scenes and lesson steps.

use eframe::egui;
use glam::Vec3;
use vbrain::clip::{ClipPlane, Section};
use vbrain::mesh::Bounds;

pub use super::action::{Handle, Slot};

/// One plane as the window sets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneControl {
    pub on: bool,
    /// Millimetres along its normal.
    pub mm: f32,
    /// Keep the side the normal points to instead.
    pub flip: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Sections {
    pub open: bool,
    /// Axial (z), coronal (y), sagittal (x), oblique (along `oblique_normal`).
    pub planes: [PlaneControl; 4],
    /// The oblique plane's unit normal (into the side removed, unflipped).
    pub oblique_normal: Vec3,
    /// What the controls set, as of the last change: its cut faces and organs kept whole are
    /// set here directly, its planes from `planes`.
    pub current: Section,
}

impl Default for Sections {
    fn default() -> Self {
        let off = PlaneControl { on: false, mm: 0.0, flip: false };
        Sections {
            open: false,
            planes: [off; 4],
            oblique_normal: Vec3::new(0.0, -1.0, 1.0).normalize(),
            current: Section::default(),
        }
    }
}

const NAMES: [(&str, &str, &str); 4] = [
    ("Axial", "superior", "inferior"),
    ("Coronal", "anterior", "posterior"),
    ("Sagittal", "right", "left"),
    ("Oblique", "near", "far"),
];

impl Sections {
    /// The unit normal of control `slot` (unflipped).
    pub fn normal(&self, slot: Slot) -> Vec3 {
        [Vec3::Z, Vec3::Y, Vec3::X, self.oblique_normal][slot.min(3)]
    }

    /// The section the controls set.
    pub fn section(&self) -> Section {
        let planes = (0..4)
            .filter(|&k| self.planes[k].on)
            .filter_map(|k| {
                let p = self.planes[k];
                ClipPlane::new(self.normal(k), p.mm).map(|c| if p.flip { c.flipped() } else { c })
            })
            .collect();
        Section { planes, caps: self.current.caps, faces: self.current.faces, whole: self.current.whole.clone() }
    }

    fn changed(&mut self) {
        self.current = self.section();
    }

    /// Takes a scene's or a lesson step's section: axis-aligned planes into the axial, coronal and
    /// sagittal controls, one other into the oblique control. Returns how many planes were left
    /// out (a second oblique one, or a second plane on one axis).
    pub fn set_section(&mut self, section: &Section) -> usize {
        self.planes.iter_mut().for_each(|p| p.on = false);
        (self.current.caps, self.current.faces, self.current.whole) =
            (section.caps, section.faces, section.whole.clone());
        self.current.whole.sort_unstable();
        self.current.whole.dedup();
        let mut left_out = 0;
        for plane in &section.planes {
            let n = plane.normal();
            let axis = (0..3).find(|&k| n[k].abs() > 0.9999 && (0..3).all(|j| j == k || n[j].abs() < 1e-4));
            let (slot, flip) = match axis {
                Some(k) => (2 - k, n[k] < 0.0),
                None => (3, false),
            };
            if self.planes[slot].on {
                left_out += 1;
                continue;
            }
            if slot == 3 {
                self.oblique_normal = n;
            }
            self.planes[slot] = PlaneControl { on: true, mm: if flip { -plane.d } else { plane.d }, flip };
        }
        self.changed();
        left_out
    }

    /// Marks organ `organ` kept whole or not.
    pub fn set_whole(&mut self, organ: usize, whole: bool) {
        self.current.whole.retain(|&o| o != organ);
        if whole {
            self.current.whole.push(organ);
            self.current.whole.sort_unstable();
        }
        self.changed();
    }

    /// The range of positions of control `slot` over `bounds`: the box's extent along its normal.
    fn range(&self, slot: Slot, b: &Bounds) -> (f32, f32) {
        let along = b.corners().map(|c| self.normal(slot).dot(c));
        let lo = along.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = along.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        (lo.floor(), hi.ceil())
    }

    /// Moves the axial, coronal and sagittal planes that are on through `point` (world
    /// millimetres), within `bounds`.
    pub fn move_to(&mut self, point: Vec3, bounds: &Bounds) {
        for slot in 0..3 {
            if self.planes[slot].on {
                let (lo, hi) = self.range(slot, bounds);
                let at = self.normal(slot).dot(point);
                if at.is_finite() {
                    self.planes[slot].mm = at.clamp(lo, hi);
                }
            }
        }
        self.changed();
    }

    /// Moves plane `slot` by `mm` along its normal, within `bounds`.
    pub fn move_plane(&mut self, slot: Slot, mm: f32, bounds: &Bounds) {
        let (lo, hi) = self.range(slot.min(3), bounds);
        let p = &mut self.planes[slot.min(3)];
        if mm.is_finite() {
            p.mm = (p.mm + mm).clamp(lo, hi);
        }
        self.changed();
    }

    /// The oblique plane faces the camera looking along `forward`, through the middle of `bounds`:
    /// it cuts away the half nearer the eye.
    pub fn align_to_view(&mut self, forward: Vec3, bounds: &Bounds) {
        let n = -forward.normalize_or_zero();
        if n == Vec3::ZERO || !n.is_finite() {
            return;
        }
        self.oblique_normal = n;
        let centre = (Vec3::from(bounds.min) + Vec3::from(bounds.max)) / 2.0;
        self.planes[3] = PlaneControl { on: true, mm: n.dot(centre), flip: false };
        self.changed();
    }

    /// The handles of the planes that are on, where each crosses the line through the middle of
    /// `bounds` along its normal.
    pub fn handles(&self, bounds: &Bounds) -> Vec<Handle> {
        let centre = (Vec3::from(bounds.min) + Vec3::from(bounds.max)) / 2.0;
        (0..4)
            .filter(|&k| self.planes[k].on)
            .map(|k| {
                let n = self.normal(k);
                Handle { slot: k, at: centre + n * (self.planes[k].mm - n.dot(centre)), normal: n }
            })
            .collect()
    }

    /// The panel (a tab of the dock) over a set with these world bounds (positions are kept within
    /// them); `forward` is the camera's view direction, for "Align to view"; `has_mri`: whether the
    /// set has an MRI to show on cut faces; `name` names organs kept whole. Returns whether the
    /// section changed.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        bounds: Option<Bounds>,
        forward: Vec3,
        has_mri: bool,
        name: impl Fn(usize) -> String,
    ) -> bool {
        let before =
            (self.planes, self.oblique_normal, self.current.caps, self.current.faces, self.current.whole.clone());
        ui.vertical(|ui| {
            let Some(b) = bounds.filter(|b| !b.is_empty()) else {
                ui.label("Open an organ set to cut it.");
                return;
            };
            for (k, (name, removed, kept)) in NAMES.iter().enumerate() {
                let (lo, hi) = self.range(k, &b);
                let p = &mut self.planes[k];
                p.mm = if p.mm.is_finite() { p.mm.clamp(lo, hi) } else { (lo + hi) / 2.0 };
                ui.horizontal_wrapped(|ui| {
                    ui.checkbox(&mut p.on, *name)
                        .on_hover_text(format!("Cut the set with the {} plane", name.to_lowercase()));
                    let slider = egui::Slider::new(&mut p.mm, lo..=hi).suffix(" mm").step_by(0.5);
                    let r = ui.add_enabled(p.on, slider);
                    super::widgets::accessible(&r, format!("{name} plane position"));
                    for (label, step) in [("-5", -5.0), ("-1", -1.0), ("+1", 1.0), ("+5", 5.0)] {
                        let r = ui.add_enabled(p.on, egui::Button::new(label).small());
                        if r.on_hover_text(format!("Move the plane {label} mm")).clicked() {
                            p.mm = (p.mm + step).clamp(lo, hi);
                        }
                    }
                    let side = if p.flip { kept } else { removed };
                    ui.checkbox(&mut p.flip, "flip").on_hover_text(format!("Now removes the {side} side"));
                });
            }
            ui.horizontal(|ui| {
                let n = self.oblique_normal;
                ui.label(egui::RichText::new(format!("oblique normal ({:.2}, {:.2}, {:.2})", n.x, n.y, n.z)).weak());
                if ui
                    .button("Align to view")
                    .on_hover_text("Turn the oblique plane to face the camera, through the middle of the set")
                    .clicked()
                {
                    self.align_to_view(forward, &b);
                }
            });
            ui.label(egui::RichText::new("Drag a plane's handle in the view to move it.").weak());
            ui.separator();
            ui.checkbox(&mut self.current.caps, "Solid cut faces").on_hover_text("Fill the cut faces of closed organs");
            ui.add_enabled_ui(self.current.caps && has_mri, |ui| cut_faces(ui, &mut self.current.faces))
                .response
                .on_disabled_hover_text(if has_mri {
                    "Turn solid cut faces on to choose what they show"
                } else {
                    "This organ set has no MRI: cut faces show the organs' colours"
                });
            if self.current.whole.is_empty() {
                ui.label(egui::RichText::new("No organ kept whole (see the inspector's \"Do not cut\").").weak());
            } else {
                ui.label("Kept whole:");
                let mut keep = None;
                ui.horizontal_wrapped(|ui| {
                    for &o in &self.current.whole {
                        if ui.small_button(format!("{} ×", name(o))).on_hover_text("Cut it again").clicked() {
                            keep = Some(o);
                        }
                    }
                });
                if let Some(o) = keep {
                    self.current.whole.retain(|&w| w != o);
                }
            }
        });
        let changed = before
            != (self.planes, self.oblique_normal, self.current.caps, self.current.faces, self.current.whole.clone());
        if changed {
            self.changed();
        }
        changed
    }
}

/// What cut faces show, and the MRI's window and level.
fn cut_faces(ui: &mut egui::Ui, faces: &mut vbrain::clip::CutFace) {
    use vbrain::clip::CutFaceShows;
    ui.horizontal(|ui| {
        ui.label("Cut faces:");
        egui::ComboBox::from_id_salt("cut faces").selected_text(faces.show.label()).show_ui(ui, |ui| {
            for show in CutFaceShows::ALL {
                ui.selectable_value(&mut faces.show, show, show.label());
            }
        });
    })
    .response
    .on_hover_text("What the cut faces of closed organs show: their colour, the set's MRI, or the MRI tinted by organ");
    if faces.show != CutFaceShows::Colour {
        let w = &mut faces.window;
        ui.horizontal(|ui| {
            let r = ui.add(egui::Slider::new(&mut w.window, 0.05..=2.0).text("window"));
            super::widgets::accessible(&r, "MRI window".to_string());
            r.on_hover_text("The range of MRI intensities from black to white (narrower: more contrast)");
            let r = ui.add(egui::Slider::new(&mut w.level, 0.0..=1.0).text("level"));
            super::widgets::accessible(&r, "MRI level".to_string());
            r.on_hover_text("The MRI intensity shown as middle grey");
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_on_become_the_section() {
        let mut s = Sections::default();
        assert!(s.section().planes.is_empty());
        s.planes[1] = PlaneControl { on: true, mm: -10.0, flip: true };
        let planes = s.section().planes;
        assert_eq!(planes.len(), 1);
        assert!(planes[0].removes(Vec3::new(0.0, -11.0, 0.0)), "flipped coronal removes the posterior side");
    }

    #[test]
    fn a_section_reads_back_and_handles_move_planes() {
        let b = Bounds { min: [-70.0, -100.0, -50.0], max: [70.0, 70.0, 80.0] };
        let mut s = Sections::default();
        s.align_to_view(Vec3::new(1.0, 1.0, 0.0), &b);
        s.planes[2] = PlaneControl { on: true, mm: 3.0, flip: true };
        s.set_whole(4, true);
        let section = s.section();
        assert_eq!(section.planes.len(), 2);
        assert!(section.planes[1].removes(Vec3::new(-20.0, -15.0, 15.0)), "near the eye, removed");
        let mut back = Sections::default();
        assert_eq!(back.set_section(&section), 0);
        assert_eq!(back.section(), section);
        let h = back.handles(&b);
        assert_eq!(h.len(), 2);
        assert!((h[0].at.x - 3.0).abs() < 1e-4 && h[0].normal == Vec3::X);
        back.move_plane(2, 500.0, &b);
        assert_eq!(back.planes[2].mm, 70.0, "kept within the set");
        let two_oblique = Section { planes: vec![section.planes[1], section.planes[1].flipped()], ..section };
        assert_eq!(back.set_section(&two_oblique), 1);
    }
}
