//! Where the viewer keeps its files: the recovery and quiz-history files beside eframe's settings.
//!
//! - Both are in eframe's storage folder for "vbrain" (`recovery.vbscene`, `quiz-history.csv`);
//!   there are none where eframe has no storage folder.
//! - The default organ set is found by [`vbrain::data_dir`], not here.

use std::path::PathBuf;

/// Where the viewer keeps its recovery file: beside its settings.
pub fn recovery_path() -> Option<PathBuf> {
    eframe::storage_dir("vbrain").map(|d| d.join("recovery.vbscene"))
}

/// Where the viewer keeps quiz results: beside its settings.
pub fn quiz_history_path() -> Option<PathBuf> {
    eframe::storage_dir("vbrain").map(|d| d.join("quiz-history.csv"))
}
