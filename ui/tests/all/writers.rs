//! Every writer by one rule (`ui/src/cli/outputs.rs`): a folder of the user's files is refused
//! unless `--force`, which replaces the folder whole; no writer takes its input as its output,
//! even with `--force`; the outputs of one run never lie inside one another; the experiments write
//! only into folders an experiment wrote before, and touch no other file there.

use super::cli::{brain, vbrain};
use super::hardening::refused;
use std::path::Path;

fn ok(args: &[&str]) {
    let o = vbrain(args);
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// A folder holding one file of the user's.
fn users_folder(dir: &Path) -> std::path::PathBuf {
    let mine = dir.join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("notes.txt"), "mine").unwrap();
    mine
}

#[test]
fn folder_writers_refuse_the_users_folder_and_with_force_replace_it_whole() {
    let dir = tempfile::tempdir().unwrap();
    let mine = users_folder(dir.path());
    let m = mine.to_str().unwrap();
    let cortex = Path::new(&brain()).join("lessons/cortex.vblesson");
    let cortex = cortex.to_str().unwrap();
    refused(&["lesson", "render", cortex, "--out", m, "--size", "64x48"], "already holds 1 files");
    refused(&["quiz", &brain(), "--out", m, "--questions", "1", "--size", "64x48"], "already holds 1 files");
    assert_eq!(std::fs::read_to_string(mine.join("notes.txt")).unwrap(), "mine");
    assert_eq!(std::fs::read_dir(&mine).unwrap().count(), 1, "nothing written beside the user's file");
    // With --force the folder becomes the lesson's, whole: no mix of old and new files.
    ok(&["lesson", "render", cortex, "--out", m, "--size", "64x48", "--force"]);
    assert!(mine.join("01.png").is_file() && mine.join("lesson.md").is_file());
    assert!(!mine.join("notes.txt").exists());
}

#[test]
fn no_writer_takes_its_input_as_its_output_even_with_force() {
    let dir = tempfile::tempdir().unwrap();
    let set = dir.path().join("city");
    let s = set.to_str().unwrap();
    ok(&["city", "--out", s]);
    let manifest = std::fs::read(set.join("organset.json")).unwrap();
    let above = dir.path().to_str().unwrap();
    refused(&["export", s, "--web", s, "--force"], "holds what this command reads");
    refused(&["export", s, "--web", above, "--force"], "holds what this command reads");
    refused(&["scale", s, "--out", s, "--factor", "4", "--force"], "holds what this command reads");
    refused(&["stand-ins", s, "--out", above, "--force"], "holds what this command reads");
    assert_eq!(std::fs::read(set.join("organset.json")).unwrap(), manifest, "the set is as it was");
    // A file output that is the input file itself.
    let lesson = dir.path().join("l.vblesson");
    std::fs::copy(Path::new(&brain()).join("lessons/cortex.vblesson"), &lesson).unwrap();
    let l = lesson.to_str().unwrap();
    refused(&["lesson", "pdf", l, "--out", l, "--force"], "is what this command reads");
    refused(&["anki", l, "--out", l, "--force"], "is what this command reads");
}

#[test]
fn the_outputs_of_one_run_never_lie_inside_one_another() {
    let dir = tempfile::tempdir().unwrap();
    let page = dir.path().join("page");
    let (p, model) = (page.to_str().unwrap(), page.join("m.glb"));
    refused(&["export", &brain(), "--gltf", model.to_str().unwrap(), "--web", p], "lies inside");
    let q = dir.path().join("quiz");
    let pdf = q.join("sheet.pdf");
    refused(&["quiz", &brain(), "--out", q.to_str().unwrap(), "--pdf", pdf.to_str().unwrap()], "lies inside");
    let png = dir.path().join("x.png");
    let x = png.to_str().unwrap();
    refused(&["render", &brain(), "--out", x, "--save-scene", x, "--size", "32x32"], "--save-scene another file");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing written");
}

#[test]
fn experiments_write_only_into_folders_an_experiment_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let mine = users_folder(dir.path());
    let m = mine.to_str().unwrap();
    refused(&["masks", "--trials", "10", "--out", m], "no vbrain experiment wrote");
    assert!(!mine.join("masks.csv").exists());
    // Given --force, the experiment writes its own files and leaves the user's.
    ok(&["masks", "--trials", "10", "--out", m, "--force"]);
    assert!(mine.join("masks.csv").is_file());
    assert_eq!(std::fs::read_to_string(mine.join("notes.txt")).unwrap(), "mine");
    // A new folder is the experiments' own: later runs write there again without --force.
    let fresh = dir.path().join("results");
    let f = fresh.to_str().unwrap();
    ok(&["masks", "--trials", "10", "--out", f]);
    ok(&["masks", "--trials", "10", "--seed", "2", "--out", f]);
}
