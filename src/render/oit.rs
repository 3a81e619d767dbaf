//! The transparency modes other than sorted blending, in screen pixels (origin top left):
//!
//! - **screen-door** (thesis chapter 4): per pass of 4x MSAA, opaque organs and then transparent
//!   ones in any order, depth tested and written, each transparent fragment keeping only the
//!   samples of its organ's mask in its screen region (`sample_mask`). Pass p draws the image
//!   shifted by a sub-pixel jitter and uses mask bits 4p..4p+3, so P passes give 4P sub-samples;
//!   each pass is resolved and added into a float image with weight 1/P. No sorting, so the image
//!   does not depend on the order organs are drawn in.
//! - **alpha-unsorted**: blending in drawing order with depth written.
//! - **weighted blended** OIT (McGuire and Bavoil 2013) over the opaque image.
//! - **exact**, the reference: per sub-sample, each transparent organ rendered alone gives its
//!   nearest surface; on the CPU those are composited in depth order over the opaque image and
//!   averaged over 16 sub-samples (a 4x4 grid of jittered single-sample renders).

use super::renderer::{clear_colour, FrameInput, PipelineFactory, RenderStats, Renderer, OVER, SAMPLE_COUNT};
use super::target::{read_texture, Target, HDR_FORMAT, REVEAL_FORMAT};
use super::COLOR_FORMAT;
use crate::error::Result;
use crate::transparency::{layout as sublayout, regions};
use wgpu::util::DeviceExt;

/// Keep in sync with `Screendoor` in shaders/organ.wgsl.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ScreendoorUniform {
    region_px: u32,
    cols: u32,
    rows: u32,
    organs: u32,
    pass_index: u32,
    pad: [u32; 3],
}

/// Sub-samples of the exact reference: a 4x4 grid per pixel.
const EXACT_GRID: usize = 4;
const LAYER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

pub(crate) struct OitPipelines {
    pub blend_unsorted: wgpu::RenderPipeline,
    opaque_hdr: wgpu::RenderPipeline,
    screendoor: wgpu::RenderPipeline,
    weighted: wgpu::RenderPipeline,
    layer: wgpu::RenderPipeline,
    screendoor_layout: wgpu::BindGroupLayout,
    screendoor_uniform: wgpu::Buffer,
    images_layout: wgpu::BindGroupLayout,
    accumulate: wgpu::RenderPipeline,
    present: wgpu::RenderPipeline,
    weighted_resolve: wgpu::RenderPipeline,
}

impl OitPipelines {
    pub fn new(
        device: &wgpu::Device,
        factory: &PipelineFactory,
        frame_layout: &wgpu::BindGroupLayout,
        organ_layout: &wgpu::BindGroupLayout,
        layout: &wgpu::PipelineLayout,
    ) -> OitPipelines {
        let entry = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty,
            count: None,
        };
        let storage = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: true },
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let uniform = wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        };
        let screendoor_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("screendoor"),
            entries: &[entry(0, uniform), entry(1, storage), entry(2, storage)],
        });
        let masked_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("organ screendoor"),
            bind_group_layouts: &[Some(frame_layout), Some(organ_layout), Some(&screendoor_layout)],
            immediate_size: 0,
        });
        let texture = wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        };
        let images_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("images"),
            entries: &[entry(0, texture), entry(1, texture), entry(2, texture)],
        });
        let samples = SAMPLE_COUNT;
        let blend_unsorted = factory.single(
            "organ blend unsorted",
            "fs_shade",
            COLOR_FORMAT,
            Some(OVER),
            true,
            Some(wgpu::Face::Back),
            samples,
            layout,
        );
        let opaque_hdr = factory.single("organ opaque hdr", "fs_shade", HDR_FORMAT, None, true, None, samples, layout);
        let screendoor =
            factory.single("organ screendoor", "fs_screendoor", HDR_FORMAT, None, true, None, samples, &masked_layout);
        let add = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let keep = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Zero,
            dst_factor: wgpu::BlendFactor::OneMinusSrc,
            operation: wgpu::BlendOperation::Add,
        };
        let weighted = factory.multi(
            "organ weighted",
            "fs_weighted",
            &[
                Some(wgpu::ColorTargetState {
                    format: HDR_FORMAT,
                    blend: Some(wgpu::BlendState { color: add, alpha: add }),
                    write_mask: wgpu::ColorWrites::ALL,
                }),
                Some(wgpu::ColorTargetState {
                    format: REVEAL_FORMAT,
                    blend: Some(wgpu::BlendState { color: keep, alpha: keep }),
                    write_mask: wgpu::ColorWrites::ALL,
                }),
            ],
            false,
            layout,
        );
        let layer = factory.single("organ layer", "fs_shade", LAYER_FORMAT, None, true, None, 1, layout);
        let composite = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("composite.wgsl"),
            source: wgpu::ShaderSource::Wgsl(super::SHADERS[1].1.into()),
        });
        let images_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("images"),
            bind_group_layouts: &[Some(&images_layout)],
            immediate_size: 0,
        });
        let fullscreen = |label, fragment, format, blend| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&images_pipeline_layout),
                vertex: wgpu::VertexState {
                    module: &composite,
                    entry_point: Some("vs_fullscreen"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: Default::default(),
                depth_stencil: None,
                multisample: Default::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &composite,
                    entry_point: Some(fragment),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState { format, blend, write_mask: wgpu::ColorWrites::ALL })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let weigh = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Constant,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        OitPipelines {
            blend_unsorted,
            opaque_hdr,
            screendoor,
            weighted,
            layer,
            screendoor_layout,
            screendoor_uniform: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("screendoor uniform"),
                size: std::mem::size_of::<ScreendoorUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            images_layout,
            accumulate: fullscreen(
                "accumulate",
                "fs_copy",
                HDR_FORMAT,
                Some(wgpu::BlendState { color: weigh, alpha: weigh }),
            ),
            present: fullscreen("present", "fs_copy", COLOR_FORMAT, None),
            weighted_resolve: fullscreen("weighted resolve", "fs_weighted_resolve", COLOR_FORMAT, None),
        }
    }

    fn images(&self, device: &wgpu::Device, views: [&wgpu::TextureView; 3]) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("images"),
            layout: &self.images_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(views[0]) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(views[1]) },
                wgpu::BindGroupEntry { binding: 2, resource: wgpu::BindingResource::TextureView(views[2]) },
            ],
        })
    }
}

/// A full-screen pass of `pipeline` over `images` into `view` (cleared first unless `load`).
#[allow(clippy::too_many_arguments)]
fn fullscreen_pass(
    encoder: &mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    pipeline: &wgpu::RenderPipeline,
    images: &wgpu::BindGroup,
    load: bool,
    blend_constant: f64,
) {
    let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("full screen"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: if load { wgpu::LoadOp::Load } else { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) },
                store: wgpu::StoreOp::Store,
            },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(pipeline);
    pass.set_bind_group(0, images, &[]);
    let w = blend_constant;
    pass.set_blend_constant(wgpu::Color { r: w, g: w, b: w, a: w });
    pass.draw(0..3, 0..1);
}

/// Pixel-unit jitter to the NDC shift of the frame uniform (y flips: pixels go down, NDC up).
fn ndc_jitter(j: glam::Vec2, target: &Target) -> [f32; 2] {
    [2.0 * j.x / target.width as f32, -2.0 * j.y / target.height as f32]
}

impl Renderer {
    /// Organs split into opaque and transparent (drawn, faded), each in drawing order.
    fn split(&self, frame: &FrameInput) -> (Vec<usize>, Vec<usize>) {
        let states = &frame.layout.organs;
        let order = frame.order(self.organ_count().min(states.len()));
        let opaque = order.iter().copied().filter(|&i| states[i].is_opaque()).collect();
        let transparent = order.iter().copied().filter(|&i| states[i].is_drawn() && !states[i].is_opaque()).collect();
        (opaque, transparent)
    }

    /// Screen-door transparency through per-region masks of the frame's mask method.
    pub(super) fn render_screendoor(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
    ) -> RenderStats {
        let settings = &frame.transparency;
        let subsamples = crate::transparency::clamp_subsamples(if frame.moving {
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
        let masks = regions::region_masks(frame.set, frame.layout, frame.camera, &params);
        let config: &[u32] = &masks.config_of_region;
        let bits: Vec<[u32; 2]> = masks.masks.iter().map(|&m| [m as u32, (m >> 32) as u32]).collect();
        let storage = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let config_buffer = storage("region configs", bytemuck::cast_slice(config));
        let mask_buffer = storage("masks", bytemuck::cast_slice(&bits));
        let oit = &self.oit;
        let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("screendoor"),
            layout: &oit.screendoor_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: oit.screendoor_uniform.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: config_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: mask_buffer.as_entire_binding() },
            ],
        });
        let hdr = target.hdr(device);
        let accumulate = oit.images(device, [&hdr.resolved, &hdr.resolved, &hdr.resolved]);
        let present = oit.images(device, [&hdr.accum, &hdr.accum, &hdr.accum]);
        self.upload(queue, frame, target.aspect());
        let (opaque, transparent) = self.split(frame);
        let passes = sublayout::passes(masks.subsamples);
        for p in 0..passes {
            self.upload_frame(queue, frame, target.aspect(), ndc_jitter(sublayout::jitter(p, passes), target));
            let u = ScreendoorUniform {
                region_px: masks.region_px,
                cols: masks.cols,
                rows: masks.rows,
                organs: masks.organ_count as u32,
                pass_index: p as u32,
                pad: [0; 3],
            };
            queue.write_buffer(&oit.screendoor_uniform, 0, bytemuck::bytes_of(&u));
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass =
                    self.begin_organ_pass(&mut encoder, [&hdr.msaa, &hdr.resolved], target, frame.background, false);
                pass.set_pipeline(&oit.opaque_hdr);
                for &i in &opaque {
                    self.draw(&mut pass, i, &self.ranges(i, frame.draw));
                }
                pass.set_pipeline(&oit.screendoor);
                pass.set_bind_group(2, &bind, &[]);
                for &i in &transparent {
                    self.draw(&mut pass, i, &self.ranges(i, frame.draw));
                }
            }
            fullscreen_pass(&mut encoder, &hdr.accum, &oit.accumulate, &accumulate, p > 0, 1.0 / passes as f64);
            queue.submit([encoder.finish()]);
        }
        let mut encoder = device.create_command_encoder(&Default::default());
        fullscreen_pass(&mut encoder, &target.color_view, &oit.present, &present, false, 1.0);
        queue.submit([encoder.finish()]);
        RenderStats { passes, mask_ms: masks.ms, mask_configs: masks.configs, ..Default::default() }
    }

    /// Weighted blended OIT: the opaque image, then weighted sums of the transparent organs over
    /// its depth, then the resolve over the opaque image.
    pub(super) fn render_weighted(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
    ) -> RenderStats {
        let oit = &self.oit;
        let hdr = target.hdr(device);
        self.upload(queue, frame, target.aspect());
        let (opaque, transparent) = self.split(frame);
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            // The opaque depth stays for the weighted pass to test against.
            let mut pass =
                self.begin_organ_pass(&mut encoder, [&hdr.msaa, &hdr.resolved], target, frame.background, true);
            pass.set_pipeline(&oit.opaque_hdr);
            for &i in &opaque {
                self.draw(&mut pass, i, &self.ranges(i, frame.draw));
            }
        }
        {
            let attachment = |view, resolve, clear_to: wgpu::Color| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: Some(resolve),
                    ops: wgpu::Operations { load: wgpu::LoadOp::Clear(clear_to), store: wgpu::StoreOp::Discard },
                })
            };
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("weighted sums"),
                color_attachments: &[
                    attachment(&hdr.msaa, &hdr.accum, wgpu::Color::TRANSPARENT),
                    attachment(&hdr.reveal_msaa, &hdr.reveal, wgpu::Color::WHITE),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &target.msaa_depth,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Load, store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, self.frame_bind(), &[]);
            pass.set_pipeline(&oit.weighted);
            for &i in &transparent {
                self.draw(&mut pass, i, &self.ranges(i, frame.draw));
            }
        }
        let images = oit.images(device, [&hdr.resolved, &hdr.accum, &hdr.reveal]);
        fullscreen_pass(&mut encoder, &target.color_view, &oit.weighted_resolve, &images, false, 1.0);
        queue.submit([encoder.finish()]);
        RenderStats { passes: 2, ..Default::default() }
    }

    /// The exact reference, composited on the CPU (see the module header). Slow by design.
    pub(super) fn render_exact(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        target: &Target,
        frame: &FrameInput,
    ) -> Result<RenderStats> {
        let (w, h) = (target.width, target.height);
        let make = |label, format| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        };
        let colour = make("layer colour", LAYER_FORMAT);
        let depth = make("layer depth", super::target::DEPTH_FORMAT);
        let (colour_view, depth_view) =
            (colour.create_view(&Default::default()), depth.create_view(&Default::default()));
        let (opaque, transparent) = self.split(frame);
        let pixels = (w * h) as usize;
        let states = &frame.layout.organs;
        // Renders `organs` alone and reads back (linear RGBA, depth) per pixel.
        let layer = |organs: &[usize], background: [f32; 4]| -> Result<(Vec<[f32; 4]>, Vec<f32>)> {
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("layer"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &colour_view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(clear_colour(background)),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                        view: &depth_view,
                        depth_ops: Some(wgpu::Operations {
                            load: wgpu::LoadOp::Clear(1.0),
                            store: wgpu::StoreOp::Store,
                        }),
                        stencil_ops: None,
                    }),
                    timestamp_writes: None,
                    occlusion_query_set: None,
                    multiview_mask: None,
                });
                pass.set_bind_group(0, self.frame_bind(), &[]);
                pass.set_pipeline(&self.oit.layer);
                for &i in organs {
                    self.draw(&mut pass, i, &self.ranges(i, frame.draw));
                }
            }
            queue.submit([encoder.finish()]);
            let c = read_texture(device, queue, &colour, 16, [0, 0], [w, h], wgpu::TextureAspect::All)?;
            let d = read_texture(device, queue, &depth, 4, [0, 0], [w, h], wgpu::TextureAspect::DepthOnly)?;
            Ok((bytemuck::pod_collect_to_vec(&c), bytemuck::pod_collect_to_vec(&d)))
        };
        self.upload(queue, frame, target.aspect());
        let mut sum = vec![[0.0f32; 4]; pixels];
        let samples = EXACT_GRID * EXACT_GRID;
        for s in 0..samples {
            let offset = glam::Vec2::new(
                ((s % EXACT_GRID) as f32 + 0.5) / EXACT_GRID as f32 - 0.5,
                ((s / EXACT_GRID) as f32 + 0.5) / EXACT_GRID as f32 - 0.5,
            );
            self.upload_frame(queue, frame, target.aspect(), ndc_jitter(offset, target));
            let (base, base_depth) = layer(&opaque, frame.background)?;
            // Fragments (pixel, depth, organ, colour) of each transparent organ's nearest surface.
            let mut fragments: Vec<(u32, f32, u32, [f32; 3])> = Vec::new();
            for &o in &transparent {
                let (c, d) = layer(std::slice::from_ref(&o), [0.0; 4])?;
                for p in 0..pixels {
                    if d[p] < 1.0 && d[p] < base_depth[p] {
                        fragments.push((p as u32, d[p], o as u32, [c[p][0], c[p][1], c[p][2]]));
                    }
                }
            }
            fragments.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
            let mut result = base;
            let mut at = 0;
            while at < fragments.len() {
                let p = fragments[at].0 as usize;
                let mut end = at;
                let (mut c, mut through) = ([0.0f32; 3], 1.0f32);
                while end < fragments.len() && fragments[end].0 as usize == p {
                    let (_, _, o, rgb) = fragments[end];
                    let a = states[o as usize].opacity.clamp(0.0, 1.0);
                    for k in 0..3 {
                        c[k] += through * a * rgb[k];
                    }
                    through *= 1.0 - a;
                    end += 1;
                }
                let b = result[p];
                result[p] =
                    [c[0] + through * b[0], c[1] + through * b[1], c[2] + through * b[2], 1.0 - through * (1.0 - b[3])];
                at = end;
            }
            for (acc, r) in sum.iter_mut().zip(&result) {
                for k in 0..4 {
                    acc[k] += r[k] / samples as f32;
                }
            }
        }
        let bytes: Vec<u8> = sum
            .iter()
            .flat_map(|c| {
                let e = |v: f32| (super::linear_to_srgb(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8;
                [e(c[0]), e(c[1]), e(c[2]), (c[3].clamp(0.0, 1.0) * 255.0 + 0.5) as u8]
            })
            .collect();
        queue.write_texture(
            target.color.as_image_copy(),
            &bytes,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(4 * w), rows_per_image: Some(h) },
            wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        );
        queue.submit([]);
        Ok(RenderStats { passes: samples * (1 + transparent.len()), ..Default::default() })
    }
}
