//! The occluder database: per grid viewpoint, its minimum-occluder-set occluders (thesis §3.2,
//! made by [`crate::mos`]), owned at run time by the [`super::Culler`].
//!
//! - Viewpoints are eyes in world space.
//! - Stored beside the set as `occluders.json` (versioned JSON, written atomically).
//! - It names the set's content and the layout it was computed for by fingerprints: a database
//!   whose set changed is stale and ignored.
//! - It serves a layout with nothing moved whose opaque organs it had opaque too (organs faded or
//!   hidden since simply no longer occlude, [`Database::serves`]); for another layout, or a camera
//!   far from every viewpoint, the culler uses projected size.

use super::LeafRef;
use crate::camera::Camera;
pub use crate::error::DbProblem;
use crate::error::{Error, Result};
use crate::layout::Layout;
use crate::organ_set::OrganSet;
use glam::Vec3;
use std::path::Path;

/// File name beside the set's manifest.
pub const FILE: &str = "occluders.json";
/// Format version; another version is ignored.
pub const VERSION: u32 = 1;
/// How near a camera must be to a viewpoint, as a share of the viewpoint's distance from its target.
pub const NEAR_DISTANCE: f32 = 0.6;
/// How far a camera's line of sight may turn from a viewpoint's.
pub const NEAR_ANGLE_DEG: f32 = 40.0;

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Viewpoint {
    pub eye: [f32; 3],
    /// Where it looks (the centre of the set's layout).
    pub target: [f32; 3],
    /// Occluders, best first, as [organ, leaf].
    pub occluders: Vec<LeafRef>,
}

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Database {
    pub version: u32,
    /// Fingerprint of the organs' ids and meshes (hex).
    pub set: String,
    /// Fingerprint of the layout: which organs are opaque and where every organ is (hex).
    pub layout: String,
    /// Which organs were opaque, and the fingerprint of where every organ was (hex); empty in
    /// files written before they were kept, which then serve their own layout only.
    #[serde(default)]
    pub opaque: Vec<bool>,
    #[serde(default)]
    pub placement: String,
    /// Grid directions, image size and occluder limit used.
    pub directions: usize,
    pub size: usize,
    pub limit: usize,
    pub viewpoints: Vec<Viewpoint>,
}

/// FNV-1a, 64 bits: stable across builds and machines.
struct Fnv(u64);

impl Fnv {
    fn new() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 = (self.0 ^ x as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn u32(&mut self, v: u32) {
        self.bytes(&v.to_le_bytes());
    }
}

/// Fingerprint of the set's content: organ ids, positions and triangles (after the hierarchy's
/// reordering, so leaf numbers mean the same leaves).
pub fn set_fingerprint(set: &OrganSet) -> String {
    let mut h = Fnv::new();
    for o in &set.organs {
        h.bytes(o.id.as_bytes());
        h.u32(o.mesh.positions.len() as u32);
        for p in &o.mesh.positions {
            p.iter().for_each(|c| h.u32(c.to_bits()));
        }
        o.mesh.indices.iter().for_each(|&i| h.u32(i));
        h.u32(o.bvh.leaves.len() as u32);
    }
    format!("{:016x}", h.0)
}

/// Fingerprint of what the pre-processing depends on in a layout: which organs are opaque and
/// every organ's placement.
pub fn layout_fingerprint(layout: &Layout) -> String {
    let mut h = Fnv::new();
    for s in &layout.organs {
        h.u32(u32::from(s.is_opaque()));
        s.transform.matrix().to_cols_array().iter().for_each(|c| h.u32(c.to_bits()));
    }
    format!("{:016x}", h.0)
}

/// Fingerprint of every organ's placement in a layout.
pub fn placement_fingerprint(layout: &Layout) -> String {
    let mut h = Fnv::new();
    for s in &layout.organs {
        s.transform.matrix().to_cols_array().iter().for_each(|c| h.u32(c.to_bits()));
    }
    format!("{:016x}", h.0)
}

impl Database {
    /// A database for `set` in `layout`, made on a grid of `directions` with images of `size`
    /// pixels and at most `limit` occluders per viewpoint.
    pub fn new(
        set: &OrganSet,
        layout: &Layout,
        (directions, size, limit): (usize, usize, usize),
        viewpoints: Vec<Viewpoint>,
    ) -> Self {
        Database {
            version: VERSION,
            set: set_fingerprint(set),
            layout: layout_fingerprint(layout),
            opaque: layout.organs.iter().map(|s| s.is_opaque()).collect(),
            placement: placement_fingerprint(layout),
            directions,
            size,
            limit,
            viewpoints,
        }
    }

    /// Is `layout` the one pre-processed (same opaque organs, nothing moved)?
    pub fn layout_matches(&self, layout: &Layout) -> bool {
        layout_fingerprint(layout) == self.layout
    }

    /// Do its occluders serve `layout`: nothing moved, and every organ opaque now was opaque when
    /// they were chosen (faded or hidden ones are left out of them)? `Some(true)` for the layout
    /// pre-processed, `Some(false)` for one with organs faded or hidden since, `None` otherwise.
    pub fn serves(&self, layout: &Layout) -> Option<bool> {
        if self.layout_matches(layout) {
            return Some(true);
        }
        (self.opaque.len() == layout.organs.len()
            && self.placement == placement_fingerprint(layout)
            && layout.organs.iter().zip(&self.opaque).all(|(s, &was)| was || !s.is_opaque()))
        .then_some(false)
    }

    /// The viewpoint nearest to the camera's eye (world space).
    pub fn nearest(&self, camera: &Camera) -> Option<&Viewpoint> {
        let eye = camera.eye;
        self.viewpoints
            .iter()
            .min_by(|a, b| eye.distance_squared(a.eye.into()).total_cmp(&eye.distance_squared(b.eye.into())))
    }

    /// The nearest viewpoint if the camera is close to it: within [`NEAR_DISTANCE`] of the
    /// viewpoint's distance from its target, looking within [`NEAR_ANGLE_DEG`] of its direction.
    /// A camera elsewhere (walking inside the set, looking away) is better served by projected size.
    pub fn near(&self, camera: &Camera) -> Option<&Viewpoint> {
        self.nearest(camera).filter(|v| {
            let (eye, target) = (Vec3::from(v.eye), Vec3::from(v.target));
            let reach = NEAR_DISTANCE * eye.distance(target);
            let forward = (target - eye).normalize_or_zero();
            let look = (camera.target - camera.eye).normalize_or_zero();
            camera.eye.distance(eye) <= reach && forward.dot(look) >= NEAR_ANGLE_DEG.to_radians().cos()
        })
    }

    /// Writes `occluders.json` into the set's folder, atomically.
    pub fn save(&self, dir: &Path) -> Result<()> {
        let path = dir.join(FILE);
        let json =
            serde_json::to_string(self).map_err(|e| Error::Encode { path: path.clone(), message: e.to_string() })?;
        crate::atomic::write(&path, |w| w.write_all(json.as_bytes()))
    }

    /// The database beside a set opened from `opened` (its folder or its manifest), if there is one
    /// and it fits the set. `Ok(None)`: no file there (or a set opened from mesh files). `Err`: why
    /// the file there is not used (unreadable, another version, stale); culling then chooses
    /// occluders by projected size only.
    pub fn load_for(opened: &Path, set: &OrganSet) -> Result<Option<Database>> {
        let manifest = crate::organ_set::MANIFEST_FILE;
        let dir = if opened.is_dir() && opened.join(manifest).is_file() {
            opened
        } else if opened.file_name().is_some_and(|n| n == manifest) {
            opened.parent().unwrap_or(Path::new("."))
        } else {
            return Ok(None);
        };
        let path = dir.join(FILE);
        let unusable = |problem| Error::OccluderDb { path: path.clone(), problem };
        if !path.exists() {
            return Ok(None);
        }
        let text = crate::input::read(&path, crate::input::Kind::Manifest)?;
        let db: Database =
            serde_json::from_slice(&text).map_err(|e| Error::parse(&path, Some(e.line()), e.to_string()))?;
        if db.version != VERSION {
            return Err(unusable(DbProblem::Version { found: db.version, reads: VERSION }));
        }
        if db.set != set_fingerprint(set) {
            return Err(unusable(DbProblem::Stale));
        }
        if !db.viewpoints.iter().flat_map(|v| &v.occluders).all(|r| r.exists_in(set)) {
            return Err(unusable(DbProblem::UnknownLeaves));
        }
        Ok(Some(db))
    }
}
