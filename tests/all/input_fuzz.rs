//! Fuzz-style property tests of everything that parses a user's file: meshes (OBJ/VBO), manifests,
//! scenes, lessons (with many steps and planes), label tables and NIfTI volumes (with extensions,
//! and header-only files paired with a data file beside them). Random text built from the files' own vocabulary (keywords,
//! numbers at the edges of f32, quotes, commas, huge and negative counts) must give a value or an
//! error naming the file, never a panic, and what is accepted must be usable: finite meshes with
//! area, cameras and transforms that are numbers.

use proptest::prelude::*;
use std::path::Path;
use vbrain::clip::{MAX_OFFSET_MM, MAX_PLANES};
use vbrain::lesson::{Lesson, MAX_STEPS};
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

/// A clip plane as files spell it: a normal and an offset, numbers at the edges.
fn plane_json() -> impl Strategy<Value = String> {
    (proptest::collection::vec(json_number(), 3), json_number())
        .prop_map(|(n, d)| format!(r#"{{"normal": [{}], "d": {d}}}"#, n.join(",")))
}

/// A lesson of `steps` steps, each cut by the planes given (cycled).
fn lesson_of(steps: usize, planes: &[Vec<String>]) -> String {
    let step = |k: usize| {
        let clip = planes.get(k % planes.len().max(1)).map(|p| p.join(",")).unwrap_or_default();
        format!(r#"{{"title": "s{k}", "caption": "", "clip": [{clip}]}}"#)
    };
    let steps: Vec<String> = (0..steps).map(step).collect();
    format!(r#"{{"format": "vbrain-lesson/1", "title": "t", "set": "s", "steps": [{}]}}"#, steps.join(","))
}

/// A NIfTI-1 file's bytes: the 348-byte header as given, the extension flag, `extension` bytes,
/// then `data` (whatever `vox_offset` says).
fn nifti_bytes(
    dims: [i16; 4],
    datatype: (i16, i16),
    vox_offset: f32,
    magic: &[u8; 4],
    extension: &[u8],
    data: &[u8],
) -> Vec<u8> {
    let mut h = vec![0u8; 348];
    let mut put = |at: usize, bytes: &[u8]| h[at..at + bytes.len()].copy_from_slice(bytes);
    put(0, &348i32.to_le_bytes());
    for (i, d) in dims.iter().enumerate() {
        put(40 + 2 * i, &d.to_le_bytes());
    }
    put(48, &1i16.to_le_bytes());
    put(70, &datatype.0.to_le_bytes());
    put(72, &datatype.1.to_le_bytes());
    for i in 0..4 {
        put(76 + 4 * i, &1f32.to_le_bytes());
    }
    put(108, &vox_offset.to_le_bytes());
    put(344, magic);
    let flag = if extension.is_empty() { [0u8; 4] } else { [1, 0, 0, 0] };
    h.extend_from_slice(&flag);
    h.extend_from_slice(extension);
    h.extend_from_slice(data);
    h
}

/// An extension block as NIfTI spells it (size, code, content), its size field possibly lying.
fn extension() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        Just(Vec::new()),
        (
            prop_oneof![Just(16i32), Just(i32::MAX), Just(-8), Just(0), 8i32..4096],
            proptest::collection::vec(any::<u8>(), 0..64)
        )
            .prop_map(|(size, body)| {
                let mut e = size.to_le_bytes().to_vec();
                e.extend_from_slice(&4i32.to_le_bytes());
                e.extend(body);
                e
            }),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Lessons of up to twice the bound in steps, each with up to six planes of any numbers: parsed
    /// within the bounds (steps, planes a step, planes that are planes), or refused naming the file.
    #[test]
    fn lessons_with_many_steps_and_planes_stay_within_their_bounds(
        steps in prop_oneof![0usize..8, (MAX_STEPS - 2)..(MAX_STEPS + 3), 900usize..1000],
        planes in proptest::collection::vec(proptest::collection::vec(plane_json(), 0..7), 1..4),
    ) {
        match Lesson::parse(&lesson_of(steps, &planes), Path::new("many.vblesson")) {
            Ok(l) => {
                prop_assert!(l.steps.len() <= MAX_STEPS);
                for s in &l.steps {
                    prop_assert!(s.clip.len() <= MAX_PLANES);
                    for p in &s.clip {
                        let n = glam::Vec3::from(p.normal);
                        prop_assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-3, "{p:?}");
                        prop_assert!(p.d.is_finite() && p.d.abs() <= MAX_OFFSET_MM, "{p:?}");
                    }
                }
            }
            Err(e) => prop_assert!(e.to_string().starts_with("many.vblesson"), "{e}"),
        }
    }

    /// NIfTI files with lying extension sizes, offsets, dimensions and types, cut short or not:
    /// a volume of the size the header gives, or an error naming the file; never a panic or an
    /// allocation the header alone asked for.
    #[test]
    fn nifti_volumes_with_extensions_read_or_name_the_file(
        dims in (1i16..5, 1i16..5, prop_oneof![1i16..5, Just(i16::MAX)], prop_oneof![Just(1i16), Just(2)]),
        datatype in prop_oneof![Just((2i16, 8i16)), Just((4, 16)), Just((16, 32)), Just((64, 64)), Just((128, 24)), Just((99, 8))],
        extra in prop_oneof![Just(0f32), Just(16.0), Just(4e9), Just(-4.0), Just(f32::NAN), 0f32..100.0],
        extension in extension(),
        data in proptest::collection::vec(any::<u8>(), 0..600),
        gz in any::<bool>(),
    ) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(if gz { "fuzz.nii.gz" } else { "fuzz.nii" });
        let vox_offset = 352.0 + extension.len() as f32 + extra;
        let [x, y, z, t] = [dims.0, dims.1, dims.2, dims.3];
        let mut bytes = nifti_bytes([3 + i16::from(t > 1), x, y, z], datatype, vox_offset, b"n+1\0", &extension, &data);
        bytes[48..50].copy_from_slice(&t.to_le_bytes());
        if gz {
            use std::io::Write;
            let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
            e.write_all(&bytes).unwrap();
            bytes = e.finish().unwrap();
        }
        std::fs::write(&path, &bytes).unwrap();
        match vbrain::nifti_file::read(&path, "label volume", 1 << 20) {
            Ok(v) => {
                prop_assert_eq!(v.dims, [x as usize, y as usize, z as usize]);
                prop_assert!((0..v.len()).all(|i| v.value(i).is_finite() || v.is_float()));
            }
            Err(e) => prop_assert!(e.to_string().contains("fuzz.nii"), "{e}"),
        }
    }
}

/// A header-only NIfTI file (magic `ni1`) beside each kind of data file a user or an attacker
/// might leave there (a file, a named pipe, a link out, nothing): refused at once, naming the
/// header, and the data file never opened (a pipe would hang the reader).
#[test]
fn header_only_nifti_files_are_refused_whatever_lies_beside_them() {
    let dir = tempfile::tempdir().unwrap();
    let outside = dir.path().join("secret");
    std::fs::write(&outside, [7u8; 8]).unwrap();
    for beside in ["file", "pipe", "link", "nothing"] {
        let sub = dir.path().join(beside);
        std::fs::create_dir(&sub).unwrap();
        let header = sub.join("v.nii");
        std::fs::write(&header, nifti_bytes([3, 2, 2, 2], (2, 8), 0.0, b"ni1\0", &[], &[])).unwrap();
        let img = sub.join("v.img");
        match beside {
            "file" => std::fs::write(&img, [1u8; 8]).unwrap(),
            "pipe" => assert!(std::process::Command::new("mkfifo").arg(&img).status().unwrap().success()),
            "link" => std::os::unix::fs::symlink(&outside, &img).unwrap(),
            _ => {}
        }
        let started = std::time::Instant::now();
        let e = vbrain::nifti_file::read(&header, "label volume", 1 << 20).err().map(|e| e.to_string());
        assert!(e.as_deref().is_some_and(|e| e.contains("v.nii") && e.contains("header-only")), "{beside}: {e:?}");
        assert!(started.elapsed().as_secs() < 5, "{beside}: the reader waited on the data file");
    }
}
