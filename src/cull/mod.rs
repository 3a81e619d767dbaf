//! Occlusion culling (thesis chapter 3), per frame on the CPU. Spaces: node bounds in organ space,
//! moved by each organ's model matrix into world space, projected by the camera into clip space and
//! then into culling pixels (a low-resolution grid over the viewport, x right, y down; depth = NDC z,
//! larger is farther).
//!
//! 1. View-frustum culling of each drawn organ's hierarchy ([`crate::bvh`]).
//! 2. Occluders: opaque, visible organs by projected size, largest first; of each, its leaves in
//!    the frustum nearest first, up to a triangle budget (no pre-processing, so organs may move);
//!    or, for an unchanged layout, the pre-computed minimum occluder sets ([`selection`],
//!    [`crate::mos`]).
//! 3. [`raster`]: their front triangles rasterised conservatively into coverage and depth.
//! 4. [`opacity_map`] (summed-area table) for the overlap test in four look-ups, and
//!    [`sparse_depth`] for the depth comparison over peaks only.
//! 5. Hierarchical traversal: a node is culled when its outward-rounded rectangle is wholly covered
//!    and its nearest depth is behind every occluder depth there; below a node whose coverage ratio
//!    is under the adaptive threshold, descendants are tested against the frustum only.
//!
//! The result is a [`DrawList`]: per organ, the index ranges to draw.

pub mod opacity_map;
pub mod raster;
pub mod selection;
pub mod sparse_depth;

pub use selection::{by_projected_size, choose_occluders, LeafRef, OccluderSource, Selection};

use crate::bvh::{Bvh, NONE};
use crate::camera::Camera;
use crate::layout::Layout;
use crate::mesh::Bounds;
use crate::organ_set::OrganSet;
use glam::{Mat4, Vec3, Vec4};
use opacity_map::OpacityMap;
use raster::{OccluderMaps, OccluderRaster};
use sparse_depth::SparseDepth;
use std::ops::Range;

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
    /// Most occluder triangles rasterised per frame.
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
            occluder_triangles: 16_384,
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
        let list = &mut self.ranges[organ];
        match list.last_mut() {
            Some(last) if last.end == r.start => last.end = r.end,
            _ => list.push(r),
        }
    }

    pub fn triangles(&self) -> usize {
        self.ranges.iter().flatten().map(|r| (r.end - r.start) as usize / 3).sum()
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
    pub occluder_triangles: usize,
    /// Where the occluders came from (`None` without occlusion culling or with occluders given).
    pub source: Option<OccluderSource>,
    pub cull_ms: f64,
}

impl CullStats {
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
    /// Inclusive pixel rectangle (rounded outward, clamped) and nearest NDC depth.
    Rect { x0: usize, y0: usize, x1: usize, y1: usize, z: f32 },
}

pub(crate) fn see(mvp: &Mat4, b: &Bounds, w: usize, h: usize) -> Seen {
    let mut out = [true; 6];
    let mut behind = false;
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for c in b.corners() {
        let p: Vec4 = *mvp * c.extend(1.0);
        let tests = [p.x < -p.w, p.x > p.w, p.y < -p.w, p.y > p.w, p.z < 0.0, p.z > p.w];
        for k in 0..6 {
            out[k] &= tests[k];
        }
        if p.w <= 1e-5 {
            behind = true;
            continue;
        }
        let ndc = p.truncate() / p.w;
        lo = lo.min(ndc);
        hi = hi.max(ndc);
    }
    if out.iter().any(|&o| o) {
        return Seen::Outside;
    }
    if behind || !lo.is_finite() || !hi.is_finite() {
        return Seen::Straddles;
    }
    let (wf, hf) = (w as f32, h as f32);
    let (px0, px1) = ((lo.x + 1.0) * 0.5 * wf, (hi.x + 1.0) * 0.5 * wf);
    let (py0, py1) = ((1.0 - hi.y) * 0.5 * hf, (1.0 - lo.y) * 0.5 * hf);
    let clamp = |v: f32, n: f32| v.clamp(0.0, n - 1.0) as usize;
    Seen::Rect {
        x0: clamp(px0.floor(), wf),
        x1: clamp(px1.ceil() - 1.0, wf),
        y0: clamp(py0.floor(), hf),
        y1: clamp(py1.ceil() - 1.0, hf),
        z: lo.z,
    }
}

/// The occluder maps and look-up structures of one frame.
pub struct Occluders {
    pub maps: OccluderMaps,
    pub opacity: OpacityMap,
    pub sparse: SparseDepth,
    pub leaves: usize,
    pub triangles: usize,
}

/// Rasterises the given occluder leaves (organ by organ, so leaves of one organ fuse into
/// patches) and builds the look-up structures.
pub fn rasterise_occluders(
    set: &OrganSet,
    layout: &Layout,
    view_proj: &Mat4,
    list: &[LeafRef],
    w: usize,
    h: usize,
) -> Occluders {
    let mut chosen: Vec<Vec<u32>> = vec![Vec::new(); set.organs.len()];
    let mut triangles = 0;
    for r in list {
        let organ = &set.organs[r.organ as usize];
        chosen[r.organ as usize].push(r.leaf);
        triangles += organ.bvh.nodes[organ.bvh.leaves[r.leaf as usize] as usize].count as usize;
    }
    let mut raster = OccluderRaster::new(w, h);
    for (o, leaves) in chosen.iter().enumerate() {
        if !leaves.is_empty() {
            let mvp = *view_proj * layout.organs[o].transform.matrix();
            rasterise_organ(&mut raster, &set.organs[o].mesh, &set.organs[o].bvh, leaves, &mvp, w, h);
        }
    }
    let maps = raster.finish();
    let opacity = OpacityMap::new(&maps.covered, w, h);
    let sparse = SparseDepth::new(&maps.depth, w, h);
    Occluders { maps, opacity, sparse, leaves: list.len(), triangles }
}

/// Triangle `t` of `mesh` in the pixels of a `w` x `h` image (x right, y down, z = NDC depth), if
/// it lies wholly beyond the near plane: the part of a triangle nearer than that is clipped when
/// drawn and hides nothing.
pub(crate) fn project_triangle(mesh: &crate::mesh::Mesh, t: u32, mvp: &Mat4, w: usize, h: usize) -> Option<[Vec3; 3]> {
    let (sx, sy) = (0.5 * w as f32, 0.5 * h as f32);
    let corner = |k: usize| {
        let p = Vec3::from(mesh.positions[mesh.indices[3 * t as usize + k] as usize]);
        let c = *mvp * p.extend(1.0);
        (c.w > 1e-5 && c.z >= 0.0).then(|| Vec3::new((c.x / c.w + 1.0) * sx, (1.0 - c.y / c.w) * sy, c.z / c.w))
    };
    Some([corner(0)?, corner(1)?, corner(2)?])
}

/// Rasterises the positively wound triangles of the chosen leaves of one organ, with the outline of
/// that set (edges whose neighbour is not in it).
fn rasterise_organ(
    raster: &mut OccluderRaster,
    mesh: &crate::mesh::Mesh,
    bvh: &Bvh,
    leaves: &[u32],
    mvp: &Mat4,
    w: usize,
    h: usize,
) {
    // Per chosen leaf, `start - first`: triangle t of the leaf sits at `offset[leaf] + t` in
    // `projected` (wrapping arithmetic; `None` for leaves not chosen).
    let mut offset: Vec<Option<u32>> = vec![None; bvh.leaves.len()];
    let mut projected: Vec<Option<[Vec3; 3]>> = Vec::new();
    for &l in leaves {
        let node = &bvh.nodes[bvh.leaves[l as usize] as usize];
        offset[l as usize] = Some((projected.len() as u32).wrapping_sub(node.first));
        for t in node.first..node.first + node.count {
            let tri = project_triangle(mesh, t, mvp, w, h).filter(|[a, b, c]| {
                // Counter-clockwise in NDC (y up) is clockwise here (y down): negative area.
                (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y) < 0.0
            });
            projected.push(tri);
        }
    }
    // Index into `projected` of a triangle, if it is in S (chosen leaf, positive winding).
    let index = |t: u32| -> Option<usize> {
        let i = offset.get(*bvh.leaf_of.get(t as usize)? as usize).copied().flatten()?.wrapping_add(t) as usize;
        projected[i].is_some().then_some(i)
    };
    // Patches: connected components of S across shared edges (union-find over `projected`).
    let mut parent: Vec<u32> = (0..projected.len() as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    let mut triangles_of = Vec::with_capacity(projected.len());
    for &l in leaves {
        let node = &bvh.nodes[bvh.leaves[l as usize] as usize];
        for t in node.first..node.first + node.count {
            if let Some(i) = index(t) {
                triangles_of.push((t, i));
                for &n in &bvh.neighbours[t as usize] {
                    if let Some(j) = index(n) {
                        let (a, b) = (root(&mut parent, i as u32), root(&mut parent, j as u32));
                        parent[a as usize] = b;
                    }
                }
            }
        }
    }
    // Each component's triangles and outline edges (edges whose neighbour is not in S).
    let mut label = vec![NONE; projected.len()];
    let mut patches: Vec<(Vec<raster::Triangle>, Vec<[Vec3; 2]>)> = Vec::new();
    for &(t, i) in &triangles_of {
        let Some(tri) = projected[i] else { continue };
        let r = root(&mut parent, i as u32) as usize;
        if label[r] == NONE {
            label[r] = patches.len() as u32;
            patches.push(Default::default());
        }
        let (tris, outline) = &mut patches[label[r] as usize];
        tris.push(tri);
        for k in 0..3 {
            if index(bvh.neighbours[t as usize][k]).is_none() {
                outline.push([tri[k], tri[(k + 1) % 3]]);
            }
        }
    }
    for (tris, outline) in &patches {
        raster.patch(tris, outline);
    }
}

/// Culls the drawn organs of `layout` for `camera` at `aspect`; returns the draw list and counts.
pub fn cull(
    set: &OrganSet,
    layout: &Layout,
    camera: &Camera,
    aspect: f32,
    settings: &CullSettings,
) -> (DrawList, CullStats) {
    cull_with(set, layout, camera, aspect, settings, None)
}

/// [`cull`] with the occluders given (`Some`, in place of the settings' selection): for the
/// occluder-selection experiments.
pub fn cull_with(
    set: &OrganSet,
    layout: &Layout,
    camera: &Camera,
    aspect: f32,
    settings: &CullSettings,
    given: Option<&[LeafRef]>,
) -> (DrawList, CullStats) {
    let started = std::time::Instant::now();
    let view_proj = camera.view_projection(aspect);
    let (w, h) = (settings.width.max(1), settings.height.max(1));
    let settings = CullSettings { width: w, height: h, ..*settings };
    let mut stats = CullStats::default();
    let occ = (settings.mode == CullMode::Occlusion).then(|| {
        let list = match given {
            Some(list) => list.to_vec(),
            None => {
                let (list, source) = choose_occluders(set, layout, camera, &view_proj, &settings);
                stats.source = Some(source);
                list
            }
        };
        rasterise_occluders(set, layout, &view_proj, &list, w, h)
    });
    let mut list = DrawList { ranges: vec![Vec::new(); set.organs.len()] };
    if let Some(o) = &occ {
        (stats.occluder_leaves, stats.occluder_triangles) = (o.leaves, o.triangles);
    }
    for (i, (organ, state)) in set.organs.iter().zip(&layout.organs).enumerate() {
        if !state.is_drawn() || organ.bvh.nodes.is_empty() {
            continue;
        }
        stats.triangles += organ.mesh.triangle_count();
        if settings.mode == CullMode::None {
            list.push(i, 0..organ.mesh.indices.len() as u32);
            continue;
        }
        let mvp = view_proj * state.transform.matrix();
        // (node, whether occlusion is still tested below it).
        let mut stack = vec![(0u32, occ.is_some())];
        while let Some((n, test)) = stack.pop() {
            let node = &organ.bvh.nodes[n as usize];
            let range = 3 * node.first..3 * (node.first + node.count);
            let seen = see(&mvp, &node.bounds, w, h);
            if seen == Seen::Outside {
                stats.frustum_culled += node.count as usize;
                continue;
            }
            let mut test_children = test;
            if let (Seen::Rect { x0, y0, x1, y1, z }, Some(o), true) = (seen, &occ, test) {
                stats.nodes_tested += 1;
                let area = ((x1 - x0 + 1) * (y1 - y0 + 1)) as u32;
                let covered = o.opacity.covered(x0, y0, x1, y1);
                let holes = settings.hole_tolerance.map_or(0, |t| (t.clamp(0.0, 1.0) * area as f32) as u32);
                if covered + holes >= area && o.sparse.all_in_front_of(&o.maps.depth, x0, y0, x1, y1, z) {
                    stats.occlusion_culled += node.count as usize;
                    continue;
                }
                // Adaptive stop: too little of it is covered for a descendant to be hidden; only
                // the frustum is tested below.
                test_children = (covered as f32) >= settings.adaptive_ratio * area as f32;
            }
            if node.is_leaf() {
                list.push(i, range);
            } else {
                stack.push((node.children[1], test_children));
                stack.push((node.children[0], test_children));
            }
        }
    }
    stats.drawn = list.triangles();
    stats.cull_ms = started.elapsed().as_secs_f64() * 1000.0;
    (list, stats)
}
