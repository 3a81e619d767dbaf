//! Input that passes the door must not break anything deeper: the `vbrain` commands run with the
//! kinds of input a user's own files and fingers produce (too large, not a file, not a number,
//! out of range, a link out of the set, a table with quotes), each refused with a message that
//! names the problem, or accepted with a warning, and never a panic or a half-written output.

use super::cli::{brain, two_blobs, vbrain};
use std::path::Path;
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Fails (exit status 1 or 2, never a panic's 101) with `expect` in its message.
pub(crate) fn refused(args: &[&str], expect: &str) {
    let o = vbrain(args);
    let code = o.status.code();
    assert!(matches!(code, Some(1 | 2)), "{args:?} exited {code:?}: {}", stderr(&o));
    assert!(stderr(&o).contains(expect), "{args:?}: expected \"{expect}\" in: {}", stderr(&o));
    assert!(!stderr(&o).contains("panicked"), "{args:?}: {}", stderr(&o));
}

const TRIANGLE: &str = "v 0 0 0\nv 10 0 0\nv 0 10 0\nf 1 2 3\n";

#[test]
fn typed_counts_and_sizes_have_bounds() {
    let b = brain();
    let out = tempfile::tempdir().unwrap();
    let png = out.path().join("x.png");
    let png = png.to_str().unwrap();
    // Sizes the texture limit accepts but the memory does not: an error before any target.
    refused(&["render", &b, "--size", "12000x12000", "--out", png], "GiB");
    refused(&["render", &b, "--size", "16384x16384", "--out", png], "choose a smaller size");
    assert!(!Path::new(png).exists());
    for (args, what) in [
        (vec!["bench", &b, "--frames", "0"], "--frames"),
        (vec!["bench", &b, "--frames", "100001"], "--frames"),
        (vec!["bench", &b, "--raster", "65535x65535"], "--raster"),
        (vec!["masks", "--k", "0"], "--k"),
        (vec!["masks", "--objects", "100000"], "--objects"),
        (vec!["masks", "--alpha", "1.5"], "--alpha"),
        (vec!["occluders", &b, "--grid", "0"], "--grid"),
        (vec!["occluders", &b, "--grid", "1000000"], "--grid"),
        (vec!["import", "v.nii", "--labels", "t.csv", "--out", "o", "--smooth", "1001"], "--smooth"),
        (vec!["scale", &b, "--factor", "0.5", "--out", "o"], "--factor"),
        (vec!["scale", &b, "--factor", "nan", "--out", "o"], "--factor"),
        (vec!["render", &b, "--k", "0", "--out", png], "--k"),
        (vec!["render", &b, "--region", "0", "--out", png], "--region"),
    ] {
        refused(&args, what);
    }
}

#[test]
fn reads_refuse_what_is_not_a_regular_file_or_leaves_the_set() {
    refused(&["info", "/dev/null"], "not a regular file");
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    #[cfg(unix)]
    {
        let fifo = d.join("pipe.obj");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status().unwrap();
        assert!(made.success());
        // Read, it would block for ever; it is refused before.
        refused(&["info", fifo.to_str().unwrap()], "not a regular file");
        // A mesh path that passes the manifest's check but links out of the set's folder.
        std::fs::write(d.join("outside.obj"), TRIANGLE).unwrap();
        let set = d.join("set");
        std::fs::create_dir(&set).unwrap();
        std::os::unix::fs::symlink(d.join("outside.obj"), set.join("link.obj")).unwrap();
        std::fs::write(set.join("inside.obj"), TRIANGLE).unwrap();
        let manifest = r##"{"format": "vbrain-organ-set/1", "title": "t", "organs": [
            {"id": "a", "name": "A", "mesh": "link.obj", "colour": "#ff0000"},
            {"id": "b", "name": "B", "mesh": "inside.obj", "colour": "#00ff00"}]}"##;
        std::fs::write(set.join("organset.json"), manifest).unwrap();
        let o = vbrain(&["info", set.to_str().unwrap()]);
        assert!(stderr(&o).contains("outside the set's folder"), "{}", stderr(&o));
        assert!(String::from_utf8_lossy(&o.stdout).contains('B'), "the rest still loads");
    }
    // An OS error is printed once, with its path.
    let o = vbrain(&["info", "/no/such/set"]);
    assert_eq!(stderr(&o).matches("os error 2").count(), 1, "{}", stderr(&o));
    assert!(!stderr(&o).contains("Os {"), "no Debug text: {}", stderr(&o));
}

#[test]
fn meshes_that_cannot_be_framed_or_shaded_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let far = dir.path().join("far.obj");
    std::fs::write(&far, "v 0 0 0\nv 1e30 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    refused(&["info", far.to_str().unwrap()], "far.obj:2");
    let flat = dir.path().join("flat.obj");
    std::fs::write(&flat, "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n").unwrap();
    refused(&["info", flat.to_str().unwrap()], "zero area");
}

#[test]
fn a_render_with_a_broken_organ_writes_and_warns_and_exits_0() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("good.obj"), TRIANGLE).unwrap();
    std::fs::write(dir.path().join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let png = dir.path().join("out.png");
    let o = vbrain(&["render", dir.path().to_str().unwrap(), "--size", "64x64", "--out", png.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("warning: ") && stderr(&o).contains("bad.obj:4"), "{}", stderr(&o));
    assert!(png.exists());
}

#[test]
fn scenes_whose_camera_or_transforms_are_not_numbers_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let (scene, png) = (dir.path().join("s.vbscene"), dir.path().join("s.png"));
    let (scene_s, png_s) = (scene.to_str().unwrap(), png.to_str().unwrap());
    let b = brain();
    let saved = vbrain(&["render", &b, "--size", "32x32", "--out", png_s, "--save-scene", scene_s]);
    assert!(saved.status.success(), "{}", stderr(&saved));
    let text = std::fs::read_to_string(&scene).unwrap();
    let edit = |key: &str, value: &str| -> String {
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v["camera"][key] = serde_json::from_str(value).unwrap();
        v.to_string()
    };
    for (key, value, expect) in [("distance", "1e39", "camera distance"), ("azimuth", "-1e300", "camera angles")] {
        std::fs::write(&scene, edit(key, value)).unwrap();
        refused(&["render", "--scene", scene_s, "--out", png_s], expect);
    }
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["organs"][0]["scale"] = serde_json::json!(1e30);
    std::fs::write(&scene, v.to_string()).unwrap();
    refused(&["render", "--scene", scene_s, "--out", png_s], "scale");
}

#[test]
fn label_tables_are_csv_with_quotes_and_a_repeated_index_names_both_lines() {
    let dir = tempfile::tempdir().unwrap();
    let vol = two_blobs(dir.path(), "seg.nii");
    let (v, out) = (vol.to_str().unwrap(), dir.path().join("set"));
    let o = out.to_str().unwrap();
    let csv = dir.path().join("labels.csv");
    std::fs::write(&csv, "index,name\n17,\"Putamen, left\"\n53,\"The \"\"right\"\" one\"\n").unwrap();
    let r = vbrain(&["import", v, "--labels", csv.to_str().unwrap(), "--out", o, "--json"]);
    assert!(r.status.success(), "{}", stderr(&r));
    let info: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    let names: Vec<&str> = info["organs"].as_array().unwrap().iter().map(|o| o["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["Putamen, left", "The \"right\" one"]);

    std::fs::write(&csv, "17,a\n53,b\n\n17,c\n").unwrap();
    let again = dir.path().join("again");
    refused(
        &["import", v, "--labels", csv.to_str().unwrap(), "--out", again.to_str().unwrap()],
        "line 1 and on line 4",
    );
    assert!(!again.exists(), "a refused import writes nothing");

    let lut = dir.path().join("lut.txt");
    std::fs::write(&lut, "17 Left-Thing 300 0 0 0\n53 Right-Thing 10 20 30 0\n").unwrap();
    let third = dir.path().join("third");
    let r = vbrain(&["import", v, "--labels", lut.to_str().unwrap(), "--out", third.to_str().unwrap()]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert!(stderr(&r).contains("lut.txt:1") && stderr(&r).contains("300 0 0"), "{}", stderr(&r));
}

#[test]
fn bench_checks_its_output_folder_before_it_runs() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("a-file");
    std::fs::write(&file, "").unwrap();
    let started = std::time::Instant::now();
    refused(&["bench", &brain(), "--frames", "100000", "--out", file.to_str().unwrap()], "a-file");
    // 100,000 frames would take hours: it stopped at the folder.
    assert!(started.elapsed().as_secs() < 60);
}

#[test]
fn commands_that_write_a_set_refuse_a_folder_that_holds_files() {
    let dir = tempfile::tempdir().unwrap();
    let mine = dir.path().join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("notes.txt"), "mine").unwrap();
    let m = mine.to_str().unwrap();
    refused(&["city", "--out", m], "--force");
    refused(&["stand-ins", &brain(), "--out", m], "--force");
    assert_eq!(std::fs::read_to_string(mine.join("notes.txt")).unwrap(), "mine");
}

/// `render --save-scene` never replaces what is not a scene (an organ set's manifest, say) without
/// `--force`, and a render that fails writes no scene.
#[test]
fn save_scene_replaces_only_scenes_and_only_after_the_render() {
    let dir = tempfile::tempdir().unwrap();
    let manifest = dir.path().join("organset.json");
    let text = "{\"format\": \"vbrain-organ-set/1\"}";
    std::fs::write(&manifest, text).unwrap();
    let png = dir.path().join("x.png");
    let (p, m) = (png.to_str().unwrap(), manifest.to_str().unwrap());
    let set = brain();
    let run = vbrain(&["render", &set, "--size", "64x48", "--out", p, "--save-scene", m]);
    assert!(!run.status.success() && stderr(&run).contains("not a vbrain scene"), "{}", stderr(&run));
    assert_eq!(std::fs::read_to_string(&manifest).unwrap(), text, "the manifest is untouched");
    assert!(!png.exists(), "nothing rendered");
    // A render that fails (a plane outside the set) writes no scene.
    let scene = dir.path().join("s.vbscene");
    let s = scene.to_str().unwrap();
    let run = vbrain(&["render", &set, "--size", "64x48", "--out", p, "--save-scene", s, "--clip", "axial=900"]);
    assert!(!run.status.success() && !scene.exists(), "{}", stderr(&run));
    // A scene it wrote it may write again.
    for _ in 0..2 {
        let run = vbrain(&["render", &set, "--size", "64x48", "--out", p, "--save-scene", s]);
        assert!(run.status.success(), "{}", stderr(&run));
    }
    assert!(scene.is_file());
}

/// Names holding terminal escape codes are printed as text by `info`, never sent raw.
#[test]
fn info_never_prints_escape_codes_raw() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("meshes")).unwrap();
    std::fs::write(
        dir.path().join("meshes/a.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n",
    )
    .unwrap();
    let manifest = r##"{"format": "vbrain-organ-set/1", "title": "T\u001b[31mred", "organs": [
        {"id": "a", "name": "A\u001b[2J\u0007", "mesh": "meshes/a.obj", "colour": "#808080"}]}"##;
    std::fs::write(dir.path().join("organset.json"), manifest).unwrap();
    let out = vbrain(&["info", dir.path().to_str().unwrap()]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(!out.stdout.contains(&0x1b) && !out.stdout.contains(&0x07), "{text}");
    assert!(text.contains("A\\u{1b}[2J\\u{7}") && text.contains("T\\u{1b}[31mred"), "{text}");
}

/// A scene naming an organ the set lacks among those kept whole renders with a warning (a scene
/// never stops at a bad organ); the same name given as `--whole` is an error naming the option.
#[test]
fn a_scenes_unknown_whole_organ_warns_but_the_option_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("s.vbscene");
    let png = dir.path().join("x.png");
    let (s, p) = (scene.to_str().unwrap(), png.to_str().unwrap());
    let made = vbrain(&["render", &brain(), "--size", "48x32", "--out", p, "--save-scene", s, "--clip", "axial=0"]);
    assert!(made.status.success(), "{}", stderr(&made));
    let text =
        std::fs::read_to_string(&scene).unwrap().replace("\"clip\"", "\"whole\": [\"no_such_organ\"],\n  \"clip\"");
    std::fs::write(&scene, text).unwrap();
    let run = vbrain(&["render", "--scene", s, "--size", "48x32", "--out", p, "--force"]);
    assert!(run.status.success() && stderr(&run).contains("no_such_organ"), "{}", stderr(&run));
    let run = vbrain(&["render", "--scene", s, "--size", "48x32", "--out", p, "--whole", "nope"]);
    assert!(!run.status.success() && stderr(&run).contains("--whole"), "{}", stderr(&run));
}

/// A manifest that is there but cannot be read (a named pipe, a link to nothing) is named with
/// its reason, not taken for a folder without a manifest.
#[test]
fn a_manifest_that_is_a_pipe_or_a_dangling_link_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let piped = dir.path().join("piped");
    std::fs::create_dir(&piped).unwrap();
    let made = std::process::Command::new("mkfifo").arg(piped.join("organset.json")).status().unwrap();
    assert!(made.success());
    refused(&["info", piped.to_str().unwrap()], "organset.json: is not a regular file");
    let linked = dir.path().join("linked");
    std::fs::create_dir(&linked).unwrap();
    std::os::unix::fs::symlink(dir.path().join("nowhere.json"), linked.join("organset.json")).unwrap();
    refused(&["info", linked.to_str().unwrap()], "organset.json: is a link to nothing");
}

/// A label volume whose affine puts it beyond where meshes may lie (1 km) is refused at import,
/// naming the file, instead of writing a set that no command can open.
#[test]
fn an_import_refuses_a_volume_placed_beyond_a_kilometre() {
    let dir = tempfile::tempdir().unwrap();
    let volume = two_blobs(dir.path(), "far.nii");
    let mut bytes = std::fs::read(&volume).unwrap();
    // srow_x's translation (bytes 292..296): 2 km to the right.
    bytes[292..296].copy_from_slice(&2e6f32.to_le_bytes());
    std::fs::write(&volume, bytes).unwrap();
    let labels = dir.path().join("labels.csv");
    std::fs::write(&labels, "index,name\n17,Left\n53,Right\n").unwrap();
    let out = dir.path().join("set");
    let (v, l, o) = (volume.to_str().unwrap(), labels.to_str().unwrap(), out.to_str().unwrap());
    refused(&["import", v, "--labels", l, "--out", o], "far.nii: header fields srow/qform");
    assert!(!out.exists(), "no set written");
}
