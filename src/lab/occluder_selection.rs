//! The occluder-selection experiment of thesis Figure 14: at fixed viewpoints, the share of
//! triangles culled against the number of occluder leaves allowed, for three ways of ranking the
//! occluders.
//!
//! - Viewpoints are world-space cameras.
//! - **PS**, projected size: pixels each candidate covers, occlusion ignored.
//! - **FH**, first hit: pixels each candidate holds in an exact ID render (the visible ones).
//! - **MOS**: the minimum occluder set selection of that viewpoint
//!   ([`crate::mos::select_for_view`]).
//! - Each prefix of each ranking is handed to the run-time culler
//!   ([`crate::cull::Culler::cull_with`]), so the figures are what the conservative culler really
//!   removes.

use crate::camera::Camera;
use crate::cull::{CullMode, CullSettings, Culler, LeafRef};
use crate::layout::Layout;
use crate::mos::{candidates, coverage, select_for_view, Params};
use crate::organ_set::OrganSet;

/// Occluder counts on the curve by default (the thesis plots up to 512).
pub const COUNTS: [usize; 14] = [1, 2, 4, 8, 16, 32, 48, 64, 96, 128, 192, 256, 384, 512];

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Curve {
    /// (occluders allowed, mean culled percent over the viewpoints).
    pub curve: Vec<(usize, f64)>,
    pub best_culled_percent: f64,
    /// The fewest occluders allowed that come within [`BEST_TOLERANCE`] points of the best.
    pub occluders_to_best: usize,
    /// Mean length of the ranking (candidates it holds) over the viewpoints.
    pub ranked: f64,
}

/// Percentage points within which a count "reaches" a method's best.
pub const BEST_TOLERANCE: f64 = 0.1;

#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Results {
    pub ps: Curve,
    pub fh: Curve,
    pub mos: Curve,
    pub viewpoints: usize,
    /// Seconds the minimum occluder set selection took per viewpoint (mean).
    pub mos_seconds_per_view: f64,
}

/// Runs the experiment. `image` is the ID render's size for first hit and projected size (square);
/// `params` the MOS pre-processing (its `size` is the culling raster's); `progress(done, total)`.
pub fn run(
    set: &OrganSet,
    layout: &Layout,
    cameras: &[Camera],
    counts: &[usize],
    image: usize,
    params: &Params,
    progress: &mut dyn FnMut(usize, usize),
) -> Results {
    let max = counts.iter().copied().max().unwrap_or(0);
    let settings = CullSettings {
        mode: CullMode::Occlusion,
        width: params.size,
        height: params.size,
        occluder_triangles: usize::MAX,
        ..Default::default()
    };
    let mut sums = [vec![0.0; counts.len()], vec![0.0; counts.len()], vec![0.0; counts.len()]];
    let mut lengths = [0usize; 3];
    let mut mos_seconds = 0.0;
    for (v, camera) in cameras.iter().enumerate() {
        let cands = candidates(set, layout, camera, image);
        let images = coverage::leaf_images(set, layout, &camera.view_projection(1.0), &cands, image, image);
        let ranked = |score: &[u32]| -> Vec<LeafRef> {
            let mut order: Vec<usize> = (0..cands.len()).filter(|&i| score[i] > 0).collect();
            order.sort_by_key(|&i| (std::cmp::Reverse(score[i]), i));
            order.into_iter().map(|i| cands[i]).collect()
        };
        let projected: Vec<u32> = images.iter().map(|im| im.as_ref().map_or(0, |im| im.pixels)).collect();
        let ps = ranked(&projected);
        let fh = ranked(&coverage::visible_pixels(&images, image, image));
        let started = std::time::Instant::now();
        let mos = select_for_view(set, layout, camera, &Params { limit: max, ..params.clone() }).occluders;
        mos_seconds += started.elapsed().as_secs_f64();
        for (m, list) in [ps, fh, mos].iter().enumerate() {
            lengths[m] += list.len();
            for (c, &n) in counts.iter().enumerate() {
                let given = &list[..n.min(list.len())];
                let input = crate::cull::CullInput::new(set, layout, camera, 1.0);
                let (_, stats) = Culler::default().cull_with(&input, &settings, Some(given));
                sums[m][c] += stats.culled_percent();
            }
        }
        progress(v + 1, cameras.len());
    }
    let views = cameras.len().max(1) as f64;
    let curve = |m: usize| {
        let curve: Vec<(usize, f64)> = counts.iter().zip(&sums[m]).map(|(&n, s)| (n, s / views)).collect();
        let best = curve.iter().map(|p| p.1).fold(0.0, f64::max);
        let to_best = curve.iter().find(|p| p.1 >= best - BEST_TOLERANCE).map_or(0, |p| p.0);
        Curve { curve, best_culled_percent: best, occluders_to_best: to_best, ranked: lengths[m] as f64 / views }
    };
    Results {
        ps: curve(0),
        fh: curve(1),
        mos: curve(2),
        viewpoints: cameras.len(),
        mos_seconds_per_view: mos_seconds / views,
    }
}
