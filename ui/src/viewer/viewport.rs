//! The viewport: draws the scene through the core renderer into a texture egui paints, and turns
//! mouse and keys into camera moves (orbit, pan, zoom toward the cursor, walk-through), picking
//! (click selects, double-click frames) and organ moves (Ctrl+drag move, Shift+drag rotate,
//! Ctrl+wheel resize). Input is in egui points; the target is in physical pixels.

use super::app::App;
use eframe::egui::{self, Key, PointerButton, Pos2, Rect, Sense};
use glam::{Quat, Vec2, Vec3};
use std::collections::VecDeque;
use std::time::Instant;
use vbrain::camera::{Camera, View};
use vbrain::cull::CullStats;
use vbrain::mesh::Bounds;
use vbrain::navigation::Navigator;
use vbrain::render::{FrameInput, RenderStats, Target};

pub struct Viewport {
    pub nav: Navigator,
    /// Walk-through camera: drag looks around, W/A/S/D/Q/E move.
    pub fly: bool,
    pub stats: RenderStats,
    pub cull: CullStats,
    /// The camera or an organ moved this frame: screen-door draws with fewer sub-samples.
    pub moving: bool,
    target: Option<(Target, egui::TextureId)>,
    /// The rectangle the viewport last occupied (points).
    pub rect: Rect,
    frame_times: VecDeque<Instant>,
}

impl Default for Viewport {
    fn default() -> Self {
        Viewport {
            nav: Navigator { target: Vec3::ZERO, distance: 400.0, azimuth: 0.0, elevation: 0.0 },
            fly: false,
            stats: RenderStats::default(),
            cull: CullStats::default(),
            moving: false,
            target: None,
            rect: Rect::NOTHING,
            frame_times: VecDeque::new(),
        }
    }
}

impl Viewport {
    pub fn reset_camera(&mut self, home: &Bounds) {
        self.nav = Navigator::framing(home, 0.0, 0.0);
    }

    pub fn set_view(&mut self, view: View, home: Option<Bounds>) {
        let (az, el) = view.angles();
        match home {
            Some(b) => self.nav = Navigator::framing(&b, az, el),
            None => (self.nav.azimuth, self.nav.elevation) = (az, el),
        }
    }

    /// Frames per second over the last second of painted frames.
    pub fn fps(&self) -> f32 {
        match (self.frame_times.front(), self.frame_times.back()) {
            (Some(a), Some(b)) if self.frame_times.len() > 1 => {
                (self.frame_times.len() - 1) as f32 / b.duration_since(*a).as_secs_f32().max(1e-6)
            }
            _ => 0.0,
        }
    }

    /// The target's size in physical pixels, if drawn yet.
    pub fn pixel_size(&self) -> Option<[u32; 2]> {
        self.target.as_ref().map(|(t, _)| [t.width, t.height])
    }
}

/// The camera of the current view: the navigator, depth fitted to what is drawn.
pub fn camera(app: &App) -> Option<Camera> {
    let scene = app.scene.as_ref()?;
    Some(app.viewport.nav.camera(&scene.layout.bounds(&scene.set).union(scene.home)))
}

/// Draws the organ-ID buffer of the current view into the viewport's target; returns the target.
fn draw_ids(app: &App) -> Option<(&Target, &egui_wgpu::RenderState)> {
    let (scene, rs, (target, _)) = (app.scene.as_ref()?, app.gpu.as_ref()?, app.viewport.target.as_ref()?);
    let camera = camera(app)?;
    let input = FrameInput::new(&scene.set, &camera, &scene.layout);
    scene.renderer.render_ids(&rs.device, &rs.queue, target, &input, app.settings.pick_min_opacity);
    Some((target, rs))
}

/// Which organ is under a point of the viewport (points), from the ID buffer.
pub fn pick(app: &App, at: Pos2) -> Option<usize> {
    let (target, rs) = draw_ids(app)?;
    let rect = app.viewport.rect;
    let px = ((at.x - rect.min.x) / rect.width() * target.width as f32) as u32;
    let py = ((at.y - rect.min.y) / rect.height() * target.height as f32) as u32;
    match target.read_id_at(&rs.device, &rs.queue, px, py) {
        Ok(Some(id)) if id > 0 => Some(id as usize - 1),
        _ => None,
    }
}

pub fn show(app: &mut App, ui: &mut egui::Ui) {
    let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
    crate::viewer::accessible(&response, "Viewport");
    app.viewport.rect = rect;
    handle_input(app, ui, &response);
    draw(app, ui, rect);
}

fn handle_input(app: &mut App, ui: &egui::Ui, response: &egui::Response) {
    let (modifiers, dt) = ui.input(|i| (i.modifiers, i.stable_dt.min(0.1)));
    let size = Vec2::new(app.viewport.rect.width(), app.viewport.rect.height());
    let delta = Vec2::new(response.drag_delta().x, response.drag_delta().y);
    let scrolled = response.hovered() && ui.input(|i| i.smooth_scroll_delta.y != 0.0);
    app.viewport.moving = delta != Vec2::ZERO || scrolled;
    let nav = &mut app.viewport.nav;
    if response.dragged_by(PointerButton::Primary) && delta != Vec2::ZERO {
        let organ = app.selected.filter(|_| modifiers.command || modifiers.shift);
        match (organ, app.scene.as_mut()) {
            (Some(sel), Some(scene)) => {
                let camera = nav.camera(&scene.home);
                manipulate(scene, sel, &camera, delta, size.y, modifiers);
            }
            _ if app.viewport.fly => nav.look(delta),
            _ => nav.orbit(delta),
        }
    }
    if (response.dragged_by(PointerButton::Secondary) || response.dragged_by(PointerButton::Middle))
        && delta != Vec2::ZERO
    {
        nav.pan(delta, size.y);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            let factor = (-scroll * 0.0015).exp();
            match (app.selected.filter(|_| modifiers.command), app.scene.as_mut()) {
                (Some(sel), Some(scene)) => {
                    let t = &mut scene.layout.organs[sel].transform;
                    t.scale = (t.scale / factor).clamp(0.05, 20.0);
                }
                _ => {
                    if let Some(p) = response.hover_pos() {
                        let cursor = Vec2::new(p.x - app.viewport.rect.min.x, p.y - app.viewport.rect.min.y);
                        app.viewport.nav.zoom_at(factor, cursor, size);
                    }
                }
            }
        }
    }
    if app.viewport.fly && !ui.ctx().egui_wants_keyboard_input() {
        let speed = app.scene.as_ref().map(|s| s.home.size().length() * 0.3).unwrap_or(50.0) * dt;
        let held = |k| ui.input(|i| i.key_down(k));
        let axis = |plus, minus| (held(plus) as i32 - held(minus) as i32) as f32 * speed;
        let (f, r, u) = (axis(Key::W, Key::S), axis(Key::D, Key::A), axis(Key::E, Key::Q));
        if f != 0.0 || r != 0.0 || u != 0.0 {
            app.viewport.nav.walk(f, r, u);
            app.viewport.moving = true;
            ui.ctx().request_repaint();
        }
    }
    if response.double_clicked() {
        if let Some(p) = response.interact_pointer_pos() {
            if let Some(organ) = pick(app, p) {
                app.selected = Some(organ);
                if let Some(scene) = &app.scene {
                    let b = scene.organ_bounds(organ);
                    app.viewport.nav.frame(&b);
                }
            }
        }
    } else if response.clicked() {
        if let Some(p) = response.interact_pointer_pos() {
            app.selected = pick(app, p);
        }
    }
}

/// Moves (Ctrl), rotates (Shift) or resizes (Ctrl+Shift) an organ by a drag, in view space.
fn manipulate(
    scene: &mut super::app::Scene,
    organ: usize,
    camera: &Camera,
    delta: Vec2,
    height: f32,
    modifiers: egui::Modifiers,
) {
    let forward = (camera.target - camera.eye).normalize();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
    let t = &mut scene.layout.organs[organ].transform;
    if modifiers.command && modifiers.shift {
        t.scale = (t.scale * (-delta.y * 0.01).exp()).clamp(0.05, 20.0);
    } else if modifiers.command {
        let centre = t.matrix().transform_point3(t.pivot);
        let depth = (centre - camera.eye).dot(forward).max(1.0);
        let k = 2.0 * depth * (camera.fov_y.to_radians() * 0.5).tan() / height.max(1.0);
        t.translation += (right * delta.x - up * delta.y) * k;
    } else {
        let turn = Quat::from_axis_angle(up, (delta.x * 0.5).to_radians())
            * Quat::from_axis_angle(right, (delta.y * 0.5).to_radians());
        let (x, y, z) = (turn * t.rotation()).to_euler(glam::EulerRot::XYZ);
        t.rotation_deg = Vec3::new(x, y, z) * (180.0 / std::f32::consts::PI);
    }
}

fn draw(app: &mut App, ui: &egui::Ui, rect: Rect) {
    let Some(rs) = app.gpu.clone() else { return };
    let Some(camera) = camera(app) else { return };
    let ppp = ui.ctx().pixels_per_point();
    let (w, h) = (((rect.width() * ppp).round() as u32).max(1), ((rect.height() * ppp).round() as u32).max(1));
    let vp = &mut app.viewport;
    if vp.target.as_ref().is_none_or(|(t, _)| t.width != w || t.height != h) {
        match Target::new(&rs.device, w, h) {
            Ok(t) => {
                let mut egui_renderer = rs.renderer.write();
                let id = match vp.target.take() {
                    Some((_, id)) => {
                        egui_renderer.update_egui_texture_from_wgpu_texture(
                            &rs.device,
                            &t.display_view,
                            wgpu::FilterMode::Linear,
                            id,
                        );
                        id
                    }
                    None => {
                        egui_renderer.register_native_texture(&rs.device, &t.display_view, wgpu::FilterMode::Linear)
                    }
                };
                vp.target = Some((t, id));
            }
            Err(e) => {
                let text = e.to_string();
                if !app.notifications.iter().any(|n| n.text == text) {
                    app.notify(text, true);
                }
                return;
            }
        }
    }
    let background = app.settings.background_linear(false);
    let Some(scene) = &mut app.scene else { return };
    let Some((target, id)) = &app.viewport.target else { return };
    let (draw, cull) = scene.culler.cull(&scene.set, &scene.layout, &camera, target.aspect(), &app.settings.cull);
    let input = FrameInput {
        draw: Some(&draw),
        background,
        transparency: app.settings.transparency,
        moving: app.viewport.moving,
        ..FrameInput::new(&scene.set, &camera, &scene.layout)
    };
    let stats = if app.settings.cull_debug {
        scene.renderer.render_cull_debug(&rs.device, &rs.queue, target, &input);
        Ok(RenderStats {
            organs_drawn: scene.layout.organs.iter().filter(|s| s.is_drawn()).count(),
            triangles_drawn: cull.drawn,
            ..Default::default()
        })
    } else {
        scene.renderer.render(&rs.device, &rs.queue, target, &input)
    };
    let (stats, failed) = match stats {
        Ok(s) => (s, None),
        Err(e) => (RenderStats::default(), Some(format!("drawing failed: {e}"))),
    };
    let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
    ui.painter().image(*id, rect, uv, egui::Color32::WHITE);
    let mut lines = Vec::new();
    if app.settings.cull.mode != vbrain::cull::CullMode::None {
        lines.push(format!(
            "culling: {}\n{:.1} % culled ({} frustum, {} occlusion triangles)\n{} occluder leaves, {} triangles{}\n{} nodes tested, {:.2} ms",
            app.settings.cull.mode.name(),
            cull.culled_percent(),
            cull.frustum_culled,
            cull.occlusion_culled,
            cull.occluder_leaves,
            cull.occluder_triangles,
            cull.source.map_or(String::new(), |s| format!(" by {}", s.name())),
            cull.nodes_tested,
            cull.cull_ms
        ));
    }
    if input.has_transparent() {
        let t = &app.settings.transparency;
        let mut line = format!("transparency: {}, {} passes", t.mode.name(), stats.passes);
        if t.mode.mask_method().is_some() {
            line += &format!(
                "\nmasks: {} sub-samples, {} configurations, {:.2} ms",
                stats.passes * 4,
                stats.mask_configs,
                stats.mask_ms
            );
        }
        lines.push(line);
    }
    if app.settings.show_stats && !lines.is_empty() {
        let text = lines.join("\n");
        let font = egui::FontId::monospace(11.0);
        ui.painter().text(
            rect.min + egui::vec2(8.0, 8.0),
            egui::Align2::LEFT_TOP,
            text,
            font,
            egui::Color32::from_gray(200),
        );
    }
    if let Some(text) = failed {
        if !app.notifications.iter().any(|n| n.text == text) {
            app.notify(text, true);
        }
    }
    let vp = &mut app.viewport;
    if vp.moving {
        // Draw once more when the motion stops, with the full masks.
        ui.ctx().request_repaint();
    }
    vp.stats = stats;
    vp.cull = cull;
    let now = Instant::now();
    vp.frame_times.push_back(now);
    while vp.frame_times.front().is_some_and(|t| now.duration_since(*t).as_secs_f32() > 1.0) {
        vp.frame_times.pop_front();
    }
}

/// The organ-ID buffer of the current view at the viewport's size: organ index + 1 per physical
/// pixel (row-major), 0 for background. For tests and tools; picking reads single pixels.
pub fn read_ids(app: &App) -> Option<(Vec<u32>, [u32; 2])> {
    let (target, rs) = draw_ids(app)?;
    Some((target.read_ids(&rs.device, &rs.queue).ok()?, [target.width, target.height]))
}

/// The image the viewport shows now, read back from its target.
pub fn read_image(app: &App) -> Option<image::RgbaImage> {
    let (rs, (target, _)) = (app.gpu.as_ref()?, app.viewport.target.as_ref()?);
    target.read_color(&rs.device, &rs.queue).ok()
}
