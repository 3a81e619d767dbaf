//! Loading organ sets and mesh files: quirky valid OBJ loads with the right triangle count; every
//! malformed input gets an error naming the file (and line), and never a panic.

use std::path::{Path, PathBuf};
use vbrain::organ_set::{self, obj};

fn parse(text: &[u8]) -> Result<obj::ObjFile, vbrain::Error> {
    obj::parse(text, Path::new("test.obj"), "test")
}

fn triangles(text: &str) -> usize {
    let f = parse(text.as_bytes()).unwrap_or_else(|e| panic!("{e}\n{text}"));
    f.objects.iter().map(|o| o.mesh.triangle_count()).sum()
}

const QUAD: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

#[test]
fn quirky_valid_files() {
    assert_eq!(triangles(&format!("{QUAD}f 1 2 3 4\n")), 2, "quad");
    assert_eq!(triangles("v 0 0 0\nv 1 0 0\nv 1 1 0\nv .5 1.5 0\nv 0 1 0\nf 1 2 3 4 5\n"), 3, "pentagon");
    assert_eq!(triangles(&format!("{QUAD}f 1 2 3 4\r\n").replace('\n', "\r\n")), 2, "CRLF");
    assert_eq!(triangles(&format!("# comment\n{QUAD}# another\nf -4 -3 -2\n")), 1, "negative indices");
    assert_eq!(triangles(&format!("{QUAD}vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n")), 1, "v/vt/vn");
    assert_eq!(triangles(&format!("{QUAD}vn 0 0 1\nf 1//1 2//1 3//1 4//1\n")), 2, "v//vn");
    assert_eq!(triangles(&format!("{QUAD}vt 0 0\nf 1/1 2/1 3/1\n")), 1, "v/vt");
    assert_eq!(triangles(&format!("mtllib missing.mtl\nusemtl skin\n{QUAD}f 1 2 3\n")), 1, "missing mtllib");
    assert_eq!(triangles("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n"), 1, "vertex colours");
    assert_eq!(triangles(&format!("{QUAD}s 1\nl 1 2 3\ns off\nf 1 2 3\n")), 1, "l and s lines");
    assert_eq!(triangles("v 1e-3 0E0 -0.0\nv 1.5e+2 0 0\nv 0 2.5E2 0\nf 1 2 3\n"), 1, "scientific notation");
    assert_eq!(triangles(&format!("{QUAD}f 1 2 3\n\n\n   \n\tf 1 3 4\n")), 2, "blank lines and tabs");
    assert_eq!(triangles(&format!("{QUAD}f 1 2 3")), 1, "no final newline");
    let warned = parse(format!("mtllib missing.mtl\n{QUAD}f 1 2 3\n").as_bytes()).unwrap();
    assert_eq!(warned.warnings.len(), 1, "a missing material library is a warning");
}

#[test]
fn objects_and_groups_are_organs() {
    let text = format!("{QUAD}o first\nf 1 2 3\ng second\nf 1 3 4\nf 1 2 4\n");
    let f = parse(text.as_bytes()).unwrap();
    let names: Vec<_> = f.objects.iter().map(|o| (o.name.as_str(), o.mesh.triangle_count())).collect();
    assert_eq!(names, [("first", 1), ("second", 2)]);
    let unnamed = parse(format!("{QUAD}f 1 2 3\n").as_bytes()).unwrap();
    assert_eq!(unnamed.objects[0].name, "test");
}

#[test]
fn normals_are_computed_when_missing() {
    let f = parse(format!("{QUAD}f 1 2 3 4\n").as_bytes()).unwrap();
    let m = &f.objects[0].mesh;
    assert_eq!(m.normals.len(), m.positions.len());
    assert!(m.normals.iter().all(|n| (n[2] - 1.0).abs() < 1e-6));
}

/// Each malformed input: the error names the file and, where given, the line.
#[test]
fn malformed_files_name_file_and_line() {
    let cases: &[(&[u8], Option<usize>, &str)] = &[
        (b"v 0 0 zero\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Some(1), "not a number"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", Some(4), "index 0"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", Some(4), "out of range"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", Some(4), "out of range"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999999\n", Some(4), "not an integer"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967297\n", Some(4), "out of range"),
        (b"v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Some(1), "not finite"),
        (b"v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n", Some(2), "not finite"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1e39\nf 1 2 3\n", Some(4), "not finite"),
        (b"v 0 0 0\nv 1 0 0\nf 1 2\n", Some(3), "at least 3"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv \xff\xfe 0 0\n", Some(5), "UTF-8"),
        (b"", None, "empty"),
        (b"\x7fELF\x02\x01\x01\x00\x00\x00", Some(1), "binary"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", None, "no faces"),
        (b"# only a comment\n", None, "no faces"),
        (b"v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Some(1), "needs 3"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0\nf 1 2 3\n", Some(4), "needs 3"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//2 2//1 3//1\n", Some(4), "normal index"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/3/4 2 3\n", Some(4), "more than three"),
        (b"v 0 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Some(1), "w = 0"),
    ];
    for (text, line, needle) in cases {
        let e = parse(text).err().unwrap_or_else(|| panic!("accepted {:?}", String::from_utf8_lossy(text))).to_string();
        let at = match line {
            Some(l) => format!("test.obj:{l}:"),
            None => "test.obj:".to_string(),
        };
        assert!(e.starts_with(&at), "{e:?} should start with {at:?}");
        assert!(e.contains(needle), "{e:?} should mention {needle:?}");
    }
}

#[test]
fn a_single_line_of_megabytes() {
    let mut text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\n# ".to_vec();
    text.extend(std::iter::repeat_n(b'x', 8 << 20));
    text.extend(b"\nf 1 2 3\n");
    assert_eq!(parse(&text).unwrap().objects[0].mesh.triangle_count(), 1);
    let mut bad = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 ".to_vec();
    bad.extend(std::iter::repeat_n(b'9', 4 << 20));
    assert!(parse(&bad).unwrap_err().to_string().contains("test.obj:4"));
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, text).unwrap();
    p
}

fn manifest(organs: &str) -> String {
    format!(
        r#"{{"format": "vbrain-organ-set/1", "title": "t", "units": "mm", "coordinates": "RAS", "organs": [{organs}]}}"#
    )
}

fn organ(id: &str, mesh: &str, extra: &str) -> String {
    format!(r##"{{"id": "{id}", "name": "{id}", "mesh": "{mesh}", "colour": "#ff0000"{extra}}}"##)
}

#[test]
fn a_broken_organ_does_not_stop_the_set() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "good.vbo", &format!("{QUAD}f 1 2 3\n"));
    write(dir.path(), "bad.vbo", &format!("{QUAD}f 1 2 9\n"));
    let organs = [
        organ("good", "good.vbo", r#", "opacity": 0.5, "group": "A/B", "info": "text""#),
        organ("bad_mesh", "bad.vbo", ""),
        organ("missing", "nope.vbo", ""),
        organ("escape", "../outside.vbo", ""),
        organ("absolute", "/etc/passwd", ""),
        organ("opaque_plus", "good.vbo", r#", "opacity": 1.5"#),
        organ("bad colour", "good.vbo", ""),
        organ("good", "good.vbo", ""),
    ]
    .join(",");
    let path = write(dir.path(), "organset.json", &manifest(&organs));
    let loaded = organ_set::open(dir.path()).unwrap();
    assert_eq!(loaded.set.organs.len(), 1);
    let o = &loaded.set.organs[0];
    assert_eq!((o.id.as_str(), o.opacity, o.group.as_str(), o.info.as_str()), ("good", 0.5, "A/B", "text"));
    let errors: Vec<String> = loaded.errors.iter().map(|e| e.to_string()).collect();
    assert_eq!(errors.len(), 7, "{errors:#?}");
    let expect = [
        ("bad.vbo:5", "out of range"),
        ("nope.vbo", ""),
        ("organset.json", "escapes"),
        ("organset.json", "relative"),
        ("organset.json", "opacity 1.5"),
        ("organset.json", "bad colour"),
        ("organset.json", "twice"),
    ];
    for (e, (file, what)) in errors.iter().zip(expect) {
        assert!(e.contains(file) && e.contains(what), "{e:?} should name {file} and {what:?}");
    }
    assert!(path.exists());
}

#[test]
fn broken_manifests_are_fatal_and_named() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("{\"format\": ", "organset.json:1"),
        ("{\"format\": \"vbrain-organ-set/1\", \"title\": 3, \"organs\": []}", "invalid type"),
        ("{\"format\": \"vbrain-organ-set/1\", \"title\": \"t\", \"organs\": {}}", "invalid type"),
        ("{\"format\": \"vbrain-organ-set/1\", \"title\": \"t\", \"units\": \"inch\", \"organs\": []}", "units"),
        ("{\"format\": \"other\", \"title\": \"t\", \"organs\": []}", "format"),
        ("{\"format\": \"vbrain-organ-set/1\", \"title\": \"t\", \"organs\": [], \"extra\": 1}", "unknown field"),
        ("\u{0}\u{1}binary", "organset.json"),
    ];
    for (text, needle) in cases {
        write(dir.path(), "organset.json", text);
        let e = organ_set::open(dir.path()).unwrap_err().to_string();
        assert!(e.contains("organset.json") && e.contains(needle), "{e:?} should mention {needle:?}");
    }
}

#[test]
fn folders_and_single_files_without_manifest() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "a.obj", &format!("{QUAD}o one\nf 1 2 3\no two\nf 1 3 4\n"));
    write(dir.path(), "b.vbo", &format!("{QUAD}f 1 2 3\n"));
    write(dir.path(), "c.OBJ", "garbage\n");
    write(dir.path(), "notes.txt", "not a mesh");
    let loaded = organ_set::open(dir.path()).unwrap();
    let ids: Vec<_> = loaded.set.organs.iter().map(|o| o.id.as_str()).collect();
    assert_eq!(ids, ["one", "two", "b"]);
    assert_ne!(loaded.set.organs[0].colour, loaded.set.organs[1].colour);
    assert_eq!(loaded.errors.len(), 1);
    assert!(loaded.errors[0].to_string().contains("c.OBJ"));
    let single = organ_set::open(&dir.path().join("b.vbo")).unwrap();
    assert_eq!(single.set.organs.len(), 1);
    assert!(organ_set::open(&dir.path().join("missing.obj")).unwrap_err().to_string().contains("missing.obj"));
    let empty = tempfile::tempdir().unwrap();
    assert!(organ_set::open(empty.path()).unwrap_err().to_string().contains("no organset.json"));
}

#[test]
fn saved_sets_load_back_identically() {
    let dir = tempfile::tempdir().unwrap();
    let src = write(dir.path(), "src.obj", &format!("{QUAD}o plate\nf 1 2 3 4\n"));
    let set = organ_set::open(&src).unwrap().set;
    let out = dir.path().join("set");
    set.save(&out).unwrap();
    let back = organ_set::open(&out).unwrap();
    assert!(back.errors.is_empty());
    assert_eq!(back.set.organs[0].mesh().indices, set.organs[0].mesh().indices);
    assert_eq!(back.set.organs[0].mesh().positions, set.organs[0].mesh().positions);
    assert_eq!(
        back.set.organs[0].colour.map(|c| (c * 255.0).round()),
        set.organs[0].colour.map(|c| (c * 255.0).round())
    );
}

mod fuzz {
    use super::*;
    use proptest::prelude::*;

    const SEEDS: &[&str] = &[
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\no a\nf 1/1/1 2/1/1 3/1/1 4/1/1\ng b\nf -1 -2 -3\nl 1 2\ns 1\n",
        "mtllib x.mtl\nusemtl m\nv 1e3 -2.5E-2 3\nv 0 0 0 0.5 0.5 0.5\nv 1 1 1\nf 1//1 2//1 3//1\n",
    ];

    fn mutate(seed: &str, edits: &[(usize, u8, u8)]) -> Vec<u8> {
        let mut b = seed.as_bytes().to_vec();
        for &(at, op, byte) in edits {
            let i = at % (b.len() + 1);
            match op % 4 {
                0 if i < b.len() => b[i] = byte,
                1 => b.insert(i, byte),
                2 if i < b.len() => {
                    b.remove(i);
                }
                _ => b.insert(i, b" -/0123456789.eEfvno\n\r#"[byte as usize % 23]),
            }
        }
        b
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

        #[test]
        fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
            let _ = parse(&bytes);
        }

        #[test]
        fn mutated_files_never_panic_and_stay_valid(seed in 0..SEEDS.len(), edits in proptest::collection::vec((any::<usize>(), any::<u8>(), any::<u8>()), 1..12)) {
            if let Ok(f) = parse(&mutate(SEEDS[seed], &edits)) {
                for o in &f.objects {
                    prop_assert!(o.mesh.validate().is_ok(), "{:?}", o.mesh.validate());
                    prop_assert!(o.mesh.triangle_count() > 0);
                }
            }
        }

        #[test]
        fn random_manifests_never_panic(text in "[{}\\[\\]\":,a-z0-9 .#/-]{0,200}") {
            let dir = tempfile::tempdir().unwrap();
            std::fs::write(dir.path().join("organset.json"), &text).unwrap();
            let _ = organ_set::open(dir.path());
        }
    }
}

#[test]
fn occluder_stand_ins_round_trip_and_a_broken_one_is_only_a_warning() {
    // A closed tetrahedron, scaled: each organ keeps its original mesh as occluder stand-in.
    let dir = tempfile::tempdir().unwrap();
    let tet = "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
    write(dir.path(), "tet.obj", tet);
    write(dir.path(), "organset.json", &manifest(&organ("tet", "tet.obj", "")));
    let set = organ_set::open(dir.path()).unwrap().set;
    assert!(set.organs[0].stand_in().is_none());
    let scaled = organ_set::scale::scale_set(&set, 3, &mut |_, _, _| {});
    let out = dir.path().join("scaled");
    scaled.save(&out).unwrap();
    let loaded = organ_set::open(&out).unwrap();
    assert!(loaded.warnings.is_empty() && loaded.errors.is_empty(), "{:?} {:?}", loaded.warnings, loaded.errors);
    let o = &loaded.set.organs[0];
    assert_eq!(o.mesh().triangle_count(), 4 * 9);
    assert_eq!(o.stand_in().map(|s| s.mesh().triangle_count()), Some(4));
    // A broken stand-in: the organ loads without it, and a warning names the file and line.
    write(&out, "meshes/tet.occluder.vbo", "v 0 0 0\nf 1 2 3\n");
    let loaded = organ_set::open(&out).unwrap();
    assert_eq!(loaded.set.organs.len(), 1);
    assert!(loaded.set.organs[0].stand_in().is_none());
    assert!(
        loaded.warnings.iter().any(|w| w.contains("tet.occluder.vbo") && w.contains("stand-in")),
        "{:?}",
        loaded.warnings
    );
}

/// Thousands of organs load on a bounded pool (a thread per organ once panicked at 34,000), and a
/// manifest past the bound is refused with it before any mesh is read.
#[test]
fn many_organs_load_and_too_many_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("meshes")).unwrap();
    std::fs::write(
        dir.path().join("meshes/a.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n",
    )
    .unwrap();
    let manifest = |n: usize| {
        let organs: Vec<String> = (0..n)
            .map(|i| format!(r##"{{"id": "o{i}", "name": "O {i}", "mesh": "meshes/a.obj", "colour": "#808080"}}"##))
            .collect();
        format!(r#"{{"format": "vbrain-organ-set/1", "title": "many", "organs": [{}]}}"#, organs.join(",\n"))
    };
    let path = dir.path().join(organ_set::MANIFEST_FILE);
    std::fs::write(&path, manifest(3000)).unwrap();
    let loaded = organ_set::open(dir.path()).unwrap();
    assert_eq!((loaded.set.organs.len(), loaded.errors.len()), (3000, 0));
    std::fs::write(&path, manifest(organ_set::manifest::MAX_ORGANS + 1)).unwrap();
    let e = organ_set::open(dir.path()).err().unwrap().to_string();
    assert!(e.contains("organset.json") && e.contains("at most 10000"), "{e}");
}

/// Writing stand-ins into a set rewrites its manifest: entries that did not load (an organ whose
/// mesh is missing, a solid that names it) stay as they were, and so does every other field.
#[test]
fn saving_stand_ins_keeps_the_entries_that_did_not_load() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "a.vbo", &format!("{QUAD}f 1 2 3\n"));
    write(dir.path(), "b.vbo", &format!("{QUAD}f 1 2 3\n"));
    let organs = [organ("a", "a.vbo", ""), organ("b", "b.vbo", ""), organ("c", "missing.vbo", "")].join(",");
    let solids = r#""solids": [{"id": "ab", "organs": ["a", "b"]}, {"id": "bc", "organs": ["b", "c"]}]"#;
    let text = manifest(&organs).replace(r#""organs": ["#, &format!(r#"{solids}, "description": "kept", "organs": ["#));
    let path = write(dir.path(), "organset.json", &text);
    let loaded = organ_set::open(dir.path()).unwrap();
    assert_eq!(loaded.set.organs.len(), 2);
    assert_eq!(loaded.set.solids.len(), 1, "the solid naming the missing organ is left out of the set");
    loaded.set.save_stand_ins(dir.path()).unwrap();
    let written: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let ids = |key: &str| -> Vec<String> {
        written[key].as_array().unwrap().iter().map(|e| e["id"].as_str().unwrap().to_string()).collect()
    };
    assert_eq!(ids("organs"), ["a", "b", "c"]);
    assert_eq!(ids("solids"), ["ab", "bc"], "the solid that did not load is kept in the manifest");
    assert_eq!(written["solids"][1]["organs"], serde_json::json!(["b", "c"]));
    assert_eq!(written["description"], "kept");
}
