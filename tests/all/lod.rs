//! Level of detail (Callahan 2005, ch. 5) on the default brain: the shipped chain of each organ
//! keeps closed organs closed and lies inside the organ; a frame drawn with coarser levels (the
//! left hemisphere faded, whose organs culling keeps) draws far fewer triangles, looks like the
//! full frame, and keeps what culling removed removed.

use crate::common::{default_database, default_set, gpu};
use vbrain::camera::Camera;
use vbrain::cull::{CullSettings, Culler};
use vbrain::layout::Layout;
use vbrain::mesh::Mesh;
use vbrain::render::{FrameInput, Renderer, Target};

#[test]
fn the_default_sets_levels_stay_closed_and_inside_their_organs() {
    let set = default_set();
    let with = set.organs.iter().filter(|o| !o.lods().is_empty()).count();
    assert!(with >= 80, "{with} organs with levels");
    for o in &set.organs {
        let mut before = o.mesh().indices.len();
        let bounds = o.bounds();
        for (k, level) in o.lods().iter().enumerate() {
            let m = Mesh { positions: o.mesh().positions.clone(), normals: Vec::new(), indices: level.clone() };
            assert!(level.len() < before, "{} level {}: {} indices after {before}", o.id, k + 1, level.len());
            if o.closed() {
                assert!(m.is_closed_outward(), "{} level {} is not closed", o.id, k + 1);
            }
            let b = m.bounds();
            let inside = (0..3).all(|a| b.min[a] >= bounds.min[a] - 1e-3 && b.max[a] <= bounds.max[a] + 1e-3);
            assert!(inside, "{} level {} leaves the organ's bounds", o.id, k + 1);
            before = level.len();
        }
    }
}

#[test]
fn a_coarser_frame_draws_fewer_triangles_looks_alike_and_keeps_culling() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    assert!(set.organs.iter().any(|o| !o.lods().is_empty()));
    let mut layout = Layout::new(set);
    for o in set.select("Left hemisphere") {
        layout.organs[o].opacity = 0.5;
    }
    let camera = Camera::orbit(&layout.bounds(set), -60.0, 15.0);
    let mut target = Target::new(&gpu.device, 256, 256).unwrap();
    let frame = FrameInput { background: [0.0, 0.0, 0.0, 1.0], ..FrameInput::new(set, &camera, &layout) };
    let mut culler = Culler::new(default_database());
    let (culled, _) = culler.cull_frame(&renderer.cull_input(&frame, &target), &CullSettings::default());
    let mut shoot = |draw: &vbrain::cull::DrawList| {
        let stats = renderer.render(&gpu.device, &gpu.queue, &mut target, &FrameInput { draw: Some(draw), ..frame });
        (stats.unwrap().triangles_drawn, target.read_color(&gpu.device, &gpu.queue).unwrap())
    };
    let (full_triangles, full) = shoot(&culled);
    let mut coarse = culled.clone();
    renderer.coarsen(&mut coarse, &vec![1; set.organs.len()]);
    for (o, (a, b)) in culled.ranges.iter().zip(&coarse.ranges).enumerate() {
        let (kept, drawn) = (a.iter().any(|r| !r.is_empty()), b.iter().any(|r| !r.is_empty()));
        assert_eq!(kept, drawn, "{}: culled {kept}, drawn coarser {drawn}", set.organs[o].id);
    }
    let (coarse_triangles, image) = shoot(&coarse);
    assert!(coarse_triangles * 2 < full_triangles, "{coarse_triangles} of {full_triangles} triangles");
    // Never more than culling kept, organ by organ.
    for (a, b) in culled.ranges.iter().zip(&coarse.ranges) {
        let count = |r: &Vec<std::ops::Range<u32>>| r.iter().map(|r| r.end - r.start).sum::<u32>();
        assert!(count(b) <= count(a));
    }
    let sum: f64 = full
        .pixels()
        .zip(image.pixels())
        .map(|(p, q)| (0..3).map(|k| (f64::from(p[k]) - f64::from(q[k])).powi(2)).sum::<f64>())
        .sum();
    let rmse = (sum / (3.0 * 256.0 * 256.0)).sqrt();
    assert!(rmse > 0.0 && rmse < 12.0, "RMSE {rmse:.2} of the coarser frame against the full one");
}
