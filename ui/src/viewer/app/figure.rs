//! The app's figure: the Sections window (clip planes, cut faces, organs kept whole) with the
//! planes' handles, the labels (which organs, the chosen list) and the exports (screenshot, glTF
//! model).
//!
//! - Changes to the section or the labels count as unsaved changes of the scene.
//! - A child module of the app, so it reaches its state.

use super::App;
use crate::viewer::action::ModelKind;
use crate::viewer::action::SectionAction;
use crate::viewer::dialogs::export;
use crate::viewer::jobs::Job;
use crate::viewer::settings::LabelMode;
use anyhow::{Context, Result};
use eframe::egui;
use std::path::{Path, PathBuf};
use vbrain::clip::Section;
use vbrain::render::FrameInput;

impl App {
    /// Carries out a section action: organs kept whole, the crosshair, a plane moved.
    pub(super) fn perform_section(&mut self, action: SectionAction) {
        match action {
            SectionAction::KeepWhole { organ, whole } => {
                self.sections.set_whole(organ, whole);
                self.touch_scene();
            }
            SectionAction::SlicePoint(point) => {
                if let Some(scene) = &mut self.scene {
                    let home = scene.home();
                    let inside = point.clamp(glam::Vec3::from(home.min), glam::Vec3::from(home.max));
                    self.slices.point = Some(inside);
                    self.sections.move_to(inside, &home);
                    scene.touch();
                }
            }
            SectionAction::MovePlane { slot, mm } => {
                if let Some(scene) = &mut self.scene {
                    self.sections.move_plane(slot, mm, &scene.home());
                    scene.touch();
                }
            }
        }
    }

    /// The planes or labels changed: the scene has unsaved changes.
    pub(super) fn touch_scene(&mut self) {
        if let Some(scene) = &mut self.scene {
            scene.touch();
        }
    }

    /// The labels the viewport and exports draw.
    pub(super) fn labels(&self) -> crate::annotate::Labels {
        if self.quiz.answering() {
            // Labels would give the answers away.
            return crate::annotate::Labels::None;
        }
        if self.quiz.run.as_ref().is_some_and(|r| r.reviewing.is_some()) {
            // The structure reviewed, named.
            return crate::annotate::Labels::Chosen(self.quiz.highlight());
        }
        self.settings.labels.labels(self.selected, &self.chosen_labels)
    }

    /// The organs outlined: the quiz's while one is open, else the lesson step's.
    pub(super) fn highlight(&self) -> &[usize] {
        if self.quiz.run.is_some() {
            &self.quiz.outlined
        } else {
            &self.lesson.highlight
        }
    }

    /// The handles of the planes, while the Sections window is open.
    pub fn plane_handles(&self) -> Vec<crate::viewer::sections::Handle> {
        match &self.scene {
            Some(scene) if self.sections.open => self.sections.handles(&scene.home()),
            _ => Vec::new(),
        }
    }

    /// Organ `organ` labelled or not: the chosen-labels mode, starting from what is labelled now.
    pub(super) fn label_organ(&mut self, organ: usize, on: bool) {
        let n = self.scene.as_ref().map_or(0, |s| s.set().organs.len());
        let mut chosen = match self.settings.labels {
            LabelMode::None => Vec::new(),
            LabelMode::Selected => self.selected.into_iter().collect(),
            LabelMode::Chosen => self.chosen_labels.clone(),
            LabelMode::All => (0..n).collect(),
        };
        chosen.retain(|&o| o != organ);
        if on {
            chosen.push(organ);
        }
        chosen.sort_unstable();
        (self.settings.labels, self.chosen_labels) = (LabelMode::Chosen, chosen);
    }

    /// The Sections tab of the dock; a change to the section is an unsaved change.
    pub(super) fn sections_tab(&mut self, ui: &mut egui::Ui) {
        let home = self.scene.as_ref().map(|s| s.home());
        let forward = self.scene.as_ref().map_or(glam::Vec3::NEG_Y, |s| {
            let c = self.viewport.camera(s);
            (c.target - c.eye).normalize_or_zero()
        });
        let scene = self.scene.as_ref();
        let name = |o: usize| scene.and_then(|s| s.set().organs.get(o)).map_or(String::new(), |x| x.name.clone());
        let has_mri = scene.is_some_and(|s| s.set().mri.is_some());
        if self.sections.show(ui, home, forward, has_mri, name) {
            self.touch_scene();
        }
    }

    /// Renders the current view at `size` into the file typed as `path`.
    pub(super) fn export(&mut self, path: &str, size: [u32; 2]) {
        let (message, saved) = match self.export_view(path, size) {
            Ok(path) => {
                self.settings.export.folder = path.parent().map(Path::to_path_buf);
                (format!("saved {} ({}x{})", path.display(), size[0], size[1]), true)
            }
            Err(e) => (format!("screenshot not saved: {e:#}"), false),
        };
        self.dialogs.export.finished(message.clone(), saved);
        self.notify(message, !saved);
    }

    /// Writes the scene as a glTF model or a web page: the organs drawn, cut by the current
    /// section; a page also has the camera, the labels, the outlines and the selection. With
    /// `lesson`, the page is the open lesson's, its steps and captions (as `vbrain export` makes it).
    /// Starts writing an Anki deck of the structures shown (and of the open lesson's quiz) into
    /// the file `typed` (`.apkg` added if missing; a new file, never one that exists), off the UI
    /// thread with progress.
    pub(super) fn export_deck(&mut self, ctx: &egui::Context, typed: &str) {
        let started = self.scene.as_ref().context("no organ set").and_then(|scene| {
            anyhow::ensure!(self.exporting.is_none(), "an export is running already");
            let path = export::file_path(typed, "apkg")?;
            anyhow::ensure!(!path.exists(), "{} exists; choose a new file name", path.display());
            let (set, layout) = (scene.set().clone(), scene.layout());
            let scope: Vec<usize> = (0..set.organs.len()).filter(|&o| layout.organs[o].is_drawn()).collect();
            anyhow::ensure!(!scope.is_empty(), "no organ is shown");
            // With a lesson open, its quiz's questions become cards too.
            let lesson = match &self.lesson.lesson {
                Some(l) if !l.quiz.is_empty() => Some((l.title.clone(), crate::anki::LessonQuestion::of(l, &set)?)),
                _ => None,
            };
            let opts = crate::anki::DeckOptions { scope, size: (768, 768), views: 2, lesson };
            let title = format!("writing {}", path.display());
            let job = Job::spawn(title, ctx, move |progress| {
                let (bytes, report) = crate::anki::build(&set, None, &opts, &mut |done, total| {
                    progress.set(done, total, &format!("{done} of {total} structures"));
                })?;
                anyhow::ensure!(!progress.is_cancelled(), "cancelled");
                crate::anki::write(&path, &bytes, false)?;
                let mut m = format!("saved {}: {} cards", path.display(), report.notes);
                if !report.unseen.is_empty() {
                    m.push_str(&format!(" (not seen from any view: {})", report.unseen.join(", ")));
                }
                Ok((path, m))
            });
            self.exporting = Some((ModelKind::Anki, job));
            Ok(())
        });
        if let Err(e) = started {
            let message = format!("not saved: {e:#}");
            self.dialogs.model(ModelKind::Anki).finished(message.clone(), false);
            self.notify(message, true);
        }
    }

    /// Starts writing a video or a PDF handout into the file `typed` (`.mp4` or `.pdf` added if
    /// missing; a new file): of the current view, or with `lesson` of the open lesson, off the UI
    /// thread with progress and Cancel.
    pub(super) fn export_lecture(&mut self, ctx: &egui::Context, kind: ModelKind, typed: &str, lesson: bool) {
        let started = self.scene.as_ref().context("no organ set").and_then(|scene| {
            anyhow::ensure!(self.exporting.is_none(), "an export is running already");
            let video = kind == ModelKind::Video;
            let path = export::file_path(typed, if video { "mp4" } else { "pdf" })?;
            anyhow::ensure!(!path.exists(), "{} exists; choose a new file name", path.display());
            if video {
                crate::video::Format::of(&path)?;
            }
            let set = scene.set().clone();
            let lesson = if lesson { self.lesson.lesson.clone() } else { None };
            let view = crate::lecture::View {
                navigator: self.viewport.navigator(),
                layout: scene.layout().clone(),
                highlight: self.highlight().to_vec(),
                section: self.sections.current.clone(),
                labels: self.labels(),
                selected: self.selected,
            };
            let title = format!("writing {}", path.display());
            let job = Job::spawn(title, ctx, move |progress| {
                let mut report = |done: usize, total: usize| {
                    progress.set(done, total, &format!("{done} of {total}"));
                    !progress.is_cancelled()
                };
                let message = if video {
                    crate::lecture::video(&set, lesson.as_ref(), &view, &path, &mut report)?
                } else {
                    crate::lecture::handout(&set, lesson.as_ref(), &view, &path, &mut report)?
                };
                Ok((path, message))
            });
            Ok(job)
        });
        match started {
            Ok(job) => self.exporting = Some((kind, job)),
            Err(e) => {
                let message = format!("not saved: {e:#}");
                self.dialogs.model(kind).finished(message.clone(), false);
                self.notify(message, true);
            }
        }
    }

    /// After a background export was written (or failed, or was cancelled).
    pub(super) fn exported(&mut self, kind: ModelKind, result: Result<(PathBuf, String)>) {
        let (message, saved) = match result {
            Ok((path, message)) => {
                self.settings.export.folder = path.parent().map(Path::to_path_buf);
                (message, true)
            }
            Err(e) => (format!("not saved: {e:#}"), false),
        };
        self.dialogs.model(kind).finished(message.clone(), saved);
        self.notify(message, !saved);
    }

    pub(super) fn export_model(&mut self, kind: ModelKind, typed: &str, lesson: bool) {
        let written = self.scene.as_ref().context("no organ set").and_then(|scene| {
            let (set, layout, section) = (scene.set(), scene.layout(), &self.sections.current);
            match kind {
                ModelKind::Gltf => {
                    let path = export::file_path(typed, "glb")?;
                    let glb = vbrain::gltf::glb(set, layout, section, vbrain::gltf::Encoding::Float);
                    Ok((export::write_glb(&path, &glb.bytes)?, glb.bytes.len()))
                }
                ModelKind::Web => {
                    let dir = PathBuf::from(typed.trim());
                    anyhow::ensure!(!dir.as_os_str().is_empty(), "no folder name");
                    let held = vbrain::atomic::folder_entries(&dir)?;
                    anyhow::ensure!(
                        held == 0,
                        "{} already holds {held} files or folders; choose a new folder",
                        dir.display()
                    );
                    if let (true, Some(lesson)) = (lesson, &self.lesson.lesson) {
                        let bytes = vbrain::web_page::write(&dir, &lesson_page(set, lesson)?)?;
                        return Ok((dir.join("index.html"), bytes));
                    }
                    let labels = self.labels();
                    let view = vbrain::web_page::View {
                        title: set.title.clone(),
                        caption: String::new(),
                        layout: layout.clone(),
                        camera: self.viewport.camera(scene),
                        highlight: self.highlight().to_vec(),
                        labels: (0..set.organs.len())
                            .filter(|&o| labels.wants(o) && layout.organs[o].is_drawn())
                            .collect(),
                        selection: self.selected,
                        section: Section::default(),
                    };
                    let page = vbrain::web_page::Page {
                        set,
                        title: set.title.clone(),
                        layout: layout.clone(),
                        section: section.clone(),
                        views: vec![view],
                        lesson: false,
                        quiz: None,
                    };
                    let bytes = vbrain::web_page::write(&dir, &page)?;
                    Ok((dir.join("index.html"), bytes))
                }
                ModelKind::Scorm => {
                    let lesson = self.lesson.lesson.as_ref().context("open a lesson with a quiz first")?;
                    anyhow::ensure!(!lesson.quiz.is_empty(), "the lesson \"{}\" has no quiz", lesson.title);
                    let path = export::file_path(typed, "zip")?;
                    anyhow::ensure!(!path.exists(), "{} exists; choose a new file name", path.display());
                    let bytes = vbrain::scorm::write(&path, &lesson_page(set, lesson)?)?;
                    Ok((path, bytes))
                }
                // Written off the UI thread by `export_deck` and `export_lecture`.
                ModelKind::Anki | ModelKind::Video | ModelKind::Pdf => {
                    anyhow::bail!("written with progress, not here")
                }
            }
        });
        let (message, saved) = match written {
            Ok((path, bytes)) => {
                let folder = match kind {
                    ModelKind::Web => path.parent().and_then(Path::parent),
                    _ => path.parent(),
                };
                self.settings.export.folder = folder.map(Path::to_path_buf);
                (format!("saved {} ({:.1} MB)", path.display(), bytes as f64 / 1e6), true)
            }
            Err(e) => (format!("not saved: {e:#}"), false),
        };
        self.dialogs.model(kind).finished(message.clone(), saved);
        self.notify(message, !saved);
    }

    fn export_view(&self, path: &str, size: [u32; 2]) -> Result<PathBuf> {
        let scene = self.scene.as_ref().context("no organ set")?;
        let rs = self.gpu.as_ref().context("no GPU")?;
        let camera = self.viewport.camera(scene);
        let path = export::file_path(path, "png")?;
        let frame = FrameInput {
            background: self.settings.background_linear(self.settings.export.transparent),
            transparency: self.settings.transparency,
            highlight: &self.lesson.highlight,
            selection: self.selected,
            section: &self.sections.current,
            ..FrameInput::new(scene.set(), &camera, scene.layout())
        };
        let labels = self.labels();
        let name = |o: usize| scene.set().organs.get(o).map_or(String::new(), |x| x.name.clone());
        export::export((&rs.device, &rs.queue, scene.renderer()), &frame, size, &path, &labels, &name)
    }
}

/// A lesson's web page with its quiz, as `vbrain export` writes it.
fn lesson_page<'a>(
    set: &'a vbrain::organ_set::OrganSet,
    lesson: &vbrain::lesson::Lesson,
) -> Result<vbrain::web_page::Page<'a>> {
    let mut page = vbrain::web_page::Page::lesson(set, lesson);
    page.quiz = crate::page_quiz::of_lesson(set, lesson, None)?.map(|built| built.quiz);
    Ok(page)
}
