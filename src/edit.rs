//! Edits: every change a user makes to the organ layout, as a value. [`apply`] performs one on a
//! [`Layout`] and returns its inverse, so undo, scene files and lesson steps can be built on one
//! path; [`Edit::describe`] names an edit for people ("hide Basal ganglia").
//!
//! - Pure data, no GUI: the viewer's components return edits and one place applies them.
//! - Organs are indices into the set (and so into the layout); an index out of range is skipped,
//!   never a panic.
//! - Camera moves are not edits.

use crate::layout::{Layout, OrganState, Transform};
use crate::organ_set::OrganSet;

/// The organs an edit changes.
#[derive(Clone, Debug, PartialEq)]
pub enum Organs {
    One(usize),
    /// A group of the set (its organs and those of its sub-groups), named for [`Edit::describe`].
    Group {
        name: String,
        organs: Vec<usize>,
    },
    /// Any list, such as the organs an inverse restores.
    List(Vec<usize>),
    /// Every organ of the layout.
    All,
}

impl Organs {
    /// The organs' indices in a layout of `n` organs (out-of-range ones left out).
    pub fn indices(&self, n: usize) -> Vec<usize> {
        match self {
            Organs::All => (0..n).collect(),
            listed => listed.listed(n).into_iter().filter(|&i| i < n).collect(),
        }
    }

    /// The listed organs as given (every organ for [`Organs::All`]): what per-organ values of an
    /// edit are index-aligned with.
    fn listed(&self, n: usize) -> Vec<usize> {
        match self {
            Organs::One(i) => vec![*i],
            Organs::Group { organs, .. } | Organs::List(organs) => organs.clone(),
            Organs::All => (0..n).collect(),
        }
    }

    /// The same organs without those out of range of a layout of `n` organs.
    fn within(self, n: usize) -> Organs {
        match self {
            Organs::Group { name, organs } => {
                Organs::Group { name, organs: organs.into_iter().filter(|&i| i < n).collect() }
            }
            Organs::List(organs) => Organs::List(organs.into_iter().filter(|&i| i < n).collect()),
            Organs::One(i) if i >= n => Organs::List(Vec::new()),
            other => other,
        }
    }

    fn label<'a>(&self, names: &impl Fn(usize) -> &'a str) -> String {
        match self {
            Organs::One(i) => names(*i).to_string(),
            Organs::Group { name, .. } => name.clone(),
            Organs::List(organs) => match organs.as_slice() {
                [] => "no organ".into(),
                [one] => names(*one).to_string(),
                many => format!("{} organs", many.len()),
            },
            Organs::All => "all organs".into(),
        }
    }
}

/// One change to the layout.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// Show or hide organs.
    Visible { organs: Organs, visible: bool },
    /// One opacity for all the organs (clamped to 0..=1).
    Opacity { organs: Organs, opacity: f32 },
    /// Each organ its own opacity, index-aligned with `organs` (clamped to 0..=1): a group's
    /// transparency toggle returns each organ to its own last translucent opacity.
    Opacities { organs: Organs, opacities: Vec<f32> },
    /// One colour (sRGB, 0..=1) for all the organs.
    Colour { organs: Organs, colour: [f32; 3] },
    /// Places one organ: its model transform (organ space to world space).
    Transform { organ: usize, transform: Transform },
    /// Organs back to no transform, each about its own pivot.
    ResetTransform { organs: Organs },
    /// Shows only these organs (hides every other).
    Isolate { organs: Organs },
    /// Organs back to the set's defaults, index-aligned with `organs` (see [`Edit::reset`]).
    Reset { organs: Organs, states: Vec<OrganState> },
    /// Organs back to earlier states, index-aligned with `organs`: what [`apply`] returns to undo.
    Restore { organs: Organs, states: Vec<OrganState> },
    /// What colours the organs (their own colours, lobes, arterial territories).
    ColourBy(crate::layout::ColourBy),
}

impl Edit {
    /// Back to the set's defaults (visibility, opacity, colour, no transform) for these organs.
    pub fn reset(set: &OrganSet, organs: Organs) -> Edit {
        let defaults = Layout::new(set);
        let organs = organs.within(defaults.organs.len());
        let states = organs.indices(defaults.organs.len()).into_iter().map(|i| defaults.organs[i]).collect();
        Edit::Reset { organs, states }
    }

    /// Shows every organ.
    pub fn show_all() -> Edit {
        Edit::Visible { organs: Organs::All, visible: true }
    }

    /// A label for people, e.g. "fade Left frontal lobe" or "hide Basal ganglia"; `names` gives an
    /// organ's name by index.
    pub fn describe<'a>(&self, names: &impl Fn(usize) -> &'a str) -> String {
        let fade = |opacity: f32| {
            if opacity >= 1.0 {
                ("make", " opaque")
            } else if opacity <= 0.0 {
                ("fade out", "")
            } else {
                ("fade", "")
            }
        };
        let (verb, organs, suffix) = match self {
            Edit::Visible { organs, visible } => (if *visible { "show" } else { "hide" }, organs, ""),
            Edit::Opacity { organs, opacity } => {
                let (verb, suffix) = fade(*opacity);
                (verb, organs, suffix)
            }
            Edit::Opacities { organs, opacities } => {
                let least = opacities.iter().copied().fold(1.0, f32::min);
                let (verb, suffix) = fade(if opacities.iter().all(|&a| a <= 0.0) { 0.0 } else { least });
                (verb, organs, suffix)
            }
            Edit::Colour { organs, .. } => ("recolour", organs, ""),
            Edit::Transform { organ, .. } => return format!("move {}", names(*organ)),
            Edit::ResetTransform { organs } => return format!("reset the transform of {}", organs.label(names)),
            Edit::Isolate { organs } => ("isolate", organs, ""),
            Edit::Reset { organs, .. } => ("reset", organs, ""),
            Edit::Restore { organs, .. } => ("restore", organs, ""),
            Edit::ColourBy(by) => return format!("colour by {}", by.label().to_lowercase()),
        };
        format!("{verb} {}{suffix}", organs.label(names))
    }
}

/// Applies `edit` to `layout` and returns the edit that undoes it: a [`Edit::Restore`] of the
/// organs it changed (none if it changed nothing), or the colouring it replaced.
pub fn apply(layout: &mut Layout, edit: &Edit) -> Edit {
    if let Edit::ColourBy(by) = edit {
        let before = std::mem::replace(&mut layout.colour_by, *by);
        return if before == *by {
            Edit::Restore { organs: Organs::List(Vec::new()), states: Vec::new() }
        } else {
            Edit::ColourBy(before)
        };
    }
    let n = layout.organs.len();
    let touched: Vec<usize> = match edit {
        Edit::Visible { organs, .. }
        | Edit::Opacity { organs, .. }
        | Edit::Opacities { organs, .. }
        | Edit::Colour { organs, .. }
        | Edit::ResetTransform { organs }
        | Edit::Reset { organs, .. }
        | Edit::Restore { organs, .. } => organs.indices(n),
        Edit::Transform { organ, .. } => Organs::One(*organ).indices(n),
        Edit::Isolate { .. } | Edit::ColourBy(_) => (0..n).collect(),
    };
    let before: Vec<OrganState> = touched.iter().map(|&i| layout.organs[i]).collect();
    let organs = &mut layout.organs;
    match edit {
        Edit::Visible { visible, .. } => touched.iter().for_each(|&i| organs[i].visible = *visible),
        Edit::Opacity { opacity, .. } => touched.iter().for_each(|&i| organs[i].opacity = opacity.clamp(0.0, 1.0)),
        Edit::Opacities { organs: which, opacities } => {
            // Index-aligned with the listed organs, so pair them before leaving out bad indices.
            for (&i, &a) in which.listed(n).iter().zip(opacities) {
                if let Some(s) = organs.get_mut(i) {
                    s.opacity = a.clamp(0.0, 1.0);
                }
            }
        }
        Edit::Colour { colour, .. } => touched.iter().for_each(|&i| organs[i].colour = *colour),
        Edit::Transform { transform, .. } => touched.iter().for_each(|&i| organs[i].transform = *transform),
        Edit::ResetTransform { .. } => {
            touched.iter().for_each(|&i| organs[i].transform = Transform::identity(organs[i].transform.pivot))
        }
        Edit::Isolate { organs: shown } => {
            let shown = shown.indices(n);
            touched.iter().for_each(|&i| organs[i].visible = shown.contains(&i));
        }
        Edit::Reset { organs: which, states } | Edit::Restore { organs: which, states } => {
            for (&i, s) in which.listed(n).iter().zip(states) {
                if let Some(state) = organs.get_mut(i) {
                    *state = *s;
                }
            }
        }
        Edit::ColourBy(_) => {}
    }
    let (changed, states): (Vec<usize>, Vec<OrganState>) =
        touched.iter().zip(before).filter(|(&i, b)| organs[i] != *b).map(|(&i, b)| (i, b)).unzip();
    Edit::Restore { organs: Organs::List(changed), states }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use proptest::prelude::*;

    fn state(i: usize) -> OrganState {
        OrganState {
            visible: !i.is_multiple_of(3),
            opacity: [1.0, 0.4, 0.0][i % 3],
            colour: [0.1 * i as f32, 0.5, 0.9],
            transform: Transform::identity(Vec3::new(i as f32, 2.0, 3.0)),
        }
    }

    fn layout(n: usize) -> Layout {
        Layout { organs: (0..n).map(state).collect(), colour_by: Default::default() }
    }

    fn names(i: usize) -> &'static str {
        ["Left frontal lobe", "Left putamen", "Brainstem"].get(i).copied().unwrap_or("?")
    }

    #[test]
    fn each_edit_and_its_inverse() {
        let moved = Transform { translation: Vec3::X, rotation_deg: Vec3::Y, scale: 2.0, pivot: Vec3::ZERO };
        let group = Organs::Group { name: "Basal ganglia".into(), organs: vec![1, 2] };
        let edits = [
            Edit::Visible { organs: Organs::One(0), visible: false },
            Edit::Visible { organs: group.clone(), visible: true },
            Edit::show_all(),
            Edit::Opacity { organs: Organs::One(0), opacity: 0.3 },
            Edit::Opacity { organs: Organs::All, opacity: 7.0 },
            Edit::Opacities { organs: group.clone(), opacities: vec![0.2, 0.6] },
            Edit::Colour { organs: Organs::List(vec![0, 2]), colour: [1.0, 0.0, 0.0] },
            Edit::Transform { organ: 1, transform: moved },
            Edit::ResetTransform { organs: Organs::All },
            Edit::Isolate { organs: group.clone() },
            Edit::Reset { organs: Organs::All, states: vec![state(5); 3] },
            Edit::Visible { organs: Organs::List(vec![1, 99]), visible: true },
        ];
        for edit in &edits {
            let mut l = layout(3);
            l.organs[1].transform = moved;
            let original = l.clone();
            let inverse = apply(&mut l, edit);
            let edited = l.clone();
            let again = apply(&mut l, &inverse);
            assert_eq!(l, original, "{edit:?}");
            apply(&mut l, &again);
            assert_eq!(l, edited, "{edit:?}: the inverse of the inverse redoes it");
        }
        let mut l = layout(3);
        apply(&mut l, &Edit::Opacity { organs: Organs::All, opacity: 7.0 });
        assert!(l.organs.iter().all(|s| s.opacity == 1.0), "opacity is clamped");
        apply(&mut l, &Edit::Isolate { organs: Organs::One(2) });
        assert_eq!(l.organs.iter().map(|s| s.visible).collect::<Vec<_>>(), [false, false, true]);
        let nothing = apply(&mut l, &Edit::Isolate { organs: Organs::One(2) });
        assert_eq!(nothing, Edit::Restore { organs: Organs::List(vec![]), states: vec![] });
    }

    #[test]
    fn descriptions() {
        let d = |e: Edit| e.describe(&names);
        let group = Organs::Group { name: "Basal ganglia".into(), organs: vec![1] };
        assert_eq!(d(Edit::Opacity { organs: Organs::One(0), opacity: 0.4 }), "fade Left frontal lobe");
        assert_eq!(d(Edit::Opacity { organs: Organs::One(0), opacity: 1.0 }), "make Left frontal lobe opaque");
        assert_eq!(d(Edit::Opacity { organs: Organs::One(2), opacity: 0.0 }), "fade out Brainstem");
        assert_eq!(d(Edit::Visible { organs: group.clone(), visible: false }), "hide Basal ganglia");
        assert_eq!(d(Edit::Opacities { organs: group.clone(), opacities: vec![0.4] }), "fade Basal ganglia");
        assert_eq!(d(Edit::show_all()), "show all organs");
        assert_eq!(d(Edit::Isolate { organs: Organs::List(vec![0, 1]) }), "isolate 2 organs");
        assert_eq!(d(Edit::Transform { organ: 1, transform: Transform::identity(Vec3::ZERO) }), "move Left putamen");
        assert_eq!(d(Edit::ResetTransform { organs: Organs::One(2) }), "reset the transform of Brainstem");
        assert_eq!(d(Edit::Colour { organs: group, colour: [0.0; 3] }), "recolour Basal ganglia");
        assert_eq!(d(Edit::Reset { organs: Organs::All, states: vec![] }), "reset all organs");
    }

    fn organs_strategy() -> impl Strategy<Value = Organs> {
        prop_oneof![
            (0..6usize).prop_map(Organs::One),
            proptest::collection::vec(0..6usize, 0..5).prop_map(Organs::List),
            proptest::collection::vec(0..6usize, 0..5).prop_map(|organs| Organs::Group { name: "g".into(), organs }),
            Just(Organs::All),
        ]
    }

    fn edit_strategy() -> impl Strategy<Value = Edit> {
        let value = prop_oneof![Just(0.0f32), Just(0.25), Just(1.0), -1.0f32..2.0];
        let transform = (-5.0f32..5.0, -90.0f32..90.0, 0.1f32..3.0).prop_map(|(t, r, s)| Transform {
            translation: Vec3::splat(t),
            rotation_deg: Vec3::new(r, 0.0, -r),
            scale: s,
            pivot: Vec3::ONE,
        });
        prop_oneof![
            (organs_strategy(), any::<bool>()).prop_map(|(organs, visible)| Edit::Visible { organs, visible }),
            (organs_strategy(), value.clone()).prop_map(|(organs, opacity)| Edit::Opacity { organs, opacity }),
            (organs_strategy(), proptest::collection::vec(value, 0..5))
                .prop_map(|(organs, opacities)| Edit::Opacities { organs, opacities }),
            (organs_strategy(), 0.0f32..1.0).prop_map(|(organs, c)| Edit::Colour { organs, colour: [c, 0.5, 1.0 - c] }),
            (0..6usize, transform).prop_map(|(organ, transform)| Edit::Transform { organ, transform }),
            organs_strategy().prop_map(|organs| Edit::ResetTransform { organs }),
            organs_strategy().prop_map(|organs| Edit::Isolate { organs }),
            organs_strategy().prop_map(|organs| Edit::Reset { organs, states: (7..12).map(state).collect() }),
        ]
    }

    proptest! {
        /// Undoing a sequence of edits, newest first, gives back the layout it started from.
        #[test]
        fn undoing_a_sequence_restores_the_layout(edits in proptest::collection::vec(edit_strategy(), 0..12)) {
            let mut l = layout(4);
            let original = l.clone();
            let inverses: Vec<Edit> = edits.iter().map(|e| apply(&mut l, e)).collect();
            for inverse in inverses.iter().rev() {
                apply(&mut l, inverse);
            }
            prop_assert_eq!(l, original);
        }
    }
}
