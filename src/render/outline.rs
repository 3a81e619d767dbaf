//! Outlines of the highlighted organs (a lesson step's) and of the selected one, drawn over a
//! finished frame so they show through every organ in front, faded or not.
//!
//! - Screen pixels, origin top left.
//! - The organs are drawn whole (culling ignored) into a two-channel mask: the highlighted ones'
//!   numbers into red with their own depth test (the nearest highlighted organ per pixel, so two
//!   that overlap keep the line between them), then the selected one into green.
//! - A full-screen pass paints a ring [`WIDTH`] pixels wide wherever a nearby pixel holds another
//!   organ's number.
//! - Numbers are organ index + 1 in a 16-bit float, exact below 2048 organs.

use super::passes::Pass;
use super::pipelines::{Composite, OrganPipeline, OrganPipelines, PipelineFactory};
use super::scene::GpuScene;
use super::target::{Target, COLOR_FORMAT, MASK_FORMAT};
use super::FrameInput;

/// Ring width in pixels (composite.wgsl's `fs_outline` reads this far).
pub const WIDTH: u32 = 2;

pub(super) struct Outline {
    /// Into the mask's red channel, then its green one.
    mask: [OrganPipelines; 2],
    ring: wgpu::RenderPipeline,
}

impl Outline {
    pub fn new(
        device: &wgpu::Device,
        factory: &PipelineFactory,
        layout: &wgpu::PipelineLayout,
        c: &Composite,
    ) -> Outline {
        let mask = [wgpu::ColorWrites::RED, wgpu::ColorWrites::GREEN].map(|write_mask| {
            factory.build(OrganPipeline {
                label: "outline mask",
                fragment: "fs_mask",
                targets: &[Some(wgpu::ColorTargetState { format: MASK_FORMAT, blend: None, write_mask })],
                depth_write: true,
                samples: 1,
                layout,
            })
        });
        let ring = c.pipeline(device, "outline ring", "fs_outline", COLOR_FORMAT, Some(super::pipelines::OVER));
        Outline { mask, ring }
    }

    /// Records the mask and ring passes for `input`'s highlighted and selected organs that are
    /// shown, after uploading organ uniforms whose colours are the mask values. Nothing when there
    /// are none.
    pub fn record(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        (scene, composite): (&GpuScene, &Composite),
        (input, target): (&FrameInput, &Target),
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let states = &input.layout.organs;
        let count = scene.organ_count().min(states.len());
        let shown = |i: &usize| *i < count && states[*i].visible;
        let highlighted: Vec<usize> = input.highlight.iter().copied().filter(shown).collect();
        let selected: Vec<usize> = input.selection.into_iter().filter(shown).collect();
        if highlighted.is_empty() && selected.is_empty() {
            return;
        }
        scene.write_frame(queue, input, target.aspect(), 0, super::uniforms::UNMOVED);
        let shown = scene.upload_organs(queue, input, 0, |i, _| [(i + 1) as f32, 1.0, 0.0, 1.0]);
        let mask = target.mask(device);
        for (channel, organs) in [highlighted, selected].iter().enumerate() {
            let load = if channel == 0 { wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT) } else { wgpu::LoadOp::Load };
            let mut pass = Pass::new("outline mask")
                .colour(mask, load)
                .depth(&target.ids_depth, wgpu::LoadOp::Clear(1.0), false)
                .begin(encoder);
            scene.set_frame(&mut pass, 0);
            scene.draw_organs((&mut pass, &shown), &self.mask[channel], 0, organs, None);
        }
        let images = composite.images(device, [mask, mask, mask]);
        super::pipelines::fullscreen_pass(encoder, &target.color_view, &self.ring, &images, true, 0.0);
    }
}
