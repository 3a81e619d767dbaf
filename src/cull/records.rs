//! What the culler knows of each organ in a frame, from the section and the layout: one record
//! per organ, read by every phase of [`super::cull_in_phases`].
//! - World space (millimetres, RAS) for the section; each record's planes in its organ's space.
//! - The clip classification is [`crate::clip::Section::organ`], the renderer's own, so what
//!   the culler assumes drawn is what is drawn.

use super::CullInput;
use crate::clip::{ModelPlane, OrganClip};
use crate::layout::Layout;

/// How far inside the clip planes an organ must lie to occlude, as a share of its far corner's
/// distance from the eye. The shaders discard what the planes remove sample by sample, at a
/// position interpolated off the triangle for a sample at its edge, far off it at grazing angles,
/// so an occluder near a plane may lose samples there. A margin of a pixel's footprint (at 64
/// pixels across) still changed samples in the identity test; this one changes none there.
pub const CLEAR_OF_PLANES: f32 = 1.0 / 16.0;

/// One organ in a frame.
#[derive(Clone, Debug)]
pub struct OrganRecord {
    /// How the section treats it, as the renderer draws it.
    pub clip: OrganClip,
    /// The planes change none of its samples: they do not apply to it, or miss it by
    /// [`CLEAR_OF_PLANES`].
    pub clear: bool,
    /// The renderer cuts its triangles at the planes ([`CullInput::exact_cuts`]), which come near
    /// it: it occludes with the triangles of its own mesh they keep wholly (never a stand-in:
    /// through the cut, what hides the inside is the cut face, drawn from the back faces beyond).
    pub cut: bool,
    /// Opaque and clear of the planes: it occludes whole and counts towards intact solids.
    pub whole: bool,
    /// It may occlude: whole, or cut and opaque.
    pub occluding: bool,
    /// Where `cut`, the planes in its space.
    pub planes: Vec<ModelPlane>,
}

impl OrganRecord {
    /// One record per organ of the frame.
    pub fn of_frame(input: &CullInput) -> Vec<OrganRecord> {
        let (section, planes) = (input.section, input.section.active_planes());
        let records = input.set.organs.iter().zip(&input.layout.organs).enumerate();
        records
            .map(|(o, (organ, state))| {
                let model = state.transform.matrix();
                let clip = section.organ(o, &organ.vertex_bounds().transformed(&model), organ.closed());
                let root = organ.bvh.nodes.first().map(|n| n.bounds.transformed(&model));
                let clear = !section.applies_to(o)
                    || root.is_some_and(|b| section.clear_of(o, &b, input.camera.eye, CLEAR_OF_PLANES));
                let cut = input.exact_cuts && !clear;
                let whole = state.is_opaque() && clear;
                let planes = if cut { crate::clip::in_model_space(planes, &model) } else { Vec::new() };
                OrganRecord { clip, clear, cut, whole, occluding: whole || (cut && state.is_opaque()), planes }
            })
            .collect()
    }

    /// The records of a frame with no section: each opaque organ occludes whole.
    pub fn unclipped(layout: &Layout) -> Vec<OrganRecord> {
        let clip = OrganClip { clipped: false, side: crate::clip::Side::Kept, capped: false };
        let record = |opaque: bool| OrganRecord {
            clip,
            clear: true,
            cut: false,
            whole: opaque,
            occluding: opaque,
            planes: Vec::new(),
        };
        layout.organs.iter().map(|s| record(s.is_opaque())).collect()
    }
}

/// Per record, whether it may occlude.
pub(super) fn occluding(records: &[OrganRecord]) -> Vec<bool> {
    records.iter().map(|r| r.occluding).collect()
}

/// Per record, whether it occludes whole.
pub(super) fn whole(records: &[OrganRecord]) -> Vec<bool> {
    records.iter().map(|r| r.whole).collect()
}
