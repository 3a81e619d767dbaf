//! Occluder selection per frame (thesis §3.1-3.2): by projected size, or the pre-computed minimum
//! occluder sets of the nearest grid viewpoint.
//!
//! - Projected sizes in the culling raster's pixels (x right, y down); distances in world space.
//! - By projected size among opaque, visible organs: no pre-processing, so organs may move.
//! - The minimum occluder sets ([`crate::mos`]) only while the database serves the layout
//!   ([`Database::serves`]: nothing moved, organs faded since left out).

use super::database::Database;
use super::project::{project_box, wholly_ahead, ScreenBox};
use super::settings::{CullSettings, Selection};
use crate::camera::Camera;
use crate::layout::Layout;
use crate::organ_set::OrganSet;
use glam::Mat4;

/// Which occluders a frame used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum OccluderSource {
    ProjectedSize,
    /// The pre-computed minimum occluder set (with organs faded or hidden since, what is left of
    /// it joined by occluders by projected size).
    Mos,
}

impl OccluderSource {
    pub fn name(self) -> &'static str {
        match self {
            OccluderSource::ProjectedSize => "projected size",
            OccluderSource::Mos => "minimum occluder set",
        }
    }
}

/// One occluder: a leaf of an organ's hierarchy, or of its occluder stand-in's (stored as
/// `[organ, leaf]`; stored ones are the organ's own).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
#[serde(from = "[u32; 2]", into = "[u32; 2]")]
pub struct LeafRef {
    pub organ: u32,
    pub leaf: u32,
    /// A leaf of the organ's stand-in ([`crate::organ_set::StandIn`]).
    pub stand_in: bool,
}

impl LeafRef {
    /// Does the set have this organ and this leaf?
    pub fn exists_in(self, set: &OrganSet) -> bool {
        set.organs.get(self.organ as usize).is_some_and(|o| match (self.stand_in, &o.stand_in) {
            (false, _) => (self.leaf as usize) < o.bvh.leaves.len(),
            (true, Some(s)) => (self.leaf as usize) < s.bvh.leaves.len(),
            (true, None) => false,
        })
    }
}

impl From<[u32; 2]> for LeafRef {
    fn from([organ, leaf]: [u32; 2]) -> Self {
        LeafRef { organ, leaf, stand_in: false }
    }
}

impl From<LeafRef> for [u32; 2] {
    fn from(r: LeafRef) -> Self {
        [r.organ, r.leaf]
    }
}

/// Occluders by projected size. Opaque, visible organs are taken in order of the projected area
/// of their bounds (largest first; an organ around the eye counts as the whole screen); of each,
/// its leaves in the frustum, nearest first, until the triangle budget (or the leaf limit) is
/// spent: the first leaf that would overspend it ends the selection (the smaller organs after it
/// could only fill the rest with a leaf or two, and finding those costs a look at every organ's
/// leaves). The budget counts the triangles that face the eye, the only ones rasterised; a leaf
/// with none is skipped. An organ with an occluder stand-in offers the stand-in's leaves instead
/// while the organ lies wholly beyond the near plane (then the eye is outside it, and every ray
/// meets its drawn surface before a point inside). Taking an organ's near side whole keeps the
/// occluder patches large, so their coverage has few outline pixels inside.
pub fn by_projected_size(
    set: &OrganSet,
    layout: &Layout,
    camera: &Camera,
    view_proj: &Mat4,
    settings: &CullSettings,
    records: &[super::OrganRecord],
) -> Vec<LeafRef> {
    let (w, h) = (settings.width, settings.height);
    let mut organs: Vec<(usize, usize)> = Vec::new(); // (projected area, organ)
    for (o, (organ, state)) in set.organs.iter().zip(&layout.organs).enumerate() {
        if !records.get(o).is_some_and(|r| r.occluding) || organ.bvh.nodes.is_empty() {
            continue;
        }
        let mvp = *view_proj * state.transform.matrix();
        match project_box(&mvp, &organ.bvh.nodes[0].bounds, w, h) {
            ScreenBox::Rect { rect, .. } => organs.push((rect.area(), o)),
            // Around the eye (a wall the camera stands at): it may fill the screen.
            ScreenBox::Straddles => organs.push((w * h, o)),
            ScreenBox::Outside => {}
        }
    }
    organs.sort_unstable_by_key(|&(area, _)| std::cmp::Reverse(area));
    let max_leaves = settings.occluder_leaves.unwrap_or(usize::MAX);
    let mut chosen = Vec::new();
    let mut triangles = 0;
    for &(_, o) in &organs {
        let (organ, state) = (&set.organs[o], &layout.organs[o]);
        let model = state.transform.matrix();
        let mvp = *view_proj * model;
        let planes = records.get(o).map_or(&[][..], |r| r.planes.as_slice());
        let whole = planes.is_empty();
        let stand_in = organ.stand_in.as_ref().filter(|_| whole && wholly_ahead(&mvp, &organ.bvh.nodes[0].bounds));
        let bvh = stand_in.map_or(&organ.bvh, |s| &s.bvh);
        // Its leaves on screen, nearest first: the near side of a shell before its far wall.
        let mut near: Vec<(f32, u32)> = Vec::new();
        for (l, &n) in bvh.leaves.iter().enumerate() {
            let bounds = &bvh.nodes[n as usize].bounds;
            let removed = planes.iter().any(|&(n, d)| bounds.corners().iter().all(|&c| n.dot(c) > d));
            if !removed && project_box(&mvp, bounds, w, h) != ScreenBox::Outside {
                near.push(((camera.eye - model.transform_point3(bounds.center())).length(), l as u32));
            }
        }
        near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        let mesh = stand_in.map_or(&organ.mesh, |s| &s.mesh);
        let eye = model.inverse().transform_point3(camera.eye);
        // Whether a leaf did not fit.
        let mut full = false;
        for (_, l) in near {
            // Only the triangles facing the eye are rasterised, so only they count.
            let count = facing(mesh, bvh.leaf_range(l), eye);
            if triangles + count > settings.occluder_triangles || chosen.len() >= max_leaves {
                full = true;
                break;
            }
            if count > 0 {
                chosen.push(LeafRef { organ: o as u32, leaf: l, stand_in: stand_in.is_some() });
                triangles += count;
            }
        }
        if full || triangles >= settings.occluder_triangles || chosen.len() >= max_leaves {
            break;
        }
    }
    chosen
}

/// How many triangles of leaf `r` (of `set`) face the eye of `camera`.
fn facing_triangles(set: &OrganSet, layout: &Layout, camera: &Camera, r: LeafRef) -> usize {
    let (organ, state) = (&set.organs[r.organ as usize], &layout.organs[r.organ as usize]);
    let eye = state.transform.matrix().inverse().transform_point3(camera.eye);
    match (r.stand_in, organ.stand_in()) {
        (true, Some(s)) => facing(&s.mesh, s.bvh.leaf_range(r.leaf), eye),
        _ => facing(&organ.mesh, organ.bvh.leaf_range(r.leaf), eye),
    }
}

/// How many triangles of an index range face `eye` (counter-clockwise seen from it; organ space).
fn facing(mesh: &crate::mesh::Mesh, range: std::ops::Range<u32>, eye: glam::Vec3) -> usize {
    let p = |i: u32| glam::Vec3::from(mesh.positions[mesh.indices[i as usize] as usize]);
    range
        .step_by(3)
        .filter(|&i| {
            let (a, b, c) = (p(i), p(i + 1), p(i + 2));
            (b - a).cross(c - a).dot(eye - a) > 0.0
        })
        .count()
}

/// The occluders of this frame among the organs marked `occluding` (opaque and visible), those
/// marked `cut` (by clip planes) with their own leaves only, never a stand-in's: the pre-computed
/// set of the nearest viewpoint where `settings.selection` allows it (automatic: the database
/// serves the layout and the camera is near a viewpoint; with organs faded or hidden since, what
/// is left of the set joined by the occluders by projected size, so that the opaque organs under
/// faded ones occlude each other, on the settings' budget plus the triangles of the set's leaves
/// left out, facing the eye), else projected size. Other or unknown organs never occlude,
/// whatever the database says.
pub fn choose_occluders(
    set: &OrganSet,
    layout: &Layout,
    camera: &Camera,
    view_proj: &Mat4,
    settings: &CullSettings,
    database: Option<&Database>,
    records: &[super::OrganRecord],
) -> (Vec<LeafRef>, OccluderSource) {
    let viewpoint = database.and_then(|db| match settings.selection {
        Selection::ProjectedSize => None,
        Selection::Mos => db.nearest(camera).map(|v| (v, true)),
        Selection::Auto => db.serves(layout).and_then(|whole| Some((db.near(camera)?, whole))),
    });
    if let Some((viewpoint, whole)) = viewpoint {
        let is_cut = |r: &LeafRef| records.get(r.organ as usize).is_some_and(|o| o.cut);
        let occludes = |r: &LeafRef| records.get(r.organ as usize).is_some_and(|o| o.occluding);
        let valid = |r: &&LeafRef| r.exists_in(set) && occludes(r) && !(r.stand_in && is_cut(r));
        let limit = settings.occluder_leaves.unwrap_or(usize::MAX);
        let list: Vec<LeafRef> = viewpoint.occluders.iter().filter(valid).take(limit).copied().collect();
        if whole {
            return (list, OccluderSource::Mos);
        }
        // With organs faded or hidden since, what is left of the set, joined by the largest
        // occluders left (the set was chosen for organs now faded, which no longer hide those
        // beneath them), on the settings' budget plus that of the set's triangles left out.
        let mut list = list;
        let kept: std::collections::BTreeSet<LeafRef> = list.iter().copied().collect();
        let left_out: usize = viewpoint
            .occluders
            .iter()
            .filter(|r| r.exists_in(set) && !kept.contains(r))
            .map(|r| facing_triangles(set, layout, camera, *r))
            .sum();
        let settings =
            CullSettings { occluder_triangles: settings.occluder_triangles.saturating_add(left_out), ..*settings };
        let more = by_projected_size(set, layout, camera, view_proj, &settings, records);
        list.extend(more.into_iter().filter(|r| !kept.contains(r)));
        return (list, OccluderSource::Mos);
    }
    (by_projected_size(set, layout, camera, view_proj, settings, records), OccluderSource::ProjectedSize)
}

/// The solids ([`crate::organ_set::Solid`]) whose stand-ins may occlude this frame: with a
/// stand-in, every organ `occluding`, all moved as one (the same transform), and the union of
/// their bounds wholly beyond the near plane (so the eye is outside it, and every ray to a point
/// inside meets a drawn surface first).
///
/// A solid inside another (whose organs another's hold) still culls where the outer stand-in is
/// shallow or the frame's occluders leave gaps, so every valid solid is chosen, unless an
/// occluding organ outside every solid encloses them all (the skull): behind it the nested
/// stand-ins only add raster work, and only the largest are chosen.
pub fn solids(set: &OrganSet, layout: &Layout, view_proj: &Mat4, occluding: &[bool]) -> Vec<usize> {
    let mut all = crate::mesh::Bounds::EMPTY;
    let valid: Vec<usize> = (0..set.solids.len())
        .filter(|&s| {
            let solid = &set.solids[s];
            let placed =
                solid.stand_in.is_some().then(|| placed_as_one(set, layout, view_proj, s, occluding)).flatten();
            if let Some((t, bounds)) = placed {
                all = all.union(bounds.transformed(&t));
            }
            placed.is_some()
        })
        .collect();
    let in_a_solid = |o: usize| set.solids.iter().any(|s| s.organs.binary_search(&o).is_ok());
    // Its box holds theirs, with the eye outside it: its near side lies between the eye and them.
    let encloses = |o: usize| {
        let (Some(root), model) = (set.organs[o].bvh.nodes.first(), layout.organs[o].transform.matrix()) else {
            return false;
        };
        let b = root.bounds.transformed(&model);
        (0..3).all(|i| b.min[i] <= all.min[i] && all.max[i] <= b.max[i])
            && wholly_ahead(&(*view_proj * model), &root.bounds)
    };
    let enclosed = !valid.is_empty()
        && (0..set.organs.len().min(layout.organs.len()))
            .any(|o| occluding.get(o).copied().unwrap_or(false) && !in_a_solid(o) && encloses(o));
    if !enclosed {
        return valid;
    }
    let holds = |a: usize, b: usize| set.solids[b].organs.iter().all(|o| set.solids[a].organs.binary_search(o).is_ok());
    // Of two with the same organs, the first.
    let larger = |a: usize, b: usize| set.solids[a].organs.len() > set.solids[b].organs.len() || a < b;
    valid.iter().copied().filter(|&b| !valid.iter().any(|&a| a != b && holds(a, b) && larger(a, b))).collect()
}

/// The solids (bit `s` for solid `s`, the first 64) whose hidden faces
/// ([`crate::organ_set::hidden_faces`]) no pixel shows this frame: those with some, whose organs
/// are all `whole` (drawn, opaque, left as they are by the clip planes), moved as one without
/// a mirror, and wholly beyond the near plane (so the eye lies outside their box).
pub fn intact_solids(set: &OrganSet, layout: &Layout, view_proj: &Mat4, whole: &[bool]) -> u64 {
    (0..set.solids.len().min(64))
        .filter(|&s| {
            !set.solids[s].hidden_faces().is_empty()
                && placed_as_one(set, layout, view_proj, s, whole).is_some_and(|(t, _)| t.determinant() > 0.0)
        })
        .fold(0, |bits, s| bits | 1 << s)
}

/// Solid `s`'s model matrix and box (organ space), where its organs (at least one) are all
/// `flagged`, have hierarchies, share one model matrix, and lie wholly beyond the near plane.
fn placed_as_one(
    set: &OrganSet,
    layout: &Layout,
    view_proj: &Mat4,
    s: usize,
    flagged: &[bool],
) -> Option<(Mat4, crate::mesh::Bounds)> {
    let organs = &set.solids[s].organs;
    let transform = layout.organs.get(*organs.first()?)?.transform.matrix();
    let mut bounds = crate::mesh::Bounds::EMPTY;
    for &o in organs {
        let root = set.organs[o].bvh.nodes.first()?;
        let ok = flagged.get(o).copied().unwrap_or(false)
            && layout.organs.get(o).is_some_and(|l| l.transform.matrix() == transform);
        if !ok {
            return None;
        }
        bounds = bounds.union(root.bounds);
    }
    wholly_ahead(&(*view_proj * transform), &bounds).then_some((transform, bounds))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::organ_set::{Organ, Solid, StandIn};
    use glam::Vec3;

    /// Per organ, whether it is opaque (and so occludes with no section).
    fn opaque(layout: &Layout) -> Vec<bool> {
        layout.organs.iter().map(|s| s.is_opaque()).collect()
    }

    /// A unit octahedron moved `x` along x.
    fn organ(id: &str, x: f32) -> Organ {
        let mut m = crate::mesh::Mesh::octahedron();
        m.positions.iter_mut().for_each(|p| p[0] += x);
        Organ::new(id.into(), id.into(), [0.5; 3], m)
    }

    #[test]
    fn faces_inside_a_solid_are_hidden_while_it_is_intact_and_ahead() {
        let mut set =
            OrganSet { organs: vec![organ("a", 0.0), organ("b", 1.0), organ("c", 2.0)], ..Default::default() };
        set.solids = vec![
            Solid { id: "ab".into(), organs: vec![0, 1], ..Default::default() },
            Solid { id: "bc".into(), organs: vec![1, 2], ..Default::default() },
        ];
        // As if each hid its first organ's first face.
        let first_face = |o: usize| vec![(o, std::iter::once(0..1).collect())];
        set.set_hidden_faces(vec![first_face(0), first_face(1)]);
        let layout = Layout::new(&set);
        let camera = Camera::orbit(&layout.bounds(&set), 30.0, 15.0);
        let vp = camera.view_projection(1.0);
        let intact = |layout: &Layout| intact_solids(&set, layout, &vp, &opaque(layout));
        assert_eq!(intact(&layout), 0b11);
        let mut faded = layout.clone();
        faded.organs[2].opacity = 0.5;
        assert_eq!(intact(&faded), 0b01);
        let mut moved = layout.clone();
        moved.organs[0].transform.translation = Vec3::X;
        assert_eq!(intact(&moved), 0b10);
        // Moved as one, still; mirrored, not (the renderer would cull their outer faces).
        let mut together = layout.clone();
        together.organs.iter_mut().for_each(|o| o.transform.translation = Vec3::Z);
        assert_eq!(intact(&together), 0b11);
        let mut mirrored = layout.clone();
        mirrored.organs.iter_mut().for_each(|o| o.transform.scale = -1.0);
        assert_eq!(intact(&mirrored), 0);
        // With the eye inside a solid's box, not that one.
        let inside = Camera { eye: Vec3::new(-0.5, 0.0, 0.0), target: Vec3::new(1.5, 0.0, 0.0), near: 0.01, ..camera };
        assert_eq!(intact_solids(&set, &layout, &inside.view_projection(1.0), &opaque(&layout)), 0b10);
        // A solid without hidden faces is never reported.
        set.set_hidden_faces(vec![Vec::new(), first_face(1)]);
        assert_eq!(intact_solids(&set, &layout, &vp, &opaque(&layout)), 0b10);
    }

    #[test]
    fn solids_occlude_while_their_organs_are_opaque_and_move_as_one() {
        let stand_in = || Some(StandIn::new(crate::mesh::Mesh::octahedron()));
        let set = OrganSet {
            organs: vec![organ("a", 0.0), organ("b", 1.0), organ("c", 2.0)],
            solids: vec![
                Solid { id: "ab".into(), organs: vec![0, 1], stand_in: stand_in(), ..Default::default() },
                Solid { id: "abc".into(), organs: vec![0, 1, 2], stand_in: stand_in(), ..Default::default() },
                Solid { id: "none".into(), organs: vec![2], stand_in: None, ..Default::default() },
            ],
            ..Default::default()
        };
        let layout = Layout::new(&set);
        let camera = Camera::orbit(&layout.bounds(&set), 30.0, 15.0);
        let vp = camera.view_projection(1.0);
        let chosen = |layout: &Layout| solids(&set, layout, &vp, &opaque(layout));
        // Every valid one, the nested too; none without a stand-in.
        assert_eq!(chosen(&layout), [0, 1]);
        let mut faded = layout.clone();
        faded.organs[2].opacity = 0.5;
        assert_eq!(chosen(&faded), [0]);
        let mut moved = layout.clone();
        moved.organs[1].transform.translation = Vec3::X;
        assert_eq!(chosen(&moved), Vec::<usize>::new());
        // Moved as one, they still occlude.
        let mut together = layout.clone();
        together.organs.iter_mut().for_each(|o| o.transform.translation = Vec3::Z);
        assert_eq!(chosen(&together), [0, 1]);
        // Inside an opaque organ of no solid that encloses them (a skull), the largest only.
        let mut skull = crate::mesh::Mesh::octahedron();
        skull.positions.iter_mut().for_each(|p| *p = [p[0] * 8.0 + 1.0, p[1] * 8.0, p[2] * 8.0]);
        let mut with_skull = set.clone();
        with_skull.organs.push(Organ::new("skull".into(), "skull".into(), [0.9; 3], skull));
        let mut skull_layout = Layout::new(&with_skull);
        let outside = Camera::orbit(&skull_layout.bounds(&with_skull), 30.0, 15.0).view_projection(1.0);
        assert_eq!(solids(&with_skull, &skull_layout, &outside, &opaque(&skull_layout)), [1]);
        // Not with the eye inside it, nor with it hidden.
        assert_eq!(solids(&with_skull, &skull_layout, &vp, &opaque(&skull_layout)), [0, 1]);
        skull_layout.organs[3].visible = false;
        assert_eq!(solids(&with_skull, &skull_layout, &outside, &opaque(&skull_layout)), [0, 1]);
        let mut hidden = layout.clone();
        hidden.organs[0].visible = false;
        assert_eq!(chosen(&hidden), Vec::<usize>::new());
        // With the eye inside, not.
        let inside = Camera { eye: Vec3::new(0.5, 0.0, 0.0), ..camera };
        assert_eq!(solids(&set, &layout, &inside.view_projection(1.0), &opaque(&layout)), Vec::<usize>::new());
    }

    #[test]
    fn facing_counts_the_triangles_turned_to_the_eye() {
        // A unit cube, counter-clockwise from outside, two triangles a face.
        let mut mesh = crate::mesh::Mesh {
            positions: (0..8).map(|i| [(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]).collect(),
            normals: vec![],
            indices: vec![
                0, 2, 1, 1, 2, 3, // z = 0, facing -z
                4, 5, 6, 5, 7, 6, // z = 1, facing +z
                0, 1, 4, 1, 5, 4, // y = 0, facing -y
                2, 6, 3, 3, 6, 7, // y = 1, facing +y
                0, 4, 2, 2, 4, 6, // x = 0, facing -x
                1, 3, 5, 3, 7, 5, // x = 1, facing +x
            ],
        };
        mesh.compute_normals();
        assert!(mesh.signed_volume() > 0.0);
        let all = 0..mesh.indices.len() as u32;
        assert_eq!(facing(&mesh, all.clone(), Vec3::new(5.0, 0.5, 0.5)), 2);
        assert_eq!(facing(&mesh, all.clone(), Vec3::new(5.0, 5.0, 0.5)), 4);
        assert_eq!(facing(&mesh, all.clone(), Vec3::new(5.0, 5.0, 5.0)), 6);
        assert_eq!(facing(&mesh, all, Vec3::splat(0.5)), 0);
    }
}
