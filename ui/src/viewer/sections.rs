//! The Sections window: the three anatomical planes (axial, coronal, sagittal), each on or off,
//! at a position in millimetres (world RAS, within the set's bounds), cutting away the superior,
//! anterior or right side or (flipped) the other one; buttons step a plane 1 mm or 5 mm at a
//! time; and solid cut faces on or off. The planes are part of what the viewport draws, picks and
//! exports; they are not saved in scenes yet.

use eframe::egui;
use vbrain::clip::ClipPlane;
use vbrain::mesh::Bounds;

/// One anatomical plane as the window sets it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneControl {
    pub on: bool,
    /// Millimetres along its axis.
    pub mm: f32,
    /// Keep the superior / anterior / right side instead.
    pub flip: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Sections {
    pub open: bool,
    /// Axial (z), coronal (y), sagittal (x).
    pub planes: [PlaneControl; 3],
    pub caps: bool,
    /// The planes that are on, as of the last [`Sections::show`].
    pub current: Vec<ClipPlane>,
}

impl Default for Sections {
    fn default() -> Self {
        let off = PlaneControl { on: false, mm: 0.0, flip: false };
        Sections { open: false, planes: [off; 3], caps: true, current: Vec::new() }
    }
}

const NAMES: [(&str, &str, &str); 3] =
    [("Axial", "superior", "inferior"), ("Coronal", "anterior", "posterior"), ("Sagittal", "right", "left")];

impl Sections {
    /// The planes that are on, as clip planes.
    pub fn clip_planes(&self) -> Vec<ClipPlane> {
        let axes = [glam::Vec3::Z, glam::Vec3::Y, glam::Vec3::X];
        self.planes
            .iter()
            .zip(axes)
            .filter(|(p, _)| p.on)
            .filter_map(|(p, axis)| ClipPlane::new(axis, p.mm).map(|c| if p.flip { c.flipped() } else { c }))
            .collect()
    }

    /// Takes a scene's planes: axis-aligned ones into the axial, coronal and sagittal controls
    /// (the others off). Returns false if some plane is oblique (left out).
    pub fn set_planes(&mut self, planes: &[ClipPlane], caps: bool) -> bool {
        self.planes.iter_mut().for_each(|p| p.on = false);
        self.caps = caps;
        let mut all = true;
        for plane in planes {
            let n = plane.normal;
            let axis = (0..3).find(|&k| n[k].abs() > 0.9999 && (0..3).all(|j| j == k || n[j].abs() < 1e-4));
            match axis {
                Some(k) => {
                    let flip = n[k] < 0.0;
                    self.planes[2 - k] = PlaneControl { on: true, mm: if flip { -plane.d } else { plane.d }, flip };
                }
                None => all = false,
            }
        }
        self.current = self.clip_planes();
        all
    }

    /// The window, over a set with these world bounds (positions are kept within them).
    pub fn show(&mut self, ctx: &egui::Context, bounds: Option<Bounds>) {
        let mut open = self.open;
        egui::Window::new("Sections").open(&mut open).resizable(false).show(ctx, |ui| {
            let Some(b) = bounds.filter(|b| !b.is_empty()) else {
                ui.label("Open an organ set to cut it.");
                return;
            };
            for (k, (name, removed, kept)) in NAMES.iter().enumerate() {
                let axis = 2 - k;
                let (lo, hi) = (b.min[axis].floor(), b.max[axis].ceil());
                let p = &mut self.planes[k];
                p.mm = if p.mm.is_finite() { p.mm.clamp(lo, hi) } else { (lo + hi) / 2.0 };
                ui.horizontal(|ui| {
                    ui.checkbox(&mut p.on, *name)
                        .on_hover_text(format!("Cut the set with the {} plane", name.to_lowercase()));
                    let slider = egui::Slider::new(&mut p.mm, lo..=hi).suffix(" mm").step_by(0.5);
                    let r = ui.add_enabled(p.on, slider);
                    super::widgets::accessible(&r, format!("{name} plane position"));
                    for (label, step) in [("-5", -5.0), ("-1", -1.0), ("+1", 1.0), ("+5", 5.0)] {
                        if ui.add_enabled(p.on, egui::Button::new(label).small()).clicked() {
                            p.mm = (p.mm + step).clamp(lo, hi);
                        }
                    }
                    let side = if p.flip { kept } else { removed };
                    ui.checkbox(&mut p.flip, "flip").on_hover_text(format!("Now removes the {side} side"));
                });
            }
            ui.separator();
            ui.checkbox(&mut self.caps, "Solid cut faces")
                .on_hover_text("Fill the cut faces of closed organs in their colour");
        });
        self.open = open;
        self.current = self.clip_planes();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_on_become_clip_planes() {
        let mut s = Sections::default();
        assert!(s.clip_planes().is_empty());
        s.planes[1] = PlaneControl { on: true, mm: -10.0, flip: true };
        let planes = s.clip_planes();
        assert_eq!(planes.len(), 1);
        assert!(planes[0].removes(glam::Vec3::new(0.0, -11.0, 0.0)), "flipped coronal removes the posterior side");
    }
}
