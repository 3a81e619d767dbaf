//! The renderer: pipelines and the set's GPU meshes, made once per device and organ set; each call
//! draws one frame from plain per-frame data ([`FrameInput`]) into a [`Target`] by one technique,
//! recorded into one encoder and submitted once (depth peeling and the exact reference submit
//! their passes as they go; see [`super::frame::Technique`]).
//! - The renderer holds nothing per view: what a technique keeps between frames (buffers, bind
//!   groups, a screen-door frame drawn in part) lives in the target, which the caller owns, so
//!   the calls that draw into a target take it `&mut`.

use super::blend::Blend;
use super::debug::CullDebug;
use super::exact::Exact;
use super::frame::{Frame, FrameInput, RenderStats, Technique};
use super::ids::{IdKind, Ids};
use super::kbuffer::KBuffer;
use super::outline::Outline;
use super::peel::{Peel, PeelFrame};
use super::pipelines::{Composite, PipelineFactory};
use super::scene::GpuScene;
use super::screendoor::{self, opaque_hdr, Screendoor, ScreendoorFrame};
use super::target::Target;
use super::timer::GpuTimer;
use super::weighted::{Weighted, WeightedFrame};
use crate::error::Result;
use crate::organ_set::OrganSet;
use crate::transparency::TransparencyMode;

pub struct Renderer {
    scene: GpuScene,
    sorted: Blend,
    unsorted: Blend,
    screendoor: Screendoor,
    weighted: Weighted,
    peel: Peel,
    kbuffer: KBuffer,
    exact: Exact,
    composite: Composite,
    ids: Ids,
    outline: Outline,
    timer: Option<GpuTimer>,
    /// The organ pipelines cut triangles at the clip planes (clip distances).
    cuts_geometry: bool,
}

impl Renderer {
    /// Creates the pipelines and uploads the set's meshes.
    pub fn new(device: &wgpu::Device, set: &OrganSet) -> Result<Renderer> {
        super::guard::guarded(device, "uploading the organs", || Self::make(device, set))
    }

    fn make(device: &wgpu::Device, set: &OrganSet) -> Result<Renderer> {
        let scene = GpuScene::new(device, set)?;
        let factory = PipelineFactory::new(device);
        let composite = Composite::new(device);
        let [sorted, unsorted] = Blend::new(&factory, &scene.layout);
        let hdr = opaque_hdr(&factory, &scene.layout);
        let screendoor = Screendoor::new(device, &factory, &scene, &composite, hdr.clone());
        let peel = Peel::new(device, &factory, &scene, &composite, hdr.clone());
        let kbuffer = KBuffer::new(device, &factory, &scene, hdr.clone());
        let weighted = Weighted::new(device, &factory, &scene.layout, &composite, hdr);
        let exact = Exact::new(&factory, &scene.layout);
        let ids = Ids::new(&factory, &scene.layout);
        let outline = Outline::new(device, &factory, &scene.layout, &composite);
        let timer = GpuTimer::new(device);
        let cuts_geometry = factory.cuts_geometry();
        Ok(Renderer {
            scene,
            sorted,
            unsorted,
            screendoor,
            weighted,
            peel,
            kbuffer,
            exact,
            composite,
            ids,
            outline,
            timer,
            cuts_geometry,
        })
    }

    /// Whether triangles are cut at the clip planes before they are rasterised (the device has clip
    /// distances), so that what the planes remove draws no sample and culling may leave it out
    /// ([`crate::cull::CullInput::exact_cuts`]).
    pub fn cuts_geometry(&self) -> bool {
        self.cuts_geometry
    }

    /// What culling `frame` for this renderer into `target` takes: the same set, layout, camera
    /// and section, at the target's aspect.
    pub fn cull_input<'a>(&self, frame: &FrameInput<'a>, target: &Target) -> crate::cull::CullInput<'a> {
        crate::cull::CullInput {
            set: frame.set,
            layout: frame.layout,
            camera: frame.camera,
            aspect: target.aspect(),
            section: frame.section,
            exact_cuts: self.cuts_geometry,
        }
    }

    /// Draws organs coarser (Callahan 2005, ch. 5), aware of culling: each organ with
    /// `levels[organ]` k > 0 is drawn whole at its level of detail k (its coarsest, where it has
    /// fewer) in place of what culling kept of its full mesh, where that level has fewer triangles
    /// than culling kept. An organ culling removed stays removed, so culling stays conservative
    /// at any level; one mostly hidden keeps its culled full mesh.
    pub fn coarsen(&self, draw: &mut crate::cull::DrawList, levels: &[u8]) {
        for (organ, (ranges, &k)) in draw.ranges.iter_mut().zip(levels).enumerate() {
            let mine = self.scene.levels(organ);
            if k == 0 || mine.is_empty() {
                continue;
            }
            let level = &mine[(k as usize).min(mine.len()) - 1];
            let kept: u32 = ranges.iter().map(|r| r.end - r.start).sum();
            if kept > level.end - level.start {
                *ranges = vec![level.clone()];
            }
        }
    }

    /// Draws the frame into `target`'s colour image: opaque organs with depth, then transparent ones
    /// as `frame.transparency` says, then the outlines of highlighted and selected organs.
    pub fn render(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &mut Target,
        frame: &FrameInput,
    ) -> Result<RenderStats> {
        let screendoor = ScreendoorFrame { technique: &self.screendoor, composite: &self.composite };
        let weighted = WeightedFrame { technique: &self.weighted, composite: &self.composite };
        let peel = PeelFrame { technique: &self.peel, composite: &self.composite, dual: false };
        let dual_peel = PeelFrame { dual: true, ..peel };
        let screendoor_mode = frame.transparency.mode.mask_method().is_some() && frame.has_transparent();
        if !screendoor_mode {
            // It draws into the images a refined screen-door frame continues from.
            screendoor::forget(&mut target.kept);
        }
        let technique: &dyn Technique = match frame.transparency.mode {
            _ if !frame.has_transparent() => &self.sorted,
            TransparencyMode::AlphaSorted => &self.sorted,
            TransparencyMode::AlphaUnsorted => &self.unsorted,
            TransparencyMode::WeightedBlended => &weighted,
            TransparencyMode::Exact => &self.exact,
            TransparencyMode::Peel => &peel,
            TransparencyMode::DualPeel => &dual_peel,
            TransparencyMode::KBuffer => &self.kbuffer,
            TransparencyMode::Screendoor
            | TransparencyMode::ScreendoorWhitenoise
            | TransparencyMode::ScreendoorPixeltree => &screendoor,
        };
        self.draw_with(technique, device, queue, target, frame)
    }

    /// Draws only the outlines of `frame`'s highlighted and selected organs over what `target`
    /// holds: a frame drawn without them becomes the one [`Renderer::render`] draws with them, for
    /// the price of the outline pass alone.
    pub fn render_outlines(&self, device: &wgpu::Device, queue: &wgpu::Queue, target: &Target, frame: &FrameInput) {
        if frame.highlight.is_empty() && frame.selection.is_none() {
            return;
        }
        submit(device, queue, |e| {
            self.outline.record(device, queue, (&self.scene, &self.composite), (frame, target), e)
        });
    }

    /// Each pixel's count of faded fragments in front of the opaque organs (rows top to bottom) in
    /// the last frame drawn into `target` with the k-buffer: the k that pixel needs for an exact
    /// result in any drawing order (Callahan 2005, Fig. 4.7). `None` if that frame was not drawn
    /// with the k-buffer.
    pub fn fragment_counts(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
    ) -> Result<Option<Vec<u32>>> {
        self.kbuffer.counts(device, queue, target)
    }

    /// The culling debug view (thesis Figure 21): what culling removed, in bright colours, seen
    /// through every drawn organ as a translucent grey model. `frame.draw` is what survived culling.
    pub fn render_cull_debug(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &mut Target,
        frame: &FrameInput,
    ) -> Result<RenderStats> {
        screendoor::forget(&mut target.kept);
        self.draw_with(&CullDebug(&self.sorted), device, queue, target, frame)
    }

    /// Records `technique`'s frame into one encoder, submits it, and counts what was drawn.
    fn draw_with(
        &self,
        technique: &dyn Technique,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &mut Target,
        input: &FrameInput,
    ) -> Result<RenderStats> {
        let mut kept = std::mem::take(&mut target.kept);
        let view = &*target;
        let drawn = super::guard::guarded(device, "drawing the frame", || {
            let target = view;
            let timer = self.timer.as_ref().filter(|_| input.time_gpu);
            if let Some(t) = timer {
                t.start(device, queue);
            }
            let mut encoder = device.create_command_encoder(&Default::default());
            let frame = Frame { device, queue, scene: &self.scene, input, target };
            let stats = technique.record(&frame, &mut kept, &mut encoder)?;
            queue.submit([encoder.finish()]);
            // Its own submission: it rewrites the organ uniforms the technique drew with.
            self.render_outlines(device, queue, target, input);
            let gpu_ms = timer.map(|t| t.stop(device, queue)).transpose()?;
            Ok(RenderStats { gpu_ms, ..stats })
        });
        target.kept = kept;
        let mut stats = drawn?;
        let states = &input.layout.organs;
        for i in (0..self.scene.organ_count().min(states.len())).filter(|&i| states[i].is_drawn()) {
            let triangles: u32 = self.scene.ranges(i, input.draw).iter().map(|r| (r.end - r.start) / 3).sum();
            stats.organs_drawn += usize::from(triangles > 0);
            stats.triangles_drawn += triangles as usize;
        }
        Ok(stats)
    }

    /// Draws organ IDs into `target`'s ID buffer: for each pixel the nearest drawn organ whose
    /// opacity is at least `min_opacity` (so clicking through a faded organ reaches what is inside).
    pub fn render_ids(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
        min_opacity: f32,
    ) {
        submit(device, queue, |e| {
            self.ids.record(queue, &self.scene, (frame, target), IdKind::Organs { min_opacity }, e)
        });
    }

    /// Draws leaf numbers into `target`'s ID buffer: `first_id[organ] + leaf + 1` of the nearest
    /// leaf of a drawn organ per pixel (0 = background), for measuring exact visibility. Every leaf
    /// of every drawn organ is drawn, as one instance numbered by the leaf.
    pub fn render_leaf_ids(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
        set: &OrganSet,
        first_id: &[u32],
    ) {
        let leaves = IdKind::Leaves { set, first_id };
        submit(device, queue, |e| self.ids.record(queue, &self.scene, (frame, target), leaves, e));
    }
}

/// Records `record` into an encoder of its own and submits it.
fn submit(device: &wgpu::Device, queue: &wgpu::Queue, record: impl FnOnce(&mut wgpu::CommandEncoder)) {
    let mut encoder = device.create_command_encoder(&Default::default());
    record(&mut encoder);
    queue.submit([encoder.finish()]);
}
