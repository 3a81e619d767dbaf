//! Fuzz-style property tests of everything that parses a user's file: meshes (OBJ/VBO), manifests,
//! scenes, lessons and label tables. Random text built from the files' own vocabulary (keywords,
//! numbers at the edges of f32, quotes, commas, huge and negative counts) must give a value or an
//! error naming the file, never a panic, and what is accepted must be usable: finite meshes with
//! area, cameras and transforms that are numbers.

use proptest::prelude::*;
use std::path::Path;
use vbrain::lesson::Lesson;
use vbrain::organ_set::{label_table, obj};
use vbrain::scene_file::SceneFile;

/// Numbers a hand-edited or corrupted file holds.
fn number() -> impl Strategy<Value = String> {
    prop_oneof![
        (-1000i32..1000).prop_map(|v| v.to_string()),
        any::<f32>().prop_map(|v| v.to_string()),
        Just("1e39".to_string()),
        Just("-1e309".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("0".to_string()),
        Just("99999999999999999999".to_string()),
        Just("".to_string()),
        Just("x".to_string()),
    ]
}

fn obj_line() -> impl Strategy<Value = String> {
    prop_oneof![
        (number(), number(), number()).prop_map(|(a, b, c)| format!("v {a} {b} {c}")),
        (number(), number(), number()).prop_map(|(a, b, c)| format!("vn {a} {b} {c}")),
        proptest::collection::vec(-5i64..12, 0..6)
            .prop_map(|f| { format!("f {}", f.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" ")) }),
        (1i64..9, 0i64..9).prop_map(|(a, b)| format!("f {a}/{b} {a}//{b} {b}/{a}/{a}")),
        "[og] [a-z ]{0,8}",
        Just("l 1 2".to_string()),
        Just("mtllib x.mtl".to_string()),
        "[ -~]{0,20}",
    ]
}

fn table_line() -> impl Strategy<Value = String> {
    prop_oneof![
        (number(), "[A-Za-z, \"-]{0,12}").prop_map(|(i, n)| format!("{i},{n}")),
        (number(), "[A-Za-z-]{1,8}", number(), number(), number())
            .prop_map(|(i, n, r, g, b)| format!("{i} {n} {r} {g} {b} 0")),
        "\"[A-Za-z,\" ]{0,10}".prop_map(|s| s),
        Just("# comment".to_string()),
        Just("index,name".to_string()),
    ]
}

/// JSON values of the shapes scenes and lessons hold, with numbers at the edges.
fn json_number() -> impl Strategy<Value = String> {
    prop_oneof![number().prop_filter("json", |n| n.parse::<f64>().is_ok_and(|v| v.is_finite())), Just("1e39".into())]
}

fn scene_text(
    target: &[String],
    distance: &str,
    angles: &[String],
    scale: &str,
    subsamples: u64,
    region: u64,
) -> String {
    format!(
        r#"{{"format": "vbrain-scene/1", "set": {{"path": "s", "fingerprint": "f"}},
        "camera": {{"mode": "orbit", "target": [{}], "distance": {distance}, "azimuth": {}, "elevation": {}}},
        "render": {{"transparency": {{"subsamples": {subsamples}, "region_px": {region}}}, "cull": "occlusion", "background": [0, 0, 0]}},
        "organs": [{{"id": "a", "visible": true, "opacity": 1, "colour": [1, 1, 1], "translation": [0, 0, 0],
            "rotation": [0, 0, 0], "scale": {scale}}}]}}"#,
        target.join(","),
        angles[0],
        angles[1]
    )
}

fn lesson_text(target: &[String], zoom: &str, angles: &[String], scale: &str) -> String {
    format!(
        r#"{{"format": "vbrain-lesson/1", "title": "t", "set": "s", "steps": [{{"title": "a", "caption": "b",
        "view": [{}, {}], "zoom": {zoom}, "place": {{"a": {{"translation": [{}], "rotation": [0, 0, 0], "scale": {scale}}}}}}}]}}"#,
        angles[0],
        angles[1],
        target.join(",")
    )
}

#[test]
fn the_fuzzed_templates_parse_with_sane_numbers() {
    let v = |s: &[&str]| s.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let (target, angles) = (v(&["1", "2", "3"]), v(&["30", "-10"]));
    let scene = SceneFile::parse(&scene_text(&target, "300", &angles, "1.5", 12, 0), Path::new("s.vbscene")).unwrap();
    assert_eq!((scene.render.transparency.subsamples, scene.render.transparency.region_px), (8, 4));
    Lesson::parse(&lesson_text(&target, "0.8", &angles, "1.5"), Path::new("l.vblesson")).unwrap();
    let far = v(&["1e39", "0", "0"]);
    // Each refused for its own reason, named in the error.
    let far =
        SceneFile::parse(&scene_text(&far, "300", &angles, "1", 64, 32), Path::new("s")).err().map(|e| e.to_string());
    assert!(far.as_deref().is_some_and(|e| e.contains("camera target") && e.contains("1 km")), "{far:?}");
    let huge =
        Lesson::parse(&lesson_text(&target, "0.8", &angles, "1e30"), Path::new("l")).err().map(|e| e.to_string());
    assert!(huge.as_deref().is_some_and(|e| e.contains("placement of \"a\"") && e.contains("scale")), "{huge:?}");
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn meshes_parse_or_name_the_file(lines in proptest::collection::vec(obj_line(), 0..24)) {
        let text = lines.join("\n");
        match obj::parse(text.as_bytes(), Path::new("fuzz.obj"), "fuzz") {
            Ok(file) => {
                for o in &file.objects {
                    prop_assert!(o.mesh.validate().is_ok());
                    prop_assert!(o.mesh.positions.iter().flatten().all(|c| c.abs() <= obj::MAX_COORDINATE));
                }
            }
            Err(e) => prop_assert!(e.to_string().starts_with("fuzz.obj"), "{e}"),
        }
    }

    #[test]
    fn label_tables_parse_or_name_the_file(lines in proptest::collection::vec(table_line(), 0..12)) {
        let text = lines.join("\n");
        match label_table::parse_label_table(&text, Path::new("t.csv")) {
            Ok(t) => {
                prop_assert!(!t.labels.is_empty());
                prop_assert!(t.labels.iter().all(|l| !l.name.is_empty()));
                let mut seen = std::collections::HashSet::new();
                prop_assert!(t.labels.iter().all(|l| seen.insert(l.index)), "an index given twice was accepted");
            }
            Err(e) => prop_assert!(e.to_string().starts_with("t.csv"), "{e}"),
        }
    }

    #[test]
    fn scenes_and_lessons_give_usable_numbers_or_an_error(
        target in proptest::collection::vec(json_number(), 3),
        distance in json_number(),
        angles in proptest::collection::vec(json_number(), 2),
        scale in json_number(),
        subsamples in 0u64..100_000,
        region in 0u64..100_000,
    ) {
        let scene = scene_text(&target, &distance, &angles, &scale, subsamples, region);
        if let Ok(s) = SceneFile::parse(&scene, Path::new("s.vbscene")) {
            prop_assert!(s.camera.problem().is_none());
            let nav = s.camera.navigator();
            prop_assert!(nav.target.is_finite() && nav.distance.is_finite() && nav.distance > 0.0);
            prop_assert!(vbrain::transparency::REGION_PX.contains(&s.render.transparency.region_px));
            prop_assert!(vbrain::transparency::SUBSAMPLE_CHOICES.contains(&s.render.transparency.subsamples));
            prop_assert!(s.organs.iter().all(|o| o.scale.is_finite() && o.scale > 0.0));
        }
        let lesson = lesson_text(&target, &distance, &angles, &scale);
        if let Ok(l) = Lesson::parse(&lesson, Path::new("l.vblesson")) {
            let s = &l.steps[0];
            prop_assert!(s.view.iter().all(|a| a.is_finite()) && s.zoom.is_finite() && s.zoom > 0.0);
            prop_assert!(s.place.values().all(|p| p.scale.is_finite() && p.translation.iter().all(|t| t.is_finite())));
        }
    }
}
