//! Faces inside a solid: the faces of a [`Solid`]'s organs that no pixel shows while the solid is
//! intact, so that the occlusion culler may leave out the hierarchy nodes made only of them (beyond
//! the thesis, whose occluders are single organs).
//!
//! - Organ space, millimetres; triangle numbers in the organs' leaf order; in files, in the order
//!   a load first builds the hierarchy in from the mesh file.
//! - The organs of a solid meet face to face: the white matter's surface is the cortex's inner
//!   one, wound the other way. While the solid is intact (its organs all drawn, opaque, cut by no
//!   plane, moved as one, mirrored by none) and the eye lies outside its box, such a face is drawn
//!   behind the solid's surface and no pixel shows it.
//! - Which faces are hidden is found once, offline (`vbrain stand-ins`), by rays, as the renderer
//!   draws: a ray from a point of a face towards the eye (outside the solid's box, so every surface
//!   it meets lies on the way) is stopped by a triangle of the solid the eye sees from its front
//!   (or either side, for an organ that is not closed, whose back faces the renderer draws).
//! - A face is hidden when every ray from each of its sample points, in every sampled direction it
//!   shows its front to, is stopped.
//! - A face sharing a corner with a face found visible counts as visible too ([`RINGS`]): where a
//!   face inside meets the surface, their depths near the junction differ by less than rounding, so
//!   which of them a sample there shows is for the depth test to decide, as it does without
//!   culling; and a face next to a gap the rays found is the likeliest to see through it where
//!   they did not look.
//! - Rays are samples: the culler's identity test compares images with and without culling.
//! - A face that crosses the solid's outer surface (the boundary of its organs' union) away from
//!   the corners they share pokes out, and is visible whatever its rays found: smoothed
//!   neighbouring organs may fold through each other where three or more meet.
//! - Each face goes to the smallest solid that hides it: a larger solid holding that one is intact
//!   only while it is.

use super::{OrganSet, Solid};
use crate::bvh::Bvh;
use crate::mesh::{ray_box_entry, ray_triangle, Mesh};
use glam::Vec3;
use rayon::prelude::*;
use std::ops::Range;

/// Directions sampled over the whole sphere (a Fibonacci lattice); a face tries those in front of it.
pub const DIRECTIONS: usize = 128;
/// Rings of shared corners around a visible face whose faces count as visible too. One: two would
/// reach through the walls between neighbouring gyri (one or two triangles from the brain's
/// surface to the white matter) and leave a quarter of the white matter drawn.
pub const RINGS: usize = 1;
/// Hits nearer than this (millimetres) to a ray's origin are not counted: the face itself, and
/// neighbours met at its corners.
const NEAREST_HIT_MM: f32 = 1e-3;

/// Per barycentric sample of a face: its centre, points near its corners, and near its edges.
const SAMPLES: [[f32; 3]; 7] = [
    [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0],
    [0.8, 0.1, 0.1],
    [0.1, 0.8, 0.1],
    [0.1, 0.1, 0.8],
    [0.45, 0.45, 0.1],
    [0.1, 0.45, 0.45],
    [0.45, 0.1, 0.45],
];

/// The hidden faces of one organ in one solid: ranges of triangle numbers, ascending.
pub type OrganFaces = (usize, Vec<Range<u32>>);

/// For each solid of `set` (in order), the faces of its organs that it hides and no smaller solid
/// does ([`OrganFaces`], organs ascending, those with none left out). `progress` is told of each
/// solid as its turn comes, smallest first.
pub fn find(set: &OrganSet, mut progress: impl FnMut(&Solid)) -> Vec<Vec<OrganFaces>> {
    let directions = fibonacci_sphere(DIRECTIONS);
    // Per organ and triangle: hidden by a solid already.
    let mut taken: Vec<Vec<bool>> = set.organs.iter().map(|o| vec![false; o.mesh.triangle_count()]).collect();
    let mut out: Vec<Vec<OrganFaces>> = vec![Vec::new(); set.solids.len()];
    let mut order: Vec<usize> = (0..set.solids.len()).collect();
    order.sort_by_key(|&s| (set.solids[s].organs.len(), s));
    for s in order {
        progress(&set.solids[s]);
        let hidden = hidden_in(set, &set.solids[s], &directions, &taken);
        for (&o, faces) in set.solids[s].organs.iter().zip(hidden) {
            let ranges = runs(faces.iter().enumerate().filter(|&(t, &h)| h && !taken[o][t]).map(|(t, _)| t as u32));
            for r in &ranges {
                r.clone().for_each(|t| taken[o][t as usize] = true);
            }
            if !ranges.is_empty() {
                out[s].push((o, ranges));
            }
        }
    }
    out
}

/// Per organ of `solid` (in its order), per triangle: hidden while the solid is intact. Faces
/// `taken` by a smaller solid are not tested again (hidden there, hidden here).
fn hidden_in(set: &OrganSet, solid: &Solid, directions: &[Vec3], taken: &[Vec<bool>]) -> Vec<Vec<bool>> {
    let surface = Surface::of(set, solid);
    let boundary = Boundary::of(set, solid);
    let mut hidden: Vec<Vec<bool>> = solid
        .organs
        .iter()
        .map(|&o| {
            let organ = &set.organs[o];
            (0..organ.mesh.triangle_count())
                .into_par_iter()
                .map(|t| {
                    let tri = organ.mesh.triangle(t);
                    taken[o][t] || (face_hidden(&surface, tri, organ.closed(), directions) && !boundary.crossed_by(tri))
                })
                .collect()
        })
        .collect();
    // Faces near a visible one are visible too: welded corners, across the solid's organs.
    let meshes: Vec<&Mesh> = solid.organs.iter().map(|&o| &set.organs[o].mesh).collect();
    let mut all = Vec::new();
    meshes.iter().for_each(|m| all.extend_from_slice(&m.positions));
    let (remap, welded) = crate::mesh::weld(&all);
    let offsets: Vec<usize> = meshes
        .iter()
        .scan(0, |n, m| {
            let at = *n;
            *n += m.positions.len();
            Some(at)
        })
        .collect();
    let corners =
        |i: usize, t: usize| [0, 1, 2].map(|k| remap[offsets[i] + meshes[i].indices[3 * t + k] as usize] as usize);
    for _ in 0..RINGS {
        let mut near_visible = vec![false; welded.len()];
        for (i, faces) in hidden.iter().enumerate() {
            for (t, _) in faces.iter().enumerate().filter(|&(_, &h)| !h) {
                corners(i, t).iter().for_each(|&v| near_visible[v] = true);
            }
        }
        for (i, faces) in hidden.iter_mut().enumerate() {
            let o = solid.organs[i];
            for (t, h) in faces.iter_mut().enumerate() {
                // A face a smaller solid hides stays hidden: its neighbours here do not matter.
                if *h && !taken[o][t] && corners(i, t).iter().any(|&v| near_visible[v]) {
                    *h = false;
                }
            }
        }
    }
    hidden
}

/// A solid's organs as the rays meet them: one mesh with a hierarchy, in which an organ that is
/// not closed (the renderer draws its back faces) has each triangle twice, wound both ways.
struct Surface {
    mesh: Mesh,
    bvh: Bvh,
}

impl Surface {
    fn of(set: &OrganSet, solid: &Solid) -> Surface {
        let mut mesh = Mesh::default();
        for &o in &solid.organs {
            let organ = &set.organs[o];
            mesh.append(&organ.mesh);
            if !organ.closed() {
                let mut flipped = organ.mesh.clone();
                flipped.indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
                mesh.append(&flipped);
            }
        }
        let bvh = Bvh::build(&mut mesh);
        Surface { mesh, bvh }
    }

    /// Whether a triangle facing `dir` (the eye beyond it sees its front) stops the ray
    /// `origin + t dir` beyond [`NEAREST_HIT_MM`].
    fn stops(&self, origin: Vec3, dir: Vec3) -> bool {
        let inv = dir.recip();
        let mut stack: Vec<&crate::bvh::Node> = Vec::with_capacity(64);
        stack.extend(self.bvh.nodes.first().filter(|r| ray_box_entry(origin, inv, &r.bounds).is_some()));
        // Nearer boxes first: a hidden face's rays mostly end near it.
        while let Some(node) = stack.pop() {
            if !node.is_leaf() {
                let [a, b] = node.children.map(|c| {
                    let child = &self.bvh.nodes[c as usize];
                    (ray_box_entry(origin, inv, &child.bounds), child)
                });
                let (near, far) = if a.0 <= b.0 || b.0.is_none() { (a, b) } else { (b, a) };
                for (at, child) in [far, near] {
                    if at.is_some() {
                        stack.push(child);
                    }
                }
                continue;
            }
            for t in node.first..node.first + node.count {
                let tri = self.mesh.triangle(t as usize);
                if (tri[1] - tri[0]).cross(tri[2] - tri[0]).dot(dir) > 0.0
                    && ray_triangle(origin, dir, tri).is_some_and(|d| d > NEAREST_HIT_MM)
                {
                    return true;
                }
            }
        }
        false
    }
}

/// A solid's outer surface: the boundary of its organs' union, with a hierarchy.
struct Boundary {
    mesh: Mesh,
    bvh: Bvh,
}

/// How near (millimetres) two corners must lie to count as shared.
const SHARED_CORNER_MM: f32 = 1e-4;

impl Boundary {
    fn of(set: &OrganSet, solid: &Solid) -> Boundary {
        let members: Vec<&Mesh> = solid.organs.iter().map(|&o| &set.organs[o].mesh).collect();
        let mut mesh = super::stand_in::union_surface(&members);
        let bvh = Bvh::build(&mut mesh);
        Boundary { mesh, bvh }
    }

    /// Whether the face `tri` crosses the outer surface away from the corners they share: part of
    /// it then pokes out (smoothed neighbouring organs may fold through each other where three or
    /// more meet), where the eye sees it however the rays from its sample points fared.
    fn crossed_by(&self, tri: [Vec3; 3]) -> bool {
        let (lo, hi) = (tri[0].min(tri[1]).min(tri[2]), tri[0].max(tri[1]).max(tri[2]));
        let overlaps = |b: &crate::mesh::Bounds| {
            (0..3).all(|i| b.min[i] <= hi[i] + SHARED_CORNER_MM && lo[i] - SHARED_CORNER_MM <= b.max[i])
        };
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        stack.extend(self.bvh.nodes.first().filter(|r| overlaps(&r.bounds)).map(|_| 0));
        while let Some(n) = stack.pop() {
            let node = &self.bvh.nodes[n as usize];
            if !node.is_leaf() {
                stack.extend(node.children.iter().copied().filter(|&c| overlaps(&self.bvh.nodes[c as usize].bounds)));
                continue;
            }
            for t in node.first..node.first + node.count {
                let other = self.mesh.triangle(t as usize);
                let shared = tri.iter().any(|a| other.iter().any(|b| a.distance(*b) < SHARED_CORNER_MM));
                if !shared && (edges_cross(tri, other) || edges_cross(other, tri)) {
                    return true;
                }
            }
        }
        false
    }
}

/// Whether an edge of triangle `a` passes through triangle `b`, strictly between its ends (by a
/// ten-thousandth of its length).
fn edges_cross(a: [Vec3; 3], b: [Vec3; 3]) -> bool {
    (0..3).any(|k| {
        let (p, q) = (a[k], a[(k + 1) % 3]);
        ray_triangle(p, q - p, b).is_some_and(|t| t > 1e-4 && t < 1.0 - 1e-4)
    })
}

/// Whether every sampled ray from the face `tri` towards its front (either side where its organ
/// is not `closed`) is stopped by the solid's `surface`.
fn face_hidden(surface: &Surface, tri: [Vec3; 3], closed: bool, directions: &[Vec3]) -> bool {
    let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
    if normal.length_squared() == 0.0 || !normal.is_finite() {
        // No area: the rasteriser draws no sample of it.
        return true;
    }
    let normal = normal.normalize();
    // Straight out first: the solid's outer faces fail at once.
    if !SAMPLES.iter().all(|w| surface.stops(tri[0] * w[0] + tri[1] * w[1] + tri[2] * w[2], normal)) {
        return false;
    }
    // Each sample point turns the directions its own way, so that the face as a whole tries
    // `SAMPLES.len()` times as many.
    SAMPLES.iter().enumerate().all(|(k, w)| {
        let p = tri[0] * w[0] + tri[1] * w[1] + tri[2] * w[2];
        let turn = glam::Quat::from_axis_angle(Vec3::new(0.36, 0.48, 0.8), 2.4 * k as f32);
        directions.iter().map(|&d| turn * d).filter(|d| !closed || d.dot(normal) > 0.0).all(|d| surface.stops(p, d))
    })
}

/// `n` unit directions spread evenly over the sphere.
fn fibonacci_sphere(n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f32 + 1.0) / n as f32;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let a = golden * i as f32;
            Vec3::new(r * a.cos(), r * a.sin(), z)
        })
        .collect()
}

/// Ascending numbers as runs.
pub(super) fn runs(numbers: impl Iterator<Item = u32>) -> Vec<Range<u32>> {
    let mut out: Vec<Range<u32>> = Vec::new();
    for n in numbers {
        match out.last_mut() {
            Some(r) if r.end == n => r.end = n + 1,
            _ => out.push(n..n + 1),
        }
    }
    out
}

/// Format version of a solid's hidden-faces file; another version is ignored.
pub const VERSION: u32 = 1;

/// A solid's hidden-faces file: per organ, its triangle count when they were found (a mesh that
/// changed since is refused) and the hidden triangles as `[first, end)` runs.
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    version: u32,
    organs: Vec<FileOrgan>,
}

#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct FileOrgan {
    id: String,
    triangles: usize,
    hidden: Vec<[u32; 2]>,
}

/// Writes the hidden faces of a solid of `set` to `path`, atomically, each triangle `t` of organ
/// `o` numbered `number(o, t)`: its number in the order a load of the set's mesh files first
/// builds the hierarchy in.
pub fn write(
    path: &std::path::Path,
    set: &OrganSet,
    faces: &[OrganFaces],
    number: impl Fn(usize, u32) -> u32,
) -> crate::error::Result<()> {
    let file = File {
        version: VERSION,
        organs: faces
            .iter()
            .map(|(o, runs)| {
                let organ = &set.organs[*o];
                let mut first: Vec<u32> = runs.iter().flat_map(|r| r.clone()).map(|t| number(*o, t)).collect();
                first.sort_unstable();
                FileOrgan {
                    id: organ.id.clone(),
                    triangles: organ.mesh.triangle_count(),
                    hidden: self::runs(first.into_iter()).iter().map(|r| [r.start, r.end]).collect(),
                }
            })
            .collect(),
    };
    let json = serde_json::to_string(&file)
        .map_err(|e| crate::error::Error::Encode { path: path.to_path_buf(), message: e.to_string() })?;
    crate::atomic::write(path, |w| w.write_all(json.as_bytes()))
}

/// Reads the hidden faces of the solid over `members` (indices into `organs`) from `path`, or
/// says why they are not used: unreadable, another version, an organ not in the solid, or runs
/// that do not fit its mesh as it is now.
pub(super) fn read(
    path: &std::path::Path,
    organs: &[super::Organ],
    members: &[usize],
) -> Result<Vec<OrganFaces>, String> {
    let text = crate::input::read(path, crate::input::Kind::Manifest).map_err(|e| e.to_string())?;
    let file: File =
        serde_json::from_slice(&text).map_err(|e| format!("{}: line {}: {e}", path.display(), e.line()))?;
    if file.version != VERSION {
        return Err(format!("{}: version {}, this vbrain reads {VERSION}", path.display(), file.version));
    }
    let mut out: Vec<OrganFaces> = Vec::new();
    for entry in file.organs {
        let Some(&o) = members.iter().find(|&&o| organs[o].id == entry.id) else {
            return Err(format!("{}: organ \"{}\" is not in the solid", path.display(), entry.id));
        };
        let count = organs[o].mesh.triangle_count();
        if entry.triangles != count {
            return Err(format!(
                "{}: organ \"{}\" had {} triangles, now {count}; run `vbrain stand-ins` again",
                path.display(),
                entry.id,
                entry.triangles
            ));
        }
        let mut end = 0;
        for &[a, b] in &entry.hidden {
            if a < end || b <= a || b as usize > count {
                return Err(format!(
                    "{}: organ \"{}\": run [{a}, {b}] out of order or range",
                    path.display(),
                    entry.id
                ));
            }
            end = b;
        }
        out.push((o, entry.hidden.iter().map(|&[a, b]| a..b).collect()));
    }
    out.sort_by_key(|f| f.0);
    Ok(out)
}

/// Per node and per part of one organ's hierarchy: the solids (bit `s` for solid `s`, the first
/// 64) that must be intact for every one of its triangles to be hidden, or 0 where one is never
/// hidden; and per node, whether a node or part at or below it is wholly hidden by some solids.
#[derive(Clone, Debug, Default)]
pub struct Inside {
    nodes: Vec<u64>,
    parts: Vec<u64>,
    below: Vec<bool>,
}

impl Inside {
    /// The index of the faces `solids` hide in the organ `o` with hierarchy `bvh`.
    pub(super) fn of(o: usize, bvh: &Bvh, solids: &[Solid]) -> Inside {
        let triangles = bvh.leaf_of.len();
        let mut needs = vec![0u64; triangles];
        for (s, solid) in solids.iter().enumerate().take(64) {
            for (_, runs) in solid.hidden.iter().filter(|f| f.0 == o) {
                for r in runs {
                    (r.start as usize..(r.end as usize).min(triangles)).for_each(|t| needs[t] |= 1 << s);
                }
            }
        }
        if needs.iter().all(|&m| m == 0) {
            return Inside::default();
        }
        let all = |first: u32, count: u32| {
            let run = &needs[first as usize..(first + count) as usize];
            match run.iter().all(|&m| m != 0) {
                true => run.iter().fold(0, |a, &m| a | m),
                false => 0,
            }
        };
        let nodes: Vec<u64> = bvh.nodes.iter().map(|n| all(n.first, n.count)).collect();
        let parts: Vec<u64> = bvh.parts.iter().map(|p| all(p.first, p.count)).collect();
        // Children come after their parents.
        let mut below: Vec<bool> = nodes.iter().map(|&m| m != 0).collect();
        for n in (0..bvh.nodes.len()).rev() {
            let node = &bvh.nodes[n];
            below[n] |= match node.is_leaf() {
                true => bvh.part_range(node.leaf).any(|p| parts[p] != 0),
                false => node.children.iter().any(|&c| below[c as usize]),
            };
        }
        Inside { nodes, parts, below }
    }

    /// Whether node `n`'s triangles are all hidden while the solids `intact` are.
    pub fn node(&self, n: u32, intact: u64) -> bool {
        self.nodes.get(n as usize).is_some_and(|&m| m != 0 && m & !intact == 0)
    }

    /// Whether part `p`'s triangles are all hidden while the solids `intact` are.
    pub fn part(&self, p: usize, intact: u64) -> bool {
        self.parts.get(p).is_some_and(|&m| m != 0 && m & !intact == 0)
    }

    /// Whether a node or part at or below node `n` may be hidden (by some solids).
    pub fn any_below(&self, n: u32) -> bool {
        self.below.get(n as usize).copied().unwrap_or(false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::organ_set::Organ;

    /// Two 2 x 2 x 2 boxes side by side along x, sharing the face x = 0, as one solid; each side
    /// of each box split `n` x `n`. `b_mesh` may change the second box.
    fn two_boxes(n: usize, b_mesh: impl FnOnce(&mut Mesh)) -> OrganSet {
        let shifted = |dx: f32| {
            let mut m = crate::mesh::split_box(n, Vec3::ONE);
            m.positions.iter_mut().for_each(|p| p[0] += dx);
            m
        };
        let mut b = shifted(1.0);
        b_mesh(&mut b);
        let organs = vec![
            Organ::new("a".into(), "a".into(), [0.5; 3], shifted(-1.0)),
            Organ::new("b".into(), "b".into(), [0.5; 3], b),
        ];
        let solids = vec![Solid { id: "ab".into(), organs: vec![0, 1], ..Default::default() }];
        OrganSet { organs, solids, ..Default::default() }
    }

    /// Per organ, the centres of its hidden faces.
    fn hidden_centres(set: &OrganSet, found: &[OrganFaces]) -> Vec<Vec<Vec3>> {
        let mut out = vec![Vec::new(); set.organs.len()];
        for (o, runs) in found {
            for t in runs.iter().flat_map(|r| r.clone()) {
                out[*o].push(set.organs[*o].mesh.triangle(t as usize).iter().sum::<Vec3>() / 3.0);
            }
        }
        out
    }

    #[test]
    fn the_face_two_boxes_share_is_hidden_but_at_its_rim() {
        let set = two_boxes(8, |_| {});
        let found = find(&set, |_| {});
        let centres = hidden_centres(&set, &found[0]);
        for (o, c) in centres.iter().enumerate() {
            // The shared face is split 8 x 8: what shares no corner with its rim (6 x 6 squares,
            // 2 triangles each) is hidden, nothing else.
            assert_eq!(c.len(), 72, "organ {o}: {c:?}");
            assert!(c.iter().all(|p| p.x.abs() < 1e-6 && p.y.abs() < 0.75 && p.z.abs() < 0.75), "{c:?}");
        }
    }

    #[test]
    fn a_face_seen_through_a_hole_is_not_hidden() {
        // A small hole in the middle of the second box's far side (x = 2): it is no longer closed,
        // so the renderer draws both sides of its faces, and every point of the shared face sees
        // the hole across the hollow box, from either side.
        let set = two_boxes(8, |m| {
            let centre = |t: &[u32]| t.iter().map(|&v| Vec3::from(m.positions[v as usize])).sum::<Vec3>() / 3.0;
            let kept: Vec<u32> = m
                .indices
                .chunks_exact(3)
                .filter(|t| {
                    let c = centre(t);
                    !(c.x > 1.99 && c.y.abs() < 0.25 && c.z.abs() < 0.25)
                })
                .flatten()
                .copied()
                .collect();
            m.indices = kept;
        });
        assert!(!set.organs[1].closed());
        let found = find(&set, |_| {});
        assert_eq!(found[0], Vec::new(), "nothing is hidden");
    }

    #[test]
    fn the_index_marks_nodes_and_parts_made_only_of_hidden_faces() {
        let mut set = two_boxes(8, |_| {});
        let found = find(&set, |_| {});
        set.set_hidden_faces(found);
        let organ = &set.organs[0];
        let hidden: std::collections::HashSet<u32> = set.solids[0].hidden[0].1.iter().flat_map(|r| r.clone()).collect();
        for (p, part) in organ.bvh.parts.iter().enumerate() {
            let all = part.triangles().all(|t| hidden.contains(&t));
            assert_eq!(organ.inside.part(p, 1), all, "part {p}");
            assert!(!organ.inside.part(p, 0), "no solid intact, nothing hidden");
        }
        assert!(!organ.inside.node(0, 1), "the root holds visible faces");
        assert!(organ.inside.any_below(0) == organ.bvh.parts.iter().enumerate().any(|(p, _)| organ.inside.part(p, 1)));
        // The hierarchy was built again with the hidden faces apart: its root's first child holds
        // them all, and no part mixes them with visible ones.
        let first = organ.bvh.nodes[0].children[0];
        assert!(organ.inside.node(first, 1), "the root's first child is hidden");
        assert_eq!(organ.bvh.nodes[first as usize].count as usize, hidden.len());
        for part in &organ.bvh.parts {
            let n = part.triangles().filter(|t| hidden.contains(t)).count();
            assert!(n == 0 || n == part.count as usize, "a part mixes hidden and visible faces");
        }
    }

    #[test]
    fn hidden_faces_saved_and_loaded_are_the_same_faces() {
        let mut set = two_boxes(8, |_| {});
        let found = find(&set, |_| {});
        set.set_hidden_faces(found);
        let centres = |set: &OrganSet| {
            let mut c: Vec<[u32; 3]> = hidden_centres(set, &set.solids[0].hidden)
                .concat()
                .iter()
                .map(|p| p.to_array().map(f32::to_bits))
                .collect();
            c.sort_unstable();
            c
        };
        let expected = centres(&set);
        assert_eq!(expected.len(), 144);
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("ab");
        // The whole set (meshes in their new order), then the stand-ins and hidden faces alone
        // beside meshes as a load first built them.
        set.save(&out).unwrap();
        let loaded = crate::organ_set::open(&out).unwrap().set;
        assert_eq!(centres(&loaded), expected);
        loaded.save_stand_ins(&out).unwrap();
        let again = crate::organ_set::open(&out).unwrap();
        assert!(again.warnings.is_empty(), "{:?}", again.warnings);
        assert_eq!(centres(&again.set), expected);
    }

    #[test]
    fn a_face_poking_through_the_outer_surface_crosses_it() {
        let mut mesh = crate::mesh::split_box(2, Vec3::ONE);
        let bvh = Bvh::build(&mut mesh);
        let boundary = Boundary { mesh, bvh };
        let inside = [Vec3::new(-0.5, -0.5, 0.0), Vec3::new(0.5, -0.5, 0.0), Vec3::new(0.0, 0.5, 0.0)];
        assert!(!boundary.crossed_by(inside));
        // One corner a little beyond the top (y = 1).
        let poking = [inside[0], inside[1], Vec3::new(0.0, 1.01, 0.0)];
        assert!(boundary.crossed_by(poking));
        // Meeting the surface at a corner it shares, and lying in the surface itself, is no crossing.
        let touching = [inside[0], inside[1], Vec3::new(0.0, 1.0, 0.0)];
        assert!(!boundary.crossed_by(touching));
        let on = boundary.mesh.triangle(0);
        assert!(!boundary.crossed_by(on));
    }

    #[test]
    fn a_file_for_another_mesh_is_refused() {
        let mut set = two_boxes(8, |_| {});
        let found = find(&set, |_| {});
        assert!(!found[0].is_empty());
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("ab.hidden.json");
        write(&path, &set, &found[0], |_, t| t).unwrap();
        assert_eq!(read(&path, &set.organs, &[0, 1]).unwrap(), found[0]);
        set.organs[1].set_mesh(crate::mesh::split_box(2, Vec3::ONE));
        let why = read(&path, &set.organs, &[0, 1]).unwrap_err();
        assert!(why.contains("\"b\" had") && why.contains("stand-ins"), "{why}");
    }
}
