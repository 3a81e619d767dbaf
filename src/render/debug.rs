//! The culling debug view (thesis Figure 21): what culling removed, in bright colours, seen through
//! every drawn organ as a translucent grey model.
//!
//! - Screen pixels.
//! - The frame's draw list is what survived culling.

use super::blend::Blend;
use super::frame::{Frame, RenderStats, Technique};
use super::target::Kept;
use crate::error::Result;
use std::ops::Range;

/// The parts of `0..end` not in the sorted, disjoint `ranges`.
fn complement(ranges: &[Range<u32>], end: u32) -> Vec<Range<u32>> {
    let mut out = Vec::new();
    let mut at = 0;
    for r in ranges {
        if r.start > at {
            out.push(at..r.start);
        }
        at = at.max(r.end);
    }
    if at < end {
        out.push(at..end);
    }
    out
}

/// The debug view, drawn with the sorted blending technique's pipelines.
pub(super) struct CullDebug<'a>(pub &'a Blend);

impl Technique for CullDebug<'_> {
    fn record(&self, f: &Frame, _kept: &mut Kept, encoder: &mut wgpu::CommandEncoder) -> Result<RenderStats> {
        let (scene, input, target) = (f.scene, f.input, f.target);
        scene.upload(f.queue, input, target.aspect());
        let grey = scene.upload_organs(f.queue, input, 1, |_, _| [0.35, 0.35, 0.35, 0.22]);
        let coloured = scene.upload_organs(f.queue, input, 2, |i, _| {
            let h = (i as f32 * 0.618_034) % 1.0;
            let hue = |o: f32| (((h + o) * std::f32::consts::TAU).sin() * 0.5 + 0.5).powf(0.8);
            [hue(0.0), hue(0.33), hue(0.67), 1.0]
        });
        let states = &input.layout.organs;
        let drawn: Vec<usize> = (0..scene.organ_count().min(states.len())).filter(|&i| states[i].is_drawn()).collect();
        let colour = [&target.msaa_color, &target.color_view];
        let mut pass = scene.begin_organ_pass(encoder, colour, target, input.background, false);
        for &i in &drawn {
            let kept = scene.ranges(i, input.draw);
            let culled = complement(&kept, scene.index_count(i));
            scene.draw_in((&mut pass, &coloured), &self.0.opaque, 2, i, &culled);
        }
        for &i in &drawn {
            scene.draw_in((&mut pass, &grey), &self.0.translucent, 1, i, &scene.ranges(i, None));
        }
        Ok(RenderStats { passes: 1, ..Default::default() })
    }
}

#[cfg(test)]
mod tests {
    use super::complement;

    #[test]
    fn complements() {
        assert_eq!(complement(&[3..6, 9..12], 15), vec![0..3, 6..9, 12..15]);
        let whole = std::iter::once(0..15).collect::<Vec<_>>();
        assert_eq!(complement(&whole, 15), vec![]);
        assert_eq!(complement(&[], 6), vec![0..6]);
    }
}
