//! Files dropped onto the viewer's window, and the import job: a label volume opens the import
//! window on it; several mesh files open together as one set; files vbrain cannot read give an
//! error notice and leave the set open; an import runs in the background, then opens the set it
//! built, or names what went wrong.

use crate::cli::two_blobs;
use crate::viewer::harness_of;
use eframe::egui;
use egui_kittest::Harness;
use std::path::{Path, PathBuf};
use vbrain_ui::viewer::action::{Action, ImportRequest};
use vbrain_ui::App;

/// A file dropped from the desktop, as the window system hands it over.
#[derive(Debug)]
struct Dropped(PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

/// Drops `paths` onto the window and draws the frame that receives them.
fn drop_files(h: &mut Harness<'static, App>, paths: &[PathBuf]) {
    let files = paths.iter().map(|p| std::sync::Arc::new(Dropped(p.clone())) as egui::DroppedFileHandle);
    h.input_mut().dropped_files.extend(files);
    h.step();
}

/// Steps `h` until `done` holds (at most 600 steps of 20 ms), then once more.
fn step_until(h: &mut Harness<'static, App>, what: &str, done: impl Fn(&App) -> bool) {
    for _ in 0..600 {
        h.step();
        if done(h.state()) {
            h.step();
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let notes: Vec<String> = h.state().notifications().iter().map(|n| n.text.clone()).collect();
    panic!("{what} did not happen; notifications: {notes:?}");
}

/// A tetrahedron 10 mm across at `x`, as an OBJ file.
fn tetrahedron(dir: &Path, name: &str, x: f32) -> PathBuf {
    let p = dir.join(name);
    let v = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, 10.0]];
    let mut text: String = v.iter().map(|[a, b, c]| format!("v {} {b} {c}\n", a + x)).collect();
    text.push_str("f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    std::fs::write(&p, text).unwrap();
    p
}

fn organ_count(app: &App) -> usize {
    app.scene().map_or(0, |s| s.set().organs.len())
}

#[test]
fn a_dropped_label_volume_opens_the_import_window_on_it() {
    let dir = tempfile::tempdir().unwrap();
    let volume = two_blobs(dir.path(), "seg.nii.gz");
    let mut h = harness_of(egui::Vec2::new(900.0, 600.0));
    assert!(!h.state().dialogs().import.open);
    drop_files(&mut h, std::slice::from_ref(&volume));
    assert!(h.state().dialogs().import.open, "the import window opens");
    assert_eq!(h.state().dialogs().import.volume(), volume.display().to_string());
    assert_eq!(organ_count(h.state()), 132, "the brain stays open until the import runs");
}

#[test]
fn dropped_mesh_files_open_as_one_set_and_unreadable_files_leave_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness_of(egui::Vec2::new(900.0, 600.0));
    // Neither sets, meshes nor volumes: a notice, and the brain stays.
    let notes = [dir.path().join("a.txt"), dir.path().join("b.txt")];
    for n in &notes {
        std::fs::write(n, "notes").unwrap();
    }
    drop_files(&mut h, &notes);
    let said = h.state().notifications().iter().any(|n| n.error && n.text.contains("neither organ sets"));
    assert!(said, "an error notice for files vbrain cannot read");
    assert_eq!(organ_count(h.state()), 132);
    // Two OBJ files (and a stray text file among them): one set of two organs.
    let meshes = [tetrahedron(dir.path(), "left.obj", 0.0), tetrahedron(dir.path(), "right.obj", 20.0)];
    drop_files(&mut h, &[meshes[0].clone(), notes[0].clone(), meshes[1].clone()]);
    step_until(&mut h, "opening the dropped meshes", |app| organ_count(app) == 2);
    let scene = h.state().scene().unwrap();
    assert_eq!(scene.source(), &meshes[..], "the set is the two meshes, the text file left out");
}

#[test]
fn an_import_runs_in_the_background_then_opens_its_set_or_names_its_error() {
    let dir = tempfile::tempdir().unwrap();
    let volume = two_blobs(dir.path(), "seg.nii.gz");
    let labels = dir.path().join("labels.csv");
    std::fs::write(&labels, "index,name\n17,Left-Hippocampus\n53,Right-Hippocampus\n").unwrap();
    let mut h = harness_of(egui::Vec2::new(900.0, 600.0));
    let ctx = h.ctx.clone();
    // A table that does not exist: the job fails, says which file, and the brain stays.
    let missing = dir.path().join("no-such-table.csv");
    let bad =
        ImportRequest { volume: volume.clone(), labels: missing.clone(), out: dir.path().join("bad"), triangles: 1500 };
    h.state_mut().perform(&ctx, vec![Action::Import(bad)]);
    assert!(h.state().is_loading(), "the import runs in the background");
    step_until(&mut h, "the failed import", |app| !app.is_loading());
    let notes: Vec<&str> = h.state().notifications().iter().filter(|n| n.error).map(|n| n.text.as_str()).collect();
    assert!(notes.iter().any(|t| t.contains("no-such-table.csv")), "the error names the missing table: {notes:?}");
    assert_eq!(organ_count(h.state()), 132);
    assert!(!dir.path().join("bad").exists(), "a failed import leaves no folder");
    // A good one: the set is written, then opened in place of the brain.
    let out = dir.path().join("hippocampi");
    let good = ImportRequest { volume, labels, out: out.clone(), triangles: 1500 };
    h.state_mut().perform(&ctx, vec![Action::Import(good)]);
    step_until(&mut h, "the import and opening its set", |app| organ_count(app) == 2);
    let scene = h.state().scene().unwrap();
    let names: Vec<&str> = scene.set().organs.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["Left-Hippocampus", "Right-Hippocampus"]);
    assert_eq!(scene.source(), &[out.clone()][..]);
    assert!(out.join("organset.json").is_file());
}
