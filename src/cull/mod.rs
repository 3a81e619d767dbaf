//! Occlusion culling (thesis chapter 3), per frame on the CPU. Spaces: node bounds in organ space,
//! moved by each organ's model matrix into world space, projected by the camera into clip space and
//! then into culling pixels (a low-resolution grid over the viewport, x right, y down; depth = NDC z,
//! larger is farther).
//!
//! 1. View-frustum culling of each drawn organ's hierarchy ([`crate::bvh`]).
//! 2. Occluders: opaque, visible organs by projected size, largest first; of each, its leaves in
//!    the frustum nearest first (of its occluder stand-in where it has one and lies wholly ahead),
//!    up to a triangle budget (no pre-processing, so organs may move); or, for an unchanged layout,
//!    the pre-computed minimum occluder sets ([`selection`], [`crate::mos`]).
//! 3. [`raster`]: their front triangles rasterised conservatively into coverage and depth.
//! 4. [`opacity_map`] (summed-area table) for the overlap test in four look-ups, and
//!    [`sparse_depth`] for the depth comparison over peaks only.
//! 5. Hierarchical traversal: a node is culled when its outward-rounded rectangle is wholly covered
//!    and its nearest depth is behind every occluder depth there, or failing that, pixel by pixel,
//!    its box's depth bound there ([`depth_bound`]: a tilted box over a tilted occluder); below a
//!    node whose coverage ratio is under the adaptive threshold, or which lies wholly in front of
//!    the occluders wherever they cover it (its far bound: a visible wall), descendants are tested
//!    against the frustum only. (Depth bounds also use each node's slab, [`crate::bvh::Slab`].) A
//!    leaf that fails falls back on its parts ([`crate::bvh::Part`]), each culled on its own, and a
//!    part that fails, where its triangles are not much smaller than the pixels, on its footprint
//!    (the rectangle of its projected vertices), then on the footprints of groups of its
//!    triangles, and then on those triangles, each tested with its own rectangle and depth plane
//!    (a vertex seen in front of the occluders ends these tests); a node wholly inside the
//!    frustum with nothing more to test is drawn as one range. A [`Culler`] kept from frame to
//!    frame starts each organ's traversal where the last frame's stopped ([`cut`]), not at its
//!    root, and first looks up, of a part seen last frame, the vertex that was seen: seen again,
//!    it shows the part without its tests ([`witness`]). Below the top levels, subtrees (and
//!    groups of small starts) are traversed as tasks [`share`]d between the calling thread and
//!    the pool, as are the occluder patches in step 3.
//!
//! The result is a [`DrawList`]: per organ, the index ranges to draw.

mod cut;
pub mod depth_bound;
pub mod opacity_map;
pub mod raster;
pub mod selection;
mod share;
pub mod sparse_depth;
mod witness;

pub use selection::{by_projected_size, choose_occluders, LeafRef, OccluderSource, Selection};

use crate::bvh::{Bvh, Part, Slab, NONE, PART_TRIANGLES};
use crate::camera::Camera;
use crate::layout::Layout;
use crate::mesh::Bounds;
use crate::organ_set::OrganSet;
use cut::{Cut, Reached};
use depth_bound::{DepthBound, FarBound, Unprojection};
use glam::{Mat4, Vec3, Vec3A, Vec4};
use opacity_map::OpacityMap;
use raster::{OccluderMaps, OccluderRaster};
use share::{Phase, Tasks};
use sparse_depth::SparseDepth;
use std::ops::Range;
use witness::Witnesses;

#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CullMode {
    /// Draw every drawn organ whole.
    None,
    /// View-frustum culling of the hierarchy only.
    Frustum,
    /// Frustum and occlusion culling.
    Occlusion,
}

impl CullMode {
    pub const ALL: [CullMode; 3] = [CullMode::None, CullMode::Frustum, CullMode::Occlusion];

    pub fn name(self) -> &'static str {
        match self {
            CullMode::None => "none",
            CullMode::Frustum => "frustum",
            CullMode::Occlusion => "occlusion",
        }
    }

    pub fn parse(s: &str) -> Option<CullMode> {
        CullMode::ALL.into_iter().find(|m| m.name() == s)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct CullSettings {
    pub mode: CullMode,
    /// Culling raster size in pixels.
    pub width: usize,
    pub height: usize,
    /// Most occluder triangles rasterised per frame (those facing the eye).
    pub occluder_triangles: usize,
    /// Stop descending below this coverage ratio (thesis: 0.2); 0 disables the adaptive stop.
    pub adaptive_ratio: f32,
    /// Approximate overlap test: tolerate this fraction of uncovered pixels. Not conservative;
    /// `None` (the default) keeps culling exact.
    pub hole_tolerance: Option<f32>,
    /// Most occluder leaves per frame (`None`: only the triangle budget limits them).
    pub occluder_leaves: Option<usize>,
    /// Where the occluders come from.
    pub selection: Selection,
}

impl Default for CullSettings {
    fn default() -> Self {
        CullSettings {
            mode: CullMode::Occlusion,
            width: 128,
            height: 128,
            occluder_triangles: 1280,
            adaptive_ratio: 0.2,
            hole_tolerance: None,
            occluder_leaves: None,
            selection: Selection::Auto,
        }
    }
}

/// Per organ, the index ranges (in indices, contiguous ones merged) to draw.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DrawList {
    pub ranges: Vec<Vec<Range<u32>>>,
}

impl DrawList {
    fn push(&mut self, organ: usize, r: Range<u32>) {
        push_merged(&mut self.ranges[organ], r);
    }

    pub fn triangles(&self) -> usize {
        self.ranges.iter().flatten().map(|r| (r.end - r.start) as usize / 3).sum()
    }
}

/// Appends a range, merged into the last one where they meet.
fn push_merged(list: &mut Vec<Range<u32>>, r: Range<u32>) {
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
    pub nodes_tested: usize,
    pub occluder_leaves: usize,
    /// Occluder triangles rasterised (facing the eye).
    pub occluder_triangles: usize,
    /// Where the occluders came from (`None` without occlusion culling or with occluders given).
    pub source: Option<OccluderSource>,
    pub cull_ms: f64,
}

impl CullStats {
    /// Adds the counts of a traversal (of an organ or a subtree).
    fn add_traversal(&mut self, o: &CullStats) {
        self.triangles += o.triangles;
        self.frustum_culled += o.frustum_culled;
        self.occlusion_culled += o.occlusion_culled;
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

/// A box seen from the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Seen {
    /// Wholly outside one frustum plane.
    Outside,
    /// Reaches behind the eye: cannot be placed on screen.
    Straddles,
    /// Inclusive pixel rectangle (rounded outward, clamped), nearest and farthest NDC depth;
    /// `inside`: wholly inside the frustum.
    Rect { x0: usize, y0: usize, x1: usize, y1: usize, z: f32, far: f32, inside: bool },
}

pub(crate) fn see(mvp: &Mat4, b: &Bounds, w: usize, h: usize) -> Seen {
    // The eight corners in clip space, four at a time: lane i of `near` is corner i (offset along
    // the box's x if i & 1, along y if i & 2), and `far` is the same four offset along z.
    let min = Vec3::from(b.min);
    let size = Vec3::from(b.max) - min;
    let base = *mvp * min.extend(1.0);
    let (dx, dy, dz) = (mvp.x_axis * size.x, mvp.y_axis * size.y, mvp.z_axis * size.z);
    let lanes = |k: usize| Vec4::new(base[k], base[k] + dx[k], base[k] + dy[k], base[k] + dx[k] + dy[k]);
    let near = [lanes(0), lanes(1), lanes(2), lanes(3)];
    let far = [near[0] + dz.x, near[1] + dz.y, near[2] + dz.z, near[3] + dz.w];
    // Per frustum plane, a bit per corner outside it.
    let outside = |[x, y, z, cw]: [Vec4; 4]| {
        [x.cmplt(-cw), x.cmpgt(cw), y.cmplt(-cw), y.cmpgt(cw), z.cmplt(Vec4::ZERO), z.cmpgt(cw)].map(|m| m.bitmask())
    };
    let (a, c) = (outside(near), outside(far));
    if (0..6).any(|k| a[k] & c[k] == 0b1111) {
        return Seen::Outside;
    }
    let inside = (0..6).all(|k| a[k] | c[k] == 0);
    let eps = Vec4::splat(1e-5);
    if near[3].cmple(eps).any() || far[3].cmple(eps).any() {
        return Seen::Straddles;
    }
    let ndc = |k: usize| (near[k] / near[3], far[k] / far[3]);
    let range = |(n, f): (Vec4, Vec4)| (n.min(f).min_element(), n.max(f).max_element());
    let ((x_lo, x_hi), (y_lo, y_hi), (z_lo, z_hi)) = (range(ndc(0)), range(ndc(1)), range(ndc(2)));
    if ![x_lo, x_hi, y_lo, y_hi, z_lo, z_hi].iter().all(|v| v.is_finite()) {
        return Seen::Straddles;
    }
    let (wf, hf) = (w as f32, h as f32);
    let (px0, px1) = ((x_lo + 1.0) * 0.5 * wf, (x_hi + 1.0) * 0.5 * wf);
    let (py0, py1) = ((1.0 - y_hi) * 0.5 * hf, (1.0 - y_lo) * 0.5 * hf);
    let (x0, x1) = (first_pixel(px0, wf), last_pixel(px1, wf));
    let (y0, y1) = (first_pixel(py0, hf), last_pixel(py1, hf));
    Seen::Rect { x0, y0, x1, y1, z: z_lo, far: z_hi, inside }
}

/// The first of `n` pixels that a span starting at `v` (in pixels) reaches, clamped (without a
/// call to floor).
fn first_pixel(v: f32, n: f32) -> usize {
    v.clamp(0.0, n - 1.0) as usize
}

/// The last of `n` pixels that a span ending at `v` (in pixels) reaches, clamped (without a call
/// to ceil).
fn last_pixel(v: f32, n: f32) -> usize {
    let v = v.clamp(0.0, n);
    let t = v as usize;
    (t + usize::from((t as f32) < v)).saturating_sub(1).min(n as usize - 1)
}

/// Does the box lie wholly beyond the near plane (so the eye is outside it)?
pub(crate) fn wholly_ahead(mvp: &Mat4, b: &Bounds) -> bool {
    b.corners().iter().all(|c| {
        let p = *mvp * c.extend(1.0);
        p.w > 1e-5 && p.z >= 0.0
    })
}

/// The occluder maps and look-up structures of one frame.
pub struct Occluders {
    pub maps: OccluderMaps,
    pub opacity: OpacityMap,
    pub sparse: SparseDepth,
    /// For the approximate test: the depth map with uncovered pixels never in the way (-inf), and
    /// its sparse depth map.
    pub approximate: Option<(Vec<f32>, SparseDepth)>,
    pub leaves: usize,
    /// Triangles rasterised: those of the leaves that face the eye, beyond the near plane.
    pub triangles: usize,
}

impl Occluders {
    /// Tests a box seen as the inclusive pixel rectangle with nearest depth `z`: how many of its
    /// pixels are covered, and whether it is hidden (wholly covered, or but for `holes` pixels
    /// with the approximate test, and behind every occluder depth there: behind the farthest over
    /// the rectangle, or else pixel by pixel behind each, by the box's depth bound `bound`).
    fn test(&self, rect: [usize; 4], z: f32, holes: Option<f32>, bound: impl FnOnce() -> DepthBound) -> (u32, bool) {
        let [x0, y0, x1, y1] = rect;
        let area = ((x1 - x0 + 1) * (y1 - y0 + 1)) as u32;
        let covered = self.opacity.covered(x0, y0, x1, y1);
        let (overlapped, depth, sparse) = match (holes, &self.approximate) {
            (Some(t), Some((depth, sparse))) => {
                (covered + (t.clamp(0.0, 1.0) * area as f32) as u32 >= area, depth, sparse)
            }
            _ => (covered >= area, &self.maps.depth, &self.sparse),
        };
        let hidden = overlapped
            && (sparse.all_in_front_of(depth, x0, y0, x1, y1, z) || bound().behind(depth, self.maps.width, rect));
        (covered, hidden)
    }

    /// Whether a part of `organ` whose box failed is hidden all the same (tested as above): by its
    /// footprint, the rectangle of its projected vertices with their nearest depth and the box's
    /// depth bound `bound`; or else group by group of [`GROUP_TRIANGLES`] consecutive triangles
    /// (lying together: a part is split like the hierarchy) by the group's footprint, and where
    /// that fails by each of its triangles on its own, with its own rectangle and depth plane. A
    /// part reaching before the near plane is not, nor one of whose first [`SEEN_VERTICES`]
    /// vertices is seen ([`Occluders::sees`]: none of these tests could then pass). Its vertices
    /// are projected once. A part not hidden is [`Verdict::Seen`] where one of its vertices is
    /// seen (looked for among the rest only once its tests failed).
    fn part_hidden(
        &self,
        organ: &crate::organ_set::Organ,
        part: &Part,
        mvp: &Mat4,
        holes: Option<f32>,
        bound: impl Fn() -> DepthBound,
    ) -> Verdict {
        let (w, h) = (self.maps.width, self.maps.height);
        // 16-byte vectors: each is stored and loaded whole.
        let mut projected = [Vec3A::ZERO; 3 * PART_TRIANGLES];
        let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        let vertices = organ.bvh.vertices_of(part);
        for (i, (at, &v)) in projected.iter_mut().zip(vertices).enumerate() {
            let Some(p) = project_point(organ.mesh.positions[v as usize], mvp, w, h) else { return Verdict::Shown };
            // With holes tolerated, a seen point does not keep a part from being culled.
            if i < SEEN_VERTICES && holes.is_none() && self.sees(p) {
                return Verdict::Seen(i);
            }
            let p = Vec3A::from(p);
            (*at, lo, hi) = (p, lo.min(p), hi.max(p));
        }
        // Off the screen, a footprint draws nothing.
        let footprint_hidden = |lo: Vec3A, hi: Vec3A| {
            let (lo, hi) = (Vec3::from(lo), Vec3::from(hi));
            self.rect(lo, hi).is_none_or(|rect| self.test(rect, lo.z, holes, &bound).1)
        };
        if footprint_hidden(lo, hi) {
            return Verdict::Hidden;
        }
        let corners = |t: u32| organ.bvh.corners[t as usize].map(|c| projected[c as usize]);
        let triangle_hidden = |t: u32| {
            let tri = corners(t);
            let (lo, hi) = (tri[0].min(tri[1]).min(tri[2]).into(), tri[0].max(tri[1]).max(tri[2]).into());
            let tri = tri.map(Vec3::from);
            self.rect(lo, hi).is_none_or(|rect| self.test(rect, lo.z, holes, || DepthBound::of_triangle(&tri)).1)
        };
        let end = part.first + part.count;
        let hidden = (part.first..end).step_by(GROUP_TRIANGLES).all(|first| {
            let group = first..(first + GROUP_TRIANGLES as u32).min(end);
            let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
            for p in group.clone().flat_map(corners) {
                (lo, hi) = (lo.min(p), hi.max(p));
            }
            footprint_hidden(lo, hi) || group.into_iter().all(triangle_hidden)
        });
        match hidden {
            true => Verdict::Hidden,
            false if holes.is_some() => Verdict::Shown,
            // A witness for the next frame, among the vertices not yet looked up.
            false => (SEEN_VERTICES..vertices.len())
                .find(|&i| self.sees(Vec3::from(projected[i])))
                .map_or(Verdict::Shown, Verdict::Seen),
        }
    }

    /// Is vertex `place` of `part` seen ([`Occluders::sees`])? Then the part is not hidden.
    fn vertex_seen(&self, organ: &crate::organ_set::Organ, part: &Part, place: usize, mvp: &Mat4) -> bool {
        let (w, h) = (self.maps.width, self.maps.height);
        let v = organ.bvh.vertices_of(part).get(place);
        v.and_then(|&v| project_point(organ.mesh.positions[v as usize], mvp, w, h)).is_some_and(|p| self.sees(p))
    }

    /// Whether point `p` (in pixels, with its NDC depth) is seen where it lies: in a pixel that no
    /// occluder covers, or in front of the occluder depth there, and inside the frustum, each by a
    /// margin ([`SEEN_MARGIN`] pixels from the pixel's border, [`SEEN_DEPTH_MARGIN`] in depth) far
    /// above the rounding by which a box's or a triangle's projection may miss a point it holds.
    /// Then no triangle through it, nor box holding it, is outside the frustum or behind the
    /// occluders over that pixel: its least depth there is at most `p`'s.
    fn sees(&self, p: Vec3) -> bool {
        // Truncation is the floor for the positive values it is used on.
        let (x, y) = (p.x as usize, p.y as usize);
        let clear = |v: f32, floor: usize| (SEEN_MARGIN..1.0 - SEEN_MARGIN).contains(&(v - floor as f32));
        p.x > 0.0
            && p.y > 0.0
            && x < self.maps.width
            && y < self.maps.height
            && clear(p.x, x)
            && clear(p.y, y)
            && (SEEN_DEPTH_MARGIN..1.0 - SEEN_DEPTH_MARGIN).contains(&p.z)
            && p.z + SEEN_DEPTH_MARGIN < self.maps.depth[y * self.maps.width + x]
    }

    /// The pixel rectangle (rounded outward, clamped) of the screen box `lo..hi` in pixels, or
    /// `None` where it lies off the screen.
    fn rect(&self, lo: Vec3, hi: Vec3) -> Option<[usize; 4]> {
        let (wf, hf) = (self.maps.width as f32, self.maps.height as f32);
        (hi.x > 0.0 && hi.y > 0.0 && lo.x < wf && lo.y < hf)
            .then(|| [first_pixel(lo.x, wf), first_pixel(lo.y, hf), last_pixel(hi.x, wf), last_pixel(hi.y, hf)])
    }
}

/// Rasterises the given occluder leaves (organ by organ, so leaves of one organ fuse into
/// patches) and builds the look-up structures.
pub(crate) fn rasterise_occluders(
    set: &OrganSet,
    layout: &Layout,
    view_proj: &Mat4,
    list: &[LeafRef],
    w: usize,
    h: usize,
    phase: &Phase<raster::Patches>,
) -> Occluders {
    // Per organ, the chosen leaves of its own hierarchy and of its stand-in's.
    let mut chosen: Vec<[Vec<u32>; 2]> = vec![Default::default(); set.organs.len()];
    for r in list {
        chosen[r.organ as usize][usize::from(r.stand_in)].push(r.leaf);
    }
    let mut raster = OccluderRaster::new(w, h);
    let mut triangles = 0;
    for (o, [own, stand_in]) in chosen.iter().enumerate() {
        let organ = &set.organs[o];
        let mvp = *view_proj * layout.organs[o].transform.matrix();
        if !own.is_empty() {
            triangles += rasterise_organ(&mut raster, &organ.mesh, &organ.bvh, own, &mvp, w, h, 0.0);
        }
        if let (Some(s), false) = (&organ.stand_in, stand_in.is_empty()) {
            // Pushed back a little: a stand-in on the surface must not hide the surface itself.
            triangles += rasterise_organ(&mut raster, &s.mesh, &s.bvh, stand_in, &mvp, w, h, STAND_IN_DEPTH_BIAS);
        }
    }
    let maps = raster.finish_on(phase);
    let opacity = OpacityMap::new(&maps.covered, w, h);
    let sparse = SparseDepth::new(&maps.depth, w, h);
    Occluders { maps, opacity, sparse, approximate: None, leaves: list.len(), triangles }
}

/// Triangle `t` of `mesh` in the pixels of a `w` x `h` image (x right, y down, z = NDC depth), if
/// it lies wholly beyond the near plane: the part of a triangle nearer than that is clipped when
/// drawn and hides nothing.
pub(crate) fn project_triangle(mesh: &crate::mesh::Mesh, t: u32, mvp: &Mat4, w: usize, h: usize) -> Option<[Vec3; 3]> {
    let corner = |k: usize| project_point(mesh.positions[mesh.indices[3 * t as usize + k] as usize], mvp, w, h);
    Some([corner(0)?, corner(1)?, corner(2)?])
}

/// A point in the pixels of a `w` x `h` image, as [`project_triangle`]: `None` before the near plane.
fn project_point(p: [f32; 3], mvp: &Mat4, w: usize, h: usize) -> Option<Vec3> {
    let (sx, sy) = (0.5 * w as f32, 0.5 * h as f32);
    let c = *mvp * Vec3::from(p).extend(1.0);
    (c.w > 1e-5 && c.z >= 0.0).then(|| Vec3::new((c.x / c.w + 1.0) * sx, (1.0 - c.y / c.w) * sy, c.z / c.w))
}

/// The vertices of some leaves of a mesh in pixels, as [`project_point`], each projected once:
/// those in the range of vertex numbers the leaves use (compact where the leaves lie together in
/// the hierarchy, vertices being numbered in leaf order). Where the range is wider than the
/// leaves have corners, none are kept, and each triangle's corners are projected as asked for.
struct ProjectedVertices {
    first: u32,
    points: Vec<Option<Vec3>>,
    mvp: Mat4,
    size: (usize, usize),
}

impl ProjectedVertices {
    fn of_leaves(mesh: &crate::mesh::Mesh, bvh: &Bvh, leaves: &[u32], mvp: &Mat4, w: usize, h: usize) -> Self {
        let (mut lo, mut hi, mut corners) = (u32::MAX, 0, 0);
        for &l in leaves {
            let range = bvh.leaf_range(l);
            corners += range.len();
            for &v in &mesh.indices[range.start as usize..range.end as usize] {
                (lo, hi) = (lo.min(v), hi.max(v));
            }
        }
        let points = if lo <= hi && ((hi - lo) as usize) < corners {
            (lo..=hi).map(|v| project_point(mesh.positions[v as usize], mvp, w, h)).collect()
        } else {
            Vec::new()
        };
        ProjectedVertices { first: lo, points, mvp: *mvp, size: (w, h) }
    }

    /// Triangle `t` of the leaves, as [`project_triangle`].
    fn triangle(&self, mesh: &crate::mesh::Mesh, t: u32) -> Option<[Vec3; 3]> {
        if self.points.is_empty() {
            return project_triangle(mesh, t, &self.mvp, self.size.0, self.size.1);
        }
        let corner = |k: usize| self.points[(mesh.indices[3 * t as usize + k] - self.first) as usize];
        Some([corner(0)?, corner(1)?, corner(2)?])
    }
}

/// NDC depth added to occluder stand-ins' triangles, far above float rounding (about 1e-7).
const STAND_IN_DEPTH_BIAS: f32 = 1e-5;

/// Adds the camera-facing triangles of the chosen leaves of one organ to the raster, each with
/// its neighbours among them, pushed back by `bias` in NDC depth; returns how many.
#[allow(clippy::too_many_arguments)]
fn rasterise_organ(
    raster: &mut OccluderRaster,
    mesh: &crate::mesh::Mesh,
    bvh: &Bvh,
    leaves: &[u32],
    mvp: &Mat4,
    w: usize,
    h: usize,
    bias: f32,
) -> usize {
    // Per chosen leaf, `start - first`: triangle t of the leaf sits at `offset[leaf] + t` in `slot`
    // (wrapping arithmetic; `None` for leaves not chosen). `slot` holds each chosen triangle's index
    // among the occluder triangles, or NONE where it faces away or reaches before the near plane.
    let mut offset: Vec<Option<u32>> = vec![None; bvh.leaves.len()];
    let chosen = leaves.iter().map(|&l| bvh.leaf_range(l).len() / 3).sum();
    let mut slot: Vec<u32> = Vec::with_capacity(chosen);
    let (mut triangles, mut ids) = (Vec::with_capacity(chosen), Vec::with_capacity(chosen));
    let projected = ProjectedVertices::of_leaves(mesh, bvh, leaves, mvp, w, h);
    for &l in leaves {
        let node = &bvh.nodes[bvh.leaves[l as usize] as usize];
        offset[l as usize] = Some((slot.len() as u32).wrapping_sub(node.first));
        for t in node.first..node.first + node.count {
            let tri = projected.triangle(mesh, t).filter(|[a, b, c]| {
                // Counter-clockwise in NDC (y up) is clockwise here (y down): negative area.
                (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) < 0.0
            });
            match tri {
                Some(tri) => {
                    slot.push(triangles.len() as u32);
                    triangles.push(tri.map(|v| v + Vec3::new(0.0, 0.0, bias)));
                    ids.push(t);
                }
                None => slot.push(NONE),
            }
        }
    }
    let index = |t: u32| -> u32 {
        let leaf = bvh.leaf_of.get(t as usize).and_then(|&l| offset.get(l as usize)).copied().flatten();
        leaf.map_or(NONE, |o| slot[o.wrapping_add(t) as usize])
    };
    let neighbours: Vec<[u32; 3]> = ids.iter().map(|&t| bvh.neighbours[t as usize].map(index)).collect();
    raster.add(&triangles, &neighbours);
    triangles.len()
}

/// Culls the drawn organs of `layout` for `camera` at `aspect`; returns the draw list and counts.
/// A frame on its own: a viewer culling frame after frame keeps a [`Culler`] instead.
pub fn cull(
    set: &OrganSet,
    layout: &Layout,
    camera: &Camera,
    aspect: f32,
    settings: &CullSettings,
) -> (DrawList, CullStats) {
    Culler::default().cull(set, layout, camera, aspect, settings)
}

/// The culler of a sequence of frames: it keeps, per organ, where the last frame's traversal
/// stopped and starts the next one there ([`cut`]), and a vertex of each visible part that was
/// seen, to look up first ([`witness`]). What it culls does not depend on what it kept; only how
/// many tests that takes. It may be used with any set: what it kept for an organ whose hierarchy
/// it does not fit is dropped.
#[derive(Clone, Debug, Default)]
pub struct Culler {
    cuts: Vec<Cut>,
    witnesses: Vec<Witnesses>,
}

impl Culler {
    /// Culls one frame, as [`cull`].
    pub fn cull(
        &mut self,
        set: &OrganSet,
        layout: &Layout,
        camera: &Camera,
        aspect: f32,
        settings: &CullSettings,
    ) -> (DrawList, CullStats) {
        self.cull_with(set, layout, camera, aspect, settings, None)
    }

    /// Culls one frame with the occluders given (`Some`, in place of the settings' selection):
    /// for the occluder-selection experiments.
    pub fn cull_with(
        &mut self,
        set: &OrganSet,
        layout: &Layout,
        camera: &Camera,
        aspect: f32,
        settings: &CullSettings,
        given: Option<&[LeafRef]>,
    ) -> (DrawList, CullStats) {
        let started = std::time::Instant::now();
        let settings = CullSettings { width: settings.width.max(1), height: settings.height.max(1), ..*settings };
        self.cuts.resize_with(set.organs.len(), Cut::default);
        self.witnesses.resize_with(set.organs.len(), Witnesses::default);
        for (w, organ) in self.witnesses.iter_mut().zip(&set.organs) {
            w.fit(organ.bvh.parts.len());
        }
        let kept = (&mut self.cuts[..], &self.witnesses[..]);
        let phases = Phases::default();
        // The pool's threads help where occlusion is tested (without it, the work is too small to
        // pay for waking them).
        let (list, mut stats) = match settings.mode {
            CullMode::Occlusion => share::with_crew(
                |quit| {
                    phases.raster.help(quit);
                    phases.traversal.help(quit);
                },
                || cull_in_phases(set, layout, camera, aspect, &settings, given, kept, &phases),
            ),
            _ => cull_in_phases(set, layout, camera, aspect, &settings, given, kept, &phases),
        };
        stats.cull_ms = started.elapsed().as_secs_f64() * 1000.0;
        (list, stats)
    }
}

/// The culler's two parallel phases: the occluder raster's patches, and the subtrees below the
/// top levels of the hierarchies.
#[derive(Default)]
struct Phases<'a> {
    raster: Phase<raster::Patches>,
    traversal: Phase<Subtrees<'a>>,
}

/// [`Culler::cull_with`], its parallel work done in `phases` (`settings`' size at least 1 x 1),
/// starting each organ's traversal at its cut where occlusion is tested.
#[allow(clippy::too_many_arguments)]
fn cull_in_phases<'a>(
    set: &'a OrganSet,
    layout: &Layout,
    camera: &Camera,
    aspect: f32,
    settings: &CullSettings,
    given: Option<&[LeafRef]>,
    (cuts, witnesses): (&mut [Cut], &'a [Witnesses]),
    phases: &Phases<'a>,
) -> (DrawList, CullStats) {
    let view_proj = camera.view_projection(aspect);
    let (w, h) = (settings.width, settings.height);
    let mut stats = CullStats::default();
    let occ = (settings.mode == CullMode::Occlusion).then(|| {
        let list = match given {
            Some(list) => list.to_vec(),
            None => {
                let (list, source) = choose_occluders(set, layout, camera, &view_proj, settings);
                stats.source = Some(source);
                list
            }
        };
        let mut o = rasterise_occluders(set, layout, &view_proj, &list, w, h, &phases.raster);
        if settings.hole_tolerance.is_some() {
            let depth: Vec<f32> =
                o.maps.depth.iter().map(|&d| if d.is_finite() { d } else { f32::NEG_INFINITY }).collect();
            let sparse = SparseDepth::new(&depth, w, h);
            o.approximate = Some((depth, sparse));
        }
        o
    });
    if let Some(o) = &occ {
        (stats.occluder_leaves, stats.occluder_triangles) = (o.leaves, o.triangles);
    }
    let testing = occ.is_some();
    let views: Vec<Option<OrganView>> = set
        .organs
        .iter()
        .zip(&layout.organs)
        .zip(witnesses)
        .map(|((organ, state), witnesses)| {
            let drawn = state.is_drawn() && !organ.bvh.nodes.is_empty();
            drawn.then(|| OrganView::new(&view_proj, &state.transform.matrix(), camera.eye, witnesses))
        })
        .collect();
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
            let start = (node, testing, true);
            traverse_below(organ, view, occ.as_ref(), settings, start, &mut walks[o], Some(&mut split));
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
    stats.drawn = list.triangles();
    (list, stats)
}

/// Where a shared traversal starts: a node of an organ, whether occlusion is tested there, and
/// whether it is a start of the frame (of the organ's cut) or a subtree below one.
#[derive(Clone, Copy, Debug)]
struct Start {
    organ: usize,
    node: u32,
    test: bool,
    started: bool,
}

/// The traversals left to share, as tasks: single subtrees, or groups of small starts of one organ
/// up to [`SUBTREE_TRIANGLES`] in all. Each gives its organs' ranges, counts and reached nodes.
struct Subtrees<'a> {
    set: &'a OrganSet,
    views: Vec<Option<OrganView<'a>>>,
    occ: Option<Occluders>,
    settings: CullSettings,
    starts: Vec<Start>,
    /// (triangles, starts) per task.
    tasks: Vec<(u32, Range<usize>)>,
}

impl Subtrees<'_> {
    /// Adds a start of `count` triangles: to the last task where `group` and that task is a
    /// group of the same organ with room left, else as a task of its own.
    fn add(&mut self, start: Start, count: u32, group: bool) {
        let i = self.starts.len();
        let same_group = |(t, r): &&mut (u32, Range<usize>)| {
            group
                && r.end == i
                && self.starts[r.start].started
                && self.starts[r.start].organ == start.organ
                && t + count <= SUBTREE_TRIANGLES
        };
        match self.tasks.last_mut().filter(same_group) {
            Some((t, r)) => (*t, r.end) = (*t + count, i + 1),
            None => self.tasks.push((count, i..i + 1)),
        }
        self.starts.push(start);
    }
}

impl Tasks for Subtrees<'_> {
    /// Per organ of the tasks run, what they gave.
    type State = Vec<(usize, Walk)>;
    fn count(&self) -> usize {
        self.tasks.len()
    }
    fn state(&self) -> Self::State {
        Vec::new()
    }
    fn run(&self, done: &mut Self::State, i: usize) {
        for &Start { organ: o, node, test, started } in &self.starts[self.tasks[i].1.clone()] {
            let Some(view) = &self.views[o] else { continue };
            if done.last().is_none_or(|(last, _)| *last != o) {
                done.push((o, Walk::default()));
            }
            if let Some((_, walk)) = done.last_mut() {
                let organ = &self.set.organs[o];
                traverse_below(organ, view, self.occ.as_ref(), &self.settings, (node, test, started), walk, None);
            }
        }
    }
}

/// How one organ is seen: its model-view-projection matrix, that matrix's inverse and the eye in
/// organ space (for the boxes' depth bounds); and its parts' witnesses, from the last frames.
struct OrganView<'a> {
    mvp: Mat4,
    inverse: Unprojection,
    eye: Vec3,
    witnesses: &'a Witnesses,
}

impl<'a> OrganView<'a> {
    fn new(view_proj: &Mat4, model: &Mat4, eye: Vec3, witnesses: &'a Witnesses) -> OrganView<'a> {
        let mvp = *view_proj * *model;
        let eye = model.inverse().transform_point3(eye);
        OrganView { mvp, inverse: Unprojection::of(&mvp), eye, witnesses }
    }

    fn depth_bound(&self, b: &Bounds, slab: Option<&Slab>, nearest: f32, w: usize, h: usize) -> DepthBound {
        DepthBound::of_box(&self.inverse, self.eye, b, slab, nearest, w, h)
    }

    fn far_bound(&self, b: &Bounds, slab: &Slab, farthest: f32, w: usize, h: usize) -> FarBound {
        FarBound::of_box(&self.inverse, self.eye, b, slab, farthest, w, h)
    }
}

/// Triangles are "not much smaller than the pixels" of a rectangle when there are at most this
/// many per pixel of it. A failing leaf's parts are then tested, and a failing part's triangles
/// one by one; where they are much smaller (10M triangles), the boxes are about as tight and the
/// extra tests cost more than they cull.
const TRIANGLES_PER_PIXEL: usize = 4;

/// A failing part's triangles are tested in groups of this many, each by its footprint first.
const GROUP_TRIANGLES: usize = 8;

/// What the tests of a part whose box failed found.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Verdict {
    Hidden,
    /// Not hidden: vertex `i` of the part (its place among the part's vertices) is seen.
    Seen(usize),
    /// Not hidden, and no vertex is seen.
    Shown,
}

impl Verdict {
    /// The vertex to look up first in the next frame ([`witness`]).
    fn witness(self) -> Option<usize> {
        match self {
            Verdict::Seen(i) => Some(i),
            _ => None,
        }
    }
}

/// How far from a pixel's border (in pixels) a point must lie to be seen ([`Occluders::sees`]).
const SEEN_MARGIN: f32 = 1e-3;

/// How far in front of the occluder depth (and inside the near and far planes) a point must lie to
/// be seen ([`Occluders::sees`]), in NDC depth: ten times the depth bounds' own margin.
const SEEN_DEPTH_MARGIN: f32 = 1e-5;

/// How many of a failing part's vertices are looked up where they lie ([`Occluders::sees`]): one
/// seen ends its tests at once (most parts that fail are visible), and the lookups of a part that
/// turns out hidden are wasted.
const SEEN_VERTICES: usize = 4;

/// Subtrees of at most this many triangles are the tasks shared between the threads.
const SUBTREE_TRIANGLES: u32 = 1 << 13;

/// What traversals of one organ gave: the index ranges that survive culling (contiguous ones
/// merged), the culled and tested counts, and where occlusion is tested, the nodes where they
/// stopped ([`cut`]).
#[derive(Default)]
struct Walk {
    list: Vec<Range<u32>>,
    stats: CullStats,
    reached: Vec<Reached>,
    /// (node, whether occlusion is still tested below it) left to visit.
    stack: Vec<(u32, bool)>,
}

/// Traverses a drawn organ below a node, into `walk`. `(root, test, started)`: the node, whether
/// occlusion is still tested there, and whether it is a start of the frame (of the organ's cut).
/// With `split`, subtrees of at most [`SUBTREE_TRIANGLES`] are left out, listed there as (node,
/// `test` there).
fn traverse_below(
    organ: &crate::organ_set::Organ,
    view: &OrganView,
    occ: Option<&Occluders>,
    settings: &CullSettings,
    (root, test, started): (u32, bool, bool),
    walk: &mut Walk,
    mut split: Option<&mut Vec<(u32, bool)>>,
) {
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
        let seen = see(&view.mvp, &node.bounds, w, h);
        if seen == Seen::Outside {
            stats.frustum_culled += node.count as usize;
            stop(true);
            continue;
        }
        let mut test_children = test;
        // Whether a failing leaf's parts are worth testing: where its triangles are not much
        // smaller than pixels, or its box lies behind the occluders at its centre (not where it
        // reaches in front of them: the occluders' own surface, mostly).
        let mut parts = true;
        if let (Seen::Rect { x0, y0, x1, y1, z, far, .. }, Some(o), true) = (seen, occ, test) {
            stats.nodes_tested += 1;
            // Computed at most once: by the test, and again by a failing leaf's gate below.
            let cell = std::cell::OnceCell::new();
            let bound = || *cell.get_or_init(|| view.depth_bound(&node.bounds, Some(&node.slab), z, w, h));
            let (covered, hidden) = o.test([x0, y0, x1, y1], z, holes, bound);
            if hidden {
                stats.occlusion_culled += node.count as usize;
                stop(true);
                continue;
            }
            let area = (x1 - x0 + 1) * (y1 - y0 + 1);
            if node.is_leaf() {
                let (x, y) = ((x0 + x1) / 2, (y0 + y1) / 2);
                parts = node.count as usize <= TRIANGLES_PER_PIXEL * area || o.maps.depth[y * w + x] < bound().at(x, y);
            }
            // Adaptive stop: too little of it is covered for a descendant to be hidden; only
            // the frustum is tested below. Nor can one be where the whole box lies in front of the
            // occluders (a visible wall).
            test_children = covered as f32 >= settings.adaptive_ratio * area as f32
                && !view.far_bound(&node.bounds, &node.slab, far, w, h).in_front(&o.maps.depth, w, [x0, y0, x1, y1]);
        }
        let testing = test_children && occ.is_some();
        if !testing && matches!(seen, Seen::Rect { inside: true, .. }) {
            // Wholly inside the frustum with nothing more to test: all of it, in one range.
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
                    // Its witness seen again: the part is drawn (its tests could not pass).
                    let witness = view.witnesses.get(p).filter(|_| holes.is_none());
                    if witness.is_some_and(|i| o.vertex_seen(organ, part, i, &view.mvp)) {
                        all_culled = false;
                        push_merged(list, 3 * part.first..3 * (part.first + part.count));
                        continue;
                    }
                    let verdict = match see(&view.mvp, &part.bounds, w, h) {
                        Seen::Outside => {
                            stats.frustum_culled += part.count as usize;
                            view.witnesses.set(p, None);
                            continue;
                        }
                        Seen::Straddles => Verdict::Shown,
                        Seen::Rect { x0, y0, x1, y1, z, .. } => {
                            let rect = [x0, y0, x1, y1];
                            // Computed at most once: by the box's test, and again by its footprint's.
                            let cell = std::cell::OnceCell::new();
                            let bound =
                                || *cell.get_or_init(|| view.depth_bound(&part.bounds, Some(&part.slab), z, w, h));
                            let area = (x1 - x0 + 1) * (y1 - y0 + 1);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    #[test]
    fn vertices_projected_once_give_the_triangles_projected_corner_by_corner() {
        // An octahedron subdivided (12,800 triangles, over 50 leaves), seen from outside.
        let mut mesh = Mesh {
            positions: vec![[1., 0., 0.], [-1., 0., 0.], [0., 1., 0.], [0., -1., 0.], [0., 0., 1.], [0., 0., -1.]],
            normals: vec![],
            indices: vec![0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5],
        };
        mesh.compute_normals();
        let mut mesh = crate::organ_set::scale::subdivide(&mesh, 40);
        let bvh = Bvh::build(&mut mesh);
        assert!(bvh.leaves.len() >= 50);
        let camera = Camera {
            eye: Vec3::new(0.3, -3.0, 0.5),
            target: Vec3::ZERO,
            up: Vec3::Z,
            fov_y: 45.0,
            near: 0.1,
            far: 10.0,
        };
        let mvp = camera.view_projection(1.0);
        let last = bvh.leaves.len() as u32 - 1;
        // Neighbouring leaves (their vertices kept) and the first with the last (each corner projected).
        for (leaves, kept) in [(vec![0, 1], true), (vec![0, last], false), ((0..=last).collect(), true)] {
            let projected = ProjectedVertices::of_leaves(&mesh, &bvh, &leaves, &mvp, 128, 96);
            assert_eq!(projected.points.is_empty(), !kept, "leaves {leaves:?}");
            for &l in &leaves {
                for t in bvh.leaf_range(l).step_by(3).map(|i| i / 3) {
                    assert_eq!(projected.triangle(&mesh, t), project_triangle(&mesh, t, &mvp, 128, 96));
                }
            }
        }
    }

    /// Occluders of a `w` x `h` depth map: covered where the depth is finite.
    fn occluders_of(depth: Vec<f32>, w: usize, h: usize) -> Occluders {
        let covered: Vec<u8> = depth.iter().map(|d| u8::from(d.is_finite())).collect();
        Occluders {
            opacity: OpacityMap::new(&covered, w, h),
            sparse: SparseDepth::new(&depth, w, h),
            maps: OccluderMaps { width: w, height: h, covered, depth },
            approximate: None,
            leaves: 0,
            triangles: 0,
        }
    }

    #[test]
    fn a_point_is_seen_where_uncovered_or_in_front() {
        // A 4 x 2 raster: pixel (1, 0) covered at depth 0.5, the rest uncovered.
        let (w, h) = (4, 2);
        let mut depth = vec![f32::INFINITY; w * h];
        depth[1] = 0.5;
        let occ = occluders_of(depth, w, h);
        assert!(occ.sees(Vec3::new(1.5, 0.5, 0.4)), "in front of the occluder");
        assert!(!occ.sees(Vec3::new(1.5, 0.5, 0.5)), "at its depth");
        assert!(!occ.sees(Vec3::new(1.5, 0.5, 0.5 - SEEN_DEPTH_MARGIN / 2.0)), "within the margin");
        assert!(!occ.sees(Vec3::new(1.5, 0.5, 0.6)), "behind it");
        assert!(occ.sees(Vec3::new(2.5, 1.5, 0.9)), "uncovered");
        assert!(occ.sees(Vec3::new(2.01, 1.99, 0.9)), "uncovered, clear of the border");
        // On or near a pixel's border, off the raster, or outside the near and far planes, nothing
        // is said.
        assert!(!occ.sees(Vec3::new(2.0, 0.5, 0.1)));
        assert!(!occ.sees(Vec3::new(2.0 + SEEN_MARGIN / 2.0, 0.5, 0.1)));
        assert!(!occ.sees(Vec3::new(0.5, 1.0 - SEEN_MARGIN / 2.0, 0.1)));
        assert!(!occ.sees(Vec3::new(-0.5, 0.5, 0.1)));
        assert!(!occ.sees(Vec3::new(4.5, 0.5, 0.1)));
        assert!(!occ.sees(Vec3::new(2.5, 1.5, 1.0)));
        assert!(!occ.sees(Vec3::new(2.5, 1.5, 0.0)));
    }

    #[test]
    fn a_part_is_seen_through_its_witness_only_where_its_tests_fail() {
        // A cube of 12 triangles (one part) under an occluder covering the whole raster at `wall`
        // depth, seen from a camera on its axis: its witness is seen exactly when the part is shown.
        let mut mesh = Mesh {
            positions: (0..8).map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]).collect(),
            normals: vec![],
            indices: vec![
                0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3,
                7, 5,
            ],
        };
        mesh.compute_normals();
        let organ = crate::organ_set::Organ::new("cube".into(), "Cube".into(), [1.0; 3], mesh);
        let camera = Camera {
            eye: Vec3::new(0.5, 0.5, 4.0),
            target: Vec3::splat(0.5),
            up: Vec3::Y,
            fov_y: 45.0,
            near: 1.0,
            far: 10.0,
        };
        let witnesses = Witnesses::default();
        let view = OrganView::new(&camera.view_projection(1.0), &Mat4::IDENTITY, camera.eye, &witnesses);
        let mvp = view.mvp;
        let (w, h) = (16, 16);
        let part = &organ.bvh.parts[0];
        let near =
            organ.mesh.positions.iter().filter_map(|&p| project_point(p, &mvp, w, h)).map(|p| p.z).fold(1.0, f32::min);
        for (wall, hidden) in [(near - 0.01, true), (1.0 - 1e-4, false)] {
            let occ = occluders_of(vec![wall; w * h], w, h);
            let Seen::Rect { z, .. } = see(&mvp, &part.bounds, w, h) else { panic!("the cube is in view") };
            let bound = || view.depth_bound(&part.bounds, Some(&part.slab), z, w, h);
            let verdict = occ.part_hidden(&organ, part, &mvp, None, bound);
            let seen: Vec<usize> = (0..8).filter(|&i| occ.vertex_seen(&organ, part, i, &mvp)).collect();
            match hidden {
                true => assert!(verdict == Verdict::Hidden && seen.is_empty(), "{verdict:?}, {seen:?}"),
                false => match verdict {
                    Verdict::Seen(i) => assert!(seen.contains(&i), "witness {i}, seen {seen:?}"),
                    _ => panic!("a part in front of the wall is {verdict:?}"),
                },
            }
        }
    }
}
