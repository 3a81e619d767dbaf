//! What the viewer remembers between sessions (eframe storage): recent sets, the last set, and
//! render and export settings.
//!
//! - Window layout is persisted by eframe itself.
//! - A store that cannot be read falls back to the defaults.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use vbrain::labels::Which;
use vbrain::organ_set::OrganSet;

pub const STORAGE_KEY: &str = "vbrain-settings";
const MAX_RECENT: usize = 10;

/// The largest exported side, in pixels.
pub const MAX_EXPORT_SIDE: u32 = 8192;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Organ sets and mesh files opened, newest first.
    pub recent: Vec<PathBuf>,
    /// The set open when the viewer was last closed.
    pub last_set: Option<PathBuf>,
    /// Open the last set at start instead of the default brain (when no path is given).
    pub reopen_last: bool,
    /// Viewport background, sRGB.
    pub background: [f32; 3],
    /// Clicks pick the nearest organ at least this opaque (so clicks reach through faded organs).
    pub pick_min_opacity: f32,
    pub show_inspector: bool,
    pub show_stats: bool,
    pub export: ExportSettings,
    /// Culling of hidden tissue in the viewport (the image is the same either way).
    pub cull: vbrain::cull::CullSettings,
    /// Show what culling removed, bright, through a translucent grey model (thesis Figure 21).
    pub cull_debug: bool,
    /// How faded organs are drawn: mode, mask sub-samples, region size, K.
    pub transparency: vbrain::transparency::TransparencySettings,
    /// Which organs are named with labels, in the viewport and in exports.
    pub labels: LabelMode,
    /// The 3-D view, slice panes, or both (View > Layout).
    #[serde(default)]
    pub view_layout: ViewLayout,
    /// Slice panes in neurological display (the patient's right on the right).
    #[serde(default)]
    pub neurological: bool,
}

/// How the central area is shared between the 3-D view and the slice panes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ViewLayout {
    #[default]
    ThreeD,
    ThreeDWithSlices,
    Slices,
}

impl ViewLayout {
    pub const ALL: [ViewLayout; 3] = [ViewLayout::ThreeD, ViewLayout::ThreeDWithSlices, ViewLayout::Slices];

    pub fn name(self) -> &'static str {
        match self {
            ViewLayout::ThreeD => "3-D",
            ViewLayout::ThreeDWithSlices => "3-D with slices",
            ViewLayout::Slices => "Slices",
        }
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum LabelMode {
    #[default]
    None,
    Selected,
    /// The organs chosen with the inspector's "Label".
    Chosen,
    All,
}

impl LabelMode {
    pub const ALL: [LabelMode; 4] = [LabelMode::None, LabelMode::Selected, LabelMode::Chosen, LabelMode::All];

    pub fn name(self) -> &'static str {
        match self {
            LabelMode::None => "No labels",
            LabelMode::Selected => "Label the selected organ",
            LabelMode::Chosen => "Label the chosen organs (inspector: Label)",
            LabelMode::All => "Label every organ seen",
        }
    }

    /// The labels this mode draws, with `selected` the selection and `chosen` the organs chosen.
    pub fn labels(self, selected: Option<usize>, chosen: &[usize]) -> crate::annotate::Labels {
        match self {
            LabelMode::None => crate::annotate::Labels::None,
            LabelMode::Selected => crate::annotate::Labels::Chosen(selected.into_iter().collect()),
            LabelMode::Chosen => crate::annotate::Labels::Chosen(chosen.to_vec()),
            LabelMode::All => crate::annotate::Labels::All,
        }
    }

    /// The mode as scene files and lesson steps name it, with `chosen` the organs of `set` chosen.
    pub fn which(self, chosen: &[usize], set: &OrganSet) -> Which {
        match self {
            LabelMode::None => Which::None,
            LabelMode::Selected => Which::Selected,
            LabelMode::Chosen => Which::Chosen(set.ids(chosen)),
            LabelMode::All => Which::All,
        }
    }

    /// The mode and chosen organs of what a scene file or lesson step names.
    pub fn of_which(which: &Which, set: &OrganSet) -> (LabelMode, Vec<usize>) {
        match which {
            Which::None => (LabelMode::None, Vec::new()),
            Which::Selected => (LabelMode::Selected, Vec::new()),
            Which::All => (LabelMode::All, Vec::new()),
            Which::Chosen(names) => (LabelMode::Chosen, Which::chosen(names, set).0),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ExportSize {
    Viewport,
    Double,
    Quadruple,
    Custom,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct ExportSettings {
    pub size: ExportSize,
    pub custom: [u32; 2],
    pub transparent: bool,
    /// Folder of the last export; the current folder if none.
    pub folder: Option<PathBuf>,
}

impl Default for ExportSettings {
    fn default() -> Self {
        ExportSettings { size: ExportSize::Double, custom: [1920, 1080], transparent: false, folder: None }
    }
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            recent: Vec::new(),
            last_set: None,
            reopen_last: false,
            background: crate::background_srgb(),
            pick_min_opacity: 0.5,
            show_inspector: true,
            show_stats: false,
            export: ExportSettings::default(),
            cull: vbrain::cull::CullSettings::default(),
            cull_debug: false,
            transparency: Default::default(),
            labels: LabelMode::None,
            view_layout: Default::default(),
            neurological: false,
        }
    }
}

impl Settings {
    /// Reads the settings; missing or unreadable (corrupted) entries give the defaults, and values
    /// out of what the menus offer are brought into it ([`Settings::clamped`]).
    pub fn load(storage: Option<&dyn eframe::Storage>) -> Settings {
        storage.and_then(|s| eframe::get_value::<Settings>(s, STORAGE_KEY)).unwrap_or_default().clamped()
    }

    /// The settings with every value inside the range its menu offers (a hand-edited settings file
    /// is input): culling raster 32..=512 square, occluder triangles 128..=131,072, ratios and
    /// colours 0..=1, the transparency settings as [`vbrain::transparency::TransparencySettings::clamped`] brings
    /// them, export sizes 1..=8192. A value that is not a number takes its default.
    pub fn clamped(mut self) -> Settings {
        let d = Settings::default();
        let unit = |v: f32, default: f32| if v.is_finite() { v.clamp(0.0, 1.0) } else { default };
        let c = &mut self.cull;
        c.width = c.width.clamp(32, 512);
        c.height = c.width;
        c.occluder_triangles = c.occluder_triangles.clamp(128, 131_072);
        c.adaptive_ratio = unit(c.adaptive_ratio, d.cull.adaptive_ratio);
        c.hole_tolerance = c.hole_tolerance.filter(|t| t.is_finite()).map(|t| t.clamp(0.0, 0.5));
        c.occluder_leaves = c.occluder_leaves.map(|n| n.clamp(1, 1 << 20));
        self.transparency = self.transparency.clamped();
        for (v, default) in self.background.iter_mut().zip(d.background) {
            *v = unit(*v, default);
        }
        self.pick_min_opacity = unit(self.pick_min_opacity, d.pick_min_opacity);
        self.export.custom = self.export.custom.map(|v| v.clamp(1, MAX_EXPORT_SIDE));
        self.recent.truncate(MAX_RECENT);
        self
    }

    pub fn save(&self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, STORAGE_KEY, self);
    }

    /// Puts `path` first in the recent list.
    pub fn remember(&mut self, path: &Path) {
        let path = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
        self.recent.retain(|p| p != &path);
        self.recent.insert(0, path.clone());
        self.recent.truncate(MAX_RECENT);
        self.last_set = Some(path);
    }

    /// The background as linear RGBA for the renderer.
    pub fn background_linear(&self, transparent: bool) -> [f32; 4] {
        crate::background_linear(self.background, transparent)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use eframe::Storage;
    use std::collections::HashMap;

    #[derive(Default)]
    struct Store(HashMap<String, String>);

    impl eframe::Storage for Store {
        fn get_string(&self, key: &str) -> Option<String> {
            self.0.get(key).cloned()
        }
        fn set_string(&mut self, key: &str, value: String) {
            self.0.insert(key.into(), value);
        }
        fn remove_string(&mut self, key: &str) {
            self.0.remove(key);
        }
        fn flush(&mut self) {}
    }

    #[test]
    fn round_trip_and_corruption() {
        let mut s = Settings { reopen_last: true, ..Default::default() };
        s.remember(Path::new("/tmp/a"));
        s.remember(Path::new("/tmp/b"));
        s.remember(Path::new("/tmp/a"));
        assert_eq!(s.recent, [PathBuf::from("/tmp/a"), PathBuf::from("/tmp/b")]);
        let mut store = Store::default();
        s.save(&mut store);
        assert_eq!(Settings::load(Some(&store)), s);
        store.set_string(STORAGE_KEY, "(recent: [[[ garbage".into());
        assert_eq!(Settings::load(Some(&store)), Settings::default());
        assert_eq!(Settings::load(None), Settings::default());
        // Unknown or missing fields do not lose the rest.
        store.set_string(STORAGE_KEY, "(show_stats: true, future_field: 3)".into());
        assert!(Settings::load(Some(&store)).show_stats);
    }

    #[test]
    fn a_hand_edited_settings_file_is_brought_into_range() {
        let mut store = Store::default();
        let mut wild = Settings::default();
        (wild.cull.width, wild.cull.height) = (65535, 65535);
        wild.cull.adaptive_ratio = f32::NAN;
        wild.transparency.subsamples = 1000;
        wild.transparency.region_px = 0;
        wild.transparency.k = 999;
        wild.background = [f32::INFINITY, -3.0, 0.5];
        wild.export.custom = [0, 1_000_000];
        wild.save(&mut store);
        let s = Settings::load(Some(&store));
        assert_eq!((s.cull.width, s.cull.height), (512, 512));
        assert_eq!(s.cull.adaptive_ratio, Settings::default().cull.adaptive_ratio);
        assert_eq!((s.transparency.subsamples, s.transparency.region_px, s.transparency.k), (64, 4, 64));
        assert_eq!(s.background, [Settings::default().background[0], 0.0, 0.5]);
        assert_eq!(s.export.custom, [1, super::MAX_EXPORT_SIDE]);
        // What the menus offer is kept as it is.
        assert_eq!(Settings::default().clamped(), Settings::default());
    }

    #[test]
    fn default_background_is_the_render_background() {
        let b = Settings::default().background_linear(false);
        for i in 0..3 {
            assert!((b[i] - crate::BACKGROUND[i]).abs() < 1e-4);
        }
    }
}
