//! The k-buffer (Callahan 2005, chapter 3 and §4.2): order-independent transparency that finishes
//! on the GPU a visibility sort the CPU did roughly. Screen pixels; one k-buffer entry per pixel
//! (faded organs are rasterised once per pixel at its centre, opaque ones at 4x MSAA as always).
//!
//! - The CPU sorts the faded organs' triangles back to front by centroid each frame
//!   ([`GpuScene::triangle_stream`]), one stream per batch; a frame given a draw order (tests)
//!   draws them unsorted in that order instead.
//! - wgpu has no fragment-shader interlock, so the k-buffer's read-modify-write is split into two
//!   passes over that stream. The depth pass inserts each fragment's depth key into the pixel's k
//!   slots with 32-bit `atomicMax`: a compare-and-swap chain that leaves the k nearest keys in
//!   order whatever the order or concurrency of the fragments (no race: the slots' final contents
//!   do not depend on it). The shade pass stores the colour of each fragment whose key is in a
//!   slot, and blends each one farther than the k nearest into the image in drawing order, back to
//!   front. The resolve composites the slots, nearest first, over that.
//! - So a pixel with at most k faded fragments is exact and draw-order independent; beyond k only
//!   the farther fragments' order is the stream's (Callahan's k-buffer composites its overflow in
//!   stream order too). No 64-bit atomics needed: it runs wherever fragment shaders may write
//!   storage buffers.
//! - The depth pass also counts each pixel's faded fragments: the k that pixel needs for an exact
//!   result in any order ([`super::Renderer::fragment_counts`]).
//! - The opaque organs' depth is tested in the shaders (before anything is written), against the
//!   farthest of a pixel's samples.

use super::frame::{Frame, RenderStats, Technique};
use super::passes::Pass;
use super::pipelines::{
    fullscreen_pipeline, module, FullscreenPipeline, OrganPipeline, OrganPipelines, PipelineFactory,
};
use super::scene::GpuScene;
use super::target::{read_buffer, Kept, Target, COLOR_FORMAT, HDR_FORMAT};
use super::uniforms::KBufferUniform;
use crate::error::{Error, Result};
use crate::transparency::KBUFFER_K;
use wgpu::util::DeviceExt;

pub(super) struct KBuffer {
    opaque: OrganPipelines,
    depth: wgpu::RenderPipeline,
    shade: wgpu::RenderPipeline,
    resolve: wgpu::RenderPipeline,
    organ_layout: wgpu::BindGroupLayout,
    resolve_layout: wgpu::BindGroupLayout,
}

/// What the k-buffer keeps in a target: its slots at the last k, made on first use.
#[derive(Default)]
struct KeptBuffers(Option<Buffers>);

/// A target's slots at one k, and the bind groups that read them.
struct Buffers {
    k: u32,
    keys: wgpu::Buffer,
    colours: wgpu::Buffer,
    counts: wgpu::Buffer,
    organ_bind: wgpu::BindGroup,
    resolve_bind: wgpu::BindGroup,
}

fn buffer(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

fn storage(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    buffer(binding, wgpu::BufferBindingType::Storage { read_only })
}

fn uniform(binding: u32) -> wgpu::BindGroupLayoutEntry {
    buffer(binding, wgpu::BufferBindingType::Uniform)
}

fn texture(binding: u32, sample_type: wgpu::TextureSampleType, multisampled: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture { sample_type, view_dimension: wgpu::TextureViewDimension::D2, multisampled },
        count: None,
    }
}

/// Premultiplied "over".
const PREMULTIPLIED: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent::OVER,
};

impl KBuffer {
    pub fn new(device: &wgpu::Device, factory: &PipelineFactory, scene: &GpuScene, opaque: OrganPipelines) -> KBuffer {
        let layout = |label, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: Some(label), entries })
        };
        let organ_layout = layout(
            "k-buffer",
            &[
                uniform(0),
                storage(1, false),
                storage(2, false),
                storage(3, false),
                texture(4, wgpu::TextureSampleType::Depth, true),
            ],
        );
        let resolve_layout = layout(
            "k-buffer resolve",
            &[
                uniform(0),
                storage(1, true),
                storage(2, true),
                texture(3, wgpu::TextureSampleType::Float { filterable: false }, false),
            ],
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("organ k-buffer"),
            bind_group_layouts: &[Some(&scene.frame_layout), Some(&scene.organ_layout), Some(&organ_layout)],
            immediate_size: 0,
        });
        let pass = |label, fragment, blend, write_mask| {
            factory.build_unculled_without_depth(OrganPipeline {
                label,
                fragment,
                targets: &[Some(wgpu::ColorTargetState { format: HDR_FORMAT, blend, write_mask })],
                depth_write: false,
                samples: 1,
                layout: &pipeline_layout,
            })
        };
        let depth = pass("k-buffer depth", "fs_kbuffer_depth", None, wgpu::ColorWrites::empty());
        let shade = pass("k-buffer shade", "fs_kbuffer_shade", Some(PREMULTIPLIED), wgpu::ColorWrites::ALL);
        let resolve = fullscreen_pipeline(
            device,
            FullscreenPipeline {
                label: "k-buffer resolve",
                module: &module(device, &super::KBUFFER_SHADER),
                layout: &resolve_layout,
                fragment: "fs_resolve",
                targets: &super::pipelines::target(COLOR_FORMAT, None),
                depth_stencil: None,
                samples: 1,
            },
        );
        KBuffer { opaque, depth, shade, resolve, organ_layout, resolve_layout }
    }

    /// The slots of `target` at `k`, made where they are not (the size checked first).
    fn buffers(&self, device: &wgpu::Device, target: &Target, k: u32) -> Result<Buffers> {
        let pixels = u64::from(target.width) * u64::from(target.height);
        let bytes = pixels * u64::from(k) * 4;
        let most = device.limits().max_storage_buffer_binding_size.min(device.limits().max_buffer_size);
        if bytes > most {
            return Err(Error::gpu(
                "the k-buffer",
                format!(
                    "{} slots of {}x{} pixels need {} MB a buffer; this GPU binds at most {} MB (choose a smaller k or size)",
                    k,
                    target.width,
                    target.height,
                    bytes >> 20,
                    most >> 20
                ),
            ));
        }
        let buffer = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let (keys, colours, counts) =
            (buffer("k-buffer keys", bytes), buffer("k-buffer colours", bytes), buffer("k-buffer counts", pixels * 4));
        let uniform = KBufferUniform { width: target.width, height: target.height, k, pad: 0 };
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("k-buffer"),
            contents: bytemuck::bytes_of(&uniform),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        fn whole(b: &wgpu::Buffer) -> wgpu::BindingResource<'_> {
            b.as_entire_binding()
        }
        let hdr = target.hdr(device);
        let organ_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("k-buffer"),
            layout: &self.organ_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: whole(&uniform) },
                wgpu::BindGroupEntry { binding: 1, resource: whole(&keys) },
                wgpu::BindGroupEntry { binding: 2, resource: whole(&colours) },
                wgpu::BindGroupEntry { binding: 3, resource: whole(&counts) },
                wgpu::BindGroupEntry { binding: 4, resource: wgpu::BindingResource::TextureView(&target.msaa_depth) },
            ],
        });
        let resolve_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("k-buffer resolve"),
            layout: &self.resolve_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: whole(&uniform) },
                wgpu::BindGroupEntry { binding: 1, resource: whole(&keys) },
                wgpu::BindGroupEntry { binding: 2, resource: whole(&colours) },
                wgpu::BindGroupEntry { binding: 3, resource: wgpu::BindingResource::TextureView(&hdr.resolved) },
            ],
        });
        Ok(Buffers { k, keys, colours, counts, organ_bind, resolve_bind })
    }

    /// Each pixel's count of faded fragments in front of the opaque organs in the last frame drawn
    /// into `target` with the k-buffer, rows top to bottom; `None` where none was.
    pub fn counts(&self, device: &wgpu::Device, queue: &wgpu::Queue, target: &Target) -> Result<Option<Vec<u32>>> {
        let Some(b) = target.kept.get::<KeptBuffers>().and_then(|k| k.0.as_ref()) else { return Ok(None) };
        let bytes = read_buffer(device, queue, &b.counts)?;
        Ok(Some(bytemuck::cast_slice(&bytes).to_vec()))
    }
}

impl Technique for KBuffer {
    fn record(&self, f: &Frame, kept: &mut Kept, encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats> {
        let (device, scene, input, target) = (f.device, f.scene, f.input, f.target);
        let k = input.transparency.kbuffer.clamp(*KBUFFER_K.start(), *KBUFFER_K.end()) as u32;
        let kept = &mut kept.entry::<KeptBuffers>().or_insert_with(Default::default).0;
        let buffers = match kept.take() {
            Some(b) if b.k == k => b,
            _ => self.buffers(device, target, k)?,
        };
        let buffers = kept.insert(buffers);
        let shown = scene.upload(f.queue, input, target.aspect());
        let (opaque, faded) = input.split(scene.organ_count());
        let hdr = target.hdr(device);
        {
            // The opaque depth stays for the k-buffer's passes to test against.
            let mut pass = scene.begin_organ_pass(encoder, [&hdr.msaa, &hdr.resolved], target, input.background, true);
            scene.draw_organs((&mut pass, &shown), &self.opaque, 0, &opaque, input.draw);
        }
        encoder.clear_buffer(&buffers.keys, 0, None);
        encoder.clear_buffer(&buffers.colours, 0, None);
        encoder.clear_buffer(&buffers.counts, 0, None);
        let streams: Vec<(usize, wgpu::Buffer, u32)> = scene
            .triangle_stream(input, &faded, input.draw_order.is_none())
            .into_iter()
            .enumerate()
            .filter(|(_, indices)| !indices.is_empty())
            .map(|(batch, indices)| {
                let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("faded triangles back to front"),
                    contents: bytemuck::cast_slice(&indices),
                    usage: wgpu::BufferUsages::INDEX,
                });
                (batch, buffer, indices.len() as u32)
            })
            .collect();
        for pipeline in [&self.depth, &self.shade] {
            let mut pass = Pass::new("k-buffer").colour(&hdr.resolved, wgpu::LoadOp::Load).begin(encoder);
            scene.set_frame(&mut pass, 0);
            pass.set_pipeline(pipeline);
            pass.set_bind_group(2, &buffers.organ_bind, &[]);
            for (batch, indices, count) in &streams {
                scene.draw_indices(&mut pass, *batch, indices, *count);
            }
        }
        {
            let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
            let mut pass = Pass::new("k-buffer resolve").colour(&target.color_view, clear).begin(encoder);
            pass.set_pipeline(&self.resolve);
            pass.set_bind_group(0, &buffers.resolve_bind, &[]);
            pass.draw(0..3, 0..1);
        }
        Ok(RenderStats { passes: 4, ..Default::default() })
    }
}
