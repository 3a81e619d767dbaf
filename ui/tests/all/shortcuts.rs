//! README.md's controls table is the viewer's: its rows are the mouse controls and then the rows
//! of the shortcut table that drives the key handling and the Help menu, in the same order, with
//! the same inputs and descriptions.

use std::path::Path;
use vbrain_ui::viewer::shortcuts::{MOUSE, SHORTCUTS};

/// The rows (input, action) of the table under "### Controls" in README.md.
fn readme_controls() -> Vec<(String, String)> {
    let readme = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../README.md")).unwrap();
    let section = readme.split("\n### Controls\n").nth(1).expect("README.md has a Controls section");
    let mut rows = section.lines().skip_while(|l| !l.starts_with('|')).take_while(|l| l.starts_with('|'));
    assert_eq!(rows.next(), Some("| input | action |"));
    assert_eq!(rows.next(), Some("|---|---|"));
    rows.map(|row| {
        let cells: Vec<&str> = row.trim_matches('|').split('|').map(str::trim).collect();
        assert_eq!(cells.len(), 2, "{row}");
        (cells[0].to_string(), cells[1].to_string())
    })
    .collect()
}

#[test]
fn readme_lists_the_mouse_controls_then_the_shortcuts() {
    let ours: Vec<(String, String)> = MOUSE
        .iter()
        .copied()
        .chain(SHORTCUTS.iter().map(|s| (s.input, s.description)))
        .map(|(input, action)| (input.to_string(), action.to_string()))
        .collect();
    let readme = readme_controls();
    for row in &readme {
        assert!(ours.contains(row), "README.md lists {row:?}, which the viewer's tables do not");
    }
    for row in &ours {
        assert!(readme.contains(row), "README.md does not list {row:?}");
    }
    assert_eq!(readme, ours, "same rows, same order");
}
