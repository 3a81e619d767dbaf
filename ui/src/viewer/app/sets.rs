//! The app's organ sets: opening one (a set, a scene or a lesson by its file, or mesh files), the
//! import job's result, and installing a loaded set as the scene.
//!
//! - A set is opened in a background job.
//! - A child module of the app, so it reaches its state.

use super::App;
use crate::viewer::action::Action;
use crate::viewer::document;
use crate::viewer::jobs::Job;
use crate::viewer::scene::Scene;
use eframe::egui;
use std::path::PathBuf;
use vbrain::cull::database::Database;
use vbrain::organ_set::{self, Loaded};
use vbrain::render::Renderer;

impl App {
    /// Loads a set (one folder or file) or several mesh files, off the UI thread.
    pub fn open(&mut self, ctx: &egui::Context, paths: Vec<PathBuf>) {
        if let [one] = paths.as_slice() {
            if document::is_scene(one) {
                return self.open_scene(ctx, one);
            }
            if one.extension().is_some_and(|e| e == vbrain::lesson::EXTENSION) {
                return self.open_lesson(ctx, one);
            }
        }
        self.document.pending = None;
        let title = match paths.as_slice() {
            [one] => one.display().to_string(),
            many => format!("{} files", many.len()),
        };
        self.loading = Some(Job::spawn(format!("loading {title}"), ctx, move |progress| {
            progress.set(0, 1, "reading meshes");
            let mut loaded = match paths.as_slice() {
                [one] => organ_set::open(one),
                many => organ_set::open_files(many, "Mesh files"),
            }?;
            let database = match paths.as_slice() {
                [one] => Database::load_for(one, &loaded.set).unwrap_or_else(|e| {
                    loaded.warnings.push(format!("{e}; occluders by projected size only"));
                    None
                }),
                _ => None,
            };
            progress.set(1, 1, "uploading");
            Ok((loaded, database, paths))
        }));
    }

    pub(super) fn poll_jobs(&mut self, ctx: &egui::Context) {
        if let Some(result) = self.exporting.as_ref().and_then(|(_, j)| j.poll()) {
            if let Some((kind, _)) = self.exporting.take() {
                self.exported(kind, result);
            }
        }
        if let Some(result) = self.importing.as_ref().and_then(|j| j.poll()) {
            self.importing = None;
            match result {
                Ok(dir) => {
                    self.notify(format!("imported into {}", dir.display()), false);
                    // Through perform, so unsaved changes are asked about first.
                    self.perform(ctx, vec![Action::Open(vec![dir])]);
                }
                Err(e) => self.notify(e.to_string(), true),
            }
        }
        let Some(result) = self.loading.as_ref().and_then(|j| j.poll()) else { return };
        self.loading = None;
        match result {
            Ok((loaded, database, paths)) => self.install(ctx, loaded, database, paths),
            Err(e) => self.notify(e.to_string(), true),
        }
    }

    /// Makes a loaded set the scene (the previous one stays if this one has no organs).
    fn install(&mut self, ctx: &egui::Context, loaded: Loaded, database: Option<Database>, paths: Vec<PathBuf>) {
        for w in loaded.warnings {
            self.notify(w, false);
        }
        for e in loaded.errors {
            self.notify(e.to_string(), true);
        }
        if loaded.set.organs.is_empty() {
            self.notify(format!("{}: no organ could be loaded", paths_label(&paths)), true);
            return;
        }
        let Some(rs) = &self.gpu else {
            self.notify("the viewer needs the wgpu renderer", true);
            return;
        };
        match Renderer::new(&rs.device, &loaded.set) {
            Ok(renderer) => {
                if let [one] = paths.as_slice() {
                    self.settings.remember(one);
                }
                let scene = Scene::new(loaded.set, paths, renderer);
                self.viewport.new_set(&scene.home(), database);
                self.selected = None;
                // Organ indices of the last set mean nothing in this one.
                let planes = self.sections.current.planes.clone();
                let (caps, faces) = (self.sections.current.caps, self.sections.current.faces);
                self.sections.set_section(&vbrain::clip::Section { planes, caps, faces, whole: Vec::new() });
                self.chosen_labels.clear();
                self.slices.new_set();
                self.document.opened_set(&scene);
                self.scene = Some(scene);
                if let Some((path, file)) = self.document.pending.take() {
                    self.apply_scene(&path, &file);
                }
                self.open_pending_lesson(ctx);
            }
            Err(e) => self.notify(e.to_string(), true),
        }
    }
}

fn paths_label(paths: &[PathBuf]) -> String {
    paths.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
}
