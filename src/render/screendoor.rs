//! Screen-door transparency (thesis chapter 4), in screen pixels (origin top left): per pass of 4x
//! MSAA, opaque organs and then transparent ones in any order, depth tested and written, each
//! transparent fragment keeping only the samples of its organ's mask in its screen region
//! (`sample_mask`). Pass p draws the image shifted by a sub-pixel jitter and uses mask bits
//! 4p..4p+3, so P passes give 4P sub-samples; each pass is resolved and added into a float image
//! with weight 1/P. No sorting, so the image does not depend on the order organs are drawn in.
//! Every pass has its own frame and screen-door uniform slots, so all are recorded at once; the
//! masks' buffers are kept from frame to frame and grow when a frame needs more.

use super::frame::{Frame, RenderStats, Technique};
use super::pipelines::{
    fullscreen_pass, target, Composite, OrganPipeline, OrganPipelines, PipelineFactory, SAMPLE_COUNT,
};
use super::scene::{uniform_entry, GpuScene};
use super::target::{Target, COLOR_FORMAT, HDR_FORMAT};
use super::uniforms::{ScreendoorUniform, MAX_PASSES, SLOT};
use crate::error::Result;
use crate::transparency::{layout as sublayout, regions};
use std::sync::Mutex;

pub(super) struct Screendoor {
    opaque: OrganPipelines,
    masked: OrganPipelines,
    accumulate: wgpu::RenderPipeline,
    present: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    /// One [`ScreendoorUniform`] per pass.
    uniforms: wgpu::Buffer,
    pool: Mutex<Option<Pool>>,
}

/// What one frame's masks need, kept for the next: the storage buffers and their bind group, and
/// the image bind groups of the last target drawn into.
struct Pool {
    configs: wgpu::Buffer,
    masks: wgpu::Buffer,
    bind: wgpu::BindGroup,
    images: Option<(u64, [wgpu::BindGroup; 2])>,
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

impl Screendoor {
    pub fn new(
        device: &wgpu::Device,
        factory: &PipelineFactory,
        scene: &GpuScene,
        composite: &Composite,
        opaque: OrganPipelines,
    ) -> Screendoor {
        let storage = |binding| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only: true },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
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
        let weigh = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Constant,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let weigh = Some(wgpu::BlendState { color: weigh, alpha: weigh });
        Screendoor {
            opaque,
            masked,
            accumulate: composite.pipeline(device, "accumulate", "fs_copy", HDR_FORMAT, weigh),
            present: composite.pipeline(device, "present", "fs_copy", COLOR_FORMAT, None),
            layout,
            uniforms: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("screendoor uniforms"),
                size: SLOT * MAX_PASSES,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            pool: Mutex::new(None),
        }
    }

    /// The pool, with storage buffers of at least these sizes (bytes).
    fn fit(&self, device: &wgpu::Device, pool: Option<Pool>, configs: u64, masks: u64) -> Pool {
        match pool {
            Some(p) if p.configs.size() >= configs && p.masks.size() >= masks => p,
            _ => {
                let storage = |label, size: u64| {
                    device.create_buffer(&wgpu::BufferDescriptor {
                        label: Some(label),
                        size: size.max(16).next_power_of_two(),
                        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                        mapped_at_creation: false,
                    })
                };
                let (configs, masks) = (storage("region configs", configs), storage("masks", masks));
                let uniform = wgpu::BufferBinding {
                    buffer: &self.uniforms,
                    offset: 0,
                    size: wgpu::BufferSize::new(std::mem::size_of::<ScreendoorUniform>() as u64),
                };
                let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("screendoor"),
                    layout: &self.layout,
                    entries: &[
                        wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::Buffer(uniform) },
                        wgpu::BindGroupEntry { binding: 1, resource: configs.as_entire_binding() },
                        wgpu::BindGroupEntry { binding: 2, resource: masks.as_entire_binding() },
                    ],
                });
                Pool { configs, masks, bind, images: None }
            }
        }
    }
}

/// Pixel-unit jitter to the NDC shift of the frame uniform (y flips: pixels go down, NDC up).
pub(super) fn ndc_jitter(j: glam::Vec2, target: &Target) -> [f32; 2] {
    [2.0 * j.x / target.width as f32, -2.0 * j.y / target.height as f32]
}

/// The bind groups of the accumulation (reading a pass's resolved image) and of the presentation
/// (reading the sum).
fn image_binds(device: &wgpu::Device, composite: &Composite, target: &Target) -> [wgpu::BindGroup; 2] {
    let hdr = target.hdr(device);
    [
        composite.images(device, [&hdr.resolved, &hdr.resolved, &hdr.resolved]),
        composite.images(device, [&hdr.accum, &hdr.accum, &hdr.accum]),
    ]
}

/// Screen-door with the composite passes it needs.
pub(super) struct ScreendoorFrame<'a> {
    pub technique: &'a Screendoor,
    pub composite: &'a Composite,
}

impl Technique for ScreendoorFrame<'_> {
    fn record(&self, f: &Frame, encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats> {
        let sd = self.technique;
        let (device, queue, scene, input, target) = (f.device, f.queue, f.scene, f.input, f.target);
        let settings = &input.transparency;
        let subsamples = crate::transparency::clamp_subsamples(if input.moving {
            settings.interactive_subsamples
        } else {
            settings.subsamples
        });
        let method = settings.mode.mask_method().unwrap_or(crate::transparency::MaskMethod::TabularNec);
        let params = regions::RegionParams {
            width: target.width,
            height: target.height,
            region_px: settings.region_px,
            subsamples,
            k: settings.k,
            method,
        };
        let masks = regions::region_masks(input.set, input.layout, input.camera, &params);
        let configs: &[u8] = bytemuck::cast_slice(&masks.config_of_region);
        let bits: Vec<[u32; 2]> = masks.masks.iter().map(|&m| [m as u32, (m >> 32) as u32]).collect();
        let bits: &[u8] = bytemuck::cast_slice(&bits);
        let mut kept = sd.pool.lock().unwrap_or_else(|e| e.into_inner());
        let mut pool = sd.fit(device, kept.take(), configs.len() as u64, bits.len() as u64);
        queue.write_buffer(&pool.configs, 0, configs);
        queue.write_buffer(&pool.masks, 0, bits);
        let images = match pool.images.take() {
            Some((id, binds)) if id == target.id() => binds,
            _ => image_binds(device, self.composite, target),
        };
        let hdr = target.hdr(device);
        scene.upload(queue, input, target.aspect());
        let (opaque, transparent) = input.split(scene.organ_count());
        let passes = sublayout::passes(masks.subsamples);
        for p in 0..passes {
            let slot = 1 + p as u64;
            scene.write_frame(queue, input, target.aspect(), slot, ndc_jitter(sublayout::jitter(p, passes), target));
            let u = ScreendoorUniform {
                region_px: masks.region_px,
                cols: masks.cols,
                rows: masks.rows,
                organs: masks.organ_count as u32,
                pass_index: p as u32,
                pad: [0; 3],
            };
            queue.write_buffer(&sd.uniforms, p as u64 * SLOT, bytemuck::bytes_of(&u));
            {
                let mut pass =
                    scene.begin_organ_pass(encoder, [&hdr.msaa, &hdr.resolved], target, input.background, false);
                scene.set_frame(&mut pass, slot);
                for &i in &opaque {
                    scene.draw(&mut pass, &sd.opaque, i, &scene.ranges(i, input.draw));
                }
                pass.set_bind_group(2, &pool.bind, &[(p as u64 * SLOT) as u32]);
                for &i in &transparent {
                    scene.draw(&mut pass, &sd.masked, i, &scene.ranges(i, input.draw));
                }
            }
            fullscreen_pass(encoder, &hdr.accum, &sd.accumulate, &images[0], p > 0, 1.0 / passes as f64);
        }
        fullscreen_pass(encoder, &target.color_view, &sd.present, &images[1], false, 1.0);
        pool.images = Some((target.id(), images));
        *kept = Some(pool);
        Ok(RenderStats { passes, mask_ms: masks.ms, mask_configs: masks.configs, ..Default::default() })
    }
}
