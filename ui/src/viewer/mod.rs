//! The desktop viewer (eframe + wgpu).
//!
//! - The scene ([`scene::Scene`]: set, layout, renderer) is data that changes only by
//!   [`vbrain::edit::Edit`]s.
//! - Components (menus, organ panel, inspector, viewport, windows, status) read it and return
//!   [`Action`]s: edits, and commands for the rest (open, import, export, camera, selection);
//!   [`App::perform`] carries them out in one place.
//! - Components keep only their own UI state (a filter, a path field, the camera).
//! - Keyboard shortcuts come from one table ([`shortcuts`]).
//! - Input is in egui points, render targets in physical pixels, the scene in world millimetres
//!   (RAS).
//! - Modules: [`about`] (Help > About), [`dock`] (the right-hand panels as tabs), [`app`] (state,
//!   frame, actions), [`dialogs`] (the file windows), [`menus`], [`panels`] (organ tree),
//!   [`inspector`], [`viewport`] (drawing, camera, picking, organ moves by mouse), [`dialogs::files`]
//!   (open, import, drops), [`dialogs::export`] (screenshots), [`status`] (status bar, notifications),
//!   [`shortcuts`], [`jobs`] (work off the UI thread), [`settings`] (what persists), [`widgets`]
//!   (shared widgets), [`window`] (the native window), [`paths`] (the viewer's files),
//!   [`welcome`] (the view when no set is found).

pub mod about;
pub mod action;
pub mod app;
pub mod dialogs;
pub mod dock;
pub mod document;
pub mod inspector;
pub mod jobs;
pub mod lesson_panel;
pub mod menus;
pub mod panels;
pub mod paths;
pub mod quiz_panel;
pub mod scene;
pub mod sections;
pub mod settings;
pub mod shortcuts;
pub mod slice_panes;
pub mod status;
pub mod viewport;
pub mod welcome;
pub mod widgets;
pub mod window;

pub use action::Action;
pub use app::{App, AppOptions};
pub use window::run;
