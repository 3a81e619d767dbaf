//! The right-hand dock: the inspector, the lesson, the quiz and the sections share one panel as
//! tabs, so that opening them all never squeezes the 3-D view or pushes a panel off the window.
//!
//! - The panel is resizable by its edge and collapses to a strip.
//! - The dock keeps only which tab is in front and whether it is collapsed; what each tab shows
//!   is its component's.

use eframe::egui;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Tab {
    Inspector,
    Lesson,
    Quiz,
    Sections,
}

impl Tab {
    pub fn title(self) -> &'static str {
        match self {
            Tab::Inspector => "Inspector",
            Tab::Lesson => "Lesson",
            Tab::Quiz => "Quiz",
            Tab::Sections => "Sections",
        }
    }
}

/// What the dock keeps between frames.
#[derive(Debug, Default)]
pub struct Dock {
    /// The tab in front, if it is open.
    pub front: Option<Tab>,
    /// The tabs open last frame, to bring a newly opened one to the front.
    open: Vec<Tab>,
    pub collapsed: bool,
}

/// What the tab bar asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Request {
    /// Close this tab (its panel's own close).
    Close(Tab),
}

impl Dock {
    /// Brings `tab` to the front and expands the dock.
    pub fn focus(&mut self, tab: Tab) {
        self.front = Some(tab);
        self.collapsed = false;
    }

    /// The tab to show this frame among `open` (in tab order): a tab that has just opened comes to
    /// the front, except the inspector while another tab is in front (selecting an organ during a
    /// lesson or a quiz keeps them in view); a closed front tab gives way to the last open one.
    pub fn arrange(&mut self, open: &[Tab]) -> Option<Tab> {
        for &tab in open {
            if !self.open.contains(&tab) && (tab != Tab::Inspector || self.front.is_none_or(|f| !open.contains(&f))) {
                self.focus(tab);
            }
        }
        if self.front.is_none_or(|f| !open.contains(&f)) {
            self.front = open.last().copied();
        }
        self.open = open.to_vec();
        self.front
    }

    /// The tab bar: a button per open tab, the collapse button and, for tabs that close from
    /// here, a close button. Returns what was asked.
    pub fn tab_bar(&mut self, ui: &mut egui::Ui, closable: &[Tab]) -> Option<Request> {
        let mut request = None;
        ui.horizontal_wrapped(|ui| {
            let r = ui.small_button("\u{00BB}").on_hover_text("Collapse the panel");
            super::widgets::accessible(&r, "Collapse panel");
            if r.clicked() {
                self.collapsed = true;
            }
            for &tab in &self.open {
                let r = ui.selectable_label(self.front == Some(tab), tab.title());
                super::widgets::accessible(&r, format!("{} tab", tab.title()));
                if r.clicked() {
                    self.front = Some(tab);
                }
            }
            if let Some(front) = self.front.filter(|f| closable.contains(f)) {
                let r = ui.small_button("\u{00D7}").on_hover_text(format!("Close {}", front.title()));
                super::widgets::accessible(&r, format!("Close {} tab", front.title()));
                if r.clicked() {
                    request = Some(Request::Close(front));
                }
            }
        });
        ui.separator();
        request
    }

    /// The collapsed dock: a strip with a button per open tab that expands it on that tab.
    pub fn strip(&mut self, ui: &mut egui::Ui) {
        ui.vertical_centered(|ui| {
            let r = ui.small_button("\u{00AB}").on_hover_text("Expand the panel");
            super::widgets::accessible(&r, "Expand panel");
            if r.clicked() {
                self.collapsed = false;
            }
            for &tab in &self.open.clone() {
                let r = ui.small_button(&tab.title()[..1]).on_hover_text(tab.title());
                super::widgets::accessible(&r, format!("{} tab", tab.title()));
                if r.clicked() {
                    self.focus(tab);
                }
            }
        });
    }
}

/// The organ panel's width at first (points).
pub const ORGAN_PANEL_WIDTH: f32 = 300.0;
/// The dock's width at first, and the narrowest it can be dragged (points).
pub const DOCK_WIDTH: [f32; 2] = [280.0, 200.0];

/// The widest the organ panel and the dock may be in a window `width` points wide: together at
/// most half of it from 1280 points up, so the 3-D view keeps at least the other half; in a
/// smaller window each may still take its default width (300 and 280 points).
pub fn side_limits(width: f32) -> (f32, f32) {
    ((width * 0.26).max(ORGAN_PANEL_WIDTH), (width * 0.24).max(DOCK_WIDTH[0]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_newly_opened_tab_comes_to_the_front_but_the_inspector_waits() {
        let mut dock = Dock::default();
        assert_eq!(dock.arrange(&[Tab::Inspector]), Some(Tab::Inspector));
        assert_eq!(dock.arrange(&[Tab::Inspector, Tab::Lesson]), Some(Tab::Lesson));
        assert_eq!(dock.arrange(&[Tab::Inspector, Tab::Lesson, Tab::Quiz]), Some(Tab::Quiz));
        // The quiz closes: the last open tab comes back.
        assert_eq!(dock.arrange(&[Tab::Inspector, Tab::Lesson]), Some(Tab::Lesson));
        // Deselect, then select during the lesson: the lesson stays in front.
        assert_eq!(dock.arrange(&[Tab::Lesson]), Some(Tab::Lesson));
        assert_eq!(dock.arrange(&[Tab::Inspector, Tab::Lesson]), Some(Tab::Lesson));
        assert_eq!(dock.arrange(&[]), None);
    }

    #[test]
    fn both_side_panels_leave_half_the_window() {
        for width in [1280.0, 1440.0, 1600.0, 1920.0] {
            let (left, right) = side_limits(width);
            assert!(left + right <= width * 0.5 + 1e-3, "{width}: {left} + {right}");
            assert!(left >= 300.0 && right >= 280.0, "{width}: the defaults fit");
        }
    }
}
