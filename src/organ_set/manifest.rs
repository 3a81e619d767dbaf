//! `organset.json`: the manifest of an organ set (serde).
//!
//! - Coordinates of every mesh are millimetres, RAS.
//! - The format is documented for users in `organs/README.md`; [`Manifest::validate`] enforces it.

use serde::{Deserialize, Serialize};

/// The format tag written into every manifest.
pub const FORMAT: &str = "vbrain-organ-set/1";

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Always [`FORMAT`].
    pub format: String,
    pub title: String,
    /// Units of the mesh coordinates; only "mm" is accepted.
    #[serde(default = "default_units")]
    pub units: String,
    /// Coordinate convention; only "RAS" (+x right, +y anterior, +z superior) is accepted.
    #[serde(default = "default_coordinates")]
    pub coordinates: String,
    #[serde(default)]
    pub description: String,
    #[serde(default)]
    pub sources: Vec<Source>,
    pub organs: Vec<OrganEntry>,
    /// Groups of organs that together form one solid, for occlusion culling.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub solids: Vec<SolidEntry>,
    /// The set's MRI (a 3-D NIfTI file inside the set's folder, registered to its organs), for cut
    /// faces and slice views ([`crate::mri`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mri: Option<String>,
    /// The set's arterial territories: a territories file inside the set's folder
    /// ([`crate::organ_set::territory`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub territories: Option<String>,
}

/// Organs that together fill one solid (their closed surfaces meet face to face, as a seamless
/// set's do), and the occluder stand-in inside their union that `vbrain stand-ins` builds.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SolidEntry {
    /// Unique among the solids: letters, digits, `_` and `-`.
    pub id: String,
    /// The organs' ids.
    pub organs: Vec<String>,
    /// The stand-in's mesh (relative path, like an organ's `mesh`), once built.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub occluder: Option<String>,
    /// The faces inside it, once found (relative path to a JSON file of triangle ranges per organ,
    /// [`super::hidden_faces`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hidden: Option<String>,
}

/// Where data came from, under which licence, and whom to credit.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Source {
    pub name: String,
    #[serde(default)]
    pub url: String,
    pub licence: String,
    pub attribution: String,
}

#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OrganEntry {
    /// Unique within the set: letters, digits, `_` and `-`.
    pub id: String,
    pub name: String,
    /// Path of the `.vbo`/`.obj` file relative to the manifest's folder; must stay inside it.
    pub mesh: String,
    /// Optional mesh with fewer triangles on or inside the organ's surface that stands in for it
    /// as an occluder (relative path, like `mesh`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub occluder: Option<String>,
    /// Optional levels of detail of the mesh, drawn while the view moves ([`crate::lod`]; relative
    /// path, like `mesh`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lod: Option<String>,
    /// `#rrggbb` (sRGB).
    pub colour: String,
    #[serde(default = "one")]
    pub opacity: f32,
    #[serde(default = "yes")]
    pub visible: bool,
    /// Group path in the organ tree, `/`-separated, e.g. `Cerebrum/Left hemisphere/Frontal lobe`.
    #[serde(default)]
    pub group: String,
    /// Terminologia Anatomica's Latin name, where there is one (e.g. `Gyrus precentralis`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub latin: Option<String>,
    /// Other names a student may search for: abbreviations, eponyms, functional names.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub synonyms: Vec<String>,
    /// A short text for students.
    #[serde(default)]
    pub info: String,
}

fn default_units() -> String {
    "mm".into()
}
fn default_coordinates() -> String {
    "RAS".into()
}
fn one() -> f32 {
    1.0
}
fn yes() -> bool {
    true
}

/// Parses `#rrggbb` into sRGB components in 0..=1.
pub fn parse_colour(s: &str) -> Option<[f32; 3]> {
    let hex = s.strip_prefix('#')?;
    // Six hex digits: from_str_radix alone would take a sign ("#+f+f+f").
    if hex.len() != 6 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let c = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).ok().map(|v| v as f32 / 255.0);
    Some([c(0)?, c(2)?, c(4)?])
}

/// Formats sRGB components in 0..=1 as `#rrggbb`.
pub fn format_colour(c: [f32; 3]) -> String {
    let b = c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
    format!("#{:02x}{:02x}{:02x}", b[0], b[1], b[2])
}

/// The most organs (and the most solids) a manifest may list.
pub const MAX_ORGANS: usize = 10_000;

impl Manifest {
    /// Checks the set-wide fields (and the organ count, [`MAX_ORGANS`]); returns one message per
    /// problem.
    pub fn validate(&self) -> Vec<String> {
        let mut problems = Vec::new();
        if self.format != FORMAT {
            problems.push(format!("format is \"{}\", expected \"{FORMAT}\"", self.format));
        }
        if self.units != "mm" {
            problems.push(format!("units \"{}\" not supported (only \"mm\")", self.units));
        }
        if self.coordinates != "RAS" {
            problems.push(format!("coordinates \"{}\" not supported (only \"RAS\")", self.coordinates));
        }
        if self.organs.len() > MAX_ORGANS || self.solids.len() > MAX_ORGANS {
            problems.push(format!(
                "{} organs and {} solids: a set has at most {MAX_ORGANS} of each",
                self.organs.len(),
                self.solids.len()
            ));
        }
        problems
    }
}

impl OrganEntry {
    /// Checks one organ's fields (not its mesh file); returns the first problem.
    pub fn validate(&self) -> Result<(), EntryProblem> {
        let id = || self.id.clone();
        if !id_ok(&self.id) {
            return Err(EntryProblem::Id(id()));
        }
        if !(0.0..=1.0).contains(&self.opacity) {
            return Err(EntryProblem::Opacity(id(), self.opacity));
        }
        if parse_colour(&self.colour).is_none() {
            return Err(EntryProblem::Colour(id(), self.colour.clone()));
        }
        let path = |what, p: &str| {
            mesh_path_ok(p).map_err(|problem| EntryProblem::Path { id: id(), what, path: p.to_string(), problem })
        };
        path("mesh", &self.mesh)?;
        if let Some(p) = &self.occluder {
            path("occluder", p)?;
        }
        match &self.lod {
            Some(p) => path("lod", p),
            None => Ok(()),
        }
    }
}

/// What is wrong with one organ's entry in a manifest.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EntryProblem {
    #[error("organ id \"{0}\" must be non-empty letters, digits, _ or -")]
    Id(String),
    #[error("organ \"{0}\": opacity {1} outside 0..1")]
    Opacity(String, f32),
    #[error("organ \"{0}\": colour \"{1}\" is not #rrggbb")]
    Colour(String, String),
    #[error("organ \"{id}\": {what} \"{path}\" {problem}")]
    Path { id: String, what: &'static str, path: String, problem: PathProblem },
}

/// Why a mesh path is refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum PathProblem {
    #[error("is empty")]
    Empty,
    #[error("escapes the set's folder")]
    Escapes,
    #[error("must be a relative path inside the set's folder")]
    Absolute,
}

/// An organ's or a solid's id: non-empty letters, digits, `_` and `-`.
pub(crate) fn id_ok(id: &str) -> bool {
    !id.is_empty() && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// A mesh path must be relative and must not climb out of the set's folder.
pub(crate) fn mesh_path_ok(p: &str) -> Result<(), PathProblem> {
    use std::path::Component;
    let path = std::path::Path::new(p);
    if p.is_empty() {
        return Err(PathProblem::Empty);
    }
    let mut depth = 0i32;
    for c in path.components() {
        match c {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir => {
                depth -= 1;
                if depth < 0 {
                    return Err(PathProblem::Escapes);
                }
            }
            Component::RootDir | Component::Prefix(_) => return Err(PathProblem::Absolute),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_round_trip() {
        assert_eq!(parse_colour("#ff8000"), Some([1.0, 128.0 / 255.0, 0.0]));
        assert_eq!(format_colour([1.0, 128.0 / 255.0, 0.0]), "#ff8000");
        assert_eq!(parse_colour("ff8000"), None);
        assert_eq!(parse_colour("#ff80"), None);
        assert_eq!(parse_colour("#+f+f+f"), None, "a sign is not a digit");
        assert_eq!(parse_colour("#-1-1-1"), None);
        assert_eq!(parse_colour("#ééé"), None);
    }

    #[test]
    fn mesh_paths() {
        assert!(mesh_path_ok("meshes/a.vbo").is_ok());
        assert!(mesh_path_ok("a/../b.vbo").is_ok());
        assert!(mesh_path_ok("../a.vbo").is_err());
        assert!(mesh_path_ok("a/../../b.vbo").is_err());
        assert!(mesh_path_ok("/etc/passwd").is_err());
    }
}
