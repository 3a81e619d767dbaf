//! Screenshot export, the export window that asks for it, and the model windows.
//!
//! - A screenshot is the current view rendered offscreen at the asked size through the same
//!   renderer as the viewport (never an upscaled screen grab), written as PNG atomically, never
//!   over an existing file.
//! - The export window asks for the size and the file and returns an [`Action::Export`].
//! - The model windows ask for a file or a folder and return an [`Action::ExportModel`]: the
//!   scene as a glTF model ([`vbrain::gltf`]) or a web page ([`vbrain::web_page`]).

use crate::viewer::action::{Action, ModelKind};
use crate::viewer::settings::{ExportSettings, ExportSize};
use crate::viewer::widgets::{accessible, PathField, Pick};
use anyhow::{bail, Result};
use eframe::egui;
use std::path::{Path, PathBuf};
use vbrain::render::{FrameInput, Renderer, Target};

pub use crate::viewer::settings::MAX_EXPORT_SIDE as MAX_SIDE;

/// `<set>-YYYYMMDD-HHMMSS.png` for the set's title and a time (UTC).
pub fn default_file_name(title: &str, now: std::time::SystemTime) -> String {
    let secs = now.duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Civil date from days since 1970-01-01 (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    let slug = vbrain::organ_set::slug(title);
    format!("{slug}-{year:04}{month:02}{day:02}-{:02}{:02}{:02}.png", rem / 3600, rem % 3600 / 60, rem % 60)
}

/// `path` if it does not exist, else the first free `name-2.png`, `name-3.png`, ...
pub fn unused_path(path: &Path) -> PathBuf {
    if !path.exists() {
        return path.to_path_buf();
    }
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_else(|| "png".into());
    (2..).map(|n| path.with_file_name(format!("{stem}-{n}.{ext}"))).find(|p| !p.exists()).unwrap_or_default()
}

/// Renders `frame` (a still: full screen-door masks) at `size`, with `labels` (named by `name`)
/// sized to the image, and writes a PNG to `path` (or, if that exists, to the next free name,
/// which is returned).
pub fn export(
    (device, queue, renderer): (&wgpu::Device, &wgpu::Queue, &Renderer),
    frame: &FrameInput,
    size: [u32; 2],
    path: &Path,
    labels: &crate::annotate::Labels,
    name: &dyn Fn(usize) -> String,
) -> Result<PathBuf> {
    let [w, h] = size;
    if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
        bail!("screenshot size {w}x{h} outside 1..={MAX_SIDE}");
    }
    let mut target = Target::new(device, w, h)?;
    let still = FrameInput { moving: false, ..*frame };
    renderer.render(device, queue, &mut target, &still)?;
    let mut image = target.read_color(device, queue)?;
    if *labels != crate::annotate::Labels::None {
        renderer.render_ids(device, queue, &target, &still, crate::annotate::PICK_OPACITY);
        let ids = target.read_ids(device, queue)?;
        crate::annotate::draw(&mut image, &ids, labels, name);
    }
    let path = unused_path(path);
    vbrain::atomic::write_png(&path, &image, false)?;
    Ok(path)
}

/// The file to write for the path typed: `extension` (`png`, `glb`) added if it has none.
pub fn file_path(typed: &str, extension: &str) -> Result<PathBuf> {
    let mut path = PathBuf::from(typed.trim());
    if path.as_os_str().is_empty() {
        bail!("no file name");
    }
    if path.extension().is_none() {
        path.set_extension(extension);
    }
    Ok(path)
}

/// Writes `glb` to `path` (or, if that exists, to the next free name, which is returned),
/// atomically and never over an existing file.
pub fn write_glb(path: &Path, glb: &[u8]) -> Result<PathBuf> {
    let path = unused_path(path);
    vbrain::atomic::write_new(&path, |w| w.write_all(glb))?;
    Ok(path)
}

/// The "Export glTF model" and "Export web page" windows: a file or a folder, and Save.
pub struct ModelWindow {
    pub kind: ModelKind,
    pub open: bool,
    pub path: PathField,
    /// With a lesson open, a web page of the lesson (its steps) rather than of the view.
    pub whole_lesson: bool,
    /// The last export's result, shown in the window.
    pub last: Option<String>,
}

impl ModelWindow {
    pub fn new(kind: ModelKind) -> ModelWindow {
        ModelWindow { kind, open: false, path: PathField::default(), whole_lesson: true, last: None }
    }

    /// The window for a set titled `title`; proposes `<set>-<time>.glb` (or a folder
    /// `<set>-<time>-page`) in the screenshots' folder. `lesson` is the open lesson's title and
    /// step count (a web page can be of it), or for a SCORM package its title and question count.
    pub fn show(
        &mut self,
        ctx: &egui::Context,
        title: &str,
        folder: Option<&Path>,
        lesson: Option<(&str, usize)>,
    ) -> Vec<Action> {
        if self.open && self.path.text.is_empty() {
            let name = default_file_name(title, std::time::SystemTime::now());
            let name = match self.kind {
                ModelKind::Gltf => name.replace(".png", ".glb"),
                ModelKind::Web => name.replace(".png", "-page"),
                ModelKind::Anki => name.replace(".png", ".apkg"),
                ModelKind::Scorm => name.replace(".png", "-scorm.zip"),
                ModelKind::Video => name.replace(".png", ".mp4"),
                ModelKind::Pdf => name.replace(".png", ".pdf"),
            };
            self.path.text = folder.unwrap_or(Path::new("")).join(name).display().to_string();
        }
        let mut open = self.open;
        let mut save = false;
        let title = match self.kind {
            ModelKind::Gltf => "Export glTF model",
            ModelKind::Web => "Export web page",
            ModelKind::Anki => "Export Anki deck",
            ModelKind::Scorm => "Export SCORM package",
            ModelKind::Video => "Export video",
            ModelKind::Pdf => "Export PDF handout",
        };
        let window = egui::Window::new(title).open(&mut open).collapsible(false).default_width(520.0);
        window.show(ctx, |ui| {
            match self.kind {
                ModelKind::Gltf => {
                    ui.label(
                        "The organs shown, with their colours, opacities, moves, groups and info texts, cut by \
                         the section planes. Opens in Blender, slide software and web viewers.",
                    );
                    save |= self.path.ui(ui, "File:", Pick::Save, &[("glTF binary", &["glb"])]);
                }
                ModelKind::Web => {
                    ui.label(
                        "A folder with index.html: students open it in any browser, from the file or a web \
                         server, and turn the view, show, hide and fade organs, click one to read about it, \
                         and see the labels. The folder must be new or empty.",
                    );
                    self.lesson_or_view(ui, lesson);
                    save |= self.path.ui(ui, "Folder:", Pick::Folder, &[]);
                }
                ModelKind::Anki => {
                    ui.label(
                        "Flashcards of every structure shown, from its best views: \"name it\" (outlined) and \
                         image occlusion (covered by a mask of its exact shape), with the Latin names and \
                         texts. Import the file in Anki (File > Import); exporting again updates the cards and \
                         keeps their reviews.",
                    );
                    save |= self.path.ui(ui, "File:", Pick::Save, &[("Anki deck", &["apkg"])]);
                }
                ModelKind::Scorm => {
                    ui.label(
                        "The open lesson's web page, asking its quiz, packaged for a course's learning \
                         platform (Moodle, Canvas, Blackboard: add it as a SCORM activity). The page reports \
                         the score, and passed or failed against the lesson's pass mark (70 % unless it sets \
                         one).",
                    );
                    match lesson {
                        Some((title, questions)) => {
                            ui.label(format!("Package of the lesson \"{title}\" ({questions} questions)."));
                        }
                        None => {
                            ui.colored_label(ui.visuals().warn_fg_color, "Open a lesson with a quiz first.");
                        }
                    }
                    save |= self.path.ui(ui, "File:", Pick::Save, &[("SCORM package", &["zip"])]);
                }
                ModelKind::Video => {
                    ui.label(
                        "A video for slides, 1280x720 at 30 frames a second: the view turned once around \
                         (8 seconds), or the open lesson played, each step eased in and held 3 seconds with \
                         its caption. MP4 and WebM are encoded by ffmpeg, which must be installed; a GIF \
                         needs nothing.",
                    );
                    self.lesson_or_view(ui, lesson);
                    let formats: &[(&str, &[&str])] =
                        &[("MP4 video", &["mp4"]), ("WebM video", &["webm"]), ("GIF", &["gif"])];
                    save |= self.path.ui(ui, "File:", Pick::Save, formats);
                }
                ModelKind::Pdf => {
                    ui.label(
                        "A handout on A4 paper: a title page crediting the atlas, then the view with its labels \
                         and the selected structure's text, or a page per step of the open lesson with its \
                         figure, title and caption.",
                    );
                    self.lesson_or_view(ui, lesson);
                    save |= self.path.ui(ui, "File:", Pick::Save, &[("PDF", &["pdf"])]);
                }
            }
            save |= ui.button("Save").clicked();
            if let Some(last) = &self.last {
                ui.label(last);
            }
        });
        self.open = open;
        if save {
            let of_lesson = matches!(self.kind, ModelKind::Web | ModelKind::Video | ModelKind::Pdf);
            let lesson = of_lesson && lesson.is_some() && self.whole_lesson;
            vec![Action::ExportModel { kind: self.kind, path: self.path.text.clone(), lesson }]
        } else {
            Vec::new()
        }
    }

    /// With a lesson open, the choice of the lesson or this view.
    fn lesson_or_view(&mut self, ui: &mut egui::Ui, lesson: Option<(&str, usize)>) {
        if let Some((lesson, steps)) = lesson {
            ui.horizontal(|ui| {
                ui.label("Of:");
                ui.radio_value(&mut self.whole_lesson, true, format!("the lesson \"{lesson}\" ({steps} steps)"));
                ui.radio_value(&mut self.whole_lesson, false, "this view");
            });
        }
    }

    /// After an export: as [`ExportWindow::finished`].
    pub fn finished(&mut self, message: String, saved: bool) {
        if saved {
            self.path.text.clear();
            self.open = false;
        }
        self.last = Some(message);
    }
}

/// The "Export screenshot" window.
#[derive(Default)]
pub struct ExportWindow {
    pub open: bool,
    pub path: PathField,
    /// The last export's result, shown in the window.
    pub last: Option<String>,
}

impl ExportWindow {
    /// The window for a set titled `title` in a viewport of `viewport` pixels; the size and
    /// background choices are the export settings, kept between sessions.
    pub fn show(
        &mut self,
        ctx: &egui::Context,
        title: &str,
        viewport: [u32; 2],
        settings: &mut ExportSettings,
    ) -> Vec<Action> {
        if self.open && self.path.text.is_empty() {
            let name = default_file_name(title, std::time::SystemTime::now());
            let folder = settings.folder.clone().unwrap_or_default();
            self.path.text = folder.join(name).display().to_string();
        }
        let mut open = self.open;
        let mut save = false;
        egui::Window::new("Export screenshot").open(&mut open).collapsible(false).show(ctx, |ui| {
            let [vw, vh] = viewport;
            let choices = [
                (ExportSize::Viewport, format!("Viewport ({vw}x{vh})")),
                (ExportSize::Double, format!("2x ({}x{})", vw * 2, vh * 2)),
                (ExportSize::Quadruple, format!("4x ({}x{})", vw * 4, vh * 4)),
                (ExportSize::Custom, "Custom".to_string()),
            ];
            for (size, label) in choices {
                ui.radio_value(&mut settings.size, size, label);
            }
            ui.add_enabled_ui(settings.size == ExportSize::Custom, |ui| {
                ui.horizontal(|ui| {
                    let r = ui.add(egui::DragValue::new(&mut settings.custom[0]).range(1..=MAX_SIDE));
                    accessible(&r, "Custom width");
                    ui.label("x");
                    let r = ui.add(egui::DragValue::new(&mut settings.custom[1]).range(1..=MAX_SIDE));
                    accessible(&r, "Custom height");
                });
            });
            ui.checkbox(&mut settings.transparent, "Transparent background");
            let entered = self.path.ui(ui, "File:", Pick::Save, &[("PNG image", &["png"])]);
            save = ui.button("Save").clicked() || entered;
            if let Some(last) = &self.last {
                ui.label(last);
            }
        });
        self.open = open;
        if !save {
            return Vec::new();
        }
        let [vw, vh] = viewport;
        let size = match settings.size {
            ExportSize::Viewport => [vw, vh],
            ExportSize::Double => [vw * 2, vh * 2],
            ExportSize::Quadruple => [vw * 4, vh * 4],
            ExportSize::Custom => settings.custom,
        };
        vec![Action::Export { path: self.path.text.clone(), size }]
    }

    /// After an export: its message shown in the window; on success the window closes and the
    /// next one proposes a new name.
    pub fn finished(&mut self, message: String, saved: bool) {
        if saved {
            self.path.text.clear();
            self.open = false;
        }
        self.last = Some(message);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names() {
        let t = std::time::UNIX_EPOCH + std::time::Duration::from_secs(1_795_305_600 + 3 * 3600 + 4 * 60 + 5);
        assert_eq!(default_file_name("Human brain (MNI152)", t), "human_brain_mni152-20261122-030405.png");
        let leap = std::time::UNIX_EPOCH + std::time::Duration::from_secs(951_782_400); // 2000-02-29
        assert!(default_file_name("x", leap).starts_with("x-20000229-"));
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.png");
        assert_eq!(unused_path(&p), p);
        std::fs::write(&p, b"x").unwrap();
        assert_eq!(unused_path(&p), dir.path().join("a-2.png"));
    }
}
