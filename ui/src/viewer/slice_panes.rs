//! The slice panes (View > Layout: 3-D | 3-D with slices | slices; issue: sectional anatomy):
//! axial, coronal and sagittal slices through one point, the crosshair, each drawn by
//! [`crate::slice_figure`] as the 3-D view's layout shows the organs (hidden ones not at all,
//! faded ones fainter).
//!
//! - The crosshair point is in world millimetres, RAS; each pane shows the plane through it
//!   perpendicular to its axis, framed on the organs shown at rest.
//! - A click in a pane moves the crosshair there (the other panes and the 3-D view's section planes
//!   that are on follow) and selects the organ under it, outlined boldly in yellow; the wheel or
//!   the arrow keys step the hovered pane's plane 1 mm; hovering names the structure.
//! - While a quiz asks, hovering names nothing, and a "name it" question's structure is outlined
//!   boldly; a click answers a "click it" question.
//! - Panes are redrawn only when what they show changed (plane, size, layout, window, display).

use super::action::Action;
use crate::viewer::action::SectionAction;
use eframe::egui;
use glam::Vec3;
use vbrain::layout::Layout;
use vbrain::mri::slice::{Axis, Pane, SlicePlane};
use vbrain::organ_set::OrganSet;

/// What a pane's image was drawn from: it is drawn again only when this changes.
#[derive(Clone, PartialEq)]
struct Drawn {
    pane: Pane,
    layout: Layout,
    window: vbrain::mri::Window,
    highlight: Option<usize>,
    title: String,
}

/// One pane's image and what it shows.
struct PaneImage {
    drawn: Drawn,
    texture: egui::TextureHandle,
    /// Organ index + 1 per pixel, for hovering and clicks.
    ids: Vec<u32>,
}

/// The crosshair and the panes' cached images.
pub struct SlicePanes {
    /// The crosshair, world millimetres; `None` until a set is shown (then its centre).
    pub point: Option<Vec3>,
    pub radiological: bool,
    pub window: vbrain::mri::Window,
    /// An organ outlined boldly in yellow: the selected one, or a quiz's "name it" structure.
    pub highlight: Option<usize>,
    /// Hovering names the structure (not while a quiz asks).
    pub names: bool,
    images: [Option<PaneImage>; 3],
    /// Where each pane was drawn last (points) and what it showed.
    shown: [Option<(egui::Rect, Pane)>; 3],
}

impl Default for SlicePanes {
    fn default() -> Self {
        SlicePanes {
            point: None,
            radiological: true,
            window: Default::default(),
            highlight: None,
            names: true,
            images: [None, None, None],
            shown: [None, None, None],
        }
    }
}

/// What the panes show this frame: the set, its layout, the bounds they frame, the selection.
#[derive(Clone, Copy)]
struct Showing<'a> {
    set: &'a OrganSet,
    layout: &'a Layout,
    shown: &'a vbrain::mesh::Bounds,
    selected: Option<usize>,
}

impl SlicePanes {
    /// A new set: the crosshair goes to its centre.
    pub fn new_set(&mut self) {
        self.point = None;
        self.images = [None, None, None];
        self.shown = [None, None, None];
    }

    /// Where the pane of `axis` was drawn last (points), and its pane, if it was.
    pub fn shown(&self, axis: Axis) -> Option<(egui::Rect, Pane)> {
        Axis::ALL.iter().position(|&a| a == axis).and_then(|k| self.shown[k])
    }

    /// The pane of `axis` in a `size` pixel rectangle, framing `bounds` (the organs shown).
    fn pane(&self, axis: Axis, bounds: &vbrain::mesh::Bounds, size: [u32; 2]) -> Option<Pane> {
        let point = self.point?;
        (!bounds.is_empty() && size[0] > 0 && size[1] > 0).then(|| {
            let plane = SlicePlane { axis, at: point[axis.normal()] };
            Pane::fit(plane, bounds, size[0], size[1], self.radiological)
        })
    }

    /// The three panes in `rect`: in a column where it is taller than wide, else in a row.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        rect: egui::Rect,
        set: &OrganSet,
        layout: &Layout,
        selected: Option<usize>,
    ) -> Vec<Action> {
        let mut out = Vec::new();
        // Once a frame, for the three panes.
        let shown = crate::slice_figure::shown_bounds(set, layout);
        if self.point.is_none() {
            self.point = Some(if shown.is_empty() { set.bounds() } else { shown }.center());
        }
        let column = rect.height() > rect.width();
        let gap = 4.0;
        let n = 3.0;
        let (w, h) = if column {
            (rect.width(), (rect.height() - gap * 2.0) / n)
        } else {
            ((rect.width() - gap * 2.0) / n, rect.height())
        };
        ui.painter().rect_filled(rect, 0.0, egui::Color32::from_gray(8));
        self.shown = [None, None, None];
        for (k, axis) in Axis::ALL.into_iter().enumerate() {
            let offset = k as f32 * if column { h + gap } else { w + gap };
            let min = rect.min + if column { egui::vec2(0.0, offset) } else { egui::vec2(offset, 0.0) };
            let pane_rect = egui::Rect::from_min_size(min, egui::vec2(w, h));
            let what = Showing { set, layout, shown: &shown, selected };
            out.extend(self.pane_ui(ui, (k, axis), pane_rect, &what));
        }
        out
    }

    fn pane_ui(
        &mut self,
        ui: &mut egui::Ui,
        (k, axis): (usize, Axis),
        rect: egui::Rect,
        what: &Showing,
    ) -> Vec<Action> {
        let Showing { set, layout, shown, selected } = *what;
        let mut out = Vec::new();
        let ppp = ui.ctx().pixels_per_point();
        let size = [(rect.width() * ppp).round().max(1.0) as u32, (rect.height() * ppp).round().max(1.0) as u32];
        let Some(pane) = self.pane(axis, shown, size) else { return out };
        self.shown[k] = Some((rect, pane));
        let title = format!("{} {} = {:.0} mm", axis.name(), axis.coordinate(), pane.plane.at);
        let drawn = Drawn { pane, layout: layout.clone(), window: self.window, highlight: self.highlight, title };
        if self.images[k].as_ref().is_none_or(|i| i.drawn != drawn) {
            let options = crate::slice_figure::Options {
                outlines: true,
                labels: crate::annotate::Labels::None,
                window: self.window,
                letters: true,
                highlight: self.highlight,
            };
            let (image, ids) = crate::slice_figure::draw(set, layout, &pane, &options);
            let colour = egui::ColorImage::from_rgba_unmultiplied([size[0] as usize, size[1] as usize], image.as_raw());
            let texture = ui.ctx().load_texture(format!("slice {}", axis.name()), colour, egui::TextureOptions::LINEAR);
            self.images[k] = Some(PaneImage { drawn, texture, ids });
        }
        let Some(image) = &self.images[k] else { return out };
        let response = ui.interact(rect, ui.scope_id().with(("slice pane", k)), egui::Sense::click_and_drag());
        let painter = ui.painter_at(rect);
        painter.image(
            image.texture.id(),
            rect,
            egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
            egui::Color32::WHITE,
        );
        // The crosshair: where the other two planes cross this one.
        let point = self.point.unwrap_or(Vec3::ZERO);
        let at = pane.pixel(point) / ppp;
        let at = rect.min + egui::vec2(at.x, at.y);
        let stroke = egui::Stroke::new(1.0, egui::Color32::from_rgba_unmultiplied(90, 220, 255, 170));
        painter.line_segment([egui::pos2(rect.left(), at.y), egui::pos2(rect.right(), at.y)], stroke);
        painter.line_segment([egui::pos2(at.x, rect.top()), egui::pos2(at.x, rect.bottom())], stroke);
        painter.text(
            rect.left_bottom() + egui::vec2(6.0, -6.0),
            egui::Align2::LEFT_BOTTOM,
            &image.drawn.title,
            egui::FontId::proportional(13.0),
            egui::Color32::from_gray(220),
        );
        if let Some(o) = selected.filter(|&o| o < set.organs.len()) {
            painter.text(
                rect.right_bottom() + egui::vec2(-6.0, -6.0),
                egui::Align2::RIGHT_BOTTOM,
                &set.organs[o].name,
                egui::FontId::proportional(13.0),
                egui::Color32::from_rgb(255, 235, 120),
            );
        }
        // What is under a pixel of the pane.
        let under = |pos: egui::Pos2| {
            let p = (pos - rect.min) * ppp;
            let (x, y) = (p.x as usize, p.y as usize);
            let inside = x < size[0] as usize && y < size[1] as usize;
            let id = if inside { image.ids.get(y * size[0] as usize + x).copied().unwrap_or(0) } else { 0 };
            (pane.world(p.x, p.y), id.checked_sub(1).map(|o| o as usize))
        };
        if let Some(pos) = response.hover_pos() {
            if let (true, (_, Some(o))) = (self.names, under(pos)) {
                response.clone().on_hover_text_at_pointer(&set.organs[o].name);
            }
            let (scroll, keys) = ui.input(|i| {
                let up = i.key_pressed(egui::Key::ArrowUp) || i.key_pressed(egui::Key::ArrowRight);
                let down = i.key_pressed(egui::Key::ArrowDown) || i.key_pressed(egui::Key::ArrowLeft);
                // One step per wheel notch (the raw events, not the smoothed delta).
                let wheel: f32 = i
                    .raw
                    .events
                    .iter()
                    .filter_map(|e| match e {
                        egui::Event::MouseWheel { delta, .. } => Some(delta.y),
                        _ => None,
                    })
                    .sum();
                (wheel, up as i32 - down as i32)
            });
            let step = if scroll > 0.0 {
                1.0
            } else if scroll < 0.0 {
                -1.0
            } else {
                keys as f32
            };
            if step != 0.0 {
                let mut p = point;
                p[axis.normal()] += step;
                out.push(Action::Section(SectionAction::SlicePoint(p)));
            }
        }
        if response.clicked() || response.dragged() {
            if let Some(pos) = response.interact_pointer_pos() {
                let (world, organ) = under(pos);
                out.push(Action::Section(SectionAction::SlicePoint(world)));
                if response.clicked() {
                    out.push(Action::Pick(organ));
                }
            }
        }
        out
    }
}
