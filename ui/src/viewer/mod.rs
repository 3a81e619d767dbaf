//! The desktop viewer.

pub mod app;
pub mod export;
pub mod files;
pub mod jobs;
mod panels;
pub mod settings;
pub mod viewport;

pub use app::{App, AppOptions};

/// Sets the accessible name of a widget (AccessKit), so screen readers and tests find it.
pub fn accessible(response: &eframe::egui::Response, label: impl Into<String>) {
    let label = label.into();
    response.ctx.accesskit_node_builder(response.id, |node| node.set_label(label));
}
