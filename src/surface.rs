//! Surface extraction and mesh clean-up, as pure functions on arrays.
//!
//! - Input grids are in voxel index space (x fastest: `values[x + nx * (y + ny * z)]`).
//! - Output meshes are in the same space until the caller applies the volume's affine.
//! - Surface nets wind triangles counter-clockwise seen from outside, where outside is
//!   `value < iso`.

use crate::mesh::Mesh;
use glam::Vec3;

/// A scalar field on a regular grid, `values[x + nx * (y + ny * z)]`.
pub struct Grid<'a> {
    pub dims: [usize; 3],
    pub values: &'a [f32],
}

/// Extracts the iso-surface `value = iso` by naive surface nets: one vertex per grid cell the surface
/// crosses (the mean of its edge crossings), one quad per grid edge the surface crosses. Triangles are
/// wound counter-clockwise seen from outside, where outside is `value < iso`. The surface is closed
/// when the field is below `iso` on the grid's border.
pub fn surface_nets(grid: &Grid, iso: f32) -> Mesh {
    let [nx, ny, nz] = grid.dims;
    let mut mesh = Mesh::default();
    if nx < 2 || ny < 2 || nz < 2 || grid.values.len() < nx * ny * nz {
        return mesh;
    }
    let at = |x: usize, y: usize, z: usize| grid.values[x + nx * (y + ny * z)];
    let (cx, cy) = (nx - 1, ny - 1);
    let cell = |x: usize, y: usize, z: usize| x + cx * (y + cy * z);
    let mut cell_vertex = vec![u32::MAX; cx * cy * (nz - 1)];
    const EDGES: [(usize, usize); 12] =
        [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];
    for z in 0..nz - 1 {
        for y in 0..ny - 1 {
            for x in 0..nx - 1 {
                let corner: [f32; 8] = std::array::from_fn(|i| at(x + (i & 1), y + ((i >> 1) & 1), z + (i >> 2)));
                let inside = corner.iter().filter(|&&v| v >= iso).count();
                if inside == 0 || inside == 8 {
                    continue;
                }
                let mut sum = Vec3::ZERO;
                let mut n = 0.0;
                for (a, b) in EDGES {
                    let (va, vb) = (corner[a], corner[b]);
                    if (va >= iso) != (vb >= iso) {
                        let t = (iso - va) / (vb - va);
                        let pa = Vec3::new((a & 1) as f32, ((a >> 1) & 1) as f32, (a >> 2) as f32);
                        let pb = Vec3::new((b & 1) as f32, ((b >> 1) & 1) as f32, (b >> 2) as f32);
                        sum += pa + (pb - pa) * t;
                        n += 1.0;
                    }
                }
                let p = Vec3::new(x as f32, y as f32, z as f32) + sum / n;
                cell_vertex[cell(x, y, z)] = mesh.positions.len() as u32;
                mesh.positions.push(p.to_array());
            }
        }
    }
    // One quad per crossing edge, between the four cells around it.
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let inside = at(x, y, z) >= iso;
                for axis in 0..3 {
                    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                    let p = [x, y, z];
                    if p[axis] + 1 >= grid.dims[axis] || p[u] == 0 || p[v] == 0 {
                        continue;
                    }
                    let mut q = p;
                    q[axis] += 1;
                    if inside == (at(q[0], q[1], q[2]) >= iso) {
                        continue;
                    }
                    let cell_of = |du: usize, dv: usize| {
                        let mut c = p;
                        c[u] = c[u] + du - 1;
                        c[v] = c[v] + dv - 1;
                        if c[0] >= nx - 1 || c[1] >= ny - 1 || c[2] >= nz - 1 {
                            return u32::MAX;
                        }
                        cell_vertex[cell(c[0], c[1], c[2])]
                    };
                    let quad = [cell_of(0, 0), cell_of(1, 0), cell_of(1, 1), cell_of(0, 1)];
                    if quad.contains(&u32::MAX) {
                        continue;
                    }
                    // (u, v, axis) is right-handed, so this order faces +axis; outward is toward outside.
                    let outward_positive = inside;
                    let [a, b, c, d] = if outward_positive { quad } else { [quad[0], quad[3], quad[2], quad[1]] };
                    let pos = |i: u32| Vec3::from(mesh.positions[i as usize]);
                    // Split along the shorter diagonal.
                    if pos(a).distance_squared(pos(c)) <= pos(b).distance_squared(pos(d)) {
                        mesh.indices.extend_from_slice(&[a, b, c, a, c, d]);
                    } else {
                        mesh.indices.extend_from_slice(&[a, b, d, b, c, d]);
                    }
                }
            }
        }
    }
    mesh
}

/// Vertex neighbours as compressed rows: `offsets[i]..offsets[i + 1]` indexes `neighbours`.
fn adjacency(vertex_count: usize, indices: &[u32]) -> (Vec<usize>, Vec<u32>) {
    let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(indices.len() * 2);
    for t in indices.chunks_exact(3) {
        for k in 0..3 {
            pairs.push((t[k], t[(k + 1) % 3]));
            pairs.push((t[(k + 1) % 3], t[k]));
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    let mut offsets = vec![0usize; vertex_count + 1];
    for &(a, _) in &pairs {
        offsets[a as usize + 1] += 1;
    }
    for i in 0..vertex_count {
        offsets[i + 1] += offsets[i];
    }
    (offsets, pairs.into_iter().map(|(_, b)| b).collect())
}

/// Taubin's lambda/mu smoothing: removes voxel staircases without shrinking the surface.
pub fn taubin_smooth(mesh: &mut Mesh, iterations: usize) {
    let (offsets, neighbours) = adjacency(mesh.positions.len(), &mesh.indices);
    let mut next = mesh.positions.clone();
    for it in 0..iterations * 2 {
        let factor = if it % 2 == 0 { 0.5 } else { -0.53 };
        for (i, out) in next.iter_mut().enumerate() {
            let ns = &neighbours[offsets[i]..offsets[i + 1]];
            let p = Vec3::from(mesh.positions[i]);
            if ns.is_empty() {
                *out = p.to_array();
                continue;
            }
            let mean = ns.iter().map(|&n| Vec3::from(mesh.positions[n as usize])).sum::<Vec3>() / ns.len() as f32;
            *out = (p + (mean - p) * factor).to_array();
        }
        std::mem::swap(&mut mesh.positions, &mut next);
    }
}

/// Drops connected components with fewer than `min_triangles` triangles (specks of stray voxels).
pub fn remove_small_components(mesh: &mut Mesh, min_triangles: usize) {
    let n = mesh.positions.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            parent[i as usize] = parent[parent[i as usize] as usize];
            i = parent[i as usize];
        }
        i
    }
    for t in mesh.indices.chunks_exact(3) {
        for k in 1..3 {
            let (a, b) = (find(&mut parent, t[0]), find(&mut parent, t[k]));
            parent[a as usize] = b;
        }
    }
    let mut count = vec![0usize; n];
    for t in mesh.indices.chunks_exact(3) {
        count[find(&mut parent, t[0]) as usize] += 1;
    }
    let mut kept = Vec::with_capacity(mesh.indices.len());
    for t in mesh.indices.chunks_exact(3) {
        if count[find(&mut parent, t[0]) as usize] >= min_triangles {
            kept.extend_from_slice(t);
        }
    }
    mesh.indices = kept;
    compact(mesh);
}

/// Removes vertices no triangle uses, keeping order.
pub fn compact(mesh: &mut Mesh) {
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let has_normals = mesh.normals.len() == mesh.positions.len();
    for i in mesh.indices.iter_mut() {
        let old = *i as usize;
        if remap[old] == u32::MAX {
            remap[old] = positions.len() as u32;
            positions.push(mesh.positions[old]);
            if has_normals {
                normals.push(mesh.normals[old]);
            }
        }
        *i = remap[old];
    }
    mesh.positions = positions;
    mesh.normals = normals;
}

/// Simplifies to at most about `target_triangles` triangles with meshoptimizer (no error bound: the
/// budget decides). Normals are recomputed by the caller.
pub fn simplify(mesh: &mut Mesh, target_triangles: usize) {
    if mesh.triangle_count() <= target_triangles || mesh.positions.is_empty() {
        return;
    }
    let bytes: &[u8] = bytemuck::cast_slice(&mesh.positions);
    let Ok(adapter) = meshopt::VertexDataAdapter::new(bytes, 12, 0) else {
        return;
    };
    let indices =
        meshopt::simplify(&mesh.indices, &adapter, target_triangles * 3, 1.0, meshopt::SimplifyOptions::None, None);
    if !indices.is_empty() {
        mesh.indices = indices;
        compact(mesh);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere_grid(n: usize, r: f32) -> Vec<f32> {
        let c = (n as f32 - 1.0) / 2.0;
        let mut v = vec![0.0; n * n * n];
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    let d = Vec3::new(x as f32 - c, y as f32 - c, z as f32 - c).length();
                    v[x + n * (y + n * z)] = r - d; // positive inside
                }
            }
        }
        v
    }

    /// Every edge of a closed, consistently wound surface is used once in each direction.
    fn is_closed_and_consistent(m: &Mesh) -> bool {
        let mut edges = std::collections::HashMap::new();
        for t in m.indices.chunks_exact(3) {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        edges.iter().all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
    }

    #[test]
    fn sphere_is_closed_outward_and_round() {
        let n = 24;
        let values = sphere_grid(n, 8.0);
        let mut m = surface_nets(&Grid { dims: [n, n, n], values: &values }, 0.0);
        assert!(m.triangle_count() > 500);
        assert!(is_closed_and_consistent(&m));
        let c = Vec3::splat((n as f32 - 1.0) / 2.0);
        for p in &m.positions {
            let d = (Vec3::from(*p) - c).length();
            assert!((d - 8.0).abs() < 0.6, "vertex at radius {d}");
        }
        // Outward winding: the signed volume is positive and close to the sphere's.
        let vol = m.signed_volume();
        let exact = 4.0 / 3.0 * std::f32::consts::PI * 512.0;
        assert!((vol - exact).abs() / exact < 0.05, "volume {vol} vs {exact}");
        taubin_smooth(&mut m, 10);
        simplify(&mut m, 300);
        assert!(m.triangle_count() <= 310 && m.triangle_count() > 100, "{}", m.triangle_count());
        assert!(is_closed_and_consistent(&m));
    }

    #[test]
    fn specks_are_removed() {
        let n = 24;
        let mut values = sphere_grid(n, 6.0);
        values.iter_mut().for_each(|v| *v = if *v > 0.0 { 1.0 } else { 0.0 });
        values[2 + n * (2 + n * 2)] = 1.0; // one stray voxel
        let mut m = surface_nets(&Grid { dims: [n, n, n], values: &values }, 0.5);
        let before = m.triangle_count();
        remove_small_components(&mut m, 50);
        assert!(m.triangle_count() < before && m.triangle_count() > 200);
        assert!(is_closed_and_consistent(&m));
    }
}
