//! What a new user met in the first hour with the viewer, each kept fixed: group rows act on the
//! whole group their name says while a search shows part of it; Esc closes a menu before it
//! deselects; the quiz picks its group from a list, and the tree shows what the quiz shows.

use super::viewer::{harness_of, organ, search};
use eframe::egui::{self, Key, Modifiers};
use egui_kittest::kittest::Queryable;
use vbrain_ui::viewer::action::LessonAction;

#[test]
fn a_group_row_fades_the_whole_group_while_a_search_shows_part_of_it() {
    let mut h = harness_of(egui::Vec2::new(900.0, 560.0));
    search(&mut h, "Broca");
    h.get_all_by_label("Transparency of group Frontal lobe").next().unwrap().click();
    h.run_steps(2);
    let scene = h.state().scene().unwrap();
    let label = scene.history().undo_label().unwrap().to_string();
    let group = label.strip_prefix("fade ").unwrap_or_else(|| panic!("{label}"));
    let members: Vec<usize> = (0..scene.set().organs.len()).filter(|&o| scene.set().organs[o].group == group).collect();
    assert!(members.len() > 4, "{group}: {members:?}");
    for o in members {
        assert!(scene.layout().organs[o].opacity < 1.0, "{} of {group} was not faded", scene.set().organs[o].id);
    }
    // What the search hid of other groups is untouched.
    assert_eq!(scene.layout().organs[organ(&h, "precentral_r")].opacity, 1.0);
}

#[test]
fn esc_closes_the_menu_first_and_deselects_second() {
    let mut h = harness_of(egui::Vec2::new(900.0, 560.0));
    let target = organ(&h, "precentral_l");
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![vbrain_ui::viewer::Action::Select(Some(target))]);
    h.get_by_label("View").click();
    h.run_steps(2);
    assert!(egui::Popup::is_any_open(&h.ctx), "the View menu did not open");
    h.key_press_modifiers(Modifiers::NONE, Key::Escape);
    h.run_steps(2);
    assert!(!egui::Popup::is_any_open(&h.ctx), "Esc left the menu open");
    assert_eq!(h.state().selected(), Some(target), "the first Esc deselected");
    h.key_press_modifiers(Modifiers::NONE, Key::Escape);
    h.run_steps(2);
    assert_eq!(h.state().selected(), None, "the second Esc did not deselect");
}

/// "Show NAME"'s box: (ticked, enabled).
fn show_box(h: &egui_kittest::Harness<'static, vbrain_ui::App>, name: &str) -> (bool, bool) {
    use egui_kittest::kittest::NodeT;
    let label = format!("Show {name}");
    let node = h.get_by_label(&label);
    let node = node.accesskit_node();
    (format!("{:?}", node.toggled()) == "Some(True)", !node.is_disabled())
}

#[test]
fn the_quiz_picks_its_group_from_a_list_and_the_tree_shows_what_it_shows() {
    use vbrain::edit::{Edit, Organs};
    use vbrain_ui::viewer::action::{Action, Window};
    let mut h = harness_of(egui::Vec2::new(1100.0, 700.0));
    let putamen = organ(&h, "putamen_l");
    let ctx = h.ctx.clone();
    let hide = Edit::Visible { organs: Organs::One(putamen), visible: false };
    h.state_mut().perform(&ctx, vec![Action::Edit(hide), Action::Show(Window::Quiz)]);
    h.run_steps(2);
    assert_eq!(show_box(&h, "Left putamen"), (false, true));
    h.get_by_label("Quiz group").click();
    h.run_steps(2);
    // The tree has a "Basal ganglia" row too; the list, drawn above it, comes last.
    h.get_all_by_label("Basal ganglia").last().unwrap().click();
    h.run_steps(2);
    assert_eq!(h.state().quiz().setup.group, "Basal ganglia");
    h.get_by_label("Start quiz").click_accesskit();
    h.run_steps(3);
    assert!(h.state().quiz().answering(), "the quiz did not start");
    // The quiz shows the basal ganglia, the putamen the user hid among them: its box says so,
    // and the tree takes no edits until the quiz ends.
    assert!(h.state().scene().unwrap().shown().organs[putamen].visible);
    assert_eq!(show_box(&h, "Left putamen"), (true, false));
}

#[test]
fn double_click_selects_the_faded_organ_in_front_and_a_click_passes_through() {
    use super::viewer::{click, point_on};
    use vbrain::camera::View;
    use vbrain::edit::{Edit, Organs};
    use vbrain_ui::viewer::action::Action;
    // Frames a sixtieth of a second apart, so that two clicks a frame apart are a double-click.
    let mut h = egui_kittest::Harness::builder()
        .with_size(egui::Vec2::new(900.0, 560.0))
        .with_step_dt(1.0 / 60.0)
        .wgpu()
        .build_eframe(|cc| {
            let path = Some(super::viewer::brain());
            vbrain_ui::App::new(
                cc,
                vbrain_ui::AppOptions { path, recovery: None, quiz_history: None, data: Default::default() },
            )
        });
    super::viewer::wait_for_set(&mut h);
    let broca = organ(&h, "parsopercularis_l");
    let ctx = h.ctx.clone();
    // Something selected first, so the inspector's dock is open and the view keeps its place.
    h.state_mut().perform(&ctx, vec![Action::View(View::Left), Action::Select(Some(broca))]);
    h.run_steps(3);
    let at = point_on(&h, broca);
    let fade = Edit::Opacity { organs: Organs::One(broca), opacity: 0.3 };
    h.state_mut().perform(&ctx, vec![Action::Edit(fade)]);
    h.run_steps(3);
    click(&h, at);
    h.run_steps(30);
    let behind = h.state().selected();
    assert!(behind.is_some() && behind != Some(broca), "a click did not pass through the faded organ: {behind:?}");
    // Two clicks a frame apart: a double-click (the single click above is half a second before).
    click(&h, at);
    h.run_steps(1);
    click(&h, at);
    h.run_steps(2);
    assert_eq!(h.state().selected(), Some(broca), "double-click did not select the faded organ in front");
}

#[test]
fn the_web_page_of_an_open_lesson_has_its_steps_and_quiz() {
    use vbrain_ui::viewer::action::{Action, ModelKind};
    let mut h = harness_of(egui::Vec2::new(900.0, 560.0));
    let file = super::viewer::brain().join("lessons/ventricles.vblesson");
    let lesson = vbrain::lesson::Lesson::load(&file).unwrap();
    let ctx = h.ctx.clone();
    h.state_mut().perform(&ctx, vec![Action::Lesson(LessonAction::Open(file))]);
    h.run_steps(4);
    assert!(h.state().lesson().is_open());
    let dir = tempfile::tempdir().unwrap();
    let (page, view) = (dir.path().join("lesson-page"), dir.path().join("view-page"));
    for (folder, lesson) in [(&page, true), (&view, false)] {
        let export = Action::ExportModel { kind: ModelKind::Web, path: folder.display().to_string(), lesson };
        h.state_mut().perform(&ctx, vec![export]);
        h.run_steps(1);
    }
    let html = std::fs::read_to_string(page.join("index.html")).unwrap();
    assert!(html.contains("\"lesson\":true"), "the page is not a lesson's");
    for step in &lesson.steps {
        assert!(html.contains(&serde_json::to_string(&step.title).unwrap()), "step {:?} missing", step.title);
    }
    assert!(html.contains("\"passMark\":70"), "the lesson's page asks its quiz");
    let html = std::fs::read_to_string(view.join("index.html")).unwrap();
    assert!(html.contains("\"lesson\":false"), "this view's page is a lesson's");
    // The lesson's quiz as a SCORM package: a zip with the manifest first.
    let zip = dir.path().join("quiz.zip");
    let export = Action::ExportModel { kind: ModelKind::Scorm, path: zip.display().to_string(), lesson: true };
    h.state_mut().perform(&ctx, vec![export]);
    h.run_steps(1);
    let bytes = std::fs::read(&zip).expect("the package is written");
    assert!(bytes.starts_with(b"PK") && bytes[30..45] == *b"imsmanifest.xml", "a zip, its manifest first");
}

#[test]
fn enter_in_the_save_lesson_as_field_saves_at_a_laptops_size() {
    let mut h = harness_of(egui::Vec2::new(1280.0, 800.0));
    h.get_by_label("Lessons").click();
    h.run_steps(2);
    h.get_by_label("New lesson").click();
    h.run_steps(2);
    h.get_by_label("Save lesson as...").click();
    h.run_steps(2);
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("mine.vblesson");
    h.get_by_label("Lesson file").focus();
    h.run_steps(1);
    h.get_by_label("Lesson file").type_text(&file.display().to_string());
    h.run_steps(1);
    h.key_press(Key::Enter);
    h.run_steps(3);
    assert!(file.is_file(), "Enter did not save the lesson");
}

#[test]
fn every_panel_open_at_a_laptops_size_leaves_half_the_window_to_the_view() {
    use egui_kittest::kittest::NodeT;
    use vbrain_ui::viewer::action::{Action, Window};
    let (w, h_px) = (1280.0, 800.0);
    let mut h = harness_of(egui::Vec2::new(w, h_px));
    let file = super::viewer::brain().join("lessons/cortex.vblesson");
    let ctx = h.ctx.clone();
    let gyrus = organ(&h, "precentral_l");
    let open = vec![
        Action::Lesson(LessonAction::Open(file)),
        Action::Select(Some(gyrus)),
        Action::Show(Window::Quiz),
        Action::Show(Window::Sections),
    ];
    h.state_mut().perform(&ctx, open);
    h.run_steps(4);
    let view = h.state().viewport().rect();
    assert!(view.width() >= w / 2.0, "the 3-D view is {} points wide of {w}", view.width());
    // Each tab in front in turn: its main buttons lie inside the window, right of the 3-D view.
    let tabs = [
        ("Inspector", vec!["Reset transform", "Isolate", "Frame"]),
        ("Lesson", vec!["< Previous", "Next >", "Save lesson as..."]),
        ("Quiz", vec!["Start quiz", "Close"]),
        ("Sections", vec!["Align to view", "Close Sections tab"]),
    ];
    for (tab, buttons) in tabs {
        h.get_by_label(&format!("{tab} tab")).click();
        h.run_steps(2);
        if tab == "Lesson" {
            h.get_by_label("Edit lesson").click();
            h.run_steps(2);
        }
        for label in buttons.iter().chain(["Collapse panel"].iter()) {
            let node = h.get_by_label(label);
            let b = node.accesskit_node().bounding_box().unwrap_or_else(|| panic!("{tab}: {label} has no bounds"));
            let inside = b.x0 >= 0.0 && b.y0 >= 0.0 && b.x1 <= w as f64 && b.y1 <= h_px as f64;
            assert!(inside, "{tab}: {label} at {b:?} is outside the window");
            assert!(b.x0 >= view.max.x as f64, "{tab}: {label} at {b:?} lies over the 3-D view ({view:?})");
        }
    }
}

/// The box of a picture's pixels that are not its background (the top-left pixel's colour).
fn figure_box(img: &image::RgbaImage) -> [u32; 4] {
    let bg = *img.get_pixel(0, 0);
    let differs = |p: &image::Rgba<u8>| (0..3).map(|k| p[k].abs_diff(bg[k]) as u32).sum::<u32>() > 30;
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for (x, y, p) in img.enumerate_pixels() {
        if differs(p) {
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
    }
    [x0, y0, x1, y1]
}

#[test]
fn worksheet_pictures_frame_the_whole_brain_centred() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("ws");
    let o = super::cli::vbrain(&[
        "quiz",
        &super::cli::brain(),
        "--out",
        out.to_str().unwrap(),
        "--questions",
        "2",
        "--mode",
        "name",
        "--size",
        "400x300",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(out.join("q01.png")).unwrap().to_rgba8();
    // The brain alone: the label plate sits beside it, so measure rows of the brain's height.
    let [x0, y0, x1, y1] = figure_box(&img);
    assert!(y0 >= 12 && y1 <= 300 - 12, "the brain touches the top or bottom: {y0}..{y1}");
    assert!(x0 >= 4 && x1 <= 400 - 4, "cut at a side: {x0}..{x1}");
    let middle = (y0 + y1) as f32 / 2.0;
    assert!((middle - 150.0).abs() < 30.0, "off-centre vertically: {y0}..{y1}");
    assert!((y1 - y0) as f32 > 300.0 * 0.5, "a small brain: {y0}..{y1}");
}

#[test]
fn lesson_pictures_take_labels_and_a_caption() {
    let dir = tempfile::tempdir().unwrap();
    let (plain, captioned) = (dir.path().join("plain"), dir.path().join("captioned"));
    let render = |out: &std::path::Path, extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["lesson", "render", "", "--out", out.to_str().unwrap(), "--size", "480x360", "--json"];
        let lesson = super::viewer::brain().join("lessons/cortex.vblesson");
        let lesson = lesson.display().to_string();
        args[2] = &lesson;
        args.extend(extra);
        let o = super::cli::vbrain(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice(&o.stdout).unwrap()
    };
    let unlabelled = render(&plain, &[]);
    let labelled = render(&captioned, &["--caption", "--labels", "all"]);
    let a = image::open(plain.join("01.png")).unwrap().to_rgba8();
    let b = image::open(captioned.join("01.png")).unwrap().to_rgba8();
    assert_eq!(b.dimensions(), (480, 360), "the caption's band is within --size");
    // The band: light text on a dark ground below the figure, where the plain picture has none.
    let light = |img: &image::RgbaImage, rows: std::ops::Range<u32>| {
        rows.flat_map(|y| (0..img.width()).map(move |x| (x, y))).filter(|&(x, y)| img.get_pixel(x, y)[0] > 150).count()
    };
    assert!(light(&b, 260..360) > 200, "no caption text in the band: {}", light(&b, 260..360));
    assert_eq!(light(&a, 340..360), 0, "the plain picture has text at its foot");
    // Labels: the shipped step 1 has none; with --labels all every step has some.
    assert_eq!(unlabelled["labels"][0], 0, "{unlabelled}");
    let counts = labelled["labels"].as_array().unwrap();
    assert!(counts.len() == 7 && counts.iter().all(|n| n.as_u64() > Some(0)), "{labelled}");
}

/// While a drag orbits the brain and frames come slowly (a software GPU), moving frames are drawn
/// smaller; once the drag ends, the view is drawn at full size again.
#[test]
fn slow_moving_frames_are_drawn_smaller_and_still_ones_in_full() {
    let mut h = harness_of(egui::Vec2::new(1280.0, 800.0));
    let centre = h.state().viewport().rect().center();
    let press = |h: &egui_kittest::Harness<'static, vbrain_ui::viewer::App>, at: egui::Pos2, pressed| {
        h.event(egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        })
    };
    h.event(egui::Event::PointerMoved(centre));
    press(&h, centre, true);
    h.step();
    let (mut smallest, mut slowest): (f32, _) = (1.0, std::time::Duration::ZERO);
    for k in 1..=12 {
        let started = std::time::Instant::now();
        h.event(egui::Event::PointerMoved(centre + egui::vec2(8.0 * k as f32, 0.0)));
        h.step();
        // The first moving frame has no frame before it to be timed against.
        if k > 1 {
            slowest = slowest.max(started.elapsed());
        }
        smallest = smallest.min(h.state().viewport().scale());
    }
    press(&h, centre + egui::vec2(96.0, 0.0), false);
    h.run_steps(4);
    let budget = vbrain_ui::viewer::viewport::motion::SCALE_BUDGET;
    assert!(slowest <= budget || smallest < 1.0, "moving frames took up to {slowest:?}, yet all were full size");
    assert_eq!(h.state().viewport().scale(), 1.0, "the still view is drawn at full size");
    assert_eq!(h.state().viewport().level(), 0, "and with the organs' full meshes");
}
