//! vbrain as installed: the default set found through `VBRAIN_DATA` from any working directory,
//! a clear error listing the places looked when it is nowhere, lessons by name, the version and
//! commit, the generated manual pages and completions, and the viewer's welcome view.
//! (scripts/test-packages.sh tests the packages themselves with the checkout hidden.)

use super::viewer::brain;
use eframe::egui;
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use std::path::Path;
use std::process::{Command, Output};
use vbrain_ui::{App, AppOptions};

/// `vbrain ARGS` from `cwd` with only HOME and `data` as `VBRAIN_DATA` set. Without `data`, the
/// XDG data dirs are a folder that is not there either, so no default set is found anywhere (the
/// Vulkan loader finds its drivers there too: those runs draw nothing).
fn vbrain_in(cwd: &Path, data: Option<&Path>, args: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_vbrain"));
    command.env_clear().current_dir(cwd).env("HOME", cwd);
    if data.is_none() {
        command.env("XDG_DATA_DIRS", cwd.join("none"));
    }
    if let Some(runtime) = std::env::var_os("XDG_RUNTIME_DIR") {
        command.env("XDG_RUNTIME_DIR", runtime);
    }
    if let Some(data) = data {
        command.env("VBRAIN_DATA", data);
    }
    command.args(args).output().unwrap()
}

fn organs_dir() -> std::path::PathBuf {
    brain().parent().unwrap().to_path_buf()
}

#[test]
fn vbrain_data_names_the_default_set_from_any_folder() {
    let cwd = tempfile::tempdir().unwrap();
    let out = vbrain_in(cwd.path(), Some(&organs_dir()), &["info", "--json"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["organs"].as_array().unwrap().len(), 132);
    let canonical = |p: &Path| std::fs::canonicalize(p).unwrap();
    assert_eq!(canonical(Path::new(v["path"].as_str().unwrap())), canonical(&brain()));
    // The set's own folder works as well as the folder holding it.
    let out = vbrain_in(cwd.path(), Some(&brain()), &["info"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn with_no_default_set_commands_say_where_they_looked() {
    let cwd = tempfile::tempdir().unwrap();
    for args in [&["info"][..], &["render", "--out", "x.png"], &["lesson", "render", "cortex", "--out", "l"]] {
        let out = vbrain_in(cwd.path(), None, args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("no default organ set found"), "{args:?}: {err}");
        assert!(err.contains(&cwd.path().join("organs/brain").display().to_string()), "{err}");
        assert!(err.contains("VBRAIN_DATA"), "{err}");
    }
    assert!(!cwd.path().join("x.png").exists());
}

#[test]
fn lessons_are_found_by_name() {
    let cwd = tempfile::tempdir().unwrap();
    let data = organs_dir();
    let out = vbrain_in(cwd.path(), Some(&data), &["lesson", "render", "ventricles", "--out", "v", "--size", "96x64"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(cwd.path().join("v/01.png").is_file() && cwd.path().join("v/lesson.md").is_file());
    let out = vbrain_in(cwd.path(), Some(&data), &["lesson", "render", "nosuch", "--out", "n"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("nosuch") && err.contains("blood-supply, cortex, deep-nuclei, pathways, ventricles"), "{err}");
}

#[test]
fn version_names_the_commit() {
    let out = vbrain_in(&organs_dir(), None, &["--version"]);
    let text = String::from_utf8_lossy(&out.stdout);
    let rest = text.trim().strip_prefix(&format!("vbrain {} (commit ", env!("CARGO_PKG_VERSION"))).unwrap_or("");
    let commit = rest.strip_suffix(')').unwrap_or("");
    assert!(commit == "unknown" || (commit.len() >= 7 && commit.chars().all(|c| c.is_ascii_hexdigit())), "{text}");
}

#[test]
fn manual_pages_and_completions_come_from_the_options() {
    let dir = tempfile::tempdir().unwrap();
    let out = vbrain_in(dir.path(), None, &["manual", "--out", "man"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let render = std::fs::read_to_string(dir.path().join("man/vbrain-render.1")).unwrap();
    assert!(render.contains("\\-\\-clip") && render.contains("\\-\\-labels"), "{render}");
    assert!(dir.path().join("man/vbrain.1").is_file() && dir.path().join("man/vbrain-lesson-render.1").is_file());
    assert!(!dir.path().join("man/vbrain-manual.1").exists(), "the hidden command has no page");
    for (shell, needle) in [("bash", "--clip"), ("zsh", "--clip"), ("fish", "clip")] {
        let out = vbrain_in(dir.path(), None, &["completions", shell]);
        let script = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success() && script.contains(needle), "{shell}: {script}");
    }
}

#[test]
fn the_viewer_welcomes_with_the_places_it_looked() {
    let cwd = tempfile::tempdir().unwrap();
    let data = vbrain::data_dir::Environment { cwd: Some(cwd.path().to_path_buf()), ..Default::default() };
    let mut h = Harness::builder().with_size(egui::Vec2::new(1000.0, 600.0)).wgpu().build_eframe(move |cc| {
        App::new(cc, AppOptions { path: None, recovery: None, quiz_history: None, data: data.clone() })
    });
    h.run_steps(3);
    let looked = h.state().welcome().expect("no welcome view").looked.clone();
    assert!(looked.contains(&cwd.path().join("organs/brain")), "{looked:?}");
    assert!(h.query_by_label_contains("Welcome to vbrain").is_some());
    assert!(h.query_by_label_contains(&cwd.path().join("organs/brain").display().to_string()).is_some());
    h.get_by_label("Open organ set or scene...").click();
    h.run_steps(2);
    assert!(h.state().dialogs().open_set.open, "Open did not open the file window");
}
