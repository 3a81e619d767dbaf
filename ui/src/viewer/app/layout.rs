//! The app's frame laid out: the menu bar, the status bar, the organ panel on the left, the dock on
//! the right, and between them the views (the 3-D viewport, the slice panes, or both, as View >
//! Layout says). Each component's actions are performed before the next one draws. A child module
//! of the app, so it reaches its state.
//!
//! - Sizes are egui points; the slice panes take the right 36 % beside the 3-D view.

use super::{dock, menus, status, App, MenuState, Status};
use crate::viewer::settings::ViewLayout;
use eframe::egui;

impl App {
    /// The menu bar, the status bar, the organ panel and the dock.
    pub(super) fn bars_and_panels(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        use egui::Panel;
        let state = MenuState {
            scene: self.scene.as_ref(),
            has_database: self.viewport.has_database(),
            fly: self.viewport.fly(),
            job: self.job(),
        };
        let labels = self.settings.labels;
        let actions = Panel::top("menu").show(ui, |ui| menus::menu_bar(ui, &state, &mut self.settings)).inner;
        if self.settings.labels != labels {
            self.touch_scene();
        }
        self.perform(ctx, actions);
        let status = Status {
            scene: self.scene.as_ref(),
            loading: self.is_loading(),
            frame: (self.viewport.stats(), self.viewport.fps(), self.viewport.fly()),
            detail: (self.viewport.scale(), self.viewport.level()),
            occluders: self.viewport.cull_stats().source,
            settings: &self.settings,
            selected: self.selected,
        };
        Panel::bottom("status").show(ui, |ui| status::status_bar(ui, &status));
        let (panel, scene, selected) = (&mut self.organ_panel, self.scene.as_ref(), self.selected);
        let quiz = self.quiz.answering();
        // Side panels never take the 3-D view's place, whatever their contents' widths.
        let (left_max, right_max) = dock::side_limits(ui.max_rect().width());
        let actions = Panel::left("organs")
            .default_size(dock::ORGAN_PANEL_WIDTH)
            .max_size(left_max)
            .resizable(true)
            .show(ui, |ui| panel.show(ui, scene, selected, quiz))
            .inner;
        self.perform(ctx, actions);
        self.dock_panel(ui, right_max);
    }

    /// The 3-D viewport and the slice panes, in the space the panels leave.
    pub(super) fn views(&mut self, ui: &mut egui::Ui, ctx: &egui::Context) {
        let full = ui.available_rect_before_wrap();
        let layout = if self.scene.is_some() { self.settings.view_layout } else { ViewLayout::ThreeD };
        let (three_d, slices) = match layout {
            ViewLayout::ThreeD => (Some(full), None),
            ViewLayout::ThreeDWithSlices => {
                let split = full.left() + full.width() * 0.64;
                let (a, b) = full.split_left_right_at_x(split);
                (Some(a), Some(b.shrink2(egui::vec2(2.0, 0.0))))
            }
            ViewLayout::Slices => (None, Some(full)),
        };
        if let Some(r) = three_d {
            ui.scope_builder(egui::UiBuilder::new().max_rect(r), |ui| {
                let (rect, response) = self.viewport.allocate(ui);
                let actions = self.with_viewport(|v, input| v.input(ui, &response, input));
                self.perform(ctx, actions);
                let actions = self.with_viewport(|v, input| v.draw(ui, rect, input));
                self.perform(ctx, actions);
            });
        }
        if let (Some(r), Some(scene)) = (slices, &self.scene) {
            self.slices.radiological = !self.settings.neurological;
            // The selected organ outlined boldly; while a quiz asks, no names on hover and only a
            // "name it" structure outlined.
            self.slices.names = !self.quiz.answering();
            let asked = self.quiz.run.as_ref().and_then(|r| r.current()).filter(|_| self.quiz.answering());
            self.slices.highlight = match asked {
                Some(q) => (q.kind != vbrain::quiz::Kind::Locate).then_some(q.organ),
                None => self.selected,
            };
            self.slices.window = self.sections.current.faces.window;
            let actions = self.slices.show(ui, r, scene.set(), scene.shown(), self.selected);
            self.perform(ctx, actions);
        }
    }
}
