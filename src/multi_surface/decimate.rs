//! Decimation of the shared interfaces, in two passes over the patches themselves.
//!
//! - Positions never move, so organs drawing a patch draw the same result and neighbours keep
//!   meeting without cracks.
//! - The passes:
//! 1. Meshoptimizer on each patch, moving no surface more than a fifth of a voxel, with the
//!    junction vertices and their neighbours locked: the bulk of flat interior, fast.
//! 2. One greedy sequence of half-edge collapses over the whole net, cheapest first by quadric
//!    error (Garland and Heckbert), each applied to every patch at once.
//!
//! - Junctions: a vertex inside a junction curve (exactly two neighbours along patch borders)
//!   collapses only along the curve, onto one of those two; patch borders add constraint planes to
//!   the quadrics, so curves keep their course. Other junction vertices (curve ends, corners) stay.
//! - A collapse is made only where every organ's surface stays a closed manifold around it (the
//!   link condition, per organ) and no triangle folds, so decimation adds no pinched edges.
//! - Once no valid collapse is left the budget is not met: what junctions and thin parts need
//!   stays.

use super::{Interfaces, Patch};
use glam::DVec3;
use rayon::prelude::*;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// How far (voxels) the meshoptimizer pass may move a surface; the quadric collapses do the rest.
const PRESIMPLIFY_ERROR: f32 = 0.2;

/// No organ's surface is decimated below this many triangles.
const MIN_ORGAN_TRIANGLES: usize = 96;

/// Weight of a patch border's constraint planes against the surfaces' own (per area).
const BORDER_WEIGHT: f64 = 4.0;

impl Interfaces {
    /// Decimates to at most `triangles` drawn triangles (see [`Interfaces::drawn_triangles`]), or
    /// as near as valid collapses allow.
    pub fn decimate(&mut self, triangles: usize) {
        self.presimplify(triangles.saturating_mul(2));
        self.collapse(triangles);
    }

    /// The bulk of the work, fast: meshoptimizer on each patch toward its share of `triangles`,
    /// with the junction vertices and their neighbours locked. Then no junction vertex gains or
    /// loses an edge, so patches still meet as before and no organ's surface gets pinched.
    fn presimplify(&mut self, triangles: usize) {
        let drawn = self.drawn_triangles();
        if drawn <= triangles {
            return;
        }
        let mut locks = self.junction.clone();
        for t in self.patches.iter().flat_map(|p| p.indices.chunks_exact(3)) {
            if t.iter().any(|&v| self.junction[v as usize]) {
                t.iter().for_each(|&v| locks[v as usize] = true);
            }
        }
        let scale = triangles as f64 / drawn as f64;
        let positions = &self.positions;
        self.patches.par_iter_mut().for_each(|patch| {
            let target = ((patch.indices.len() / 3) as f64 * scale) as usize;
            simplify_patch(patch, positions, &locks, target.max(1));
        });
    }

    /// Half-edge collapses, cheapest first, down to `triangles` drawn triangles.
    fn collapse(&mut self, triangles: usize) {
        let mut drawn = self.drawn_triangles();
        if drawn <= triangles {
            return;
        }
        let mut soup = Soup::new(&self.positions, &self.junction, &self.patches);
        let mut quadrics = soup.quadrics();
        // One entry per vertex at most, `(cost, v, target, stamp)`; an entry whose stamp is
        // behind its vertex's (its neighbourhood changed) is re-costed when it comes up.
        let mut stamp = vec![0u32; self.positions.len()];
        let mut queued = vec![false; self.positions.len()];
        let mut heap = BinaryHeap::new();
        let push = |heap: &mut BinaryHeap<_>, queued: &mut [bool], (cost, v, w): (f64, u32, u32), stamp: u32| {
            heap.push(Reverse((cost.max(0.0).to_bits(), v, w, stamp)));
            queued[v as usize] = true;
        };
        for v in 0..self.positions.len() as u32 {
            if let Some(&(cost, w)) = soup.targets(v, &quadrics).first() {
                push(&mut heap, &mut queued, (cost, v, w), 0);
            }
        }
        while drawn > triangles {
            let Some(Reverse((_, v, w, s))) = heap.pop() else {
                break;
            };
            queued[v as usize] = false;
            let now = stamp[v as usize];
            if s != now {
                if let Some(&(cost, u)) = soup.targets(v, &quadrics).first() {
                    push(&mut heap, &mut queued, (cost, v, u), now);
                }
                continue;
            }
            if !soup.can_collapse(v, w) {
                // Its cheapest valid target, if any; else it waits for its neighbourhood to change.
                let next = soup.targets(v, &quadrics).into_iter().find(|&(_, u)| u != w && soup.can_collapse(v, u));
                if let Some((cost, u)) = next {
                    push(&mut heap, &mut queued, (cost, v, u), now);
                }
                continue;
            }
            drawn -= soup.collapse(v, w);
            let q = quadrics[v as usize];
            quadrics[w as usize].add(&q);
            for u in soup.ring(w).into_iter().chain([w]) {
                stamp[u as usize] += 1;
                if !queued[u as usize] {
                    if let Some(&(cost, t)) = soup.targets(u, &quadrics).first() {
                        push(&mut heap, &mut queued, (cost, u, t), stamp[u as usize]);
                    }
                }
            }
        }
        for p in &mut self.patches {
            p.indices.clear();
        }
        for (t, tri) in soup.tris.iter().enumerate().filter(|&(t, _)| soup.alive[t]) {
            self.patches[soup.patch[t] as usize].indices.extend_from_slice(tri);
        }
    }
}

/// A symmetric 4x4 quadric `[a², ab, ac, ad, b², bc, bd, c², cd, d²]` of plane `ax + by + cz + d`.
#[derive(Clone, Copy, Default)]
struct Quadric([f64; 10]);

impl Quadric {
    fn plane(n: DVec3, through: DVec3, weight: f64) -> Quadric {
        let [a, b, c] = n.to_array();
        let d = -n.dot(through);
        Quadric([a * a, a * b, a * c, a * d, b * b, b * c, b * d, c * c, c * d, d * d].map(|x| x * weight))
    }

    fn add(&mut self, o: &Quadric) {
        self.0.iter_mut().zip(o.0).for_each(|(x, y)| *x += y);
    }

    /// The weighted sum of squared distances of `p` from the planes.
    fn error(&self, p: DVec3) -> f64 {
        let [a2, ab, ac, ad, b2, bc, bd, c2, cd, d2] = self.0;
        let [x, y, z] = p.to_array();
        a2 * x * x
            + b2 * y * y
            + c2 * z * z
            + 2.0 * (ab * x * y + ac * x * z + bc * y * z + ad * x + bd * y + cd * z)
            + d2
    }
}

/// All patches' triangles in one list, with the live triangles around each vertex.
struct Soup<'a> {
    positions: &'a [[f32; 3]],
    junction: &'a [bool],
    organs: Vec<[u32; 2]>,
    tris: Vec<[u32; 3]>,
    patch: Vec<u32>,
    alive: Vec<bool>,
    around: Vec<Vec<u32>>,
    /// Live triangles per organ number.
    organ_triangles: Vec<usize>,
}

impl<'a> Soup<'a> {
    fn new(positions: &'a [[f32; 3]], junction: &'a [bool], patches: &[Patch]) -> Soup<'a> {
        let mut soup = Soup {
            positions,
            junction,
            organs: patches.iter().map(|p| p.organs).collect(),
            tris: Vec::new(),
            patch: Vec::new(),
            alive: Vec::new(),
            around: vec![Vec::new(); positions.len()],
            organ_triangles: Vec::new(),
        };
        for (k, p) in patches.iter().enumerate() {
            for t in p.indices.chunks_exact(3) {
                t.iter().for_each(|&u| soup.around[u as usize].push(soup.tris.len() as u32));
                soup.tris.push([t[0], t[1], t[2]]);
                soup.patch.push(k as u32);
            }
        }
        soup.alive = vec![true; soup.tris.len()];
        let organs = soup.organs.iter().flatten().max().map_or(0, |&o| o as usize + 1);
        soup.organ_triangles = vec![0; organs];
        for p in patches {
            p.organs.iter().for_each(|&o| soup.organ_triangles[o as usize] += p.indices.len() / 3);
        }
        soup
    }

    fn at(&self, v: u32) -> DVec3 {
        DVec3::from(self.positions[v as usize].map(f64::from))
    }

    fn normal(&self, tri: [u32; 3]) -> DVec3 {
        let [a, b, c] = tri.map(|u| self.at(u));
        (b - a).cross(c - a)
    }

    /// Per vertex: the planes of its triangles (weighted by area) and, along patch borders,
    /// planes through the border edge perpendicular to its triangle.
    fn quadrics(&self) -> Vec<Quadric> {
        let mut q = vec![Quadric::default(); self.positions.len()];
        let mut edges: Vec<(u32, u32, u32, u32)> = Vec::with_capacity(self.tris.len() * 3);
        for (t, &tri) in self.tris.iter().enumerate() {
            let n = self.normal(tri);
            let plane = Quadric::plane(n.normalize_or_zero(), self.at(tri[0]), n.length() / 2.0);
            tri.iter().for_each(|&u| q[u as usize].add(&plane));
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                edges.push((self.patch[t], a.min(b), a.max(b), t as u32));
            }
        }
        edges.sort_unstable();
        for run in edges.chunk_by(|x, y| x.0 == y.0 && x.1 == y.1 && x.2 == y.2).filter(|r| r.len() == 1) {
            let (_, a, b, t) = run[0];
            let (pa, pb) = (self.at(a), self.at(b));
            let m = (pb - pa).cross(self.normal(self.tris[t as usize])).normalize_or_zero();
            let plane = Quadric::plane(m, pa, BORDER_WEIGHT * pa.distance_squared(pb));
            q[a as usize].add(&plane);
            q[b as usize].add(&plane);
        }
        q
    }

    /// The vertices sharing a live triangle with `v`, ascending.
    fn ring(&self, v: u32) -> Vec<u32> {
        let mut r: Vec<u32> =
            self.around[v as usize].iter().flat_map(|&t| self.tris[t as usize]).filter(|&u| u != v).collect();
        r.sort_unstable();
        r.dedup();
        r
    }

    /// The vertices joined to `v` by a border edge of some patch (an edge of one triangle there).
    fn curve_neighbours(&self, v: u32) -> Vec<u32> {
        let mut edges: Vec<(u32, u32)> = Vec::new();
        for &t in &self.around[v as usize] {
            let tri = self.tris[t as usize];
            edges.extend(tri.iter().filter(|&&u| u != v).map(|&u| (self.patch[t as usize], u)));
        }
        edges.sort_unstable();
        let mut out: Vec<u32> =
            edges.chunk_by(|a, b| a == b).filter(|run| run.len() == 1).map(|run| run[0].1).collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Where `v` may collapse to, cheapest first: any neighbour off junctions, along its curve on
    /// one, nowhere at curve ends and corners.
    fn targets(&self, v: u32, quadrics: &[Quadric]) -> Vec<(f64, u32)> {
        let candidates = if !self.junction[v as usize] {
            self.ring(v)
        } else {
            let along = self.curve_neighbours(v);
            if along.len() == 2 {
                along
            } else {
                Vec::new()
            }
        };
        let mut out: Vec<(f64, u32)> = candidates
            .into_iter()
            .map(|w| {
                let mut q = quadrics[v as usize];
                q.add(&quadrics[w as usize]);
                (q.error(self.at(w)), w)
            })
            .collect();
        out.sort_by(|a, b| a.0.total_cmp(&b.0));
        out
    }

    /// Whether collapsing `v` onto `w` keeps every organ's surface a closed manifold around them and
    /// folds no triangle.
    fn can_collapse(&self, v: u32, w: u32) -> bool {
        let (tv, tw) = (&self.around[v as usize], &self.around[w as usize]);
        let mut organs: Vec<u32> = tv.iter().flat_map(|&t| self.organs[self.patch[t as usize] as usize]).collect();
        organs.sort_unstable();
        organs.dedup();
        for o in organs.into_iter().filter(|&o| o != 0) {
            let of_o = |ts: &[u32]| -> Vec<u32> {
                ts.iter().copied().filter(|&t| self.organs[self.patch[t as usize] as usize].contains(&o)).collect()
            };
            let ring = |ts: &[u32], centre: u32| -> Vec<u32> {
                let mut r: Vec<u32> = ts.iter().flat_map(|&t| self.tris[t as usize]).filter(|&u| u != centre).collect();
                r.sort_unstable();
                r.dedup();
                r
            };
            let tv = of_o(tv);
            let (nv, nw) = (ring(&tv, v), ring(&of_o(tw), w));
            let mut thirds: Vec<u32> = tv
                .iter()
                .map(|&t| self.tris[t as usize])
                .filter(|tri| tri.contains(&w))
                .flat_map(|tri| tri.into_iter().filter(|&u| u != v && u != w))
                .collect();
            thirds.sort_unstable();
            let common: Vec<u32> = nv.iter().copied().filter(|u| nw.binary_search(u).is_ok()).collect();
            // One triangle on each side of the edge, whose far corners are the only common
            // neighbours; `w` keeps at least three neighbours, the organ enough triangles.
            if thirds.len() != 2
                || common != thirds
                || nv.len() + nw.len() < common.len() + 5
                || self.organ_triangles[o as usize] < MIN_ORGAN_TRIANGLES + 2
            {
                return false;
            }
        }
        tv.iter().map(|&t| self.tris[t as usize]).filter(|tri| !tri.contains(&w)).all(|tri| {
            let before = self.normal(tri);
            let after = self.normal(tri.map(|u| if u == v { w } else { u }));
            after.length_squared() > 1e-12 && before.dot(after) > 0.2 * before.length() * after.length()
        })
    }

    /// Collapses `v` onto `w` in every patch: triangles with both go, the others take `w`.
    /// Returns the drawn triangles removed.
    fn collapse(&mut self, v: u32, w: u32) -> usize {
        let mut removed = 0;
        for t in std::mem::take(&mut self.around[v as usize]) {
            let tri = &mut self.tris[t as usize];
            if tri.contains(&w) {
                self.alive[t as usize] = false;
                let organs = self.organs[self.patch[t as usize] as usize];
                organs.iter().for_each(|&o| self.organ_triangles[o as usize] -= 1);
                removed += if organs[0] == 0 { 1 } else { 2 };
                for u in *tri {
                    self.around[u as usize].retain(|&x| x != t);
                }
            } else {
                tri.iter_mut().filter(|u| **u == v).for_each(|u| *u = w);
                self.around[w as usize].push(t);
            }
        }
        removed
    }
}

/// Meshoptimizer on one patch, to about `target` triangles, `locks` and the patch's border kept.
fn simplify_patch(patch: &mut Patch, positions: &[[f32; 3]], locks: &[bool], target: usize) {
    if patch.indices.len() / 3 <= target {
        return;
    }
    let mut used = patch.indices.clone();
    used.sort_unstable();
    used.dedup();
    let local: Vec<u32> = patch
        .indices
        .iter()
        .map(|g| match used.binary_search(g) {
            Ok(i) | Err(i) => i as u32,
        })
        .collect();
    let vertices: Vec<[f32; 3]> = used.iter().map(|&g| positions[g as usize]).collect();
    let locks: Vec<bool> = used.iter().map(|&g| locks[g as usize]).collect();
    let options = meshopt::SimplifyOptions::LockBorder | meshopt::SimplifyOptions::ErrorAbsolute;
    let out =
        meshopt::simplify_with_locks_decoder(&local, &vertices, &locks, target * 3, PRESIMPLIFY_ERROR, options, None);
    if !out.is_empty() {
        patch.indices = out.iter().map(|&l| used[l as usize]).collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat hexagonal bipyramid (ring 0..6, top 6, bottom 7) as one organ's only patch.
    fn bipyramid() -> (Vec<[f32; 3]>, Vec<Patch>) {
        let mut positions: Vec<[f32; 3]> = (0..6)
            .map(|i| {
                let a = i as f32 * std::f32::consts::FRAC_PI_3;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        positions.extend([[0.0, 0.0, 0.2], [0.0, 0.0, -0.2]]);
        let indices = (0..6u32).flat_map(|i| [i, (i + 1) % 6, 6, (i + 1) % 6, i, 7]).collect();
        (positions, vec![Patch { organs: [0, 1], indices }])
    }

    #[test]
    fn collapses_that_fold_or_pinch_are_refused() {
        let (positions, patches) = bipyramid();
        let junction = vec![false; positions.len()];
        let mut soup = Soup::new(&positions, &junction, &patches);
        assert_eq!(soup.organ_triangles, [12, 12]);
        assert!(!soup.can_collapse(0, 1), "no organ goes below MIN_ORGAN_TRIANGLES");
        soup.organ_triangles[1] = 200;
        assert!(soup.can_collapse(0, 1), "along the ring: fine");
        assert!(!soup.can_collapse(0, 6), "onto the apex: its lower triangles would fold up");
        assert!(!soup.can_collapse(0, 3), "not an edge");
        assert_eq!(soup.collapse(0, 1), 2);
        assert!(soup.can_collapse(2, 3));
        // Down to a triangular bipyramid: one more collapse would leave a pillow of two triangles.
        assert_eq!(soup.collapse(2, 3) + soup.collapse(4, 5), 4);
        assert!(soup.ring(1).len() == 4 && !soup.can_collapse(1, 3));
    }
}
