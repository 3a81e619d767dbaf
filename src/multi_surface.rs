//! Seamless multi-label surfaces: one surface net for all organs of a label grid at once, so that
//! neighbouring organs share their interface exactly (multi-material surface nets, cf. Frisken,
//! "SurfaceNets for multi-label segmentations with preservation of sharp boundaries", JCGT 2022).
//!
//! - Grids hold one organ number per voxel, `organs[x + nx * (y + ny * z)]`, 0 = outside and organ
//!   `k` numbered `k + 1`.
//! - Positions are in voxel index space (voxel `(x, y, z)` centred at `(x, y, z)`) until the
//!   caller applies the volume's affine with [`Interfaces::transform`].
//! - Shared: one vertex array for all organs, one vertex per 2x2x2 cell of voxels that are not all
//!   one organ.
//! - The triangles between organs `lo < hi` (`lo = 0`: `hi` and the outside) form one [`Patch`],
//!   wound counter-clockwise seen from `lo`, i.e. outward from `hi`. Organ `hi` draws it as it is,
//!   organ `lo` reversed, so two neighbours draw the very same vertices and triangles and every
//!   organ's surface is closed.
//! - Smoothing and decimation work once on the shared patches; vertices on *junctions* (cells of
//!   three or more organs, outside included), where patches meet, move only along their junction
//!   curve or not at all, so thin parts keep their shape.
//! - Stages: [`interfaces`] (specks merged, nets, joint smoothing), [`Interfaces::decimate`],
//!   [`Interfaces::transform`], [`Interfaces::organ_meshes`]; [`extract`] runs all but the
//!   transform.

use crate::mesh::Mesh;
use glam::{Mat4, Vec3};
use std::collections::HashMap;

mod decimate;
mod grid;

use grid::crop;
pub use grid::remove_islands;

/// Organ numbers on a grid, `organs[x + nx * (y + ny * z)]`; 0 is outside.
pub struct OrganGrid<'a> {
    pub dims: [usize; 3],
    pub organs: &'a [u32],
}

/// Labels on a grid as read from a volume, `labels[x + nx * (y + ny * z)]`; 0 is background.
pub struct LabelGrid<'a> {
    pub dims: [usize; 3],
    pub labels: &'a [u32],
}

/// Options of [`extract`].
#[derive(Clone, Debug)]
pub struct Options {
    /// Taubin smoothing iterations (one lambda and one mu step each).
    pub smoothing: usize,
    /// Triangle budget of all organs together; a patch counts once per organ that draws it.
    pub triangles: usize,
    /// Connected voxel islands of an organ smaller than this join their neighbours' majority organ
    /// (an organ's largest island always stays).
    pub min_island: usize,
}

impl Default for Options {
    fn default() -> Self {
        Options { smoothing: 10, triangles: 200_000, min_island: 30 }
    }
}

/// The triangles between two organs: `organs = [lo, hi]`, `lo < hi`, `lo = 0` for the outside;
/// wound counter-clockwise seen from `lo` (outward from `hi`).
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    pub organs: [u32; 2],
    pub indices: Vec<u32>,
}

/// The surfaces of all organs of a grid as shared patches over one vertex array.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Interfaces {
    pub positions: Vec<[f32; 3]>,
    /// Per vertex: in a cell of three or more organs. Smoothing moves it only along its junction
    /// curve, decimation removes it only onto its curve neighbours.
    pub junction: Vec<bool>,
    pub patches: Vec<Patch>,
}

/// Organ numbers of a label grid: `organs[k]` lists the labels of organ `k` (number `k + 1`);
/// labels of no organ are outside (0).
pub fn organ_numbers(labels: &[u32], organs: &[Vec<u32>]) -> Vec<u32> {
    let number: HashMap<u32, u32> =
        organs.iter().enumerate().flat_map(|(k, ls)| ls.iter().map(move |&l| (l, k as u32 + 1))).collect();
    labels.iter().map(|l| number.get(l).copied().unwrap_or(0)).collect()
}

/// One closed mesh per organ (`organs[k]`: the labels of organ `k`), in voxel index space, with
/// normals. Neighbouring organs share their interface's vertices and triangles exactly.
pub fn extract(grid: &LabelGrid, organs: &[Vec<u32>], opts: &Options) -> Vec<Mesh> {
    let numbers = organ_numbers(grid.labels, organs);
    let mut shared = interfaces(&OrganGrid { dims: grid.dims, organs: &numbers }, opts);
    shared.decimate(opts.triangles);
    shared.organ_meshes(organs.len())
}

/// The smoothed, undecimated interfaces of an organ grid: islands below `opts.min_island` voxels
/// merged into their neighbours, surface nets, then `opts.smoothing` joint Taubin iterations.
pub fn interfaces(grid: &OrganGrid, opts: &Options) -> Interfaces {
    let Some((mut organs, dims, origin)) = crop(grid) else {
        return Interfaces::default();
    };
    remove_islands(&mut organs, dims, opts.min_island);
    let net = nets(&organs, dims);
    let (offsets, neighbours) = smoothing_neighbours(&net, &organs, dims);
    let mut positions = net.positions;
    taubin(&mut positions, &offsets, &neighbours, opts.smoothing);
    let patches = net
        .patch_organs
        .iter()
        .zip(&net.quads)
        .map(|(&organs, quads)| Patch { organs, indices: triangulate(quads, &positions) })
        .collect();
    let shift = Vec3::new(origin[0] as f32, origin[1] as f32, origin[2] as f32);
    Interfaces {
        positions: positions.iter().map(|&p| (p + shift).to_array()).collect(),
        junction: net.junction,
        patches,
    }
}

impl Interfaces {
    /// Triangles as drawn: a patch between two organs counts twice, one on the outside once.
    pub fn drawn_triangles(&self) -> usize {
        self.patches.iter().map(|p| p.indices.len() / 3 * if p.organs[0] == 0 { 1 } else { 2 }).sum()
    }

    /// Maps positions by `m` (voxel index space -> world); a mirroring `m` reverses the winding so
    /// surfaces stay outward.
    pub fn transform(&mut self, m: Mat4) {
        for p in &mut self.positions {
            *p = m.transform_point3(Vec3::from(*p)).to_array();
        }
        if m.determinant() < 0.0 {
            for t in self.patches.iter_mut().flat_map(|p| p.indices.chunks_exact_mut(3)) {
                t.swap(1, 2);
            }
        }
    }

    /// Each organ's mesh (`organ_count` organs, numbers 1..=organ_count) assembled from its patches,
    /// outward, shared vertices welded by index, with normals. Empty where an organ has no surface.
    pub fn organ_meshes(&self, organ_count: usize) -> Vec<Mesh> {
        let mut triangles = vec![Vec::<u32>::new(); organ_count];
        for p in &self.patches {
            let [lo, hi] = p.organs.map(|o| (o as usize).checked_sub(1));
            if let Some(t) = hi.and_then(|k| triangles.get_mut(k)) {
                t.extend_from_slice(&p.indices);
            }
            if let Some(t) = lo.and_then(|k| triangles.get_mut(k)) {
                t.extend(p.indices.chunks_exact(3).flat_map(|t| [t[0], t[2], t[1]]));
            }
        }
        let mut local = vec![u32::MAX; self.positions.len()];
        triangles
            .into_iter()
            .map(|global| {
                let mut mesh = Mesh::default();
                for &g in &global {
                    if local[g as usize] == u32::MAX {
                        local[g as usize] = mesh.positions.len() as u32;
                        mesh.positions.push(self.positions[g as usize]);
                    }
                    mesh.indices.push(local[g as usize]);
                }
                global.iter().for_each(|&g| local[g as usize] = u32::MAX);
                mesh.compute_normals();
                mesh
            })
            .collect()
    }
}

/// The raw multi-material surface net of a padded organ grid.
struct Net {
    positions: Vec<Vec3>,
    /// Per vertex: its cell, as the grid index of the cell's lowest voxel.
    cells: Vec<usize>,
    junction: Vec<bool>,
    patch_organs: Vec<[u32; 2]>,
    /// Per patch: its quads, wound like [`Patch`].
    quads: Vec<Vec<[u32; 4]>>,
}

/// The organs of the eight voxels of the cell whose lowest voxel is `cell`.
fn cell_corners(organs: &[u32], dims: [usize; 3], cell: usize) -> [u32; 8] {
    let (sy, sz) = (dims[0], dims[0] * dims[1]);
    std::array::from_fn(|i| organs[cell + (i & 1) + sy * ((i >> 1) & 1) + sz * (i >> 2)])
}

/// The distinct organs among a cell's corners: `(set, n)`, `set[..n]` ascending.
fn distinct(mut o: [u32; 8]) -> ([u32; 8], usize) {
    o.sort_unstable();
    let mut n = 1;
    for i in 1..8 {
        if o[i] != o[n - 1] {
            o[n] = o[i];
            n += 1;
        }
    }
    (o, n)
}

/// Multi-material surface nets: a vertex in every cell of more than one organ (the mean of the
/// midpoints of its edges between different organs), a quad around every voxel edge between two
/// organs, filed under their patch.
fn nets(organs: &[u32], dims: [usize; 3]) -> Net {
    const EDGES: [(usize, usize); 12] =
        [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)];
    let corner = |i: usize| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, (i >> 2) as f32);
    let [nx, ny, nz] = dims;
    let strides = [1, nx, nx * ny];
    let mut net = Net { positions: vec![], cells: vec![], junction: vec![], patch_organs: vec![], quads: vec![] };
    let mut cell_vertex = vec![u32::MAX; organs.len()];
    for z in 0..nz - 1 {
        for y in 0..ny - 1 {
            for x in 0..nx - 1 {
                let c = x + nx * (y + ny * z);
                let o = cell_corners(organs, dims, c);
                let (_, count) = distinct(o);
                if count == 1 {
                    continue;
                }
                let (mut sum, mut n) = (Vec3::ZERO, 0.0);
                for &(a, b) in EDGES.iter().filter(|&&(a, b)| o[a] != o[b]) {
                    sum += corner(a) + corner(b);
                    n += 2.0;
                }
                cell_vertex[c] = net.positions.len() as u32;
                net.positions.push(Vec3::new(x as f32, y as f32, z as f32) + sum / n);
                net.cells.push(c);
                net.junction.push(count >= 3);
            }
        }
    }
    let mut patch_of: HashMap<[u32; 2], usize> = HashMap::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let (p, pc) = (x + nx * (y + ny * z), [x, y, z]);
                for axis in 0..3 {
                    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                    if pc[axis] + 1 >= dims[axis] || pc[u] == 0 || pc[v] == 0 {
                        continue;
                    }
                    let (a, b) = (organs[p], organs[p + strides[axis]]);
                    if a == b {
                        continue;
                    }
                    let (su, sv) = (strides[u], strides[v]);
                    // (u, v, axis) is right-handed: this order faces +axis, from a toward b.
                    let quad = [p - su - sv, p - sv, p, p - su].map(|c| cell_vertex[c]);
                    if quad.contains(&u32::MAX) {
                        continue;
                    }
                    let key = [a.min(b), a.max(b)];
                    let quad = if a == key[1] { quad } else { [quad[0], quad[3], quad[2], quad[1]] };
                    let k = *patch_of.entry(key).or_insert_with(|| {
                        net.patch_organs.push(key);
                        net.quads.push(Vec::new());
                        net.quads.len() - 1
                    });
                    net.quads[k].push(quad);
                }
            }
        }
    }
    net
}

/// The neighbours each vertex is smoothed toward, as compressed rows (`offsets[i]..offsets[i + 1]`
/// indexes `neighbours`): a vertex between two organs, all its neighbours along quad sides; a
/// vertex on a junction of three organs, its two neighbours on the same junction curve (cells with
/// at least those organs); other junction vertices (curve ends, corners of four or more organs,
/// tangles) none: they hold still.
fn smoothing_neighbours(net: &Net, organs: &[u32], dims: [usize; 3]) -> (Vec<usize>, Vec<u32>) {
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for q in net.quads.iter().flatten() {
        for k in 0..4 {
            pairs.push((q[k], q[(k + 1) % 4]));
            pairs.push((q[(k + 1) % 4], q[k]));
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    let mut offsets = vec![0usize; net.positions.len() + 1];
    let mut neighbours = Vec::with_capacity(pairs.len());
    for row in pairs.chunk_by(|a, b| a.0 == b.0) {
        let i = row[0].0 as usize;
        if !net.junction[i] {
            neighbours.extend(row.iter().map(|p| p.1));
        } else {
            let (mine, count) = distinct(cell_corners(organs, dims, net.cells[i]));
            let along: Vec<u32> = row
                .iter()
                .map(|p| p.1)
                .filter(|&n| net.junction[n as usize])
                .filter(|&n| {
                    let (theirs, m) = distinct(cell_corners(organs, dims, net.cells[n as usize]));
                    mine[..count].iter().all(|o| theirs[..m].contains(o))
                })
                .collect();
            if count == 3 && along.len() == 2 {
                neighbours.extend(along);
            }
        }
        offsets[i + 1] = neighbours.len();
    }
    for i in 0..net.positions.len() {
        offsets[i + 1] = offsets[i + 1].max(offsets[i]);
    }
    (offsets, neighbours)
}

/// Taubin's lambda/mu smoothing (as [`crate::surface::taubin_smooth`]) over given neighbour rows.
fn taubin(positions: &mut Vec<Vec3>, offsets: &[usize], neighbours: &[u32], iterations: usize) {
    let mut next = positions.clone();
    for it in 0..iterations * 2 {
        let factor = if it % 2 == 0 { 0.5 } else { -0.53 };
        for (i, out) in next.iter_mut().enumerate() {
            let ns = &neighbours[offsets[i]..offsets[i + 1]];
            let p = positions[i];
            *out = if ns.is_empty() {
                p
            } else {
                let mean = ns.iter().map(|&n| positions[n as usize]).sum::<Vec3>() / ns.len() as f32;
                p + (mean - p) * factor
            };
        }
        std::mem::swap(positions, &mut next);
    }
}

/// Two triangles per quad, split along the shorter diagonal.
fn triangulate(quads: &[[u32; 4]], positions: &[Vec3]) -> Vec<u32> {
    let mut indices = Vec::with_capacity(quads.len() * 6);
    for &[a, b, c, d] in quads {
        let at = |i: u32| positions[i as usize];
        if at(a).distance_squared(at(c)) <= at(b).distance_squared(at(d)) {
            indices.extend_from_slice(&[a, b, c, a, c, d]);
        } else {
            indices.extend_from_slice(&[a, b, d, b, c, d]);
        }
    }
    indices
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    /// A grid with each box `(lo, hi exclusive, label)` painted over the last.
    fn paint(dims: [usize; 3], boxes: &[([usize; 3], [usize; 3], u32)]) -> Vec<u32> {
        let mut g = vec![0; dims[0] * dims[1] * dims[2]];
        for &(lo, hi, label) in boxes {
            for z in lo[2]..hi[2] {
                for y in lo[1]..hi[1] {
                    for x in lo[0]..hi[0] {
                        g[x + dims[0] * (y + dims[1] * z)] = label;
                    }
                }
            }
        }
        g
    }

    /// Directed edges not used exactly once, or whose reverse is not: 0 for a closed 2-manifold.
    /// Panics where the surface is not watertight (an edge's uses unmatched the other way).
    fn defects(m: &Mesh) -> usize {
        let mut edges = HashMap::new();
        for t in m.indices.chunks_exact(3) {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        assert!(edges.iter().all(|(&(a, b), &n)| edges.get(&(b, a)) == Some(&n)), "not watertight");
        edges.values().filter(|&&n| n != 1).count()
    }

    /// Closed and consistently wound: every edge is used by exactly two triangles, once each way.
    fn is_closed(m: &Mesh) -> bool {
        m.triangle_count() > 0 && defects(m) == 0
    }

    type Tri = [[u32; 3]; 3];

    /// A triangle by its corners' exact coordinates, rotated to start at the least (winding kept).
    fn tri(m: &Mesh, t: &[u32], reversed: bool) -> Tri {
        let c = |i: u32| m.positions[i as usize].map(f32::to_bits);
        let mut v = if reversed { [c(t[0]), c(t[2]), c(t[1])] } else { [c(t[0]), c(t[1]), c(t[2])] };
        let least = (0..3).min_by_key(|&k| v[k]).unwrap_or(0);
        v.rotate_left(least);
        v
    }

    fn tris(m: &Mesh, reversed: bool) -> HashSet<Tri> {
        m.indices.chunks_exact(3).map(|t| tri(m, t, reversed)).collect()
    }

    fn area(m: &Mesh, t: &[u32]) -> f32 {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(m.positions[i as usize]));
        (b - a).cross(c - a).length() / 2.0
    }

    /// How many triangles of `a` organ `b` draws too (reversed, same coordinates), and their area.
    fn shared(a: &Mesh, b: &Mesh) -> (usize, f32) {
        let theirs = tris(b, true);
        let mine: Vec<&[u32]> = a.indices.chunks_exact(3).filter(|t| theirs.contains(&tri(a, t, false))).collect();
        (mine.len(), mine.iter().map(|t| area(a, t)).sum())
    }

    fn opts(smoothing: usize, triangles: usize) -> Options {
        Options { smoothing, triangles, ..Default::default() }
    }

    #[test]
    fn labels_become_organ_numbers() {
        let numbers = organ_numbers(&[0, 5, 7, 9, 4, 5], &[vec![5, 9], vec![7]]);
        assert_eq!(numbers, [0, 1, 2, 1, 0, 1]);
    }

    #[test]
    fn two_boxes_share_their_face() {
        let dims = [16, 10, 10];
        let g = paint(dims, &[([2, 2, 2], [8, 8, 8], 1), ([8, 2, 2], [14, 8, 8], 2)]);
        let grid = LabelGrid { dims, labels: &g };
        for budget in [1_000_000, 300] {
            let m = extract(&grid, &[vec![1], vec![2]], &opts(10, budget));
            for mesh in &m {
                assert!(is_closed(mesh), "budget {budget}");
                let vol = mesh.signed_volume();
                assert!(vol > 0.7 * 216.0 && vol < 216.0, "budget {budget}: volume {vol}");
                assert!(mesh.validate().is_ok());
            }
            // Voxel index space: box 1 covers voxel centres 2..=7, so x spans about [1.5, 7.5].
            let b = m[0].bounds();
            assert!(b.min[0] > 1.4 && b.min[0] < 1.6 && b.max[0] == 7.5, "{b:?}");
            // The face x = 7.5: the same vertices and (reversed) triangles in both.
            let on_face = |mesh: &Mesh| -> HashSet<[u32; 3]> {
                mesh.positions.iter().filter(|p| p[0] == 7.5).map(|p| p.map(f32::to_bits)).collect()
            };
            assert!(on_face(&m[0]).len() >= 4, "budget {budget}");
            assert_eq!(on_face(&m[0]), on_face(&m[1]), "budget {budget}");
            let (n01, a01) = shared(&m[0], &m[1]);
            assert_eq!(n01, shared(&m[1], &m[0]).0);
            assert!(a01 > 0.8 * 36.0 && a01 < 1.05 * 36.0, "budget {budget}: shared area {a01}");
            if budget == 1_000_000 {
                assert!(on_face(&m[0]).len() >= 25);
            } else {
                let drawn: usize = m.iter().map(Mesh::triangle_count).sum();
                assert!(drawn <= 330, "{drawn} triangles");
            }
        }
    }

    #[test]
    fn decimated_to_the_end_nothing_folds() {
        let dims = [16, 10, 10];
        let g = paint(dims, &[([2, 2, 2], [8, 8, 8], 1), ([8, 2, 2], [14, 8, 8], 2)]);
        let m = extract(&LabelGrid { dims, labels: &g }, &[vec![1], vec![2]], &opts(10, 0));
        for (mesh, centre) in m.iter().zip([Vec3::new(4.5, 4.5, 4.5), Vec3::new(10.5, 4.5, 4.5)]) {
            assert!(is_closed(mesh) && mesh.signed_volume() > 0.4 * 216.0);
            // Both boxes stay convex: every triangle faces away from its box's centre.
            for t in mesh.indices.chunks_exact(3) {
                let [a, b, c] = [t[0], t[1], t[2]].map(|i| Vec3::from(mesh.positions[i as usize]));
                assert!((b - a).cross(c - a).dot((a + b + c) / 3.0 - centre) > 0.0, "folded: {a} {b} {c}");
            }
        }
    }

    /// Checks the three organs of a cube split in three: closed, and each pair sharing its face.
    fn check_three(m: &[Mesh], stage: &str) {
        for (k, mesh) in m.iter().enumerate() {
            assert!(is_closed(mesh), "{stage}: organ {k} not closed");
            assert!(mesh.signed_volume() > 0.0, "{stage}: organ {k} inside out");
        }
        for (a, b) in [(0, 1), (0, 2), (1, 2)] {
            let (n, area) = shared(&m[a], &m[b]);
            assert_eq!(n, shared(&m[b], &m[a]).0, "{stage}: {a}-{b}");
            // Each interface is a 6 x 12 face.
            assert!(area > 0.8 * 72.0 && area < 1.05 * 72.0, "{stage}: {a}-{b} shares area {area}");
        }
    }

    #[test]
    fn three_organs_meet_seamlessly() {
        let dims = [16, 16, 16];
        let g = paint(dims, &[([2, 2, 2], [8, 14, 14], 1), ([8, 2, 2], [14, 8, 14], 2), ([8, 8, 2], [14, 14, 14], 3)]);
        let mut shared_net = interfaces(&OrganGrid { dims, organs: &g }, &opts(10, 0));
        check_three(&shared_net.organ_meshes(3), "smoothed");
        assert!(junction_curve(&shared_net.organ_meshes(3)) >= 8);
        let before = shared_net.drawn_triangles();
        shared_net.decimate(before / 4);
        assert!(shared_net.drawn_triangles() < before / 3, "{before} -> {}", shared_net.drawn_triangles());
        check_three(&shared_net.organ_meshes(3), "decimated");
        // As far as it goes: the junction curve keeps its course, all stay closed.
        shared_net.decimate(0);
        let m = shared_net.organ_meshes(3);
        assert!(m.iter().all(|m| is_closed(m) && m.signed_volume() > 0.5 * 432.0));
        junction_curve(&m);
    }

    /// The vertices all three organs share (away from the curve's ends), which must stay in the
    /// plane between 2 and 3, near x = 7.5: how many there are.
    fn junction_curve(m: &[Mesh]) -> usize {
        let keys = |m: &Mesh| -> HashSet<[u32; 3]> { m.positions.iter().map(|p| p.map(f32::to_bits)).collect() };
        let curve: Vec<[u32; 3]> = keys(&m[0])
            .intersection(&keys(&m[1]))
            .filter(|k| keys(&m[2]).contains(*k) && (3.0..12.0).contains(&f32::from_bits(k[2])))
            .copied()
            .collect();
        let off = |k: &[u32; 3]| f32::from_bits(k[1]) != 7.5 || !(7.5..7.7).contains(&f32::from_bits(k[0]));
        assert!(!curve.iter().any(off), "{curve:?}");
        curve.len()
    }

    fn sphere_in_shell(n: usize, inner: f32, outer: f32) -> Vec<u32> {
        let c = (n as f32 - 1.0) / 2.0;
        (0..n * n * n)
            .map(|i| {
                let d = Vec3::new((i % n) as f32 - c, ((i / n) % n) as f32 - c, (i / (n * n)) as f32 - c).length();
                if d < inner {
                    1
                } else if d < outer {
                    2
                } else {
                    0
                }
            })
            .collect()
    }

    /// The shell's inner surface is the sphere's, reversed: same vertices, same triangles.
    fn check_nested(m: &[Mesh], stage: &str) {
        let (sphere, shell) = (&m[0], &m[1]);
        assert!(is_closed(sphere) && is_closed(shell), "{stage}");
        assert!(tris(sphere, true).is_subset(&tris(shell, false)), "{stage}");
        let keys = |m: &Mesh| -> HashSet<[u32; 3]> { m.positions.iter().map(|p| p.map(f32::to_bits)).collect() };
        assert!(keys(sphere).is_subset(&keys(shell)), "{stage}");
        assert_eq!(shared(sphere, shell).0, sphere.triangle_count(), "{stage}");
        // The shell's signed volume is its outer surface's less the inner one's.
        let exact = 4.0 / 3.0 * std::f32::consts::PI * (10.0f32.powi(3) - 5.0f32.powi(3));
        let vol = shell.signed_volume();
        assert!((vol - exact).abs() / exact < 0.1, "{stage}: shell volume {vol} vs {exact}");
    }

    #[test]
    fn sphere_in_shell_shares_the_inner_surface() {
        let n = 28;
        let g = sphere_in_shell(n, 5.0, 10.0);
        let mut net = interfaces(&OrganGrid { dims: [n; 3], organs: &g }, &opts(10, 0));
        check_nested(&net.organ_meshes(2), "smoothed");
        let budget = 1500;
        assert!(net.drawn_triangles() > 3 * budget, "{}", net.drawn_triangles());
        net.decimate(budget);
        let m = net.organ_meshes(2);
        check_nested(&m, "decimated");
        let drawn: usize = m.iter().map(Mesh::triangle_count).sum();
        assert_eq!(drawn, net.drawn_triangles());
        assert!(drawn as f32 > 0.8 * budget as f32 && drawn as f32 <= 1.05 * budget as f32, "{drawn}");
    }

    #[test]
    fn thin_sheet_stays_closed_and_whole() {
        // A sheet of 3, one voxel thick, between boxes 1 and 2; its rim on the outside.
        let dims = [16, 14, 14];
        let g = paint(dims, &[([2, 2, 2], [7, 12, 12], 1), ([7, 2, 2], [8, 12, 12], 3), ([8, 2, 2], [13, 12, 12], 2)]);
        let mut net = interfaces(&OrganGrid { dims, organs: &g }, &opts(10, 0));
        let budget = net.drawn_triangles() / 10;
        for (budget, whole) in [(budget, 0.7), (0, 0.3)] {
            net.decimate(budget);
            let m = net.organ_meshes(3);
            assert!(m.iter().all(is_closed), "budget {budget}");
            for (k, mesh) in m.iter().enumerate() {
                let (vol, full) = (mesh.signed_volume(), [500.0, 500.0, 100.0][k]);
                assert!(vol > whole * full && vol < full, "budget {budget}: organ {k} volume {vol}");
            }
            let faces = [shared(&m[2], &m[0]).1, shared(&m[2], &m[1]).1];
            assert!(faces.iter().all(|&a| a > whole * 100.0), "budget {budget}: sheet faces {faces:?}");
        }
    }

    #[test]
    fn decimation_adds_no_pinches() {
        // Twelve organs in a ball, cut as the nearest of random seeds, with ragged borders.
        let (n, mut rng) = (40, crate::rng::XorShift::seeded(7));
        let seeds: Vec<Vec3> = (0..12).map(|_| Vec3::new(rng.unit(), rng.unit(), rng.unit()) * 30.0 + 5.0).collect();
        let g: Vec<u32> = (0..n * n * n)
            .map(|i| {
                let p = Vec3::new((i % n) as f32, ((i / n) % n) as f32, (i / (n * n)) as f32);
                let jitter = Vec3::new(rng.unit(), rng.unit(), rng.unit()) * 3.0;
                let nearest = (0..12)
                    .min_by(|&a, &b| (p + jitter).distance(seeds[a]).total_cmp(&(p + jitter).distance(seeds[b])));
                if p.distance(Vec3::splat(19.5)) < 17.0 {
                    nearest.map_or(0, |k| k as u32 + 1)
                } else {
                    0
                }
            })
            .collect();
        let mut net = interfaces(&OrganGrid { dims: [n; 3], organs: &g }, &Options::default());
        let raw: Vec<usize> = net.organ_meshes(12).iter().map(defects).collect();
        for budget in [net.drawn_triangles() / 8, 0] {
            net.decimate(budget);
            let m = net.organ_meshes(12);
            for (k, mesh) in m.iter().enumerate() {
                assert!(defects(mesh) <= raw[k], "budget {budget}: organ {k}: {} > {}", defects(mesh), raw[k]);
                assert!(mesh.signed_volume() > 0.0, "budget {budget}: organ {k} inside out");
            }
        }
        assert!(raw.iter().sum::<usize>() > 0, "ragged enough to have some");
    }

    #[test]
    fn islands_join_their_neighbours() {
        let dims = [16, 12, 12];
        let clean =
            paint(dims, &[([2, 2, 2], [8, 8, 8], 1), ([9, 2, 2], [13, 8, 8], 2), ([11, 10, 10], [12, 11, 11], 3)]);
        let at = |x: usize, y: usize, z: usize| x + 16 * (y + 12 * z);
        let mut g = clean.clone();
        g[at(4, 4, 4)] = 2; // a speck of 2 inside 1
        g[at(3, 3, 3)] = 0; // a bubble of outside inside 1
        g[at(4, 10, 10)] = 1; // a speck of 1 in the outside
        g[at(5, 10, 10)] = 1;
        let mut fixed = g.clone();
        assert_eq!(remove_islands(&mut fixed, dims, 30), 4);
        assert_eq!(fixed, clean, "specks gone; organ 3's only island stays, however small");
        let meshes = |g: &[u32]| interfaces(&OrganGrid { dims, organs: g }, &opts(5, 0)).organ_meshes(3);
        let (specked, smooth) = (meshes(&g), meshes(&clean));
        assert!(specked.iter().all(is_closed));
        assert_eq!(specked, smooth);
    }

    #[test]
    fn performance_64_cubed() {
        let n = 64;
        let c = (n as f32 - 1.0) / 2.0;
        let g: Vec<u32> = (0..n * n * n)
            .map(|i| {
                let p = Vec3::new((i % n) as f32, ((i / n) % n) as f32, (i / (n * n)) as f32) - c;
                match p.length() {
                    d if d < 20.0 => 1 + (p.x > 0.0) as u32 + 2 * (p.y > 0.0) as u32,
                    d if d < 28.0 => 5,
                    _ => 0,
                }
            })
            .collect();
        let start = std::time::Instant::now();
        let mut net = interfaces(&OrganGrid { dims: [n; 3], organs: &g }, &Options::default());
        let smoothed = start.elapsed();
        let raw = net.drawn_triangles();
        net.decimate(20_000);
        let m = net.organ_meshes(5);
        println!(
            "64^3, 5 organs: nets + smoothing {smoothed:?}, total {:?}; {raw} -> {} drawn triangles",
            start.elapsed(),
            net.drawn_triangles()
        );
        assert!(m.iter().all(is_closed));
    }
}
