//! The real viewer app under egui_kittest, drawn through wgpu (lavapipe in CI): load the default
//! brain, hide an organ and see it gone, change an opacity, select an organ by clicking the
//! viewport, export a screenshot and check it, and one snapshot of the whole window.

use eframe::egui::{self, Event, Key, Modifiers, PointerButton, Pos2};
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use std::path::Path;
use vbrain_ui::viewer::action::{DocumentAction, LessonAction, SectionAction};
use vbrain_ui::viewer::settings::ExportSize;
use vbrain_ui::{App, AppOptions};

pub fn brain() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../organs/brain")
}

/// The app on the default brain, loaded and drawn, at the snapshot's size.
fn harness() -> Harness<'static, App> {
    harness_of(egui::Vec2::new(1100.0, 700.0))
}

/// The app on the default brain in a window of `size`: smaller draws faster on a software GPU.
pub fn harness_of(size: egui::Vec2) -> Harness<'static, App> {
    harness_with(size, None)
}

/// The same, keeping its recovery file at `recovery`.
fn harness_with(size: egui::Vec2, recovery: Option<std::path::PathBuf>) -> Harness<'static, App> {
    let mut h = Harness::builder().with_size(size).wgpu().build_eframe(move |cc| {
        App::new(
            cc,
            AppOptions {
                path: Some(brain()),
                recovery: recovery.clone(),
                quiz_history: None,
                data: Default::default(),
            },
        )
    });
    wait_for_set(&mut h);
    h
}

/// Steps `h` until its set has loaded (at most 600 steps), then three more.
pub fn wait_for_set(h: &mut Harness<'static, App>) {
    for _ in 0..600 {
        h.step();
        if h.state().scene().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(h.state().scene().is_some(), "the default brain did not load: {:?}", messages(h));
    h.run_steps(3);
}

/// The viewport's image once refinement has put every screen-door sub-sample in (a still view
/// adds a pass a frame).
fn converged_image(h: &mut Harness<'static, App>) -> image::RgbaImage {
    for _ in 0..32 {
        let stats = h.state().viewport().stats();
        if stats.subsamples_done >= stats.subsamples_total {
            break;
        }
        h.run_steps(1);
    }
    h.state().read_image().unwrap()
}

fn messages(h: &Harness<'static, App>) -> Vec<String> {
    h.state().notifications().iter().map(|n| n.text.clone()).collect()
}

pub fn organ(h: &Harness<'static, App>, id: &str) -> usize {
    h.state().scene().unwrap().set().find(id).unwrap()
}

pub fn pixels_of(h: &Harness<'static, App>, organ: usize) -> usize {
    let (ids, _) = h.state().read_ids().unwrap();
    ids.iter().filter(|&&i| i == organ as u32 + 1).count()
}

/// Points of the viewport where `organ` is drawn, near the middle of its pixels.
pub fn point_on(h: &Harness<'static, App>, organ: usize) -> Pos2 {
    let (ids, [w, _]) = h.state().read_ids().unwrap();
    let hits: Vec<usize> = (0..ids.len()).filter(|&i| ids[i] == organ as u32 + 1).collect();
    let i = hits[hits.len() / 2];
    let rect = h.state().viewport().rect();
    let ppp = h.ctx.pixels_per_point();
    Pos2::new(rect.min.x + ((i % w as usize) as f32 + 0.5) / ppp, rect.min.y + ((i / w as usize) as f32 + 0.5) / ppp)
}

/// A left click at a point of the window.
pub fn click(h: &Harness<'static, App>, at: Pos2) {
    h.event(Event::PointerMoved(at));
    for pressed in [true, false] {
        h.event(Event::PointerButton { pos: at, button: PointerButton::Primary, pressed, modifiers: Modifiers::NONE });
    }
}

/// Types `query` into the organ search.
pub fn search(h: &mut Harness<'static, App>, query: &str) {
    h.get_by_label("Search organs").focus();
    h.run_steps(1);
    h.get_by_label("Search organs").type_text(query);
    h.run_steps(2);
}

/// The organs the tree shows (by their eye toggles' labels "Show NAME").
fn rows(h: &Harness<'static, App>) -> Vec<String> {
    let scene = h.state().scene().unwrap();
    scene
        .set()
        .organs
        .iter()
        .filter(|o| h.query_by_label(&format!("Show {}", o.name)).is_some())
        .map(|o| o.name.clone())
        .collect()
}

#[test]
fn search_finds_gyri_by_name_synonym_and_latin() {
    let mut h = harness_of(egui::Vec2::new(760.0, 480.0));
    for (query, expect) in [
        ("precentral", vec!["Left precentral gyrus", "Right precentral gyrus"]),
        (
            "Broca",
            vec![
                "Left pars opercularis of the inferior frontal gyrus",
                "Left pars triangularis of the inferior frontal gyrus",
                "Right pars opercularis of the inferior frontal gyrus",
                "Right pars triangularis of the inferior frontal gyrus",
            ],
        ),
        ("gyrus précentralis", vec!["Left precentral gyrus", "Right precentral gyrus"]),
    ] {
        if h.query_by_label("Clear search").is_some() {
            h.get_by_label("Clear search").click();
            h.run_steps(2);
        }
        search(&mut h, query);
        let mut found = rows(&h);
        found.sort();
        assert_eq!(found, expect, "search \"{query}\"");
    }
}

#[test]
fn hide_fade_select_and_export() {
    let mut h = harness();
    let frontal = organ(&h, "precentral_l");
    let total = h.state().scene().unwrap().set().triangle_count();
    // The visible cortex is drawn; culling leaves out what it hides.
    let drawn = h.state().viewport().stats().triangles_drawn;
    assert!(drawn > 20_000 && drawn < total, "{drawn} of {total} triangles drawn");
    let before = h.state().read_image().unwrap();
    assert!(pixels_of(&h, frontal) > 1000);
    // The lobes start closed; a search opens the groups of what it finds.
    assert!(h.query_by_label("Show Left precentral gyrus").is_none());
    search(&mut h, "precentral");

    // Hide it with its eye toggle: gone from the viewport.
    h.get_by_label("Show Left precentral gyrus").click();
    h.run_steps(2);
    assert!(!h.state().scene().unwrap().layout().organs[frontal].visible);
    assert_eq!(pixels_of(&h, frontal), 0);
    assert_ne!(h.state().read_image().unwrap(), before);
    h.get_by_label("Show Left precentral gyrus").click();
    h.run_steps(2);
    assert_eq!(h.state().read_image().unwrap(), before, "showing it again restores the image");

    // Fade it with its transparency toggle: still drawn, now translucent, and the image changes.
    h.get_by_label("Transparency of Left precentral gyrus").click();
    h.run_steps(2);
    let opacity = h.state().scene().unwrap().layout().organs[frontal].opacity;
    assert!(opacity > 0.0 && opacity < 1.0, "{opacity}");
    assert_ne!(h.state().read_image().unwrap(), before);
    h.get_by_label("Transparency of Left precentral gyrus").click();
    h.run_steps(2);
    assert_eq!(h.state().scene().unwrap().layout().organs[frontal].opacity, 1.0);

    // Select it by clicking the viewport: the inspector shows it.
    click(&h, point_on(&h, frontal));
    h.run_steps(3);
    assert_eq!(h.state().selected(), Some(frontal));
    assert!(h.query_by_label("Inspector opacity of Left precentral gyrus").is_some());

    // Export at the viewport's size: the PNG is exactly what the viewport shows.
    let dir = tempfile::tempdir().unwrap();
    let shown = h.state().read_image().unwrap();
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    h.run_steps(2);
    assert!(h.state().dialogs().export.open, "Ctrl+E opens the export window");
    let file = dir.path().join("view.png");
    h.state_mut().dialogs_mut().export.path.text = file.display().to_string();
    h.state_mut().settings_mut().export.size = ExportSize::Viewport;
    h.get_by_label("Save").click();
    h.run_steps(2);
    let png = image::open(&file).unwrap_or_else(|e| panic!("{e}: {:?}", messages(&h))).to_rgba8();
    assert_eq!(png.dimensions(), shown.dimensions());
    assert_eq!(png, shown, "the exported image matches the viewport");

    // Twice the size, into the same name: a new file, never an overwrite.
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    h.run_steps(2);
    h.state_mut().dialogs_mut().export.path.text = file.display().to_string();
    h.state_mut().settings_mut().export.size = ExportSize::Double;
    h.get_by_label("Save").click();
    h.run_steps(2);
    let second = image::open(dir.path().join("view-2.png")).unwrap();
    assert_eq!((second.width(), second.height()), (shown.width() * 2, shown.height() * 2));
    assert_eq!(image::open(&file).unwrap().to_rgba8(), shown);

    // With the selected organ labelled, the export names it: its plate and line are drawn in.
    h.state_mut().settings_mut().labels = vbrain_ui::viewer::settings::LabelMode::Selected;
    h.key_press_modifiers(Modifiers::COMMAND, Key::E);
    h.run_steps(2);
    h.state_mut().dialogs_mut().export.path.text = file.display().to_string();
    h.state_mut().settings_mut().export.size = ExportSize::Viewport;
    h.get_by_label("Save").click();
    h.run_steps(2);
    let labelled = image::open(dir.path().join("view-3.png")).unwrap().to_rgba8();
    let changed = labelled.pixels().zip(shown.pixels()).filter(|(a, b)| a != b).count();
    assert!(changed > 500, "the label of the selected organ is in the export ({changed} pixels changed)");

    // The scene as a glTF model and as a web page, from the File menu's windows.
    use vbrain_ui::viewer::action::{Action, ModelKind};
    let ctx = h.ctx.clone();
    let (glb, page) = (dir.path().join("brain.glb"), dir.path().join("page"));
    for (kind, path) in [(ModelKind::Gltf, &glb), (ModelKind::Web, &page)] {
        let export = Action::ExportModel { kind, path: path.display().to_string(), lesson: false };
        h.state_mut().perform(&ctx, vec![export]);
    }
    h.run_steps(2);
    assert_eq!(&std::fs::read(&glb).unwrap_or_else(|e| panic!("{e}: {:?}", messages(&h)))[0..4], b"glTF");
    let html = std::fs::read_to_string(page.join("index.html")).unwrap_or_else(|e| panic!("{e}: {:?}", messages(&h)));
    let data_at = html.find("id=\"vbrain-data\">").unwrap();
    assert!(html[data_at..].contains("\"labels\":[\"precentral_l\"]"), "the selected organ is labelled on the page");
    assert!(html[data_at..].contains("\"selection\":\"precentral_l\""));
    // A folder that now holds files is refused, and left as it was.
    h.state_mut().perform(
        &ctx,
        vec![Action::ExportModel { kind: ModelKind::Web, path: page.display().to_string(), lesson: false }],
    );
    h.run_steps(2);
    assert!(messages(&h).iter().any(|m| m.contains("choose a new folder")), "{:?}", messages(&h));
}

#[test]
fn snapshot_of_the_viewer() {
    let mut h = harness();
    // Timings change from run to run; the snapshot shows everything else. lavapipe draws the same
    // pixels every run (two runs matched at 0 failed pixels), so any difference is a change.
    h.state_mut().settings_mut().show_stats = false;
    h.run_steps(2);
    h.snapshot_options(
        "viewer_default_brain",
        &egui_kittest::SnapshotOptions::new().threshold(1.0).max_failed_pixels(0),
    );
}

#[test]
fn shortcuts_act_on_the_selected_organ() {
    let mut h = harness_of(egui::Vec2::new(760.0, 480.0));
    let frontal = organ(&h, "superiorfrontal_l");
    let state = |h: &Harness<'static, App>| h.state().scene().unwrap().layout().organs[frontal];
    click(&h, point_on(&h, frontal));
    h.run_steps(3);
    assert_eq!(h.state().selected(), Some(frontal));
    h.key_press(Key::T);
    h.run_steps(2);
    let faded = state(&h).opacity;
    assert!(faded > 0.0 && faded < 1.0, "T fades it: {faded}");
    h.key_press(Key::T);
    h.run_steps(2);
    assert_eq!(state(&h).opacity, 1.0, "T again makes it opaque");
    h.key_press(Key::T);
    h.run_steps(2);
    assert_eq!(state(&h).opacity, faded, "and again back to the same translucent opacity");
    h.key_press(Key::H);
    h.run_steps(2);
    assert!(!state(&h).visible, "H hides it");
    h.key_press(Key::I);
    h.run_steps(2);
    let layout = h.state().scene().unwrap().layout().clone();
    assert!(layout.organs.iter().enumerate().all(|(i, s)| s.visible == (i == frontal)), "I isolates it");
    h.key_press_modifiers(Modifiers::COMMAND, Key::R);
    h.run_steps(2);
    assert_eq!(state(&h).opacity, 1.0, "Ctrl+R resets the layout");
    assert!(h.state().scene().unwrap().layout().organs.iter().filter(|s| s.visible).count() > 30);
    let reset = h.state().scene().unwrap().layout().clone();

    // Undo walks back through every change, one step each; redo (both keys) walks forward.
    let shift = Modifiers { shift: true, ..Modifiers::COMMAND };
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().scene().unwrap().layout(), &layout, "Ctrl+Z undoes the reset");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert!(!state(&h).visible && h.state().scene().unwrap().layout().organs.iter().filter(|s| s.visible).count() > 30);
    h.key_press_modifiers(shift, Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().scene().unwrap().layout(), &layout, "Ctrl+Shift+Z redoes the isolate");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    h.run_steps(2);
    assert_eq!(h.state().scene().unwrap().layout(), &reset, "Ctrl+Y redoes the reset");
    for _ in 0..6 {
        h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
        h.run_steps(1);
    }
    h.run_steps(1);
    assert_eq!(state(&h).opacity, 1.0);
    assert!(state(&h).visible);
    assert_eq!(h.state().scene().unwrap().history().len(), 0, "all six steps undone");

    // The Edit menu names what it would redo.
    h.get_by_label("Edit").click();
    h.run_steps(2);
    let redo: Vec<String> = h.query_all_by_label_contains("Redo").map(|n| format!("{n:?}")).collect();
    assert!(
        redo.iter().any(|l| l.contains("Redo fade Left superior frontal gyrus")),
        "the Edit menu names the step: {redo:?}"
    );
    h.key_press(Key::Escape);
    h.run_steps(2);
    h.key_press(Key::Escape);
    h.run_steps(2);
    assert_eq!(h.state().selected(), None, "Esc deselects");
}

#[test]
fn save_a_scene_then_reopen_it() {
    let mut h = harness_of(egui::Vec2::new(760.0, 480.0));
    let dir = tempfile::tempdir().unwrap();
    let gyrus = organ(&h, "superiorfrontal_l");
    click(&h, point_on(&h, gyrus));
    h.run_steps(3);
    h.key_press(Key::T);
    h.key_press(Key::Num3);
    h.run_steps(3);
    assert!(h.state().document().unsaved(h.state().scene()), "a faded organ is an unsaved change");

    // Ctrl+S with no file yet asks where; the scene is written there.
    h.key_press_modifiers(Modifiers::COMMAND, Key::S);
    h.run_steps(2);
    assert!(h.state().document().save_window.open, "Ctrl+S asks where to save a new scene");
    let file = dir.path().join("lesson-view");
    h.state_mut().document_mut().save_window.field.text = file.display().to_string();
    h.get_by_label("Save").click();
    h.run_steps(2);
    let file = dir.path().join("lesson-view.vbscene");
    assert!(file.is_file(), "{:?}", messages(&h));
    assert!(!h.state().document().unsaved(h.state().scene()));
    let saved_layout = h.state().scene().unwrap().layout().clone();
    let shown = converged_image(&mut h);

    // Change everything, then open the scene: the same organs, selection, camera and pixels.
    h.key_press_modifiers(Modifiers::COMMAND, Key::R);
    h.key_press(Key::Escape);
    h.key_press(Key::Num5);
    h.run_steps(3);
    assert_ne!(h.state().read_image().unwrap(), shown);
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![vbrain_ui::viewer::action::Action::Open(vec![file.clone()])]);
    h.run_steps(2);
    // The reset since the save is an unsaved change: the viewer asks first.
    h.get_by_label("Don't save").click();
    h.run_steps(3);
    assert!(h.state().scene().unwrap().layout() == &saved_layout, "the saved layout is back");
    assert_eq!(h.state().selected(), Some(gyrus));
    assert_eq!(converged_image(&mut h), shown, "the reopened scene shows the same pixels");
    assert!(!h.state().document().unsaved(h.state().scene()));

    // The scene rendered headless at the viewport's size is what the viewer exports.
    let exported = dir.path().join("export.png");
    let ctx = h.ctx.clone();
    let size = [shown.width(), shown.height()];
    let export = vbrain_ui::viewer::action::Action::Export { path: exported.display().to_string(), size };
    h.state_mut().perform(&ctx, vec![export]);
    h.run_steps(2);
    let headless = dir.path().join("headless.png");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_vbrain"))
        .args(["render", "--scene", &file.display().to_string(), "--out", &headless.display().to_string()])
        .args(["--size", &format!("{}x{}", size[0], size[1])])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (a, b) = (image::open(&exported).unwrap().to_rgba8(), image::open(&headless).unwrap().to_rgba8());
    assert!(a == b, "vbrain render --scene matches the viewer's export ({} pixels differ)", differing(&a, &b));
}

fn differing(a: &image::RgbaImage, b: &image::RgbaImage) -> usize {
    a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count()
}

#[test]
fn author_a_lesson_step_and_undo_it() {
    use vbrain::edit::{Edit, Organs};
    use vbrain_ui::viewer::action::Action;
    let mut h = harness_of(egui::Vec2::new(900.0, 640.0));
    let ctx = h.ctx.clone();
    h.get_by_label("Lessons").click();
    h.run_steps(2);
    h.get_by_label("New lesson").click();
    h.run_steps(2);
    let steps = |h: &Harness<'static, App>| h.state().lesson().lesson.as_ref().map_or(0, |l| l.steps.len());
    assert_eq!(steps(&h), 1, "a new lesson starts with the current view");
    let start = h.state().scene().unwrap().layout().clone();

    // Fade a gyrus, then add a step from the view: the step shows exactly that layout.
    let gyrus = organ(&h, "precentral_l");
    h.state_mut().perform(&ctx, vec![Action::Edit(Edit::Opacity { organs: Organs::One(gyrus), opacity: 0.3 })]);
    h.run_steps(1);
    h.get_by_label("+ Add step from view").click();
    h.run_steps(2);
    assert_eq!(steps(&h), 2);
    let faded = h.state().scene().unwrap().layout().clone();
    let set = h.state().scene().unwrap().set().clone();
    assert_eq!(h.state().lesson().lesson.as_ref().unwrap().steps[1].view(&set).layout, faded);
    assert_eq!(h.state().lesson().step, 1, "the new step is the current one");

    // Undo takes back the step, then the fade; redo brings both back, from the Edit menu too.
    h.get_by_label("Edit").click();
    h.run_steps(2);
    let undo: Vec<String> = h.query_all_by_label_contains("Undo").map(|n| format!("{n:?}")).collect();
    assert!(undo.iter().any(|l| l.contains("Undo add step 2")), "the Edit menu names the lesson edit: {undo:?}");
    h.key_press(Key::Escape);
    h.run_steps(1);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_eq!(steps(&h), 1);
    assert_eq!(h.state().scene().unwrap().layout(), &faded, "undoing the step leaves the organs");
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().scene().unwrap().layout(), &start);
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::Z);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Y);
    h.run_steps(2);
    assert_eq!((steps(&h), h.state().scene().unwrap().layout()), (2, &faded));

    // Caption, reorder, delete.
    h.get_by_label("2. Step 2").click();
    h.run_steps(3);
    h.get_by_label("Caption").click();
    h.run_steps(1);
    h.get_by_label("Caption").type_text("The **precentral** gyrus, faded.");
    h.run_steps(1);
    h.get_by_label("Step title").click();
    h.run_steps(2);
    let lesson = |h: &Harness<'static, App>| h.state().lesson().lesson.clone().unwrap();
    assert_eq!(lesson(&h).steps[1].caption, "The **precentral** gyrus, faded.");
    h.get_by_label("Move step 2 up").click();
    h.run_steps(2);
    assert_eq!(lesson(&h).steps[0].caption, "The **precentral** gyrus, faded.");
    h.get_by_label("Delete step 2").click();
    h.run_steps(2);
    assert_eq!(steps(&h), 1);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_eq!(steps(&h), 2, "a delete is undone like any edit");

    // Closing an unsaved lesson asks; saving writes a lesson that reads back the same.
    h.state_mut().perform(&ctx, vec![Action::Lesson(LessonAction::Close)]);
    h.run_steps(2);
    assert!(h.query_by_label("Save changes?").is_some(), "closing an unsaved lesson asks");
    h.get_by_label("Cancel").click();
    h.run_steps(2);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("mine.vblesson");
    h.state_mut().perform(&ctx, vec![Action::Lesson(LessonAction::SaveTo(file.clone()))]);
    h.run_steps(2);
    let saved = vbrain::lesson::Lesson::load(&file).unwrap_or_else(|e| panic!("{e}: {:?}", messages(&h)));
    assert_eq!(saved.steps, lesson(&h).steps);
    assert_eq!(saved.set_path(&file).canonicalize().unwrap(), brain().canonicalize().unwrap());
    assert!(!h.state().lesson().unsaved());
    h.state_mut().perform(&ctx, vec![Action::Lesson(LessonAction::Close)]);
    h.run_steps(2);
    assert!(!h.state().lesson().is_open(), "a saved lesson closes without asking");
}

#[test]
fn unsaved_changes_are_asked_about_and_recovered() {
    use vbrain::edit::{Edit, Organs};
    use vbrain_ui::viewer::action::Action;
    let dir = tempfile::tempdir().unwrap();
    // In a folder not made yet, as the settings' folder is on a first run.
    let recovery = dir.path().join("first-run/vbrain/recovery.vbscene");
    let size = egui::Vec2::new(640.0, 400.0);
    let mut h = harness_with(size, Some(recovery.clone()));
    let gyrus = organ(&h, "precentral_l");
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Edit(Edit::Visible { organs: Organs::One(gyrus), visible: false })]);
    h.run_steps(2);
    assert!(recovery.is_file(), "the first unsaved change is written to the recovery file at once");
    let kept = dir.path().join("kept.vbscene");
    std::fs::copy(&recovery, &kept).unwrap();

    // Quitting asks; Cancel keeps everything.
    h.state_mut().perform(&ctx, vec![Action::Quit]);
    h.run_steps(2);
    assert!(h.query_by_label("Save changes?").is_some(), "quitting with unsaved changes asks");
    h.get_by_label("Cancel").click();
    h.run_steps(2);
    assert!(h.query_by_label("Save changes?").is_none());
    assert!(!h.state().scene().unwrap().layout().organs[gyrus].visible);

    // So does closing the window.
    h.input_mut().viewports.entry(egui::ViewportId::ROOT).or_default().events.push(egui::ViewportEvent::Close);
    h.run_steps(2);
    assert!(h.query_by_label("Save changes?").is_some(), "closing the window with unsaved changes asks");
    h.get_by_label("Cancel").click();
    h.run_steps(2);

    // Opening another set asks too; Don't save goes on and removes the recovery file.
    h.state_mut().perform(&ctx, vec![Action::Open(vec![brain()])]);
    h.run_steps(2);
    assert!(h.query_by_label("Save changes?").is_some(), "opening another set with unsaved changes asks");
    h.get_by_label("Don't save").click();
    h.run_steps(2);
    assert!(!recovery.exists(), "discarded changes need no recovery");

    // A recovery file found at start is offered back, as unsaved changes.
    std::fs::rename(&kept, &recovery).unwrap();
    let mut h = harness_with(size, Some(recovery.clone()));
    h.run_steps(2);
    assert!(h.query_by_label("Restore unsaved changes?").is_some(), "{:?}", messages(&h));
    h.get_by_label("Restore").click();
    h.run_steps(3);
    assert!(!h.state().scene().unwrap().layout().organs[gyrus].visible, "the hidden gyrus is back");
    assert!(h.state().document().unsaved(h.state().scene()), "restored changes are not saved anywhere yet");
}

#[test]
fn play_a_shipped_lesson_step_by_step() {
    use vbrain_ui::viewer::action::Action;
    let mut h = harness_of(egui::Vec2::new(900.0, 560.0));
    h.get_by_label("Lessons").click();
    h.run_steps(2);
    h.get_by_label("The ventricular system").click();
    h.run_steps(3);
    let path = h.state().lesson().path.clone().expect("the Lessons menu opens it");
    let lesson = vbrain::lesson::Lesson::load(&path).unwrap();
    let layout_of = |k: usize, h: &Harness<'static, App>| lesson.steps[k].view(h.state().scene().unwrap().set()).layout;
    assert_eq!(h.state().scene().unwrap().layout(), &layout_of(0, &h), "it opens at step 1");
    let first = h.state().read_image().unwrap();

    h.key_press(Key::PageDown);
    h.run_steps(1);
    let halfway = h.state().scene().unwrap().shown().clone();
    assert!(halfway != layout_of(0, &h) && halfway != layout_of(1, &h), "the step eases in");
    h.run_steps(2);
    assert_eq!(h.state().scene().unwrap().shown(), &layout_of(1, &h), "and ends at the step");
    assert_eq!(h.state().lesson().step, 1);
    assert_eq!(h.state().scene().unwrap().layout(), &layout_of(1, &h), "Page Down shows step 2");
    assert_ne!(h.state().read_image().unwrap(), first);
    assert!(h.query_by_label_contains("interventricular foramina").is_some(), "the caption is shown");

    h.get_by_label("< Previous").click();
    h.run_steps(3);
    assert_eq!(h.state().lesson().step, 0);
    assert_eq!(h.state().read_image().unwrap(), first, "back at step 1, the same picture");
    h.get_by_label("5. The flow of cerebrospinal fluid").click();
    h.run_steps(3);
    assert_eq!(h.state().scene().unwrap().layout(), &layout_of(4, &h));

    // A step's layout is an undoable change like any other.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().scene().unwrap().layout(), &layout_of(0, &h));
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Lesson(LessonAction::Close)]);
    h.run_steps(2);
    assert!(!h.state().lesson().is_open());
}

#[test]
fn cut_keep_an_organ_whole_drag_a_plane_and_label_it() {
    use vbrain_ui::viewer::action::{Action, Window};
    use vbrain_ui::viewer::settings::LabelMode;
    // The plane's handle is mid-view, beside the dock.
    let mut h = harness_of(egui::Vec2::new(760.0, 640.0));
    let dir = tempfile::tempdir().unwrap();
    let gyrus = organ(&h, "superiorfrontal_l");
    let name = h.state().scene().unwrap().set().organs[gyrus].name.clone();
    click(&h, point_on(&h, gyrus));
    h.run_steps(3);
    let whole = pixels_of(&h, gyrus);
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Show(Window::Sections)]);
    h.run_steps(2);

    // The axial plane at 0 mm takes away the superior half: most of the superior frontal gyrus.
    h.get_by_label("Axial").click();
    h.run_steps(3);
    assert_eq!(h.state().sections().current.planes.len(), 1);
    let cut = pixels_of(&h, gyrus);
    assert!(cut * 2 < whole, "cut {cut} of {whole} pixels");
    assert!(h.state().document().unsaved(h.state().scene()), "a plane is an unsaved change");
    // The inspector shares the dock with the sections: bring its tab to the front.
    h.get_by_label("Inspector tab").click();
    h.run_steps(2);
    h.get_by_label(&format!("Do not cut {name}")).click_accesskit();
    h.run_steps(3);
    assert_eq!(h.state().sections().current.whole, vec![gyrus]);
    assert!(pixels_of(&h, gyrus) * 10 > whole * 9, "kept whole, it is all there again");

    // Dragging the plane's handle up (seen from the front, superior is up) moves it superiorly.
    let handles = h.state().plane_handles();
    assert_eq!(handles.len(), 1);
    let (dot, _) = h.state().viewport().handle_points(h.state().scene().unwrap(), &handles[0]).unwrap();
    let press = |h: &Harness<'static, App>, at: Pos2, pressed| {
        h.event(Event::PointerButton { pos: at, button: PointerButton::Primary, pressed, modifiers: Modifiers::NONE })
    };
    h.event(Event::PointerMoved(dot));
    press(&h, dot, true);
    h.run_steps(1);
    for k in 1..=4 {
        h.event(Event::PointerMoved(dot - egui::vec2(0.0, 10.0 * k as f32)));
        h.run_steps(1);
    }
    press(&h, dot - egui::vec2(0.0, 40.0), false);
    h.run_steps(2);
    let mm = h.state().sections().planes[0].mm;
    assert!(mm > 5.0, "the plane moved up to {mm} mm");
    assert_eq!(h.state().selected(), Some(gyrus), "a drag on a handle does not orbit or pick");

    // Label it: the chosen-labels mode; the scene saves planes, whole organs and labels.
    h.get_by_label(&format!("Label {name}")).click_accesskit();
    h.run_steps(2);
    assert_eq!((h.state().settings().labels, h.state().chosen_labels()), (LabelMode::Chosen, &[gyrus][..]));
    let file = dir.path().join("cut.vbscene");
    h.state_mut().perform(&ctx, vec![Action::Document(DocumentAction::SaveTo(file.clone()))]);
    h.run_steps(1);
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.contains("\"whole\"") && text.contains("\"labels\": \"superiorfrontal_l\""), "{text}");
    let section = h.state().sections().current.clone();
    h.state_mut().perform(&ctx, vec![Action::Section(SectionAction::KeepWhole { organ: gyrus, whole: false })]);
    h.state_mut().perform(&ctx, vec![Action::Open(vec![file.clone()])]);
    h.run_steps(2);
    h.get_by_label("Don't save").click();
    h.run_steps(3);
    assert_eq!(h.state().sections().current, section, "{:?}", messages(&h));
    assert_eq!(h.state().chosen_labels(), &[gyrus]);
}

/// A hand-made set that tests the panels' limits: a 3,000-character name with no space, a long
/// description, a group 500 deep, and 300 organs in all. The window keeps its 3-D view.
#[test]
fn long_names_deep_groups_and_many_organs_leave_the_view_in_place() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("meshes")).unwrap();
    let mut organs = Vec::new();
    for i in 0..300 {
        let (x, y) = ((i % 20) as f32 * 12.0, (i / 20) as f32 * 12.0);
        let obj = format!(
            "v {x} {y} 0\nv {} {y} 0\nv {x} {} 0\nv {x} {y} 8\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n",
            x + 8.0,
            y + 8.0
        );
        std::fs::write(dir.path().join(format!("meshes/o{i}.obj")), obj).unwrap();
        let (name, group, info) = if i == 0 {
            let deep: Vec<String> = (0..500).map(|d| format!("level{d}")).collect();
            ("N".repeat(3000), deep.join("/"), "A long description. ".repeat(2000))
        } else {
            (format!("Organ {i}"), format!("Group {}", i % 7), String::new())
        };
        let colour = "#c08080";
        organs.push(serde_json::json!({"id": format!("o{i}"), "name": name, "mesh": format!("meshes/o{i}.obj"),
            "colour": colour, "group": group, "info": info}));
    }
    let manifest = serde_json::json!({"format": "vbrain-organ-set/1", "title": "T".repeat(500), "organs": organs});
    std::fs::write(dir.path().join("organset.json"), manifest.to_string()).unwrap();
    let set = dir.path().to_path_buf();
    let size = egui::Vec2::new(1000.0, 640.0);
    let mut h = Harness::builder().with_size(size).wgpu().build_eframe(move |cc| {
        App::new(
            cc,
            AppOptions { path: Some(set.clone()), recovery: None, quiz_history: None, data: Default::default() },
        )
    });
    for _ in 0..600 {
        h.step();
        if h.state().scene().is_some() {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert_eq!(h.state().scene().map(|s| s.set().organs.len()), Some(300), "{:?}", messages(&h));
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![vbrain_ui::viewer::Action::Select(Some(0))]);
    h.run_steps(4);
    let view = h.state().viewport().rect();
    // The organ panel at its default width (330 points), the inspector at most 320.
    assert!(view.width() >= size.x - 660.0 && view.height() >= size.y * 0.5, "3-D view squeezed to {view:?}");
    let image = h.state().read_image().unwrap();
    let background = *image.get_pixel(0, 0);
    assert!(image.pixels().filter(|&&p| p != background).count() > 1000, "the organs are drawn");
}
