//! Occluder stand-ins built from an organ's own closed surface: meshes of fewer triangles inside
//! the organ's solid, which the culler may rasterise in place of the organ.
//!
//! - Organ space, millimetres.
//! - Seen from outside the organ, a stand-in hides nothing the organ does not hide: a ray from the
//!   eye to a point inside the solid crosses the organ's surface first.
//! - [`build_inner`] makes one in three steps:
//! 1. The surface's vertices (welded by position) move inward along their normals to the middle of
//!    the solid there (half the distance to the surface across, found by a ray), at most `offset`.
//! 2. meshoptimizer simplifies that inner surface towards the target triangle count, within an
//!    absolute error of half the offset.
//! 3. Every triangle of the result is verified: it keeps a margin from every triangle of the
//!    surface (a separating-axis test) and its centre is inside (ray parity, three rays agreeing).
//!    One that fails is left out, so the stand-in never rests on the simplifier's error bound.

use super::StandIn;
use crate::bvh::Bvh;
use crate::mesh::{ray_triangle, Bounds, Mesh};
use glam::Vec3;

/// How a stand-in is made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InnerOptions {
    /// Triangles to simplify towards.
    pub triangles: usize,
    /// Most inward offset, in millimetres.
    pub offset: f32,
}

/// A stand-in and what verification left out.
#[derive(Clone, Debug)]
pub struct Inner {
    pub stand_in: StandIn,
    /// Triangles of the simplified surface that failed verification.
    pub dropped: usize,
}

/// Why an organ gets no stand-in.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum StandInError {
    #[error("not a closed surface ({0} edges with no matching edge the other way)")]
    NotClosed(usize),
    #[error("cannot simplify: {0}")]
    Simplify(String),
}

/// Builds a verified inner stand-in for a closed surface (`bvh` built over `mesh`).
pub fn build_inner(mesh: &Mesh, bvh: &Bvh, options: InnerOptions) -> Result<Inner, StandInError> {
    let (positions, indices) = welded(mesh);
    let open = mesh.open_edges();
    if open > 0 || indices.is_empty() {
        return Err(StandInError::NotClosed(open));
    }
    let surface = Surface { mesh, bvh, margin: 1e-4 * mesh.bounds().size().max_element() };
    // Outward is where the triangles wind counter-clockwise.
    let outward = if mesh.signed_volume() < 0.0 { -1.0 } else { 1.0 };
    let mut normals = vec![Vec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| positions[t[k] as usize]);
        let n = (b - a).cross(c - a);
        for &v in t {
            normals[v as usize] += n;
        }
    }
    use rayon::prelude::*;
    let inner: Vec<[f32; 3]> = positions
        .par_iter()
        .zip(&normals)
        .map(|(&p, &n)| {
            let inward = -outward * n.normalize_or_zero();
            let across = surface.nearest_hit(p, inward).unwrap_or(0.0);
            (p + inward * (0.5 * across).min(options.offset)).to_array()
        })
        .collect();
    let bytes: &[u8] = bytemuck::cast_slice(&inner);
    let adapter = meshopt::VertexDataAdapter::new(bytes, 12, 0).map_err(|e| StandInError::Simplify(e.to_string()))?;
    let simplified = meshopt::simplify(
        &indices,
        &adapter,
        options.triangles * 3,
        0.5 * options.offset,
        meshopt::SimplifyOptions::ErrorAbsolute,
        None,
    );
    let kept: Vec<[u32; 3]> = simplified
        .par_chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .filter(|t| surface.holds(t.map(|v| Vec3::from(inner[v as usize]))))
        .collect();
    let dropped = simplified.len() / 3 - kept.len();
    let mut out = Mesh { positions: inner, normals: Vec::new(), indices: kept.into_iter().flatten().collect() };
    crate::surface::compact(&mut out);
    out.compute_normals();
    Ok(Inner { stand_in: StandIn::new(out), dropped })
}

/// The boundary of the union of closed surfaces that meet face to face (as a seamless set's organs
/// do): their triangles with vertices welded by position, less each pair of coincident triangles
/// wound opposite ways (a face two of them share, inside the union). Triangles that lose their area
/// in the welding are left out.
pub fn union_surface(meshes: &[&Mesh]) -> Mesh {
    let mut all = Mesh::default();
    for m in meshes {
        all.append(m);
    }
    let (positions, indices) = welded(&all);
    // Per triangle: its corners rotated to start at the least, and whether the rest ascend.
    let key = |t: &[u32]| {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
        let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
        ((a, b.min(c), b.max(c)), b < c)
    };
    let mut count: std::collections::HashMap<(u32, u32, u32), [u32; 2]> = std::collections::HashMap::new();
    for t in indices.chunks_exact(3) {
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            let (k, up) = key(t);
            count.entry(k).or_default()[usize::from(up)] += 1;
        }
    }
    // Of each face, as many of the more frequent winding as it has beyond the other.
    let mut kept: Vec<u32> = Vec::new();
    for t in indices.chunks_exact(3) {
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            continue;
        }
        let (k, up) = key(t);
        let Some(c) = count.get_mut(&k) else { continue };
        let (this, other) = (usize::from(up), 1 - usize::from(up));
        if c[this] > c[other] {
            c[this] -= 1;
            kept.extend_from_slice(t);
        }
    }
    let mut out =
        Mesh { positions: positions.iter().map(|p| p.to_array()).collect(), normals: Vec::new(), indices: kept };
    crate::surface::compact(&mut out);
    out.compute_normals();
    out
}

/// Vertices welded by position, and the triangles over them.
fn welded(mesh: &Mesh) -> (Vec<Vec3>, Vec<u32>) {
    let (remap, positions) = crate::mesh::weld(&mesh.positions);
    (positions.into_iter().map(Vec3::from).collect(), mesh.indices.iter().map(|&i| remap[i as usize]).collect())
}

/// A closed surface with its hierarchy, for ray and proximity queries.
struct Surface<'a> {
    mesh: &'a Mesh,
    bvh: &'a Bvh,
    /// Distances below this count as touching.
    margin: f32,
}

impl Surface<'_> {
    fn triangle(&self, t: u32) -> [Vec3; 3] {
        self.mesh.triangle(t as usize)
    }

    /// Calls `visit` with each triangle whose leaf's box passes `near`.
    fn each_triangle(&self, near: impl Fn(&Bounds) -> bool, mut visit: impl FnMut(u32)) {
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let node = &self.bvh.nodes[n as usize];
            if !near(&node.bounds) {
                continue;
            }
            if node.is_leaf() {
                (node.first..node.first + node.count).for_each(&mut visit);
            } else {
                stack.extend(node.children);
            }
        }
    }

    /// Distances along the ray `origin + t dir` (t > margin) at which it crosses the surface.
    fn hits(&self, origin: Vec3, dir: Vec3) -> Vec<f32> {
        let mut out = Vec::new();
        self.each_triangle(
            |b| ray_meets_box(origin, dir, b),
            |t| {
                if let Some(d) = ray_triangle(origin, dir, self.triangle(t)).filter(|&d| d > self.margin) {
                    out.push(d);
                }
            },
        );
        out
    }

    fn nearest_hit(&self, origin: Vec3, dir: Vec3) -> Option<f32> {
        self.hits(origin, dir).into_iter().reduce(f32::min)
    }

    /// Is the triangle wholly inside: apart from every surface triangle, its centre inside?
    fn holds(&self, tri: [Vec3; 3]) -> bool {
        let mut bounds = Bounds::EMPTY;
        tri.iter().for_each(|p| bounds.include(p.to_array()));
        let m = self.margin;
        let mut apart = true;
        self.each_triangle(
            |b| (0..3).all(|k| b.min[k] - m <= bounds.max[k] && bounds.min[k] <= b.max[k] + m),
            |t| apart &= separated(&tri, &self.triangle(t), m),
        );
        let centre = (tri[0] + tri[1] + tri[2]) / 3.0;
        // Three rays in unrelated directions must all cross an odd number of times.
        apart
            && [Vec3::new(0.5773, 0.6172, 0.5345), Vec3::new(-0.2673, 0.8018, -0.5345), Vec3::new(0.69, -0.42, -0.59)]
                .iter()
                .all(|&d| self.hits(centre, d.normalize()).len() % 2 == 1)
    }
}

/// Slab test: does the ray (t >= 0) meet the box?
fn ray_meets_box(origin: Vec3, dir: Vec3, b: &Bounds) -> bool {
    crate::mesh::ray_box_entry(origin, dir.recip(), b).is_some()
}

/// Separating-axis test of two triangles: is there an axis (a face normal or a cross product of
/// edges) along which they lie more than `margin` apart? Coplanar triangles are never separated
/// here (their in-plane axes are not tried), which only leaves more out.
fn separated(a: &[Vec3; 3], b: &[Vec3; 3], margin: f32) -> bool {
    let edges = |t: &[Vec3; 3]| [t[1] - t[0], t[2] - t[1], t[0] - t[2]];
    let (ea, eb) = (edges(a), edges(b));
    let mut axes = vec![ea[0].cross(ea[1]), eb[0].cross(eb[1])];
    for i in 0..3 {
        for j in 0..3 {
            axes.push(ea[i].cross(eb[j]));
        }
    }
    let interval = |t: &[Vec3; 3], n: Vec3| {
        let d = t.map(|p| p.dot(n));
        (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]))
    };
    axes.into_iter().any(|axis| {
        let n = axis.normalize_or_zero();
        if n == Vec3::ZERO {
            return false;
        }
        let ((a0, a1), (b0, b1)) = (interval(a, n), interval(b, n));
        a1 + margin < b0 || b1 + margin < a0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_union_of_two_boxes_sharing_a_face_is_their_outside() {
        // Two 2 x 2 x 2 boxes side by side along x share the face x = 0 (each split 2 x 2).
        let shifted = |dx: f32| {
            let mut m = crate::mesh::split_box(2, Vec3::ONE);
            m.positions.iter_mut().for_each(|p| p[0] += dx);
            m
        };
        let (a, b) = (shifted(-1.0), shifted(1.0));
        let union = union_surface(&[&a, &b]);
        // 12 faces of 8 triangles less the shared face of each.
        assert_eq!(union.triangle_count(), 2 * 48 - 2 * 8);
        assert_eq!(union.open_edges(), 0, "the union is closed");
        assert!((union.signed_volume() - 16.0).abs() < 1e-3, "volume {}", union.signed_volume());
        // Boxes apart keep every triangle.
        assert_eq!(union_surface(&[&shifted(-2.0), &shifted(2.0)]).triangle_count(), 2 * 48);
    }

    fn inside_box(p: Vec3, half: Vec3) -> bool {
        (0..3).all(|k| p[k].abs() < half[k])
    }

    #[test]
    fn cube_stand_in_is_inside_and_smaller() {
        let half = Vec3::new(10.0, 8.0, 6.0);
        let mut mesh = crate::mesh::split_box(12, half);
        let bvh = Bvh::build(&mut mesh);
        assert!(mesh.signed_volume() > 0.0);
        let built = build_inner(&mesh, &bvh, InnerOptions { triangles: 48, offset: 1.0 }).unwrap();
        let s = &built.stand_in.mesh;
        assert!(s.triangle_count() > 0 && s.triangle_count() <= 200, "{} triangles", s.triangle_count());
        for p in &s.positions {
            assert!(inside_box(Vec3::from(*p), half), "{p:?} outside");
        }
        // It still spans most of the box.
        let b = s.bounds();
        assert!(b.size().x > 15.0, "{b:?}");
    }

    #[test]
    fn shell_stand_in_stays_inside_the_wall() {
        // A hollow box: outer surface outward, inner surface facing the cavity (wound inward).
        let (outer, inner) = (Vec3::splat(10.0), Vec3::splat(8.0));
        let mut mesh = crate::mesh::split_box(10, outer);
        let mut hole = crate::mesh::split_box(8, inner);
        hole.indices.chunks_exact_mut(3).for_each(|t| t.swap(1, 2));
        mesh.append(&hole);
        mesh.compute_normals();
        let bvh = Bvh::build(&mut mesh);
        let built = build_inner(&mesh, &bvh, InnerOptions { triangles: 100, offset: 3.0 }).unwrap();
        let s = &built.stand_in.mesh;
        assert!(s.triangle_count() > 0);
        // Every vertex in the wall (between 8 and 10 from the centre along some axis).
        for p in &s.positions {
            let p = Vec3::from(*p);
            assert!(inside_box(p, outer) && !inside_box(p, inner - Vec3::splat(1e-3)), "{p:?} outside the wall");
        }
        // Offsets capped by half the wall's thickness: about 9 from the centre.
        let b = s.bounds();
        assert!((b.max[0] - 9.0).abs() < 0.2, "{b:?}");
    }

    #[test]
    fn a_triangle_crossing_the_surface_is_left_out() {
        let half = Vec3::splat(5.0);
        let mut mesh = crate::mesh::split_box(4, half);
        let bvh = Bvh::build(&mut mesh);
        let s = Surface { mesh: &mesh, bvh: &bvh, margin: 1e-3 };
        let inside = [Vec3::new(-1., -1., 0.), Vec3::new(1., -1., 0.), Vec3::new(0., 1., 0.)];
        assert!(s.holds(inside));
        let crossing = [Vec3::new(-1., -1., 0.), Vec3::new(7., -1., 0.), Vec3::new(0., 1., 0.)];
        assert!(!s.holds(crossing));
        let outside = inside.map(|p| p + Vec3::new(20.0, 0.0, 0.0));
        assert!(!s.holds(outside));
        // Touching the surface within the margin counts as crossing it.
        let touching = [Vec3::new(-1., -1., 0.), Vec3::new(5.0 - 1e-4, -1., 0.), Vec3::new(0., 1., 0.)];
        assert!(!s.holds(touching));
    }

    #[test]
    fn open_surfaces_are_refused() {
        let mut mesh = crate::mesh::split_box(2, Vec3::ONE);
        mesh.indices.truncate(mesh.indices.len() - 3);
        let bvh = Bvh::build(&mut mesh);
        let err = build_inner(&mesh, &bvh, InnerOptions { triangles: 8, offset: 0.1 }).unwrap_err();
        assert!(matches!(err, StandInError::NotClosed(n) if n > 0), "{err}");
    }
}
