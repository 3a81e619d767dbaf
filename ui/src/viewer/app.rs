//! The viewer's app: its state, the frame, and [`App::perform`], the one place where the
//! components' [`Action`]s are carried out (scene edits through [`Scene::apply`], and the
//! commands: open, import, export, camera, selection, windows, notifications).
//!
//! - A frame: first its logic (`logic`: the gesture ended, finished jobs, the lesson's easing, the
//!   quiz's time limit), then dropped files, keyboard shortcuts, menu bar, status bar, organ panel,
//!   dock, views, windows, notifications; each component's actions are performed before the next
//!   component draws, so every component shows what the ones before it changed.
//! - The lesson, the quiz, the sections and the scene file each carry out their own nested actions
//!   (`perform_lesson`, `perform_quiz`, `perform_section`, `perform_document`, in the child
//!   modules beside their state).

use super::about::About;
use super::action::{Action, ModelKind, Window};
use super::dialogs::files;
use super::dialogs::Dialogs;
use super::dock::{self, Dock, Tab};
use super::document::{self, Document};
use super::jobs::Job;
use super::lesson_panel::LessonPanel;
use super::menus::{self, MenuState};
use super::panels::OrganPanel;
use super::quiz_panel::QuizPanel;
use super::scene::Scene;
use super::sections::Sections;
use super::settings::Settings;
use super::shortcuts::{self, Command};
use super::status::{self, Notification, Status};
use super::viewport::{self, Viewport};
use super::welcome;
use crate::viewer::action::{DocumentAction, LessonAction};
use anyhow::Result;
use eframe::egui;
use std::path::PathBuf;
use vbrain::camera::View;
use vbrain::cull::database::Database;
use vbrain::edit::{Edit, Organs};
use vbrain::organ_set::Loaded;

mod docked;
mod figure;
mod layout;
mod lessons;
mod quiz;
mod scene_files;
mod sets;

/// An export written in the background: the file, and what to tell the user.
type Export = Job<Result<(PathBuf, String)>>;

/// How the viewer starts.
#[derive(Clone, Debug, Default)]
pub struct AppOptions {
    /// What to open; `None` opens the default brain (or the last set, if the settings say so).
    pub path: Option<PathBuf>,
    /// The recovery file for unsaved changes ([`recovery_path`](super::paths::recovery_path) for the viewer; `None` writes none).
    pub recovery: Option<PathBuf>,
    /// The file of quiz results kept per set ([`quiz_history_path`](super::paths::quiz_history_path); `None` keeps none).
    pub quiz_history: Option<PathBuf>,
    /// Where the default set is looked up when no path is given ([`vbrain::data_dir`]).
    pub data: vbrain::data_dir::Environment,
}

/// A set read off the UI thread, with the paths it came from.
/// A set as loaded, with its occluder database (if one beside it fits), and where it came from.
type Opened = (Loaded, Option<Database>, Vec<PathBuf>);

pub struct App {
    /// The device eframe renders with; the scene draws with it too.
    gpu: Option<egui_wgpu::RenderState>,
    scene: Option<Scene>,
    selected: Option<usize>,
    /// The arterial territory at the point last clicked on the selected organ.
    supply: Option<u8>,
    settings: Settings,
    notifications: Vec<Notification>,
    viewport: Viewport,
    organ_panel: OrganPanel,
    dialogs: Dialogs,
    loading: Option<Job<Result<Opened>>>,
    importing: Option<Job<Result<PathBuf>>>,
    /// A deck, video or handout being written, for which export window.
    exporting: Option<(ModelKind, Export)>,
    /// The scene file: its path, whether it is saved, a scene waiting for its set.
    document: Document,
    /// The window title last set.
    title: String,
    /// The lesson being followed, if any.
    lesson: LessonPanel,
    /// The Sections window: clip planes, cut faces and organs kept whole.
    sections: Sections,
    /// The slice panes' crosshair and images (View > Layout).
    slices: super::slice_panes::SlicePanes,
    /// The organs labelled in the chosen-labels mode (indices, sorted).
    chosen_labels: Vec<usize>,
    /// The Quiz panel and the quiz under way.
    quiz: QuizPanel,
    /// Where quiz results are kept.
    quiz_history: Option<PathBuf>,
    /// A lesson whose set is loading: opened once the set is installed.
    pending_lesson: Option<PathBuf>,
    /// The user chose to close (nothing unsaved, or discarded): let the window close.
    closing: bool,
    /// No set was given and no default set was found: the places looked, shown in a welcome view.
    welcome: Option<vbrain::data_dir::NotFound>,
    /// Help > About.
    about: About,
    /// The right-hand dock: inspector, lesson, quiz and sections as tabs.
    dock: Dock,
}

impl App {
    pub fn new(cc: &eframe::CreationContext, options: AppOptions) -> App {
        let settings = Settings::load(cc.storage);
        if let Some(rs) = &cc.wgpu_render_state {
            // A GPU error the renderer's scopes do not catch is reported, not a panic.
            vbrain::render::guard::log_uncaptured(&rs.device);
        }
        let mut app = App {
            gpu: cc.wgpu_render_state.clone(),
            scene: None,
            selected: None,
            supply: None,
            notifications: Vec::new(),
            viewport: Viewport::default(),
            organ_panel: OrganPanel::default(),
            dialogs: Dialogs::default(),
            loading: None,
            importing: None,
            exporting: None,
            document: Document::default(),
            title: String::new(),
            lesson: LessonPanel::default(),
            sections: Sections::default(),
            slices: Default::default(),
            chosen_labels: Vec::new(),
            quiz: QuizPanel::default(),
            quiz_history: options.quiz_history.clone(),
            pending_lesson: None,
            closing: false,
            welcome: None,
            about: About::default(),
            dock: Dock::default(),
            settings,
        };
        app.document.offer_recovery = options.recovery.as_ref().is_some_and(|p| p.is_file());
        app.document.recovery = options.recovery;
        let path = match options.path {
            Some(p) => p,
            None => match &app.settings.last_set {
                Some(last) if app.settings.reopen_last && last.exists() => last.clone(),
                _ => match vbrain::data_dir::find_in(&options.data) {
                    Ok(set) => set,
                    Err(not_found) => {
                        app.welcome = Some(not_found);
                        return app;
                    }
                },
            },
        };
        app.open(&cc.egui_ctx, vec![path]);
        app
    }

    /// Where the viewer looked for the default set, when it found none (the welcome view shows it).
    pub fn welcome(&self) -> Option<&vbrain::data_dir::NotFound> {
        self.welcome.as_ref()
    }

    /// The loaded set, its layout and renderer.
    pub fn scene(&self) -> Option<&Scene> {
        self.scene.as_ref()
    }

    pub fn selected(&self) -> Option<usize> {
        self.selected
    }

    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    pub fn settings_mut(&mut self) -> &mut Settings {
        &mut self.settings
    }

    pub fn notifications(&self) -> &[Notification] {
        &self.notifications
    }

    pub fn viewport(&self) -> &Viewport {
        &self.viewport
    }

    /// The Sections window: planes, cut faces, organs kept whole.
    pub fn slices(&self) -> &super::slice_panes::SlicePanes {
        &self.slices
    }

    pub fn sections(&self) -> &Sections {
        &self.sections
    }

    /// The Quiz panel and the quiz under way.
    pub fn quiz(&self) -> &QuizPanel {
        &self.quiz
    }

    pub fn quiz_mut(&mut self) -> &mut QuizPanel {
        &mut self.quiz
    }

    /// The organs chosen to be labelled.
    pub fn chosen_labels(&self) -> &[usize] {
        &self.chosen_labels
    }

    pub fn dialogs(&self) -> &Dialogs {
        &self.dialogs
    }

    pub fn dialogs_mut(&mut self) -> &mut Dialogs {
        &mut self.dialogs
    }

    /// What the viewport reads (the one place it is built).
    fn viewport_input(&self) -> viewport::Input<'_> {
        viewport::Input {
            scene: self.scene.as_ref(),
            gpu: self.gpu.as_ref(),
            settings: &self.settings,
            selected: self.selected,
            highlight: self.highlight(),
            section: &self.sections.current,
            labels: self.labels(),
            handles: self.plane_handles(),
        }
    }

    /// Runs `step` on the viewport with what it reads, as it is now; returns the actions it asks for.
    fn with_viewport(&mut self, step: impl FnOnce(&mut Viewport, &viewport::Input) -> Vec<Action>) -> Vec<Action> {
        // The viewport is out of the App while the input borrows the rest of it.
        let mut viewport = std::mem::take(&mut self.viewport);
        let actions = step(&mut viewport, &self.viewport_input());
        self.viewport = viewport;
        actions
    }

    /// The organ-ID buffer of the current view (see [`Viewport::read_ids`]).
    pub fn read_ids(&self) -> Option<(Vec<u32>, [u32; 2])> {
        self.viewport.read_ids(&self.viewport_input())
    }

    /// The image the viewport shows now.
    pub fn read_image(&self) -> Option<image::RgbaImage> {
        self.viewport.read_image(self.gpu.as_ref()?)
    }

    /// The lesson panel (the lesson open and its step).
    pub fn lesson(&self) -> &LessonPanel {
        &self.lesson
    }

    pub fn document(&self) -> &Document {
        &self.document
    }

    pub fn document_mut(&mut self) -> &mut Document {
        &mut self.document
    }

    /// Is an export (a deck, video or handout) being written in the background?
    pub fn is_exporting(&self) -> bool {
        self.exporting.is_some()
    }

    pub fn is_loading(&self) -> bool {
        self.loading.is_some() || self.importing.is_some()
    }

    /// The running job: title, progress (if known) and message.
    fn job(&self) -> Option<menus::Job> {
        let (title, p, cancellable) = match (&self.loading, &self.importing, &self.exporting) {
            (Some(j), ..) => (&j.title, &j.progress, false),
            (None, Some(j), _) => (&j.title, &j.progress, false),
            (None, None, Some((_, j))) => (&j.title, &j.progress, true),
            _ => return None,
        };
        Some(menus::Job { title: title.clone(), fraction: p.fraction(), message: p.message(), cancellable })
    }

    pub fn notify(&mut self, text: impl Into<String>, error: bool) {
        self.notifications.push(Notification { text: text.into(), error });
    }

    /// Carries out the components' actions, in order.
    pub fn perform(&mut self, ctx: &egui::Context, actions: Vec<Action>) {
        let quiz =
            actions.iter().any(|a| matches!(a, Action::Quiz(_))) || (self.quiz.answering() && !actions.is_empty());
        self.perform_each(ctx, actions);
        if quiz {
            self.quiz.refresh();
            ctx.request_repaint();
        }
    }

    fn perform_each(&mut self, ctx: &egui::Context, actions: Vec<Action>) {
        for action in actions {
            log::debug!("{action:?}");
            if matches!(action, Action::Edit(_)) {
                // Widgets drawn earlier in this frame (rows above the one edited) showed the layout
                // before the edit: draw once more.
                ctx.request_repaint();
            }
            match action {
                Action::Edit(edit) => {
                    let dragging = ctx.input(|i| i.pointer.any_down());
                    if let Some(scene) = &mut self.scene {
                        scene.apply(&edit, dragging);
                    }
                }
                Action::Document(action) => self.perform_document(action),
                Action::Lesson(action) => self.perform_lesson(ctx, action),
                Action::Undo => self.undo(ctx, true),
                Action::Redo => self.undo(ctx, false),
                Action::Pick(organ) if self.quiz.answering() => self.quiz_click(organ, ctx.input(|i| i.time)),
                Action::Pick(organ) => (self.selected, self.supply) = (organ, None),
                Action::Select(organ) => (self.selected, self.supply) = (organ, None),
                Action::Supply(territory) => self.supply = territory,
                Action::Quiz(action) => self.perform_quiz(ctx, action),
                Action::Section(action) => self.perform_section(action),
                Action::Label { organ, on } => {
                    self.label_organ(organ, on);
                    self.touch_scene();
                }
                Action::Open(paths) if self.unsaved(&document::Pending::Open(Vec::new())) => {
                    self.document.confirm = Some(document::Pending::Open(paths));
                }
                Action::Open(paths) => self.open(ctx, paths),
                Action::Show(window) => self.show(window),
                Action::ImportVolume(volume) => self.dialogs.import.open_on(&volume),
                Action::Import(request) => {
                    let title = format!("importing {}", request.volume.display());
                    self.importing = Some(Job::spawn(title, ctx, move |progress| files::import(&request, progress)));
                }
                Action::Export { path, size } => self.export(&path, size),
                Action::ExportModel { kind: ModelKind::Anki, path, .. } => self.export_deck(ctx, &path),
                Action::ExportModel { kind: kind @ (ModelKind::Video | ModelKind::Pdf), path, lesson } => {
                    self.export_lecture(ctx, kind, &path, lesson)
                }
                Action::CancelJob => {
                    if let Some((_, job)) = &self.exporting {
                        job.progress.cancel();
                    }
                }
                Action::ExportModel { kind, path, lesson } => self.export_model(kind, &path, lesson),
                Action::View(view) => self.viewport.set_view(view, self.scene.as_ref().map(Scene::home)),
                Action::ResetCamera => {
                    if let Some(s) = &self.scene {
                        self.viewport.reset_camera(&s.home());
                    }
                }
                Action::ToggleFly => self.viewport.toggle_fly(),
                Action::Frame(organ) => {
                    if let Some(s) = &self.scene {
                        self.viewport.frame(&s.organ_bounds(organ));
                    }
                }
                Action::Notify { text, error } => self.notify(text, error),
                Action::NotifyOnce(text) if self.notifications.iter().any(|n| n.text == text) => {}
                Action::NotifyOnce(text) => self.notify(text, true),
                Action::Dismiss(None) => self.notifications.clear(),
                Action::Dismiss(Some(i)) => {
                    if i < self.notifications.len() {
                        self.notifications.remove(i);
                    }
                }
                Action::Quit if self.unsaved(&document::Pending::Quit) => {
                    self.document.confirm = Some(document::Pending::Quit);
                }
                Action::Quit => {
                    self.closing = true;
                    ctx.send_viewport_cmd(egui::ViewportCommand::Close);
                }
            }
        }
    }

    /// Undoes (or redoes) the last step: of the layout, or of the lesson where that came last.
    fn undo(&mut self, ctx: &egui::Context, undo: bool) {
        let Some(scene) = &mut self.scene else { return };
        let history = scene.history();
        if (undo && history.undo_is_outside()) || (!undo && history.redo_is_outside()) {
            self.lesson.undo(!undo);
        }
        let done = if undo { scene.undo() } else { scene.redo() };
        if done.is_none() {
            self.notify(if undo { "nothing to undo" } else { "nothing to redo" }, false);
        }
        ctx.request_repaint();
    }

    /// Opens a window, or brings a dock tab to the front.
    fn show(&mut self, window: Window) {
        match window {
            Window::OpenSet => self.dialogs.open_set.open = true,
            Window::About => self.about.open = true,
            Window::OpenMeshes => self.dialogs.open_meshes.open = true,
            Window::Import => self.dialogs.import.open = true,
            Window::Export => self.dialogs.export.open = true,
            Window::ExportModel(kind) => self.dialogs.model(kind).open = true,
            Window::Sections => {
                self.sections.open = true;
                self.dock.focus(Tab::Sections);
            }
            Window::Quiz => {
                self.quiz.open = true;
                self.dock.focus(Tab::Quiz);
                self.load_quiz_history();
            }
        }
    }

    /// The keyboard shortcuts pressed this frame, as actions.
    fn key_actions(&self, ctx: &egui::Context) -> Vec<Action> {
        let mut out = Vec::new();
        // Esc before an organ's shortcut in the same frame leaves that shortcut no organ.
        let mut selected = self.selected;
        let menu_open = egui::Popup::is_any_open(ctx);
        for (command, key) in shortcuts::pressed(ctx) {
            let organ = self.scene.as_ref().zip(selected);
            match command {
                Command::Views => out.extend(View::ALL.get(key).map(|&v| Action::View(v))),
                Command::ResetCamera => out.push(Action::ResetCamera),
                Command::ToggleFly => out.push(Action::ToggleFly),
                // Esc closes an open menu first (egui does); only the next one deselects.
                Command::Deselect if menu_open => {}
                Command::Deselect => {
                    selected = None;
                    out.push(Action::Select(None));
                }
                Command::Open => out.push(Action::Show(Window::OpenSet)),
                Command::Export => out.push(Action::Show(Window::Export)),
                Command::Undo => out.push(Action::Undo),
                Command::SaveAs => out.push(Action::Document(DocumentAction::Save { as_new: true })),
                Command::Save => out.push(Action::Document(DocumentAction::Save { as_new: false })),
                Command::NextStep => out.extend(self.lesson.step_by(1).map(|k| Action::Lesson(LessonAction::Step(k)))),
                Command::PreviousStep => {
                    out.extend(self.lesson.step_by(-1).map(|k| Action::Lesson(LessonAction::Step(k))))
                }
                Command::Redo | Command::RedoY => out.push(Action::Redo),
                Command::ResetLayout => out.extend(self.scene.as_ref().map(|s| Action::Edit(s.reset_layout()))),
                Command::ToggleTransparency => {
                    out.extend(organ.map(|(s, sel)| Action::Edit(s.toggle_transparency(sel))));
                }
                Command::ToggleVisible => out.extend(organ.map(|(s, sel)| Action::Edit(s.toggle_visible(sel)))),
                Command::Isolate => {
                    out.extend(organ.map(|(_, sel)| Action::Edit(Edit::Isolate { organs: Organs::One(sel) })));
                }
                Command::Frame => out.extend(organ.map(|(_, sel)| Action::Frame(sel))),
            }
        }
        out
    }

    /// The windows, each one's actions performed before the next draws.
    fn windows(&mut self, ctx: &egui::Context) {
        let actions = self.dialogs.open_set.show_set(ctx, &self.settings.recent);
        self.perform(ctx, actions);
        let actions = self.dialogs.open_meshes.show_meshes(ctx);
        self.perform(ctx, actions);
        let actions = self.dialogs.import.show(ctx, self.importing.is_some());
        self.perform(ctx, actions);
        let set_dir = self.scene.as_ref().and_then(|s| s.source().first()).filter(|p| p.is_dir()).cloned();
        self.about.show(ctx, set_dir);
        let actions = self.document.save_window.show(ctx);
        self.perform(ctx, actions);
        self.unsaved_changes(ctx);
        let title = format!("vbrain - {}", self.document.title(self.scene.as_ref()));
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
        if let Some(scene) = &self.scene {
            let viewport = self.viewport.pixel_size().unwrap_or([1280, 800]);
            let mut actions = self.dialogs.export.show(ctx, &scene.set().title, viewport, &mut self.settings.export);
            let folder = self.settings.export.folder.as_deref();
            let lesson = self.lesson.lesson.as_ref().map(|l| (l.title.as_str(), l.steps.len()));
            actions.extend(self.dialogs.gltf.show(ctx, &scene.set().title, folder, None));
            actions.extend(self.dialogs.web.show(ctx, &scene.set().title, folder, lesson));
            actions.extend(self.dialogs.anki.show(ctx, &scene.set().title, folder, None));
            let quizzed = self.lesson.lesson.as_ref().filter(|l| !l.quiz.is_empty());
            let quizzed = quizzed.map(|l| (l.title.as_str(), l.quiz.len()));
            actions.extend(self.dialogs.scorm.show(ctx, &scene.set().title, folder, quizzed));
            actions.extend(self.dialogs.video.show(ctx, &scene.set().title, folder, lesson));
            actions.extend(self.dialogs.pdf.show(ctx, &scene.set().title, folder, lesson));
            self.perform(ctx, actions);
        }
    }
}

impl eframe::App for App {
    /// The frame's logic before anything is drawn: the gesture ended, finished jobs taken in, the
    /// lesson's transition eased on, the quiz's time limit checked.
    fn logic(&mut self, ctx: &egui::Context, _frame: &mut eframe::Frame) {
        if !ctx.input(|i| i.pointer.any_down()) {
            // No drag goes on: the next edit starts a new undo step.
            if let Some(scene) = &mut self.scene {
                scene.end_gesture();
            }
        }
        self.poll_jobs(ctx);
        self.ease_lesson_step(ctx);
        self.quiz_tick(ctx);
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.perform(&ctx, files::dropped(&ctx));
        let keys = self.key_actions(&ctx);
        self.perform(&ctx, keys);
        self.bars_and_panels(ui, &ctx);
        match &self.welcome {
            Some(not_found) if self.scene.is_none() && !self.is_loading() => {
                let actions = egui::CentralPanel::default().show(ui, |ui| welcome::view(ui, not_found)).inner;
                self.perform(&ctx, actions);
            }
            _ => {
                egui::CentralPanel::no_frame().show(ui, |ui| self.views(ui, &ctx));
            }
        }
        self.windows(&ctx);
        let actions = status::notifications(&ctx, &self.notifications);
        self.perform(&ctx, actions);
        if self.is_loading() {
            ctx.request_repaint_after(std::time::Duration::from_millis(100));
        }
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        self.settings.save(storage);
    }
}
