//! The app's right-hand dock ([`crate::viewer::dock`]): which tabs are open (the inspector while
//! an organ is selected, the lesson, the quiz, the sections), the panel with its tab bar, and the
//! tab in front drawn by its component.
//!
//! - The front tab's actions are performed at once.
//! - A child module of the app, so it reaches its state.

use super::App;
use crate::viewer::dock::{Request, Tab, DOCK_WIDTH};
use crate::viewer::inspector::{inspector, Marks};
use eframe::egui::{self, Panel};

impl App {
    /// The tabs open now, in tab order.
    fn dock_tabs(&self) -> Vec<Tab> {
        let open = [
            (Tab::Inspector, self.settings.show_inspector && self.selected.is_some()),
            (Tab::Lesson, self.lesson.is_open()),
            (Tab::Quiz, self.quiz.open),
            (Tab::Sections, self.sections.open),
        ];
        open.into_iter().filter(|(_, on)| *on).map(|(tab, _)| tab).collect()
    }

    /// The dock, at most `max_width` points wide; nothing while no tab is open.
    pub(super) fn dock_panel(&mut self, ui: &mut egui::Ui, max_width: f32) {
        let ctx = ui.ctx().clone();
        let tabs = self.dock_tabs();
        let Some(front) = self.dock.arrange(&tabs) else { return };
        if self.dock.collapsed {
            Panel::right("dock collapsed").exact_size(30.0).resizable(false).show(ui, |ui| self.dock.strip(ui));
            return;
        }
        let panel = Panel::right("dock")
            .default_size(DOCK_WIDTH[0])
            .min_size(DOCK_WIDTH[1])
            .max_size(max_width)
            .resizable(true);
        let actions = panel
            .show(ui, |ui| {
                let request = self.dock.tab_bar(ui, &[Tab::Sections]);
                if request == Some(Request::Close(Tab::Sections)) {
                    self.sections.open = false;
                    return Vec::new();
                }
                // Whatever a tab holds scrolls inside the dock, never past the window's edge.
                let scroll = egui::ScrollArea::vertical().id_salt(front).auto_shrink([false; 2]);
                scroll
                    .show(ui, |ui| match front {
                        Tab::Inspector => self.inspector_tab(ui),
                        Tab::Lesson => self.lesson.show(ui),
                        Tab::Quiz => self.quiz_tab(ui),
                        Tab::Sections => {
                            self.sections_tab(ui);
                            Vec::new()
                        }
                    })
                    .inner
            })
            .inner;
        self.perform(&ctx, actions);
    }

    fn inspector_tab(&self, ui: &mut egui::Ui) -> Vec<crate::viewer::Action> {
        let (Some(scene), Some(sel)) = (self.scene.as_ref(), self.selected) else { return Vec::new() };
        let marks = Marks {
            whole: self.sections.current.whole.contains(&sel),
            labelled: self.labels().wants(sel),
            supply: self.supply,
        };
        inspector(ui, scene, sel, marks)
    }

    fn quiz_tab(&mut self, ui: &mut egui::Ui) -> Vec<crate::viewer::Action> {
        let now = ui.input(|i| i.time);
        let scene = self.scene.as_ref();
        let organ = |o: usize| scene.and_then(|s| s.set().organs.get(o));
        let name = |o: usize| organ(o).map_or(String::new(), |x| x.name.clone());
        let info = |o: usize| organ(o).map_or(String::new(), |x| x.info.clone());
        let artery = |k: usize| {
            let territories = scene.and_then(|s| s.set().territories.as_ref());
            territories.and_then(|t| t.arteries.get(k)).map_or(String::new(), |a| format!("{} ({})", a.name, a.short))
        };
        let groups = scene.map(|s| s.set().group_paths()).unwrap_or_default();
        self.quiz.show(ui, (&name, &artery), &info, &groups, now)
    }
}
