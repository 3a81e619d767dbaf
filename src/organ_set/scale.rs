//! Scaled scenes for benchmarks: a denser copy of a set made by subdividing every triangle into
//! n x n smaller ones in its own plane.
//!
//! - Organ space; the shape is unchanged, only the count grows.
//! - For a requested density factor, `n = round(sqrt(factor))`, so the achieved factor is `n * n`.
//! - Vertices on an original edge are shared by both triangles of that edge, keeping the mesh
//!   closed where it was.

use super::OrganSet;
use crate::mesh::Mesh;
use glam::Vec3;
use std::collections::HashMap;

/// The subdivision level for a requested density factor: each triangle becomes `n * n` triangles
/// with `n = round(sqrt(factor))`, so the achieved factor is `n * n`.
pub fn level_for_factor(factor: f64) -> usize {
    factor.max(1.0).sqrt().round().max(1.0) as usize
}

/// Splits every triangle into `n * n` triangles. Vertices on an original edge are shared by both
/// triangles of that edge (computed from the edge's lower index, so bit-identical), keeping the mesh
/// closed where it was.
pub fn subdivide(mesh: &Mesh, n: usize) -> Mesh {
    if n <= 1 {
        return mesh.clone();
    }
    let mut out = Mesh { positions: mesh.positions.clone(), normals: mesh.normals.clone(), indices: Vec::new() };
    out.indices.reserve(mesh.indices.len() * n * n);
    let mut edge_points: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    let lerp_vertex = |out: &mut Mesh, a: u32, b: u32, t: f32| {
        let (pa, pb) = (Vec3::from(mesh.positions[a as usize]), Vec3::from(mesh.positions[b as usize]));
        let (na, nb) = (Vec3::from(mesh.normals[a as usize]), Vec3::from(mesh.normals[b as usize]));
        out.positions.push(pa.lerp(pb, t).to_array());
        out.normals.push(na.lerp(nb, t).try_normalize().unwrap_or(na).to_array());
        out.positions.len() as u32 - 1
    };
    for t in mesh.indices.chunks_exact(3) {
        let (a, b, c) = (t[0], t[1], t[2]);
        // Point (i, j) of the triangle's lattice, i along a->b, j along a->c, i + j <= n.
        let mut grid = vec![u32::MAX; (n + 1) * (n + 1)];
        let idx = |i: usize, j: usize| i * (n + 1) + j;
        grid[idx(0, 0)] = a;
        grid[idx(n, 0)] = b;
        grid[idx(0, n)] = c;
        // Edge points, shared through the map; edge (u, v) stores points from min(u, v) outward.
        for (u, v, at) in [(a, b, 0usize), (b, c, 1), (c, a, 2)] {
            let key = (u.min(v), u.max(v));
            let pts = edge_points
                .entry(key)
                .or_insert_with(|| (1..n).map(|k| lerp_vertex(&mut out, key.0, key.1, k as f32 / n as f32)).collect())
                .clone();
            for k in 1..n {
                // k-th point from u toward v.
                let p = if u == key.0 { pts[k - 1] } else { pts[n - k - 1] };
                let (i, j) = match at {
                    0 => (k, 0),
                    1 => (n - k, k),
                    _ => (0, n - k),
                };
                grid[idx(i, j)] = p;
            }
        }
        let (pa, pb, pc) = (
            Vec3::from(mesh.positions[a as usize]),
            Vec3::from(mesh.positions[b as usize]),
            Vec3::from(mesh.positions[c as usize]),
        );
        let (na, nb, nc) = (
            Vec3::from(mesh.normals[a as usize]),
            Vec3::from(mesh.normals[b as usize]),
            Vec3::from(mesh.normals[c as usize]),
        );
        for i in 1..n {
            for j in 1..n - i {
                let (s, r) = (i as f32 / n as f32, j as f32 / n as f32);
                let w = 1.0 - s - r;
                out.positions.push((pa * w + pb * s + pc * r).to_array());
                out.normals.push((na * w + nb * s + nc * r).try_normalize().unwrap_or(na).to_array());
                grid[idx(i, j)] = out.positions.len() as u32 - 1;
            }
        }
        for i in 0..n {
            for j in 0..n - i {
                out.indices.extend_from_slice(&[grid[idx(i, j)], grid[idx(i + 1, j)], grid[idx(i, j + 1)]]);
                if i + j + 1 < n {
                    out.indices.extend_from_slice(&[grid[idx(i + 1, j)], grid[idx(i + 1, j + 1)], grid[idx(i, j + 1)]]);
                }
            }
        }
    }
    out
}

/// A copy of the set with every organ subdivided to level `n`; `progress` hears of each organ.
/// Each organ keeps its original mesh (or its stand-in) as occluder stand-in: it lies exactly on
/// the subdivided surface with `n * n` times fewer triangles.
/// What a copy at level `n` will hold, estimated before any work (upper bounds).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Estimate {
    pub triangles: u64,
    /// Vertices of the organ with the most: a mesh indexes them with 32 bits.
    pub largest_organ_vertices: u64,
    /// Bytes in memory for the copy: vertices (position and normal), indices and hierarchy.
    pub memory_bytes: u64,
}

/// The copy of `set` at level `n`: per organ, each of F triangles gives n^2, and at most
/// 3F(n-1) + F(n-1)(n-2)/2 new vertices (each edge counted once per triangle).
pub fn estimate(set: &OrganSet, n: usize) -> Estimate {
    let n = n.max(1) as u64;
    let mut e = Estimate { triangles: 0, largest_organ_vertices: 0, memory_bytes: 0 };
    for o in &set.organs {
        let (v, f) = (o.mesh().positions.len() as u64, o.mesh().triangle_count() as u64);
        let vertices = v + 3 * f * (n - 1) + f * (n - 1) * n.saturating_sub(2) / 2;
        let triangles = f * n * n;
        e.triangles += triangles;
        e.largest_organ_vertices = e.largest_organ_vertices.max(vertices);
        // 24 bytes per vertex, 12 per triangle's indices, about 40 per triangle of hierarchy.
        e.memory_bytes += vertices * 24 + triangles * (12 + 40);
    }
    e
}

pub fn scale_set(set: &OrganSet, n: usize, progress: super::import::Progress) -> OrganSet {
    let mut out = set.clone();
    out.title = format!("{} (x{})", set.title, n * n);
    let total = out.organs.len();
    for (i, o) in out.organs.iter_mut().enumerate() {
        progress(i, total, &o.id);
        let stand_in = o.stand_in.take().unwrap_or_else(|| super::StandIn { mesh: o.mesh.clone(), bvh: o.bvh.clone() });
        o.set_mesh(subdivide(&o.mesh, n));
        if n > 1 {
            o.stand_in = Some(stand_in);
        }
    }
    // The faces inside the solids are numbered in the old meshes: `vbrain stand-ins` finds them
    // again for the new ones.
    out.solids.iter_mut().for_each(|s| s.hidden.clear());
    progress(total, total, "done");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> Mesh {
        let mut m = Mesh {
            positions: vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
            normals: vec![],
            indices: vec![0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3],
        };
        m.compute_normals();
        m
    }

    #[test]
    fn counts_and_closure() {
        assert_eq!(level_for_factor(50.0), 7);
        assert_eq!(level_for_factor(0.3), 1);
        let m = tetrahedron();
        for n in 1..6 {
            let s = subdivide(&m, n);
            assert_eq!(s.triangle_count(), 4 * n * n);
            assert!(s.validate().is_ok());
            // Closed and consistently wound: every directed edge has its reverse.
            let mut edges = std::collections::HashSet::new();
            for t in s.indices.chunks_exact(3) {
                for k in 0..3 {
                    assert!(edges.insert((t[k], t[(k + 1) % 3])), "edge used twice at n = {n}");
                }
            }
            assert!(edges.iter().all(|&(a, b)| edges.contains(&(b, a))), "open at n = {n}");
            // Euler characteristic of a sphere: V - E + F = 2.
            assert_eq!(s.positions.len() as i64 - edges.len() as i64 / 2 + s.triangle_count() as i64, 2);
        }
    }
}
