//! Minimum occluder sets (thesis §3.2, Poon & Wang 1999): pre-processing that picks, per viewpoint
//! of a grid around the set, a small list of occluder leaves that hides as much as a much larger
//! list chosen by projected size, for the set's layout as it was pre-processed.
//!
//! - Viewpoints and cameras in world space; occluders and occludees are projected into the pixels
//!   of a square image of the culling raster's size (x right, y down, depth = NDC z).
//! - The result is stored in a [`crate::cull::database::Database`] beside the set, used at run
//!   time while the layout is unchanged ([`crate::cull::choose_occluders`]).
//! - Per viewpoint ([`select_for_view`]):
//! 1. candidates: the on-screen leaves of opaque, visible organs, each rasterised alone
//!    ([`coverage`], centre-sampled) and cut to the pixels inside its organ's image (the run-time
//!    rasteriser counts only pixels wholly inside an occluder);
//! 2. occludees: the on-screen hierarchy nodes of drawn organs with more than 20 triangles; per
//!    pixel of an occludee's rectangle its occluder stack (candidates nearer than the occludee's
//!    nearest depth), the combination table and its cheapest minimum occluder sets ([`search`]);
//! 3. gains (the triangles of the occludees a set hides, supersets inheriting), cost (occluders
//!    and their projected size), score and selection over an ID buffer ([`select`]).

pub mod coverage;
pub mod search;
pub mod select;

use crate::camera::Camera;
use crate::cull::project::{project_box, ScreenBox};
use crate::cull::{LeafRef, PixelRect};
use crate::layout::Layout;
use crate::mesh::Bounds;
use crate::organ_set::OrganSet;
use coverage::LeafImage;
use rayon::prelude::*;
use search::SearchLimits;

use crate::cull::database::{self, Database};

/// Pre-processing parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Params {
    /// Image (and culling raster) size, pixels.
    pub size: usize,
    /// Most occluders kept per viewpoint.
    pub limit: usize,
    /// Occludees are nodes with more triangles than this (thesis: 20 primitives).
    pub min_occludee_triangles: u32,
    /// Minimum occluder sets kept per occludee, and partial sets tried per occludee.
    pub search: SearchLimits,
    /// Cost of a set = its occluders + `size_weight` x their projected size in units of the mean
    /// candidate's projected size.
    pub size_weight: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            size: 128,
            limit: 128,
            min_occludee_triangles: 20,
            search: SearchLimits { keep: 4, steps: 4000 },
            size_weight: 0.5,
        }
    }
}

/// What one viewpoint's selection found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ViewSelection {
    /// Chosen occluders, best first.
    pub occluders: Vec<LeafRef>,
    pub candidates: usize,
    /// Occludees examined, and those some set of candidates could hide.
    pub occludees: usize,
    pub hideable: usize,
    /// Distinct minimum occluder sets found.
    pub sets: usize,
}

/// The leaves of opaque, visible organs in the frustum (those around the eye included: the
/// rasterisers keep their triangles in front of it): the occluder candidates.
pub fn candidates(set: &OrganSet, layout: &Layout, camera: &Camera, size: usize) -> Vec<LeafRef> {
    let view_proj = camera.view_projection(1.0);
    let mut out = Vec::new();
    for (o, (organ, state)) in set.organs.iter().zip(&layout.organs).enumerate() {
        if !state.is_opaque() {
            continue;
        }
        let mvp = view_proj * state.transform.matrix();
        for (l, &n) in organ.bvh.leaves.iter().enumerate() {
            if project_box(&mvp, &organ.bvh.nodes[n as usize].bounds, size, size) != ScreenBox::Outside {
                out.push(LeafRef { organ: o as u32, leaf: l as u32, stand_in: false });
            }
        }
    }
    out
}

/// The occluders of one viewpoint by the minimum occluder set algorithm.
pub fn select_for_view(set: &OrganSet, layout: &Layout, camera: &Camera, params: &Params) -> ViewSelection {
    let n = params.size.max(1);
    let view_proj = camera.view_projection(1.0);
    let cands = candidates(set, layout, camera, n);
    let images = coverage::leaf_images(set, layout, &view_proj, &cands, n, n);
    let organs: Vec<u32> = cands.iter().map(|c| c.organ).collect();
    let images = coverage::interior(&images, &organs, n, n);
    // Per pixel, the candidates covering it, nearest first.
    let mut lists: Vec<Vec<(f32, u32)>> = vec![Vec::new(); n * n];
    for (i, image) in images.iter().enumerate() {
        for (x, y, d) in image.iter().flat_map(|im| im.covered()) {
            lists[y * n + x].push((d, i as u32));
        }
    }
    lists.par_iter_mut().for_each(|l| l.sort_unstable_by(|a, b| a.0.total_cmp(&b.0)));
    let cost = cost_fn(&images, params.size_weight);
    // Occludees: on-screen nodes of drawn organs above the size threshold.
    let mut occludees: Vec<(f64, PixelRect, f32)> = Vec::new();
    for (organ, state) in set.organs.iter().zip(&layout.organs) {
        if !state.is_drawn() {
            continue;
        }
        let mvp = view_proj * state.transform.matrix();
        for node in &organ.bvh.nodes {
            if node.count > params.min_occludee_triangles {
                if let ScreenBox::Rect { rect, z, .. } = project_box(&mvp, &node.bounds, n, n) {
                    occludees.push((node.count as f64, rect, z));
                }
            }
        }
    }
    let found: Vec<Vec<(Vec<u32>, f64)>> = occludees
        .par_iter()
        .map(|&(gain, rect, z)| {
            let PixelRect { x0, y0, x1, y1 } = rect;
            let stack = |x: usize, y: usize| {
                let l = &lists[y * n + x];
                let mut ids: Vec<u32> = l[..l.partition_point(|e| e.0 < z)].iter().map(|e| e.1).collect();
                ids.sort_unstable();
                ids
            };
            // Quick rejection: a pixel with nothing in front.
            let open = (y0..=y1).any(|y| (x0..=x1).any(|x| lists[y * n + x].first().is_none_or(|e| e.0 >= z)));
            if open {
                return Vec::new();
            }
            let stacks: Vec<Vec<u32>> =
                (y0..=y1).flat_map(|y| (x0..=x1).map(move |x| (x, y))).map(|(x, y)| stack(x, y)).collect();
            let Some(table) = search::combination_table(stacks.iter().map(|s| s.as_slice())) else {
                return Vec::new();
            };
            search::minimum_occluder_sets(&table, &cost, params.search).into_iter().map(|s| (s, gain)).collect()
        })
        .collect();
    let hideable = found.iter().filter(|f| !f.is_empty()).count();
    let grouped = select::gains(found.into_iter().flatten());
    let sets = grouped.len();
    let ranked = select::rank(grouped, &cost);
    let chosen = select::select(&ranked, &images, n, n, params.limit);
    ViewSelection {
        occluders: chosen.into_iter().map(|i| cands[i as usize]).collect(),
        candidates: cands.len(),
        occludees: occludees.len(),
        hideable,
        sets,
    }
}

/// Cost of a set of candidates: their number plus `size_weight` x their projected size in units
/// of the mean candidate's.
fn cost_fn(images: &[Option<LeafImage>], size_weight: f64) -> impl Fn(&[u32]) -> f64 + Sync + '_ {
    let sizes: Vec<f64> = images.iter().map(|im| im.as_ref().map_or(0.0, |im| im.pixels as f64)).collect();
    let mean = (sizes.iter().sum::<f64>() / sizes.len().max(1) as f64).max(1.0);
    move |set: &[u32]| set.iter().map(|&i| 1.0 + size_weight * sizes[i as usize] / mean).sum()
}

/// The viewpoint grid: `directions` points spread evenly on a sphere (a Fibonacci lattice) around
/// the centre of `home`, each at the distances (multiples of the distance that frames `home`),
/// looking at the centre.
pub fn viewpoints(home: &Bounds, directions: usize, distances: &[f32]) -> Vec<Camera> {
    let golden = 180.0 * (3.0 - 5f32.sqrt());
    let mut out = Vec::new();
    for i in 0..directions {
        let elevation = (1.0 - 2.0 * (i as f32 + 0.5) / directions as f32).asin().to_degrees();
        let azimuth = (i as f32 * golden) % 360.0;
        let base = Camera::orbit(home, azimuth, elevation);
        for &d in distances {
            let mut camera = base.zoomed(d);
            camera.fit_depth(home);
            out.push(camera);
        }
    }
    out
}

/// The default distances of the grid: the framing distance and half again.
pub const DISTANCES: [f32; 2] = [1.0, 1.5];

/// Pre-processes the set for `layout`: every viewpoint of the grid, in parallel;
/// `progress(done, total)` hears of each.
pub fn preprocess(
    set: &OrganSet,
    layout: &Layout,
    directions: usize,
    params: &Params,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Database {
    let cameras = viewpoints(&layout.bounds(set), directions, &DISTANCES);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let views: Vec<database::Viewpoint> = cameras
        .par_iter()
        .map(|camera| {
            let chosen = select_for_view(set, layout, camera, params);
            progress(done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1, cameras.len());
            database::Viewpoint { eye: camera.eye.into(), target: camera.target.into(), occluders: chosen.occluders }
        })
        .collect();
    Database::new(set, layout, (directions, params.size, params.limit), views)
}
