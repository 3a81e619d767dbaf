//! The front-to-back traversal of one organ's hierarchy (thesis §3.4): frustum test, then the
//! occlusion tests of each node against the frame's [`Occluders`], the adaptive stop, and the
//! fall-back on a failing leaf's parts.
//!
//! - Boxes in organ space, projected into culling pixels.

use super::cut::Reached;
use super::depth_bound::{DepthBound, FarBound, Unprojection};
use super::draw_list::{push_merged, CullStats};
use super::occluders::{Occluders, Verdict};
use super::project::{project_box, ScreenBox};
use super::settings::CullSettings;
use super::witness::Witnesses;
use crate::bvh::{Cone, Slab};
use crate::camera::Camera;
use crate::mesh::Bounds;
use crate::organ_set::hidden_faces::Inside;
use crate::organ_set::Organ;
use glam::{Mat4, Vec3};
use std::ops::Range;

/// Triangles are "not much smaller than the pixels" of a rectangle when there are at most this
/// many per pixel of it. A failing leaf's parts are then tested, and a failing part's triangles
/// one by one; where they are much smaller (10M triangles), the boxes are about as tight and the
/// extra tests cost more than they cull.
pub(super) const TRIANGLES_PER_PIXEL: usize = 4;

/// Subtrees of at most this many triangles are the tasks shared between the threads.
pub(super) const SUBTREE_TRIANGLES: u32 = 1 << 13;
/// Where a shared traversal starts: a node of an organ, whether occlusion is tested there, and
/// whether it is a start of the frame (of the organ's cut) or a subtree below one.
#[derive(Clone, Copy, Debug)]
pub(super) struct Start {
    pub organ: usize,
    pub node: u32,
    pub test: bool,
    pub started: bool,
}

/// How one organ is seen: its model-view-projection matrix, that matrix's inverse and the eye in
/// organ space (for the boxes' depth bounds); and its parts' witnesses, from the last frames.
pub(super) struct OrganView<'a> {
    pub mvp: Mat4,
    inverse: Unprojection,
    eye: Vec3,
    pub witnesses: &'a Witnesses,
    /// Whether the renderer culls its back faces in this frame (closed, not mirrored, no cut faces
    /// drawn): runs of triangles facing away are then culled by their normal cones.
    back_faces_culled: bool,
    /// Clip planes that cut away what lies beyond them, in organ space
    /// ([`crate::clip::in_model_space`]): where the renderer cuts triangles at the planes, a box
    /// wholly beyond one is culled.
    removing: Vec<crate::clip::ModelPlane>,
    /// Its nodes and parts made of faces inside solids, and the solids intact this frame (bits).
    inside: (&'a Inside, u64),
}

impl<'a> OrganView<'a> {
    pub fn new(
        view_proj: &Mat4,
        model: &Mat4,
        camera: &Camera,
        witnesses: &'a Witnesses,
        back_faces_culled: bool,
        removing: &[crate::clip::ClipPlane],
        inside: (&'a Inside, u64),
    ) -> OrganView<'a> {
        let mvp = *view_proj * *model;
        let eye = model.inverse().transform_point3(camera.eye);
        let back_faces_culled = back_faces_culled && model.determinant() > 0.0;
        let removing = crate::clip::in_model_space(removing, model);
        OrganView { mvp, inverse: Unprojection::of(&mvp), eye, witnesses, back_faces_culled, removing, inside }
    }

    /// Whether node `n` is made only of faces inside solids intact this frame: no pixel shows it.
    fn inside(&self, n: u32) -> bool {
        self.inside.1 != 0 && self.inside.0.node(n, self.inside.1)
    }

    /// Whether part `p` is, as [`OrganView::inside`].
    fn inside_part(&self, p: usize) -> bool {
        self.inside.1 != 0 && self.inside.0.part(p, self.inside.1)
    }

    /// Whether a node or part at or below node `n` may be inside an intact solid.
    fn inside_below(&self, n: u32) -> bool {
        self.inside.1 != 0 && self.inside.0.any_below(n)
    }

    /// Whether the clip planes remove all of `bounds` (the renderer draws nothing of it).
    pub fn removed(&self, bounds: &Bounds) -> bool {
        let m = crate::clip::SIDE_MARGIN_MM;
        self.removing.iter().any(|&(n, d)| bounds.corners().iter().all(|&c| n.dot(c) > d + m))
    }

    /// Whether a clip plane passes through `bounds`, so that its children may be removed.
    fn cut(&self, bounds: &Bounds) -> bool {
        let m = crate::clip::SIDE_MARGIN_MM;
        self.removing.iter().any(|&(n, d)| bounds.corners().iter().any(|&c| n.dot(c) > d + m))
    }

    /// Whether a run of triangles in `bounds` with normals in `cone` faces away, so the renderer
    /// draws none of it.
    pub fn faces_away(&self, bounds: &Bounds, cone: &Cone) -> bool {
        self.back_faces_culled && cone.faces_away(bounds, self.eye)
    }

    pub fn depth_bound(&self, b: &Bounds, slab: Option<&Slab>, nearest: f32, w: usize, h: usize) -> DepthBound {
        DepthBound::of_box(&self.inverse, self.eye, b, slab, nearest, w, h)
    }

    pub fn far_bound(&self, b: &Bounds, slab: &Slab, farthest: f32, w: usize, h: usize) -> FarBound {
        FarBound::of_box(&self.inverse, self.eye, b, slab, farthest, w, h)
    }
}

/// What traversals of one organ gave: the index ranges that survive culling (contiguous ones
/// merged), the culled and tested counts, and where occlusion is tested, the nodes where they
/// stopped ([`cut`]).
#[derive(Default)]
pub(super) struct Walk {
    pub list: Vec<Range<u32>>,
    pub stats: CullStats,
    pub reached: Vec<Reached>,
    /// (node, whether occlusion is still tested below it) left to visit.
    stack: Vec<(u32, bool)>,
}

/// Traverses drawn `organ` below `start`, into `walk`. With `split`, subtrees of at most
/// [`SUBTREE_TRIANGLES`] are left out, listed there as (node, whether occlusion is tested there).
pub(super) fn traverse_below(
    organ: &Organ,
    view: &OrganView,
    occ: Option<&Occluders>,
    settings: &CullSettings,
    start: Start,
    (walk, mut split): (&mut Walk, Option<&mut Vec<(u32, bool)>>),
) {
    let Start { node: root, test, started, .. } = start;
    let (w, h) = (settings.width, settings.height);
    let holes = settings.hole_tolerance;
    let Walk { list, stats, reached, stack } = walk;
    stack.push((root, test));
    while let Some((n, test)) = stack.pop() {
        let node = &organ.bvh.nodes[n as usize];
        // Where occlusion is tested, a node the traversal stops at is one of the cut: `closed`
        // where nothing below it is tested.
        let mut stop = |closed: bool| {
            if test && occ.is_some() {
                reached.push(Reached { node: n, first: node.first, closed, started: started && n == root });
            }
        };
        let seen = project_box(&view.mvp, &node.bounds, w, h);
        if seen == ScreenBox::Outside {
            stats.frustum_culled += node.count as usize;
            stop(true);
            continue;
        }
        if view.removed(&node.bounds) {
            stats.clip_culled += node.count as usize;
            stop(true);
            continue;
        }
        if view.inside(n) {
            stats.occlusion_culled += node.count as usize;
            stats.inside_culled += node.count as usize;
            stop(true);
            continue;
        }
        if occ.is_some() && view.faces_away(&node.bounds, &node.cone) {
            stats.back_face_culled += node.count as usize;
            stop(true);
            continue;
        }
        let mut test_children = test;
        // Whether a failing leaf's parts are worth testing: where its triangles are not much
        // smaller than pixels, or its box lies behind the occluders at its centre (not where it
        // reaches in front of them: the occluders' own surface, mostly).
        let mut parts = true;
        if let (ScreenBox::Rect { rect, z, far, .. }, Some(o), true) = (seen, occ, test) {
            stats.nodes_tested += 1;
            // Computed at most once: by the test, and again by a failing leaf's gate below.
            let cell = std::cell::OnceCell::new();
            let bound = || *cell.get_or_init(|| view.depth_bound(&node.bounds, Some(&node.slab), z, w, h));
            let (covered, hidden) = o.test(rect, z, holes, bound);
            if hidden {
                stats.occlusion_culled += node.count as usize;
                stop(true);
                continue;
            }
            let area = rect.area();
            if node.is_leaf() {
                let (x, y) = rect.centre();
                parts = node.count as usize <= TRIANGLES_PER_PIXEL * area || o.maps.depth[y * w + x] < bound().at(x, y);
            }
            // Adaptive stop: too little of it is covered for a descendant to be hidden; only
            // the frustum is tested below. Nor can one be where the whole box lies in front of the
            // occluders (a visible wall).
            test_children = covered as f32 >= settings.adaptive_ratio * area as f32
                && !view.far_bound(&node.bounds, &node.slab, far, w, h).in_front(&o.maps.depth, w, rect);
        }
        let testing = test_children && occ.is_some();
        if !testing
            && matches!(seen, ScreenBox::Rect { inside: true, .. })
            && !view.cut(&node.bounds)
            && !view.inside_below(n)
        {
            // Wholly inside the frustum and the planes with nothing more to test: all of it, in one
            // range.
            push_merged(list, 3 * node.first..3 * (node.first + node.count));
            stop(true);
            continue;
        }
        match (node.is_leaf(), occ) {
            // A leaf that failed: its parts' tighter boxes may still be hidden.
            (true, Some(o)) if test_children && parts => {
                let mut all_culled = true;
                for p in organ.bvh.part_range(node.leaf) {
                    let part = &organ.bvh.parts[p];
                    stats.nodes_tested += 1;
                    if view.removed(&part.bounds) {
                        stats.clip_culled += part.count as usize;
                        view.witnesses.set(p, None);
                        continue;
                    }
                    if view.inside_part(p) {
                        stats.occlusion_culled += part.count as usize;
                        stats.inside_culled += part.count as usize;
                        view.witnesses.set(p, None);
                        continue;
                    }
                    if view.faces_away(&part.bounds, &part.cone) {
                        stats.back_face_culled += part.count as usize;
                        view.witnesses.set(p, None);
                        continue;
                    }
                    // Its witness seen again: the part is drawn (its tests could not pass).
                    let witness = view.witnesses.get(p).filter(|_| holes.is_none());
                    if witness.is_some_and(|i| o.shows_vertex(organ, part, i, &view.mvp)) {
                        all_culled = false;
                        push_merged(list, 3 * part.first..3 * (part.first + part.count));
                        continue;
                    }
                    let verdict = match project_box(&view.mvp, &part.bounds, w, h) {
                        ScreenBox::Outside => {
                            stats.frustum_culled += part.count as usize;
                            view.witnesses.set(p, None);
                            continue;
                        }
                        ScreenBox::Straddles => Verdict::Shown,
                        ScreenBox::Rect { rect, z, .. } => {
                            // Computed at most once: by the box's test, and again by its footprint's.
                            let cell = std::cell::OnceCell::new();
                            let bound =
                                || *cell.get_or_init(|| view.depth_bound(&part.bounds, Some(&part.slab), z, w, h));
                            let area = rect.area();
                            if o.test(rect, z, holes, bound).1 {
                                Verdict::Hidden
                            } else if part.count as usize <= TRIANGLES_PER_PIXEL * area {
                                o.part_hidden(organ, part, &view.mvp, holes, bound)
                            } else {
                                Verdict::Shown
                            }
                        }
                    };
                    view.witnesses.set(p, verdict.witness());
                    match verdict {
                        Verdict::Hidden => stats.occlusion_culled += part.count as usize,
                        _ => {
                            all_culled = false;
                            push_merged(list, 3 * part.first..3 * (part.first + part.count))
                        }
                    }
                }
                stop(all_culled);
            }
            (true, _) if view.cut(&node.bounds) || view.inside_below(n) => {
                // A plane passes through it, or some of its parts lie inside an intact solid:
                // those parts are left out.
                for p in organ.bvh.part_range(node.leaf) {
                    let part = &organ.bvh.parts[p];
                    if view.removed(&part.bounds) {
                        stats.clip_culled += part.count as usize;
                    } else if view.inside_part(p) {
                        stats.occlusion_culled += part.count as usize;
                        stats.inside_culled += part.count as usize;
                    } else {
                        push_merged(list, 3 * part.first..3 * (part.first + part.count));
                    }
                }
                stop(true);
            }
            (true, _) => {
                push_merged(list, 3 * node.first..3 * (node.first + node.count));
                stop(true);
            }
            (false, _) => {
                if !testing {
                    stop(true);
                }
                for child in [node.children[1], node.children[0]] {
                    match split.as_deref_mut() {
                        Some(split) if organ.bvh.nodes[child as usize].count <= SUBTREE_TRIANGLES => {
                            split.push((child, test_children))
                        }
                        _ => stack.push((child, test_children)),
                    }
                }
            }
        }
    }
}
