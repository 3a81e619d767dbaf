//! Lessons (`.vblesson`, JSON, `"format": "vbrain-lesson/1"`): a title, the organ set (a path
//! relative to the lesson file) and ordered steps. [`LessonEdit`]s change a lesson one undoable
//! step at a time.
//!
//! - A step says what differs from the set's default layout (organs or groups shown, hidden,
//!   faded, by id or group path as [`OrganSet::select`] reads them), where the camera looks, a
//!   caption in simple markup (`**bold**`, `*italics*`, lines starting `- ` as a list) and the
//!   organs to highlight.
//! - The camera: azimuth and elevation in degrees from the anterior view, toward the subject's
//!   right and upward, and a distance relative to the framed one.
//! - Steps are applied in order to the default layout each time, so each step stands alone.
//! - A step made in the viewer ([`Step::capture`]) says everything that differs from the default
//!   layout, colours and placements (millimetres and degrees, world space) too, and holds the
//!   camera exactly where it is not the framed view of an angle.
//! - Reading never panics: a file that is not JSON names itself and the line; a newer format says
//!   so; ids and groups the set does not have are collected as warnings, once each.

use crate::clip::{SavedSection, Section};
use crate::error::{Error, Result};
use crate::labels::Which;
use crate::layout::ColourBy;
use crate::layout::{Layout, Transform};
use crate::navigation::Navigator;
use crate::organ_set::OrganSet;
use crate::scene_file::{CameraMode, CameraState};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

pub const FORMAT: &str = "vbrain-lesson/1";
/// The file name extension of lessons.
pub const EXTENSION: &str = "vblesson";

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lesson {
    pub format: String,
    pub title: String,
    /// The organ set, relative to the lesson file's folder (or absolute).
    pub set: PathBuf,
    pub steps: Vec<Step>,
    /// The instructor's quiz on the lesson: questions in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub quiz: Vec<QuizQuestion>,
    /// The share of the quiz, in per cent (0..=100), that passes it where a learning platform
    /// records the result (a SCORM package); [`DEFAULT_PASS_MARK`] where not given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pass_mark: Option<f32>,
}

/// The pass mark of a lesson's quiz, in per cent, where the lesson sets none.
pub const DEFAULT_PASS_MARK: f32 = 70.0;

/// A question of a lesson's quiz: its kind, the organ's id and, optionally, the ids offered as
/// choices (else the nearest structures, as generated quizzes choose them).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QuizQuestion {
    pub kind: crate::quiz::Kind,
    pub organ: String,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub choices: Vec<String>,
    /// The step (1-based) whose layout and camera the question starts from, instead of the
    /// default layout seen from the structure's side.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step: Option<usize>,
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
    /// Colour by id (sRGB, 0..=1), where it differs from the set's.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub colour: BTreeMap<String, [f32; 3]>,
    /// Placement by id, where an organ is moved.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub place: BTreeMap<String, Placement>,
    /// The camera exactly (instead of `view` and `zoom`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraState>,
    /// Organ ids or groups the step points at.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub highlight: Vec<String>,
    /// Clip planes cutting the set (world RAS, removing `n . p > d`), as scene files keep them.
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
    /// Which organs are labelled (`none`, `selected`, `all` or ids and groups); absent, the
    /// viewer's own choice.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub labels: Option<String>,
    /// What colours the organs: `organ` (absent), `lobe` or `territory`.
    #[serde(default, skip_serializing_if = "ColourBy::is_default")]
    pub colour_by: ColourBy,
}

/// Where an organ is moved: millimetres (world space), degrees about x, y, z about its centre, and
/// a scale.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Placement {
    pub translation: [f32; 3],
    pub rotation: [f32; 3],
    pub scale: f32,
}

fn one() -> f32 {
    1.0
}

/// One undoable change to a lesson.
#[derive(Clone, Debug, PartialEq)]
pub enum LessonEdit {
    /// Insert a step before index `at` (at the end if past it).
    Insert {
        at: usize,
        step: Box<Step>,
    },
    Remove(usize),
    /// Move step `from` to index `to`.
    Move {
        from: usize,
        to: usize,
    },
    /// Replace step `at`.
    Replace {
        at: usize,
        step: Box<Step>,
    },
    Retitle(String),
}

/// A step over a set: its layout, camera and highlighted organs.
#[derive(Clone, Debug)]
pub struct StepView {
    pub layout: Layout,
    pub navigator: Navigator,
    /// The camera walks through rather than orbits.
    pub fly: bool,
    pub highlight: Vec<usize>,
    pub section: Section,
    /// `None`: the step leaves labels to the viewer.
    pub labels: Option<Which>,
}

/// The most steps, and the most quiz questions, a lesson may have.
pub const MAX_STEPS: usize = 500;

impl Lesson {
    /// Parses a lesson's text; `path` names it in errors (a lesson has at most [`MAX_STEPS`] steps
    /// and questions, each step at most [`crate::clip::MAX_PLANES`] planes).
    pub fn parse(text: &str, path: &Path) -> Result<Lesson> {
        let lesson: Lesson = crate::json_file::parse(text, path, FORMAT, "lesson")?;
        if lesson.steps.is_empty() {
            return Err(Error::parse(path, None, "a lesson needs at least one step"));
        }
        if lesson.steps.len() > MAX_STEPS || lesson.quiz.len() > MAX_STEPS {
            let (steps, questions) = (lesson.steps.len(), lesson.quiz.len());
            return Err(Error::parse(
                path,
                None,
                format!("{steps} steps and {questions} quiz questions: a lesson has at most {MAX_STEPS} of each"),
            ));
        }
        if let Some(k) = lesson.quiz.iter().position(|q| q.kind == crate::quiz::Kind::Supply) {
            return Err(Error::parse(
                path,
                None,
                format!("quiz question {}: a lesson's quiz asks locate and name questions (supply questions come from a supply quiz)", k + 1),
            ));
        }
        if let Some(mark) = lesson.pass_mark.filter(|m| !(0.0..=100.0).contains(m)) {
            return Err(Error::parse(path, None, format!("pass_mark {mark} is not a percentage in 0..=100")));
        }
        for (i, step) in lesson.steps.iter().enumerate() {
            let problem = crate::scene_file::angle_problem("view", step.view)
                .or_else(|| {
                    (!(step.zoom.is_finite() && step.zoom > 1e-4 && step.zoom <= 1e4))
                        .then(|| format!("zoom {} is not in (0.0001, 10000]", step.zoom))
                })
                .or_else(|| step.camera.as_ref().and_then(|c| c.problem()))
                .or_else(|| crate::clip::planes_problem(&step.clip))
                .or_else(|| {
                    step.place.iter().find_map(|(id, p)| {
                        let t = Transform::from_parts(p.translation, p.rotation, p.scale, glam::Vec3::ZERO);
                        t.err().map(|problem| format!("placement of \"{id}\": {problem}"))
                    })
                });
            if let Some(problem) = problem {
                return Err(Error::parse(path, None, format!("step {}: {problem}", i + 1)));
            }
        }
        Ok(lesson)
    }

    /// A new lesson over the set at `set_path`, to be saved at `lesson_path`.
    pub fn new(title: &str, set_path: &Path, lesson_path: &Path, steps: Vec<Step>) -> Lesson {
        let base = lesson_path.parent().unwrap_or(Path::new(""));
        let set = crate::scene_file::relative_to(set_path, base);
        Lesson { format: FORMAT.into(), title: title.into(), set, steps, quiz: Vec::new(), pass_mark: None }
    }

    /// The JSON text (keys in a fixed order, two-space indents, a final newline).
    pub fn to_json(&self, path: &Path) -> Result<String> {
        crate::json_file::to_json(self, path)
    }

    /// Writes the lesson atomically.
    pub fn save(&self, path: &Path) -> Result<()> {
        crate::json_file::save(self, path)
    }

    /// This lesson to be saved at `to` instead of `from`: its set path made relative to the new
    /// folder.
    pub fn moved(&self, from: &Path, to: &Path) -> Lesson {
        Lesson {
            quiz: self.quiz.clone(),
            pass_mark: self.pass_mark,
            ..Lesson::new(&self.title, &self.set_path(from), to, self.steps.clone())
        }
    }

    /// The view question `k` of the lesson's quiz starts from, where it names a step.
    pub fn question_view(&self, k: usize, set: &OrganSet) -> Option<StepView> {
        let step = self.quiz.get(k)?.step?;
        Some(self.steps.get(step.checked_sub(1)?)?.view(set))
    }

    /// The lesson's quiz over `set`, choices filled in where not given (from the quiz's organs,
    /// then the set, nearest first; shuffled with a seed from the question's place). An organ the
    /// set lacks is an error naming it.
    pub fn questions(&self, set: &OrganSet) -> std::result::Result<Vec<crate::quiz::Question>, String> {
        let find = |id: &str| {
            set.find(id).ok_or_else(|| format!("the lesson's quiz names \"{id}\", which the set does not have"))
        };
        let organs = self.quiz.iter().map(|q| find(&q.organ)).collect::<std::result::Result<Vec<_>, _>>()?;
        if let Some(bad) = self.quiz.iter().filter_map(|q| q.step).find(|&s| s == 0 || s > self.steps.len()) {
            return Err(format!(
                "the lesson's quiz names step {bad}, but the lesson has steps 1 to {}",
                self.steps.len()
            ));
        }
        let mut out = Vec::new();
        for (k, (q, &organ)) in self.quiz.iter().zip(&organs).enumerate() {
            let mut rng = crate::rng::XorShift::seeded(k as u64);
            let choices = if q.choices.is_empty() {
                crate::quiz::choices(set, organ, &organs, &mut rng)
            } else {
                let mut c = q.choices.iter().map(|id| find(id)).collect::<std::result::Result<Vec<_>, _>>()?;
                if !c.contains(&organ) {
                    c.push(organ);
                }
                c.dedup();
                rng.shuffle(&mut c);
                c
            };
            out.push(crate::quiz::Question { kind: q.kind, organ, choices, slice: None });
        }
        Ok(out)
    }

    /// Applies an edit; returns what it did, for the Edit menu ("add step 3"), or `None` if it
    /// changed nothing (an index out of range, a lesson's last step removed).
    pub fn edit(&mut self, edit: &LessonEdit) -> Option<String> {
        let n = self.steps.len();
        match edit {
            LessonEdit::Insert { at, step } => {
                let at = (*at).min(n);
                self.steps.insert(at, (**step).clone());
                Some(format!("add step {}", at + 1))
            }
            LessonEdit::Remove(at) if *at < n && n > 1 => {
                self.steps.remove(*at);
                Some(format!("delete step {}", at + 1))
            }
            LessonEdit::Move { from, to } if *from < n && *to < n && from != to => {
                let step = self.steps.remove(*from);
                self.steps.insert(*to, step);
                Some(format!("move step {} to {}", from + 1, to + 1))
            }
            LessonEdit::Replace { at, step } if *at < n && self.steps[*at] != **step => {
                self.steps[*at] = (**step).clone();
                Some(format!("change step {}", at + 1))
            }
            LessonEdit::Retitle(t) if *t != self.title => {
                self.title = t.clone();
                Some("rename the lesson".into())
            }
            _ => None,
        }
    }

    pub fn load(path: &Path) -> Result<Lesson> {
        let text = crate::input::read_text(path, crate::input::Kind::Document)?;
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
            let names = names.chain(s.colour.keys()).chain(s.place.keys()).chain(&s.whole);
            let labelled = match s.labels.as_deref().map(Which::parse) {
                Some(Which::Chosen(list)) => list,
                _ => Vec::new(),
            };
            let names = names.chain(&labelled);
            for n in names {
                if set.select(n).is_empty() && !unknown.contains(n) {
                    unknown.push(n.clone());
                }
            }
        }
        for q in &self.quiz {
            for n in std::iter::once(&q.organ).chain(&q.choices) {
                if set.find(n).is_none() && !unknown.contains(n) {
                    unknown.push(n.clone());
                }
            }
        }
        unknown
    }
}

impl Step {
    /// A step showing `layout` over `set` from `camera`: everything that differs from the set's
    /// default layout, by group where a whole group (as [`OrganSet::select`] reads a group path)
    /// shares a change, else by id; the camera as a view and zoom where it frames the default
    /// layout's centre from an orbit, else exactly; its highlight, section and labels as given.
    pub fn capture(
        set: &OrganSet,
        layout: &Layout,
        camera: CameraState,
        title: &str,
        highlight: &[usize],
        section: &Section,
        labels: &Which,
    ) -> Step {
        let default = Layout::new(set);
        let n = set.organs.len().min(layout.organs.len());
        let (mut show, mut hide, mut opacity, mut colour, mut place) =
            (Vec::new(), Vec::new(), BTreeMap::new(), BTreeMap::new(), BTreeMap::new());
        let visible: Vec<Option<bool>> = (0..n)
            .map(|i| (layout.organs[i].visible != default.organs[i].visible).then_some(layout.organs[i].visible))
            .collect();
        for (key, v) in by_group(set, &visible) {
            if v {
                show.push(key)
            } else {
                hide.push(key)
            }
        }
        let faded: Vec<Option<u32>> = (0..n)
            .map(|i| {
                (layout.organs[i].opacity != default.organs[i].opacity).then_some(layout.organs[i].opacity.to_bits())
            })
            .collect();
        for (key, bits) in by_group(set, &faded) {
            opacity.insert(key, f32::from_bits(bits));
        }
        for i in 0..n {
            let (s, id) = (&layout.organs[i], &set.organs[i].id);
            if s.colour != default.organs[i].colour {
                colour.insert(id.clone(), s.colour);
            }
            if !s.transform.is_identity() {
                let t = &s.transform;
                let p =
                    Placement { translation: t.translation.into(), rotation: t.rotation_deg.into(), scale: t.scale };
                place.insert(id.clone(), p);
            }
        }
        let framed = Navigator::framing(&default.bounds(set), camera.azimuth, camera.elevation);
        let orbit = camera.mode == CameraMode::Orbit && framed.target == glam::Vec3::from(camera.target);
        let saved = SavedSection::of(section, set);
        Step {
            title: title.into(),
            caption: String::new(),
            view: [camera.azimuth, camera.elevation],
            zoom: if orbit { camera.distance / framed.distance } else { 1.0 },
            show,
            hide,
            opacity,
            colour,
            place,
            camera: (!orbit).then_some(camera),
            highlight: set.ids(highlight),
            clip: saved.planes,
            caps: saved.caps,
            cut_face: saved.faces,
            whole: saved.whole,
            labels: labels.key(),
            colour_by: layout.colour_by,
        }
    }

    /// The step's section as saved (its `clip`, `caps` and `whole`).
    pub fn section(&self) -> SavedSection {
        SavedSection { planes: self.clip.clone(), caps: self.caps, faces: self.cut_face, whole: self.whole.clone() }
    }

    /// This step over `set`: the default layout changed as it says, the camera framing the set's
    /// default layout from its view, and the highlighted organs. Names the set lacks are skipped
    /// (see [`Lesson::unknown_names`]).
    pub fn view(&self, set: &OrganSet) -> StepView {
        let mut layout = Layout { colour_by: self.colour_by, ..Layout::new(set) };
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
        for (id, c) in &self.colour {
            for i in set.select(id) {
                layout.organs[i].colour = c.map(|v| if v.is_finite() { v.clamp(0.0, 1.0) } else { 0.5 });
            }
        }
        for (id, p) in &self.place {
            for i in set.select(id) {
                let t = &mut layout.organs[i].transform;
                *t = Transform::from_parts(p.translation, p.rotation, p.scale, t.pivot)
                    .unwrap_or(Transform::identity(t.pivot));
            }
        }
        let (navigator, fly) = match &self.camera {
            Some(c) => (c.navigator(), c.mode == CameraMode::Walk),
            None => {
                let mut navigator = Navigator::framing(&Layout::new(set).bounds(set), self.view[0], self.view[1]);
                if self.zoom.is_finite() && self.zoom > 0.0 {
                    navigator.distance *= self.zoom;
                }
                (navigator, false)
            }
        };
        let mut highlight: Vec<usize> = self.highlight.iter().flat_map(|n| set.select(n)).collect();
        highlight.sort_unstable();
        highlight.dedup();
        let section = self.section().resolve(set).0;
        let labels = self.labels.as_deref().map(Which::parse);
        StepView { layout, navigator, fly, highlight, section, labels }
    }
}

/// Per-organ changes (`None`: unchanged) as keys: the largest groups whose organs all share one
/// change, then ids for the rest, in the set's order.
fn by_group<T: Copy + PartialEq>(set: &OrganSet, changes: &[Option<T>]) -> Vec<(String, T)> {
    let mut groups: Vec<String> = Vec::new();
    for o in &set.organs {
        let parts: Vec<&str> = o.group.split('/').filter(|p| !p.is_empty()).collect();
        for k in 1..=parts.len() {
            let g = parts[..k].join("/");
            if !groups.contains(&g) && set.find(&g).is_none() {
                groups.push(g);
            }
        }
    }
    let members: Vec<(String, Vec<usize>)> =
        groups.into_iter().map(|g| (set.select(&g), g)).map(|(m, g)| (g, m)).collect();
    let mut order: Vec<&(String, Vec<usize>)> = members.iter().filter(|(_, m)| m.len() > 1).collect();
    order.sort_by_key(|(_, m)| std::cmp::Reverse(m.len()));
    let mut covered = vec![false; changes.len()];
    let mut out = Vec::new();
    for (g, m) in order {
        let Some(&Some(v)) = m.first().and_then(|&i| changes.get(i)) else { continue };
        if m.iter().all(|&i| !covered.get(i).copied().unwrap_or(true) && changes.get(i) == Some(&Some(v))) {
            m.iter().for_each(|&i| covered[i] = true);
            out.push((g.clone(), v));
        }
    }
    for (i, c) in changes.iter().enumerate() {
        if let (Some(v), false) = (c, covered[i]) {
            out.push((set.organs[i].id.clone(), *v));
        }
    }
    out
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
    fn a_captured_step_shows_the_same_layout_and_camera_and_names_groups() {
        let set = set();
        let mut layout = Layout::new(&set);
        layout.organs[0].visible = false;
        layout.organs[1].visible = false;
        layout.organs[2].opacity = 0.3;
        layout.organs[2].colour = [0.1, 0.2, 0.3];
        layout.organs[1].transform.translation = glam::Vec3::new(5.0, 0.0, -2.5);
        layout.organs[1].transform.rotation_deg = glam::Vec3::new(0.0, 30.0, 0.0);
        let framed = Navigator::framing(&Layout::new(&set).bounds(&set), 40.0, -15.0);
        let mut orbit = CameraState::of(&framed, CameraMode::Orbit);
        orbit.distance *= 0.75;
        let section = Section {
            planes: vec![crate::clip::ClipPlane::parse("coronal=-4:flip").unwrap()],
            caps: false,
            faces: crate::clip::CutFace { show: crate::clip::CutFaceShows::Tinted, ..Default::default() },
            whole: vec![1],
        };
        let labels = Which::Chosen(vec!["c".into()]);
        let step = Step::capture(&set, &layout, orbit, "t", &[2], &section, &labels);
        assert_eq!((step.whole.clone(), step.labels.as_deref()), (vec!["b".to_string()], Some("c")));
        assert_eq!(step.section().resolve(&set).0, section, "the cut faces' setting too");
        assert_eq!(step.hide, vec!["G".to_string()], "a whole group is named once");
        assert_eq!(step.opacity.keys().collect::<Vec<_>>(), ["c"]);
        assert!(step.camera.is_none() && step.view == [40.0, -15.0]);
        let v = step.view(&set);
        assert_eq!(v.layout, layout);
        assert!((v.navigator.distance - orbit.distance).abs() < 1e-4);
        assert_eq!((v.highlight, v.section, v.labels), (vec![2], section, Some(labels)));
        let walk = CameraState { mode: CameraMode::Walk, target: [1.0, 2.0, 3.0], ..orbit };
        let step = Step::capture(&set, &layout, walk, "t", &[], &Section::default(), &Which::None);
        let v = step.view(&set);
        assert_eq!((CameraState::of(&v.navigator, CameraMode::Walk), v.fly), (walk, true));
        let text = Lesson::new("L", Path::new("/s/set"), Path::new("/s/l/x.vblesson"), vec![step.clone()]);
        let text = text.to_json(Path::new("x")).unwrap();
        let back = Lesson::parse(&text, Path::new("x")).unwrap();
        assert_eq!((back.steps[0].clone(), back.set), (step, PathBuf::from("../set")));
    }

    #[test]
    fn a_lessons_quiz_names_its_organs_or_says_which_it_lacks() {
        let text = r#"{"format": "vbrain-lesson/1", "title": "T", "set": "s", "steps": [{"title": "s", "caption": ""}],
            "quiz": [{"kind": "locate", "organ": "a"}, {"kind": "name", "organ": "c", "choices": ["a", "b"], "step": 1}]}"#;
        let lesson = Lesson::parse(text, Path::new("l")).unwrap();
        let q = lesson.questions(&set()).unwrap();
        assert_eq!((q[0].kind, q[0].organ), (crate::quiz::Kind::Locate, 0));
        let mut choices = q[1].choices.clone();
        choices.sort_unstable();
        assert_eq!(choices, vec![0, 1, 2]);
        assert!(lesson.question_view(0, &set()).is_none() && lesson.question_view(1, &set()).is_some());
        let late = Lesson::parse(&text.replace(r#""step": 1"#, r#""step": 2"#), Path::new("l")).unwrap();
        assert!(late.questions(&set()).unwrap_err().contains("step 2"));
        let bad = text.replace(r#""organ": "a""#, r#""organ": "zz""#);
        let lesson = Lesson::parse(&bad, Path::new("l")).unwrap();
        assert!(lesson.questions(&set()).unwrap_err().contains("zz"));
        assert_eq!(lesson.unknown_names(&set()), vec!["zz".to_string()]);
    }

    #[test]
    fn lesson_edits_insert_move_replace_and_remove() {
        let step = |t: &str| {
            Step::capture(
                &set(),
                &Layout::new(&set()),
                CameraState::of(&Navigator::framing(&Layout::new(&set()).bounds(&set()), 0.0, 0.0), CameraMode::Orbit),
                t,
                &[],
                &Section::default(),
                &Which::None,
            )
        };
        let mut l = Lesson::new("L", Path::new("set"), Path::new("x.vblesson"), vec![step("a")]);
        assert_eq!(l.edit(&LessonEdit::Insert { at: 9, step: Box::new(step("b")) }).as_deref(), Some("add step 2"));
        assert!(l.edit(&LessonEdit::Move { from: 1, to: 0 }).is_some());
        let titles = |l: &Lesson| l.steps.iter().map(|s| s.title.clone()).collect::<Vec<_>>();
        assert_eq!(titles(&l), ["b", "a"]);
        assert!(l.edit(&LessonEdit::Replace { at: 1, step: Box::new(step("a")) }).is_none(), "no change");
        assert!(l.edit(&LessonEdit::Remove(0)).is_some());
        assert!(l.edit(&LessonEdit::Remove(0)).is_none(), "a lesson keeps one step");
        assert_eq!(titles(&l), ["a"]);
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
        let supply = r#"{"format": "vbrain-lesson/1", "title": "t", "set": ".", "steps": [{"title": "s",
            "caption": "c"}], "quiz": [{"kind": "name", "organ": "a"}, {"kind": "supply", "organ": "a"}]}"#;
        let e = Lesson::parse(supply, p).unwrap_err().to_string();
        assert!(e.contains("quiz question 2") && e.contains("supply questions come from a supply quiz"), "{e}");
        let step_typo = r#"{"format": "vbrain-lesson/1", "title": "t", "set": ".", "steps": [
            {"title": "s", "caption": "c", "hid": ["a"]}]}"#;
        assert!(Lesson::parse(step_typo, p).unwrap_err().to_string().contains("hid"), "a misspelt key is named");
        let top_typo = r#"{"format": "vbrain-lesson/1", "title": "t", "set": ".", "pasmark": 50, "steps": [
            {"title": "s", "caption": "c"}]}"#;
        assert!(Lesson::parse(top_typo, p).unwrap_err().to_string().contains("pasmark"), "at the top level too");
        let steps = |n: usize, step: &str| {
            let all = vec![step; n].join(",");
            format!(r#"{{"format": "vbrain-lesson/1", "title": "t", "set": ".", "steps": [{all}]}}"#)
        };
        let plain = r#"{"title": "s", "caption": "c"}"#;
        assert!(Lesson::parse(&steps(MAX_STEPS, plain), p).is_ok());
        let e = Lesson::parse(&steps(MAX_STEPS + 1, plain), p).unwrap_err().to_string();
        assert!(e.contains("501 steps") && e.contains("at most 500"), "{e}");
        let plane = r#"{"normal": [0, 0, 1], "d": 2}"#;
        let cut = format!(r#"{{"title": "s", "caption": "c", "clip": [{}]}}"#, [plane; 5].join(","));
        let e = Lesson::parse(&steps(1, &cut), p).unwrap_err().to_string();
        assert!(e.contains("step 1: 5 clip planes"), "{e}");
        let far = r#"{"title": "s", "caption": "c", "clip": [{"normal": [0, 0, 1], "d": 1e39}]}"#;
        assert!(Lesson::parse(&steps(1, far), p).is_err(), "a plane 1e39 mm away");
    }
}
