//! Where the viewer finds and keeps its files: the default organ set, and the recovery and
//! quiz-history files beside eframe's settings.

use std::path::{Path, PathBuf};

/// Where the viewer keeps its recovery file: beside its settings.
pub fn recovery_path() -> Option<PathBuf> {
    eframe::storage_dir("vbrain").map(|d| d.join("recovery.vbscene"))
}

/// Where the viewer keeps quiz results: beside its settings.
pub fn quiz_history_path() -> Option<PathBuf> {
    eframe::storage_dir("vbrain").map(|d| d.join("quiz-history.csv"))
}

/// The default organ set: `organs/brain` under the working directory, else beside the sources.
pub fn default_set_path() -> PathBuf {
    let here = PathBuf::from("organs/brain");
    if here.is_dir() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../organs/brain")
}
