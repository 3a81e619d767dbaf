//! Screen-door transparency (thesis chapter 4) at 4x MSAA: the opaque organs are drawn once, the
//! faded organs once per pass through their masks, and the passes averaged and shown over the
//! opaque image.
//!
//! - Screen pixels, origin top left.
//! - The opaque organs are drawn once into the float image with depth.
//! - The faded organs are drawn once per pass, depth tested and written, each fragment keeping
//!   only the samples of its organ's mask in its screen region (`sample_mask`; pass p uses mask
//!   bits 4p..4p+3, so P passes give 4P sub-samples), each pass shifted by its own fraction of a
//!   pixel ([`sublayout::pass_offset`]) so that the passes sample distinct positions.
//! - Each pass draws into its own tile of an atlas ([`super::tiles`]), a copy of the rectangle the
//!   faded organs cover, first filled per sample with the opaque colour and depth (`fs_restore`;
//!   cleared to the background where no opaque triangle is drawn), so a pass costs the faded
//!   organs' triangles and pixels, not the scene's.
//! - Tiles are resolved and averaged into the rectangle (`fs_gather`, a running mean), and the
//!   rectangle is shown over the opaque image.
//! - No sorting by depth, and the image does not depend on drawing order (faded organs are drawn
//!   in index order, which settles exact depth ties).
//! - Progressive refinement ([`super::FrameInput::refine`]): a first frame draws the interactive
//!   count of passes, and each call for the same frame adds one more, until all are in. The masks,
//!   the opaque image and the running mean are kept in the pool between those calls.

use super::frame::{Frame, FrameInput, RenderStats, Technique};
use super::passes::Pass;
use super::pipelines::{
    blend, fullscreen_pipeline, module, target, Composite, FullscreenPipeline, OrganPipeline, OrganPipelines,
    PipelineFactory, SAMPLE_COUNT,
};
use super::scene::{uniform_entry, GpuScene, Shown};
use super::target::{image_view, Kept, Target, COLOR_FORMAT, DEPTH_FORMAT, HDR_FORMAT};
use super::tiles::{tiling, Rect, Tiling, ATLAS_BUDGET_PX, GAP};
use super::uniforms::{GatherUniform, ScreendoorUniform, MAX_PASSES, SLOT};
use crate::error::Result;
use crate::transparency::{layout as sublayout, regions};

pub(super) struct Screendoor {
    opaque: OrganPipelines,
    masked: OrganPipelines,
    restore: wgpu::RenderPipeline,
    gather: wgpu::RenderPipeline,
    present: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    restore_layout: wgpu::BindGroupLayout,
    gather_layout: wgpu::BindGroupLayout,
    /// One [`ScreendoorUniform`] per pass.
    uniforms: wgpu::Buffer,
    /// One [`GatherUniform`] per round (indexed by the round's first pass).
    gathers: wgpu::Buffer,
}

/// What screen-door keeps in a target.
#[derive(Default)]
struct KeptFrame {
    pool: Option<Pool>,
    /// The last frame's mask configurations, kept where they come again.
    masks: regions::MaskCache,
}

/// What one frame needs, kept for the next: the masks' storage buffers and their bind group, the
/// atlas, the bind groups over the target's images, and how far its image has converged.
struct Pool {
    configs: wgpu::Buffer,
    masks: wgpu::Buffer,
    bind: wgpu::BindGroup,
    atlas: Option<Atlas>,
    images: Option<Images>,
    progress: Option<Progress>,
}

/// The tiles' images: multisampled colour and depth, and the resolved colour the gather reads.
struct Atlas {
    size: [u32; 2],
    msaa: wgpu::TextureView,
    depth: wgpu::TextureView,
    resolved: wgpu::TextureView,
    gather_bind: wgpu::BindGroup,
}

/// Bind groups that read one target's images.
struct Images {
    /// The opaque image (multisampled colour and depth) for `fs_restore`.
    restore: wgpu::BindGroup,
    /// The opaque image resolved, and the rectangle's running mean, for the presentation.
    opaque: wgpu::BindGroup,
    mean: wgpu::BindGroup,
}

/// A frame drawn in part, to be continued by the next call for the same frame.
struct Progress {
    key: u64,
    /// Each pass's uniform, written again at each call (another target may have drawn between).
    uniforms: Vec<ScreendoorUniform>,
    done: usize,
    total: usize,
    tiling: Tiling,
    mask_ms: f64,
    mask_configs: usize,
}

/// The pipelines that draw organs into the float image with depth: opaque ones, shared with
/// weighted blending.
pub(super) fn opaque_hdr(factory: &PipelineFactory, layout: &wgpu::PipelineLayout) -> OrganPipelines {
    factory.build(OrganPipeline {
        label: "organ opaque hdr",
        fragment: "fs_shade",
        targets: &target(HDR_FORMAT, None),
        depth_write: true,
        samples: SAMPLE_COUNT,
        layout,
    })
}

fn layout_entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::FRAGMENT, ty, count: None }
}

fn uniforms(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: SLOT * MAX_PASSES,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A binding of one slot of a uniform buffer holding `T`s.
fn slot_of<T>(buffer: &wgpu::Buffer) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
        buffer,
        offset: 0,
        size: wgpu::BufferSize::new(std::mem::size_of::<T>() as u64),
    })
}

impl Screendoor {
    pub fn new(
        device: &wgpu::Device,
        factory: &PipelineFactory,
        scene: &GpuScene,
        composite: &Composite,
        opaque: OrganPipelines,
    ) -> Screendoor {
        let storage = |binding| {
            layout_entry(
                binding,
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: true },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
            )
        };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("screendoor"),
            entries: &[uniform_entry(wgpu::ShaderStages::FRAGMENT), storage(1), storage(2)],
        });
        let masked_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("organ screendoor"),
            bind_group_layouts: &[Some(&scene.frame_layout), Some(&scene.organ_layout), Some(&layout)],
            immediate_size: 0,
        });
        let masked = factory.build(OrganPipeline {
            label: "organ screendoor",
            fragment: "fs_screendoor",
            targets: &target(HDR_FORMAT, None),
            depth_write: true,
            samples: SAMPLE_COUNT,
            layout: &masked_layout,
        });
        let texture = |binding, sample_type, multisampled| {
            layout_entry(
                binding,
                wgpu::BindingType::Texture {
                    sample_type,
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled,
                },
            )
        };
        let float = wgpu::TextureSampleType::Float { filterable: false };
        let restore_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("tile restore"),
            entries: &[
                uniform_entry(wgpu::ShaderStages::FRAGMENT),
                texture(1, float, true),
                texture(2, wgpu::TextureSampleType::Depth, true),
            ],
        });
        let mut gather_uniform = uniform_entry(wgpu::ShaderStages::FRAGMENT);
        gather_uniform.binding = 3;
        let gather_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("gather"),
            entries: &[gather_uniform, texture(4, float, false)],
        });
        let shader = module(device, &super::SCREENDOOR_SHADER);
        let fullscreen = |label, layout, fragment, targets, depth_stencil, samples| {
            let spec = FullscreenPipeline { label, module: &shader, layout, fragment, targets, depth_stencil, samples };
            fullscreen_pipeline(device, spec)
        };
        // The opaque depth, written whatever was there.
        let restored_depth = wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: Default::default(),
            bias: Default::default(),
        };
        let mean = blend(wgpu::BlendFactor::Constant, wgpu::BlendFactor::OneMinusConstant, wgpu::BlendOperation::Add);
        Screendoor {
            opaque,
            masked,
            restore: fullscreen(
                "tile restore",
                &restore_layout,
                "fs_restore",
                &target(HDR_FORMAT, None),
                Some(restored_depth),
                SAMPLE_COUNT,
            ),
            gather: fullscreen("gather", &gather_layout, "fs_gather", &target(HDR_FORMAT, mean), None, 1),
            present: composite.pipeline(device, "present", "fs_copy", COLOR_FORMAT, None),
            layout,
            restore_layout,
            gather_layout,
            uniforms: uniforms(device, "screendoor uniforms"),
            gathers: uniforms(device, "gather uniforms"),
        }
    }

    /// The pool, with storage buffers of at least these sizes (bytes).
    fn fit(&self, device: &wgpu::Device, pool: Option<Pool>, configs: u64, masks: u64) -> Pool {
        match pool {
            Some(p) if p.configs.size() >= configs && p.masks.size() >= masks => p,
            old => {
                let storage = |label, size: u64| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size: size.max(16).next_power_of_two(),
                        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                };
                let (configs, masks) = (storage("region configs", configs), storage("masks", masks));
                let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("screendoor"),
                    layout: &self.layout,
                    entries: &[
                        wgpu::BindGroupEntry { binding: 0, resource: slot_of::<ScreendoorUniform>(&self.uniforms) },
                        wgpu::BindGroupEntry { binding: 1, resource: configs.as_entire_binding() },
                        wgpu::BindGroupEntry { binding: 2, resource: masks.as_entire_binding() },
                    ],
                });
                let (atlas, images) = old.map(|p| (p.atlas, p.images)).unwrap_or((None, None));
                Pool { configs, masks, bind, atlas, images, progress: None }
            }
        }
    }

    /// An atlas of at least `need` pixels (kept if the last one is large enough; sides rounded up
    /// to 256 so that a rectangle growing a little does not make a new one every frame).
    fn atlas(&self, device: &wgpu::Device, old: Option<Atlas>, need: [u32; 2]) -> Atlas {
        if let Some(a) = old.filter(|a| a.size[0] >= need[0] && a.size[1] >= need[1]) {
            return a;
        }
        let max = device.limits().max_texture_dimension_2d;
        let size = need.map(|v| v.div_ceil(256).saturating_mul(256).min(max).max(v));
        let resolved = image_view(device, "atlas resolved", size, HDR_FORMAT, 1);
        let gather_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("gather"),
            layout: &self.gather_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 3, resource: slot_of::<GatherUniform>(&self.gathers) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&resolved) },
            ],
        });
        Atlas {
            size,
            msaa: image_view(device, "atlas msaa", size, HDR_FORMAT, SAMPLE_COUNT),
            depth: image_view(device, "atlas depth", size, DEPTH_FORMAT, SAMPLE_COUNT),
            resolved,
            gather_bind,
        }
    }

    /// The bind groups over `target`'s images.
    fn images(&self, device: &wgpu::Device, composite: &Composite, target: &Target) -> Images {
        let hdr = target.hdr(device);
        let restore = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("tile restore"),
            layout: &self.restore_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: slot_of::<ScreendoorUniform>(&self.uniforms) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&hdr.msaa) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(&target.msaa_depth) },
            ],
        });
        Images {
            restore,
            opaque: composite.images(device, [&hdr.resolved, &hdr.resolved, &hdr.resolved]),
            mean: composite.images(device, [&hdr.accum, &hdr.accum, &hdr.accum]),
        }
    }
}

/// Screen-door with the composite passes it needs.
pub(super) struct ScreendoorFrame<'a> {
    pub technique: &'a Screendoor,
    pub composite: &'a Composite,
}

/// Passes drawn by the first call of a refined frame: the interactive count.
fn first_passes(input: &FrameInput, total: usize) -> usize {
    if input.refine {
        let interactive = crate::transparency::clamp_subsamples(input.transparency.interactive_subsamples);
        sublayout::passes(interactive).min(total)
    } else {
        total
    }
}

impl Technique for ScreendoorFrame<'_> {
    fn record(&self, f: &Frame, kept: &mut Kept, encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats> {
        let sd = self.technique;
        let (device, queue, scene, input, target) = (f.device, f.queue, f.scene, f.input, f.target);
        let settings = &input.transparency;
        let subsamples = crate::transparency::clamp_subsamples(if input.moving {
            settings.interactive_subsamples
        } else {
            settings.subsamples
        });
        let key = input.fingerprint();
        let KeptFrame { pool: kept, masks: cache } = kept.entry::<KeptFrame>().or_insert_with(Default::default);
        let same = |p: &Progress| input.refine && p.key == key;
        let mut pool = kept.take();
        let continued = pool.as_mut().and_then(|p| p.progress.take()).filter(same);
        let (mut pool, mut progress, from, to) = match (pool, continued) {
            (Some(mut pool), Some(progress)) if progress.done >= progress.total => {
                // Converged: the target still shows it.
                let stats = stats(&progress, 0);
                pool.progress = Some(progress);
                *kept = Some(pool);
                return Ok(stats);
            }
            (Some(pool), Some(progress)) => {
                let (from, to) = (progress.done, progress.done + 1);
                (pool, progress, from, to)
            }
            (pool, _) => {
                let (pool, progress) = start(sd, f, pool, cache, (subsamples, key));
                let to = first_passes(input, progress.total);
                (pool, progress, 0, to)
            }
        };
        let shown = scene.upload(queue, input, target.aspect());
        if from == 0 {
            draw_opaque(sd, (f, &shown), encoder);
        }
        for (p, u) in progress.uniforms.iter().enumerate() {
            queue.write_buffer(&sd.uniforms, p as u64 * SLOT, bytemuck::bytes_of(u));
        }
        let images = pool.images.take().unwrap_or_else(|| sd.images(device, self.composite, target));
        let tiling = progress.tiling;
        let drawn = if tiling.rect.is_empty() { 0 } else { to - from };
        if drawn > 0 {
            let atlas = sd.atlas(device, pool.atlas.take(), tiling.atlas);
            draw_passes(sd, (f, &shown), encoder, (&pool, &atlas, &images), &tiling, (from..to, progress.total));
            pool.atlas = Some(atlas);
        }
        progress.done = if tiling.rect.is_empty() { progress.total } else { to };
        present(sd, encoder, target, &images, (!tiling.rect.is_empty() && progress.done > 0).then_some(tiling.rect));
        let stats = stats(&progress, usize::from(from == 0) + drawn);
        pool.images = Some(images);
        pool.progress = Some(progress);
        *kept = Some(pool);
        Ok(stats)
    }
}

fn stats(p: &Progress, passes: usize) -> RenderStats {
    RenderStats {
        passes,
        mask_ms: p.mask_ms,
        mask_configs: p.mask_configs,
        subsamples_done: p.done * 4,
        subsamples_total: p.total * 4,
        ..Default::default()
    }
}

/// Forgets any frame drawn in part into `kept`'s target: another technique drew into the images
/// it continues.
pub(super) fn forget(kept: &mut Kept) {
    if let Some(pool) = kept.entry::<KeptFrame>().or_insert_with(Default::default).pool.as_mut() {
        pool.progress = None;
    }
}

/// A new frame: its masks into the pool's buffers, and where its passes go.
fn start(
    sd: &Screendoor,
    f: &Frame,
    pool: Option<Pool>,
    cache: &mut regions::MaskCache,
    (subsamples, key): (usize, u64),
) -> (Pool, Progress) {
    let (device, queue, input, target) = (f.device, f.queue, f.input, f.target);
    let settings = &input.transparency;
    let method = settings.mode.mask_method().unwrap_or(crate::transparency::MaskMethod::TabularNec);
    let params = regions::RegionParams {
        width: target.width,
        height: target.height,
        region_px: settings.region_px,
        subsamples,
        k: settings.k,
        method,
    };
    let masks = regions::region_masks_kept(input.set, input.layout, input.camera, &params, cache);
    let configs: &[u8] = bytemuck::cast_slice(&masks.config_of_region);
    let bits: Vec<[u32; 2]> = masks.masks.iter().map(|&m| [m as u32, (m >> 32) as u32]).collect();
    let bits: &[u8] = bytemuck::cast_slice(&bits);
    let pool = sd.fit(device, pool, configs.len() as u64, bits.len() as u64);
    queue.write_buffer(&pool.configs, 0, configs);
    queue.write_buffer(&pool.masks, 0, bits);
    let [x, y, w, h] = masks.covered;
    let total = sublayout::passes(masks.subsamples);
    let max_side = device.limits().max_texture_dimension_2d;
    let tiling = tiling(Rect { x, y, w, h }, total, ATLAS_BUDGET_PX, max_side);
    let uniforms = (0..total)
        .map(|p| ScreendoorUniform {
            region_px: masks.region_px,
            cols: masks.cols,
            rows: masks.rows,
            organs: masks.organ_count as u32,
            pass_index: p as u32,
            offset: tiling.offset(p % tiling.per_round),
            pad: 0,
        })
        .collect();
    let progress = Progress { key, uniforms, done: 0, total, tiling, mask_ms: masks.ms, mask_configs: masks.configs };
    (pool, progress)
}

/// The opaque organs into the float image (resolved) and the multisampled depth, both kept.
fn draw_opaque(sd: &Screendoor, (f, shown): (&Frame, &Shown), encoder: &mut wgpu::CommandEncoder) {
    let (scene, input, target) = (f.scene, f.input, f.target);
    let hdr = target.hdr(f.device);
    let background = wgpu::LoadOp::Clear(super::pipelines::clear_colour(input.background));
    let mut pass = Pass::new("opaque")
        .resolved(&hdr.msaa, &hdr.resolved, background, true)
        .depth(&target.msaa_depth, wgpu::LoadOp::Clear(1.0), true)
        .begin(encoder);
    scene.set_frame(&mut pass, 0);
    // In index order too (see `draw_passes`): exact depth ties between opaque organs.
    let (mut opaque, _) = input.split(scene.organ_count());
    opaque.sort_unstable();
    scene.draw_organs((&mut pass, shown), &sd.opaque, 0, &opaque, input.draw);
}

/// Passes `passes` of `total` of the faded organs, each shifted by its
/// [`sublayout::pass_offset`], in rounds of tiles, each round averaged into the rectangle's running
/// mean (weighted by the passes it adds to those before).
fn draw_passes(
    sd: &Screendoor,
    (f, shown): (&Frame, &Shown),
    encoder: &mut wgpu::CommandEncoder,
    (pool, atlas, images): (&Pool, &Atlas, &Images),
    tiling: &Tiling,
    (passes, total): (std::ops::Range<usize>, usize),
) {
    let (queue, scene, input, target) = (f.queue, f.scene, f.input, f.target);
    // In index order, whatever the drawing order: where two faded surfaces meet at exactly the
    // same depth in a sample both masks hold, the first drawn wins, so this keeps the image the
    // same in any drawing order (no sorting by depth is involved; the masks do the rest).
    let (opaque, mut faded) = input.split(scene.organ_count());
    faded.sort_unstable();
    // Where no opaque triangle is drawn, the opaque image is the background: a clear restores it.
    let restore = opaque.iter().any(|&i| scene.ranges(i, input.draw).iter().any(|r| !r.is_empty()));
    let clear = match restore {
        true => wgpu::Color::TRANSPARENT,
        false => super::pipelines::clear_colour(input.background),
    };
    let hdr = target.hdr(f.device);
    let rect = tiling.rect;
    let mut first = passes.start;
    while first < passes.end {
        // Pass p draws into tile p % per_round (its uniforms say so), so a round ends where the
        // tiles wrap.
        let first_tile = first % tiling.per_round;
        let count = (tiling.per_round - first_tile).min(passes.end - first);
        for t in first_tile..first_tile + count {
            let p = first + t - first_tile;
            let mut place = tiling.place(t, [target.width, target.height], atlas.size);
            // The pass's shift, in atlas pixels (NDC y up).
            let shift = sublayout::pass_offset(p, total);
            place[0] += 2.0 * shift.x / atlas.size[0] as f32;
            place[1] -= 2.0 * shift.y / atlas.size[1] as f32;
            scene.write_frame(queue, input, target.aspect(), 1 + p as u64, place);
        }
        {
            let mut pass = Pass::new("screendoor tiles")
                .resolved(&atlas.msaa, &atlas.resolved, wgpu::LoadOp::Clear(clear), false)
                .depth(&atlas.depth, wgpu::LoadOp::Clear(1.0), false)
                .begin(encoder);
            for t in first_tile..first_tile + count {
                let p = (first + t - first_tile) as u64;
                let c = tiling.corner(t);
                pass.set_scissor_rect(c[0], c[1], rect.w, rect.h);
                if restore {
                    pass.set_pipeline(&sd.restore);
                    pass.set_bind_group(0, &images.restore, &[(p * SLOT) as u32]);
                    pass.draw(0..3, 0..1);
                }
                scene.set_frame(&mut pass, 1 + p);
                pass.set_bind_group(2, &pool.bind, &[(p * SLOT) as u32]);
                scene.draw_organs((&mut pass, shown), &sd.masked, 0, &faded, input.draw);
            }
        }
        let g = GatherUniform {
            origin: [rect.x as i32, rect.y as i32],
            tile: [(rect.w + GAP) as i32, (rect.h + GAP) as i32],
            tiles_x: tiling.tiles_x,
            first: first_tile as u32,
            count: count as u32,
            pad: 0,
        };
        queue.write_buffer(&sd.gathers, first as u64 * SLOT, bytemuck::bytes_of(&g));
        let mut pass = Pass::new("gather").colour(&hdr.accum, wgpu::LoadOp::Load).begin(encoder);
        pass.set_scissor_rect(rect.x, rect.y, rect.w, rect.h);
        pass.set_pipeline(&sd.gather);
        pass.set_bind_group(0, &atlas.gather_bind, &[(first as u64 * SLOT) as u32]);
        // Running mean: the round's mean weighs its share of the passes drawn so far.
        let w = count as f64 / (first + count) as f64;
        pass.set_blend_constant(wgpu::Color { r: w, g: w, b: w, a: w });
        pass.draw(0..3, 0..1);
        first += count;
    }
}

/// The opaque image, and over it the rectangle's running mean where there is one.
fn present(sd: &Screendoor, encoder: &mut wgpu::CommandEncoder, target: &Target, images: &Images, rect: Option<Rect>) {
    let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
    let mut pass = Pass::new("present").colour(&target.color_view, clear).begin(encoder);
    pass.set_pipeline(&sd.present);
    pass.set_bind_group(0, &images.opaque, &[]);
    pass.draw(0..3, 0..1);
    if let Some(r) = rect {
        pass.set_scissor_rect(r.x, r.y, r.w, r.h);
        pass.set_bind_group(0, &images.mean, &[]);
        pass.draw(0..3, 0..1);
    }
}
