//! Opaque organs with depth and 4x MSAA, then faded ones alpha blended into the resolved colour
//! image.
//!
//! - `alpha-sorted`: faded organs back to front by centre (also every frame with nothing faded).
//! - `alpha-unsorted`: faded organs in drawing order, with depth written.

use super::frame::{Frame, RenderStats, Technique};
use super::pipelines::{target, OrganPipeline, OrganPipelines, PipelineFactory, OVER, SAMPLE_COUNT};
use super::target::{Kept, COLOR_FORMAT};
use crate::error::Result;

pub(super) struct Blend {
    pub opaque: OrganPipelines,
    pub translucent: OrganPipelines,
    /// Translucent organs back to front (else in drawing order).
    sorted: bool,
}

impl Blend {
    /// Both blending techniques, sorted first; they share the opaque pipeline.
    pub fn new(factory: &PipelineFactory, layout: &wgpu::PipelineLayout) -> [Blend; 2] {
        let organ = |label, blend, depth_write| {
            factory.build(OrganPipeline {
                label,
                fragment: "fs_shade",
                targets: &target(COLOR_FORMAT, blend),
                depth_write,
                samples: SAMPLE_COUNT,
                layout,
            })
        };
        let opaque = organ("organ opaque", None, true);
        let sorted =
            Blend { opaque: opaque.clone(), translucent: organ("organ blend", Some(OVER), false), sorted: true };
        let unsorted = Blend { opaque, translucent: organ("organ blend unsorted", Some(OVER), true), sorted: false };
        [sorted, unsorted]
    }
}

impl Technique for Blend {
    fn record(&self, f: &Frame, _kept: &mut Kept, encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats> {
        let (scene, input, target) = (f.scene, f.input, f.target);
        let shown = scene.upload(f.queue, input, target.aspect());
        let (opaque, mut translucent) = input.split(scene.organ_count());
        if self.sorted {
            let states = &input.layout.organs;
            let eye = input.camera.eye;
            let distance = |i: usize| {
                let c = states[i].transform.matrix().transform_point3(scene.center(i));
                (c - eye).length_squared()
            };
            translucent.sort_by(|&a, &b| distance(b).total_cmp(&distance(a)).then(a.cmp(&b)));
        }
        let colour = [&target.msaa_color, &target.color_view];
        let mut pass = scene.begin_organ_pass(encoder, colour, target, input.background, false);
        scene.draw_organs((&mut pass, &shown), &self.opaque, 0, &opaque, input.draw);
        scene.draw_organs((&mut pass, &shown), &self.translucent, 0, &translucent, input.draw);
        Ok(RenderStats { passes: 1, ..Default::default() })
    }
}
