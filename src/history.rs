//! Undo and redo of layout edits: a bounded history of steps, each an [`Edit`] with the inverse
//! [`crate::edit::apply`] returned for it and a label for people ("fade Left precentral gyrus").
//!
//! - A continuous gesture (a slider or mouse drag) is one step: edits recorded with the same
//!   [`Gesture`] key while it lasts merge into the step it began, which keeps the state from
//!   before the gesture.
//! - Camera moves are not edits and never enter the history.
//! - Steps made outside the layout (a lesson's steps edited) take their place in the same order:
//!   [`History::record_outside`] records one by its label, undo and redo of it leave the layout
//!   alone, and [`History::undo_is_outside`] tells the owner to undo its own change too.

use crate::edit::{apply, Edit, Organs};
use crate::layout::Layout;

/// Steps kept; the oldest are dropped beyond this.
pub const DEFAULT_LIMIT: usize = 200;

/// What makes consecutive edits one step: the same gesture on the same thing (e.g. dragging the
/// opacity slider of organ 12). Edits without a key are steps of their own.
pub type Gesture = (&'static str, usize);

/// The gesture an edit continues while a drag lasts: a slider or a mouse drag changes the opacity,
/// colour or transform of the same organs frame after frame.
pub fn gesture_of(edit: &Edit) -> Option<Gesture> {
    let first = |organs: &Organs| match organs {
        Organs::One(i) => *i,
        Organs::Group { organs, .. } | Organs::List(organs) => organs.first().map_or(usize::MAX, |&i| i),
        Organs::All => usize::MAX,
    };
    match edit {
        Edit::Opacity { organs, .. } => Some(("opacity", first(organs))),
        Edit::Colour { organs, .. } => Some(("colour", first(organs))),
        Edit::Transform { organ, .. } => Some(("transform", *organ)),
        _ => None,
    }
}

#[derive(Clone, Debug, PartialEq)]
struct Step {
    label: String,
    /// Applied to redo (for a merged gesture, a restore of where it ended).
    redo: Edit,
    /// Applied to undo: restores the state from before the step.
    undo: Edit,
    gesture: Option<Gesture>,
    /// A step made outside the layout: its owner undoes and redoes it.
    outside: bool,
}

/// An edit that changes nothing (an outside step's part in the layout).
fn nothing() -> Edit {
    Edit::Restore { organs: Organs::List(Vec::new()), states: Vec::new() }
}

#[derive(Clone, Debug)]
pub struct History {
    done: Vec<Step>,
    undone: Vec<Step>,
    limit: usize,
    /// The gesture of the last step is still going on (further edits with its key merge).
    open: bool,
}

impl Default for History {
    fn default() -> Self {
        History::new(DEFAULT_LIMIT)
    }
}

impl History {
    pub fn new(limit: usize) -> History {
        History { done: Vec::new(), undone: Vec::new(), limit: limit.max(1), open: false }
    }

    /// Applies `edit` to `layout` and records it (unless it changed nothing); returns whether it
    /// changed the layout. With `gesture`, an edit that continues the last step's open gesture
    /// merges into it.
    pub fn apply(&mut self, layout: &mut Layout, edit: Edit, label: String, gesture: Option<Gesture>) -> bool {
        let inverse = apply(layout, &edit);
        let changed = !matches!(&inverse, Edit::Restore { states, .. } if states.is_empty());
        // Only organ edits merge (their inverses are restores); a colouring change is a step.
        let organs = matches!(inverse, Edit::Restore { .. });
        let continues = |s: &Step| {
            self.open && organs && matches!(s.undo, Edit::Restore { .. }) && gesture.is_some() && s.gesture == gesture
        };
        let merge_into = match self.done.last_mut() {
            Some(last) if continues(last) => Some(last),
            _ => None,
        };
        if let Some(last) = merge_into {
            // The step still undoes to the state from before the gesture: organs this edit changed
            // for the first time join its restore, with their states from before this edit.
            if let (
                Edit::Restore { organs: Organs::List(kept), states: kept_states },
                Edit::Restore { organs, states },
            ) = (&mut last.undo, inverse)
            {
                for (i, s) in organs.indices(layout.organs.len()).into_iter().zip(states) {
                    if !kept.contains(&i) {
                        kept.push(i);
                        kept_states.push(s);
                    }
                }
                // Redo restores where the gesture ended, for every organ it changed.
                let ended = kept.iter().map(|&i| layout.organs[i]).collect();
                last.redo = Edit::Restore { organs: Organs::List(kept.clone()), states: ended };
            }
            last.label = label;
        } else {
            if !changed {
                return false;
            }
            self.push(Step { label, redo: edit, undo: inverse, gesture, outside: false });
        }
        self.undone.clear();
        self.open = gesture.is_some();
        changed
    }

    fn push(&mut self, step: Step) {
        self.done.push(step);
        if self.done.len() > self.limit {
            self.done.remove(0);
        }
    }

    /// Records a step made outside the layout, by its label; what was undone cannot be redone.
    pub fn record_outside(&mut self, label: String) {
        self.push(Step { label, redo: nothing(), undo: nothing(), gesture: None, outside: true });
        self.undone.clear();
        self.open = false;
    }

    /// Is the step [`History::undo`] would undo one made outside the layout?
    pub fn undo_is_outside(&self) -> bool {
        self.done.last().is_some_and(|s| s.outside)
    }

    pub fn redo_is_outside(&self) -> bool {
        self.undone.last().is_some_and(|s| s.outside)
    }

    /// Forgets the steps made outside the layout (their owner is gone: a lesson was closed).
    pub fn forget_outside(&mut self) {
        self.done.retain(|s| !s.outside);
        self.undone.retain(|s| !s.outside);
    }

    /// Ends the current gesture (the drag was released): the next edit is a new step.
    pub fn end_gesture(&mut self) {
        self.open = false;
    }

    /// Undoes the last step; returns its label.
    pub fn undo(&mut self, layout: &mut Layout) -> Option<String> {
        let step = self.done.pop()?;
        apply(layout, &step.undo);
        let label = step.label.clone();
        self.undone.push(step);
        self.open = false;
        Some(label)
    }

    /// Redoes the last undone step; returns its label.
    pub fn redo(&mut self, layout: &mut Layout) -> Option<String> {
        let step = self.undone.pop()?;
        apply(layout, &step.redo);
        let label = step.label.clone();
        self.done.push(step);
        self.open = false;
        Some(label)
    }

    /// The label of what [`History::undo`] would undo.
    pub fn undo_label(&self) -> Option<&str> {
        self.done.last().map(|s| s.label.as_str())
    }

    pub fn redo_label(&self) -> Option<&str> {
        self.undone.last().map(|s| s.label.as_str())
    }

    /// Steps that can be undone.
    pub fn len(&self) -> usize {
        self.done.len()
    }

    pub fn is_empty(&self) -> bool {
        self.done.is_empty()
    }

    /// Forgets everything (a new set or scene was opened).
    pub fn clear(&mut self) {
        *self = History::new(self.limit);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{OrganState, Transform};
    use glam::Vec3;
    use proptest::prelude::*;

    fn layout(n: usize) -> Layout {
        Layout {
            organs: (0..n)
                .map(|i| OrganState {
                    visible: true,
                    opacity: 1.0,
                    colour: [0.5, 0.5, 0.5],
                    transform: Transform::identity(Vec3::splat(i as f32)),
                })
                .collect(),
            colour_by: Default::default(),
        }
    }

    fn edit() -> impl Strategy<Value = Edit> {
        let organs = prop_oneof![
            (0usize..8).prop_map(Organs::One),
            proptest::collection::vec(0usize..8, 0..4).prop_map(Organs::List),
            Just(Organs::All),
        ];
        (organs, 0u8..6, 0.0f32..1.0, -30.0f32..30.0).prop_map(|(organs, kind, a, x)| match kind {
            0 => Edit::Visible { organs, visible: a < 0.5 },
            1 => Edit::Opacity { organs, opacity: a },
            2 => Edit::Colour { organs, colour: [a, 1.0 - a, 0.5] },
            3 => Edit::Transform {
                organ: (x.abs() as usize) % 8,
                transform: Transform { translation: Vec3::new(x, 0.0, -x), ..Transform::identity(Vec3::ZERO) },
            },
            4 => Edit::ColourBy(crate::layout::ColourBy::ALL[(a * 3.0) as usize % 3]),
            _ => Edit::Isolate { organs },
        })
    }

    proptest! {
        /// Any sequence of edits, some of them dragged as gestures: undoing every step gives the
        /// first layout back, redoing every step the last.
        #[test]
        fn undo_all_then_redo_all(edits in proptest::collection::vec((edit(), 0u8..4), 0..40)) {
            let start = layout(8);
            let mut now = start.clone();
            let mut history = History::new(1000);
            for (e, g) in edits {
                // A quarter of the edits continue a gesture (a drag on organ 3's slider).
                let gesture = (g == 0).then_some(("drag", 3));
                if g == 1 {
                    history.end_gesture();
                }
                history.apply(&mut now, e, "edit".into(), gesture);
            }
            let end = now.clone();
            while history.undo(&mut now).is_some() {}
            prop_assert_eq!(&now, &start);
            while history.redo(&mut now).is_some() {}
            prop_assert_eq!(&now, &end);
        }
    }

    #[test]
    fn a_drag_is_one_step_and_a_new_edit_clears_redo() {
        let mut l = layout(3);
        let mut h = History::default();
        for a in [0.9, 0.7, 0.5, 0.3] {
            h.apply(
                &mut l,
                Edit::Opacity { organs: Organs::One(1), opacity: a },
                "fade B".into(),
                Some(("opacity", 1)),
            );
        }
        h.end_gesture();
        assert_eq!(h.len(), 1);
        assert_eq!(h.undo_label(), Some("fade B"));
        h.undo(&mut l);
        assert_eq!(l.organs[1].opacity, 1.0);
        h.redo(&mut l);
        assert_eq!(l.organs[1].opacity, 0.3);
        h.undo(&mut l);
        h.apply(&mut l, Edit::Visible { organs: Organs::One(0), visible: false }, "hide A".into(), None);
        assert_eq!(h.redo_label(), None, "a new edit ends what could be redone");
        // An edit that changes nothing is not a step.
        h.apply(&mut l, Edit::Visible { organs: Organs::One(0), visible: false }, "hide A".into(), None);
        assert_eq!(h.len(), 1);
    }

    #[test]
    fn the_history_is_bounded() {
        let mut l = layout(2);
        let mut h = History::new(3);
        for k in 0..10 {
            h.apply(&mut l, Edit::Opacity { organs: Organs::One(0), opacity: k as f32 / 10.0 }, "fade".into(), None);
        }
        assert_eq!(h.len(), 3);
    }
}
