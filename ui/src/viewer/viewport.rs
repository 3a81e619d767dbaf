//! The viewport: draws the scene through the core renderer into a texture egui paints, and turns
//! mouse and keys into camera moves, picking and organ moves.
//!
//! - Camera moves: orbit, pan, zoom toward the cursor, walk-through. Picking: click selects,
//!   double-click frames. Organ moves: Ctrl+drag move, Shift+drag rotate, Ctrl+Shift+drag and
//!   Ctrl+wheel resize.
//! - Input is in egui points; the target is in physical pixels.
//! - The camera, the render target, the culler's frame-to-frame state and the statistics are the
//!   viewport's own (camera moves are not edits); organ moves and selection are returned as
//!   [`Action`]s.
//! - A frame is [`Viewport::allocate`], [`Viewport::input`], the app performing its actions, then
//!   [`Viewport::draw`], so what is drawn includes this frame's moves.

pub mod cull_choice;
pub mod motion;
mod overlays;

use super::action::Action;
use super::scene::Scene;
use super::settings::Settings;
use super::widgets::accessible;
use crate::viewer::action::SectionAction;
use eframe::egui::{self, Key, PointerButton, Pos2, Rect, Sense};
use glam::{Quat, Vec2, Vec3};
use std::collections::VecDeque;
use std::time::Instant;
use vbrain::camera::{Camera, View};
use vbrain::cull::database::Database;
use vbrain::cull::{CullStats, Culler};
use vbrain::edit::Edit;
use vbrain::layout::Transform;
use vbrain::mesh::Bounds;
use vbrain::navigation::Navigator;
use vbrain::render::{FrameInput, RenderStats, Target};

/// What the viewport reads each frame.
/// How near (points) a press must be to a plane's handle to drag it.
const HANDLE_REACH: f32 = 10.0;

#[derive(Clone)]
pub struct Input<'a> {
    pub scene: Option<&'a Scene>,
    pub gpu: Option<&'a egui_wgpu::RenderState>,
    pub settings: &'a Settings,
    pub selected: Option<usize>,
    /// Organs the lesson step highlights.
    pub highlight: &'a [usize],
    /// The Sections window's planes, cut faces and organs kept whole.
    pub section: &'a vbrain::clip::Section,
    /// Which organs get labels.
    pub labels: crate::annotate::Labels,
    /// Handles to drag planes by (while the Sections window is open).
    pub handles: Vec<super::action::Handle>,
}

pub struct Viewport {
    nav: Navigator,
    /// Walk-through camera: drag looks around, W/A/S/D/Q/E move.
    fly: bool,
    stats: RenderStats,
    cull: CullStats,
    /// Culls frame after frame, keeping where each organ's last traversal stopped.
    culler: Culler,
    /// Whether occlusion culling pays here, measured now and then (the setting "occlusion").
    cull_choice: cull_choice::CullChoice,
    /// The camera or an organ moved this frame: screen-door draws with fewer sub-samples.
    moving: bool,
    /// How moving frames draw faded organs, and when the last one was drawn.
    motion: (motion::MotionQuality, Option<Instant>),
    target: Option<(Target, egui::TextureId)>,
    /// The smaller image moving frames are drawn into ([`motion::MotionQuality::scale`]).
    reduced: Option<(Target, egui::TextureId)>,
    /// The render scale of the frame last drawn (1 at full size).
    scale: f32,
    /// The level of detail of the frame last drawn (0: full meshes).
    level: u8,
    /// The rectangle the viewport last occupied (points).
    rect: Rect,
    frame_times: VecDeque<Instant>,
    /// The labels last painted, with the layout and the labels asked for they were laid out on:
    /// their anchors are kept while the camera moves and they stay deep in their organs; a new
    /// layout (an edit, a lesson step) or other labels lay them out afresh.
    labels: std::cell::RefCell<LaidLabels>,
    /// The plane whose handle is being dragged.
    dragging_plane: Option<usize>,
}

/// Labels as painted, and the layout and the labels asked for they were laid out on.
type LaidLabels = (Vec<crate::annotate::Laid>, Option<(vbrain::layout::Layout, crate::annotate::Labels)>);

impl Default for Viewport {
    fn default() -> Self {
        Viewport {
            nav: Navigator { target: Vec3::ZERO, distance: 400.0, azimuth: 0.0, elevation: 0.0 },
            fly: false,
            stats: RenderStats::default(),
            cull: CullStats::default(),
            culler: Culler::default(),
            cull_choice: Default::default(),
            moving: false,
            motion: Default::default(),
            target: None,
            reduced: None,
            scale: 1.0,
            level: 0,
            rect: Rect::NOTHING,
            frame_times: VecDeque::new(),
            labels: Default::default(),
            dragging_plane: None,
        }
    }
}

impl Viewport {
    /// A new set: the camera framing `home`, a new culler with the set's occluder database.
    pub fn new_set(&mut self, home: &Bounds, database: Option<Database>) {
        self.reset_camera(home);
        self.culler = Culler::new(database);
    }

    /// Whether the set has pre-computed occluders (for the culling menu).
    pub fn has_database(&self) -> bool {
        self.culler.database().is_some()
    }

    /// The camera's navigator (what a scene file saves).
    pub fn navigator(&self) -> Navigator {
        self.nav
    }

    /// The camera of a scene: its navigator, orbiting or walking.
    pub fn set_navigator(&mut self, nav: Navigator, fly: bool) {
        self.nav = nav;
        self.fly = fly;
    }

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

    /// The camera framing these world bounds, from where it looks now.
    pub fn frame(&mut self, bounds: &Bounds) {
        self.nav.frame(bounds);
    }

    /// The camera as a scene file keeps it.
    pub fn camera_state(&self) -> vbrain::scene_file::CameraState {
        use vbrain::scene_file::{CameraMode, CameraState};
        CameraState::of(&self.navigator(), if self.fly() { CameraMode::Walk } else { CameraMode::Orbit })
    }

    /// The render scale of the frame last drawn: below 1 while moving frames are drawn smaller.
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The last frame's level of detail: above 0 while moving frames draw coarser organs.
    pub fn level(&self) -> u8 {
        self.level
    }

    pub fn fly(&self) -> bool {
        self.fly
    }

    pub fn toggle_fly(&mut self) {
        self.fly = !self.fly;
    }

    /// What the last frame drew.
    pub fn stats(&self) -> RenderStats {
        self.stats
    }

    /// How the last frame culled.
    pub fn cull_stats(&self) -> &CullStats {
        &self.cull
    }

    /// The rectangle the viewport last occupied (points).
    pub fn rect(&self) -> Rect {
        self.rect
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

    /// The camera of the current view: the navigator, depth fitted to what is drawn.
    pub fn camera(&self, scene: &Scene) -> Camera {
        self.nav.camera(&scene.layout().bounds(scene.set()).union(scene.home()))
    }

    /// Takes the rest of `ui` for the viewport.
    pub fn allocate(&mut self, ui: &mut egui::Ui) -> (Rect, egui::Response) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), Sense::click_and_drag());
        accessible(&response, "Viewport");
        self.rect = rect;
        (rect, response)
    }

    /// Mouse and keys: camera moves here, organ moves and picks as actions.
    pub fn input(&mut self, ui: &egui::Ui, response: &egui::Response, input: &Input) -> Vec<Action> {
        let mut out = Vec::new();
        let (modifiers, dt) = ui.input(|i| (i.modifiers, i.stable_dt.min(0.1)));
        let size = Vec2::new(self.rect.width(), self.rect.height());
        let delta = Vec2::new(response.drag_delta().x, response.drag_delta().y);
        let scrolled = response.hovered() && ui.input(|i| i.smooth_scroll_delta.y != 0.0);
        self.moving = delta != Vec2::ZERO || scrolled;
        // The selected organ's transform as this frame's drag and wheel leave it.
        let mut placed: Option<(usize, Transform, Transform)> = None;
        let transform = |scene: &Scene, organ: usize| scene.layout().organs.get(organ).map(|s| s.transform);
        if response.drag_started_by(PointerButton::Primary) {
            let from = ui.input(|i| i.pointer.press_origin());
            self.dragging_plane = from.and_then(|p| self.handle_at(input, p));
        }
        if !response.dragged() {
            self.dragging_plane = None;
        }
        if let (Some(slot), Some(scene)) = (self.dragging_plane, input.scene) {
            if delta != Vec2::ZERO {
                if let Some(h) = input.handles.iter().find(|h| h.slot == slot) {
                    let mm = self.drag_along(scene, h, delta);
                    out.push(Action::Section(SectionAction::MovePlane { slot, mm }));
                }
            }
        } else if response.dragged_by(PointerButton::Primary) && delta != Vec2::ZERO {
            let organ = input.selected.filter(|_| modifiers.command || modifiers.shift);
            match (organ, input.scene) {
                (Some(sel), Some(scene)) => {
                    let camera = self.nav.camera(&scene.home());
                    if let Some(before) = transform(scene, sel) {
                        let mut t = before;
                        manipulate(&mut t, &camera, delta, size.y, modifiers);
                        placed = Some((sel, before, t));
                    }
                }
                _ if self.fly => self.nav.look(delta),
                _ => self.nav.orbit(delta),
            }
        }
        if (response.dragged_by(PointerButton::Secondary) || response.dragged_by(PointerButton::Middle))
            && delta != Vec2::ZERO
        {
            self.nav.pan(delta, size.y);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                let factor = (-scroll * 0.0015).exp();
                match (input.selected.filter(|_| modifiers.command), input.scene) {
                    (Some(sel), Some(scene)) => {
                        let current = match placed {
                            Some((organ, before, t)) if organ == sel => Some((before, t)),
                            _ => transform(scene, sel).map(|t| (t, t)),
                        };
                        if let Some((before, mut t)) = current {
                            t.scale = (t.scale / factor).clamp(0.05, 20.0);
                            placed = Some((sel, before, t));
                        }
                    }
                    _ => {
                        if let Some(p) = response.hover_pos() {
                            let cursor = Vec2::new(p.x - self.rect.min.x, p.y - self.rect.min.y);
                            self.nav.zoom_at(factor, cursor, size);
                        }
                    }
                }
            }
        }
        if let Some((organ, before, transform)) = placed {
            if transform != before {
                out.push(Action::Edit(Edit::Transform { organ, transform }));
            }
        }
        if self.fly && !ui.ctx().egui_wants_keyboard_input() {
            let speed = input.scene.map(|s| s.home().size().length() * 0.3).unwrap_or(50.0) * dt;
            let held = |k| ui.input(|i| i.key_down(k));
            let axis = |plus, minus| (held(plus) as i32 - held(minus) as i32) as f32 * speed;
            let (f, r, u) = (axis(Key::W, Key::S), axis(Key::D, Key::A), axis(Key::E, Key::Q));
            if f != 0.0 || r != 0.0 || u != 0.0 {
                self.nav.walk(f, r, u);
                self.moving = true;
                ui.ctx().request_repaint();
            }
        }
        if response.double_clicked() {
            // Double-click frames what the user sees in front, faded or not.
            if let Some(p) = response.interact_pointer_pos() {
                if let Some(organ) = self.pick(input, p, f32::MIN_POSITIVE) {
                    out.push(Action::Select(Some(organ)));
                    if let Some(scene) = input.scene {
                        self.nav.frame(&scene.organ_bounds(organ));
                    }
                }
            }
        } else if response.clicked() {
            if let Some(p) = response.interact_pointer_pos() {
                let organ = self.pick(input, p, input.settings.pick_min_opacity);
                out.push(Action::Pick(organ));
                out.push(Action::Supply(organ.and_then(|o| self.territory_at(input, p, o))));
            }
        }
        out
    }

    /// Draws the organ-ID buffer of the current view into the viewport's target, organs fainter
    /// than `min_opacity` left out (clicked through); returns it.
    fn draw_ids<'a>(&'a self, input: &Input<'a>, min_opacity: f32) -> Option<(&'a Target, &'a egui_wgpu::RenderState)> {
        let (scene, rs, (target, _)) = (input.scene?, input.gpu?, self.target.as_ref()?);
        let camera = self.camera(scene);
        let frame = FrameInput { section: input.section, ..FrameInput::new(scene.set(), &camera, scene.shown()) };
        scene.renderer().render_ids(&rs.device, &rs.queue, target, &frame, min_opacity);
        Some((target, rs))
    }

    /// The organ-ID buffer of `layout` seen from `nav` at the viewport's size, organs fainter than
    /// a half see-through (as picking sees them); for a quiz's reveal.
    pub fn ids_of(&self, input: &Input, layout: &vbrain::layout::Layout, nav: Navigator) -> Option<Vec<u32>> {
        let (scene, rs, (target, _)) = (input.scene?, input.gpu?, self.target.as_ref()?);
        let camera = nav.camera(&layout.bounds(scene.set()).union(scene.home()));
        let frame = FrameInput::new(scene.set(), &camera, layout);
        scene.renderer().render_ids(&rs.device, &rs.queue, target, &frame, crate::annotate::PICK_OPACITY);
        target.read_ids(&rs.device, &rs.queue).ok()
    }

    /// Labels over the viewport, placed as exports place them (vbrain::labels) and painted by egui
    /// at the same size relative to the viewport.
    fn paint_labels(&self, ui: &egui::Ui, rect: Rect, input: &Input, labels: &crate::annotate::Labels) {
        let Some(scene) = input.scene else { return };
        let Some((ids, size)) = self.read_ids(input) else { return };
        let ppp = ui.ctx().pixels_per_point();
        let px = crate::annotate::text_px(size[1]);
        let font = egui::FontId::proportional(px / ppp);
        let galley = |o: usize| {
            let name = scene.set().organs.get(o).map_or(String::new(), |x| x.name.clone());
            ui.painter().layout_no_wrap(name, font.clone(), egui::Color32::from_rgb(245, 245, 240))
        };
        let (previous, laid_on) = self.labels.take();
        let same = laid_on.as_ref().is_some_and(|(layout, which)| layout == scene.shown() && which == labels);
        let previous = if same { previous } else { Vec::new() };
        let laid = crate::annotate::lay_out(&ids, size, labels, &previous, px, |o| galley(o).size().x * ppp);
        self.labels.replace((laid.clone(), Some((scene.shown().clone(), labels.clone()))));
        let at = |p: [f32; 2]| rect.min + egui::vec2(p[0], p[1]) / ppp;
        let painter = ui.painter_at(rect);
        let s = px / 20.0 / ppp;
        let black = egui::Color32::from_black_alpha(150);
        for crate::annotate::Laid { placed: p, end } in laid {
            painter.line_segment([at(p.anchor), at(end)], egui::Stroke::new(3.0 * s, black));
            painter.line_segment([at(p.anchor), at(end)], egui::Stroke::new(1.4 * s, egui::Color32::WHITE));
            painter.circle(at(p.anchor), 2.2 * s, egui::Color32::WHITE, egui::Stroke::new(1.0 * s, black));
            let plate = Rect::from_min_max(at([p.rect[0], p.rect[1]]), at([p.rect[2], p.rect[3]]));
            painter.rect_filled(plate, 0.0, egui::Color32::from_rgba_unmultiplied(20, 22, 28, 200));
            let text = galley(p.organ);
            let text_at =
                plate.min + egui::vec2(crate::annotate::PAD * px / ppp, (plate.height() - text.size().y) / 2.0);
            painter.galley(text_at, text, egui::Color32::WHITE);
        }
    }

    /// Where a world point appears in the viewport (points), if in front of the camera.
    fn project(&self, scene: &Scene, p: Vec3) -> Option<Pos2> {
        let rect = self.rect;
        let m = self.camera(scene).view_projection(rect.width() / rect.height().max(1.0));
        let c = m * p.extend(1.0);
        (c.w > 1e-6).then(|| {
            let (x, y) = (c.x / c.w, c.y / c.w);
            Pos2::new(rect.min.x + (x + 1.0) / 2.0 * rect.width(), rect.min.y + (1.0 - y) / 2.0 * rect.height())
        })
    }

    /// A handle's dot and the tip of its arrow (12 mm along the plane's normal), in points.
    pub fn handle_points(&self, scene: &Scene, h: &super::action::Handle) -> Option<(Pos2, Pos2)> {
        Some((self.project(scene, h.at)?, self.project(scene, h.at + h.normal * 12.0)?))
    }

    /// The plane whose handle is under a point of the viewport (points).
    fn handle_at(&self, input: &Input, at: Pos2) -> Option<usize> {
        let scene = input.scene?;
        input
            .handles
            .iter()
            .filter_map(|h| {
                let (dot, tip) = self.handle_points(scene, h)?;
                let d = dot.distance(at).min(tip.distance(at));
                (d <= HANDLE_REACH).then_some((d, h.slot))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, slot)| slot)
    }

    /// Millimetres a drag of `delta` points moves a plane: its component along the handle's
    /// arrow on screen, scaled by the arrow's length.
    fn drag_along(&self, scene: &Scene, h: &super::action::Handle, delta: Vec2) -> f32 {
        let Some((dot, tip)) = self.handle_points(scene, h) else { return 0.0 };
        let arrow = Vec2::new(tip.x - dot.x, tip.y - dot.y);
        let len = arrow.length();
        if len < 2.0 {
            // The normal points at the eye: move by the vertical drag instead.
            return -delta.y * 0.25;
        }
        delta.dot(arrow / len) * 12.0 / len
    }

    /// The planes' handles: a dot where each plane crosses the set's middle and an arrow along
    /// its normal, the one dragged brighter.
    fn paint_handles(&self, ui: &egui::Ui, rect: Rect, input: &Input) {
        let Some(scene) = input.scene else { return };
        let painter = ui.painter_at(rect);
        for h in &input.handles {
            let Some((dot, tip)) = self.handle_points(scene, h) else { continue };
            let hot = self.dragging_plane == Some(h.slot);
            let colour =
                if hot { egui::Color32::from_rgb(255, 230, 120) } else { egui::Color32::from_rgb(250, 190, 60) };
            let dark = egui::Stroke::new(4.0, egui::Color32::from_black_alpha(160));
            painter.line_segment([dot, tip], dark);
            painter.line_segment([dot, tip], egui::Stroke::new(2.0, colour));
            painter.circle(tip, 3.5, colour, egui::Stroke::new(1.0, egui::Color32::BLACK));
            painter.circle(dot, 6.0, colour, egui::Stroke::new(1.5, egui::Color32::BLACK));
        }
    }

    /// Which organ is under a point of the viewport (points), from the ID buffer; organs fainter
    /// than `min_opacity` are seen through.
    pub fn pick(&self, input: &Input, at: Pos2, min_opacity: f32) -> Option<usize> {
        let (target, rs) = self.draw_ids(input, min_opacity)?;
        let rect = self.rect;
        let px = ((at.x - rect.min.x) / rect.width() * target.width as f32) as u32;
        let py = ((at.y - rect.min.y) / rect.height() * target.height as f32) as u32;
        match target.read_id_at(&rs.device, &rs.queue, px, py) {
            Ok(Some(id)) if id > 0 => Some(id as usize - 1),
            _ => None,
        }
    }

    /// The arterial territory at a point of the viewport (points) on `organ`, where the set has
    /// territories: where the ray through it first meets the organ on the side the planes keep.
    fn territory_at(&self, input: &Input, at: Pos2, organ: usize) -> Option<u8> {
        let scene = input.scene?;
        let territories = scene.set().territories.as_ref()?;
        let r = self.rect;
        let ndc = Vec2::new((at.x - r.min.x) / r.width() * 2.0 - 1.0, 1.0 - (at.y - r.min.y) / r.height() * 2.0);
        let ray = self.camera(scene).ray(r.width() / r.height().max(1.0), ndc);
        let model = scene.layout().organs.get(organ)?.transform.matrix();
        let planes = if input.section.applies_to(organ) { input.section.active_planes() } else { &[] };
        let kept = |p| !planes.iter().any(|plane| plane.removes(p));
        vbrain::organ_set::territory::under_ray(territories, scene.set().organs[organ].mesh(), model, ray, kept)
    }

    /// The organ-ID buffer of the current view at the viewport's size: organ index + 1 per
    /// physical pixel (row-major), 0 for background. For tests and tools; picking reads single
    /// pixels.
    pub fn read_ids(&self, input: &Input) -> Option<(Vec<u32>, [u32; 2])> {
        let (target, rs) = self.draw_ids(input, input.settings.pick_min_opacity)?;
        Some((target.read_ids(&rs.device, &rs.queue).ok()?, [target.width, target.height]))
    }

    /// The image the viewport shows now, read back from its target.
    pub fn read_image(&self, gpu: &egui_wgpu::RenderState) -> Option<image::RgbaImage> {
        let (target, _) = self.target.as_ref()?;
        target.read_color(&gpu.device, &gpu.queue).ok()
    }

    /// Draws the scene into `rect`, with the statistics overlay; problems come back as actions.
    pub fn draw(&mut self, ui: &egui::Ui, rect: Rect, input: &Input) -> Vec<Action> {
        let mut out = Vec::new();
        let (Some(rs), Some(scene)) = (input.gpu, input.scene) else { return out };
        let camera = self.camera(scene);
        let ppp = ui.ctx().pixels_per_point();
        let (w, h) = (((rect.width() * ppp).round() as u32).max(1), ((rect.height() * ppp).round() as u32).max(1));
        // Moving and slow: a smaller image, scaled up; still frames at full size.
        let scale = if self.moving { self.motion.0.scale() } else { 1.0 };
        let small = |v: u32| ((v as f32 * scale).round() as u32).max(1);
        let fitted = fit_target(&mut self.target, rs, w, h).and_then(|()| {
            if scale < 1.0 {
                fit_target(&mut self.reduced, rs, small(w), small(h))
            } else {
                Ok(())
            }
        });
        if let Err(e) = fitted {
            out.push(Action::NotifyOnce(e.to_string()));
            return out;
        }
        let settings = input.settings;
        let drawn_into = if scale < 1.0 { &mut self.reduced } else { &mut self.target };
        let Some((target, id)) = drawn_into else { return out };
        // Moving and slow: fewer sub-samples, down to one blended pass.
        let transparency = self.motion.0.frame(settings.transparency, self.moving);
        let frame = FrameInput {
            background: settings.background_linear(false),
            transparency,
            moving: self.moving,
            // Still: one more screen-door pass a frame into the image, until all are in.
            refine: !self.moving,
            highlight: input.highlight,
            selection: input.selected,
            section: input.section,
            ..FrameInput::new(scene.set(), &camera, scene.shown())
        };
        let cull_input = scene.renderer().cull_input(&frame, target);
        // With the setting "occlusion", frustum culling where occlusion culling does not pay.
        let (mut cull_settings, mut probe) = (settings.cull, false);
        if cull_settings.mode == vbrain::cull::CullMode::Occlusion && !settings.cull_debug {
            let key = cull_choice::layout_key(scene.shown());
            (cull_settings.mode, probe) = self.cull_choice.next(Instant::now(), key);
        }
        let started = Instant::now();
        let (mut draw, cull) = self.culler.cull_frame(&cull_input, &cull_settings);
        let level = if self.moving { self.motion.0.level() } else { 0 };
        if level > 0 {
            scene.renderer().coarsen(&mut draw, &vec![level; scene.set().organs.len()]);
        }
        let frame = FrameInput { draw: Some(&draw), time_gpu: probe, ..frame };
        let faded = frame.has_transparent();
        let stats = if settings.cull_debug {
            scene.renderer().render_cull_debug(&rs.device, &rs.queue, target, &frame)
        } else {
            scene.renderer().render(&rs.device, &rs.queue, target, &frame)
        };
        let (stats, failed) = match stats {
            Ok(s) => (s, None),
            Err(e) => (RenderStats::default(), Some(format!("drawing failed: {e}"))),
        };
        if probe {
            // Its drawing time: the GPU's, else the wall time until the GPU has finished.
            let draw_ms = stats.gpu_ms.unwrap_or_else(|| {
                let _ = rs.device.poll(wgpu::PollType::wait_indefinitely());
                started.elapsed().as_secs_f64() * 1000.0 - cull.cull_ms
            });
            self.cull_choice.observe(cull_settings.mode, cull.cull_ms + draw_ms);
        }
        let uv = Rect::from_min_max(Pos2::ZERO, Pos2::new(1.0, 1.0));
        ui.painter().image(*id, rect, uv, egui::Color32::WHITE);
        if settings.show_stats {
            let why = (settings.cull.mode == vbrain::cull::CullMode::Occlusion).then(|| self.cull_choice.reason());
            overlays::stats(ui, rect, (settings, &transparency), (&cull, why), &stats, faded);
        }
        overlays::legend(ui, rect, scene);
        if input.labels != crate::annotate::Labels::None {
            self.paint_labels(ui, rect, input, &input.labels);
        } else {
            self.labels.take();
        }
        self.paint_handles(ui, rect, input);
        if let Some(text) = failed {
            out.push(Action::NotifyOnce(text));
        }
        if self.moving || stats.subsamples_done < stats.subsamples_total {
            // Draw once more when the motion stops, and again until the image has every sub-sample.
            ui.ctx().request_repaint();
        }
        self.stats = stats;
        self.cull = cull;
        self.scale = scale;
        self.level = level;
        let now = Instant::now();
        let (quality, last) = &mut self.motion;
        if let (true, Some(last)) = (self.moving, *last) {
            quality.observe_detail(now - last);
        }
        // Only frames whose faded organs screen-door draws tell how it fares.
        let screendoor = faded && settings.transparency.mode.mask_method().is_some();
        if let (true, true, Some(last)) = (self.moving, screendoor, *last) {
            let setting = settings.transparency.interactive_subsamples;
            quality.observe(setting, quality.moving(setting), now - last);
        }
        *last = self.moving.then_some(now);
        self.frame_times.push_back(now);
        while self.frame_times.front().is_some_and(|t| now.duration_since(*t).as_secs_f32() > 1.0) {
            self.frame_times.pop_front();
        }
        out
    }
}

/// Makes `slot` a target of `w` x `h` physical pixels, registered with egui as a texture.
fn fit_target(
    slot: &mut Option<(Target, egui::TextureId)>,
    rs: &egui_wgpu::RenderState,
    w: u32,
    h: u32,
) -> vbrain::Result<()> {
    if slot.as_ref().is_some_and(|(t, _)| t.width == w && t.height == h) {
        return Ok(());
    }
    let t = Target::new(&rs.device, w, h)?;
    let mut egui_renderer = rs.renderer.write();
    let id = match slot.take() {
        Some((_, id)) => {
            egui_renderer.update_egui_texture_from_wgpu_texture(
                &rs.device,
                &t.display_view,
                wgpu::FilterMode::Linear,
                id,
            );
            id
        }
        None => egui_renderer.register_native_texture(&rs.device, &t.display_view, wgpu::FilterMode::Linear),
    };
    *slot = Some((t, id));
    Ok(())
}

/// Moves (Ctrl), rotates (Shift) or resizes (Ctrl+Shift) an organ by a drag, in view space.
fn manipulate(t: &mut Transform, camera: &Camera, delta: Vec2, height: f32, modifiers: egui::Modifiers) {
    let forward = (camera.target - camera.eye).normalize();
    let right = forward.cross(camera.up).normalize();
    let up = right.cross(forward);
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
