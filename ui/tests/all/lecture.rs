//! Material for the lecture, read by the programs that read it: videos by ffprobe and ffmpeg
//! (Debian's ffmpeg), PDF handouts by Poppler (pdfinfo, pdftotext, pdftoppm; Debian's
//! poppler-utils).

use crate::cli::{brain, json, vbrain};
use eframe::egui;
use egui_kittest::kittest::Queryable;
use std::path::Path;
use std::process::Command;
use vbrain_ui::viewer::action::LessonAction;

/// Runs a program and gives its standard output, failing with what to install when it is missing.
fn run(program: &str, args: &[&str], package: &str) -> String {
    let out = Command::new(program)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("{program} could not be started ({e}); install Debian's {package}"));
    assert!(out.status.success(), "{program} {args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// ffprobe's view of a video's one stream: codec, frames counted by decoding, frame rate,
/// duration and size.
fn probe(video: &Path) -> serde_json::Value {
    let text = run(
        "ffprobe",
        &[
            "-v",
            "error",
            "-count_frames",
            "-show_entries",
            "stream=codec_name,nb_read_frames,r_frame_rate,width,height:format=duration",
            "-of",
            "json",
            video.to_str().unwrap(),
        ],
        "ffmpeg",
    );
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut stream = v["streams"][0].clone();
    stream["duration"] = v["format"]["duration"].clone();
    stream
}

/// Frame `k` of a video, decoded by ffmpeg.
fn frame(video: &Path, k: usize) -> image::RgbaImage {
    let png = video.with_extension(format!("frame{k}.png"));
    let select = format!("select=eq(n\\,{k})");
    let (input, out) = (video.to_str().unwrap(), png.to_str().unwrap());
    run("ffmpeg", &["-v", "error", "-y", "-i", input, "-vf", &select, "-frames:v", "1", out], "ffmpeg");
    image::open(&png).unwrap().to_rgba8()
}

/// Peak signal-to-noise ratio of `b` against `a` (RGB), in dB.
fn psnr(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let mut sum = 0.0;
    for (p, q) in a.pixels().zip(b.pixels()) {
        for c in 0..3 {
            let d = p[c] as f64 - q[c] as f64;
            sum += d * d;
        }
    }
    let mse = sum / (a.width() * a.height() * 3) as f64;
    10.0 * (255.0 * 255.0 / mse.max(1e-9)).log10()
}

#[test]
fn a_turntable_in_each_format_is_read_by_ffprobe_and_starts_as_render_draws_it() {
    let dir = tempfile::tempdir().unwrap();
    let reference = dir.path().join("render.png");
    let r = vbrain(&["render", &brain(), "--size", "320x240", "--out", reference.to_str().unwrap()]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let reference = image::open(&reference).unwrap().to_rgba8();
    for (name, codec, lowest_psnr) in
        [("spin.gif", "gif", 30.0), ("spin.mp4", "h264", 35.0), ("spin.webm", "vp9", 35.0)]
    {
        let out = dir.path().join(name);
        let args = ["video", &brain(), "--turntable", "360", "--seconds", "1", "--fps", "12", "--size", "320x240"];
        let report = json(&vbrain(&[&args[..], &["--out", out.to_str().unwrap(), "--json"]].concat()));
        assert_eq!(report["frames"], 12, "{report}");
        let p = probe(&out);
        assert_eq!(p["codec_name"], codec, "{name}: {p}");
        assert_eq!(p["nb_read_frames"], "12", "{name}: {p}");
        assert_eq!((p["width"].as_u64(), p["height"].as_u64()), (Some(320), Some(240)), "{name}: {p}");
        let duration: f64 = p["duration"].as_str().unwrap().parse().unwrap();
        assert!((duration - 1.0).abs() < 0.05, "{name}: {duration} s");
        if codec != "gif" {
            assert_eq!(p["r_frame_rate"], "12/1", "{name}: {p}");
        }
        // The first frame is `vbrain render`'s picture of the same camera; a later one has turned.
        let first = frame(&out, 0);
        let db = psnr(&reference, &first);
        assert!(db >= lowest_psnr, "{name}: first frame at {db:.1} dB against vbrain render");
        let turned = psnr(&reference, &frame(&out, 3));
        assert!(turned < db - 3.0, "{name}: a quarter turn later the picture should differ ({turned:.1} dB)");
    }
}

#[test]
fn a_lesson_video_eases_each_step_in_and_holds_it_with_its_caption() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ventricles.mp4");
    let lesson = Path::new(&brain()).join("lessons/ventricles.vblesson");
    let args = ["video", lesson.to_str().unwrap(), "--hold", "0.5", "--fps", "10", "--size", "320x240", "--captions"];
    let report = json(&vbrain(&[&args[..], &["--out", out.to_str().unwrap(), "--json"]].concat()));
    let text: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(lesson).unwrap()).unwrap();
    let steps = text["steps"].as_array().unwrap().len();
    // Per step 5 held frames, and 5 easing frames (0.5 s) into each step after the first.
    let frames = steps * 5 + (steps - 1) * 5;
    assert_eq!(report["frames"], frames, "{report}");
    assert_eq!(probe(&out)["nb_read_frames"], frames.to_string());
    // The caption's band is the bottom of every frame, with light text on it.
    let held = frame(&out, 4);
    let band = (held.height() * 3 / 4..held.height()).flat_map(|y| (0..held.width()).map(move |x| (x, y)));
    let text_pixels = band.filter(|&(x, y)| held.get_pixel(x, y).0[..3].iter().all(|&c| c > 150)).count();
    assert!(text_pixels > 100, "{text_pixels} light pixels in the caption band");
    // Between two held steps the view moves: the easing frames differ from both ends.
    let (before, easing, after) = (frame(&out, 4), frame(&out, 7), frame(&out, 14));
    assert!(psnr(&before, &easing) < 40.0 && psnr(&after, &easing) < 40.0);
}

#[test]
fn a_bad_video_request_is_refused_before_any_work_and_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = |n: &str| dir.path().join(n).to_str().unwrap().to_string();
    let refused = |args: &[&str], says: &str| {
        let out = vbrain(args);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!out.status.success() && err.contains(says), "{args:?}: {err}");
    };
    refused(&["video", &brain(), "--turntable", "90", "--out", &path("x.avi")], ".gif, .mp4");
    refused(&["video", &brain(), "--out", &path("x.gif")], "--turntable");
    let cortex = Path::new(&brain()).join("lessons/cortex.vblesson");
    refused(&["video", cortex.to_str().unwrap(), "--turntable", "90", "--out", &path("x.gif")], "lesson");
    refused(
        &["video", &brain(), "--turntable", "90", "--seconds", "1200", "--fps", "60", "--out", &path("x.mp4")],
        "at most 36000",
    );
    refused(&["video", &brain(), "--turntable", "90", "--size", "321x240", "--out", &path("x.mp4")], "even");
    refused(&["video", &brain(), "--turntable", "90", "--fps", "0", "--out", &path("x.gif")], "--fps");
    // Never over a file without --force.
    std::fs::write(path("kept.gif"), "not mine").unwrap();
    refused(&["video", &brain(), "--turntable", "90", "--out", &path("kept.gif")], "--force");
    assert_eq!(std::fs::read_to_string(path("kept.gif")).unwrap(), "not mine");
    // A failed encoder leaves no partial file.
    let out = Command::new(env!("CARGO_BIN_EXE_vbrain"))
        .args(["video", &brain(), "--turntable", "90", "--seconds", "0.2", "--fps", "10", "--size", "64x48"])
        .args(["--out", &path("failed.mp4")])
        .env("FFMPEG", "false")
        .output()
        .unwrap();
    assert!(!out.status.success(), "an encoder that fails must fail the export");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left, vec![std::ffi::OsString::from("kept.gif")], "only the kept file stays");
}

/// A lesson whose caption has Latin and other languages' accents, on the default brain.
fn accented_lesson(dir: &Path) -> std::path::PathBuf {
    let file = dir.join("accents.vblesson");
    let lesson = serde_json::json!({
        "format": "vbrain-lesson/1",
        "title": "Noms et accents",
        "set": brain(),
        "steps": [
            {"title": "Le système ventriculaire", "caption": "Le **ventricule latéral** (*ventriculus lateralis*) et le quatrième ventricule.\n\n- Großhirn: cortex cerebri\n- ἐγκέφαλος", "view": [-60, 20], "highlight": ["Ventricles"], "labels": "selected"},
            {"title": "Le cervelet", "caption": "Le *cerebellum* et ses hémisphères.", "view": [180, 0], "highlight": ["Cerebellum"]}
        ]
    });
    std::fs::write(&file, serde_json::to_string_pretty(&lesson).unwrap()).unwrap();
    file
}

#[test]
fn a_lesson_handout_is_read_by_poppler_with_its_captions_accents_and_figures() {
    let dir = tempfile::tempdir().unwrap();
    let lesson = accented_lesson(dir.path());
    let pdf = dir.path().join("handout.pdf");
    let (l, p) = (lesson.to_str().unwrap(), pdf.to_str().unwrap());
    json(&vbrain(&["lesson", "pdf", l, "--out", p, "--json"]));
    let info = run("pdfinfo", &[p], "poppler-utils");
    assert!(info.contains("Pages:           3"), "{info}");
    assert!(info.contains("595.28 x 841.89 pts (A4)"), "{info}");
    let text = run("pdftotext", &[p, "-"], "poppler-utils");
    for words in [
        "Noms et accents",
        "Le système ventriculaire",
        "ventricule latéral",
        "ventriculus lateralis",
        "Großhirn: cortex cerebri",
        "ἐγκέφαλος",
        "Le cervelet",
        "hémisphères",
    ] {
        assert!(text.contains(words), "pdftotext lacks \"{words}\": {text}");
    }
    // The set's attribution is on the title page.
    let title_page = run("pdftotext", &["-f", "1", "-l", "1", p, "-"], "poppler-utils");
    assert!(title_page.contains("Desikan"), "{title_page}");
    // Page 2's figure: the dark view behind the brain, and the brain's colours on it.
    let png = dir.path().join("page");
    run("pdftoppm", &["-r", "40", "-png", "-f", "2", "-l", "2", p, png.to_str().unwrap()], "poppler-utils");
    let page = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|f| f.file_name().unwrap().to_string_lossy().starts_with("page"))
        .unwrap();
    let page = image::open(page).unwrap().to_rgb8();
    let dark = page.pixels().filter(|p| p.0.iter().all(|&c| c < 50)).count();
    let coloured = page.pixels().filter(|p| p.0.iter().max().unwrap() - p.0.iter().min().unwrap() > 40).count();
    let all = (page.width() * page.height()) as usize;
    assert!(dark > all / 8 && coloured > all / 50, "dark {dark}, coloured {coloured} of {all}");
    // US Letter, and never over a file without --force.
    let letter = dir.path().join("letter.pdf");
    json(&vbrain(&["lesson", "pdf", l, "--out", letter.to_str().unwrap(), "--paper", "letter", "--json"]));
    assert!(run("pdfinfo", &[letter.to_str().unwrap()], "poppler-utils").contains("612 x 792 pts (letter)"));
    let again = vbrain(&["lesson", "pdf", l, "--out", p]);
    assert!(!again.status.success() && String::from_utf8_lossy(&again.stderr).contains("--force"));
}

#[test]
fn a_quiz_worksheet_pdf_has_a_page_per_question_then_the_answer_key() {
    let dir = tempfile::tempdir().unwrap();
    let (out, pdf) = (dir.path().join("quiz"), dir.path().join("quiz.pdf"));
    let args = ["quiz", &brain(), "--questions", "3", "--size", "400x300", "--group", "Basal ganglia"];
    let report = json(&vbrain(
        &[&args[..], &["--out", out.to_str().unwrap(), "--pdf", pdf.to_str().unwrap(), "--json"]].concat(),
    ));
    let p = pdf.to_str().unwrap();
    let info = run("pdfinfo", &[p], "poppler-utils");
    assert!(info.contains("Pages:           5"), "a title page, 3 questions and the key: {info}");
    let key = run("pdftotext", &["-f", "5", "-l", "5", p, "-"], "poppler-utils");
    assert!(key.contains("Answer key"), "{key}");
    let names = std::fs::read_to_string(out.join("answers.md")).unwrap();
    for (k, q) in report["questions"].as_array().unwrap().iter().enumerate() {
        let line = names.lines().find(|l| l.starts_with(&format!("{}.", k + 1))).unwrap();
        assert!(key.contains(line), "the key lacks \"{line}\" ({q})");
        let page = run("pdftotext", &["-f", &(k + 2).to_string(), "-l", &(k + 2).to_string(), p, "-"], "poppler-utils");
        assert!(page.starts_with(&format!("{}.", k + 1)), "page {}: {page}", k + 2);
        assert!(!page.contains("Answer key"));
    }
}

/// Runs the viewer until its background export has ended (at most two minutes).
fn until_exported(h: &mut egui_kittest::Harness<'static, vbrain_ui::viewer::app::App>) {
    let started = std::time::Instant::now();
    while h.state().is_exporting() {
        assert!(started.elapsed().as_secs() < 120, "the export did not end");
        h.run_steps(1);
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    h.run_steps(1);
}

#[test]
fn the_viewer_exports_handouts_of_the_lesson_and_the_view_and_cancels_a_video() {
    use vbrain_ui::viewer::action::{Action, ModelKind};
    let mut h = crate::viewer::harness_of(egui::Vec2::new(1280.0, 800.0));
    let file = crate::viewer::brain().join("lessons/ventricles.vblesson");
    let steps = vbrain::lesson::Lesson::load(&file).unwrap().steps.len();
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Lesson(LessonAction::Open(file))]);
    h.run_steps(4);
    let dir = tempfile::tempdir().unwrap();
    let (lesson_pdf, view_pdf) = (dir.path().join("lesson.pdf"), dir.path().join("view.pdf"));
    for (pdf, lesson, pages) in [(&lesson_pdf, true, steps + 1), (&view_pdf, false, 2)] {
        let export = Action::ExportModel { kind: ModelKind::Pdf, path: pdf.display().to_string(), lesson };
        h.state_mut().perform(&ctx, vec![export]);
        until_exported(&mut h);
        let info = run("pdfinfo", &[pdf.to_str().unwrap()], "poppler-utils");
        assert!(info.contains(&format!("Pages:           {pages}\n")), "{info}");
    }
    let text = run("pdftotext", &[lesson_pdf.to_str().unwrap(), "-"], "poppler-utils");
    assert!(text.contains("The ventricular system") && text.contains("foramen of Magendie"), "{text}");

    // A video started from the menu, then cancelled with the Cancel beside its progress.
    let gif = dir.path().join("turn.gif");
    let export = Action::ExportModel { kind: ModelKind::Video, path: gif.display().to_string(), lesson: false };
    h.state_mut().perform(&ctx, vec![export]);
    h.run_steps(2);
    assert!(h.state().is_exporting());
    h.get_by_label("Cancel").click();
    until_exported(&mut h);
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left.len(), 2, "a cancelled video leaves no file: {left:?}");
}
