//! Scene files (`.vbscene`, JSON, `"format": "vbrain-scene/1"`): exactly what is on screen, to
//! reopen on another machine. docs/SCENES.md documents the format with an example.
//!
//! - Contents: the organ set (its path relative to the scene file where it can be, and its
//!   fingerprint), the camera (the navigator's target, distance and angles, orbit or
//!   walk-through), every organ's visibility, opacity, colour and transform by id, the render
//!   settings a user chose (transparency, culling mode, background) and the selection.
//! - World space is millimetres, RAS; angles are degrees.
//! - Keys come in a fixed order and floats are written exactly (shortest round trip), so a scene
//!   diffs well and reopens to the same pixels.
//! - Reading never panics: a file that is not JSON or has a bad value names itself and the line;
//!   one of a newer format version says so; organs the set does not have are listed once as
//!   warnings, and organs the scene does not name keep the set's defaults.

use crate::cull::CullMode;
use crate::error::{Error, Result};
use crate::layout::{Layout, OrganState, Transform};
use crate::navigation::Navigator;
use crate::organ_set::OrganSet;
use crate::transparency::TransparencySettings;
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::path::{Component, Path, PathBuf};

pub const FORMAT: &str = "vbrain-scene/1";
/// The file name extension of scene files.
pub const EXTENSION: &str = "vbscene";

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneFile {
    pub format: String,
    pub set: SetRef,
    pub camera: CameraState,
    pub render: RenderState,
    /// The selected organ's id.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub selection: Option<String>,
    /// Clip planes cutting the set (world RAS, removing `n . p > d`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub clip: Vec<crate::clip::ClipPlane>,
    /// Solid cut faces where planes cut closed organs.
    #[serde(default = "crate::json_file::yes", skip_serializing_if = "crate::json_file::is_true")]
    pub caps: bool,
    /// What cut faces show: the organs' colours (absent), the set's MRI or the MRI tinted.
    #[serde(default, skip_serializing_if = "crate::clip::CutFace::is_default")]
    pub cut_face: crate::clip::CutFace,
    /// Ids or groups the planes do not cut.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub whole: Vec<String>,
    /// Which organs are labelled: "selected", "all" or ids and groups separated by commas (none
    /// when absent; see [`crate::labels::Which`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub labels: Option<String>,
    /// What colours the organs: `organ` (absent), `lobe` or `territory`.
    #[serde(default, skip_serializing_if = "crate::layout::ColourBy::is_default")]
    pub colour_by: crate::layout::ColourBy,
    /// Every organ of the set, in the set's order.
    pub organs: Vec<OrganEntry>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SetRef {
    /// The set's folder or file: relative to the scene file's folder where it can be.
    pub path: PathBuf,
    /// The set's content (`cull::database::set_fingerprint`): another value means the set changed.
    pub fingerprint: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum CameraMode {
    Orbit,
    Walk,
}

/// The navigator: the eye at `distance` from `target`, turned by `azimuth` (toward the subject's
/// right) and `elevation` (upward) from the anterior view.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct CameraState {
    pub mode: CameraMode,
    pub target: [f32; 3],
    pub distance: f32,
    pub azimuth: f32,
    pub elevation: f32,
}

impl CameraState {
    pub fn of(nav: &Navigator, mode: CameraMode) -> CameraState {
        CameraState {
            mode,
            target: nav.target.to_array(),
            distance: nav.distance,
            azimuth: nav.azimuth,
            elevation: nav.elevation,
        }
    }

    /// What makes this camera unusable, if anything: a target beyond 1 km of the origin, a
    /// distance not in (0, 10 km], an angle beyond +-1,000,000 degrees, or any non-number.
    pub fn problem(&self) -> Option<String> {
        if !self.target.iter().all(|v| v.is_finite() && v.abs() <= 1e6) {
            return Some(format!("camera target {:?} is not a point within 1 km (1e6 mm) of the origin", self.target));
        }
        if !(self.distance.is_finite() && self.distance > 0.0 && self.distance <= 1e7) {
            return Some(format!("camera distance {} is not in (0, 1e7] mm", self.distance));
        }
        angle_problem("camera", [self.azimuth, self.elevation])
    }

    pub fn navigator(&self) -> Navigator {
        Navigator {
            target: Vec3::from(self.target),
            distance: self.distance,
            azimuth: self.azimuth,
            elevation: self.elevation,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RenderState {
    pub transparency: TransparencySettings,
    pub cull: CullMode,
    /// sRGB, 0..=1.
    pub background: [f32; 3],
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OrganEntry {
    pub id: String,
    pub visible: bool,
    pub opacity: f32,
    /// sRGB, 0..=1.
    pub colour: [f32; 3],
    /// Millimetres, world space.
    pub translation: [f32; 3],
    /// Degrees about x, y, z (applied in that order), about the organ's centre.
    pub rotation: [f32; 3],
    pub scale: f32,
}

/// A scene read back into a set: the layout and selection, with what did not fit.
#[derive(Clone, Debug)]
pub struct Applied {
    pub layout: Layout,
    pub selection: Option<usize>,
    /// Problems worth a word, each once: organs the set does not have, a changed set.
    pub warnings: Vec<String>,
}

impl SceneFile {
    /// The scene's section as saved (its `clip`, `caps` and `whole`).
    pub fn section(&self) -> crate::clip::SavedSection {
        crate::clip::SavedSection {
            planes: self.clip.clone(),
            caps: self.caps,
            faces: self.cut_face,
            whole: self.whole.clone(),
        }
    }

    /// Keeps `section` as the scene's.
    pub fn set_section(&mut self, section: crate::clip::SavedSection) {
        (self.clip, self.caps, self.cut_face, self.whole) =
            (section.planes, section.caps, section.faces, section.whole);
    }

    /// The scene of `layout` over `set` (opened from `set_path`), to be saved at `scene_path`.
    pub fn capture(
        set: &OrganSet,
        set_path: &Path,
        scene_path: &Path,
        layout: &Layout,
        camera: CameraState,
        render: RenderState,
        selection: Option<usize>,
    ) -> SceneFile {
        let organs = set
            .organs
            .iter()
            .zip(&layout.organs)
            .map(|(o, s)| OrganEntry {
                id: o.id.clone(),
                visible: s.visible,
                opacity: s.opacity,
                colour: s.colour,
                translation: s.transform.translation.to_array(),
                rotation: s.transform.rotation_deg.to_array(),
                scale: s.transform.scale,
            })
            .collect();
        SceneFile {
            format: FORMAT.into(),
            set: SetRef {
                path: relative_to(set_path, scene_path.parent().unwrap_or(Path::new(""))),
                fingerprint: crate::cull::database::set_fingerprint(set),
            },
            camera,
            render,
            selection: selection.and_then(|i| set.organs.get(i)).map(|o| o.id.clone()),
            clip: Vec::new(),
            caps: true,
            cut_face: Default::default(),
            whole: Vec::new(),
            labels: None,
            colour_by: layout.colour_by,
            organs,
        }
    }

    /// The JSON text: keys in the order of the structs, two-space indents, a final newline.
    pub fn to_json(&self, path: &Path) -> Result<String> {
        crate::json_file::to_json(self, path)
    }

    /// Writes the scene atomically.
    pub fn save(&self, path: &Path) -> Result<()> {
        crate::json_file::save(self, path)
    }

    /// Parses a scene file's text; `path` names it in errors.
    /// A camera that makes no picture is refused; render settings out of range are brought into
    /// it (as the viewer's settings are).
    pub fn parse(text: &str, path: &Path) -> Result<SceneFile> {
        let mut scene: SceneFile = crate::json_file::parse(text, path, FORMAT, "scene")?;
        if let Some(problem) = scene.camera.problem().or_else(|| crate::clip::planes_problem(&scene.clip)) {
            return Err(Error::parse(path, None, problem));
        }
        for e in &scene.organs {
            Transform::from_parts(e.translation, e.rotation, e.scale, Vec3::ZERO)
                .map_err(|problem| Error::parse(path, None, format!("organ \"{}\": {problem}", e.id)))?;
        }
        scene.render.transparency = scene.render.transparency.clamped();
        scene.render.background = scene.render.background.map(|c| if c.is_finite() { c.clamp(0.0, 1.0) } else { 0.0 });
        Ok(scene)
    }

    /// Reads a scene file.
    pub fn load(path: &Path) -> Result<SceneFile> {
        let text = crate::input::read_text(path, crate::input::Kind::Document)?;
        SceneFile::parse(&text, path)
    }

    /// The set's path, for a scene read from `scene_path`.
    pub fn set_path(&self, scene_path: &Path) -> PathBuf {
        if self.set.path.is_absolute() {
            self.set.path.clone()
        } else {
            scene_path.parent().unwrap_or(Path::new("")).join(&self.set.path)
        }
    }

    /// The layout and selection of this scene over `set`.
    pub fn apply(&self, set: &OrganSet) -> Applied {
        let mut layout = Layout { colour_by: self.colour_by, ..Layout::new(set) };
        let mut unknown = Vec::new();
        for e in &self.organs {
            match set.find(&e.id) {
                Some(i) => {
                    let pivot = layout.organs[i].transform.pivot;
                    layout.organs[i] = OrganState {
                        visible: e.visible,
                        opacity: if e.opacity.is_finite() { e.opacity.clamp(0.0, 1.0) } else { 1.0 },
                        colour: e.colour.map(|c| if c.is_finite() { c.clamp(0.0, 1.0) } else { 0.5 }),
                        transform: Transform::from_parts(e.translation, e.rotation, e.scale, pivot)
                            .unwrap_or(Transform::identity(pivot)),
                    };
                }
                None => unknown.push(e.id.as_str()),
            }
        }
        let mut warnings = Vec::new();
        if !unknown.is_empty() {
            warnings.push(format!("the set has no organ {}: left out", list(&unknown)));
        }
        if self.set.fingerprint != crate::cull::database::set_fingerprint(set) {
            warnings.push("the organ set changed since the scene was saved; it may look different".into());
        }
        let selection = self.selection.as_deref().and_then(|id| set.find(id));
        Applied { layout, selection, warnings }
    }
}

/// A problem with azimuth and elevation `angles` (of `what`): not finite, or beyond +-1e6 degrees
/// (where a degree no longer holds a pixel's precision).
pub(crate) fn angle_problem(what: &str, angles: [f32; 2]) -> Option<String> {
    (!angles.iter().all(|a| a.is_finite() && a.abs() <= 1e6))
        .then(|| format!("{what} angles {angles:?} are not degrees within +-1000000"))
}

/// Up to five ids quoted, then how many more.
fn list(ids: &[&str]) -> String {
    let mut s: Vec<String> = ids.iter().take(5).map(|id| format!("\"{id}\"")).collect();
    if ids.len() > 5 {
        s.push(format!("and {} more", ids.len() - 5));
    }
    s.join(", ")
}

/// `path` relative to the folder `base` where both are relative or both absolute (after making
/// them absolute against the working directory); else `path` as given.
pub(crate) fn relative_to(path: &Path, base: &Path) -> PathBuf {
    let absolute = |p: &Path| std::path::absolute(p).ok();
    let (Some(p), Some(b)) = (absolute(path), absolute(base)) else {
        return path.to_path_buf();
    };
    let (p, b): (Vec<Component>, Vec<Component>) = (p.components().collect(), b.components().collect());
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == 0 {
        return path.to_path_buf();
    }
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c);
    }
    if out.as_os_str().is_empty() {
        out.push(".");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::organ_set::Organ;

    fn set() -> OrganSet {
        let organ = |id: &str| Organ::new(id.into(), id.to_uppercase(), [0.5, 0.5, 0.5], Mesh::octahedron());
        OrganSet { title: "t".into(), organs: vec![organ("a"), organ("b"), organ("c")], ..Default::default() }
    }

    fn scene(set: &OrganSet, layout: &Layout) -> SceneFile {
        let nav = Navigator { target: Vec3::new(1.5, -2.25, 0.1), distance: 333.3, azimuth: 12.7, elevation: -3.1 };
        let render =
            RenderState { transparency: Default::default(), cull: CullMode::Occlusion, background: [0.1, 0.2, 0.3] };
        SceneFile::capture(
            set,
            Path::new("/data/sets/brain"),
            Path::new("/data/scenes/x.vbscene"),
            layout,
            CameraState::of(&nav, CameraMode::Orbit),
            render,
            Some(1),
        )
    }

    #[test]
    fn a_scene_round_trips_exactly() {
        let set = set();
        let mut layout = Layout::new(&set);
        layout.organs[0].opacity = 0.123_456_79;
        layout.organs[1].visible = false;
        layout.organs[2].transform.translation = Vec3::new(0.1, 1e-7, -30.000_002);
        layout.organs[2].transform.rotation_deg = Vec3::new(33.3, 0.0, -1.0);
        layout.organs[2].transform.scale = 1.1;
        let mut s = scene(&set, &layout);
        assert_eq!(s.set.path, Path::new("../sets/brain"));
        assert!(!s.to_json(Path::new("x")).unwrap().contains("clip"), "no planes, no key");
        s.clip = vec![crate::clip::ClipPlane::parse("coronal=-7.25:flip").unwrap()];
        (s.caps, s.labels, s.whole) = (false, Some("all".into()), vec!["brainstem".into()]);
        let text = s.to_json(Path::new("x.vbscene")).unwrap();
        let back = SceneFile::parse(&text, Path::new("x.vbscene")).unwrap();
        assert_eq!(back, s);
        let applied = back.apply(&set);
        assert_eq!(applied.layout, layout);
        assert_eq!(applied.selection, Some(1));
        assert!(applied.warnings.is_empty(), "{:?}", applied.warnings);
        assert_eq!(back.camera.navigator(), s.camera.navigator());
        assert_eq!(back.set_path(Path::new("/data/scenes/x.vbscene")), Path::new("/data/scenes/../sets/brain"));
        // Keys in a fixed order: the format first.
        assert!(text.starts_with("{\n  \"format\": \"vbrain-scene/1\",\n  \"set\""), "{text}");
    }

    #[test]
    fn planes_and_cut_faces_are_checked_where_they_are_read() {
        let set = set();
        let mut s = scene(&set, &Layout::new(&set));
        s.clip = vec![crate::clip::ClipPlane::parse("axial=3").unwrap()];
        s.cut_face = crate::clip::CutFace { show: crate::clip::CutFaceShows::Mri, ..Default::default() };
        let mut coloured = Layout::new(&set);
        coloured.colour_by = crate::layout::ColourBy::Territory;
        s.colour_by = scene(&set, &coloured).colour_by;
        let good = s.to_json(Path::new("x.vbscene")).unwrap();
        assert!(good.contains("\"colour_by\": \"territory\""), "{good}");
        assert_eq!(SceneFile::parse(&good, Path::new("x.vbscene")).unwrap(), s, "the cut faces round-trip");
        assert_eq!(s.apply(&set).layout.colour_by, crate::layout::ColourBy::Territory);
        let lobes = good.replace("\"territory\"", "\"lobes\"");
        let e = SceneFile::parse(&lobes, Path::new("x.vbscene")).unwrap_err().to_string();
        assert!(e.contains("x.vbscene:") && e.contains("lobes"), "{e}");
        let p = Path::new("bad.vbscene");
        let plane = "\"normal\": [\n        0.0,\n        0.0,\n        1.0\n      ],\n      \"d\": 3.0";
        assert!(good.contains(plane), "{good}");
        for (bad, says) in [
            (good.replace(plane, "\"normal\": [0.0, 0.0, 0.0], \"d\": 3.0"), "non-zero normal"),
            (good.replace(plane, "\"normal\": [0.0, 0.0, 1.0], \"d\": 1e30"), "within 10000 mm"),
            (good.replace(plane, "\"normal\": [0.0, 0.0, 1.0], \"d\": 3.0, \"e\": 1"), "unknown field"),
            (good.replace("\"level\": 0.6", "\"level\": 9.0"), "level"),
            (good.replace("\"show\": \"mri\"", "\"show\": \"xray\""), "unknown variant"),
        ] {
            let e = SceneFile::parse(&bad, p).unwrap_err().to_string();
            assert!(e.starts_with("bad.vbscene") && e.contains(says), "{says}: {e}");
        }
        // A byte-order mark before the text is no error; a format with a stray space is not "newer".
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("bom.vbscene");
        std::fs::write(&file, format!("\u{feff}{good}")).unwrap();
        assert_eq!(SceneFile::load(&file).unwrap(), s);
        let e = SceneFile::parse(&good.replace("vbrain-scene/1", "vbrain-scene/1 "), p).unwrap_err().to_string();
        assert!(e.contains("is not a vbrain scene") && !e.contains("newer"), "{e}");
        let e = SceneFile::parse(&good.replace("vbrain-scene/1", "vbrain-scene/2"), p).unwrap_err().to_string();
        assert!(e.contains("newer"), "{e}");
        s.clip = vec![crate::clip::ClipPlane::parse("axial=3").unwrap(); 5];
        let five = s.to_json(p).unwrap();
        let e = SceneFile::parse(&five, p).unwrap_err().to_string();
        assert!(e.contains("5 clip planes") && e.contains("at most 4"), "{e}");
    }

    #[test]
    fn bad_scenes_name_the_file_and_line_and_the_rest_applies() {
        let p = Path::new("bad.vbscene");
        let e = SceneFile::parse("{\n  \"format\": \"vbrain-scene/1\",\n  \"set\": 3\n}", p).unwrap_err();
        assert!(e.to_string().starts_with("bad.vbscene:3:"), "{e}");
        let e = SceneFile::parse("{\"format\": \"vbrain-scene/2\"}", p).unwrap_err();
        assert!(e.to_string().contains("newer vbrain"), "{e}");
        let e = SceneFile::parse("not json", p).unwrap_err();
        assert!(e.to_string().starts_with("bad.vbscene:1:"), "{e}");
        assert!(SceneFile::parse("{\"format\": \"vbrain-organ-set/1\"}", p).is_err());

        let set = set();
        let mut s = scene(&set, &Layout::new(&set));
        s.organs[0].id = "zz".into();
        s.organs[1].opacity = f32::NAN;
        s.set.fingerprint = "other".into();
        let applied = s.apply(&set);
        assert_eq!(applied.warnings.len(), 2, "{:?}", applied.warnings);
        assert!(applied.warnings[0].contains("\"zz\""));
        assert_eq!(applied.layout.organs[1].opacity, 1.0);
        assert_eq!(applied.layout.organs[0], Layout::new(&set).organs[0], "organs not named keep their defaults");
    }
}
