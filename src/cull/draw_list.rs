//! What culling gives: per organ, the index ranges to draw, and the counts of one frame.
//!
//! - Ranges are in indices (three per triangle) into each organ's index buffer, one list per organ
//!   of the set; contiguous ranges are merged.
//! - [`CullStats`] counts triangles (drawn, and culled by each cause), nodes tested and occluders
//!   rasterised; `cull_ms` is the CPU time in milliseconds, `occluders_ms` the part of it spent
//!   choosing and rasterising the occluders and building their maps.

use super::selection::OccluderSource;
use std::ops::Range;

/// Per organ, the index ranges (in indices, contiguous ones merged) to draw.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DrawList {
    pub ranges: Vec<Vec<Range<u32>>>,
}

impl DrawList {
    pub(super) fn push(&mut self, organ: usize, r: Range<u32>) {
        push_merged(&mut self.ranges[organ], r);
    }

    pub fn triangles(&self) -> usize {
        self.ranges.iter().flatten().map(|r| (r.end - r.start) as usize / 3).sum()
    }
}

/// Appends a range, merged into the last one where they meet.
pub(super) fn push_merged(list: &mut Vec<Range<u32>>, r: Range<u32>) {
    match list.last_mut() {
        Some(last) if last.end == r.start => last.end = r.end,
        _ => list.push(r),
    }
}

/// What one frame's culling did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CullStats {
    /// Triangles of the drawn organs.
    pub triangles: usize,
    pub drawn: usize,
    pub frustum_culled: usize,
    pub occlusion_culled: usize,
    /// Of those occlusion culled, made only of faces inside solids intact in the frame
    /// ([`crate::organ_set::hidden_faces`]).
    pub inside_culled: usize,
    /// Culled as facing away (by normal cones), apart from occlusion.
    pub back_face_culled: usize,
    /// Culled as removed by the clip planes.
    pub clip_culled: usize,
    pub nodes_tested: usize,
    /// Occluder leaves rasterised (where organs are tested against different occluders, the most
    /// any organ is tested against).
    pub occluder_leaves: usize,
    /// Solids whose stand-ins were rasterised (their leaves are among the occluder leaves), for
    /// every organ or for those of no solid behind a cut.
    pub solids: usize,
    /// Occluder triangles rasterised (facing the eye; counted as the leaves are).
    pub occluder_triangles: usize,
    /// Where the occluders came from (`None` without occlusion culling or with occluders given).
    pub source: Option<OccluderSource>,
    pub cull_ms: f64,
    /// Of `cull_ms`, choosing and rasterising the occluders and building their maps.
    pub occluders_ms: f64,
}

impl CullStats {
    /// Adds the counts of a traversal (of an organ or a subtree).
    pub(super) fn add_traversal(&mut self, o: &CullStats) {
        self.triangles += o.triangles;
        self.frustum_culled += o.frustum_culled;
        self.occlusion_culled += o.occlusion_culled;
        self.inside_culled += o.inside_culled;
        self.back_face_culled += o.back_face_culled;
        self.clip_culled += o.clip_culled;
        self.nodes_tested += o.nodes_tested;
    }

    pub fn culled_percent(&self) -> f64 {
        if self.triangles == 0 {
            0.0
        } else {
            100.0 * (self.triangles - self.drawn) as f64 / self.triangles as f64
        }
    }
}
