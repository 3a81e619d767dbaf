//! The culler's parallel work as tasks for [`super::share`]: the subtrees below the top levels of
//! the hierarchies (and groups of small starts), traversed by the calling thread and the pool.
//!
//! - No coordinate space: a task is a single subtree, or a group of small starts of one organ up
//!   to `SUBTREE_TRIANGLES` triangles in all, and gives its organs' ranges, counts and reached
//!   nodes.

use super::occluders::Occluders;
use super::settings::CullSettings;
use super::share::Tasks;
use super::traversal::{traverse_below, OrganView, Start, Walk, SUBTREE_TRIANGLES};
use crate::organ_set::OrganSet;
use std::ops::Range;

/// The traversals left to share, as tasks: single subtrees, or groups of small starts of one organ
/// up to [`SUBTREE_TRIANGLES`] in all. Each gives its organs' ranges, counts and reached nodes.
pub(super) struct Subtrees<'a> {
    pub set: &'a OrganSet,
    pub views: Vec<Option<OrganView<'a>>>,
    pub occ: Option<Occluders>,
    pub settings: CullSettings,
    pub starts: Vec<Start>,
    /// (triangles, starts) per task.
    pub tasks: Vec<(u32, Range<usize>)>,
}

impl Subtrees<'_> {
    /// Adds a start of `count` triangles: to the last task where `group` and that task is a
    /// group of the same organ with room left, else as a task of its own.
    pub fn add(&mut self, start: Start, count: u32, group: bool) {
        let i = self.starts.len();
        let same_group = |(t, r): &&mut (u32, Range<usize>)| {
            group
                && r.end == i
                && self.starts[r.start].started
                && self.starts[r.start].organ == start.organ
                && t + count <= SUBTREE_TRIANGLES
        };
        match self.tasks.last_mut().filter(same_group) {
            Some((t, r)) => (*t, r.end) = (*t + count, i + 1),
            None => self.tasks.push((count, i..i + 1)),
        }
        self.starts.push(start);
    }
}

impl Tasks for Subtrees<'_> {
    /// Per organ of the tasks run, what they gave.
    type State = Vec<(usize, Walk)>;
    fn count(&self) -> usize {
        self.tasks.len()
    }
    fn state(&self) -> Self::State {
        Vec::new()
    }
    fn run(&self, done: &mut Self::State, i: usize) {
        for &Start { organ: o, node, test, started } in &self.starts[self.tasks[i].1.clone()] {
            let Some(view) = &self.views[o] else { continue };
            if done.last().is_none_or(|(last, _)| *last != o) {
                done.push((o, Walk::default()));
            }
            if let Some((_, walk)) = done.last_mut() {
                let organ = &self.set.organs[o];
                let start = Start { organ: o, node, test, started };
                traverse_below(organ, view, self.occ.as_ref(), &self.settings, start, (walk, None));
            }
        }
    }
}
