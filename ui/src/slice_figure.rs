//! A slice as radiology shows it (issue: sectional anatomy), for `vbrain slice` and the viewer's
//! slice panes: the set's MRI in grey through a window, each organ's outline in its colour, the
//! side letters in the top corners, and on demand leader-line labels.
//!
//! - Image pixels: origin top left, y down; the pane ([`vbrain::mri::slice::Pane`]) places them on
//!   the plane (millimetres RAS), radiological (patient's right on the left) by default.
//! - Organs are drawn as the layout shows them: hidden ones not at all, faded ones with outlines
//!   as faint as they are. A set without an MRI shows its organs filled in their colours instead.
//! - Outlines are `height / 400` pixels wide (at least one), so a figure reads alike at any size.

use crate::annotate::{self, Labels};
use image::{Rgba, RgbaImage};
use vbrain::layout::Layout;
use vbrain::mri::slice::{self, Pane};
use vbrain::mri::Window;
use vbrain::organ_set::OrganSet;

/// What a slice figure shows besides the MRI.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    pub outlines: bool,
    pub labels: Labels,
    pub window: Window,
    /// The side letters (R/L, A/P) in the top corners.
    pub letters: bool,
    /// An organ outlined boldly in yellow, over the other outlines (a quiz's structure).
    pub highlight: Option<usize>,
}

/// The organs a slice shows: those the layout draws.
pub fn shown(layout: &Layout) -> Vec<usize> {
    (0..layout.organs.len()).filter(|&o| layout.organs[o].is_drawn()).collect()
}

/// The bounds of the organs a slice shows, at rest: what a pane frames.
pub fn shown_bounds(set: &OrganSet, layout: &Layout) -> vbrain::mesh::Bounds {
    shown(layout).iter().fold(vbrain::mesh::Bounds::EMPTY, |b, &o| b.union(set.organs[o].bounds()))
}

/// The figure of `pane` through `set` as `layout` shows it, and its ID buffer (organ index + 1
/// per pixel, 0 for none) for picking and labels.
pub fn draw(set: &OrganSet, layout: &Layout, pane: &Pane, options: &Options) -> (RgbaImage, Vec<u32>) {
    let (w, h) = (pane.width, pane.height);
    let ids = slice::organ_ids(set, &shown(layout), pane);
    let greys = set.mri.as_ref().map(|mri| slice::greys(mri, pane, options.window));
    let mut image = RgbaImage::from_pixel(w, h, Rgba([0, 0, 0, 255]));
    let organ_colour = |id: u32| {
        let s = &layout.organs[id as usize - 1];
        (s.colour.map(|c| (c * 255.0).round() as u8), s.opacity)
    };
    for (i, p) in image.pixels_mut().enumerate() {
        let grey = match &greys {
            Some(g) => g.get(i).copied().flatten().map_or(0, |v| (v * 255.0).round() as u8),
            None => 0,
        };
        *p = Rgba([grey, grey, grey, 255]);
        if greys.is_none() && ids[i] != 0 {
            let (c, a) = organ_colour(ids[i]);
            *p = Rgba(std::array::from_fn(|k| if k == 3 { 255 } else { mix(grey, c[k], a) }));
        }
    }
    if options.outlines {
        let radius = (h / 800) as usize;
        let line = slice::outline(&ids, w, radius);
        for (i, p) in image.pixels_mut().enumerate() {
            if line[i] {
                let (c, a) = organ_colour(ids[i]);
                let c = if greys.is_none() { c.map(|v| v / 2) } else { c };
                *p = Rgba([mix(p[0], c[0], a), mix(p[1], c[1], a), mix(p[2], c[2], a), 255]);
            }
        }
    }
    if let Some(target) = options.highlight {
        let bold: Vec<u32> = ids.iter().map(|&id| u32::from(id == target as u32 + 1)).collect();
        let line = slice::outline(&bold, w, (h / 400).max(1) as usize);
        for (i, p) in image.pixels_mut().enumerate() {
            if line[i] {
                *p = Rgba([255, 225, 40, 255]);
            }
        }
    }
    if options.labels != Labels::None {
        annotate::draw(&mut image, &ids, &options.labels, |o| set.organs[o].name.clone());
    }
    if options.letters {
        let px = annotate::text_px(h) * 1.3;
        let [left, right] = pane.edge_letters();
        // In the top corners: labels take the sides.
        annotate::letter(&mut image, left, [px * 0.9, px * 0.9], px);
        annotate::letter(&mut image, right, [w as f32 - px * 0.9, px * 0.9], px);
    }
    (image, ids)
}

fn mix(a: u8, b: u8, t: f32) -> u8 {
    (a as f32 * (1.0 - t) + b as f32 * t).round() as u8
}

/// The caption of a slice: "Coronal slice, y = -10 mm (radiological: the patient's right on the
/// left)".
pub fn caption(pane: &Pane) -> String {
    let axis = pane.plane.axis;
    let mut name = axis.name().to_string();
    name[..1].make_ascii_uppercase();
    let side = match (axis, pane.radiological) {
        (vbrain::mri::slice::Axis::Sagittal, _) => "anterior on the left",
        (_, true) => "radiological: the patient's right on the left",
        (_, false) => "neurological: the patient's right on the right",
    };
    format!("{name} slice, {} = {} mm ({side})", axis.coordinate(), pane.plane.at)
}
