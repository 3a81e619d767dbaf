//! The exact reference for transparency: per sub-sample, each transparent organ rendered alone
//! gives its nearest surface, and those are composited on the CPU.
//!
//! - Screen pixels.
//! - Composited in depth order over the opaque image and averaged over 16 sub-samples (a 4x4 grid
//!   of jittered single-sample renders).
//! - Slow by design: it submits and reads back a layer per organ and sub-sample, and writes the
//!   result into the target's colour image, which the frame's submission then holds.

use super::frame::{Frame, RenderStats, Technique};
use super::passes::Pass;
use super::pipelines::{clear_colour, target, OrganPipeline, OrganPipelines, PipelineFactory};
use super::target::{read_texture, Kept, DEPTH_FORMAT};
use crate::error::Result;

/// Sub-samples of the exact reference: a 4x4 grid per pixel.
const EXACT_GRID: usize = 4;
const LAYER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;

pub(super) struct Exact {
    layer: OrganPipelines,
}

impl Exact {
    pub fn new(factory: &PipelineFactory, layout: &wgpu::PipelineLayout) -> Exact {
        let layer = factory.build(OrganPipeline {
            label: "organ layer",
            fragment: "fs_shade",
            targets: &target(LAYER_FORMAT, None),
            depth_write: true,
            samples: 1,
            layout,
        });
        Exact { layer }
    }
}

/// Pixel-unit jitter to the frame uniform's NDC shift (y flips: pixels go down, NDC up).
fn ndc_jitter(j: glam::Vec2, target: &super::target::Target) -> [f32; 4] {
    [2.0 * j.x / target.width as f32, -2.0 * j.y / target.height as f32, 1.0, 1.0]
}

impl Technique for Exact {
    fn record(&self, f: &Frame, _kept: &mut Kept, _encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats> {
        let (device, queue, scene, input, target) = (f.device, f.queue, f.scene, f.input, f.target);
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
        let depth = make("layer depth", DEPTH_FORMAT);
        let (colour_view, depth_view) =
            (colour.create_view(&Default::default()), depth.create_view(&Default::default()));
        let (opaque, transparent) = input.split(scene.organ_count());
        let shown = scene.upload(queue, input, target.aspect());
        let pixels = (w * h) as usize;
        let states = &input.layout.organs;
        // Renders `organs` alone and reads back (linear RGBA, depth) per pixel.
        let layer = |organs: &[usize], background: [f32; 4]| -> Result<(Vec<[f32; 4]>, Vec<f32>)> {
            let mut encoder = device.create_command_encoder(&Default::default());
            {
                let mut pass = Pass::new("layer")
                    .colour(&colour_view, wgpu::LoadOp::Clear(clear_colour(background)))
                    .depth(&depth_view, wgpu::LoadOp::Clear(1.0), true)
                    .begin(&mut encoder);
                scene.set_frame(&mut pass, 0);
                scene.draw_organs((&mut pass, &shown), &self.layer, 0, organs, input.draw);
            }
            queue.submit([encoder.finish()]);
            let c = read_texture(device, queue, &colour, 16, [0, 0], [w, h], wgpu::TextureAspect::All)?;
            let d = read_texture(device, queue, &depth, 4, [0, 0], [w, h], wgpu::TextureAspect::DepthOnly)?;
            Ok((bytemuck::pod_collect_to_vec(&c), bytemuck::pod_collect_to_vec(&d)))
        };
        let mut sum = vec![[0.0f32; 4]; pixels];
        let samples = EXACT_GRID * EXACT_GRID;
        for s in 0..samples {
            let offset = glam::Vec2::new(
                ((s % EXACT_GRID) as f32 + 0.5) / EXACT_GRID as f32 - 0.5,
                ((s / EXACT_GRID) as f32 + 0.5) / EXACT_GRID as f32 - 0.5,
            );
            scene.write_frame(queue, input, target.aspect(), 0, ndc_jitter(offset, target));
            let (base, base_depth) = layer(&opaque, input.background)?;
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
        Ok(RenderStats { passes: samples * (1 + transparent.len()), ..Default::default() })
    }
}
