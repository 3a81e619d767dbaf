//! Lessons (`.vblesson`, JSON, `"format": "vbrain-lesson/1"`): a title, the organ set (a path
//! relative to the lesson file) and ordered steps. A step says what differs from the set's default
//! layout (organs or groups shown, hidden, faded, by id or group path as
//! [`OrganSet::select`] reads them), where the camera looks (azimuth and elevation in degrees from
//! the anterior view, toward the subject's right and upward, and a distance relative to the framed
//! one), a caption in simple markup (`**bold**`, `*italics*`, lines starting `- ` as a list) and
//! the organs to highlight. Steps are applied in order to the default layout each time, so each
//! step stands alone.
//!
//! Reading never panics: a file that is not JSON names itself and the line; a newer format says
//! so; ids and groups the set does not have are collected as warnings, once each.

use crate::error::{Error, Result};
use crate::layout::Layout;
use crate::navigation::Navigator;
use crate::organ_set::OrganSet;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub const FORMAT: &str = "vbrain-lesson/1";
/// The file name extension of lessons.
pub const EXTENSION: &str = "vblesson";

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Lesson {
    pub format: String,
    pub title: String,
    /// The organ set, relative to the lesson file's folder (or absolute).
    pub set: PathBuf,
    pub steps: Vec<Step>,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Step {
    pub title: String,
    pub caption: String,
    /// Camera azimuth and elevation, degrees from the anterior view.
    #[serde(default)]
    pub view: [f32; 2],
    /// Camera distance relative to the distance that frames the set (below 1 moves in).
    #[serde(default = "one")]
    pub zoom: f32,
    /// Ids or groups shown (e.g. the skull, hidden by default).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub show: Vec<String>,
    /// Ids or groups hidden.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hide: Vec<String>,
    /// Opacity by id or group, applied in key order after `show` and `hide`.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub opacity: BTreeMap<String, f32>,
    /// Organ ids or groups the step points at.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub highlight: Vec<String>,
}

fn one() -> f32 {
    1.0
}

/// A step over a set: its layout, camera and highlighted organs.
#[derive(Clone, Debug)]
pub struct StepView {
    pub layout: Layout,
    pub navigator: Navigator,
    pub highlight: Vec<usize>,
}

impl Lesson {
    /// Parses a lesson's text; `path` names it in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Lesson> {
        let value: serde_json::Value =
            serde_json::from_str(text).map_err(|e| Error::parse(path, Some(e.line()), e.to_string()))?;
        match value.get("format").and_then(|f| f.as_str()) {
            Some(FORMAT) => {}
            Some(f) if f.starts_with("vbrain-lesson/") => {
                return Err(Error::parse(
                    path,
                    None,
                    format!("format \"{f}\": written by a newer vbrain (this one reads {FORMAT})"),
                ))
            }
            _ => return Err(Error::parse(path, None, format!("not a vbrain lesson (\"format\": \"{FORMAT}\")"))),
        }
        let lesson: Lesson =
            serde_json::from_str(text).map_err(|e| Error::parse(path, Some(e.line()), e.to_string()))?;
        if lesson.steps.is_empty() {
            return Err(Error::parse(path, None, "a lesson needs at least one step"));
        }
        Ok(lesson)
    }

    pub fn load(path: &Path) -> Result<Lesson> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        Lesson::parse(&text, path)
    }

    /// The set's path for a lesson read from `lesson_path`.
    pub fn set_path(&self, lesson_path: &Path) -> PathBuf {
        if self.set.is_absolute() {
            self.set.clone()
        } else {
            lesson_path.parent().unwrap_or(Path::new("")).join(&self.set)
        }
    }

    /// Every id or group of every step that `set` does not have, once each.
    pub fn unknown_names(&self, set: &OrganSet) -> Vec<String> {
        let mut unknown: Vec<String> = Vec::new();
        for s in &self.steps {
            let names = s.show.iter().chain(&s.hide).chain(s.opacity.keys()).chain(&s.highlight);
            for n in names {
                if set.select(n).is_empty() && !unknown.contains(n) {
                    unknown.push(n.clone());
                }
            }
        }
        unknown
    }
}

impl Step {
    /// This step over `set`: the default layout changed as it says, the camera framing the set's
    /// default layout from its view, and the highlighted organs. Names the set lacks are skipped
    /// (see [`Lesson::unknown_names`]).
    pub fn view(&self, set: &OrganSet) -> StepView {
        let mut layout = Layout::new(set);
        for (names, visible) in [(&self.show, true), (&self.hide, false)] {
            for n in names {
                for i in set.select(n) {
                    layout.organs[i].visible = visible;
                }
            }
        }
        for (n, &a) in &self.opacity {
            for i in set.select(n) {
                layout.organs[i].opacity = if a.is_finite() { a.clamp(0.0, 1.0) } else { 1.0 };
            }
        }
        let mut navigator = Navigator::framing(&Layout::new(set).bounds(set), self.view[0], self.view[1]);
        if self.zoom.is_finite() && self.zoom > 0.0 {
            navigator.distance *= self.zoom;
        }
        let mut highlight: Vec<usize> = self.highlight.iter().flat_map(|n| set.select(n)).collect();
        highlight.dedup();
        StepView { layout, navigator, highlight }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;
    use crate::organ_set::Organ;

    fn set() -> OrganSet {
        let organ = |id: &str, group: &str| {
            let mut o = Organ::new(id.into(), id.into(), [0.5; 3], Mesh::octahedron());
            o.group = group.into();
            o
        };
        OrganSet { organs: vec![organ("a", "G/One"), organ("b", "G/One"), organ("c", "H")], ..Default::default() }
    }

    #[test]
    fn a_step_changes_the_default_layout_by_id_and_group() {
        let text = r#"{"format": "vbrain-lesson/1", "title": "T", "set": "../set", "steps": [
            {"title": "s", "caption": "**x**", "view": [-90, 10], "zoom": 0.5, "hide": ["One"],
             "show": ["c"], "opacity": {"c": 0.25}, "highlight": ["c", "zz"]}]}"#;
        let lesson = Lesson::parse(text, Path::new("l.vblesson")).unwrap();
        let set = set();
        let v = lesson.steps[0].view(&set);
        assert!(!v.layout.organs[0].visible && !v.layout.organs[1].visible && v.layout.organs[2].visible);
        assert_eq!(v.layout.organs[2].opacity, 0.25);
        assert_eq!(v.highlight, vec![2]);
        assert_eq!(v.navigator.azimuth, -90.0);
        let framed = Navigator::framing(&Layout::new(&set).bounds(&set), -90.0, 10.0);
        assert!((v.navigator.distance - framed.distance * 0.5).abs() < 1e-3);
        assert_eq!(lesson.unknown_names(&set), vec!["zz".to_string()]);
        assert_eq!(lesson.set_path(Path::new("/x/lessons/l.vblesson")), Path::new("/x/lessons/../set"));
    }

    #[test]
    fn bad_lessons_name_the_file_and_line() {
        let p = Path::new("bad.vblesson");
        let e = Lesson::parse("{\n\"format\": \"vbrain-lesson/1\",\n\"title\": 3}", p).unwrap_err();
        assert!(e.to_string().starts_with("bad.vblesson:3:"), "{e}");
        let e = Lesson::parse(r#"{"format": "vbrain-lesson/7"}"#, p).unwrap_err();
        assert!(e.to_string().contains("newer vbrain"), "{e}");
        let e =
            Lesson::parse(r#"{"format": "vbrain-lesson/1", "title": "t", "set": ".", "steps": []}"#, p).unwrap_err();
        assert!(e.to_string().contains("at least one step"), "{e}");
        let step_typo = r#"{"format": "vbrain-lesson/1", "title": "t", "set": ".", "steps": [
            {"title": "s", "caption": "c", "hid": ["a"]}]}"#;
        assert!(Lesson::parse(step_typo, p).unwrap_err().to_string().contains("hid"), "a misspelt key is named");
    }
}
