//! Helpers shared by the integration tests: synthetic meshes.

use glam::Vec3;
use vbrain::mesh::Mesh;
use vbrain::organ_set::scale::subdivide;

/// A closed box of half-size `half` around `center`, wound outward, each triangle split into
/// `level` x `level` smaller ones (`level` 0 or 1 keeps the 12 triangles).
pub fn cube(center: Vec3, half: Vec3, level: usize) -> Mesh {
    let c = |x: f32, y: f32, z: f32| (center + half * Vec3::new(x, y, z)).to_array();
    let mut m = Mesh {
        positions: vec![
            c(-1., -1., -1.),
            c(1., -1., -1.),
            c(1., 1., -1.),
            c(-1., 1., -1.),
            c(-1., -1., 1.),
            c(1., -1., 1.),
            c(1., 1., 1.),
            c(-1., 1., 1.),
        ],
        normals: vec![],
        indices: vec![
            0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7,
        ],
    };
    m.compute_normals();
    subdivide(&m, level)
}
