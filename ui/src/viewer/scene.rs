//! The scene: a loaded organ set with its renderer and the user's layout.
//!
//! - The layout is in world space, millimetres RAS.
//! - The layout changes only through [`Scene::apply`], one [`Edit`] at a time, and through undo
//!   and redo of its [`History`]; everything else reads it.
//! - The builders (`toggle_*`, `reset_layout`) make the edits that depend on the current state.

use std::path::PathBuf;
use vbrain::edit::{Edit, Organs};
use vbrain::history::{gesture_of, History};
use vbrain::layout::Layout;
use vbrain::mesh::Bounds;
use vbrain::organ_set::OrganSet;
use vbrain::render::Renderer;

pub struct Scene {
    set: OrganSet,
    /// Where it was opened from (a folder, a file, or several files joined by the title).
    source: Vec<PathBuf>,
    layout: Layout,
    renderer: Renderer,
    /// What the camera frames on reset: the organs shown when the set was opened (world space).
    home: Bounds,
    /// Per organ, the opacity the transparency toggle returns to: the last translucent one set.
    last_translucent: Vec<f32>,
    history: History,
    /// Changes to the layout so far (edits, undos, redos, a scene applied): what "unsaved" compares.
    changes: u64,
    /// What is drawn instead of the layout while a lesson step eases in.
    shown: Option<Layout>,
}

impl Scene {
    /// The set with its default layout.
    pub fn new(set: OrganSet, source: Vec<PathBuf>, renderer: Renderer) -> Scene {
        let layout = Layout::new(&set);
        let home = layout.bounds(&set);
        let last_translucent = set.organs.iter().map(|o| if o.opacity < 1.0 { o.opacity } else { 0.4 }).collect();
        Scene {
            set,
            source,
            layout,
            renderer,
            home,
            last_translucent,
            history: History::default(),
            changes: 0,
            shown: None,
        }
    }

    pub fn set(&self) -> &OrganSet {
        &self.set
    }

    pub fn source(&self) -> &[PathBuf] {
        &self.source
    }

    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The layout as drawn: the layout, or the eased state of a step change under way.
    pub fn shown(&self) -> &Layout {
        self.shown.as_ref().unwrap_or(&self.layout)
    }

    /// Draws `layout` instead of the layout (a transition's state); `None` draws the layout.
    pub fn show_instead(&mut self, layout: Option<Layout>) {
        self.shown = layout.filter(|l| l.organs.len() == self.layout.organs.len());
    }

    pub fn renderer(&self) -> &Renderer {
        &self.renderer
    }

    pub fn home(&self) -> Bounds {
        self.home
    }

    /// World bounds of one organ as placed now.
    pub fn organ_bounds(&self, organ: usize) -> Bounds {
        self.set.organs[organ].mesh().bounds().transformed(&self.layout.organs[organ].transform.matrix())
    }

    /// Applies an edit as one undoable step named after it; while `dragging` (a pointer button is
    /// down), edits of the same gesture (a slider, a mouse drag) merge into one step. Opacity edits
    /// remember translucent values for the transparency toggle.
    pub fn apply(&mut self, edit: &Edit, dragging: bool) {
        let label = {
            let names = |i: usize| self.set.organs.get(i).map_or("?", |o| o.name.as_str());
            edit.describe(&names)
        };
        let gesture = if dragging { gesture_of(edit) } else { None };
        if self.history.apply(&mut self.layout, edit.clone(), label, gesture) {
            self.changes += 1;
        }
        if let Edit::Opacity { organs, .. } | Edit::Opacities { organs, .. } = edit {
            for i in organs.indices(self.layout.organs.len()) {
                let opacity = self.layout.organs[i].opacity;
                if opacity > 0.0 && opacity < 1.0 {
                    self.last_translucent[i] = opacity;
                }
            }
        }
    }

    /// The drag that was going on ended: the next edit is a new step.
    pub fn end_gesture(&mut self) {
        self.history.end_gesture();
    }

    /// Undoes the last step; returns what it was.
    pub fn undo(&mut self) -> Option<String> {
        let done = self.history.undo(&mut self.layout);
        self.changes += u64::from(done.is_some());
        done
    }

    /// Redoes the last undone step; returns what it was.
    pub fn redo(&mut self) -> Option<String> {
        let done = self.history.redo(&mut self.layout);
        self.changes += u64::from(done.is_some());
        done
    }

    /// Records a change made outside the layout (a lesson edited) as an undoable step, in order
    /// with layout edits.
    pub fn record_outside(&mut self, label: String) {
        self.history.record_outside(label);
    }

    /// Forgets the outside steps (their lesson was closed).
    pub fn forget_outside(&mut self) {
        self.history.forget_outside();
    }

    /// How many changes the layout has seen (compare two values to tell whether it changed).
    pub fn changes(&self) -> u64 {
        self.changes
    }

    /// Something saved with the scene besides the layout changed (its clip planes, the organs kept
    /// whole, its labels): counted as a change, so it is saved or asked about, not undone.
    pub fn touch(&mut self) {
        self.changes += 1;
    }

    pub fn history(&self) -> &History {
        &self.history
    }

    /// Replaces the layout (a scene opened over this set); the history starts again.
    pub fn set_layout(&mut self, layout: Layout) {
        if layout.organs.len() == self.layout.organs.len() {
            self.layout = layout;
            self.history.clear();
            self.changes += 1;
        }
    }

    /// Opaque <-> the organ's last translucent opacity.
    pub fn toggle_transparency(&self, organ: usize) -> Edit {
        let opacity = if self.layout.organs[organ].opacity >= 1.0 { self.last_translucent[organ] } else { 1.0 };
        Edit::Opacity { organs: Organs::One(organ), opacity }
    }

    /// A group's transparency: all opaque -> each organ's last translucent opacity, else opaque.
    pub fn toggle_group_transparency(&self, name: &str, organs: &[usize]) -> Edit {
        let group = Organs::Group { name: name.to_string(), organs: organs.to_vec() };
        if organs.iter().all(|&i| self.layout.organs[i].opacity >= 1.0) {
            Edit::Opacities { organs: group, opacities: organs.iter().map(|&i| self.last_translucent[i]).collect() }
        } else {
            Edit::Opacity { organs: group, opacity: 1.0 }
        }
    }

    /// Shown <-> hidden.
    pub fn toggle_visible(&self, organ: usize) -> Edit {
        Edit::Visible { organs: Organs::One(organ), visible: !self.layout.organs[organ].visible }
    }

    /// Back to the set's defaults: visibility, opacity, colour, no transforms.
    pub fn reset_layout(&self) -> Edit {
        Edit::reset(&self.set, Organs::All)
    }
}
