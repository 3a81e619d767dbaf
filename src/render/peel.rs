//! Depth peeling (Everitt 2001) and dual depth peeling (Bavoil and Myers 2008): the transparency of
//! 3D Slicer, VTK and brainrender, drawn by the same renderer for comparison with screen-door. Both
//! in screen pixels at 4x MSAA, per sample (the faded organs' fragments are shaded once per
//! sample, so edges are as smooth as the opaque organs'), over the opaque organs drawn once.
//!
//! - `peel`: each pass draws the faded organs and keeps, per sample, the nearest surface behind
//!   the layer peeled last; the layers are composited front to back ("under").
//! - `dual-peel`: each pass peels the nearest and the farthest remaining layer at once, by MAX
//!   blending of (-depth, depth) into 32-bit float targets (the device must blend them: wgpu's
//!   `FLOAT32_BLENDABLE`).
//!
//! Both stop at [`crate::transparency::TransparencySettings::peel_layers`] layers, or
//! earlier when an occlusion query finds that a pass peeled nothing (each pass is submitted and
//! its query read back before the next: the stall peeling pays for stopping early).

use super::frame::{Frame, RenderStats, Technique};
use super::passes::Pass;
use super::pipelines::{
    blend, fullscreen_pipeline, module, Composite, FullscreenPipeline, OrganPipeline, OrganPipelines, PipelineFactory,
    OVER, SAMPLE_COUNT,
};
use super::scene::{GpuScene, Shown};
use super::target::{image_view, Kept, Target, DEPTH_FORMAT, HDR_FORMAT};
use crate::error::{Error, Result};

const DEPTH_CHANNEL: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

pub(super) struct Peel {
    opaque: OrganPipelines,
    layer: OrganPipelines,
    /// Dual peeling's init and peel pipelines, where the device blends 32-bit floats.
    dual: Option<[OrganPipelines; 2]>,
    /// A per-sample image blended under what is in front: each layer, then the opaque image.
    under: wgpu::RenderPipeline,
    back: wgpu::RenderPipeline,
    final_pass: wgpu::RenderPipeline,
    present: wgpu::RenderPipeline,
    peel_layout: wgpu::BindGroupLayout,
    dual_layout: wgpu::BindGroupLayout,
    sample_layout: wgpu::BindGroupLayout,
    final_layout: wgpu::BindGroupLayout,
}

/// What peeling keeps in a target: its images, made on first use.
#[derive(Default)]
struct KeptImages(Option<Images>);

/// A target's peeling images (multisampled) and the bind groups that read them.
struct Images {
    layer: wgpu::TextureView,
    accum: wgpu::TextureView,
    depth: [wgpu::TextureView; 2],
    near: [wgpu::TextureView; 2],
    far: [wgpu::TextureView; 2],
    front: [wgpu::TextureView; 2],
    /// `peel_binds[i]` reads `depth[i]` as the layer peeled last.
    peel_binds: [wgpu::BindGroup; 2],
    /// `dual_binds[i]` reads `near[i]`, `far[i]`, `front[i]`.
    dual_binds: [wgpu::BindGroup; 2],
    /// Reads `layer`: a peeled layer, or a dual pass's back layer.
    layer_bind: wgpu::BindGroup,
    opaque_bind: wgpu::BindGroup,
    /// `final_binds[i]` reads `front[i]` over the opaque image with the back layers.
    final_binds: [wgpu::BindGroup; 2],
    present_bind: wgpu::BindGroup,
}

fn entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: true,
        },
        count: None,
    }
}

fn views_bind(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    first: u32,
    views: &[&wgpu::TextureView],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = views
        .iter()
        .enumerate()
        .map(|(i, v)| wgpu::BindGroupEntry {
            binding: first + i as u32,
            resource: wgpu::BindingResource::TextureView(v),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor { label: Some("peel"), layout, entries: &entries })
}

impl Peel {
    pub fn new(
        device: &wgpu::Device,
        factory: &PipelineFactory,
        scene: &GpuScene,
        composite: &Composite,
        opaque: OrganPipelines,
    ) -> Peel {
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries })
        };
        let depth = wgpu::TextureSampleType::Depth;
        let float = wgpu::TextureSampleType::Float { filterable: false };
        let peel_layout = layout("peel", &[entry(0, depth), entry(1, depth)]);
        let dual_layout = layout("dual peel", &[entry(2, float), entry(3, float), entry(4, float)]);
        let sample_layout = layout("peel sample", &[entry(0, float)]);
        let final_layout = layout("dual final", &[entry(0, float), entry(1, float)]);
        let organ_layout = |group: &wgpu::BindGroupLayout| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("organ peel"),
                bind_group_layouts: &[Some(&scene.frame_layout), Some(&scene.organ_layout), Some(group)],
                immediate_size: 0,
            })
        };
        let hdr =
            |blend| Some(wgpu::ColorTargetState { format: HDR_FORMAT, blend, write_mask: wgpu::ColorWrites::ALL });
        let layer = factory.build(OrganPipeline {
            label: "organ peel",
            fragment: "fs_peel",
            targets: &[hdr(None)],
            depth_write: true,
            samples: SAMPLE_COUNT,
            layout: &organ_layout(&peel_layout),
        });
        let max = blend(wgpu::BlendFactor::One, wgpu::BlendFactor::One, wgpu::BlendOperation::Max);
        let channel =
            Some(wgpu::ColorTargetState { format: DEPTH_CHANNEL, blend: max, write_mask: wgpu::ColorWrites::ALL });
        let dual = device.features().contains(wgpu::Features::FLOAT32_BLENDABLE).then(|| {
            let dual_pipeline_layout = organ_layout(&dual_layout);
            [
                factory.build(OrganPipeline {
                    label: "organ dual init",
                    fragment: "fs_dual_init",
                    targets: &[channel.clone(), channel.clone()],
                    depth_write: false,
                    samples: SAMPLE_COUNT,
                    layout: &dual_pipeline_layout,
                }),
                factory.build(OrganPipeline {
                    label: "organ dual peel",
                    fragment: "fs_dual_peel",
                    targets: &[channel.clone(), channel.clone(), hdr(max), hdr(max)],
                    depth_write: false,
                    samples: SAMPLE_COUNT,
                    layout: &dual_pipeline_layout,
                }),
            ]
        });
        let shader = module(device, &super::PEEL_SHADER);
        let fullscreen = |label, layout, fragment, blend| {
            let targets = [hdr(blend)];
            let spec = FullscreenPipeline {
                label,
                module: &shader,
                layout,
                fragment,
                targets: &targets,
                depth_stencil: None,
                samples: SAMPLE_COUNT,
            };
            fullscreen_pipeline(device, spec)
        };
        // Front to back: what is already in front lets (1 - its alpha) through.
        let under = blend(wgpu::BlendFactor::OneMinusDstAlpha, wgpu::BlendFactor::One, wgpu::BlendOperation::Add);
        Peel {
            opaque,
            layer,
            dual,
            under: fullscreen("peel under", &sample_layout, "fs_sample", under),
            back: fullscreen("dual back", &sample_layout, "fs_back", Some(OVER)),
            final_pass: fullscreen("dual final", &final_layout, "fs_dual_final", None),
            present: composite.pipeline(device, "present", "fs_copy", super::COLOR_FORMAT, None),
            peel_layout,
            dual_layout,
            sample_layout,
            final_layout,
        }
    }

    fn images(&self, device: &wgpu::Device, composite: &Composite, target: &Target) -> Images {
        let make = |label, format| image_view(device, label, [target.width, target.height], format, SAMPLE_COUNT);
        let two = |label, format| [make(label, format), make(label, format)];
        let (depth, near, far, front) = (
            two("peel depth", DEPTH_FORMAT),
            two("dual near", DEPTH_CHANNEL),
            two("dual far", DEPTH_CHANNEL),
            two("dual front", HDR_FORMAT),
        );
        let (layer, accum) = (make("peel layer", HDR_FORMAT), make("peel accum", HDR_FORMAT));
        let hdr = target.hdr(device);
        let pair = |f: &dyn Fn(usize) -> wgpu::BindGroup| [f(0), f(1)];
        Images {
            peel_binds: pair(&|i| views_bind(device, &self.peel_layout, 0, &[&depth[i], &target.msaa_depth])),
            dual_binds: pair(&|i| views_bind(device, &self.dual_layout, 2, &[&near[i], &far[i], &front[i]])),
            layer_bind: views_bind(device, &self.sample_layout, 0, &[&layer]),
            opaque_bind: views_bind(device, &self.sample_layout, 0, &[&hdr.msaa]),
            final_binds: pair(&|i| views_bind(device, &self.final_layout, 0, &[&front[i], &hdr.msaa])),
            present_bind: composite.images(device, [&hdr.resolved, &hdr.resolved, &hdr.resolved]),
            layer,
            accum,
            depth,
            near,
            far,
            front,
        }
    }
}

/// Submits `encoder` with the occlusion query's result copied out, and reads it back (blocking).
fn submit_counting(f: &Frame, mut encoder: wgpu::CommandEncoder, query: &wgpu::QuerySet) -> Result<u64> {
    let readback = super::target::QueryReadback::new(f.device, "occlusion", 1);
    readback.record(&mut encoder, query);
    f.queue.submit([encoder.finish()]);
    Ok(readback.read(f.device, "occlusion query")?[0])
}

/// Depth peeling or dual depth peeling, with the composite passes they need.
pub(super) struct PeelFrame<'a> {
    pub technique: &'a Peel,
    pub composite: &'a Composite,
    pub dual: bool,
}

impl PeelFrame<'_> {
    /// The opaque organs into the float image and the depth, both kept.
    fn opaque(
        &self,
        (f, shown): (&Frame, &Shown),
        encoder: &mut wgpu::CommandEncoder,
        opaque: &[usize],
        pipelines: &OrganPipelines,
    ) {
        let hdr = f.target.hdr(f.device);
        let background = wgpu::LoadOp::Clear(super::pipelines::clear_colour(f.input.background));
        let mut p = Pass::new("peel opaque")
            .colour(&hdr.msaa, background)
            .depth(&f.target.msaa_depth, wgpu::LoadOp::Clear(1.0), true)
            .begin(encoder);
        f.scene.set_frame(&mut p, 0);
        f.scene.draw_organs((&mut p, shown), pipelines, 0, opaque, f.input.draw);
    }

    /// Peels up to `layers` layers, front to back; returns the layers drawn.
    fn peel(&self, (f, shown): (&Frame, &Shown), images: &Images, faded: &[usize], layers: usize) -> Result<usize> {
        let pe = self.technique;
        let query = f.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("peel"),
            ty: wgpu::QueryType::Occlusion,
            count: 1,
        });
        let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
        let mut drawn = 0;
        for layer in 0..layers {
            let (prev, cur) = (layer % 2, (layer + 1) % 2);
            let mut encoder = f.device.create_command_encoder(&Default::default());
            if layer == 0 {
                // Nothing peeled yet; nothing in front yet.
                drop(Pass::new("peel start").colour(&images.accum, clear).begin(&mut encoder));
                drop(
                    Pass::new("peel start")
                        .depth(&images.depth[prev], wgpu::LoadOp::Clear(0.0), true)
                        .begin(&mut encoder),
                );
            }
            {
                let mut p = Pass::new("peel layer")
                    .colour(&images.layer, clear)
                    .depth(&images.depth[cur], wgpu::LoadOp::Clear(1.0), true)
                    .counting(&query)
                    .begin(&mut encoder);
                f.scene.set_frame(&mut p, 0);
                p.set_bind_group(2, &images.peel_binds[prev], &[]);
                p.begin_occlusion_query(0);
                f.scene.draw_organs((&mut p, shown), &pe.layer, 0, faded, f.input.draw);
                p.end_occlusion_query();
            }
            {
                let mut p = Pass::new("peel under").colour(&images.accum, wgpu::LoadOp::Load).begin(&mut encoder);
                p.set_pipeline(&pe.under);
                p.set_bind_group(0, &images.layer_bind, &[]);
                p.draw(0..3, 0..1);
            }
            drawn += 1;
            if submit_counting(f, encoder, &query)? == 0 {
                break;
            }
        }
        Ok(drawn)
    }

    /// Dual peeling, up to `layers` layers (two a pass); returns the passes drawn and the front
    /// image that holds the front layers.
    fn dual_peel(
        &self,
        (f, shown): (&Frame, &Shown),
        images: &Images,
        faded: &[usize],
        layers: usize,
    ) -> Result<(usize, usize)> {
        let pe = self.technique;
        let Some([init, peel]) = &pe.dual else {
            return Err(Error::gpu(
                "dual depth peeling",
                "this device cannot blend 32-bit float images (wgpu FLOAT32_BLENDABLE); use peel",
            ));
        };
        let hdr = f.target.hdr(f.device);
        let query = f.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("dual peel"),
            ty: wgpu::QueryType::Occlusion,
            count: 1,
        });
        let unpeeled = wgpu::LoadOp::Clear(wgpu::Color { r: -1.0, g: -1.0, b: -1.0, a: -1.0 });
        let none = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
        let depth = &f.target.msaa_depth;
        let mut encoder = f.device.create_command_encoder(&Default::default());
        drop(Pass::new("dual start").colour(&images.front[0], none).begin(&mut encoder));
        {
            let mut p = Pass::new("dual init")
                .colour(&images.near[0], unpeeled)
                .colour(&images.far[0], unpeeled)
                .depth(depth, wgpu::LoadOp::Load, true)
                .begin(&mut encoder);
            f.scene.set_frame(&mut p, 0);
            p.set_bind_group(2, &images.dual_binds[1], &[]);
            f.scene.draw_organs((&mut p, shown), init, 0, faded, f.input.draw);
        }
        let mut passes = 0;
        let mut front = 0;
        let mut pending = Some(encoder);
        for step in 0..layers.div_ceil(2) {
            let (prev, cur) = (step % 2, (step + 1) % 2);
            let mut encoder = pending.take().unwrap_or_else(|| f.device.create_command_encoder(&Default::default()));
            {
                let mut p = Pass::new("dual peel")
                    .colour(&images.near[cur], unpeeled)
                    .colour(&images.far[cur], unpeeled)
                    .colour(&images.front[cur], none)
                    .colour(&images.layer, none)
                    .depth(depth, wgpu::LoadOp::Load, true)
                    .begin(&mut encoder);
                f.scene.set_frame(&mut p, 0);
                p.set_bind_group(2, &images.dual_binds[prev], &[]);
                f.scene.draw_organs((&mut p, shown), peel, 0, faded, f.input.draw);
            }
            {
                let mut p =
                    Pass::new("dual back").colour(&hdr.msaa, wgpu::LoadOp::Load).counting(&query).begin(&mut encoder);
                p.set_pipeline(&pe.back);
                p.set_bind_group(0, &images.layer_bind, &[]);
                p.begin_occlusion_query(0);
                p.draw(0..3, 0..1);
                p.end_occlusion_query();
            }
            passes += 1;
            front = cur;
            // No back layer peeled: at most one layer was left, and this pass took it.
            if submit_counting(f, encoder, &query)? == 0 {
                break;
            }
        }
        Ok((passes, front))
    }
}

impl Technique for PeelFrame<'_> {
    fn record(&self, f: &Frame, kept: &mut Kept, encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats> {
        let pe = self.technique;
        let (device, scene, input, target) = (f.device, f.scene, f.input, f.target);
        let kept = &mut kept.entry::<KeptImages>().or_insert_with(Default::default).0;
        let images = kept.get_or_insert_with(|| pe.images(device, self.composite, target));
        let shown = scene.upload(f.queue, input, target.aspect());
        let (opaque, faded) = input.split(scene.organ_count());
        let layers = input.transparency.peel_layers.max(1);
        let hdr = target.hdr(device);
        let mut first = device.create_command_encoder(&Default::default());
        self.opaque((f, &shown), &mut first, &opaque, &pe.opaque);
        f.queue.submit([first.finish()]);
        let passes = if self.dual {
            let (passes, front) = self.dual_peel((f, &shown), images, &faded, layers)?;
            let mut p =
                Pass::new("dual final").resolved(&images.layer, &hdr.resolved, wgpu::LoadOp::Load, true).begin(encoder);
            p.set_pipeline(&pe.final_pass);
            p.set_bind_group(0, &images.final_binds[front], &[]);
            p.draw(0..3, 0..1);
            passes + 1
        } else {
            let passes = self.peel((f, &shown), images, &faded, layers)?;
            let mut p =
                Pass::new("peel final").resolved(&images.accum, &hdr.resolved, wgpu::LoadOp::Load, true).begin(encoder);
            p.set_pipeline(&pe.under);
            p.set_bind_group(0, &images.opaque_bind, &[]);
            p.draw(0..3, 0..1);
            passes
        };
        super::pipelines::fullscreen_pass(encoder, &target.color_view, &pe.present, &images.present_bind, false, 1.0);
        Ok(RenderStats { passes: 1 + passes, ..Default::default() })
    }
}
