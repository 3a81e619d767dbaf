//! The status bar (frames per second, triangles and organs drawn, camera and render modes, the
//! selected organ) and the notifications (bottom right, newest first, each dismissible).
//!
//! - Both only read; dismissing returns an [`Action`].

use super::action::Action;
use super::scene::Scene;
use super::settings::Settings;
use eframe::egui;

/// A message for the user; errors name the file that failed.
pub struct Notification {
    pub text: String,
    pub error: bool,
}

/// What the status bar shows.
pub struct Status<'a> {
    pub scene: Option<&'a Scene>,
    pub loading: bool,
    /// The last frame's counts, the frame rate, and whether the camera walks (not orbits).
    pub frame: (vbrain::render::RenderStats, f32, bool),
    /// The last frame's render scale (below 1 while moving frames are drawn smaller) and level of
    /// detail (above 0 while they draw coarser organs).
    pub detail: (f32, u8),
    /// Where the last frame's occluders came from.
    pub occluders: Option<vbrain::cull::OccluderSource>,
    pub settings: &'a Settings,
    pub selected: Option<usize>,
}

pub fn status_bar(ui: &mut egui::Ui, s: &Status) {
    ui.horizontal(|ui| {
        let Some(scene) = s.scene else {
            ui.label(if s.loading { "loading..." } else { "no organ set: File > Open organ set..." });
            return;
        };
        let (stats, fps, fly) = s.frame;
        if s.settings.show_stats {
            ui.label(format!("{fps:.0} fps"));
            ui.separator();
        }
        ui.label(format!("{} / {} triangles drawn", stats.triangles_drawn, scene.set().triangle_count()));
        ui.separator();
        ui.label(format!("{} organs drawn", stats.organs_drawn));
        let (scale, level) = s.detail;
        if scale < 1.0 || level > 0 {
            ui.separator();
            let coarser = if level > 0 { format!("organs at level of detail {level}") } else { String::new() };
            let smaller = if scale < 1.0 { format!("drawn at {:.0} % size", scale * 100.0) } else { String::new() };
            let both = if level > 0 && scale < 1.0 { ", " } else { "" };
            let r = ui.label(format!("moving: {coarser}{both}{smaller}"));
            r.on_hover_text(
                "While the view moves slowly, organs are drawn with fewer triangles, then frames smaller and \
                 scaled up; still frames are full detail and size",
            );
        }
        ui.separator();
        ui.label(if fly { "walk-through camera" } else { "orbit camera" });
        ui.separator();
        ui.label(format!("transparency: {}", s.settings.transparency.mode.name()));
        ui.separator();
        let occluders = match s.occluders {
            Some(vbrain::cull::OccluderSource::Mos) => ", pre-computed occluders",
            Some(vbrain::cull::OccluderSource::ProjectedSize) => ", occluders by projected size",
            None => "",
        };
        ui.label(format!("culling: {}{occluders}", s.settings.cull.mode.name()));
        if let Some(sel) = s.selected {
            ui.separator();
            ui.label(format!("selected: {}", scene.set().organs[sel].name));
        }
    });
}

/// The newest eight notifications; a click on "x" (or "Dismiss all") dismisses.
pub fn notifications(ctx: &egui::Context, notifications: &[Notification]) -> Vec<Action> {
    if notifications.is_empty() {
        return Vec::new();
    }
    let mut dismiss = Vec::new();
    egui::Area::new(egui::Id::unique("notifications")).anchor(egui::Align2::RIGHT_BOTTOM, [-12.0, -36.0]).show(
        ctx,
        |ui| {
            egui::Frame::popup(ui.style()).show(ui, |ui| {
                ui.set_max_width(520.0);
                for (i, n) in notifications.iter().enumerate().rev().take(8) {
                    ui.horizontal(|ui| {
                        let colour = if n.error { egui::Color32::LIGHT_RED } else { ui.visuals().text_color() };
                        if ui.small_button("x").on_hover_text("Dismiss").clicked() {
                            dismiss = vec![Action::Dismiss(Some(i))];
                        }
                        ui.add(egui::Label::new(egui::RichText::new(&n.text).color(colour)).wrap());
                    });
                }
                if notifications.len() > 1 && ui.button("Dismiss all").clicked() {
                    dismiss = vec![Action::Dismiss(None)];
                }
            });
        },
    );
    dismiss
}
