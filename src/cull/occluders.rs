//! One frame's occluders (thesis §3.3-3.4): the chosen leaves rasterised into coverage and depth
//! ([`super::raster`]), the opacity map and sparse depth map over them, and the tests of boxes,
//! footprints, triangles and points against them.
//!
//! - Culling pixels (x right, y down); NDC depth (larger is farther).
//! - A frame's occluder triangles are found source by source (each solid's stand-in, each organ's
//!   chosen leaves) on the culler's threads and joined in source order, so the raster is the same
//!   however the sources were shared.
//! - Rectangles are inclusive.

use super::depth_bound::DepthBound;
use super::opacity_map::OpacityMap;
use super::project::{first_pixel, last_pixel, project_point, ProjectedVertices};
use super::raster::{OccluderMaps, OccluderRaster, Patches};
use super::records::OrganRecord;
use super::rect::PixelRect;
use super::selection::LeafRef;
use super::share::{Phase, Tasks};
use super::sparse_depth::SparseDepth;
use crate::bvh::{Bvh, Part, NONE, PART_TRIANGLES};
use crate::clip::ModelPlane;
use crate::layout::Layout;
use crate::mesh::Mesh;
use crate::organ_set::{Organ, OrganSet, Solid};
use glam::{Mat4, Vec3, Vec3A};

/// A failing part's triangles are tested in groups of this many, each by its footprint first.
const GROUP_TRIANGLES: usize = 8;

/// What the tests of a part whose box failed found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Verdict {
    Hidden,
    /// Not hidden: vertex `i` of the part (its place among the part's vertices) is visible, its
    /// witness for the next frame.
    Witnessed(usize),
    /// Not hidden, and no vertex is seen.
    Shown,
}

impl Verdict {
    /// The vertex to look up first in the next frame ([`witness`]).
    pub(super) fn witness(self) -> Option<usize> {
        match self {
            Verdict::Witnessed(i) => Some(i),
            _ => None,
        }
    }
}

/// How far from a pixel's border (in pixels) a point must lie to be seen ([`Occluders::shows`]).
const VISIBLE_MARGIN: f32 = 1e-3;

/// How far in front of the occluder depth (and inside the near and far planes) a point must lie to
/// be seen ([`Occluders::shows`]), in NDC depth: ten times the depth bounds' own margin.
const VISIBLE_DEPTH_MARGIN: f32 = 1e-5;

/// How many of a failing part's vertices are looked up where they lie ([`Occluders::shows`]): one
/// seen ends its tests at once (most parts that fail are visible), and the lookups of a part that
/// turns out hidden are wasted.
const LOOKED_UP_VERTICES: usize = 4;

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
    pub(super) fn test(
        &self,
        rect: PixelRect,
        z: f32,
        holes: Option<f32>,
        bound: impl FnOnce() -> DepthBound,
    ) -> (u32, bool) {
        let area = rect.area() as u32;
        let covered = self.opacity.covered(rect);
        let (overlapped, depth, sparse) = match (holes, &self.approximate) {
            (Some(t), Some((depth, sparse))) => {
                (covered + (t.clamp(0.0, 1.0) * area as f32) as u32 >= area, depth, sparse)
            }
            _ => (covered >= area, &self.maps.depth, &self.sparse),
        };
        let hidden =
            overlapped && (sparse.all_in_front_of(depth, rect, z) || bound().behind(depth, self.maps.width, rect));
        (covered, hidden)
    }

    /// Whether a part of `organ` whose box failed is hidden all the same (tested as above): by its
    /// footprint, the rectangle of its projected vertices with their nearest depth and the box's
    /// depth bound `bound`; or else group by group of [`GROUP_TRIANGLES`] consecutive triangles
    /// (lying together: a part is split like the hierarchy) by the group's footprint, and where
    /// that fails by each of its triangles on its own, with its own rectangle and depth plane. A
    /// part reaching before the near plane is not, nor one of whose first [`LOOKED_UP_VERTICES`]
    /// vertices is seen ([`Occluders::shows`]: none of these tests could then pass). Its vertices
    /// are projected once. A part not hidden is [`Verdict::Witnessed`] where one of its vertices is
    /// seen (looked for among the rest only once its tests failed).
    pub(super) fn part_hidden(
        &self,
        organ: &Organ,
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
            if i < LOOKED_UP_VERTICES && holes.is_none() && self.shows(p) {
                return Verdict::Witnessed(i);
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
            false => (LOOKED_UP_VERTICES..vertices.len())
                .find(|&i| self.shows(Vec3::from(projected[i])))
                .map_or(Verdict::Shown, Verdict::Witnessed),
        }
    }

    /// Is vertex `place` of `part` seen ([`Occluders::shows`])? Then the part is not hidden.
    pub(super) fn shows_vertex(&self, organ: &Organ, part: &Part, place: usize, mvp: &Mat4) -> bool {
        let (w, h) = (self.maps.width, self.maps.height);
        let v = organ.bvh.vertices_of(part).get(place);
        v.and_then(|&v| project_point(organ.mesh.positions[v as usize], mvp, w, h)).is_some_and(|p| self.shows(p))
    }

    /// Whether point `p` (in pixels, with its NDC depth) is seen where it lies: in a pixel that no
    /// occluder covers, or in front of the occluder depth there, and inside the frustum, each by a
    /// margin ([`VISIBLE_MARGIN`] pixels from the pixel's border, [`VISIBLE_DEPTH_MARGIN`] in depth) far
    /// above the rounding by which a box's or a triangle's projection may miss a point it holds.
    /// Then no triangle through it, nor box holding it, is outside the frustum or behind the
    /// occluders over that pixel: its least depth there is at most `p`'s.
    pub(super) fn shows(&self, p: Vec3) -> bool {
        // Truncation is the floor for the positive values it is used on.
        let (x, y) = (p.x as usize, p.y as usize);
        let clear = |v: f32, floor: usize| (VISIBLE_MARGIN..1.0 - VISIBLE_MARGIN).contains(&(v - floor as f32));
        p.x > 0.0
            && p.y > 0.0
            && x < self.maps.width
            && y < self.maps.height
            && clear(p.x, x)
            && clear(p.y, y)
            && (VISIBLE_DEPTH_MARGIN..1.0 - VISIBLE_DEPTH_MARGIN).contains(&p.z)
            && p.z + VISIBLE_DEPTH_MARGIN < self.maps.depth[y * self.maps.width + x]
    }

    /// The pixel rectangle (rounded outward, clamped) of the screen box `lo..hi` in pixels, or
    /// `None` where it lies off the screen.
    fn rect(&self, lo: Vec3, hi: Vec3) -> Option<PixelRect> {
        let (wf, hf) = (self.maps.width as f32, self.maps.height as f32);
        (hi.x > 0.0 && hi.y > 0.0 && lo.x < wf && lo.y < hf).then(|| {
            let (x0, y0) = (first_pixel(lo.x, wf), first_pixel(lo.y, hf));
            // A box flat in screen space still covers the pixel its span lies in.
            PixelRect { x0, y0, x1: last_pixel(hi.x, wf).max(x0), y1: last_pixel(hi.y, hf).max(y0) }
        })
    }
}

/// Where occluder triangles come from: a solid's stand-in (all its leaves), or one organ's chosen
/// leaves of its own hierarchy or of its stand-in's.
#[derive(Clone, Copy, Debug)]
enum Source {
    Solid(usize),
    Own(usize),
    StandIn(usize),
}

/// One frame's occluder sources as tasks to share: each projects its triangles and links them
/// to their neighbours on its own ([`OccluderRaster`]s of their own), claimed biggest first and
/// added to the frame's raster in their order, so the raster is the same however they are shared.
pub(crate) struct Sources<'a> {
    set: &'a OrganSet,
    layout: &'a Layout,
    view_proj: Mat4,
    records: Vec<OrganRecord>,
    /// Per organ, the chosen leaves of its own hierarchy and of its stand-in's.
    chosen: Vec<[Vec<u32>; 2]>,
    size: (usize, usize),
    sources: Vec<Source>,
    /// Indices into `sources`, the most triangles first.
    order: Vec<usize>,
}

impl Tasks for Sources<'_> {
    type State = Vec<(usize, OccluderRaster)>;
    fn count(&self) -> usize {
        self.order.len()
    }
    fn state(&self) -> Self::State {
        Vec::new()
    }
    fn run(&self, done: &mut Self::State, i: usize) {
        let at = self.order[i];
        done.push((at, self.triangles(self.sources[at])));
    }
}

impl Sources<'_> {
    /// The triangles of one source. An organ the planes cut (its record's `cut`) gives only its
    /// own triangles, cut at the planes; a solid one of whose organs they cut gives its stand-in
    /// cut there.
    fn triangles(&self, source: Source) -> OccluderRaster {
        let (set, layout, (w, h)) = (self.set, self.layout, self.size);
        let mut raster = OccluderRaster::new(w, h);
        let organ = |o: usize| (&set.organs[o], self.view_proj * layout.organs[o].transform.matrix());
        let planes = |o: usize| self.records.get(o).map_or(&[][..], |r| r.planes.as_slice());
        match source {
            Source::Solid(s) => {
                add_stand_in(&mut raster, &set.solids[s], layout, &self.view_proj, &self.records);
            }
            Source::Own(o) => {
                let (organ, mvp) = organ(o);
                let leaves = (&organ.mesh, &organ.bvh, &self.chosen[o][0][..]);
                rasterise_organ(&mut raster, leaves, &mvp, (w, h), 0.0, planes(o), false);
                if self.records.get(o).is_some_and(|r| r.cut && r.clip.capped) {
                    // Its faces turned away, drawn as the cut face, hide what lies behind them too.
                    rasterise_organ(&mut raster, leaves, &mvp, (w, h), 0.0, planes(o), true);
                }
            }
            Source::StandIn(o) => {
                let (organ, mvp) = organ(o);
                if let Some(s) = &organ.stand_in {
                    // Pushed back a little: a stand-in on the surface must not hide the surface itself.
                    let leaves = (&s.mesh, &s.bvh, &self.chosen[o][1][..]);
                    rasterise_organ(&mut raster, leaves, &mvp, (w, h), STAND_IN_DEPTH_BIAS, &[], false);
                }
            }
        }
        raster
    }
}

/// Rasterises the stand-ins of `solids` (indices into the set's solids) and the given occluder
/// leaves (organ by organ, so leaves of one organ fuse into patches), and builds the look-up
/// structures: the triangles of each source found in the `sources` phase, rasterised in the
/// `raster` phase. An organ's stand-in leaves occlude only while no plane cuts the organ (the
/// caller chose a cut solid only where that hides what lies behind).
pub(super) fn rasterise_occluders<'a>(
    (set, layout): (&'a OrganSet, &'a Layout),
    view_proj: &Mat4,
    (solids, list): (&[usize], &[LeafRef]),
    records: &[OrganRecord],
    (w, h): (usize, usize),
    (sources_phase, raster_phase): (&Phase<Sources<'a>>, &Phase<Patches>),
) -> Occluders {
    let mut chosen: Vec<[Vec<u32>; 2]> = vec![Default::default(); set.organs.len()];
    for r in list {
        chosen[r.organ as usize][usize::from(r.stand_in)].push(r.leaf);
    }
    let solids: Vec<usize> = solids.iter().copied().filter(|&s| s < set.solids.len()).collect();
    let mut sources: Vec<Source> = solids.iter().map(|&s| Source::Solid(s)).collect();
    let no_planes = |o: usize| records.get(o).is_none_or(|r| r.planes.is_empty());
    for (o, [own, stand_in]) in chosen.iter().enumerate() {
        if !own.is_empty() {
            sources.push(Source::Own(o));
        }
        if set.organs[o].stand_in.is_some() && !stand_in.is_empty() && no_planes(o) {
            sources.push(Source::StandIn(o));
        }
    }
    // The biggest first: a solid's stand-in whole, else the chosen leaves' triangles.
    let size = |source: &Source| -> usize {
        let leaves = |bvh: &Bvh, ls: &[u32]| ls.iter().map(|&l| bvh.leaf_range(l).len()).sum();
        match *source {
            Source::Solid(s) => set.solids[s].stand_in.as_ref().map_or(0, |st| st.mesh.indices.len()),
            Source::Own(o) => leaves(&set.organs[o].bvh, &chosen[o][0]),
            Source::StandIn(o) => set.organs[o].stand_in.as_ref().map_or(0, |st| leaves(&st.bvh, &chosen[o][1])),
        }
    };
    let mut order: Vec<usize> = (0..sources.len()).collect();
    order.sort_by_key(|&i| std::cmp::Reverse(size(&sources[i])));
    let leaves = list.len()
        + solids.iter().map(|&s| set.solids[s].stand_in.as_ref().map_or(0, |st| st.bvh.leaves.len())).sum::<usize>();
    let job =
        Sources { set, layout, view_proj: *view_proj, records: records.to_vec(), chosen, size: (w, h), sources, order };
    let mut found: Vec<(usize, OccluderRaster)> = sources_phase.run(job).into_iter().flatten().collect();
    found.sort_unstable_by_key(|(at, _)| *at);
    let mut raster = OccluderRaster::new(w, h);
    for (_, r) in &found {
        raster.append(r);
    }
    let triangles = raster.len();
    Occluders::over(raster.finish_on(raster_phase), leaves, triangles)
}

impl Occluders {
    /// The look-up structures over `maps`, of `leaves` leaves and `triangles` triangles.
    fn over(maps: OccluderMaps, leaves: usize, triangles: usize) -> Occluders {
        let opacity = OpacityMap::new(&maps.covered, maps.width, maps.height);
        let sparse = SparseDepth::new(&maps.depth, maps.width, maps.height);
        Occluders { maps, opacity, sparse, approximate: None, leaves, triangles }
    }
}

/// Adds the faces facing the eye of `solid`'s stand-in (all its leaves) to the raster, cut where
/// `planes` (per organ, in its space) cut any of its organs.
fn add_stand_in(
    raster: &mut OccluderRaster,
    solid: &Solid,
    layout: &Layout,
    view_proj: &Mat4,
    records: &[OrganRecord],
) {
    let (Some(s), Some(&first)) = (&solid.stand_in, solid.organs.first()) else { return };
    let mvp = *view_proj * layout.organs[first].transform.matrix();
    let all: Vec<u32> = (0..s.bvh.leaves.len() as u32).collect();
    // Its organs move as one, so the planes cutting any of them are the same in its space.
    let planes = solid.organs.iter().find_map(|&o| records.get(o).map(|r| &r.planes).filter(|p| !p.is_empty()));
    let planes = planes.map_or(&[][..], Vec::as_slice);
    let size = (raster.width, raster.height);
    rasterise_organ(raster, (&s.mesh, &s.bvh, &all), &mvp, size, STAND_IN_DEPTH_BIAS, planes, false);
}

/// NDC depth added to occluder stand-ins' triangles, far above float rounding (about 1e-7).
const STAND_IN_DEPTH_BIAS: f32 = 1e-5;

/// How wide (NDC units, across its longest edge) a triangle must be seen to count as facing the
/// eye. The GPU decides facing on vertices snapped to a sub-pixel grid, where a sliver seen edge-on
/// may come out facing away: culled as a back face, it leaves a crack of samples that the culler
/// must not count as covered. 1e-4 is a twentieth of a pixel at 1920 pixels wide, far above the
/// snapping (a 256th of a pixel).
const FACING_MARGIN_NDC: f32 = 1e-4;

/// Adds the camera-facing triangles of the chosen leaves of one organ to the raster (with `away`,
/// those facing away instead, their corners reversed), each with its neighbours among them, pushed
/// back by `bias` in NDC depth. With clip planes in `keep` (organ space), a triangle they cut gives
/// the part they keep by [`crate::clip::SIDE_MARGIN_MM`], as a fan (the renderer cuts it at the
/// planes the same way), linked to its neighbours across the parts of its own edges it keeps
/// ([`Pieces`]). Returns how many.
fn rasterise_organ(
    raster: &mut OccluderRaster,
    (mesh, bvh, leaves): (&Mesh, &Bvh, &[u32]),
    mvp: &Mat4,
    (w, h): (usize, usize),
    bias: f32,
    keep: &[ModelPlane],
    away: bool,
) -> usize {
    let m = crate::clip::SIDE_MARGIN_MM;
    let corners = |t: u32| [0, 1, 2].map(|k| Vec3::from(mesh.positions[mesh.indices[3 * t as usize + k] as usize]));
    let margin = FACING_MARGIN_NDC * 0.5 * w.max(h) as f32;
    // Counter-clockwise in NDC (y up) is clockwise here (y down): negative area; wider than the
    // margin across its longest edge.
    let faces = |[a, b, c]: &[Vec3; 3]| {
        let twice_area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        let longest =
            (*b - *a).truncate().length().max((*c - *b).truncate().length()).max((*a - *c).truncate().length());
        let facing = if away { twice_area } else { -twice_area };
        facing > margin * longest
    };
    let oriented =
        |[a, b, c]: [Vec3; 3]| (if away { [a, c, b] } else { [a, b, c] }).map(|v| v + Vec3::new(0.0, 0.0, bias));
    // Corners reversed (a, c, b), edge k runs along the old edge 2 - k.
    let linked = |[n0, n1, n2]: [u32; 3]| if away { [n2, n1, n0] } else { [n0, n1, n2] };
    // Per chosen leaf, `start - first`: triangle t of the leaf sits at `offset[leaf] + t` in `slot`
    // (wrapping arithmetic; `None` for leaves not chosen). `slot` holds each chosen triangle's index
    // among the occluder triangles, or NONE where it is not one whole (it faces away, reaches
    // before the near plane, or the planes cut or remove it).
    let mut offset: Vec<Option<u32>> = vec![None; bvh.leaves.len()];
    let chosen = leaves.iter().map(|&l| bvh.leaf_range(l).len() / 3).sum();
    let mut slot: Vec<u32> = Vec::with_capacity(chosen);
    // Per occluder triangle, the mesh triangle it is, whole or a piece of it.
    let (mut triangles, mut ids) = (Vec::with_capacity(chosen), Vec::with_capacity(chosen));
    let mut pieces = Pieces::default();
    let projected = ProjectedVertices::of_leaves(mesh, bvh, leaves, mvp, w, h);
    for &l in leaves {
        let node = &bvh.nodes[bvh.leaves[l as usize] as usize];
        offset[l as usize] = Some((slot.len() as u32).wrapping_sub(node.first));
        for t in node.first..node.first + node.count {
            let side = crate::clip::triangle_side(corners(t), keep, m);
            let tri = projected.triangle(mesh, t).filter(|tri| side == crate::clip::Side::Kept && faces(tri));
            match tri {
                Some(tri) => {
                    slot.push(triangles.len() as u32);
                    triangles.push(oriented(tri));
                    ids.push(Id::Whole(t));
                }
                None => slot.push(NONE),
            }
            if side != crate::clip::Side::Cut {
                continue;
            }
            let polygon = crate::clip::clip_triangle(corners(t), keep, m);
            let points: Option<Vec<Vec3>> =
                polygon.iter().map(|p| super::project::project_point(p.to_array(), mvp, w, h)).collect();
            let Some(points) = points else { continue };
            // The fan from the first corner; a piece links to the pieces beside it that are kept.
            let fan: Vec<usize> = (1..points.len().saturating_sub(1))
                .filter(|&i| faces(&[points[0], points[i], points[i + 1]]))
                .collect();
            let first = triangles.len() as u32;
            for (n, &i) in fan.iter().enumerate() {
                let before = if n > 0 && fan[n - 1] == i - 1 { first + n as u32 - 1 } else { NONE };
                let after = if fan.get(n + 1) == Some(&(i + 1)) { first + n as u32 + 1 } else { NONE };
                triangles.push(oriented([points[0], points[i], points[i + 1]]));
                let model = [polygon[0], polygon[i], polygon[i + 1]];
                // Edges 0 and 2 are the polygon's own only at the fan's ends.
                let own = [i == 1, true, i + 2 == points.len()];
                ids.push(Id::Piece { t, fan: [before, after], model, own });
            }
            pieces.add(t, first..triangles.len() as u32);
        }
    }
    let index = |t: u32| -> u32 {
        let leaf = bvh.leaf_of.get(t as usize).and_then(|&l| offset.get(l as usize)).copied().flatten();
        leaf.map_or(NONE, |o| slot[o.wrapping_add(t) as usize])
    };
    let neighbours: Vec<[u32; 3]> = ids
        .iter()
        .map(|id| {
            linked(match *id {
                Id::Whole(t) => {
                    let (across, c) = (bvh.neighbours[t as usize], corners(t));
                    [0, 1, 2].map(|k| match index(across[k]) {
                        NONE => pieces.across(across[k], [c[k], c[(k + 1) % 3]], &ids, &corners),
                        j => j,
                    })
                }
                Id::Piece { t, fan: [before, after], model, own } => [0, 1, 2].map(|k| match (k, own[k]) {
                    (0, false) => before,
                    (2, false) => after,
                    _ => {
                        // A polygon edge: on the neighbour across one of the triangle's edges.
                        let edge = [model[k], model[(k + 1) % 3]];
                        let beside = |u: u32| match index(u) {
                            NONE => pieces.across(u, edge, &ids, &corners),
                            j if ids[j as usize].reverses(edge, &corners) => j,
                            _ => NONE,
                        };
                        bvh.neighbours[t as usize].into_iter().map(beside).find(|&j| j != NONE).unwrap_or(NONE)
                    }
                }),
            })
        })
        .collect();
    raster.add(&triangles, &neighbours);
    triangles.len()
}

/// What an occluder triangle of [`rasterise_organ`] is: mesh triangle `t` whole, or a piece of
/// the fan of what the planes keep of it, with the pieces beside it in the fan (edges 0 and 2,
/// NONE where none), its corners in organ space (in the mesh's winding) and which of its edges
/// lie on the kept polygon's boundary.
#[derive(Clone, Copy)]
enum Id {
    Whole(u32),
    Piece { t: u32, fan: [u32; 2], model: [Vec3; 3], own: [bool; 3] },
}

impl Id {
    /// Whether it has edge `[a, b]` (organ space) reversed: one of its mesh triangle's edges
    /// (given by `corners`) where whole, one on its polygon's boundary where a piece.
    fn reverses(&self, [a, b]: [Vec3; 2], corners: &impl Fn(u32) -> [Vec3; 3]) -> bool {
        let (c, own) = match *self {
            Id::Whole(t) => (corners(t), [true; 3]),
            Id::Piece { model, own, .. } => (model, own),
        };
        (0..3).any(|k| own[k] && c[k] == b && c[(k + 1) % 3] == a)
    }
}

/// The pieces of the mesh triangles the planes cut, by mesh triangle. Where the planes cut two
/// neighbours, what each keeps of their shared edge is the same segment to the bit (kept corners
/// are copied, and [`crate::clip::crossing`] computes a crossing from the lesser end), so a piece
/// links to the triangle or piece beside it that has its edge reversed, exactly; a whole
/// neighbour's edge is whole in the piece's polygon only where the planes keep both its corners.
#[derive(Default)]
struct Pieces {
    of: std::collections::HashMap<u32, std::ops::Range<u32>>,
}

impl Pieces {
    fn add(&mut self, t: u32, pieces: std::ops::Range<u32>) {
        if !pieces.is_empty() {
            self.of.insert(t, pieces);
        }
    }

    /// The piece of mesh triangle `u` with edge `edge` (organ space) reversed, or NONE.
    fn across(&self, u: u32, edge: [Vec3; 2], ids: &[Id], corners: &impl Fn(u32) -> [Vec3; 3]) -> u32 {
        let Some(range) = self.of.get(&u) else { return NONE };
        range.clone().find(|&j| ids[j as usize].reverses(edge, corners)).unwrap_or(NONE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Camera;
    use crate::cull::depth_bound::Unprojection;
    use crate::cull::project::{project_box, ScreenBox};
    use crate::mesh::Mesh;

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
        assert!(occ.shows(Vec3::new(1.5, 0.5, 0.4)), "in front of the occluder");
        assert!(!occ.shows(Vec3::new(1.5, 0.5, 0.5)), "at its depth");
        assert!(!occ.shows(Vec3::new(1.5, 0.5, 0.5 - VISIBLE_DEPTH_MARGIN / 2.0)), "within the margin");
        assert!(!occ.shows(Vec3::new(1.5, 0.5, 0.6)), "behind it");
        assert!(occ.shows(Vec3::new(2.5, 1.5, 0.9)), "uncovered");
        assert!(occ.shows(Vec3::new(2.01, 1.99, 0.9)), "uncovered, clear of the border");
        // On or near a pixel's border, off the raster, or outside the near and far planes, nothing
        // is said.
        assert!(!occ.shows(Vec3::new(2.0, 0.5, 0.1)));
        assert!(!occ.shows(Vec3::new(2.0 + VISIBLE_MARGIN / 2.0, 0.5, 0.1)));
        assert!(!occ.shows(Vec3::new(0.5, 1.0 - VISIBLE_MARGIN / 2.0, 0.1)));
        assert!(!occ.shows(Vec3::new(-0.5, 0.5, 0.1)));
        assert!(!occ.shows(Vec3::new(4.5, 0.5, 0.1)));
        assert!(!occ.shows(Vec3::new(2.5, 1.5, 1.0)));
        assert!(!occ.shows(Vec3::new(2.5, 1.5, 0.0)));
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
        let organ = Organ::new("cube".into(), "Cube".into(), [1.0; 3], mesh);
        let camera = Camera {
            eye: Vec3::new(0.5, 0.5, 4.0),
            target: Vec3::splat(0.5),
            up: Vec3::Y,
            fov_y: 45.0,
            near: 1.0,
            far: 10.0,
        };
        let mvp = camera.view_projection(1.0);
        let inverse = Unprojection::of(&mvp);
        let (w, h) = (16, 16);
        let part = &organ.bvh.parts[0];
        let near =
            organ.mesh.positions.iter().filter_map(|&p| project_point(p, &mvp, w, h)).map(|p| p.z).fold(1.0, f32::min);
        for (wall, hidden) in [(near - 0.01, true), (1.0 - 1e-4, false)] {
            let occ = occluders_of(vec![wall; w * h], w, h);
            let ScreenBox::Rect { z, .. } = project_box(&mvp, &part.bounds, w, h) else {
                panic!("the cube is in view")
            };
            let bound = || DepthBound::of_box(&inverse, camera.eye, &part.bounds, Some(&part.slab), z, w, h);
            let verdict = occ.part_hidden(&organ, part, &mvp, None, bound);
            let seen: Vec<usize> = (0..8).filter(|&i| occ.shows_vertex(&organ, part, i, &mvp)).collect();
            match hidden {
                true => assert!(verdict == Verdict::Hidden && seen.is_empty(), "{verdict:?}, {seen:?}"),
                false => match verdict {
                    Verdict::Witnessed(i) => assert!(seen.contains(&i), "witness {i}, seen {seen:?}"),
                    _ => panic!("a part in front of the wall is {verdict:?}"),
                },
            }
        }
    }

    #[test]
    fn a_surface_cut_by_a_plane_covers_across_the_triangles_it_cuts() {
        // An 8 x 8 grid of squares (two triangles each) on z = 0 from -1 to 1, seen head on; a
        // plane removes x > 0.1, cutting the column of triangles from 0 to 0.25.
        let n = 8u32;
        let at = |k: u32| -1.0 + 2.0 * k as f32 / n as f32;
        let positions = (0..=n).flat_map(|j| (0..=n).map(move |i| [at(i), at(j), 0.0])).collect();
        let v = |i: u32, j: u32| j * (n + 1) + i;
        let indices = (0..n * n)
            .flat_map(|c| {
                let (i, j) = (c % n, c / n);
                let (a, b, c, d) = (v(i, j), v(i + 1, j), v(i, j + 1), v(i + 1, j + 1));
                [a, b, d, a, d, c]
            })
            .collect();
        let mut mesh = Mesh { positions, normals: vec![], indices };
        mesh.compute_normals();
        let organ = Organ::new("grid".into(), "Grid".into(), [1.0; 3], mesh);
        let camera = Camera {
            eye: Vec3::new(0.0, 0.0, 3.0),
            target: Vec3::ZERO,
            up: Vec3::Y,
            fov_y: 45.0,
            near: 1.0,
            far: 10.0,
        };
        let (mvp, (w, h)) = (camera.view_projection(1.0), (64, 64));
        let leaves: Vec<u32> = (0..organ.bvh.leaves.len() as u32).collect();
        let mut raster = OccluderRaster::new(w, h);
        let keep = [(Vec3::X, 0.1)];
        rasterise_organ(&mut raster, (&organ.mesh, &organ.bvh, &leaves), &mvp, (w, h), 0.0, &keep, false);
        let maps = raster.finish_on(&Phase::default());
        // Every pixel wholly between the grid's left edge and the plane is covered, those on the
        // cut column's edge at x = 0 too: its pieces join the triangles beside them.
        let pixel = |x: f32, y: f32| project_point([x, y, 0.0], &mvp, w, h).unwrap_or_default();
        let (from, to) = (pixel(-1.0, 0.0).x.floor() as usize + 1, pixel(0.1, 0.0).x.ceil() as usize - 1);
        let y = pixel(0.0, 0.3).y.floor() as usize;
        let gaps: Vec<usize> = (from..to).filter(|&i| maps.covered[y * w + i] == 0).collect();
        assert!(to > from + 20 && gaps.is_empty(), "uncovered columns {gaps:?} of {from}..{to} in row {y}");
    }
}
