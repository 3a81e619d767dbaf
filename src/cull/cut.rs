//! Frame-to-frame coherence of the traversal: where each organ's hierarchy is entered, kept by a
//! [`Culler`](super::Culler) from one frame to the next.
//!
//! - No coordinate space: only nodes of the hierarchy ([`crate::bvh`]) and their triangle ranges.
//! - Traversed from its root, an organ's hierarchy is tested down to a *cut*: the nodes where the
//!   traversal stopped testing (hidden, outside the frustum, a leaf, or a node below which nothing
//!   more is tested). The inner nodes above the cut were tested and failed, and in the next frame,
//!   the camera having moved a little, most of them fail again.
//! - So the next frame's traversal starts at the cut: every node of the cut is tested as the root
//!   would be, and descended from where it fails, as before.
//! - Starting lower is always conservative (each triangle still lies below exactly one start, and
//!   testing more culls no less where a node is hidden), so only the cost depends on the cut.
//! - To keep the cut from sinking, two siblings that both started the frame and both stopped there
//!   (culled, or tested no further) give way to their parent for the next frame; where the parent
//!   then fails, its children return, reached by descent, and stay a frame before they may merge
//!   again.

use crate::bvh::Bvh;

/// Where the traversal reached and stopped in one frame: a node of the next cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Reached {
    pub node: u32,
    /// The node's first triangle: where it lies in the organ's triangle order.
    pub first: u32,
    /// Nothing below it was tested for occlusion: it was culled whole, or a test found nothing
    /// below it worth testing.
    pub closed: bool,
    /// It was a start of this frame's traversal (not reached by descent from a node that failed).
    pub started: bool,
}

/// One organ's cut, kept from frame to frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Cut {
    /// The starts of the next traversal: nodes whose triangle ranges tile the organ's, in order.
    nodes: Vec<u32>,
    /// Per node of the hierarchy the cut was made for, its parent (`NONE` for the root).
    parent: Vec<u32>,
}

impl Cut {
    /// Where to start in `bvh`: the kept cut where it still tiles `bvh`'s triangles exactly (it
    /// was made for this hierarchy), else the root alone.
    pub fn starts(&mut self, bvh: &Bvh) -> &[u32] {
        if self.parent.len() != bvh.nodes.len() {
            self.parent = parents(bvh);
            self.nodes.clear();
        }
        if !tiles(bvh, &self.nodes) {
            self.nodes = if bvh.nodes.is_empty() { Vec::new() } else { vec![0] };
        }
        &self.nodes
    }

    /// Keeps the nodes the traversal reached as the next frame's starts, merging sibling pairs
    /// (see the module's header). `reached` comes as a few runs in triangle order (one per
    /// thread), which a stable sort joins in about linear time.
    pub fn keep(&mut self, mut reached: Vec<Reached>) {
        reached.sort_by_key(|r| r.first);
        self.nodes.clear();
        let parent_of = |r: &Reached| self.parent.get(r.node as usize).copied().unwrap_or(crate::bvh::NONE);
        let mut i = 0;
        while i < reached.len() {
            let r = reached[i];
            let parent = parent_of(&r);
            // In triangle order, two children of one parent are its first and its second.
            let merge = match reached.get(i + 1) {
                Some(s) => {
                    let mergeable = |x: &Reached| x.closed && x.started;
                    mergeable(&r) && mergeable(s) && parent != crate::bvh::NONE && parent_of(s) == parent
                }
                None => false,
            };
            if merge {
                self.nodes.push(parent);
                i += 2;
            } else {
                self.nodes.push(r.node);
                i += 1;
            }
        }
    }
}

/// Each node's parent (`NONE` for the root).
fn parents(bvh: &Bvh) -> Vec<u32> {
    let mut parent = vec![crate::bvh::NONE; bvh.nodes.len()];
    for (n, node) in bvh.nodes.iter().enumerate() {
        if !node.is_leaf() {
            for c in node.children {
                if let Some(p) = parent.get_mut(c as usize) {
                    *p = n as u32;
                }
            }
        }
    }
    parent
}

/// Do the nodes' triangle ranges, in order, tile all of `bvh`'s triangles exactly once?
fn tiles(bvh: &Bvh, nodes: &[u32]) -> bool {
    let Some(root) = bvh.nodes.first() else { return nodes.is_empty() };
    let mut next = root.first;
    for &n in nodes {
        match bvh.nodes.get(n as usize) {
            Some(node) if node.first == next => next += node.count,
            _ => return false,
        }
    }
    next == root.first + root.count && !nodes.is_empty()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    /// A hierarchy of a few thousand triangles (a strip), deep enough for several levels.
    fn strip(triangles: usize) -> Bvh {
        let mut positions = Vec::new();
        for i in 0..=triangles / 2 {
            positions.push([i as f32, 0.0, 0.0]);
            positions.push([i as f32, 1.0, (i % 3) as f32]);
        }
        let mut indices = Vec::new();
        for i in 0..triangles as u32 / 2 {
            indices.extend([2 * i, 2 * i + 2, 2 * i + 1, 2 * i + 1, 2 * i + 2, 2 * i + 3]);
        }
        let normals = vec![[0.0, 0.0, 1.0]; positions.len()];
        let mut mesh = Mesh { positions, normals, indices };
        Bvh::build(&mut mesh)
    }

    fn reach(bvh: &Bvh, node: u32, closed: bool, started: bool) -> Reached {
        Reached { node, first: bvh.nodes[node as usize].first, closed, started }
    }

    fn leaves(bvh: &Bvh) -> Vec<u32> {
        let mut l = bvh.leaves.clone();
        l.sort_by_key(|&n| bvh.nodes[n as usize].first);
        l
    }

    #[test]
    fn a_new_cut_starts_at_the_root() {
        let bvh = strip(4000);
        assert_eq!(Cut::default().starts(&bvh), &[0]);
    }

    #[test]
    fn closed_siblings_that_started_merge_into_their_parent() {
        let bvh = strip(4000);
        let mut cut = Cut::default();
        cut.starts(&bvh);
        let reached = |closed: bool, started: bool| -> Vec<Reached> {
            leaves(&bvh).into_iter().map(|node| reach(&bvh, node, closed, started)).collect()
        };
        cut.keep(reached(true, true));
        let merged = cut.starts(&bvh).to_vec();
        assert_eq!(merged.len(), bvh.leaves.len() / 2, "every pair of sibling leaves merged once");
        assert!(merged.iter().all(|&n| !bvh.nodes[n as usize].is_leaf()));
        // Not closed, or reached by descent: kept as they are.
        for (closed, started) in [(false, true), (true, false)] {
            cut.keep(reached(closed, started));
            assert_eq!(cut.starts(&bvh), leaves(&bvh).as_slice());
        }
    }

    #[test]
    fn a_cut_that_does_not_tile_the_hierarchy_starts_again_at_the_root() {
        let bvh = strip(4000);
        let mut cut = Cut::default();
        cut.starts(&bvh);
        // A leaf missing: its triangles would never be drawn.
        let mut reached: Vec<Reached> = leaves(&bvh).into_iter().map(|node| reach(&bvh, node, false, false)).collect();
        reached.remove(3);
        cut.keep(reached);
        assert_eq!(cut.starts(&bvh), &[0]);
        // Another organ's hierarchy.
        let other = strip(1000);
        cut.keep(leaves(&bvh).into_iter().map(|node| reach(&bvh, node, false, false)).collect());
        assert_eq!(cut.starts(&other), &[0]);
    }
}
