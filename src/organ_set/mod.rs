//! Organ sets: the organs of one scene with their meshes and metadata.
//!
//! - Organ space = millimetres, RAS.
//! - [`open`] reads any of: a folder with `organset.json` (see [`manifest`]), a folder of
//!   `.obj`/`.vbo` files without a manifest, or a single `.obj`/`.vbo` file.
//! - Without a manifest every object (`o`/`g`) of every file is one organ, named after the object
//!   or file, with distinct colours.
//! - A broken organ does not stop the rest: it is reported in [`Loaded::errors`] and left out.

pub mod hidden_faces;
pub mod import;
pub mod label_table;
mod load;
pub mod manifest;
pub mod names;
pub mod obj;
pub mod scale;
pub mod stand_in;
pub mod territory;

use crate::bvh::Bvh;
use crate::error::{Error, Result};
use crate::mesh::{Bounds, Mesh};
use manifest::{Manifest, OrganEntry, Source};
use std::path::Path;

pub use load::{is_mesh_file, open, open_files, open_manifest};

pub const MANIFEST_FILE: &str = "organset.json";

#[derive(Clone, Debug)]
pub struct Organ {
    pub id: String,
    pub name: String,
    /// `/`-separated group path for the organ tree; empty for the top level.
    pub group: String,
    /// sRGB components in 0..=1.
    pub colour: [f32; 3],
    pub opacity: f32,
    pub visible: bool,
    /// Terminologia Anatomica's Latin name, where there is one.
    pub latin: Option<String>,
    /// Other names a student may search for ([`names::matches`]).
    pub synonyms: Vec<String>,
    pub info: String,
    /// Triangles in the order of `bvh`'s leaves (changed only with the hierarchy, by
    /// [`Organ::set_mesh`]).
    pub(crate) mesh: Mesh,
    pub(crate) bvh: Bvh,
    /// A mesh with fewer triangles on or inside this organ's surface (organ space) that stands in
    /// for it as an occluder, e.g. the original of a subdivided set.
    pub(crate) stand_in: Option<StandIn>,
    /// Levels of detail ([`crate::lod`]): triangles over the mesh's own vertices, coarsest last.
    pub(crate) lods: Vec<Vec<u32>>,
    /// [`Mesh::is_closed_outward`]: drawn with its back faces culled.
    closed: bool,
    /// [`Mesh::bounds`], kept with the mesh.
    vertex_bounds: Bounds,
    /// Its hierarchy's nodes and parts made only of faces inside solids ([`OrganSet::index_hidden_faces`]).
    pub(crate) inside: hidden_faces::Inside,
    /// Per triangle, its number in the order the hierarchy was first built in from the mesh
    /// (which hidden-faces files use), once it was built again to keep those faces apart
    /// ([`OrganSet::set_hidden_faces`]); `None` while the triangles are still in that order.
    pub(crate) first_order: Option<Vec<u32>>,
}

/// An occluder stand-in: its mesh (in the order of its own hierarchy's leaves) and hierarchy.
#[derive(Clone, Debug, Default)]
pub struct StandIn {
    pub(crate) mesh: Mesh,
    pub(crate) bvh: Bvh,
}

impl StandIn {
    pub fn new(mut mesh: Mesh) -> StandIn {
        let bvh = Bvh::build(&mut mesh);
        StandIn { mesh, bvh }
    }

    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }
}

impl Organ {
    /// An organ with the set's defaults; builds its hierarchy (reordering the mesh's triangles).
    pub fn new(id: String, name: String, colour: [f32; 3], mut mesh: Mesh) -> Organ {
        let bvh = Bvh::build(&mut mesh);
        let closed = mesh.is_closed_outward();
        Organ {
            closed,
            vertex_bounds: mesh.bounds(),
            id,
            name,
            group: String::new(),
            colour,
            opacity: 1.0,
            visible: true,
            latin: None,
            synonyms: Vec::new(),
            info: String::new(),
            mesh,
            bvh,
            stand_in: None,
            lods: Vec::new(),
            inside: hidden_faces::Inside::default(),
            first_order: None,
        }
    }

    /// The mesh, in organ space, its triangles in the order of the hierarchy's leaves.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The bounds of its triangles in organ space, from its hierarchy's root (no pass over the
    /// vertices).
    pub fn bounds(&self) -> Bounds {
        self.bvh.nodes.first().map_or_else(|| self.mesh.bounds(), |root| root.bounds)
    }

    /// The bounds of all its vertices in organ space ([`Mesh::bounds`], as the renderer takes
    /// them to tell which organs the clip planes cut), kept with the mesh.
    pub fn vertex_bounds(&self) -> Bounds {
        self.vertex_bounds
    }

    /// The bounding-volume hierarchy over the mesh.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Closed and wound outward ([`Mesh::is_closed_outward`]): its back faces are never seen from
    /// outside, and the renderer culls them.
    pub fn closed(&self) -> bool {
        self.closed
    }

    /// The occluder stand-in, if it has one.
    pub fn stand_in(&self) -> Option<&StandIn> {
        self.stand_in.as_ref()
    }

    /// Gives it an occluder stand-in (or none); the caller vouches that it lies inside.
    pub fn set_stand_in(&mut self, stand_in: Option<StandIn>) {
        self.stand_in = stand_in;
    }

    /// Its levels of detail ([`crate::lod`]), coarsest last; none where the set has none.
    pub fn lods(&self) -> &[Vec<u32>] {
        &self.lods
    }

    /// Builds its levels of detail from its mesh ([`crate::lod::levels`]).
    pub fn build_lods(&mut self) {
        self.lods = crate::lod::levels(&self.mesh, self.closed);
    }

    /// Replaces the mesh, rebuilding the hierarchy; the occluder stand-in is dropped (it may no
    /// longer lie inside).
    pub fn set_mesh(&mut self, mut mesh: Mesh) {
        self.bvh = Bvh::build(&mut mesh);
        self.closed = mesh.is_closed_outward();
        self.vertex_bounds = mesh.bounds();
        self.mesh = mesh;
        self.stand_in = None;
        self.lods = Vec::new();
        self.inside = hidden_faces::Inside::default();
        self.first_order = None;
    }

    /// Its triangle `t`'s number in the order its hierarchy was first built in.
    pub(crate) fn first_number(&self, t: u32) -> u32 {
        self.first_order.as_ref().map_or(t, |f| f[t as usize])
    }
}

#[derive(Clone, Debug, Default)]
pub struct OrganSet {
    pub title: String,
    pub description: String,
    pub sources: Vec<Source>,
    pub organs: Vec<Organ>,
    pub solids: Vec<Solid>,
    /// Its MRI, registered to the organs, where the manifest names one that loads.
    pub mri: Option<std::sync::Arc<crate::mri::Mri>>,
    /// Its arterial territories, where the manifest names a file that loads.
    pub territories: Option<std::sync::Arc<territory::Territories>>,
}

/// Organs that together fill one solid ([`manifest::SolidEntry`]), and a stand-in inside their
/// union: while they are all opaque and moved as one, the culler rasterises it in their place,
/// with no seams between them (cut where clip planes cut them, [`crate::cull`]). No other organ
/// of the set lies inside the solid.
#[derive(Clone, Debug, Default)]
pub struct Solid {
    pub id: String,
    /// Indices into [`OrganSet::organs`], increasing.
    pub organs: Vec<usize>,
    pub(crate) stand_in: Option<StandIn>,
    /// The faces of its organs it hides and no smaller solid does ([`hidden_faces`]).
    pub(crate) hidden: Vec<hidden_faces::OrganFaces>,
}

impl Solid {
    pub fn stand_in(&self) -> Option<&StandIn> {
        self.stand_in.as_ref()
    }

    /// Gives it a stand-in (or none); the caller vouches that it lies inside the organs' union.
    pub fn set_stand_in(&mut self, stand_in: Option<StandIn>) {
        self.stand_in = stand_in;
    }

    /// The faces of its organs it hides and no smaller solid does: per organ, runs of triangles.
    pub fn hidden_faces(&self) -> &[hidden_faces::OrganFaces] {
        &self.hidden
    }
}

/// An opened set with what went wrong on the way.
#[derive(Debug, Default)]
pub struct Loaded {
    pub set: OrganSet,
    /// Organs (files) that failed to load; the set holds the others.
    pub errors: Vec<Error>,
    pub warnings: Vec<String>,
}

impl OrganSet {
    pub fn triangle_count(&self) -> usize {
        self.organs.iter().map(|o| o.mesh.triangle_count()).sum()
    }

    /// Bounds of all organs in their default positions.
    pub fn bounds(&self) -> Bounds {
        self.organs.iter().fold(Bounds::EMPTY, |b, o| b.union(o.mesh.bounds()))
    }

    pub fn find(&self, id: &str) -> Option<usize> {
        self.organs.iter().position(|o| o.id == id)
    }

    /// The ids of these organs (indices; any past the end left out).
    pub fn ids(&self, organs: &[usize]) -> Vec<String> {
        organs.iter().filter_map(|&i| self.organs.get(i).map(|o| o.id.clone())).collect()
    }

    /// The organ with id `key`, or else every organ in the group `key` names
    /// ([`names::in_group`]: "Frontal lobe", "Left hemisphere/Frontal lobe"); empty if neither.
    pub fn select(&self, key: &str) -> Vec<usize> {
        match self.find(key) {
            Some(i) => vec![i],
            None => (0..self.organs.len()).filter(|&i| names::in_group(&self.organs[i], key)).collect(),
        }
    }

    /// Every group path of the set's organs and each of its ancestors ("Cerebrum",
    /// "Cerebrum/Left hemisphere", ...), sorted, so a parent comes right before its children.
    pub fn group_paths(&self) -> Vec<String> {
        let mut paths = std::collections::BTreeSet::new();
        for organ in &self.organs {
            let mut path = String::new();
            for part in organ.group.split('/').filter(|p| !p.is_empty()) {
                if !path.is_empty() {
                    path.push('/');
                }
                path.push_str(part);
                paths.insert(path.clone());
            }
        }
        paths.into_iter().collect()
    }

    /// The manifest that describes this set with meshes at `meshes/<id>.vbo` (and occluder
    /// stand-ins at `meshes/<id>.occluder.vbo`).
    pub fn manifest(&self) -> Manifest {
        Manifest {
            format: manifest::FORMAT.into(),
            title: self.title.clone(),
            units: "mm".into(),
            coordinates: "RAS".into(),
            description: self.description.clone(),
            sources: self.sources.clone(),
            organs: self
                .organs
                .iter()
                .map(|o| OrganEntry {
                    id: o.id.clone(),
                    name: o.name.clone(),
                    mesh: format!("meshes/{}.vbo", o.id),
                    occluder: o.stand_in.as_ref().map(|_| format!("meshes/{}.occluder.vbo", o.id)),
                    // Levels name the vertices as the mesh file loads them: a set written from this
                    // has none until `vbrain lod` builds them over its new files.
                    lod: None,
                    colour: manifest::format_colour(o.colour),
                    opacity: o.opacity,
                    visible: o.visible,
                    group: o.group.clone(),
                    latin: o.latin.clone(),
                    synonyms: o.synonyms.clone(),
                    info: o.info.clone(),
                })
                .collect(),
            solids: self
                .solids
                .iter()
                .map(|s| manifest::SolidEntry {
                    id: s.id.clone(),
                    organs: s.organs.iter().map(|&o| self.organs[o].id.clone()).collect(),
                    occluder: s.stand_in.as_ref().map(|_| format!("meshes/{}.solid.vbo", s.id)),
                    hidden: (!s.hidden.is_empty()).then(|| format!("meshes/{}.hidden.json", s.id)),
                })
                .collect(),
            // The MRI file is not rewritten with the meshes: a set written from this has none.
            mri: None,
            territories: None,
        }
    }

    /// Writes the set as the folder `dir`: `organset.json`, `meshes/<id>.vbo`, the stand-ins and
    /// the faces hidden inside solids, staged beside it and moved into place whole
    /// ([`crate::atomic::write_folder`]), replacing what `dir` held. Callers ask first where `dir`
    /// holds anything ([`crate::atomic::folder_entries`]).
    pub fn save(&self, dir: &Path) -> Result<()> {
        crate::atomic::write_folder(dir, |staging| self.write_into(staging))
    }

    fn write_into(&self, dir: &Path) -> Result<()> {
        let meshes = dir.join("meshes");
        std::fs::create_dir_all(&meshes).map_err(|e| Error::io(&meshes, e))?;
        for o in &self.organs {
            crate::atomic::write(&meshes.join(format!("{}.vbo", o.id)), |w| obj::write_vbo(&[(&o.name, &o.mesh)], w))?;
        }
        self.write_stand_ins(dir)?;
        // The meshes go out in their leaf order, from which a load builds the hierarchies afresh:
        // the hidden faces are numbered in the order that build gives.
        let fresh: Vec<Option<Vec<u32>>> = self
            .organs
            .iter()
            .map(|o| {
                o.first_order.as_ref().map(|_| {
                    let (_, order) = Bvh::build_apart(&mut o.mesh.clone(), &[]);
                    let mut number = vec![0; order.len()];
                    order.iter().enumerate().for_each(|(new, &old)| number[old as usize] = new as u32);
                    number
                })
            })
            .collect();
        self.write_hidden_faces(dir, |o, t| fresh[o].as_ref().map_or(t, |n| n[t as usize]))?;
        write_manifest(dir, &self.manifest())
    }

    /// Writes each solid's hidden faces into `dir/meshes`, numbered by `number` (organ, triangle).
    fn write_hidden_faces(&self, dir: &Path, number: impl Fn(usize, u32) -> u32 + Copy) -> Result<()> {
        for s in self.solids.iter().filter(|s| !s.hidden.is_empty()) {
            hidden_faces::write(&dir.join("meshes").join(format!("{}.hidden.json", s.id)), self, &s.hidden, number)?;
        }
        Ok(())
    }

    /// Builds every organ's levels of detail, organs in parallel ([`Organ::build_lods`]).
    pub fn build_lods(&mut self) {
        use rayon::prelude::*;
        self.organs.par_iter_mut().for_each(Organ::build_lods);
    }

    /// Writes the organs' levels of detail into the set's folder `dir` (`meshes/<id>.lod`, each
    /// atomically) and names them in its `organset.json`, leaving everything else there as it is.
    /// The levels must have been built over the meshes as this set loaded them from `dir`.
    pub fn save_lods(&self, dir: &Path) -> Result<()> {
        let path = dir.join(MANIFEST_FILE);
        let text = crate::input::read_text(&path, crate::input::Kind::Manifest)?;
        let mut manifest: Manifest =
            serde_json::from_str(&text).map_err(|e| Error::parse(&path, Some(e.line()), e.to_string()))?;
        let meshes = dir.join("meshes");
        std::fs::create_dir_all(&meshes).map_err(|e| Error::io(&meshes, e))?;
        for o in self.organs.iter().filter(|o| !o.lods.is_empty()) {
            let file = meshes.join(format!("{}.lod", o.id));
            crate::atomic::write(&file, |w| crate::lod::write(&o.lods, o.mesh.positions.len(), w))?;
        }
        for entry in &mut manifest.organs {
            if let Some(o) = self.organs.iter().find(|o| o.id == entry.id) {
                entry.lod = (!o.lods.is_empty()).then(|| format!("meshes/{}.lod", o.id));
            }
        }
        write_manifest(dir, &manifest)
    }

    /// Writes the occluder stand-ins and the faces hidden inside solids into the set's folder `dir`
    /// and names them in its `organset.json`, leaving everything else there as it is: the organs'
    /// meshes (their triangle order, which `occluders.json` names, stays) and every other field of
    /// the manifest (the meshes' paths among them). The manifest is read first; one that does not
    /// read is an error, and nothing is written.
    pub fn save_stand_ins(&self, dir: &Path) -> Result<()> {
        let path = dir.join(MANIFEST_FILE);
        let text = crate::input::read_text(&path, crate::input::Kind::Manifest)?;
        let mut manifest: Manifest =
            serde_json::from_str(&text).map_err(|e| Error::parse(&path, Some(e.line()), e.to_string()))?;
        self.write_stand_ins(dir)?;
        // The meshes stay as they are: numbered as their hierarchies were first built.
        self.write_hidden_faces(dir, |o, t| self.organs[o].first_number(t))?;
        for entry in &mut manifest.organs {
            if let Some(o) = self.organs.iter().find(|o| o.id == entry.id) {
                entry.occluder = o.stand_in.as_ref().map(|_| format!("meshes/{}.occluder.vbo", o.id));
            }
        }
        // Per solid entry that loaded, its files; an entry that did not load (a member's mesh
        // missing, say) stays as it is.
        for entry in &mut manifest.solids {
            if let Some(s) = self.solids.iter().find(|s| s.id == entry.id) {
                entry.occluder = s.stand_in.as_ref().map(|_| format!("meshes/{}.solid.vbo", s.id));
                entry.hidden = (!s.hidden.is_empty()).then(|| format!("meshes/{}.hidden.json", s.id));
            }
        }
        write_manifest(dir, &manifest)
    }

    /// Writes the organs' and the solids' stand-ins into `dir/meshes`, each file atomically.
    fn write_stand_ins(&self, dir: &Path) -> Result<()> {
        let meshes = dir.join("meshes");
        std::fs::create_dir_all(&meshes).map_err(|e| Error::io(&meshes, e))?;
        for o in &self.organs {
            if let Some(stand_in) = &o.stand_in {
                let path = meshes.join(format!("{}.occluder.vbo", o.id));
                crate::atomic::write(&path, |w| obj::write_vbo(&[(&o.name, &stand_in.mesh)], w))?;
            }
        }
        for s in &self.solids {
            if let Some(stand_in) = &s.stand_in {
                let path = meshes.join(format!("{}.solid.vbo", s.id));
                crate::atomic::write(&path, |w| obj::write_vbo(&[(&s.id, &stand_in.mesh)], w))?;
            }
        }
        Ok(())
    }

    /// Gives the solids the faces they hide (per solid, as [`hidden_faces::find`] gives them) and
    /// indexes them in the organs' hierarchies, for the culler. The caller vouches that they were
    /// found for these meshes.
    pub fn set_hidden_faces(&mut self, faces: Vec<Vec<hidden_faces::OrganFaces>>) {
        for (solid, faces) in self.solids.iter_mut().zip(faces) {
            solid.hidden = faces;
        }
        self.keep_hidden_faces_apart();
        self.index_hidden_faces();
    }

    /// Builds again the hierarchy of each organ with faces hidden inside solids, the hidden faces
    /// split from the rest at its root, so that no node or part mixes the two: a leaf of the
    /// cortex's inner surface is then culled while its solid is intact, where one holding a few
    /// faces of the outer surface too would be drawn. The solids' hidden faces are renumbered to
    /// the new order.
    fn keep_hidden_faces_apart(&mut self) {
        use rayon::prelude::*;
        let solids = &self.solids;
        // Per organ with hidden faces: the new order (new number -> old).
        let orders: Vec<Option<Vec<u32>>> = self
            .organs
            .par_iter_mut()
            .enumerate()
            .map(|(o, organ)| {
                let mut apart = vec![false; organ.mesh.triangle_count()];
                for (_, runs) in solids.iter().flat_map(|s| &s.hidden).filter(|f| f.0 == o) {
                    runs.iter().flat_map(|r| r.clone()).for_each(|t| apart[t as usize] = true);
                }
                if !apart.contains(&true) {
                    return None;
                }
                let (bvh, order) = Bvh::build_apart(&mut organ.mesh, &apart);
                organ.bvh = bvh;
                organ.first_order = Some(order.iter().map(|&t| organ.first_number(t)).collect());
                Some(order)
            })
            .collect();
        for solid in &mut self.solids {
            for (o, runs) in &mut solid.hidden {
                let Some(order) = &orders[*o] else { continue };
                let mut hidden = vec![false; order.len()];
                runs.iter().flat_map(|r| r.clone()).for_each(|t| hidden[t as usize] = true);
                *runs = hidden_faces::runs((0..order.len() as u32).filter(|&t| hidden[order[t as usize] as usize]));
            }
        }
    }

    /// Indexes the solids' hidden faces in each organ's hierarchy ([`hidden_faces::Inside`]).
    fn index_hidden_faces(&mut self) {
        for (o, organ) in self.organs.iter_mut().enumerate() {
            organ.inside = hidden_faces::Inside::of(o, &organ.bvh, &self.solids);
        }
    }
}

/// Writes `organset.json` into `dir`, atomically.
fn write_manifest(dir: &Path, manifest: &Manifest) -> Result<()> {
    let path = dir.join(MANIFEST_FILE);
    let json = crate::json_file::to_json(manifest, &path)?;
    crate::atomic::write(&path, |w| w.write_all(json.as_bytes()))
}

/// An id from a name: lowercase ASCII letters and digits, other runs become `_`.
pub fn slug(name: &str) -> String {
    let mut s = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            s.push(c.to_ascii_lowercase());
        } else if !s.ends_with('_') {
            s.push('_');
        }
    }
    let s = s.trim_matches('_').to_string();
    if s.is_empty() {
        "organ".into()
    } else {
        s
    }
}

fn unique_id(base: &str, taken: &mut std::collections::HashSet<String>) -> String {
    let mut id = base.to_string();
    let mut n = 2;
    while !taken.insert(id.clone()) {
        id = format!("{base}_{n}");
        n += 1;
    }
    id
}

/// The `i`-th of a sequence of well-separated colours (golden-angle hues, sRGB).
pub fn distinct_colour(i: usize) -> [f32; 3] {
    let h = (i as f32 * 0.381_966) % 1.0;
    let (s, v) = (0.55, 0.9);
    let f = |n: f32| {
        let k = (n + h * 6.0) % 6.0;
        v - v * s * k.min(4.0 - k).clamp(0.0, 1.0)
    };
    [f(5.0), f(3.0), f(1.0)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slugs_and_ids() {
        assert_eq!(slug("Left Thalamus (proper)"), "left_thalamus_proper");
        assert_eq!(slug("***"), "organ");
        let mut taken = Default::default();
        assert_eq!(unique_id("a", &mut taken), "a");
        assert_eq!(unique_id("a", &mut taken), "a_2");
    }

    #[test]
    fn colours_differ() {
        let c: Vec<_> = (0..12).map(distinct_colour).collect();
        for i in 0..c.len() {
            for j in 0..i {
                let d: f32 = (0..3).map(|k| (c[i][k] - c[j][k]).abs()).sum();
                assert!(d > 0.05, "{i} and {j} too close: {:?} {:?}", c[i], c[j]);
            }
        }
    }
}
