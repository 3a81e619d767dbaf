//! The viewer's file windows, kept together: open a set or mesh files, import a label volume,
//! export a screenshot, a glTF model, a web page, an Anki deck, a SCORM package, a video or a
//! PDF handout.
//!
//! - The windows live in [`files`] and [`export`]; each returns actions, which the app performs.

use super::action::ModelKind;
pub mod export;
pub mod files;

use export::{ExportWindow, ModelWindow};
use files::{ImportWindow, OpenWindow};

/// The viewer's windows.
pub struct Dialogs {
    pub open_set: OpenWindow,
    pub open_meshes: OpenWindow,
    pub import: ImportWindow,
    pub export: ExportWindow,
    pub gltf: ModelWindow,
    pub web: ModelWindow,
    pub anki: ModelWindow,
    pub scorm: ModelWindow,
    pub video: ModelWindow,
    pub pdf: ModelWindow,
}

impl Default for Dialogs {
    fn default() -> Dialogs {
        Dialogs {
            open_set: OpenWindow::default(),
            open_meshes: OpenWindow::default(),
            import: ImportWindow::default(),
            export: ExportWindow::default(),
            gltf: ModelWindow::new(ModelKind::Gltf),
            web: ModelWindow::new(ModelKind::Web),
            anki: ModelWindow::new(ModelKind::Anki),
            scorm: ModelWindow::new(ModelKind::Scorm),
            video: ModelWindow::new(ModelKind::Video),
            pdf: ModelWindow::new(ModelKind::Pdf),
        }
    }
}

impl Dialogs {
    /// The window of a model export.
    pub fn model(&mut self, kind: ModelKind) -> &mut ModelWindow {
        match kind {
            ModelKind::Gltf => &mut self.gltf,
            ModelKind::Web => &mut self.web,
            ModelKind::Anki => &mut self.anki,
            ModelKind::Scorm => &mut self.scorm,
            ModelKind::Video => &mut self.video,
            ModelKind::Pdf => &mut self.pdf,
        }
    }
}
