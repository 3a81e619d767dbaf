//! A mesh cut by clip planes on the CPU, for export: what the renderer's shaders discard is removed
//! from the triangles, and a closed mesh gets solid cap faces on each plane, as the renderer's
//! `caps` pipeline draws them (issue: cross-sections).
//!
//! - Positions in whatever space the planes are given in (organ space for export, millimetres
//!   RAS); a plane removes `n · p > d` ([`ClipPlane`]).
//! - Triangles are clipped against each plane in turn (Sutherland-Hodgman on a convex polygon,
//!   fanned back into triangles).
//! - A cap is the mesh's cross-section with one plane: the segments where its triangles cross the
//!   plane, chained into loops by the edges they lie on, nested by even-odd depth into outlines
//!   with holes, triangulated by earcut, turned to face the removed side and clipped by the other
//!   planes.

use crate::clip::{self, ClipPlane};
use crate::mesh::Mesh;
use glam::{Vec2, Vec3};
use std::collections::HashMap;

/// `mesh` with what `planes` remove cut away; with `caps` (for closed meshes) the cut faces are
/// filled. `None` where no plane removes any of it; a mesh wholly removed comes back empty.
pub fn cut(mesh: &Mesh, planes: &[ClipPlane], caps: bool) -> Option<Mesh> {
    let removes_any = |p: &ClipPlane| mesh.positions.iter().any(|&q| p.removes(Vec3::from(q)));
    if !planes.iter().any(removes_any) {
        return None;
    }
    let mut out = clip_triangles(mesh, planes);
    if caps {
        for (i, plane) in planes.iter().enumerate() {
            let others: Vec<ClipPlane> = planes.iter().enumerate().filter(|&(j, _)| j != i).map(|(_, p)| *p).collect();
            let cap = clip_triangles(&cap(mesh, plane), &others);
            out.append(&cap);
        }
    }
    Some(compact(out))
}

/// A vertex being clipped: position and normal.
#[derive(Clone, Copy)]
struct Vertex {
    p: Vec3,
    n: Vec3,
}

impl clip::Corner for Vertex {
    fn position(self) -> Vec3 {
        self.p
    }
    fn lerp(self, other: Vertex, t: f32) -> Vertex {
        Vertex { p: self.p.lerp(other.p, t), n: self.n.lerp(other.n, t) }
    }
}

/// Clips every triangle of `mesh` by every plane. Triangles no plane touches keep their vertices;
/// cut ones get new vertices of their own.
fn clip_triangles(mesh: &Mesh, planes: &[ClipPlane]) -> Mesh {
    let mut out = Mesh { positions: mesh.positions.clone(), normals: mesh.normals.clone(), indices: Vec::new() };
    let vertex = |i: u32| Vertex { p: Vec3::from(mesh.positions[i as usize]), n: Vec3::from(mesh.normals[i as usize]) };
    for tri in mesh.indices.chunks_exact(3) {
        let corners = [vertex(tri[0]), vertex(tri[1]), vertex(tri[2])];
        let touched = planes.iter().any(|pl| corners.iter().any(|v| pl.removes(v.p)));
        if !touched {
            out.indices.extend_from_slice(tri);
            continue;
        }
        let mut poly = corners.to_vec();
        for plane in planes {
            poly = clip::clip_polygon(&poly, (plane.normal(), plane.d));
            if poly.len() < 3 {
                break;
            }
        }
        if poly.len() < 3 {
            continue;
        }
        // Unit normals, as glTF requires: where two interpolated ones cancel, the face's.
        let face = (corners[1].p - corners[0].p).cross(corners[2].p - corners[0].p).normalize_or(Vec3::Z);
        let base = out.positions.len() as u32;
        for v in &poly {
            out.positions.push(v.p.into());
            out.normals.push(v.n.try_normalize().unwrap_or(face).into());
        }
        for k in 1..poly.len() as u32 - 1 {
            out.indices.extend_from_slice(&[base, base + k, base + k + 1]);
        }
    }
    out
}

/// The cap of `mesh` on `plane`: its cross-section filled, facing the removed side (+normal).
/// Only closed loops are filled; an open mesh's loose ends are left open.
fn cap(mesh: &Mesh, plane: &ClipPlane) -> Mesh {
    let n = plane.normal();
    let loops = section_loops(mesh, plane);
    // A frame in the plane: u, v with u x v = n.
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let origin = n * plane.d;
    let flat: Vec<Vec<Vec2>> = loops
        .iter()
        .map(|l| l.iter().map(|&p| Vec2::new((p - origin).dot(u), (p - origin).dot(v))).collect())
        .collect();
    let mut out = Mesh::default();
    // Even-odd nesting: a loop inside an even number of others is an outline, else a hole of the
    // innermost outline around it.
    let depth: Vec<usize> = (0..flat.len())
        .map(|i| (0..flat.len()).filter(|&j| j != i && contains(&flat[j], flat[i][0])).count())
        .collect();
    for outer in (0..flat.len()).filter(|&i| depth[i].is_multiple_of(2)) {
        let holes: Vec<usize> =
            (0..flat.len()).filter(|&h| depth[h] == depth[outer] + 1 && contains(&flat[outer], flat[h][0])).collect();
        let mut coords: Vec<[f64; 2]> = flat[outer].iter().map(|p| [f64::from(p.x), f64::from(p.y)]).collect();
        let mut hole_starts = Vec::new();
        for &h in &holes {
            hole_starts.push(coords.len());
            coords.extend(flat[h].iter().map(|p| [f64::from(p.x), f64::from(p.y)]));
        }
        let points: Vec<Vec3> =
            std::iter::once(outer).chain(holes.iter().copied()).flat_map(|k| loops[k].iter().copied()).collect();
        let mut triangles = Vec::new();
        earcut::Earcut::new().earcut(coords.iter().copied(), &hole_starts, &mut triangles);
        let base = out.positions.len() as u32;
        out.positions.extend(points.iter().map(|&p| <[f32; 3]>::from(p)));
        out.normals.extend(points.iter().map(|_| <[f32; 3]>::from(n)));
        for t in triangles.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]];
            let facing = (points[b] - points[a]).cross(points[c] - points[a]).dot(n);
            let tri = if facing >= 0.0 { [a, b, c] } else { [a, c, b] };
            out.indices.extend(tri.iter().map(|&k| base + k as u32));
        }
    }
    out
}

/// Where `plane` crosses `mesh`, as closed loops of points. A triangle crossing the plane gives one
/// segment between two of its edges; segments meet at shared edges (by vertex index), which chains
/// them without comparing floats.
fn section_loops(mesh: &Mesh, plane: &ClipPlane) -> Vec<Vec<Vec3>> {
    let vertex = |i: u32| Vertex { p: Vec3::from(mesh.positions[i as usize]), n: Vec3::ZERO };
    let removed: Vec<bool> = mesh.positions.iter().map(|&p| plane.removes(Vec3::from(p))).collect();
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let point_on = |a: u32, b: u32| clip::crossing(vertex(a), vertex(b), (plane.normal(), plane.d)).p;
    // Each segment runs from the edge where the triangle's boundary leaves the kept side to the one
    // where it comes back, so loops run one way round.
    let mut next: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
    let mut points: HashMap<(u32, u32), Vec3> = HashMap::new();
    for tri in mesh.indices.chunks_exact(3) {
        let mut leave = None;
        let mut enter = None;
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            match (removed[a as usize], removed[b as usize]) {
                (false, true) => leave = Some(key(a, b)),
                (true, false) => enter = Some(key(a, b)),
                _ => {}
            }
        }
        if let (Some(l), Some(e)) = (leave, enter) {
            for k in [l, e] {
                points.entry(k).or_insert_with(|| point_on(k.0, k.1));
            }
            next.insert(l, e);
        }
    }
    let mut loops = Vec::new();
    let mut starts: Vec<(u32, u32)> = next.keys().copied().collect();
    starts.sort_unstable();
    for start in starts {
        if !next.contains_key(&start) {
            continue;
        }
        let mut ring = Vec::new();
        let mut at = start;
        let closed = loop {
            let Some(to) = next.remove(&at) else { break false };
            ring.push(points[&at]);
            at = to;
            if at == start {
                break true;
            }
        };
        if closed && ring.len() >= 3 {
            loops.push(ring);
        }
    }
    loops
}

/// Whether `p` lies inside the polygon `poly` (even-odd rule).
fn contains(poly: &[Vec2], p: Vec2) -> bool {
    let mut inside = false;
    let mut j = poly.len() - 1;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
            inside = !inside;
        }
        j = i;
    }
    inside
}

/// Drops vertices no triangle uses, keeping the order of the rest.
fn compact(mesh: Mesh) -> Mesh {
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    let mut out = Mesh::default();
    for &i in &mesh.indices {
        if remap[i as usize] == u32::MAX {
            remap[i as usize] = out.positions.len() as u32;
            out.positions.push(mesh.positions[i as usize]);
            out.normals.push(mesh.normals[i as usize]);
        }
        out.indices.push(remap[i as usize]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closed, outward-facing box from `lo` to `hi`.
    fn cuboid(lo: Vec3, hi: Vec3) -> Mesh {
        let mut m = Mesh::default();
        for k in 0..8 {
            let pick = |bit: usize, axis: usize| if k & bit != 0 { hi[axis] } else { lo[axis] };
            m.positions.push([pick(1, 0), pick(2, 1), pick(4, 2)]);
        }
        // Faces as quads of corner indices, counter-clockwise seen from outside.
        for [a, b, c, d] in [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]] {
            m.indices.extend_from_slice(&[a, b, c, a, c, d]);
        }
        m.compute_normals();
        m
    }

    fn plane(normal: Vec3, d: f32) -> ClipPlane {
        ClipPlane::new(normal, d).unwrap()
    }

    #[test]
    fn a_box_cut_in_half_stays_closed_with_half_its_volume() {
        let cube = cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
        assert!(cube.is_closed_outward());
        let cut = cut(&cube, &[plane(Vec3::Z, 0.0)], true).unwrap();
        assert!((cut.signed_volume() - 4.0).abs() < 1e-4, "{}", cut.signed_volume());
        assert!(cut.positions.iter().all(|p| p[2] <= 1e-6));
        assert_eq!(cut.open_edges(), 0, "the cap closes the cut");
        // Without caps the cut is open.
        assert!(super::cut(&cube, &[plane(Vec3::Z, 0.0)], false).unwrap().open_edges() > 0);
    }

    #[test]
    fn two_planes_leave_a_quarter_and_a_hollow_box_gets_a_ring() {
        let cube = cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
        let quarter = cut(&cube, &[plane(Vec3::Z, 0.0), plane(Vec3::X, 0.0)], true).unwrap();
        assert!((quarter.signed_volume() - 2.0).abs() < 1e-4, "{}", quarter.signed_volume());
        // A box with a box-shaped hole (inner faces inward): the cap is a ring, volume 8 - 1 halved.
        let mut hollow = cube.clone();
        let mut inner = cuboid(Vec3::splat(-0.5), Vec3::splat(0.5));
        for t in inner.indices.chunks_exact_mut(3) {
            t.swap(1, 2);
        }
        hollow.append(&inner);
        let half = cut(&hollow, &[plane(Vec3::Z, 0.0)], true).unwrap();
        assert!((half.signed_volume() - 3.5).abs() < 1e-4, "{}", half.signed_volume());
    }

    #[test]
    fn untouched_and_wholly_removed_meshes() {
        let cube = cuboid(Vec3::splat(-1.0), Vec3::splat(1.0));
        assert_eq!(cut(&cube, &[plane(Vec3::Z, 5.0)], true), None);
        assert_eq!(cut(&cube, &[plane(Vec3::Z, -5.0)], true).map(|m| m.indices.len()), Some(0));
    }
}
