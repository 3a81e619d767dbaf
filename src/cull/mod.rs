//! Occlusion culling (thesis chapter 3), per frame on the CPU: a [`Culler`] kept from frame to
//! frame picks each organ's triangles to draw, one module per step; the result is a [`DrawList`].
//!
//! - Node bounds are in organ space, moved by each organ's model matrix into world space and
//!   projected into culling pixels: a low-resolution grid over the viewport, x right, y down,
//!   depth = NDC z (larger is farther).
//! - Rectangles of culling pixels are [`PixelRect`]s, inclusive on all four sides.
//! - The [`Culler`] starts each traversal at the last frame's [`cut`] and looks up each visible
//!   part's [`witness`] first.
//! - The steps of a frame, one module each:
//! 1. [`selection`]: occluders by projected size, or the pre-computed minimum occluder sets of the
//!    [`database`] while the layout is unchanged (§3.1-3.2); and the set's solids whose organs are
//!    all opaque, unmoved relative to each other and clear of the clip planes (beyond the thesis:
//!    one stand-in inside a union of organs, with no seams between them; cut at the clip planes
//!    while the eye lies on the side they keep);
//! 2. [`raster`]: their front triangles rasterised conservatively into coverage and depth (§3.3);
//! 3. maps: the [`opacity_map`] (summed-area table) and the [`sparse_depth`] map (§3.4), held with
//!    the tests of boxes, footprints, triangles and points by [`occluders`] ([`depth_bound`]: a
//!    box's depth pixel by pixel);
//! 4. [`traversal`]: each organ's hierarchy front to back, with the adaptive stop (§3.4), and
//!    normal cones culling runs that face away (beyond the thesis; counted apart); nodes and parts
//!    made only of faces inside a solid that is intact this frame
//!    ([`crate::organ_set::hidden_faces`], [`selection::intact_solids`]) are culled untested
//!    (beyond the thesis; counted among the occluded and apart);
//! 5. [`jobs`]: the traversal's subtrees shared between the calling thread and the pool
//!    ([`share`]).

mod cut;
pub mod database;
pub(crate) mod depth_bound;
mod draw_list;
mod jobs;
mod occluders;
pub(crate) mod opacity_map;
pub(crate) mod project;
pub(crate) mod raster;
mod records;
mod rect;
pub mod selection;
mod settings;
mod share;
pub(crate) mod sparse_depth;
mod traversal;
mod witness;

pub use draw_list::{CullStats, DrawList};
pub use records::{OrganRecord, CLEAR_OF_PLANES};
pub use rect::PixelRect;
pub use selection::{by_projected_size, choose_occluders, LeafRef, OccluderSource};
pub use settings::{CullMode, CullSettings, Selection};

use crate::camera::Camera;
use crate::clip::{Section, NO_SECTION};
use crate::layout::Layout;
use crate::organ_set::OrganSet;
use cut::Cut;
use jobs::Subtrees;
use occluders::{rasterise_occluders, Occluders};
use share::Phase;
use sparse_depth::SparseDepth;
use traversal::{traverse_below, OrganView, Start, Walk, SUBTREE_TRIANGLES};
use witness::Witnesses;

/// Culls the drawn organs of `layout` for `camera` at `aspect`, with occluders by projected size
/// (no database); returns the draw list and counts. A frame on its own: a viewer culling frame
/// after frame keeps a [`Culler`] instead.
pub fn cull(
    set: &OrganSet,
    layout: &Layout,
    camera: &Camera,
    aspect: f32,
    settings: &CullSettings,
) -> (DrawList, CullStats) {
    Culler::default().cull(set, layout, camera, aspect, settings)
}

/// The culler of a sequence of frames. It owns the set's occluder database (if any), and keeps,
/// per organ, where the last frame's traversal stopped and starts the next one there ([`cut`]),
/// and a vertex of each visible part that was seen, to look up first ([`witness`]). What it kept
/// changes how many tests a frame takes and, where a start lies below a node whose adaptive stop
/// a fresh traversal would take, which hidden nodes are found; never a pixel (culling stays
/// conservative either way). It may be used with any set: what it kept for an organ whose
/// hierarchy it does not fit is dropped.
#[derive(Clone, Debug, Default)]
pub struct Culler {
    cuts: Vec<Cut>,
    witnesses: Vec<Witnesses>,
    database: Option<database::Database>,
}

impl Culler {
    /// A culler choosing occluders from `database` where its settings allow it.
    pub fn new(database: Option<database::Database>) -> Culler {
        Culler { database, ..Default::default() }
    }

    /// The pre-computed occluders it uses, if any.
    pub fn database(&self) -> Option<&database::Database> {
        self.database.as_ref()
    }

    /// Culls one frame with no section, as [`cull`].
    pub fn cull(
        &mut self,
        set: &OrganSet,
        layout: &Layout,
        camera: &Camera,
        aspect: f32,
        settings: &CullSettings,
    ) -> (DrawList, CullStats) {
        self.cull_with(&CullInput::new(set, layout, camera, aspect), settings, None)
    }

    /// Culls one frame, cut by its section. Organs the planes cut (or come near) occlude only where
    /// the renderer cuts triangles at the planes, with what the planes keep of their own
    /// triangles, and their solids' stand-ins cut there (while the eye is on the side the planes
    /// keep); their back-facing runs are not culled while cut faces are drawn (the renderer draws
    /// those runs again as the cut faces). What the planes remove is culled only where the
    /// renderer cuts triangles at the planes ([`CullInput::exact_cuts`]): where the shaders
    /// discard removed samples instead, a sample of a removed triangle seen at a grazing angle
    /// may pass (its position is interpolated off the triangle), so culling it would change that
    /// sample.
    pub fn cull_frame(&mut self, input: &CullInput, settings: &CullSettings) -> (DrawList, CullStats) {
        self.cull_with(input, settings, None)
    }

    /// Culls one frame with the occluders given (`Some`, in place of the settings' selection):
    /// for the occluder-selection experiments.
    pub fn cull_with(
        &mut self,
        input: &CullInput,
        settings: &CullSettings,
        given: Option<&[LeafRef]>,
    ) -> (DrawList, CullStats) {
        let set = input.set;
        let started = std::time::Instant::now();
        let settings = CullSettings { width: settings.width.max(1), height: settings.height.max(1), ..*settings };
        self.cuts.resize_with(set.organs.len(), Cut::default);
        self.witnesses.resize_with(set.organs.len(), Witnesses::default);
        for (w, organ) in self.witnesses.iter_mut().zip(&set.organs) {
            w.fit(organ.bvh.parts.len());
        }
        let kept = (&mut self.cuts[..], &self.witnesses[..]);
        let given = match given {
            Some(list) => Given::Occluders(list),
            None => Given::Database(self.database.as_ref()),
        };
        let phases = Phases::default();
        // The pool's threads help where occlusion is tested (without it, the work is too small to
        // pay for waking them).
        let (list, mut stats) = match settings.mode {
            CullMode::Occlusion => share::with_crew(
                |quit| {
                    phases.sources.help(quit);
                    phases.raster.help(quit);
                    phases.traversal.help(quit);
                },
                || cull_in_phases(input, &settings, given, kept, &phases),
            ),
            _ => cull_in_phases(input, &settings, given, kept, &phases),
        };
        stats.cull_ms = started.elapsed().as_secs_f64() * 1000.0;
        (list, stats)
    }
}

/// What one frame culls: the set as laid out, seen by a camera at an aspect (width / height), cut
/// by a section.
#[derive(Clone, Copy)]
pub struct CullInput<'a> {
    pub set: &'a OrganSet,
    pub layout: &'a Layout,
    pub camera: &'a Camera,
    pub aspect: f32,
    pub section: &'a Section,
    /// The renderer cuts triangles at the planes before rasterising them
    /// ([`crate::render::Renderer::cuts_geometry`]), so a triangle the planes remove draws no
    /// sample, and the nodes they remove are culled. Without it the shaders discard removed samples
    /// one by one, and what the planes remove is drawn.
    pub exact_cuts: bool,
}

impl<'a> CullInput<'a> {
    /// A frame with no section.
    pub fn new(set: &'a OrganSet, layout: &'a Layout, camera: &'a Camera, aspect: f32) -> CullInput<'a> {
        CullInput { set, layout, camera, aspect, section: &NO_SECTION, exact_cuts: false }
    }

    /// Whether the renderer cuts triangles at the planes and the eye lies where every plane keeps
    /// (by [`EYE_CLEAR_OF_PLANES_MM`]). What the planes keep is their half-spaces' intersection,
    /// so a ray from the eye to a kept point stays kept: it never passes through a cut, and enters
    /// any closed surface it then leaves through a drawn face.
    fn eye_kept(&self) -> bool {
        let planes = self.section.active_planes();
        self.exact_cuts && planes.iter().all(|p| p.normal().dot(self.camera.eye) < p.d - EYE_CLEAR_OF_PLANES_MM)
    }
}

/// How far (millimetres) inside every clip plane the eye must lie for the stand-ins of solids
/// the planes cut to occlude.
const EYE_CLEAR_OF_PLANES_MM: f32 = 1.0;

/// Where a frame's occluders come from: given by the caller, or chosen with the database.
#[derive(Clone, Copy)]
enum Given<'a> {
    Occluders(&'a [LeafRef]),
    Database(Option<&'a database::Database>),
}

/// The culler's parallel phases: the occluders' triangles source by source, the occluder raster's
/// patches, and the subtrees below the top levels of the hierarchies.
#[derive(Default)]
struct Phases<'a> {
    sources: Phase<occluders::Sources<'a>>,
    raster: Phase<raster::Patches>,
    traversal: Phase<Subtrees<'a>>,
}

/// [`Culler::cull_with`], its parallel work done in `phases` (`settings`' size at least 1 x 1),
/// starting each organ's traversal at its cut where occlusion is tested.
fn cull_in_phases<'a>(
    input: &CullInput<'a>,
    settings: &CullSettings,
    given: Given,
    (cuts, witnesses): (&mut [Cut], &'a [Witnesses]),
    phases: &Phases<'a>,
) -> (DrawList, CullStats) {
    let view_proj = input.camera.view_projection(input.aspect);
    let records = OrganRecord::of_frame(input);
    let mut stats = CullStats::default();
    let started = std::time::Instant::now();
    let occ = (settings.mode == CullMode::Occlusion)
        .then(|| frame_occluders(input, &view_proj, settings, given, &records, phases, &mut stats));
    stats.occluders_ms = started.elapsed().as_secs_f64() * 1000.0;
    if let Some(o) = &occ {
        (stats.occluder_leaves, stats.occluder_triangles) = (o.leaves, o.triangles);
    }
    let views = organ_views(input, &view_proj, &records, witnesses, occ.is_some());
    let list = traverse(input.set, settings, (views, occ), (cuts, phases), &mut stats);
    stats.drawn = list.triangles();
    (list, stats)
}

/// The occluders of a frame: chosen (or given), rasterised with the solids' stand-ins.
fn frame_occluders<'a>(
    input: &CullInput<'a>,
    view_proj: &glam::Mat4,
    settings: &CullSettings,
    given: Given,
    records: &[OrganRecord],
    phases: &Phases<'a>,
    stats: &mut CullStats,
) -> Occluders {
    let CullInput { set, layout, camera, .. } = *input;
    let (occluding, whole) = (records::occluding(records), records::whole(records));
    let list = match given {
        Given::Occluders(list) => list.to_vec(),
        Given::Database(database) => {
            let (list, source) = choose_occluders(set, layout, camera, view_proj, settings, database, records);
            stats.source = Some(source);
            list
        }
    };
    // A solid the planes cut occludes with its stand-in cut at them only while the eye lies where
    // every plane keeps: no ray from it to a kept point then passes a plane, so each enters the
    // solid through a drawn surface, never through a cut face (drawn at the depth of the faces
    // beyond it, behind the stand-in). Seen through a cut, it hides nothing: organs that touch
    // its organs (a cortex on its white matter) have faces on, or just inside, the surfaces drawn
    // as cut faces, which may show through them.
    let solids = selection::solids(set, layout, view_proj, if input.eye_kept() { &occluding } else { &whole });
    let (w, h) = (settings.width, settings.height);
    let phases = (&phases.sources, &phases.raster);
    let mut occ = rasterise_occluders((set, layout), view_proj, (&solids, &list), records, (w, h), phases);
    stats.solids = solids.len();
    if settings.hole_tolerance.is_some() {
        let depth: Vec<f32> =
            occ.maps.depth.iter().map(|&d| if d.is_finite() { d } else { f32::NEG_INFINITY }).collect();
        let sparse = SparseDepth::new(&depth, w, h);
        occ.approximate = Some((depth, sparse));
    }
    occ
}

/// Per organ, how its traversal sees it (`None` where it is not drawn): its back faces culled
/// unless the renderer draws them as cut faces, the planes that remove its nodes where the
/// renderer cuts triangles, and (where occlusion is `testing`) the solids intact this frame, whose
/// inside faces are hidden whatever the occluders.
///
/// - Where occlusion is tested and the eye lies where the planes keep ([`CullInput::eye_kept`]),
///   no ray from it passes through a cut: a solid whose organs are all cut or whole (and all
///   under the planes, so none is drawn beyond them) hides its inside faces as if intact, and an
///   opaque closed organ the planes cut, wholly beyond the near plane (so the eye is outside it),
///   hides its faces turned away (drawn as its cut face) behind those facing the eye.
fn organ_views<'w>(
    input: &CullInput<'w>,
    view_proj: &glam::Mat4,
    records: &[OrganRecord],
    witnesses: &'w [Witnesses],
    testing: bool,
) -> Vec<Option<OrganView<'w>>> {
    let CullInput { set, layout, camera, section, .. } = *input;
    let whole = records::whole(records);
    let kept = testing && input.eye_kept();
    let mut intact = if testing { selection::intact_solids(set, layout, view_proj, &whole) } else { 0 };
    if kept {
        let sealed: Vec<bool> = records.iter().enumerate().map(|(o, r)| r.occluding && section.applies_to(o)).collect();
        intact |= selection::intact_solids(set, layout, view_proj, &sealed);
    }
    let organs = set.organs.iter().zip(&layout.organs).zip(witnesses).zip(records);
    organs
        .map(|(((organ, state), witnesses), record)| {
            let drawn = state.is_drawn() && !organ.bvh.nodes.is_empty();
            let model = state.transform.matrix();
            let cut_faces_hidden = kept
                && record.occluding
                && organ
                    .bvh
                    .nodes
                    .first()
                    .is_some_and(|root| project::wholly_ahead(&(*view_proj * model), &root.bounds));
            let back_faces_culled = organ.closed() && (!record.clip.capped || cut_faces_hidden);
            let removing = if record.cut { section.active_planes() } else { &[] };
            let inside = (&organ.inside, intact);
            drawn.then(|| OrganView::new(view_proj, &model, camera, witnesses, back_faces_culled, removing, inside))
        })
        .collect()
}

/// Each drawn organ's hierarchy traversed from its cut (where occlusion is tested), the subtrees
/// shared between this thread and the pool; the draw list in triangle order, and the cuts kept.
fn traverse<'a>(
    set: &'a OrganSet,
    settings: &CullSettings,
    (views, occ): (Vec<Option<OrganView<'a>>>, Option<Occluders>),
    (cuts, phases): (&mut [Cut], &Phases<'a>),
    stats: &mut CullStats,
) -> DrawList {
    let testing = occ.is_some();
    // Per organ, what its traversals gave. Starts above the subtree size are traversed here, their
    // subtrees below shared; smaller starts are shared in groups.
    let mut walks: Vec<Walk> = set.organs.iter().map(|_| Walk::default()).collect();
    let mut job =
        Subtrees { set, views: Vec::new(), occ: None, settings: *settings, starts: Vec::new(), tasks: Vec::new() };
    for (o, (organ, view)) in set.organs.iter().zip(&views).enumerate() {
        let Some(view) = view else { continue };
        stats.triangles += organ.mesh.triangle_count();
        if settings.mode == CullMode::None {
            walks[o].list.push(0..organ.mesh.indices.len() as u32);
            continue;
        }
        let starts = if testing { cuts[o].starts(&organ.bvh) } else { &[0][..] };
        for &node in starts {
            let count = organ.bvh.nodes[node as usize].count;
            if count <= SUBTREE_TRIANGLES {
                job.add(Start { organ: o, node, test: testing, started: true }, count, true);
                continue;
            }
            let mut split = Vec::new();
            let start = Start { organ: o, node, test: testing, started: true };
            let here = (&mut walks[o], Some(&mut split));
            traverse_below(organ, view, occ.as_ref(), settings, start, here);
            for (node, test) in split {
                let count = organ.bvh.nodes[node as usize].count;
                job.add(Start { organ: o, node, test, started: false }, count, false);
            }
        }
    }
    // In triangle order: each thread then hands back an organ's ranges and reached nodes as one
    // ordered run, which the stable sorts below join in about linear time.
    let first = |s: &Start| (s.organ, set.organs[s.organ].bvh.nodes[s.node as usize].first);
    job.tasks.sort_by_key(|t| first(&job.starts[t.1.start]));
    (job.views, job.occ) = (views, occ);
    for (o, walk) in phases.traversal.run(job).into_iter().flatten() {
        let to = &mut walks[o];
        to.list.extend(walk.list);
        to.stats.add_traversal(&walk.stats);
        to.reached.extend(walk.reached);
    }
    // In triangle order, as one traversal depth first would give them.
    let mut list = DrawList { ranges: vec![Vec::new(); set.organs.len()] };
    for (o, walk) in walks.into_iter().enumerate() {
        stats.add_traversal(&walk.stats);
        if testing && !walk.reached.is_empty() {
            cuts[o].keep(walk.reached);
        }
        let mut r = walk.list;
        r.sort_by_key(|r| r.start);
        r.into_iter().for_each(|r| list.push(o, r));
    }
    list
}
