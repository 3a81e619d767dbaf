//! The menu bar: File, Edit (undo, redo), View (camera, colouring, culling, transparency,
//! panels, background), Organs, Lessons and Help, with the running job's progress at the end.
//!
//! - One function per menu; each reads the scene and pushes [`Action`]s.
//! - The viewer's settings (culling, transparency, panels, background) are edited in place: they
//!   are preferences, not part of the scene.

use super::action::{Action, ModelKind, Window};
use super::scene::Scene;
use super::settings::Settings;
use super::shortcuts::{self, Command};
use super::widgets::accessible;
use crate::viewer::action::{DocumentAction, LessonAction};
use eframe::egui;
use vbrain::camera::View;
use vbrain::cull::{CullMode, CullSettings, Selection};
use vbrain::edit::Edit;
use vbrain::layout::ColourBy;
use vbrain::transparency::{TransparencyMode, TransparencySettings, SUBSAMPLE_CHOICES};

/// A job in the background: title, progress (if known) and message.
pub struct Job {
    pub title: String,
    pub fraction: Option<f32>,
    pub message: String,
    /// It can be stopped (an export): a Cancel button beside its progress.
    pub cancellable: bool,
}

/// What the menus read besides the settings they edit.
pub struct MenuState<'a> {
    pub scene: Option<&'a Scene>,
    /// The set has pre-computed occluders.
    pub has_database: bool,
    pub fly: bool,
    pub job: Option<Job>,
}

pub fn menu_bar(ui: &mut egui::Ui, state: &MenuState, settings: &mut Settings) -> Vec<Action> {
    let mut out = Vec::new();
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| file_menu(ui, state.scene, &settings.recent, &mut out));
        ui.menu_button("Edit", |ui| edit_menu(ui, state.scene, &mut out));
        ui.menu_button("View", |ui| view_menu(ui, state, settings, &mut out));
        ui.menu_button("Organs", |ui| organs_menu(ui, state.scene, settings, &mut out));
        ui.menu_button("Lessons", |ui| lessons_menu(ui, state.scene, &mut out));
        ui.menu_button("Help", |ui| help_menu(ui, &mut out));
        if let Some(job) = &state.job {
            if progress(ui, job) {
                out.push(Action::CancelJob);
            }
        }
    });
    out
}

/// The controls, and About.
fn help_menu(ui: &mut egui::Ui, out: &mut Vec<Action>) {
    if ui.button("About vbrain...").clicked() {
        out.push(Action::Show(Window::About));
    }
    ui.separator();
    shortcuts::help(ui);
}

/// Undo and Redo, named after what they undo and redo.
fn edit_menu(ui: &mut egui::Ui, scene: Option<&Scene>, out: &mut Vec<Action>) {
    let history = scene.map(Scene::history);
    let undo = history.and_then(|h| h.undo_label()).map_or("Undo".to_string(), |l| format!("Undo {l}"));
    let button = egui::Button::new(undo).shortcut_text(shortcuts::text(ui.ctx(), Command::Undo));
    let r = ui.add_enabled(history.is_some_and(|h| h.undo_label().is_some()), button);
    if r.clicked() {
        out.push(Action::Undo);
    }
    let redo = history.and_then(|h| h.redo_label()).map_or("Redo".to_string(), |l| format!("Redo {l}"));
    let button = egui::Button::new(redo).shortcut_text(shortcuts::text(ui.ctx(), Command::Redo));
    let r = ui.add_enabled(history.is_some_and(|h| h.redo_label().is_some()), button);
    if r.clicked() {
        out.push(Action::Redo);
    }
}

fn file_menu(ui: &mut egui::Ui, scene: Option<&Scene>, recent: &[std::path::PathBuf], out: &mut Vec<Action>) {
    let open = egui::Button::new("Open organ set or scene...").shortcut_text(shortcuts::text(ui.ctx(), Command::Open));
    if ui.add(open).clicked() {
        out.push(Action::Show(Window::OpenSet));
    }
    if ui.button("Open mesh files...").clicked() {
        out.push(Action::Show(Window::OpenMeshes));
    }
    if ui.button("Import label volume...").clicked() {
        out.push(Action::Show(Window::Import));
    }
    let save = egui::Button::new("Save scene").shortcut_text(shortcuts::text(ui.ctx(), Command::Save));
    if ui.add_enabled(scene.is_some(), save).clicked() {
        out.push(Action::Document(DocumentAction::Save { as_new: false }));
    }
    let save_as = egui::Button::new("Save scene as...").shortcut_text(shortcuts::text(ui.ctx(), Command::SaveAs));
    if ui.add_enabled(scene.is_some(), save_as).clicked() {
        out.push(Action::Document(DocumentAction::Save { as_new: true }));
    }
    ui.separator();
    ui.menu_button("Recent sets and scenes", |ui| {
        if recent.is_empty() {
            ui.label("none yet");
        }
        for p in recent {
            if ui.button(p.display().to_string()).clicked() {
                out.push(Action::Open(vec![p.clone()]));
            }
        }
    });
    ui.separator();
    let export = egui::Button::new("Export screenshot...").shortcut_text(shortcuts::text(ui.ctx(), Command::Export));
    if ui.add_enabled(scene.is_some(), export).clicked() {
        out.push(Action::Show(Window::Export));
    }
    let models = [
        (
            ModelKind::Gltf,
            "Export glTF model...",
            "The organs shown, as a 3-D model for Blender, slides or web viewers",
        ),
        (ModelKind::Web, "Export web page...", "The organs shown, as a web page students open in any browser"),
        (ModelKind::Anki, "Export Anki deck...", "Flashcards of the structures shown, to review in Anki"),
        (
            ModelKind::Scorm,
            "Export SCORM package...",
            "The open lesson's page and quiz, as a graded activity for a learning platform",
        ),
        (ModelKind::Video, "Export video...", "The view turned around, or the open lesson played, for slides"),
        (ModelKind::Pdf, "Export PDF handout...", "The view with its labels, or the open lesson's steps, to print"),
    ];
    for (kind, label, hover) in models {
        if ui.add_enabled(scene.is_some(), egui::Button::new(label)).on_hover_text(hover).clicked() {
            out.push(Action::Show(Window::ExportModel(kind)));
        }
    }
    ui.separator();
    if ui.button("Quit").clicked() {
        out.push(Action::Quit);
    }
}

fn view_menu(ui: &mut egui::Ui, state: &MenuState, settings: &mut Settings, out: &mut Vec<Action>) {
    for (i, view) in View::ALL.into_iter().enumerate() {
        let label = format!("{}{}", view.name()[..1].to_uppercase(), &view.name()[1..]);
        let key = shortcuts::key_text(ui.ctx(), Command::Views, i);
        if ui.add(egui::Button::new(label).shortcut_text(key)).clicked() {
            out.push(Action::View(view));
        }
    }
    ui.separator();
    if ui
        .add(egui::Button::new("Reset camera").shortcut_text(shortcuts::text(ui.ctx(), Command::ResetCamera)))
        .clicked()
    {
        out.push(Action::ResetCamera);
    }
    let mut fly = state.fly;
    let label = format!("Walk-through camera ({})", shortcuts::text(ui.ctx(), Command::ToggleFly));
    if ui.checkbox(&mut fly, label).changed() {
        out.push(Action::ToggleFly);
    }
    if ui.button("Sections...").on_hover_text("Cut the set along the axial, coronal and sagittal planes").clicked() {
        out.push(Action::Show(Window::Sections));
    }
    ui.menu_button("Layout", |ui| {
        for layout in super::settings::ViewLayout::ALL {
            ui.radio_value(&mut settings.view_layout, layout, layout.name());
        }
        ui.separator();
        ui.checkbox(&mut settings.neurological, "Neurological display (right on the right)").on_hover_text(
            "Slices show the patient's right on the left (radiological, as on the ward) unless this is on",
        );
    })
    .response
    .on_hover_text("The 3-D view, axial, coronal and sagittal slices through one point, or both");
    ui.menu_button("Labels", |ui| {
        for mode in super::settings::LabelMode::ALL {
            ui.radio_value(&mut settings.labels, mode, mode.name());
        }
    });
    if let Some(scene) = state.scene {
        ui.menu_button("Colour by", |ui| colour_by_menu(ui, scene, out))
            .response
            .on_hover_text("Each organ its own colour, its lobe's, or the artery that supplies each point");
    }
    ui.separator();
    let has_db = state.has_database;
    ui.menu_button("Culling of hidden tissue", |ui| culling_menu(ui, has_db, settings));
    ui.menu_button("Transparency of faded organs", |ui| transparency_menu(ui, &mut settings.transparency));
    ui.separator();
    ui.checkbox(&mut settings.show_inspector, "Inspector");
    ui.checkbox(&mut settings.show_stats, "Statistics (fps, culling and mask overlay)");
    ui.horizontal(|ui| {
        ui.label("Background");
        let r = ui.color_edit_button_rgb(&mut settings.background);
        accessible(&r, "Background colour");
    });
}

/// Organ, lobe or arterial territory (where the set has territories), with a legend in the view.
fn colour_by_menu(ui: &mut egui::Ui, scene: &Scene, out: &mut Vec<Action>) {
    let now = scene.layout().colour_by;
    for by in ColourBy::ALL {
        let has = by != ColourBy::Territory || scene.set().territories.is_some();
        let r = ui.add_enabled(has, egui::RadioButton::new(now == by, by.label()));
        let r = if has { r } else { r.on_disabled_hover_text("This organ set has no arterial territories") };
        if r.clicked() && now != by {
            out.push(Action::Edit(Edit::ColourBy(by)));
        }
    }
}

/// Culling mode, occluder selection, raster, budgets, the approximate test and the debug view.
fn culling_menu(ui: &mut egui::Ui, has_db: bool, settings: &mut Settings) {
    let c = &mut settings.cull;
    for mode in CullMode::ALL {
        ui.radio_value(&mut c.mode, mode, mode.name());
    }
    ui.separator();
    ui.label("Occluders");
    let choices = [
        (Selection::Auto, "automatic: pre-computed while nothing moved"),
        (Selection::ProjectedSize, "projected size (every frame)"),
        (Selection::Mos, "pre-computed minimum occluder sets"),
    ];
    for (selection, label) in choices {
        let r = ui.radio_value(&mut c.selection, selection, label);
        accessible(&r, format!("Occluders: {}", selection.name()));
    }
    if !has_db {
        ui.weak("This set has no occluder database (vbrain occluders PATH).");
    }
    ui.separator();
    let r = ui.add(egui::Slider::new(&mut c.width, 32..=512).text("culling raster (pixels)"));
    accessible(&r, "Culling raster size");
    c.height = c.width;
    let r = ui
        .add(egui::Slider::new(&mut c.occluder_triangles, 128..=131_072).logarithmic(true).text("occluder triangles"));
    accessible(&r, "Occluder triangle budget");
    let r = ui.add(egui::Slider::new(&mut c.adaptive_ratio, 0.0..=1.0).text("adaptive stop below coverage"));
    accessible(&r, "Adaptive stop ratio");
    let mut approximate = c.hole_tolerance.is_some();
    if ui.checkbox(&mut approximate, "approximate overlap test (not exact)").changed() {
        c.hole_tolerance = approximate.then_some(0.05);
    }
    if let Some(t) = &mut c.hole_tolerance {
        ui.add(egui::Slider::new(t, 0.0..=0.5).text("hole tolerance"));
    }
    if ui.button("Defaults").clicked() {
        *c = CullSettings::default();
    }
    ui.separator();
    ui.checkbox(&mut settings.cull_debug, "Debug view: culled triangles in colour");
}

/// Transparency mode, the screen-door masks' sub-samples, region size and K, and the k-buffer's k.
fn transparency_menu(ui: &mut egui::Ui, t: &mut TransparencySettings) {
    for mode in TransparencyMode::ALL {
        ui.radio_value(&mut t.mode, mode, mode.name());
    }
    ui.separator();
    ui.label("Screen-door masks");
    let moving = "At most: fewer while moving frames take over a tenth of a second, and below one pass \
                  (4), one weighted blended pass";
    for (label, value, tip) in [
        ("sub-samples, still", &mut t.subsamples, "What a still image converges to"),
        ("sub-samples, moving", &mut t.interactive_subsamples, moving),
    ] {
        egui::ComboBox::from_label(label)
            .selected_text(value.to_string())
            .show_ui(ui, |ui| {
                for n in SUBSAMPLE_CHOICES {
                    ui.selectable_value(value, n, n.to_string());
                }
            })
            .response
            .on_hover_text(tip);
    }
    let r = ui.add(egui::Slider::new(&mut t.region_px, vbrain::transparency::REGION_PX).text("region (pixels)"));
    accessible(&r, "Mask region size");
    let r = ui
        .add(egui::Slider::new(&mut t.k, vbrain::transparency::K_RANGE).text("K nearest organs compensated"))
        .on_hover_text("At most this many; masks of n sub-samples follow no more than log2(n) - 1 (5 for 64)");
    accessible(&r, "Neighbourhood error compensation K");
    ui.separator();
    let r = ui
        .add(egui::Slider::new(&mut t.kbuffer, vbrain::transparency::KBUFFER_K).text("k-buffer fragments"))
        .on_hover_text("Fragments the k-buffer sorts exactly per pixel; farther ones are blended in rough order");
    accessible(&r, "k-buffer fragments per pixel");
    if ui.button("Defaults").clicked() {
        *t = TransparencySettings::default();
    }
}

/// The lessons in the `lessons` folder beside the open set.
fn lessons_menu(ui: &mut egui::Ui, scene: Option<&Scene>, out: &mut Vec<Action>) {
    let lessons = match scene.map(Scene::source) {
        Some([set]) => vbrain::data_dir::lesson_files(set),
        _ => Vec::new(),
    };
    let new = ui.add_enabled(scene.is_some(), egui::Button::new("New lesson"));
    if new.on_hover_text("A lesson whose first step is the current view; add steps in the Lesson panel").clicked() {
        out.push(Action::Lesson(LessonAction::New));
    }
    let quiz = ui.add_enabled(scene.is_some(), egui::Button::new("Quiz yourself..."));
    if quiz.on_hover_text("Locate and name structures, scored, with a review").clicked() {
        out.push(Action::Show(Window::Quiz));
    }
    ui.separator();
    if lessons.is_empty() {
        ui.label("This set has no lessons (a lessons folder of .vblesson files beside it).");
    }
    for path in lessons {
        let title = vbrain::lesson::Lesson::load(&path).map_or_else(|e| e.to_string(), |l| l.title);
        if ui.button(title).clicked() {
            out.push(Action::Lesson(LessonAction::Open(path)));
        }
    }
}

fn organs_menu(ui: &mut egui::Ui, scene: Option<&Scene>, settings: &mut Settings, out: &mut Vec<Action>) {
    if ui.add_enabled(scene.is_some(), egui::Button::new("Show all")).clicked() {
        out.push(Action::Edit(vbrain::edit::Edit::show_all()));
    }
    let reset = egui::Button::new("Reset organ layout").shortcut_text(shortcuts::text(ui.ctx(), Command::ResetLayout));
    if ui.add_enabled(scene.is_some(), reset).clicked() {
        if let Some(s) = scene {
            out.push(Action::Edit(s.reset_layout()));
        }
    }
    ui.add(egui::Slider::new(&mut settings.pick_min_opacity, 0.0..=1.0).text("click through below opacity"));
}

/// The running job: its title ("loading ...", "writing ...") with a progress bar, or a spinner
/// before its total is known; and Cancel where it can be stopped. True when Cancel was clicked.
fn progress(ui: &mut egui::Ui, job: &Job) -> bool {
    ui.separator();
    ui.label(&job.title);
    match job.fraction {
        Some(f) => {
            ui.add(egui::ProgressBar::new(f).desired_width(160.0).text(job.message.as_str()));
        }
        None => {
            ui.spinner();
        }
    }
    job.cancellable && ui.button("Cancel").on_hover_text("Stop the export; no file is left").clicked()
}
