//! A scene, set or lesson as a self-contained web page (issue: share as a web page): `index.html`
//! holds everything it needs inline, so that it opens from a file (where browsers refuse module
//! imports and fetches) as from any static server, with nothing fetched from the network. Beside it
//! go the model (`scene.glb`, [`crate::gltf`]) and the vendored three.js (MIT) with its licence.
//!
//! The page (`web/page.html`, `web/page.js`) reads three parts of itself: the three.js modules, as
//! `data:` URLs in an import map (their relative imports renamed to bare names the map resolves);
//! the model, base64 in a `<script>` element; and a JSON description (title, camera, labels, for
//! a lesson its steps, for a quiz its questions with their views and pass mark). A view's organ
//! colours are as its colouring shows them ([`crate::colouring`]); in territory colouring the
//! model's vertex colours show instead (`territories`). Conventions of
//! that JSON: positions and directions in glTF space (metres, +Y superior, +Z anterior:
//! [`crate::gltf::ROOT_MATRIX`]), colours sRGB in 0..=1, organs by id. Every text from the set
//! reaches the page as JSON data and is shown as text, never parsed as HTML; the JSON is escaped
//! so that no `</script>` can end its element.
//!
//! - A quiz's answers are in the page (it works offline, with no server): a page for graded
//!   work trusts its students as a paper quiz with the key on its back does.

use crate::camera::Camera;
use crate::clip::Section;
use crate::labels::Which;
use crate::layout::Layout;
use crate::lesson::Lesson;
use crate::navigation::Navigator;
use crate::organ_set::OrganSet;
use glam::{Mat4, Vec3};
use serde_json::{json, Value};

/// The page's template: `{{TITLE}}`, `{{IMPORTMAP}}`, `{{DATA}}`, `{{GLB}}` and `{{APP}}` are filled in.
const TEMPLATE: &str = include_str!("../web/page.html");
/// The page's program, an ES module over three.js.
const APP: &str = include_str!("../web/page.js");

/// The vendored three.js files: (bare name in the import map, file name, text).
const THREE: [(&str, &str, &str); 5] = [
    ("three", "three.module.min.js", include_str!("../web/vendor/three/three.module.min.js")),
    ("three/core", "three.core.min.js", include_str!("../web/vendor/three/three.core.min.js")),
    ("three/gltf-loader", "GLTFLoader.js", include_str!("../web/vendor/three/GLTFLoader.js")),
    ("three/orbit-controls", "OrbitControls.js", include_str!("../web/vendor/three/OrbitControls.js")),
    (
        "three/buffer-geometry-utils",
        "BufferGeometryUtils.js",
        include_str!("../web/vendor/three/BufferGeometryUtils.js"),
    ),
];
/// three.js's licence, written beside the vendored files.
pub const THREE_LICENCE: &str = include_str!("../web/vendor/three/LICENSE");
/// The relative imports of the vendored files, and the bare names they become.
const RENAMED_IMPORTS: [(&str, &str); 2] = [
    ("\"./three.core.min.js\"", "\"three/core\""),
    ("'../utils/BufferGeometryUtils.js'", "'three/buffer-geometry-utils'"),
];

/// What the page opens on, or one step of a lesson.
#[derive(Clone, Debug)]
pub struct View {
    pub title: String,
    pub caption: String,
    pub layout: Layout,
    pub camera: Camera,
    /// Organs outlined (a lesson step's highlight).
    pub highlight: Vec<usize>,
    /// Organs labelled.
    pub labels: Vec<usize>,
    pub selection: Option<usize>,
    /// The cut the page applies, without cut faces (a lesson's steps; a scene's cut, faces and
    /// all, is in the model itself).
    pub section: Section,
}

/// A page: the set, the model's layout and section, and its views (one, or a lesson's steps).
pub struct Page<'a> {
    pub set: &'a OrganSet,
    pub title: String,
    /// What the model holds: the organs it draws, as they look before any step.
    pub layout: Layout,
    /// The cut baked into the model.
    pub section: Section,
    pub views: Vec<View>,
    /// A lesson (steps with next and previous) rather than one view.
    pub lesson: bool,
    /// The quiz the page asks, if any.
    pub quiz: Option<PageQuiz>,
}

/// A quiz in a page: its questions in order and the pass mark (per cent) it reports to a
/// learning platform ([`crate::scorm`]).
#[derive(Clone, Debug)]
pub struct PageQuiz {
    pub questions: Vec<PageQuestion>,
    pub pass_mark: f32,
}

/// One question of a page's quiz: what it asks about which organ, the names offered (organ
/// indices, the organ among them) and the view it is asked in (what hides the organ faded; a
/// name question's organ outlined).
#[derive(Clone, Debug)]
pub struct PageQuestion {
    pub kind: crate::quiz::Kind,
    pub organ: usize,
    pub choices: Vec<usize>,
    pub view: View,
}

impl<'a> Page<'a> {
    /// A lesson's page: every organ in the model, uncut; each step shows, fades, colours, places
    /// and cuts them (without cut faces) in the page, with its labels and highlights.
    pub fn lesson(set: &'a OrganSet, lesson: &Lesson) -> Page<'a> {
        let views: Vec<View> = lesson
            .steps
            .iter()
            .map(|step| {
                let v = step.view(set);
                let which = v.labels.clone().unwrap_or_default();
                View {
                    title: step.title.clone(),
                    caption: step.caption.clone(),
                    labels: labelled(set, &v.layout, &which, None),
                    camera: camera(set, &v.layout, &v.navigator),
                    layout: v.layout,
                    highlight: v.highlight,
                    selection: None,
                    section: v.section,
                }
            })
            .collect();
        let mut model = Layout::new(set);
        for o in &mut model.organs {
            (o.visible, o.opacity) = (true, 1.0);
        }
        // The model carries territory colours where a step shows them.
        if views.iter().any(|v| v.layout.colour_by == crate::layout::ColourBy::Territory) {
            model.colour_by = crate::layout::ColourBy::Territory;
        }
        Page {
            set,
            title: lesson.title.clone(),
            layout: model,
            section: Section::default(),
            views,
            lesson: true,
            quiz: None,
        }
    }
}

/// The organs `which` labels among those `layout` draws, `selection` being the selected organ.
pub fn labelled(set: &OrganSet, layout: &Layout, which: &Which, selection: Option<usize>) -> Vec<usize> {
    let wanted: Vec<usize> = match which {
        Which::None => Vec::new(),
        Which::All => (0..set.organs.len()).collect(),
        Which::Selected => selection.into_iter().collect(),
        Which::Chosen(names) => Which::chosen(names, set).0,
    };
    wanted.into_iter().filter(|&o| layout.organs.get(o).is_some_and(|s| s.is_drawn())).collect()
}

/// The camera a page shows `layout` from `nav` with (depth range over the layout and the set's
/// default layout, as `vbrain render` frames them).
pub fn camera(set: &OrganSet, layout: &Layout, nav: &Navigator) -> Camera {
    nav.camera(&layout.bounds(set).union(Layout::new(set).bounds(set)))
}

/// The files of the page: (path relative to its folder, bytes).
pub fn files(page: &Page) -> Vec<(String, Vec<u8>)> {
    let glb = crate::gltf::glb(page.set, &page.layout, &page.section, crate::gltf::Encoding::CompactNormals).bytes;
    let mut out = vec![("index.html".to_string(), html(page, &glb).into_bytes()), ("scene.glb".to_string(), glb)];
    for (_, file, text) in THREE {
        out.push((format!("vendor/three/{file}"), text.as_bytes().to_vec()));
    }
    out.push(("vendor/three/LICENSE".to_string(), THREE_LICENCE.as_bytes().to_vec()));
    out
}

/// Writes the page's files into the folder `dir`, staged beside it and moved into place whole
/// (replacing what `dir` held: callers ask first where it holds anything); gives their bytes.
pub fn write(dir: &std::path::Path, page: &Page) -> crate::Result<usize> {
    let files = files(page);
    crate::atomic::write_folder(dir, |staging| {
        for (name, bytes) in &files {
            let path = staging.join(name);
            if let Some(parent) = path.parent() {
                std::fs::create_dir_all(parent).map_err(|e| crate::Error::io(parent, e))?;
            }
            crate::atomic::write(&path, |w| w.write_all(bytes))?;
        }
        Ok(())
    })?;
    Ok(files.iter().map(|(_, b)| b.len()).sum())
}

/// `index.html`: the template with the import map, the description, the model and the program.
fn html(page: &Page, glb: &[u8]) -> String {
    let imports: serde_json::Map<String, Value> =
        THREE.iter().map(|(name, _, text)| (name.to_string(), json!(module_url(text)))).collect();
    let import_map = json!({ "imports": imports }).to_string();
    fill(
        TEMPLATE,
        &[
            ("TITLE", &escape_markup(&page.title)),
            ("IMPORTMAP", &json_safe(&import_map)),
            ("DATA", &json_safe(&description(page).to_string())),
            ("GLB", &base64(glb)),
            ("APP", &script_safe(APP)),
        ],
    )
}

/// `template` with each `{{NAME}}` of `values` replaced, in one pass: what a value holds is never
/// searched again, so a caption holding `{{APP}}` stays text. Unknown names stay as they are.
fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let mut out = String::with_capacity(template.len() + values.iter().map(|(_, v)| v.len()).sum::<usize>());
    let mut rest = template;
    while let Some(i) = rest.find("{{") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 2..];
        let known = after
            .find("}}")
            .and_then(|j| values.iter().find(|(name, _)| *name == &after[..j]).map(|(_, value)| (*value, j)));
        match known {
            Some((value, j)) => {
                out.push_str(value);
                rest = &after[j + 2..];
            }
            None => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// A vendored module as a `data:` URL, its relative imports renamed to the import map's names.
/// Only what a URL parser would drop or cut (`%`, `#`, line breaks, tabs) is percent-encoded.
fn module_url(text: &str) -> String {
    let mut text = text.to_string();
    for (from, to) in RENAMED_IMPORTS {
        text = text.replace(from, to);
    }
    let mut url = String::with_capacity(text.len() + 64);
    url.push_str("data:text/javascript;charset=utf-8,");
    for c in text.chars() {
        match c {
            '%' => url.push_str("%25"),
            '#' => url.push_str("%23"),
            '\n' => url.push_str("%0A"),
            '\r' => url.push_str("%0D"),
            '\t' => url.push_str("%09"),
            c => url.push(c),
        }
    }
    url
}

/// Text that may stand inside a `<script>` element: `</` becomes `<\/`, which JSON and JavaScript
/// strings read alike, so the element cannot be closed early.
fn script_safe(text: &str) -> String {
    text.replace("</", "<\\/")
}

/// JSON that may stand inside a `<script>` element: every `<` (only ever inside a JSON string)
/// becomes `\u003c`, which JSON reads alike, so no `</script>` or `<!--` reaches the HTML parser.
fn json_safe(json: &str) -> String {
    json.replace('<', "\\u003c")
}

/// Text for HTML or XML: `&`, `<`, `>` and quotes escaped; control characters (which XML
/// forbids) become spaces.
pub fn escape_markup(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c if c.is_control() && !matches!(c, '\n' | '\t') => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], chunk.get(1).copied().unwrap_or(0), chunk.get(2).copied().unwrap_or(0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A point of RAS millimetres in glTF space.
fn point(p: Vec3) -> [f32; 3] {
    Mat4::from_cols_array(&crate::gltf::ROOT_MATRIX).transform_point3(p).to_array()
}

/// A direction of RAS in glTF space, unit length.
fn direction(d: Vec3) -> [f32; 3] {
    Mat4::from_cols_array(&crate::gltf::ROOT_MATRIX).transform_vector3(d).normalize_or(Vec3::Y).to_array()
}

/// The JSON the page reads.
fn description(page: &Page) -> Value {
    let views: Vec<Value> = page.views.iter().map(|v| view_json(page.set, v)).collect();
    let quiz = page.quiz.as_ref().map(|q| {
        let name = |o: usize| json!({"id": page.set.organs[o].id, "name": page.set.organs[o].name});
        let questions: Vec<Value> = q
            .questions
            .iter()
            .map(|q| {
                json!({"kind": q.kind, "organ": name(q.organ), "choices": q.choices.iter().map(|&o| name(o)).collect::<Vec<_>>(),
                    "view": view_json(page.set, &q.view)})
            })
            .collect();
        json!({"passMark": q.pass_mark, "questions": questions})
    });
    json!({"title": page.title, "lesson": page.lesson, "views": views, "quiz": quiz})
}

/// One view's JSON: each organ's state, the camera, outlines, labels and cut.
fn view_json(set: &OrganSet, v: &View) -> Value {
    let ids = |organs: &[usize]| -> Vec<&str> { organs.iter().map(|&i| set.organs[i].id.as_str()).collect() };
    let c = &v.camera;
    let colours = crate::colouring::organ_colours(set, &v.layout);
    let organs: serde_json::Map<String, Value> = set
        .organs
        .iter()
        .zip(&v.layout.organs)
        .zip(colours)
        .map(|((o, s), colour)| {
            let m = s.transform.matrix();
            let matrix = (m != Mat4::IDENTITY).then(|| m.to_cols_array().to_vec());
            let state = json!({"visible": s.visible, "opacity": s.opacity, "colour": colour, "matrix": matrix});
            (o.id.clone(), state)
        })
        .collect();
    // A plane removes n.p > d in RAS; three.js keeps n'.p + d' >= 0: n' = -n, d' = d (in metres).
    let clip: Vec<Value> =
        v.section.planes.iter().map(|p| json!({"normal": direction(-p.normal()), "constant": p.d / 1000.0})).collect();
    json!({
        "title": v.title, "caption": v.caption, "organs": organs,
        "camera": {"eye": point(c.eye), "target": point(c.target), "up": direction(c.up), "fov": c.fov_y},
        "highlight": ids(&v.highlight), "labels": ids(&v.labels),
        "selection": v.selection.map(|i| set.organs[i].id.clone()), "clip": clip,
        "whole": ids(&v.section.whole),
        "territories": v.layout.colour_by == crate::layout::ColourBy::Territory,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placeholders_in_the_values_stay_text() {
        let filled =
            fill("<t>{{TITLE}}</t><s>{{APP}}</s>{{NONE}}", &[("TITLE", "{{APP}} and {{GLB}}"), ("APP", "code")]);
        assert_eq!(filled, "<t>{{APP}} and {{GLB}}</t><s>code</s>{{NONE}}");
        assert_eq!(fill("{{", &[]), "{{");
        assert_eq!(fill("a}}b{{APP", &[("APP", "x")]), "a}}b{{APP");
    }
    use crate::mesh::Mesh;
    use crate::organ_set::Organ;

    #[test]
    fn base64_matches_the_standard() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(&[0xff, 0xfe, 0x00, 0x01]), "//4AAQ==");
    }

    #[test]
    fn names_stay_text_and_modules_lose_their_relative_imports() {
        let mut set = OrganSet { title: "<b>Brain</b>".into(), ..Default::default() };
        set.organs.push(Organ::new(
            "s".into(),
            "</script><script>alert(1)</script>".into(),
            [1.0; 3],
            Mesh::octahedron(),
        ));
        let layout = Layout::new(&set);
        let camera = Camera::orbit(&layout.bounds(&set), 0.0, 0.0);
        let view = View {
            title: String::new(),
            caption: set.organs[0].name.clone(),
            layout: layout.clone(),
            camera,
            highlight: vec![],
            labels: vec![0],
            selection: None,
            section: Section::default(),
        };
        let page = Page {
            set: &set,
            title: set.title.clone(),
            layout,
            section: Section::default(),
            views: vec![view],
            lesson: false,
            quiz: None,
        };
        let files = files(&page);
        let html = String::from_utf8(files[0].1.clone()).unwrap();
        assert!(html.contains("<title>&lt;b&gt;Brain&lt;/b&gt;"));
        assert!(!html.contains("</script><script>alert"), "an organ's name cannot close a script element");
        assert!(html.contains("\\u003c/script>\\u003cscript>alert(1)\\u003c/script>"));
        assert!(!html.contains("./three.core.min.js") && !html.contains("../utils/BufferGeometryUtils.js"));
        assert!(files.iter().any(|(p, _)| p == "vendor/three/LICENSE"));
        assert_eq!(&files[1].1[0..4], b"glTF");
    }
}
