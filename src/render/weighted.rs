//! Weighted blended order-independent transparency, a comparison mode: the opaque image with
//! depth, then weighted sums of the transparent organs over that depth, then the resolve over the
//! opaque image.
//!
//! - Screen pixels.
//! - Implements McGuire and Bavoil 2013.

use super::frame::{Frame, RenderStats, Technique};
use super::passes::Pass;
use super::pipelines::{fullscreen_pass, Composite, OrganPipeline, OrganPipelines, PipelineFactory};
use super::target::{Kept, COLOR_FORMAT, HDR_FORMAT, REVEAL_FORMAT};
use crate::error::Result;

pub(super) struct Weighted {
    opaque: OrganPipelines,
    sums: OrganPipelines,
    resolve: wgpu::RenderPipeline,
}

impl Weighted {
    pub fn new(
        device: &wgpu::Device,
        factory: &PipelineFactory,
        layout: &wgpu::PipelineLayout,
        composite: &Composite,
        opaque: OrganPipelines,
    ) -> Weighted {
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
        let sums = factory.build(OrganPipeline {
            label: "organ weighted",
            fragment: "fs_weighted",
            targets: &[
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
            depth_write: false,
            samples: super::SAMPLE_COUNT,
            layout,
        });
        let resolve = composite.pipeline(device, "weighted resolve", "fs_weighted_resolve", COLOR_FORMAT, None);
        Weighted { opaque, sums, resolve }
    }
}

/// Weighted blending with the composite passes it needs.
pub(super) struct WeightedFrame<'a> {
    pub technique: &'a Weighted,
    pub composite: &'a Composite,
}

impl Technique for WeightedFrame<'_> {
    fn record(&self, f: &Frame, _kept: &mut Kept, encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats> {
        let wb = self.technique;
        let (scene, input, target) = (f.scene, f.input, f.target);
        let hdr = target.hdr(f.device);
        let shown = scene.upload(f.queue, input, target.aspect());
        let (opaque, transparent) = input.split(scene.organ_count());
        {
            // The opaque depth stays for the weighted pass to test against.
            let mut pass = scene.begin_organ_pass(encoder, [&hdr.msaa, &hdr.resolved], target, input.background, true);
            scene.draw_organs((&mut pass, &shown), &wb.opaque, 0, &opaque, input.draw);
        }
        {
            let mut pass = Pass::new("weighted sums")
                .resolved(&hdr.msaa, &hdr.accum, wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT), false)
                .resolved(&hdr.reveal_msaa, &hdr.reveal, wgpu::LoadOp::Clear(wgpu::Color::WHITE), false)
                .depth(&target.msaa_depth, wgpu::LoadOp::Load, false)
                .begin(encoder);
            scene.set_frame(&mut pass, 0);
            scene.draw_organs((&mut pass, &shown), &wb.sums, 0, &transparent, input.draw);
        }
        let images = self.composite.images(f.device, [&hdr.resolved, &hdr.accum, &hdr.reveal]);
        fullscreen_pass(encoder, &target.color_view, &wb.resolve, &images, false, 1.0);
        Ok(RenderStats { passes: 2, ..Default::default() })
    }
}
