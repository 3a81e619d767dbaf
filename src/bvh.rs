//! The culling hierarchy of one organ: a binary bounding-volume tree (thesis §3.1), its leaves
//! split into parts, and per triangle its neighbours across its edges.
//!
//! - Organ space, millimetres.
//! - Leaves hold at most [`LEAF_TRIANGLES`] triangles (thesis §3.1). The mesh's triangles are
//!   reordered so each leaf is one contiguous range of the index buffer, and the vertices
//!   renumbered in order of first use, so a leaf's vertices lie together in memory.
//! - Within a leaf the triangles are split further, the same way, into contiguous *parts* of at
//!   most [`PART_TRIANGLES`], whose tighter boxes and thin slabs the occlusion test falls back on
//!   when a leaf's box fails.
//! - Per triangle, its neighbours across its three edges (by position, consistently wound), which
//!   the occluder rasteriser needs to find the outline of a set of triangles.

use crate::mesh::{Bounds, Mesh};
use glam::Vec3;
use std::collections::HashMap;

/// The most triangles in a leaf.
pub const LEAF_TRIANGLES: usize = 256;
/// The most triangles in a part of a leaf.
pub const PART_TRIANGLES: usize = 32;
/// No node, no neighbour.
pub const NONE: u32 = u32::MAX;

#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub bounds: Bounds,
    /// A slab holding its triangles.
    pub slab: Slab,
    /// Children, or `[NONE, NONE]` for a leaf.
    pub children: [u32; 2],
    /// Triangles `first..first + count` (in triangle units) of everything below this node.
    pub first: u32,
    pub count: u32,
    /// Leaf number for a leaf, else `NONE`.
    pub leaf: u32,
    /// A cone holding its triangles' normals.
    pub cone: Cone,
}

impl Node {
    pub fn is_leaf(&self) -> bool {
        self.children[0] == NONE
    }
}

/// Triangles `first..first + count` of a leaf, their bounds, and a slab holding them; and their
/// vertices, each once: `Bvh::part_vertices[vertices.0..vertices.1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Part {
    pub bounds: Bounds,
    pub first: u32,
    pub count: u32,
    pub slab: Slab,
    pub vertices: (u32, u32),
    /// A cone holding its triangles' normals.
    pub cone: Cone,
}

impl Part {
    pub fn triangles(&self) -> std::ops::Range<u32> {
        self.first..self.first + self.count
    }
}

/// The points p with `min <= normal . p <= max`: two parallel planes across the mean normal of a
/// patch of surface that hold all its triangles. A small patch is nearly flat, so its slab is far
/// thinner than its box; where the normals cancel (no mean direction), it holds everything.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Slab {
    pub normal: Vec3,
    pub min: f32,
    pub max: f32,
}

impl Slab {
    /// The slab of everything.
    pub const ALL: Slab = Slab { normal: Vec3::ZERO, min: f32::NEG_INFINITY, max: f32::INFINITY };

    /// The slab of triangles (each given by its three corners).
    pub fn of(triangles: impl Iterator<Item = [Vec3; 3]> + Clone) -> Slab {
        let sum: Vec3 = triangles.clone().map(|[a, b, c]| (b - a).cross(c - a)).sum();
        let normal = sum.normalize_or_zero();
        if normal == Vec3::ZERO {
            return Slab::ALL;
        }
        let (mut min, mut max, mut reach) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f32);
        for p in triangles.flatten() {
            let d = normal.dot(p);
            (min, max, reach) = (min.min(d), max.max(d), reach.max(p.abs().element_sum()));
        }
        // Widened well beyond the rounding of the products (a few ulps of the largest term).
        let margin = 1e-5 * reach;
        Slab { normal, min: min - margin, max: max + margin }
    }
}

/// The directions within `spread` radians of `axis` (a unit vector): a cone holding the normals of
/// a run of triangles (meshoptimizer's cluster cones). Where the eye lies behind every triangle's
/// plane, the run faces away and a renderer culling back faces draws none of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    pub axis: Vec3,
    pub spread: f32,
}

/// How far (radians) every triangle must be turned from edge-on, away from the eye, for a run to
/// count as facing away. The GPU decides facing on vertices snapped to a sub-pixel grid, so a
/// triangle seen nearly edge-on may come out facing the eye; 0.1 rad keeps a triangle's projected
/// area far above that snapping for any triangle wider than a few sub-pixel steps.
pub const FACING_AWAY_MARGIN: f32 = 0.1;

impl Cone {
    /// No cone: the normals spread too far for a run to face away as a whole.
    pub const NONE: Cone = Cone { axis: Vec3::ZERO, spread: std::f32::consts::PI };

    /// The cone of triangles (each given by its corners) around `axis` (their mean normal, or
    /// zero where the normals cancel). Triangles without area have no normal and draw nothing.
    pub fn of(triangles: impl Iterator<Item = [Vec3; 3]>, axis: Vec3) -> Cone {
        if axis == Vec3::ZERO {
            return Cone::NONE;
        }
        let mut spread = 0.0f32;
        for [a, b, c] in triangles {
            let n = (b - a).cross(c - a).normalize_or_zero();
            if n != Vec3::ZERO {
                spread = spread.max(axis.dot(n).clamp(-1.0, 1.0).acos());
            }
        }
        // Above the rounding of the angles (about 1e-7 rad a step).
        Cone { axis, spread: spread + 1e-4 }
    }

    /// Whether every triangle of a run inside `bounds` with this cone faces away from `eye` (same
    /// space), each turned at least [`FACING_AWAY_MARGIN`] from edge-on: the angle from any normal
    /// to the direction from the eye to any point of the bounds' sphere is below a right angle by
    /// the margin, as the spread plus the angle to the sphere's centre plus the sphere's half-angle.
    pub fn faces_away(&self, bounds: &Bounds, eye: Vec3) -> bool {
        if self.spread >= std::f32::consts::FRAC_PI_2 - FACING_AWAY_MARGIN {
            return false;
        }
        let (centre, radius) = (bounds.center(), 0.5 * bounds.size().length());
        let d = centre - eye;
        let distance = d.length();
        // (A NaN distance fails too.)
        if distance.is_nan() || distance <= radius * 1.001 {
            return false;
        }
        let towards = (self.axis.dot(d) / distance).clamp(-1.0, 1.0).acos();
        let half_angle = (radius / distance).clamp(0.0, 1.0).asin();
        towards + self.spread + half_angle < std::f32::consts::FRAC_PI_2 - FACING_AWAY_MARGIN
    }
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Bvh {
    /// Root first.
    pub(crate) nodes: Vec<Node>,
    /// The node of each leaf, in triangle order.
    pub(crate) leaves: Vec<u32>,
    /// Per triangle: the leaf it belongs to.
    pub(crate) leaf_of: Vec<u32>,
    /// The parts of all leaves, in triangle order; leaf l's are `leaf_parts[l]..leaf_parts[l + 1]`.
    pub(crate) parts: Vec<Part>,
    pub(crate) leaf_parts: Vec<u32>,
    /// The parts' vertices (indices into the mesh's positions), each part's in order of first use.
    pub(crate) part_vertices: Vec<u32>,
    /// Per triangle, its corners as places in its part's vertices: the occlusion test projects a
    /// part's vertices once, then its triangles from them.
    pub(crate) corners: Vec<[u8; 3]>,
    /// Per triangle and edge (a->b, b->c, c->a): the triangle across it, or `NONE` at a border, a
    /// non-manifold edge, or a neighbour wound the other way.
    pub(crate) neighbours: Vec<[u32; 3]>,
}

impl Bvh {
    /// Builds the tree, reorders `mesh`'s triangles into leaf order and its vertices into order of
    /// first use (dropping unused ones). Splits at the median split position along the longest
    /// axis of their bounds.
    pub fn build(mesh: &mut Mesh) -> Bvh {
        Bvh::build_apart(mesh, &[]).0
    }

    /// As [`Bvh::build`], but the root splits the triangles marked in `apart` (by their numbers in
    /// `mesh` as given; empty for none) from the rest, so no node or part below it mixes the two
    /// (a shell's own root split is then not made). Also gives, per triangle of the reordered
    /// mesh, its number before.
    pub fn build_apart(mesh: &mut Mesh, apart: &[bool]) -> (Bvh, Vec<u32>) {
        let tri_count = mesh.triangle_count();
        let mut bvh = Bvh::default();
        if tri_count == 0 {
            return (bvh, Vec::new());
        }
        let tri = |t: u32| {
            let i = 3 * t as usize;
            [mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]].map(|v| Vec3::from(mesh.positions[v as usize]))
        };
        let centroids: Vec<Vec3> = (0..tri_count as u32).map(|t| tri(t).iter().sum::<Vec3>() / 3.0).collect();
        let mut order: Vec<u32> = (0..tri_count as u32).collect();
        // Explicit stack of (node, first, count).
        bvh.nodes.push(Node {
            bounds: Bounds::EMPTY,
            slab: Slab::ALL,
            children: [NONE; 2],
            first: 0,
            count: tri_count as u32,
            leaf: NONE,
            cone: Cone::NONE,
        });
        // Bounds of a run of triangles, and the midpoint split of their centroids along the
        // longest axis (the run reordered so the first half holds the lower centroids).
        let bound = |slice: &[u32]| {
            let mut bounds = Bounds::EMPTY;
            for &t in slice {
                for p in tri(t) {
                    bounds.include(p.to_array());
                }
            }
            bounds
        };
        let split = |slice: &mut [u32]| {
            let mut cb = Bounds::EMPTY;
            for &t in slice.iter() {
                cb.include(centroids[t as usize].to_array());
            }
            let size = cb.size();
            let axis = if size.x >= size.y && size.x >= size.z {
                0
            } else if size.y >= size.z {
                1
            } else {
                2
            };
            let mid = slice.len() / 2;
            slice.select_nth_unstable_by(mid, |&a, &b| {
                centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
            });
            mid
        };
        // The root splits the marked triangles from the rest, or a shell's outer surface from its
        // inner one (see `shell_split`).
        let marked = apart.iter().filter(|&&m| m).count();
        let root_split = if apart.len() == tri_count && marked > 0 && marked < tri_count {
            order.sort_by_key(|&t| !apart[t as usize]);
            Some(marked)
        } else {
            shell_split(mesh, &mut order)
        };
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let (first, count) = (bvh.nodes[n as usize].first as usize, bvh.nodes[n as usize].count as usize);
            let slice = &mut order[first..first + count];
            bvh.nodes[n as usize].bounds = bound(slice);
            let slab = Slab::of(slice.iter().map(|&t| tri(t)));
            bvh.nodes[n as usize].cone = Cone::of(slice.iter().map(|&t| tri(t)), slab.normal);
            bvh.nodes[n as usize].slab = slab;
            if count <= LEAF_TRIANGLES {
                continue;
            }
            let mid = match (n, root_split) {
                (0, Some(mid)) => mid,
                _ => split(slice),
            };
            let left = bvh.nodes.len() as u32;
            for (f, c) in [(first, mid), (first + mid, count - mid)] {
                bvh.nodes.push(Node {
                    bounds: Bounds::EMPTY,
                    slab: Slab::ALL,
                    children: [NONE; 2],
                    first: f as u32,
                    count: c as u32,
                    leaf: NONE,
                    cone: Cone::NONE,
                });
            }
            bvh.nodes[n as usize].children = [left, left + 1];
            stack.push(left + 1);
            stack.push(left);
        }
        // Leaves in triangle order.
        let mut leaves: Vec<u32> = (0..bvh.nodes.len() as u32).filter(|&n| bvh.nodes[n as usize].is_leaf()).collect();
        leaves.sort_by_key(|&n| bvh.nodes[n as usize].first);
        bvh.leaf_of = vec![0; tri_count];
        for (l, &n) in leaves.iter().enumerate() {
            let node = &mut bvh.nodes[n as usize];
            node.leaf = l as u32;
            bvh.leaf_of[node.first as usize..(node.first + node.count) as usize].fill(l as u32);
        }
        // Parts of each leaf, in order (depth first, lower half first).
        bvh.leaf_parts.push(0);
        for &n in &leaves {
            let node = &bvh.nodes[n as usize];
            let mut runs = vec![(node.first as usize, node.count as usize)];
            while let Some((first, count)) = runs.pop() {
                let slice = &mut order[first..first + count];
                if count <= PART_TRIANGLES {
                    let slab = Slab::of(slice.iter().map(|&t| tri(t)));
                    let cone = Cone::of(slice.iter().map(|&t| tri(t)), slab.normal);
                    let (first, count) = (first as u32, count as u32);
                    bvh.parts.push(Part { bounds: bound(slice), first, count, slab, vertices: (0, 0), cone });
                    continue;
                }
                let mid = split(slice);
                runs.push((first + mid, count - mid));
                runs.push((first, mid));
            }
            bvh.leaf_parts.push(bvh.parts.len() as u32);
        }
        bvh.leaves = leaves;
        mesh.indices =
            order.iter().flat_map(|&t| (0..3).map(move |k| 3 * t as usize + k)).map(|i| mesh.indices[i]).collect();
        crate::surface::compact(mesh);
        bvh.neighbours = neighbours(mesh);
        bvh.index_part_vertices(mesh);
        (bvh, order)
    }

    /// Fills in each part's vertices and each triangle's corners among them.
    fn index_part_vertices(&mut self, mesh: &Mesh) {
        // Per vertex: its place in the current part's list, valid while `owner` is that part.
        let mut owner = vec![u32::MAX; mesh.positions.len()];
        let mut place = vec![0u8; mesh.positions.len()];
        self.corners = vec![[0; 3]; mesh.triangle_count()];
        for (p, part) in self.parts.iter_mut().enumerate() {
            let start = self.part_vertices.len();
            for t in part.triangles() {
                for k in 0..3 {
                    let v = mesh.indices[3 * t as usize + k] as usize;
                    if owner[v] != p as u32 {
                        // At most 3 * PART_TRIANGLES = 96 vertices per part: fits a byte.
                        (owner[v], place[v]) = (p as u32, (self.part_vertices.len() - start) as u8);
                        self.part_vertices.push(v as u32);
                    }
                    self.corners[t as usize][k] = place[v];
                }
            }
            part.vertices = (start as u32, self.part_vertices.len() as u32);
        }
    }

    /// The vertices of a part (indices into the mesh's positions).
    pub fn vertices_of(&self, part: &Part) -> &[u32] {
        &self.part_vertices[part.vertices.0 as usize..part.vertices.1 as usize]
    }

    /// The parts of a leaf.
    pub fn parts_of(&self, leaf: u32) -> &[Part] {
        &self.parts[self.part_range(leaf)]
    }

    /// Where the parts of a leaf lie in [`Bvh::parts`].
    pub fn part_range(&self, leaf: u32) -> std::ops::Range<usize> {
        self.leaf_parts[leaf as usize] as usize..self.leaf_parts[leaf as usize + 1] as usize
    }

    /// Index-buffer range (in indices) of a leaf.
    pub fn leaf_range(&self, leaf: u32) -> std::ops::Range<u32> {
        let n = &self.nodes[self.leaves[leaf as usize] as usize];
        3 * n.first..3 * (n.first + n.count)
    }
}

/// A shell's inner surface, in most directions from its centre, lies wholly nearer it than its outer
/// surface: in more than this share of the direction bins holding both (the skull of the default
/// set: 77 %, its lobes of cortex: at most 35 %).
const SHELL_NESTED: f32 = 0.6;
/// Direction bins: per face of a cube around the centre, this many by this many.
const SHELL_BINS: usize = 8;

/// For a shell (a skull: a closed wall around a hollow), reorders `order` so the
/// triangles facing away from the centre of its bounds (its outer surface) come first and returns
/// how many there are; `None` for other solids (nothing reordered). Split this way at the root,
/// the hierarchy keeps the outer surface's near side, which is visible, apart from the inner
/// surface just behind it, so whole subtrees of it lie in front of the occluders and need no
/// further tests.
///
/// A shell, seen from the centre of its bounds, is two nested surfaces: in (almost) every
/// direction the triangles facing the centre lie nearer it than those facing away. A folded sheet
/// (a lobe of cortex) has both kinds at every distance.
fn shell_split(mesh: &Mesh, order: &mut [u32]) -> Option<usize> {
    let centre = mesh.bounds().center();
    let outward = mesh.signed_volume().signum();
    // Per triangle: whether it faces away from the centre, its direction bin and distance.
    let classify = |t: u32| {
        let i = 3 * t as usize;
        let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(mesh.positions[mesh.indices[i + k] as usize]));
        let d = (a + b + c) / 3.0 - centre;
        let out = outward * (b - a).cross(c - a).dot(d) >= 0.0;
        let m = d.abs();
        let axis = if m.x >= m.y && m.x >= m.z {
            0
        } else if m.y >= m.z {
            1
        } else {
            2
        };
        let major = m[axis].max(f32::MIN_POSITIVE);
        let cell = |v: f32| (((v / major + 1.0) * 0.5 * SHELL_BINS as f32) as usize).min(SHELL_BINS - 1);
        let (u, v) = (cell(d[(axis + 1) % 3]), cell(d[(axis + 2) % 3]));
        let face = 2 * axis + usize::from(d[axis] < 0.0);
        (out, (face * SHELL_BINS + u) * SHELL_BINS + v, d.length())
    };
    // Per bin: farthest inward-facing and nearest outward-facing triangle.
    let mut bins = vec![(f32::NEG_INFINITY, f32::INFINITY); 6 * SHELL_BINS * SHELL_BINS];
    let mut facing_out = vec![false; mesh.triangle_count()];
    for &t in order.iter() {
        let (out, bin, r) = classify(t);
        facing_out[t as usize] = out;
        let (inner, outer) = &mut bins[bin];
        if out {
            *outer = outer.min(r);
        } else {
            *inner = inner.max(r);
        }
    }
    let both = bins.iter().filter(|(i, o)| i.is_finite() && o.is_finite());
    let (mixed, nested) = both.fold((0, 0), |(m, n), (i, o)| (m + 1, n + usize::from(i <= o)));
    if mixed == 0 || (nested as f32) < SHELL_NESTED * mixed as f32 {
        return None;
    }
    order.sort_by_key(|&t| !facing_out[t as usize]);
    let outer = facing_out.iter().filter(|&&out| out).count();
    (outer > 0 && outer < order.len()).then_some(outer)
}

/// Neighbours across edges, matching vertices by position so split vertices (seams of normals)
/// still connect.
fn neighbours(mesh: &Mesh) -> Vec<[u32; 3]> {
    let (ids, _) = crate::mesh::weld(&mesh.positions);
    let tris = mesh.triangle_count();
    let corner = |t: usize, k: usize| ids[mesh.indices[3 * t + k] as usize];
    // Directed edge -> triangle, and how often each undirected edge occurs.
    let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(tris * 3);
    let mut undirected: HashMap<(u32, u32), u8> = HashMap::with_capacity(tris * 3 / 2);
    for t in 0..tris {
        for k in 0..3 {
            let (a, b) = (corner(t, k), corner(t, (k + 1) % 3));
            if a == b {
                continue;
            }
            if directed.insert((a, b), t as u32).is_some() {
                // The same directed edge twice: inconsistent winding; make it a border for both.
                directed.insert((a, b), NONE);
            }
            let c = undirected.entry((a.min(b), a.max(b))).or_insert(0);
            *c = c.saturating_add(1);
        }
    }
    (0..tris)
        .map(|t| {
            std::array::from_fn(|k| {
                let (a, b) = (corner(t, k), corner(t, (k + 1) % 3));
                let manifold = undirected.get(&(a.min(b), a.max(b))) == Some(&2);
                let me = directed.get(&(a, b)).copied();
                match (manifold && me != Some(NONE), directed.get(&(b, a))) {
                    (true, Some(&n)) if n != NONE && n != t as u32 => n,
                    _ => NONE,
                }
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cone_faces_away_only_where_every_triangle_does() {
        // A patch facing +z, its normals within 0.3 rad of the axis, inside a 2 mm box at the origin.
        let bounds = Bounds { min: [-1.0; 3], max: [1.0; 3] };
        let cone = Cone { axis: Vec3::Z, spread: 0.3 };
        // Seen from below, far off and straight on: faces away; from above: faces the eye.
        assert!(cone.faces_away(&bounds, Vec3::new(0.0, 0.0, -100.0)));
        assert!(!cone.faces_away(&bounds, Vec3::new(0.0, 0.0, 100.0)));
        // From the side, nearly edge-on for the outermost normals: not (within the margin).
        assert!(!cone.faces_away(&bounds, Vec3::new(100.0, 0.0, -30.0)));
        // Close by, the box's own extent counts: from just below it some normal may face the eye.
        assert!(!cone.faces_away(&bounds, Vec3::new(0.0, 0.0, -1.5)));
        assert!(!Cone::NONE.faces_away(&bounds, Vec3::new(0.0, 0.0, -100.0)));
        // Brute force on a curved patch: wherever its cone says it faces away, every triangle does.
        let tris: Vec<[Vec3; 3]> = (0..16)
            .map(|i| {
                let a = i as f32 * 0.05;
                [Vec3::new(a, 0.0, 0.0), Vec3::new(a + 0.05, 0.0, -0.05 * a), Vec3::new(a, 0.05, 0.0)]
            })
            .collect();
        let axis = tris.iter().map(|[a, b, c]| (b - a).cross(c - a)).sum::<Vec3>().normalize();
        let cone = Cone::of(tris.iter().copied(), axis);
        let mut b = Bounds::EMPTY;
        tris.iter().flatten().for_each(|p| b.include(p.to_array()));
        let mut rng = crate::rng::XorShift(7);
        let mut away = 0;
        for _ in 0..2000 {
            let r = |rng: &mut crate::rng::XorShift| (rng.next_u64() % 2001) as f32 / 100.0 - 10.0;
            let eye = Vec3::new(r(&mut rng), r(&mut rng), r(&mut rng));
            if cone.faces_away(&b, eye) {
                away += 1;
                assert!(tris.iter().all(|[a, b, c]| (b - a).cross(c - a).dot(eye - *a) < 0.0), "{eye}");
            }
        }
        assert!(away > 100, "only {away} eyes see the patch facing away");
    }
    use crate::organ_set::scale::subdivide;

    fn icosphere(level: usize) -> Mesh {
        // An octahedron subdivided: closed, consistently wound.
        subdivide(&Mesh::octahedron(), level)
    }

    #[test]
    fn leaves_are_small_contiguous_and_bounded() {
        // 8 * 144 = 1152 triangles, compared by their corners' positions (vertices are renumbered).
        let mut m = icosphere(12);
        let corners = |m: &Mesh| -> Vec<[[u32; 3]; 3]> {
            let mut t: Vec<_> = m
                .indices
                .chunks_exact(3)
                .map(|t| [0, 1, 2].map(|k| m.positions[t[k] as usize].map(f32::to_bits)))
                .collect();
            t.sort();
            t
        };
        let before = corners(&m);
        let bvh = Bvh::build(&mut m);
        assert_eq!(before, corners(&m), "same triangles, reordered");
        // Vertices in order of first use.
        let mut next = 0;
        for &v in &m.indices {
            assert!(v <= next, "vertex {v} used before {next}");
            next = next.max(v + 1);
        }
        assert_eq!(next as usize, m.positions.len());
        let mut covered = 0;
        for (l, &n) in bvh.leaves.iter().enumerate() {
            let node = &bvh.nodes[n as usize];
            assert!(node.count as usize <= LEAF_TRIANGLES && node.count > 0);
            assert_eq!(node.first, covered, "leaves tile the triangles in order");
            covered += node.count;
            assert_eq!(bvh.leaf_range(l as u32), 3 * node.first..3 * (node.first + node.count));
            for t in node.first..node.first + node.count {
                assert_eq!(bvh.leaf_of[t as usize], l as u32);
                for k in 0..3 {
                    let p = m.positions[m.indices[3 * t as usize + k] as usize];
                    let b = node.bounds;
                    assert!((0..3).all(|i| b.min[i] <= p[i] && p[i] <= b.max[i]));
                    let d = node.slab.normal.dot(Vec3::from(p));
                    assert!(node.slab.min <= d && d <= node.slab.max);
                }
            }
        }
        assert_eq!(covered as usize, m.triangle_count());
        // Parts tile each leaf in order, bounded.
        for (l, &n) in bvh.leaves.iter().enumerate() {
            let node = &bvh.nodes[n as usize];
            let mut at = node.first;
            for part in bvh.parts_of(l as u32) {
                assert!(part.count as usize <= PART_TRIANGLES && part.count > 0);
                let vertices = bvh.vertices_of(part);
                for t in part.triangles() {
                    let corners = bvh.corners[t as usize].map(|c| vertices[c as usize]);
                    assert_eq!(corners, std::array::from_fn(|k| m.indices[3 * t as usize + k]));
                }
                assert_eq!(part.first, at);
                at += part.count;
                for t in part.triangles() {
                    for k in 0..3 {
                        let p = m.positions[m.indices[3 * t as usize + k] as usize];
                        assert!((0..3).all(|i| part.bounds.min[i] <= p[i] && p[i] <= part.bounds.max[i]));
                        let d = part.slab.normal.dot(Vec3::from(p));
                        assert!(part.slab.min <= d && d <= part.slab.max);
                    }
                }
            }
            assert_eq!(at, node.first + node.count);
        }
        // Parents contain children.
        for n in &bvh.nodes {
            for &c in n.children.iter().filter(|&&c| c != NONE) {
                let cb = bvh.nodes[c as usize].bounds;
                assert!((0..3).all(|i| n.bounds.min[i] <= cb.min[i] && cb.max[i] <= n.bounds.max[i]));
            }
        }
    }

    #[test]
    fn a_shell_splits_its_outer_surface_from_its_inner_one_at_the_root() {
        // A hollow octahedron (subdivided): one of radius 1 and, wound the other way, one of 0.8.
        let outer = icosphere(8);
        let mut inner = icosphere(8);
        inner.positions.iter_mut().for_each(|p| *p = p.map(|c| 0.8 * c));
        inner.indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
        let mut shell = outer.clone();
        shell.append(&inner);
        let bvh = Bvh::build(&mut shell);
        let root = &bvh.nodes[0];
        let [a, b] = root.children.map(|c| &bvh.nodes[c as usize]);
        assert_eq!((a.count as usize, b.count as usize), (outer.triangle_count(), inner.triangle_count()));
        // The outer child holds only the outer surface, the inner one only the inner (radius as
        // |x| + |y| + |z|, constant over an octahedron).
        let radius = |n: &Node| {
            (3 * n.first..3 * (n.first + n.count))
                .map(|i| Vec3::from(shell.positions[shell.indices[i as usize] as usize]).abs().element_sum())
                .fold((f32::INFINITY, 0.0f32), |(lo, hi), r| (lo.min(r), hi.max(r)))
        };
        assert!(radius(a).0 > 0.999 && radius(b).1 < 0.801, "{:?} {:?}", radius(a), radius(b));
        // A solid ball is not a shell: its root splits in space, into halves.
        let mut ball = icosphere(8);
        let bvh = Bvh::build(&mut ball);
        let [a, b] = bvh.nodes[0].children.map(|c| bvh.nodes[c as usize].count);
        assert_eq!(a + b, ball.triangle_count() as u32);
        assert!(a.abs_diff(b) <= 1);
    }

    #[test]
    fn neighbours_of_a_closed_mesh_are_mutual() {
        let mut m = icosphere(3);
        let bvh = Bvh::build(&mut m);
        for (t, ns) in bvh.neighbours.iter().enumerate() {
            for &n in ns {
                assert_ne!(n, NONE, "a closed mesh has no border");
                assert!(bvh.neighbours[n as usize].contains(&(t as u32)));
            }
        }
        // Split every vertex (as per-face normals do): neighbours still found by position.
        let mut split = Mesh::default();
        for t in m.indices.chunks_exact(3) {
            let base = split.positions.len() as u32;
            for &i in t {
                split.positions.push(m.positions[i as usize]);
                split.normals.push(m.normals[i as usize]);
            }
            split.indices.extend([base, base + 1, base + 2]);
        }
        let b2 = Bvh::build(&mut split);
        assert!(b2.neighbours.iter().flatten().all(|&n| n != NONE));
        // Open a hole: its rim becomes border.
        let mut open = m.clone();
        open.indices.truncate(open.indices.len() - 3);
        let b3 = Bvh::build(&mut open);
        assert_eq!(b3.neighbours.iter().flatten().filter(|&&n| n == NONE).count(), 3);
    }
}
