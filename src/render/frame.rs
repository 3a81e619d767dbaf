//! What one frame shows ([`FrameInput`]), what drawing it counted ([`RenderStats`]), and the one
//! interface through which the renderer calls each drawing technique ([`Technique`]).
//!
//! - The background is linear RGBA (alpha 0: transparent); organs are drawn in index order unless
//!   the frame gives a permutation; without a draw list every drawn organ is drawn whole.

use super::scene::GpuScene;
use super::target::{Kept, Target};
use crate::camera::Camera;
use crate::clip::{Section, NO_SECTION};
use crate::cull::DrawList;
use crate::error::Result;
use crate::layout::Layout;
use crate::organ_set::OrganSet;
use crate::transparency::TransparencySettings;

/// What one frame shows.
#[derive(Clone, Copy)]
pub struct FrameInput<'a> {
    /// The set the renderer was made for (screen-door masks are built from its meshes).
    pub set: &'a OrganSet,
    pub camera: &'a Camera,
    pub layout: &'a Layout,
    /// What survived culling; `None` draws every drawn organ whole.
    pub draw: Option<&'a DrawList>,
    /// Linear RGBA clear colour; alpha 0 gives a transparent background.
    pub background: [f32; 4],
    /// How transparent organs are drawn.
    pub transparency: TransparencySettings,
    /// The camera or an organ is moving: screen-door uses its interactive sub-sample count.
    pub moving: bool,
    /// Order in which organs are drawn (a permutation of organ indices); `None` is index order.
    pub draw_order: Option<&'a [usize]>,
    /// Organs outlined as highlighted (a lesson step's), seen through whatever is in front.
    pub highlight: &'a [usize],
    /// The selected organ, outlined in its own colour.
    pub selection: Option<usize>,
    /// The cross-section: clip planes, cut faces, organs kept whole.
    pub section: &'a Section,
    /// Progressive refinement (the viewer): if the target shows this same frame in part, add one
    /// more screen-door pass to it; otherwise start it with the interactive count of passes.
    /// `false` draws the full count at once (exports, headless renders).
    pub refine: bool,
    /// Measure the frame's GPU time ([`RenderStats::gpu_ms`]); waits for the GPU, so for benchmarks.
    pub time_gpu: bool,
}

impl<'a> FrameInput<'a> {
    /// A still frame of every drawn organ on a transparent background, default transparency.
    pub fn new(set: &'a OrganSet, camera: &'a Camera, layout: &'a Layout) -> FrameInput<'a> {
        FrameInput {
            set,
            camera,
            layout,
            draw: None,
            background: [0.0; 4],
            transparency: TransparencySettings::default(),
            moving: false,
            draw_order: None,
            highlight: &[],
            selection: None,
            section: &NO_SECTION,
            refine: false,
            time_gpu: false,
        }
    }

    /// A hash of everything that changes the image a technique draws: equal for the same frame.
    /// Not `refine` or `time_gpu`; not the outlines (`highlight`, `selection`), drawn over the
    /// finished image at every call; and not the draw list: culling never changes a pixel, so
    /// passes drawn with different lists of the same view add up to the same image. The struct is taken apart
    /// field by field, so that a new field must be placed here or left out on purpose.
    pub fn fingerprint(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let FrameInput {
            set: _,
            camera,
            layout,
            draw: _,
            background,
            transparency,
            moving,
            draw_order,
            highlight: _,
            selection: _,
            section,
            refine: _,
            time_gpu: _,
        } = *self;
        let mut h = std::collections::hash_map::DefaultHasher::new();
        let floats =
            |v: &[f32], h: &mut std::collections::hash_map::DefaultHasher| v.iter().for_each(|f| f.to_bits().hash(h));
        let c = camera;
        floats(&[c.eye.x, c.eye.y, c.eye.z, c.target.x, c.target.y, c.target.z], &mut h);
        floats(&[c.up.x, c.up.y, c.up.z, c.fov_y, c.near, c.far], &mut h);
        for s in &layout.organs {
            (s.visible, s.opacity.to_bits()).hash(&mut h);
            let t = &s.transform;
            floats(&s.colour, &mut h);
            floats(&t.translation.to_array(), &mut h);
            floats(&t.rotation_deg.to_array(), &mut h);
            floats(&t.pivot.to_array(), &mut h);
            t.scale.to_bits().hash(&mut h);
        }
        floats(&background, &mut h);
        let t = &transparency;
        (t.mode.name(), t.subsamples, t.interactive_subsamples, t.region_px, t.k).hash(&mut h);
        (moving, draw_order, section.caps, &section.whole).hash(&mut h);
        for p in &section.planes {
            floats(&p.normal, &mut h);
            p.d.to_bits().hash(&mut h);
        }
        h.finish()
    }

    /// Organ indices in drawing order.
    pub(crate) fn order(&self, count: usize) -> Vec<usize> {
        match self.draw_order {
            Some(o) if o.len() == count && o.iter().all(|&i| i < count) => o.to_vec(),
            _ => (0..count).collect(),
        }
    }

    /// Of the first `count` organs, the opaque and the transparent (drawn, faded) ones, each in
    /// drawing order.
    pub(super) fn split(&self, count: usize) -> (Vec<usize>, Vec<usize>) {
        let states = &self.layout.organs;
        let order = self.order(count.min(states.len()));
        let opaque = order.iter().copied().filter(|&i| states[i].is_opaque()).collect();
        let transparent = order.iter().copied().filter(|&i| states[i].is_drawn() && !states[i].is_opaque()).collect();
        (opaque, transparent)
    }

    /// Whether any drawn organ is faded.
    pub fn has_transparent(&self) -> bool {
        self.layout.organs.iter().any(|s| s.is_drawn() && !s.is_opaque())
    }
}

/// Counts of one rendered frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderStats {
    pub organs_drawn: usize,
    pub triangles_drawn: usize,
    /// Passes over the scene (screen-door draws one per 4 sub-samples).
    pub passes: usize,
    /// Screen-door mask regeneration: milliseconds and distinct region configurations.
    pub mask_ms: f64,
    pub mask_configs: usize,
    /// Screen-door: sub-samples in the image so far, of the frame's full count (equal once
    /// converged; both 0 for the other techniques).
    pub subsamples_done: usize,
    pub subsamples_total: usize,
    /// The frame's GPU time in milliseconds, when asked for and the adapter has timestamp queries.
    pub gpu_ms: Option<f64>,
}

/// Everything a technique draws a frame with.
pub(super) struct Frame<'a> {
    pub device: &'a wgpu::Device,
    pub queue: &'a wgpu::Queue,
    pub scene: &'a GpuScene,
    pub input: &'a FrameInput<'a>,
    pub target: &'a Target,
}

/// A way of drawing a frame (opaque and blended, screen-door, weighted blended, exact, the culling
/// debug view). It writes its per-frame and per-pass data (uniform slots, pooled buffers) through
/// the queue and records its passes into the frame's encoder, which the renderer submits. What it
/// keeps for the next frame into the same target (buffers, bind groups, a frame drawn in part) it
/// keeps in the target's [`Kept`], never in itself. Most
/// techniques record the whole frame there; depth peeling submits each peel on its own (an
/// occlusion query then says whether to go on), and the exact reference submits a layer at a time.
pub(super) trait Technique {
    /// Records the frame; the stats' `passes` and mask figures (the renderer counts what was drawn).
    fn record(&self, frame: &Frame, kept: &mut Kept, encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats>;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::View;
    use crate::clip::ClipPlane;
    use crate::organ_set::Organ;

    /// Each field that changes what a technique draws changes the fingerprint; the others do not.
    #[test]
    fn the_fingerprint_follows_what_changes_the_image() {
        let triangle = crate::mesh::Mesh {
            positions: vec![[0.0; 3], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]],
            normals: vec![[0.0, 0.0, 1.0]; 3],
            indices: vec![0, 1, 2],
        };
        let set =
            OrganSet { organs: vec![Organ::new("a".into(), "A".into(), [0.5; 3], triangle)], ..Default::default() };
        let layout = Layout::new(&set);
        let camera = Camera::view(&layout.bounds(&set), View::Anterior);
        let base = FrameInput::new(&set, &camera, &layout);
        let of = |f: FrameInput| f.fingerprint();
        let cut = Section { planes: vec![ClipPlane::parse("axial=0").unwrap()], ..Section::default() };
        let no_caps = Section { caps: false, ..Section::default() };
        let whole = Section { whole: vec![0], ..Section::default() };
        let moved = Camera { eye: camera.eye + glam::Vec3::X, ..camera };
        let mut faded = layout.clone();
        faded.organs[0].opacity = 0.5;
        let order = [0usize];
        let changed = [
            FrameInput { section: &cut, ..base },
            FrameInput { section: &no_caps, ..base },
            FrameInput { section: &whole, ..base },
            FrameInput { camera: &moved, ..base },
            FrameInput { layout: &faded, ..base },
            FrameInput { background: [1.0; 4], ..base },
            FrameInput { moving: true, ..base },
            FrameInput { draw_order: Some(&order), ..base },
            FrameInput { transparency: TransparencySettings { region_px: 8, ..base.transparency }, ..base },
        ];
        for (i, f) in changed.into_iter().enumerate() {
            assert_ne!(of(f), of(base), "change {i} must change the fingerprint");
        }
        let draw = DrawList { ranges: vec![Vec::new()] };
        let same = [
            FrameInput { refine: true, ..base },
            FrameInput { time_gpu: true, ..base },
            FrameInput { draw: Some(&draw), ..base },
            FrameInput { selection: Some(0), highlight: &order, ..base },
        ];
        for (i, f) in same.into_iter().enumerate() {
            assert_eq!(of(f), of(base), "change {i} must leave the fingerprint");
        }
    }
}
