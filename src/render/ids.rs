//! The ID passes, into the target's single-sampled ID buffer: organ numbers for picking, or leaf
//! numbers for measuring exact visibility.
//!
//! - Screen pixels, 0 = background.
//! - For picking, organ index + 1 of the nearest drawn organ per pixel.

use super::passes::Pass;
use super::pipelines::{target, OrganPipeline, OrganPipelines, PipelineFactory};
use super::scene::GpuScene;
use super::target::{Target, ID_FORMAT};
use super::FrameInput;

pub(super) struct Ids {
    organ: OrganPipelines,
    leaf: OrganPipelines,
}

/// What an ID pass writes.
pub(super) enum IdKind<'a> {
    /// Organs whose opacity is at least this.
    Organs { min_opacity: f32 },
    /// `first_id[organ] + leaf + 1` of every leaf of `set`'s opaque organs (faded ones hide
    /// nothing).
    Leaves { set: &'a crate::organ_set::OrganSet, first_id: &'a [u32] },
}

impl Ids {
    pub fn new(factory: &PipelineFactory, layout: &wgpu::PipelineLayout) -> Ids {
        let pick = |label, fragment| {
            factory.build(OrganPipeline {
                label,
                fragment,
                targets: &target(ID_FORMAT, None),
                depth_write: true,
                samples: 1,
                layout,
            })
        };
        Ids { organ: pick("organ pick", "fs_pick"), leaf: pick("leaf pick", "fs_pick_instance") }
    }

    /// Records one ID pass (cleared to 0, with its own depth) after uploading the frame's uniforms.
    pub fn record(
        &self,
        queue: &wgpu::Queue,
        scene: &GpuScene,
        (input, target): (&FrameInput, &Target),
        kind: IdKind,
        encoder: &mut wgpu::CommandEncoder,
    ) {
        let shown = scene.upload(queue, input, target.aspect());
        let label = match kind {
            IdKind::Organs { .. } => "organ ids",
            IdKind::Leaves { .. } => "leaf ids",
        };
        let mut pass = Pass::new(label)
            .colour(&target.ids_view, wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT))
            .depth(&target.ids_depth, wgpu::LoadOp::Clear(1.0), false)
            .begin(encoder);
        scene.set_frame(&mut pass, 0);
        let organs = input.layout.organs.iter().enumerate().take(scene.organ_count());
        match kind {
            IdKind::Organs { min_opacity } => {
                for (i, s) in organs {
                    if s.is_drawn() && s.opacity >= min_opacity {
                        scene.draw((&mut pass, &shown), &self.organ, i, &scene.ranges(i, input.draw));
                    }
                }
            }
            IdKind::Leaves { set, first_id } => {
                for (i, _) in organs.filter(|(_, s)| s.is_opaque()) {
                    let base = scene.bind_organ(&mut pass, &self.leaf, 0, i);
                    let bvh = &set.organs[i].bvh;
                    for l in 0..bvh.leaves.len() as u32 {
                        let id = first_id[i] + l + 1;
                        let r = bvh.leaf_range(l);
                        pass.draw_indexed(r.start + base..r.end + base, 0, id..id + 1);
                    }
                }
            }
        }
    }
}
