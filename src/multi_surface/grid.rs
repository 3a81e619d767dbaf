//! Preparing an organ grid for the net: cropping it with a margin of outside, and merging specks
//! (tiny voxel islands) into their neighbours, so no organ keeps a speck and none gets a hole.
//!
//! - Grids as in the parent module: one organ number per voxel, x fastest, 0 = outside.
//! - The crop keeps one layer of outside all round, so every surface closes.
//! - A speck is a 6-connected island of one organ, below a size cap and off the grid's border.

use super::OrganGrid;
use std::collections::{HashMap, HashSet};

/// The grid cropped to its organs' voxels plus one layer of outside all round (so every surface
/// closes), its dims, and its origin in the input grid. `None` without organ voxels.
pub(super) fn crop(grid: &OrganGrid) -> Option<(Vec<u32>, [usize; 3], [i64; 3])> {
    let [nx, ny, nz] = grid.dims;
    if grid.organs.len() < nx * ny * nz {
        return None;
    }
    let (mut lo, mut hi) = ([usize::MAX; 3], [0usize; 3]);
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                if grid.organs[x + nx * (y + ny * z)] != 0 {
                    for (k, c) in [x, y, z].into_iter().enumerate() {
                        lo[k] = lo[k].min(c);
                        hi[k] = hi[k].max(c);
                    }
                }
            }
        }
    }
    if lo[0] == usize::MAX {
        return None;
    }
    let dims: [usize; 3] = std::array::from_fn(|k| hi[k] - lo[k] + 3);
    let mut out = vec![0u32; dims[0] * dims[1] * dims[2]];
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            let src = nx * (y + ny * z);
            let dst = 1 + dims[0] * (y - lo[1] + 1 + dims[1] * (z - lo[2] + 1));
            out[dst..=dst + hi[0] - lo[0]].copy_from_slice(&grid.organs[src + lo[0]..=src + hi[0]]);
        }
    }
    Some((out, dims, std::array::from_fn(|k| lo[k] as i64 - 1)))
}

/// The 6 face neighbours of voxel `i` inside the grid.
fn face_neighbours(dims: [usize; 3], i: usize) -> impl Iterator<Item = usize> {
    let [nx, ny, _] = dims;
    let p = [i % nx, (i / nx) % ny, i / (nx * ny)];
    let strides = [1, nx, nx * ny];
    (0..3)
        .flat_map(move |k| [(p[k] > 0).then(|| i - strides[k]), (p[k] + 1 < dims[k]).then(|| i + strides[k])])
        .flatten()
}

/// The 6-connected island of `seed`'s organ, if it has fewer than `cap` voxels and keeps off the
/// grid's border.
fn island(organs: &[u32], dims: [usize; 3], seed: usize, cap: usize) -> Option<Vec<usize>> {
    let [nx, ny, nz] = dims;
    let on_border = |i: usize| {
        let p = [i % nx, (i / nx) % ny, i / (nx * ny)];
        p.contains(&0) || p[0] + 1 == nx || p[1] + 1 == ny || p[2] + 1 == nz
    };
    let mut members = vec![seed];
    let mut seen: HashSet<usize> = members.iter().copied().collect();
    let mut next = 0;
    while let Some(&i) = members.get(next) {
        next += 1;
        if on_border(i) {
            return None;
        }
        for n in face_neighbours(dims, i).filter(|&n| organs[n] == organs[seed]) {
            if seen.insert(n) {
                members.push(n);
                if members.len() >= cap {
                    return None;
                }
            }
        }
    }
    Some(members)
}

/// Relabels every 6-connected island of an organ (outside included) with fewer than `min_voxels`
/// voxels to the organ most of its face neighbours have (ties: the lower number); an organ's
/// largest island and islands touching the grid's border stay. Returns the voxels relabelled.
pub fn remove_islands(organs: &mut [u32], dims: [usize; 3], min_voxels: usize) -> usize {
    let n = dims[0] * dims[1] * dims[2];
    if organs.len() < n || min_voxels < 2 {
        return 0;
    }
    // Every island's organ, size and first voxel.
    let mut seen = vec![false; n];
    let mut islands: Vec<(u32, usize, usize)> = Vec::new();
    let mut stack = Vec::new();
    for seed in 0..n {
        if seen[seed] {
            continue;
        }
        let (organ, mut size) = (organs[seed], 0);
        seen[seed] = true;
        stack.push(seed);
        while let Some(i) = stack.pop() {
            size += 1;
            for m in face_neighbours(dims, i) {
                if !seen[m] && organs[m] == organ {
                    seen[m] = true;
                    stack.push(m);
                }
            }
        }
        islands.push((organ, size, seed));
    }
    let mut largest: HashMap<u32, usize> = HashMap::new();
    for &(organ, size, _) in &islands {
        let l = largest.entry(organ).or_insert(0);
        *l = (*l).max(size);
    }
    let mut relabelled = 0;
    for &(organ, size, seed) in &islands {
        if size >= min_voxels || largest.get(&organ) == Some(&size) || organs[seed] != organ {
            continue;
        }
        // Grown by an island relabelled before it, it may no longer be small.
        let Some(members) = island(organs, dims, seed, min_voxels) else {
            continue;
        };
        let mut votes: HashMap<u32, usize> = HashMap::new();
        for &i in &members {
            for m in face_neighbours(dims, i).filter(|&m| organs[m] != organ) {
                *votes.entry(organs[m]).or_insert(0) += 1;
            }
        }
        let Some((winner, _)) = votes.into_iter().max_by_key(|&(o, c)| (c, std::cmp::Reverse(o))) else {
            continue;
        };
        members.iter().for_each(|&i| organs[i] = winner);
        relabelled += members.len();
    }
    relabelled
}
