//! The culling benchmark (thesis §5, Figure 22): the camera orbits the set, and each culling mode
//! runs over the same frames in the same process.
//!
//! - The orbit is in world space, around the set's centre.
//! - Each frame records CPU cull time, frame time (wall time until the GPU queue has finished),
//!   triangles drawn and the share culled.
//! - Once per frame it also renders every leaf's number at full resolution to find the leaves
//!   exact visibility could cull, and how many of those the culler culled.

use crate::camera::Camera;
use crate::cull::database::Database;
use crate::cull::{CullInput, CullMode, CullSettings, Culler, DrawList};
use crate::error::{Error, Result};
use crate::layout::Layout;
use crate::organ_set::OrganSet;
use crate::render::{FrameInput, GpuContext, Renderer, Target};
use crate::transparency::TransparencySettings;
use std::time::Instant;

/// One frame of one mode.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FrameRecord {
    pub mode: CullMode,
    pub frame: usize,
    pub cull_ms: f64,
    /// Of `cull_ms`, choosing and rasterising the occluders ([`crate::cull::CullStats::occluders_ms`]).
    pub occluders_ms: f64,
    pub frame_ms: f64,
    /// The frame's GPU time, where the adapter has timestamp queries.
    pub gpu_ms: Option<f64>,
    pub triangles: usize,
    pub triangles_drawn: usize,
    pub culled_percent: f64,
    pub occluder_triangles: usize,
    pub occluder_leaves: usize,
    /// Where the occluders came from.
    pub source: Option<crate::cull::OccluderSource>,
    pub nodes_tested: usize,
    /// Triangles culled as facing away (normal cones), apart from occlusion.
    pub back_face_culled: usize,
    /// Triangles culled as removed by the clip planes.
    pub clip_culled: usize,
    /// Triangles culled as faces inside intact solids (among the occlusion culled).
    pub inside_culled: usize,
    /// Leaves hidden in an exact visibility pass, and how many of them this mode culled.
    pub exact_hidden_leaves: usize,
    pub culled_hidden_leaves: usize,
    /// Triangles of those hidden leaves (what an exact pass could cull), and of the visible ones.
    pub exact_hidden_triangles: usize,
    pub exact_visible_triangles: usize,
}

/// The camera of frame `i` of `n`: a full turn around the set at 15 degrees elevation.
pub fn orbit_camera(home: &crate::mesh::Bounds, i: usize, n: usize) -> Camera {
    Camera::orbit(home, 360.0 * i as f32 / n.max(1) as f32, 15.0)
}

/// The camera path of a run: the orbit of the Virtual Brain run, or one of the thesis's three
/// walkthrough routes (§5.1.1.2) for a city on a street grid at 1/20 of its extent ([`super::city`]),
/// at 5 m above the ground in a 2 km city.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Route {
    Orbit,
    /// From the lower-left corner towards the centre, looking across the city: the most occluded.
    Best,
    /// Along the central street, looking down it and to the sides.
    Average,
    /// At the upper-right corner, looking out of the city: hardly anything to cull.
    Worst,
}

impl Route {
    pub const ALL: [Route; 4] = [Route::Orbit, Route::Best, Route::Average, Route::Worst];

    pub fn name(self) -> &'static str {
        match self {
            Route::Orbit => "orbit",
            Route::Best => "best",
            Route::Average => "average",
            Route::Worst => "worst",
        }
    }

    pub fn parse(s: &str) -> Option<Route> {
        Route::ALL.into_iter().find(|r| r.name() == s)
    }

    /// The camera of frame `i` of `n` (world space).
    pub fn camera(self, home: &crate::mesh::Bounds, i: usize, n: usize) -> Camera {
        use glam::Vec3;
        let t = if n > 1 { i as f32 / (n - 1) as f32 } else { 0.0 };
        let (min, max, centre) = (Vec3::from(home.min), Vec3::from(home.max), home.center());
        let extent = (max.x - min.x).max(max.y - min.y);
        let street = extent / 20.0;
        let z = min.z + extent * 0.0025;
        let (eye, target) = match self {
            Route::Orbit => return orbit_camera(home, i, n),
            Route::Best => {
                let eye = Vec3::new(min.x + street + t * (centre.x - min.x - 3.0 * street), min.y + street, z);
                (eye, Vec3::new(centre.x, centre.y, z))
            }
            Route::Average => {
                let eye = Vec3::new(centre.x - 5.0 * street + t * 10.0 * street, centre.y, z);
                let a = 0.6 * (t * std::f32::consts::TAU).sin();
                (eye, eye + Vec3::new(a.cos(), a.sin(), 0.0))
            }
            Route::Worst => {
                let eye = Vec3::new(max.x - street, max.y - 4.0 * street + t * 3.0 * street, z);
                let a = t * std::f32::consts::FRAC_PI_2;
                (eye, eye + Vec3::new(a.cos(), a.sin(), 0.0))
            }
        };
        let mut camera = Camera { eye, target, up: Vec3::Z, fov_y: crate::camera::FOV_Y, near: 0.1, far: 1.0 };
        camera.fit_depth(home);
        camera
    }
}

/// What one benchmark run measures.
#[derive(Clone, Debug)]
pub struct Run<'a> {
    /// Image size, pixels.
    pub size: [u32; 2],
    pub frames: usize,
    /// The culling modes compared, each over the same frames.
    pub modes: &'a [CullMode],
    pub settings: CullSettings,
    /// How faded organs are drawn in the timed frames.
    pub transparency: TransparencySettings,
    pub route: Route,
    /// The set's pre-computed occluders, for the modes' cullers.
    pub database: Option<&'a Database>,
    /// Clip planes (with cut faces and organs kept whole) cutting every frame.
    pub section: &'a crate::clip::Section,
}

/// Runs the benchmark; `progress(done, total)` hears of every frame.
pub fn run(
    gpu: &GpuContext,
    set: &OrganSet,
    layout: &Layout,
    run: &Run,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<FrameRecord>> {
    let Run { size, frames, modes, ref settings, transparency, route, database, section } = *run;
    let renderer = Renderer::new(&gpu.device, set)?;
    let mut target = Target::new(&gpu.device, size[0], size[1])?;
    let home = layout.bounds(set);
    let first_id: Vec<u32> = set
        .organs
        .iter()
        .scan(0u32, |acc, o| {
            let first = *acc;
            *acc += o.bvh.leaves.len() as u32;
            Some(first)
        })
        .collect();
    let wait = || gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| Error::gpu("poll", e));
    // Exact visibility per frame, shared by all modes.
    let mut hidden: Vec<Vec<bool>> = Vec::with_capacity(frames);
    let total_leaves: usize = set.organs.iter().map(|o| o.bvh.leaves.len()).sum();
    for i in 0..frames {
        let camera = route.camera(&home, i, frames);
        let frame = FrameInput { section, ..FrameInput::new(set, &camera, layout) };
        renderer.render_leaf_ids(&gpu.device, &gpu.queue, &target, &frame, set, &first_id);
        let ids = target.read_ids(&gpu.device, &gpu.queue)?;
        let mut h = vec![true; total_leaves];
        for id in ids.into_iter().filter(|&id| id > 0) {
            if let Some(x) = h.get_mut(id as usize - 1) {
                *x = false;
            }
        }
        hidden.push(h);
    }
    let mut records = Vec::new();
    let total = frames * modes.len();
    for (m, &mode) in modes.iter().enumerate() {
        let settings = CullSettings { mode, ..*settings };
        // Each mode culls its frames in turn, as a viewer would.
        let mut culler = Culler::new(database.cloned());
        // One frame: cull, draw, wait for the GPU.
        let mut frame = |i: usize| -> Result<(DrawList, crate::cull::CullStats, Option<f64>)> {
            let camera = route.camera(&home, i, frames);
            let exact_cuts = renderer.cuts_geometry();
            let cull = CullInput { section, exact_cuts, ..CullInput::new(set, layout, &camera, target.aspect()) };
            let (draw, stats) = culler.cull_frame(&cull, &settings);
            // The frame waits for the GPU anyway: its GPU time costs nothing more.
            let input = FrameInput {
                draw: Some(&draw),
                transparency,
                section,
                time_gpu: true,
                ..FrameInput::new(set, &camera, layout)
            };
            let drawn = renderer.render(&gpu.device, &gpu.queue, &mut target, &input)?;
            wait()?;
            Ok((draw, stats, drawn.gpu_ms))
        };
        // Warm up pipelines and caches.
        for i in 0..3.min(frames) {
            frame(i)?;
        }
        for (i, hidden) in hidden.iter().enumerate() {
            let started = Instant::now();
            let (draw, stats, gpu_ms) = frame(i)?;
            let frame_ms = started.elapsed().as_secs_f64() * 1000.0;
            let exact = hidden_leaves_culled(set, layout, &draw, hidden, &first_id);
            records.push(FrameRecord {
                mode,
                frame: i,
                cull_ms: stats.cull_ms,
                occluders_ms: stats.occluders_ms,
                frame_ms,
                gpu_ms,
                triangles: stats.triangles,
                triangles_drawn: stats.drawn,
                culled_percent: stats.culled_percent(),
                occluder_triangles: stats.occluder_triangles,
                occluder_leaves: stats.occluder_leaves,
                source: stats.source,
                nodes_tested: stats.nodes_tested,
                back_face_culled: stats.back_face_culled,
                clip_culled: stats.clip_culled,
                inside_culled: stats.inside_culled,
                exact_hidden_leaves: exact.hidden_leaves,
                culled_hidden_leaves: exact.culled_leaves,
                exact_hidden_triangles: exact.hidden_triangles,
                exact_visible_triangles: stats.triangles - exact.hidden_triangles,
            });
            progress(m * frames + i + 1, total);
        }
    }
    Ok(records)
}

/// The drawn organs' leaves that exact visibility hides: how many, how many the draw list left
/// out, and their triangles.
#[derive(Default)]
struct Hidden {
    hidden_leaves: usize,
    culled_leaves: usize,
    hidden_triangles: usize,
}

fn hidden_leaves_culled(set: &OrganSet, layout: &Layout, draw: &DrawList, hidden: &[bool], first_id: &[u32]) -> Hidden {
    let mut out = Hidden::default();
    for (o, organ) in set.organs.iter().enumerate() {
        // Faded organs hide nothing in the exact pass, and their own leaves are not counted.
        if !layout.organs[o].is_opaque() {
            continue;
        }
        let ranges = &draw.ranges[o];
        for l in 0..organ.bvh.leaves.len() as u32 {
            if !hidden[(first_id[o] + l) as usize] {
                continue;
            }
            let r = organ.bvh.leaf_range(l);
            out.hidden_leaves += 1;
            out.hidden_triangles += r.len() / 3;
            if !ranges.iter().any(|d| d.start < r.end && r.start < d.end) {
                out.culled_leaves += 1;
            }
        }
    }
    out
}

/// Summary of one mode over all frames.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Summary {
    pub median_frame_ms: f64,
    pub median_cull_ms: f64,
    /// Median time of a frame's occluders (chosen, rasterised, their maps built), part of the cull.
    pub median_occluders_ms: f64,
    /// Median GPU time of a frame, where the adapter has timestamp queries.
    pub median_gpu_ms: Option<f64>,
    /// Median triangles drawn in a frame.
    pub median_triangles_drawn: f64,
    pub mean_culled_percent: f64,
    pub max_culled_percent: f64,
    /// Share (percent) of the exactly hidden leaves that were culled, over all frames.
    pub hidden_leaves_culled_percent: f64,
    /// Share (percent) of the drawn organs' triangles in exactly hidden leaves: what an exact pass
    /// could cull, over all frames.
    pub exact_hidden_triangles_percent: f64,
    /// Share (percent) of the drawn organs' triangles culled as facing away, over all frames.
    pub back_face_culled_percent: f64,
    /// Share (percent) of the drawn organs' triangles culled as removed by the clip planes.
    pub clip_culled_percent: f64,
    /// Share (percent) of the drawn organs' triangles culled as faces inside intact solids.
    pub inside_culled_percent: f64,
    /// Triangles drawn over the triangles of exactly visible leaves, over all frames: 1 is the
    /// bound at leaf granularity.
    pub drawn_over_visible: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

pub fn summarise(records: &[FrameRecord], mode: CullMode) -> Summary {
    let r: Vec<&FrameRecord> = records.iter().filter(|r| r.mode == mode).collect();
    let n = r.len().max(1) as f64;
    let exact: usize = r.iter().map(|r| r.exact_hidden_leaves).sum();
    let culled: usize = r.iter().map(|r| r.culled_hidden_leaves).sum();
    let sum = |f: fn(&FrameRecord) -> usize| r.iter().map(|r| f(r)).sum::<usize>() as f64;
    let triangles = sum(|r| r.triangles).max(1.0);
    Summary {
        median_frame_ms: median(r.iter().map(|r| r.frame_ms).collect()),
        median_cull_ms: median(r.iter().map(|r| r.cull_ms).collect()),
        median_occluders_ms: median(r.iter().map(|r| r.occluders_ms).collect()),
        median_gpu_ms: r
            .iter()
            .all(|r| r.gpu_ms.is_some())
            .then(|| median(r.iter().filter_map(|r| r.gpu_ms).collect())),
        median_triangles_drawn: median(r.iter().map(|r| r.triangles_drawn as f64).collect()),
        mean_culled_percent: r.iter().map(|r| r.culled_percent).sum::<f64>() / n,
        max_culled_percent: r.iter().map(|r| r.culled_percent).fold(0.0, f64::max),
        hidden_leaves_culled_percent: if exact == 0 { 100.0 } else { 100.0 * culled as f64 / exact as f64 },
        exact_hidden_triangles_percent: 100.0 * sum(|r| r.exact_hidden_triangles) / triangles,
        back_face_culled_percent: 100.0 * sum(|r| r.back_face_culled) / triangles,
        clip_culled_percent: 100.0 * sum(|r| r.clip_culled) / triangles,
        inside_culled_percent: 100.0 * sum(|r| r.inside_culled) / triangles,
        drawn_over_visible: sum(|r| r.triangles_drawn) / sum(|r| r.exact_visible_triangles).max(1.0),
    }
}

/// What drawing a triangle must cost (nanoseconds) for `with` culling to pay against `without`
/// (frustum culling or none): its extra CPU time per frame over the triangles a frame it spares.
/// `None` where it spares none.
pub fn break_even_ns(with: &Summary, without: &Summary) -> Option<f64> {
    let spared = without.median_triangles_drawn - with.median_triangles_drawn;
    (spared > 0.0).then(|| (with.median_cull_ms - without.median_cull_ms).max(0.0) * 1e6 / spared)
}

/// What drawing a triangle costs on this adapter (nanoseconds): a frame's GPU time (or, without
/// timestamp queries, its time less culling) over the triangles it drew, with `summary`'s culling.
pub fn draw_ns_per_triangle(summary: &Summary) -> Option<f64> {
    let draw_ms = summary.median_gpu_ms.unwrap_or(summary.median_frame_ms - summary.median_cull_ms);
    (summary.median_triangles_drawn > 0.0).then(|| draw_ms * 1e6 / summary.median_triangles_drawn)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn culling_pays_while_a_triangle_costs_more_than_the_culling_per_triangle_spared() {
        let summary = |cull: f64, drawn: f64| Summary {
            median_frame_ms: 10.0,
            median_cull_ms: cull,
            median_occluders_ms: 0.0,
            median_gpu_ms: Some(4.0),
            median_triangles_drawn: drawn,
            mean_culled_percent: 0.0,
            max_culled_percent: 0.0,
            hidden_leaves_culled_percent: 0.0,
            exact_hidden_triangles_percent: 0.0,
            back_face_culled_percent: 0.0,
            clip_culled_percent: 0.0,
            inside_culled_percent: 0.0,
            drawn_over_visible: 0.0,
        };
        // 5 ms more culling spares 200,000 triangles: it pays above 25 ns a triangle.
        let (with, without) = (summary(5.5, 50_000.0), summary(0.5, 250_000.0));
        assert_eq!(break_even_ns(&with, &without), Some(25.0));
        assert_eq!(break_even_ns(&without, &with), None, "sparing nothing never pays");
        assert_eq!(draw_ns_per_triangle(&without), Some(16.0), "4 ms of GPU time over 250,000");
    }

    #[test]
    fn medians() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(vec![]), 0.0);
    }
}
