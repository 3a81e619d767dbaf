//! What the viewport paints over its image: the statistics overlay (top left) and the legend of
//! the colouring (bottom left, in lobe or territory colouring).
//!
//! - Positions are egui points inside the viewport's rect.

use super::super::scene::Scene;
use super::super::settings::Settings;
use eframe::egui::{self, Rect};
use vbrain::cull::CullStats;
use vbrain::render::RenderStats;

/// The statistics overlay (top left): culling and transparency figures of the frame, with
/// `transparency` as this frame drew (see [`motion`]).
pub(super) fn stats(
    ui: &egui::Ui,
    rect: Rect,
    (settings, transparency): (&Settings, &vbrain::transparency::TransparencySettings),
    (cull, why): (&CullStats, Option<String>),
    stats: &RenderStats,
    faded: bool,
) {
    let mut lines = Vec::new();
    if settings.cull.mode != vbrain::cull::CullMode::None {
        lines.push(format!(
            "culling: {}{}\n{:.1} % culled ({} frustum, {} occlusion{}, {} facing away{} triangles)\n{} occluder leaves, {} triangles{}{}\n{} nodes tested, {:.2} ms",
            settings.cull.mode.name(),
            why.map_or(String::new(), |w| format!(" ({w})")),
            cull.culled_percent(),
            cull.frustum_culled,
            cull.occlusion_culled,
            match cull.inside_culled {
                0 => String::new(),
                n => format!(" of which {n} inside solids"),
            },
            cull.back_face_culled,
            match cull.clip_culled {
                0 => String::new(),
                n => format!(", {n} cut away"),
            },
            cull.occluder_leaves,
            cull.occluder_triangles,
            cull.source.map_or(String::new(), |s| format!(" by {}", s.name())),
            match cull.solids {
                0 => String::new(),
                n => format!(", {n} solid{}", if n == 1 { "" } else { "s" }),
            },
            cull.nodes_tested,
            cull.cull_ms
        ));
    }
    if faded {
        let t = transparency;
        let passes = if stats.passes == 1 { "pass" } else { "passes" };
        let mut line = format!("transparency: {}, {} {passes} this frame", t.mode.name(), stats.passes);
        if t.mode != settings.transparency.mode {
            line += &format!(" (moving; {} when still)", settings.transparency.mode.name());
        }
        if t.mode.mask_method().is_some() {
            let (done, total) = (stats.subsamples_done, stats.subsamples_total);
            let state = if done < total { "refining" } else { "converged" };
            line += &format!(
                "\n{state}: {done} of {total} sub-samples\nmasks: {} configurations, {:.2} ms",
                stats.mask_configs, stats.mask_ms
            );
        }
        lines.push(line);
    }
    if !lines.is_empty() {
        let font = egui::FontId::monospace(11.0);
        ui.painter().text(
            rect.min + egui::vec2(8.0, 8.0),
            egui::Align2::LEFT_TOP,
            lines.join("\n"),
            font,
            egui::Color32::from_gray(200),
        );
    }
}

/// The colouring's legend: a swatch and a name for each lobe drawn or each artery, bottom left.
pub(super) fn legend(ui: &egui::Ui, rect: Rect, scene: &Scene) {
    let entries = vbrain::colouring::legend(scene.set(), scene.layout());
    if entries.is_empty() {
        return;
    }
    let painter = ui.painter_at(rect);
    let font = egui::FontId::proportional(12.0);
    let line = 16.0;
    let width = entries
        .iter()
        .map(|(name, _)| painter.layout_no_wrap(name.clone(), font.clone(), egui::Color32::WHITE).size().x)
        .fold(0.0, f32::max)
        + 30.0;
    let height = line * entries.len() as f32 + 8.0;
    let frame = Rect::from_min_size(egui::pos2(rect.min.x + 8.0, rect.max.y - height - 8.0), egui::vec2(width, height));
    painter.rect_filled(frame, 4.0, egui::Color32::from_black_alpha(150));
    for (k, (name, c)) in entries.iter().enumerate() {
        let y = frame.min.y + 4.0 + line * k as f32;
        let [r, g, b] = c.map(|v| (v.clamp(0.0, 1.0) * 255.0).round() as u8);
        let swatch = Rect::from_min_size(egui::pos2(frame.min.x + 6.0, y + 2.0), egui::vec2(14.0, 12.0));
        painter.rect_filled(swatch, 2.0, egui::Color32::from_rgb(r, g, b));
        painter.text(
            egui::pos2(frame.min.x + 26.0, y + line / 2.0),
            egui::Align2::LEFT_CENTER,
            name,
            font.clone(),
            egui::Color32::from_gray(225),
        );
    }
}
