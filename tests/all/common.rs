//! Helpers shared by the integration tests: synthetic meshes, the GPU and the default set (each
//! opened once per binary).

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

/// The headless GPU of this test binary, opened once.
pub fn gpu() -> &'static vbrain::render::GpuContext {
    static GPU: std::sync::OnceLock<vbrain::render::GpuContext> = std::sync::OnceLock::new();
    GPU.get_or_init(|| {
        vbrain::render::GpuContext::headless().unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"))
    })
}

/// The default set's folder.
pub fn brain_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("organs/brain")
}

/// The default set, loaded once per test binary (with no organ failing to load).
pub fn default_set() -> &'static vbrain::organ_set::OrganSet {
    static SET: std::sync::OnceLock<vbrain::organ_set::OrganSet> = std::sync::OnceLock::new();
    SET.get_or_init(|| {
        let loaded = vbrain::organ_set::open(&brain_dir()).unwrap();
        assert!(loaded.errors.is_empty(), "{:?}", loaded.errors);
        loaded.set
    })
}

/// The default set's occluder database, checked against the set.
pub fn default_database() -> Option<vbrain::cull::database::Database> {
    vbrain::cull::database::Database::load_for(&brain_dir(), default_set()).unwrap()
}
