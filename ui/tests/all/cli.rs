//! The `vbrain` binary's headless commands, run as a user would: summaries, JSON, exit codes and
//! error messages that name the broken file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub(crate) fn vbrain(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vbrain")).args(args).output().unwrap()
}

pub(crate) fn brain() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../organs/brain").display().to_string()
}

pub(crate) fn json(out: &Output) -> serde_json::Value {
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn info_json_of_the_default_brain() {
    let v = json(&vbrain(&["info", &brain(), "--json"]));
    let organs = v["organs"].as_array().unwrap();
    assert!(organs.len() >= 20);
    let total = v["triangles"].as_u64().unwrap();
    assert!((150_000..=340_000).contains(&total), "{total}");
    let sum: u64 = organs.iter().map(|o| o["triangles"].as_u64().unwrap()).sum();
    assert_eq!(sum, total);
    assert!(organs.iter().all(|o| o["id"].is_string() && o["name"].is_string()));
}

/// A scene saved by one render and rendered by another gives the same bytes; options beside
/// `--scene` override it; a broken scene names itself.
#[test]
fn a_saved_scene_renders_the_same_picture() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b, c) = (dir.path().join("a.png"), dir.path().join("b.png"), dir.path().join("c.png"));
    let scene = dir.path().join("s.vbscene");
    let p = |p: &Path| p.display().to_string();
    let set = brain();
    let size = ["--size", "96x80"];
    json(&vbrain(
        &[
            &[
                "render",
                &set,
                "--orbit",
                "30,10",
                "--opacity",
                "precentral_l=0.4",
                "--hide",
                "Right hemisphere/Occipital lobe",
            ][..],
            &["--save-scene", &p(&scene), "--out", &p(&a), "--json"],
            &size,
        ]
        .concat(),
    ));
    let text = std::fs::read_to_string(&scene).unwrap();
    assert!(text.starts_with("{\n  \"format\": \"vbrain-scene/1\""), "{text}");
    json(&vbrain(&[&["render", "--scene", &p(&scene), "--out", &p(&b), "--json"][..], &size].concat()));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap(), "the scene renders the same bytes");
    json(&vbrain(
        &[&["render", "--scene", &p(&scene), "--opacity", "precentral_l=1", "--out", &p(&c), "--json"][..], &size]
            .concat(),
    ));
    assert_ne!(std::fs::read(&a).unwrap(), std::fs::read(&c).unwrap(), "an option overrides the scene");

    // Planes and labels are saved and rendered again the same.
    let cut = ["--clip", "sagittal=-4", "--view", "right", "--labels", "all"];
    json(&vbrain(
        &[&["render", &set][..], &cut, &["--save-scene", &p(&scene), "--out", &p(&a), "--json"], &size].concat(),
    ));
    assert!(std::fs::read_to_string(&scene).unwrap().contains("\"clip\""));
    json(&vbrain(&[&["render", "--scene", &p(&scene), "--out", &p(&b), "--json"][..], &size].concat()));
    assert_eq!(
        std::fs::read(&a).unwrap(),
        std::fs::read(&b).unwrap(),
        "the cut, labelled scene renders the same bytes"
    );

    std::fs::write(&scene, text.replacen("\"camera\": {", "\"camera\": {,", 1)).unwrap();
    let r = vbrain(&["render", "--scene", &p(&scene), "--out", &p(&c)]);
    assert!(!r.status.success());
    let err = String::from_utf8_lossy(&r.stderr);
    assert!(err.contains("s.vbscene:"), "{err}");
}

/// Every shipped lesson renders: one PNG per step, each step's picture different from the one
/// before, and lesson.md with every step's title and picture.
#[test]
fn lesson_render_writes_every_step_of_every_shipped_lesson() {
    let dir = tempfile::tempdir().unwrap();
    let lessons = Path::new(env!("CARGO_MANIFEST_DIR")).join("../organs/brain/lessons");
    for name in ["cortex", "deep-nuclei", "ventricles", "blood-supply", "pathways"] {
        let out = dir.path().join(name);
        let lesson = lessons.join(format!("{name}.vblesson"));
        let v = json(&vbrain(&[
            "lesson",
            "render",
            &lesson.display().to_string(),
            "--out",
            &out.display().to_string(),
            "--size",
            "64x48",
            "--json",
        ]));
        let files: Vec<PathBuf> =
            v["files"].as_array().unwrap().iter().map(|f| PathBuf::from(f.as_str().unwrap())).collect();
        assert_eq!(v["steps"].as_u64(), Some(files.len() as u64));
        assert!(files.len() >= 5, "{name}: {} steps", files.len());
        assert_eq!(files[0], out.join("01.png"));
        let pictures: Vec<Vec<u8>> = files.iter().map(|f| std::fs::read(f).unwrap()).collect();
        assert!(pictures.windows(2).all(|w| w[0] != w[1]), "{name}: two steps in a row look the same");
        let md = std::fs::read_to_string(out.join("lesson.md")).unwrap();
        assert!(md.starts_with("# ") && md.contains("](01.png)") && md.matches("\n## ").count() == files.len(), "{md}");
    }
    let r = vbrain(&["lesson", "render", "no-such.vblesson", "--out", &dir.path().display().to_string()]);
    assert!(!r.status.success() && String::from_utf8_lossy(&r.stderr).contains("no-such.vblesson"));
}

#[test]
fn render_writes_a_png_of_the_asked_size() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let o = out.to_str().unwrap();
    let set = brain();
    let v = json(&vbrain(&[
        "render",
        &set,
        "--out",
        o,
        "--size",
        "96x64",
        "--orbit",
        "-30,20",
        "--hide",
        "Left hemisphere/Frontal lobe",
        "--opacity",
        "all=0.8",
        "--json",
    ]));
    assert_eq!(v["width"], 96);
    let img = image::open(&out).unwrap();
    assert_eq!((img.width(), img.height()), (96, 64));
    for bad in [
        vec!["--size", "0x10"],
        vec!["--size", "big"],
        vec!["--view", "sideways"],
        vec!["--orbit", "1"],
        vec!["--hide", "no_such_organ"],
        vec!["--opacity", "precentral_l=2"],
        vec!["--hide", "Frontal"],
        vec!["--view", "left", "--orbit", "0,0"],
    ] {
        let mut args = vec!["render", &set, "--out", o];
        args.extend(bad.iter().copied());
        let r = vbrain(&args);
        assert!(!r.status.success(), "{bad:?} accepted");
        assert!(String::from_utf8_lossy(&r.stderr).contains("error"), "{bad:?}");
    }
}

#[test]
fn a_broken_organ_is_reported_and_the_rest_listed() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("good.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(dir.path().join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let r = vbrain(&["info", dir.path().to_str().unwrap()]);
    assert!(!r.status.success());
    assert!(String::from_utf8_lossy(&r.stdout).contains("good"));
    assert!(String::from_utf8_lossy(&r.stderr).contains("bad.obj:4"), "{}", String::from_utf8_lossy(&r.stderr));
    let missing = vbrain(&["info", "/no/such/set"]);
    assert!(!missing.status.success() && String::from_utf8_lossy(&missing.stderr).contains("/no/such/set"));
}

/// A minimal NIfTI-1 file (gzip-compressed when the name ends in .gz): int16 labels, 2 mm voxels,
/// sform with a mirrored x axis as radiological volumes have.
pub(crate) fn write_nifti(path: &Path, dims: [usize; 3], labels: &[i16]) {
    let mut h = vec![0u8; 352];
    let put = |h: &mut Vec<u8>, at: usize, bytes: &[u8]| h[at..at + bytes.len()].copy_from_slice(bytes);
    put(&mut h, 0, &348i32.to_le_bytes());
    let dim: [i16; 8] = [3, dims[0] as i16, dims[1] as i16, dims[2] as i16, 1, 1, 1, 1];
    for (i, d) in dim.iter().enumerate() {
        put(&mut h, 40 + 2 * i, &d.to_le_bytes());
    }
    put(&mut h, 70, &4i16.to_le_bytes()); // datatype int16
    put(&mut h, 72, &16i16.to_le_bytes()); // bitpix
    for (i, p) in [1.0f32, 2.0, 2.0, 2.0].iter().enumerate() {
        put(&mut h, 76 + 4 * i, &p.to_le_bytes());
    }
    put(&mut h, 108, &352f32.to_le_bytes()); // vox_offset
    put(&mut h, 112, &1f32.to_le_bytes()); // scl_slope
    put(&mut h, 254, &1i16.to_le_bytes()); // sform_code
    let rows = [[-2.0f32, 0.0, 0.0, 40.0], [0.0, 2.0, 0.0, -20.0], [0.0, 0.0, 2.0, -10.0]];
    for (r, row) in rows.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            put(&mut h, 280 + 16 * r + 4 * c, &v.to_le_bytes());
        }
    }
    put(&mut h, 344, b"n+1\0");
    for l in labels {
        h.extend_from_slice(&l.to_le_bytes());
    }
    if path.extension().is_some_and(|e| e == "gz") {
        use std::io::Write;
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(&h).unwrap();
        h = gz.finish().unwrap();
    }
    std::fs::write(path, h).unwrap();
}

pub(crate) fn two_blobs(dir: &Path, name: &str) -> PathBuf {
    let dims = [24, 16, 16];
    let mut labels = vec![0i16; 24 * 16 * 16];
    for z in 4..12 {
        for y in 4..12 {
            for x in 3..10 {
                labels[x + 24 * (y + 16 * z)] = 17;
                labels[x + 11 + 24 * (y + 16 * z)] = 53;
            }
        }
    }
    let p = dir.join(name);
    write_nifti(&p, dims, &labels);
    p
}

#[test]
fn a_seamless_import_shares_the_interface_of_touching_organs() {
    let dir = tempfile::tempdir().unwrap();
    let dims = [24, 16, 16];
    let mut labels = vec![0i16; 24 * 16 * 16];
    for z in 4..12 {
        for y in 4..12 {
            for x in 3..17 {
                labels[x + 24 * (y + 16 * z)] = if x < 10 { 17 } else { 53 };
            }
        }
    }
    let vol = dir.path().join("touching.nii.gz");
    write_nifti(&vol, dims, &labels);
    let csv = dir.path().join("labels.csv");
    std::fs::write(&csv, "index,name\n17,Left part\n53,Right part\n").unwrap();
    let out = dir.path().join("set");
    let (v, o) = (vol.to_str().unwrap(), out.to_str().unwrap());
    json(&vbrain(&["import", v, "--labels", csv.to_str().unwrap(), "--out", o, "--seamless", "--json"]));
    let info = json(&vbrain(&["info", o, "--json"]));
    let organs = info["organs"].as_array().unwrap();
    assert_eq!(organs.len(), 2);
    // The two blocks meet in one plane: where one ends along x, the other begins, exactly.
    let x = |i: usize, end: &str| organs[i]["bounds"][end][0].as_f64().unwrap();
    let (a, b) = ((x(0, "min"), x(0, "max")), (x(1, "min"), x(1, "max")));
    assert!(a.1 == b.0 || b.1 == a.0, "no shared face: {a:?} and {b:?}");
}

#[test]
fn import_a_label_volume_then_scale_it() {
    let dir = tempfile::tempdir().unwrap();
    let vol = two_blobs(dir.path(), "seg.nii.gz");
    let csv = dir.path().join("labels.csv");
    std::fs::write(&csv, "index,name\n0,Unknown\n17,Left-Hippocampus\n53,Right-Hippocampus\n").unwrap();
    let out = dir.path().join("set");
    let v = json(&vbrain(&[
        "import",
        vol.to_str().unwrap(),
        "--labels",
        csv.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--triangles",
        "1500",
        "--json",
    ]));
    let organs = v["organs"].as_array().unwrap();
    assert_eq!(organs.len(), 2);
    assert_eq!(organs[0]["name"], "Left-Hippocampus");
    assert!(v["triangles"].as_u64().unwrap() <= 1600);
    // Voxel x 3..10 at -2 mm from +40 lies at x = 20..34 mm: world space, not voxel space.
    let info = json(&vbrain(&["info", out.to_str().unwrap(), "--json"]));
    let b = &info["organs"][0]["bounds"];
    assert!(b["min"][0].as_f64().unwrap() > 18.0 && b["max"][0].as_f64().unwrap() < 36.0, "{b}");

    // A FreeSurfer colour table works too, and its colours are used.
    let lut = dir.path().join("lut.txt");
    std::fs::write(
        &lut,
        "#No. Label Name: R G B A\n17  Left-Hippocampus  220 216 20 0\n53 Right-Hippocampus 220 216 20 0\n",
    )
    .unwrap();
    let out2 = dir.path().join("set2");
    json(&vbrain(&[
        "import",
        vol.to_str().unwrap(),
        "--labels",
        lut.to_str().unwrap(),
        "--out",
        out2.to_str().unwrap(),
        "--json",
    ]));
    assert!(std::fs::read_to_string(out2.join("organset.json")).unwrap().contains("#dcd814"));

    // Occluder stand-ins, in place: only the stand-ins and the manifest are written, and the
    // manifest keeps the meshes' own paths (here one moved out of `meshes/<id>.vbo`).
    let manifest_path = out.join("organset.json");
    let manifest = std::fs::read_to_string(&manifest_path).unwrap();
    let first: serde_json::Value = serde_json::from_str(&manifest).unwrap();
    let moved = first["organs"][0]["mesh"].as_str().unwrap().to_string();
    std::fs::rename(out.join(&moved), out.join("moved.vbo")).unwrap();
    std::fs::write(&manifest_path, manifest.replace(&format!("\"{moved}\""), "\"moved.vbo\"")).unwrap();
    let mesh = std::fs::read(out.join("moved.vbo")).unwrap();
    let st = json(&vbrain(&[
        "stand-ins",
        out.to_str().unwrap(),
        "--min-triangles",
        "100",
        "--ratio",
        "0.2",
        "--offset",
        "1",
        "--json",
    ]));
    let built: Vec<_> = st["organs"].as_array().unwrap().iter().filter(|o| o["stand_in"].is_u64()).collect();
    assert!(!built.is_empty(), "{st}");
    for o in &built {
        assert!(2 * o["stand_in"].as_u64().unwrap() <= o["triangles"].as_u64().unwrap(), "{o}");
    }
    assert!(std::fs::read_to_string(out.join("organset.json")).unwrap().contains("occluder.vbo"));
    assert!(std::fs::read_dir(out.join("meshes"))
        .unwrap()
        .any(|e| { e.unwrap().file_name().to_string_lossy().ends_with(".occluder.vbo") }));
    assert_eq!(std::fs::read(out.join("moved.vbo")).unwrap(), mesh, "an organ's mesh was rewritten");
    assert!(std::fs::read_to_string(&manifest_path).unwrap().contains("\"moved.vbo\""), "the mesh's path was lost");
    let after = json(&vbrain(&["info", out.to_str().unwrap(), "--json"]));
    assert_eq!(after["organs"].as_array().unwrap().len(), first["organs"].as_array().unwrap().len());
    let r = vbrain(&["stand-ins", vol.to_str().unwrap()]);
    assert!(!r.status.success() && String::from_utf8_lossy(&r.stderr).contains("give --out"));

    let scaled = dir.path().join("scaled");
    let s =
        json(&vbrain(&["scale", out.to_str().unwrap(), "--factor", "4", "--out", scaled.to_str().unwrap(), "--json"]));
    assert_eq!(s["triangles"].as_u64().unwrap(), 4 * v["triangles"].as_u64().unwrap());

    // A folder that holds a set is not written over without --force, nor a manifest by an image.
    let before = std::fs::read(out.join("organset.json")).unwrap();
    let (o, s) = (out.to_str().unwrap(), scaled.to_str().unwrap());
    for (args, says) in [
        (&["import", vol.to_str().unwrap(), "--labels", csv.to_str().unwrap(), "--out", o][..], "--force"),
        // Its own input, which --force would not change.
        (&["scale", o, "--factor", "4", "--out", o], "holds what this command reads"),
        (&["scale", o, "--factor", "4", "--out", s], "--force"),
    ] {
        let r = vbrain(args);
        assert!(!r.status.success() && String::from_utf8_lossy(&r.stderr).contains(says), "{args:?}");
    }
    let manifest = out.join("organset.json");
    let r = vbrain(&["render", o, "--size", "32x32", "--out", manifest.to_str().unwrap()]);
    assert!(!r.status.success() && String::from_utf8_lossy(&r.stderr).contains("not a PNG"));
    assert_eq!(std::fs::read(&manifest).unwrap(), before, "the manifest was written over");
    json(&vbrain(&["scale", o, "--factor", "4", "--out", s, "--force", "--json"]));

    // Bad input: clear errors naming the file.
    let fresh = dir.path().join("fresh");
    let out = &fresh;
    let junk = dir.path().join("junk.nii");
    std::fs::write(&junk, b"not a nifti").unwrap();
    let r =
        vbrain(&["import", junk.to_str().unwrap(), "--labels", csv.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!r.status.success() && String::from_utf8_lossy(&r.stderr).contains("junk.nii"));
    let bad_csv = dir.path().join("bad.csv");
    std::fs::write(&bad_csv, "index,name\n17,a\nseventeen,b\n").unwrap();
    let r = vbrain(&[
        "import",
        vol.to_str().unwrap(),
        "--labels",
        bad_csv.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!r.status.success() && String::from_utf8_lossy(&r.stderr).contains("bad.csv:3"));
    // A table none of whose labels the volume holds yields no organ: an error, and no set.
    let other = dir.path().join("other.csv");
    std::fs::write(&other, "index,name\n5,Fifth\n").unwrap();
    let r =
        vbrain(&["import", vol.to_str().unwrap(), "--labels", other.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(
        !r.status.success() && String::from_utf8_lossy(&r.stderr).contains("no label of the table occurs"),
        "{r:?}"
    );
    assert!(!out.join("organset.json").exists());
}

#[test]
fn render_rejects_bad_clip_planes_and_cuts_with_good_ones() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let render =
        |clip: &str| vbrain(&["render", &brain(), "--out", out.to_str().unwrap(), "--size", "96x96", "--clip", clip]);
    for (clip, says) in [
        ("0,0,0,1", "zero"),
        ("axial=NaN", "millimetres"),
        ("axial=500", "outside the set"),
        ("oblique=3", "unknown plane"),
    ] {
        let o = render(clip);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(says), "--clip {clip}: {err}");
    }
    let whole = vbrain(&["render", &brain(), "--out", out.to_str().unwrap(), "--size", "96x96", "--view", "left"]);
    assert!(whole.status.success());
    let before = image::open(&out).unwrap().to_rgba8();
    let o = vbrain(&[
        "render",
        &brain(),
        "--out",
        out.to_str().unwrap(),
        "--size",
        "96x96",
        "--view",
        "left",
        "--clip",
        "sagittal=-20:flip",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cut = image::open(&out).unwrap().to_rgba8();
    assert_ne!(cut, before, "the cut shows the inside");
    // Every organ kept whole: the cut removes nothing.
    let left = ["--size", "96x96", "--view", "left", "--clip", "sagittal=-20:flip"];
    let o = vbrain(
        &[&["render", &brain(), "--out", out.to_str().unwrap(), "--whole", "Cerebrum,Brainstem,Cerebellum"][..], &left]
            .concat(),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let kept = image::open(&out).unwrap().to_rgba8();
    let differ =
        |a: &image::RgbaImage, b: &image::RgbaImage| a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count();
    assert!(differ(&kept, &cut) > 0);
    assert!(kept == before, "what is seen is kept whole: {} pixels differ", differ(&kept, &before));
    let o = vbrain(&[&["render", &brain(), "--out", out.to_str().unwrap(), "--whole", "nonesuch"][..], &left].concat());
    assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains("--whole"));
}

#[test]
fn labels_keep_their_share_of_the_image_at_any_size() {
    let dir = tempfile::tempdir().unwrap();
    let share = |size: u32| {
        let mut images = Vec::new();
        for labels in ["none", "all"] {
            let out = dir.path().join(format!("{labels}-{size}.png"));
            let s = format!("{size}x{size}");
            let o = vbrain(&[
                "render",
                &brain(),
                "--out",
                out.to_str().unwrap(),
                "--size",
                &s,
                "--clip",
                "sagittal=-4",
                "--view",
                "right",
                "--labels",
                labels,
                "--subsamples",
                "4",
            ]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            images.push(image::open(&out).unwrap().to_rgba8());
        }
        let changed = images[0].pixels().zip(images[1].pixels()).filter(|(a, b)| a != b).count();
        changed as f64 / (size * size) as f64
    };
    let (small, large) = (share(512), share(2048));
    assert!(small > 0.02, "labels drawn at 512: {:.1} % of the image", small * 100.0);
    assert!(
        (large / small - 1.0).abs() < 0.3,
        "labels cover {:.1} % at 512 but {:.1} % at 2048",
        small * 100.0,
        large * 100.0
    );
}

#[test]
fn render_rejects_an_unknown_transparency_mode() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let o = vbrain(&["render", &brain(), "--out", out.to_str().unwrap(), "--transparency", "glass"]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("glass") && err.contains("screendoor"), "{err}");
}

#[test]
fn quiz_writes_a_worksheet_with_an_answer_key() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("quiz");
    let o = vbrain(&[
        "quiz",
        &brain(),
        "--group",
        "Basal ganglia",
        "--questions",
        "12",
        "--seed",
        "3",
        "--size",
        "160x120",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stderr).contains("only 8 structures"), "more questions than structures: said");
    let v = json(&o);
    let questions = v["questions"].as_array().unwrap();
    assert_eq!(questions.len(), 8);
    let answers = std::fs::read_to_string(out.join("answers.md")).unwrap();
    for q in questions {
        let image = image::open(q["image"].as_str().unwrap()).unwrap();
        assert_eq!((image.width(), image.height()), (160, 120));
        let organ = q["organ"].as_str().unwrap();
        assert!(
            organ.contains("caudate")
                || organ.contains("putamen")
                || organ.contains("pallidum")
                || organ.contains("accumbens")
        );
        assert!(q["choices"].as_array().unwrap().iter().any(|c| c == organ));
    }
    assert_eq!(answers.lines().filter(|l| l.starts_with(char::is_numeric)).count(), 8);
    // The same seed again, over the first worksheet (replaced whole with --force).
    let again = vbrain(&[
        "quiz",
        &brain(),
        "--group",
        "Basal ganglia",
        "--seed",
        "3",
        "--size",
        "160x120",
        "--force",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(json(&again)["questions"], v["questions"], "a seed gives the same worksheet");
    for (group, says) in [("nonesuch", "no organ or group"), ("optic_chiasm", "at least two")] {
        let o = vbrain(&["quiz", &brain(), "--group", group, "--out", out.to_str().unwrap()]);
        assert!(!o.status.success() && String::from_utf8_lossy(&o.stderr).contains(says), "{group}");
    }
}
