//! Screen-door transparency on rendered images (lavapipe in CI): the image does not depend on the
//! order organs are drawn in, and a transparent organ shows only its outermost layer.

use crate::common::{cube, default_set, gpu};
use glam::Vec3;
use vbrain::camera::Camera;
use vbrain::layout::Layout;
use vbrain::organ_set::{Organ, OrganSet};
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};
use vbrain::rng::XorShift;
use vbrain::transparency::{TransparencyMode, TransparencySettings};

fn render(
    gpu: &GpuContext,
    renderer: &Renderer,
    set: &OrganSet,
    layout: &Layout,
    camera: &Camera,
    mode: TransparencyMode,
    order: Option<&[usize]>,
) -> image::RgbaImage {
    let target = Target::new(&gpu.device, 160, 128).unwrap();
    let transparency = TransparencySettings { mode, subsamples: 16, ..Default::default() };
    let frame = FrameInput {
        background: [0.0, 0.0, 0.0, 1.0],
        transparency,
        draw_order: order,
        ..FrameInput::new(set, camera, layout)
    };
    renderer.render(&gpu.device, &gpu.queue, &target, &frame).unwrap();
    target.read_color(&gpu.device, &gpu.queue).unwrap()
}

#[test]
fn screendoor_does_not_depend_on_draw_order() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let mut layout = Layout::new(set);
    for (i, s) in layout.organs.iter_mut().enumerate() {
        s.opacity = [0.3, 0.5, 0.7, 1.0, 0.45][i % 5];
    }
    let camera = Camera::orbit(&layout.bounds(set), 35.0, 10.0);
    let n = set.organs.len();
    let base = render(gpu, &renderer, set, &layout, &camera, TransparencyMode::Screendoor, None);
    assert!(base.pixels().filter(|p| p[0] > 20).count() > 1000, "the brain is not in the picture");
    for seed in 1..4 {
        let order = XorShift::permutation(n, seed);
        let img = render(gpu, &renderer, set, &layout, &camera, TransparencyMode::Screendoor, Some(&order));
        let diff = base.pixels().zip(img.pixels()).filter(|(a, b)| a != b).count();
        if diff > 0 {
            base.save(std::env::temp_dir().join("screendoor-order-base.png")).unwrap();
            img.save(std::env::temp_dir().join(format!("screendoor-order-{seed}.png"))).unwrap();
        }
        assert_eq!(diff, 0, "draw order seed {seed} changed {diff} pixels (images in the temp folder)");
    }
    // The check can fail: blending without sorting does depend on the order.
    let unsorted: Vec<_> = (1..4)
        .map(|seed| {
            let order = XorShift::permutation(n, seed);
            render(gpu, &renderer, set, &layout, &camera, TransparencyMode::AlphaUnsorted, Some(&order))
        })
        .collect();
    assert!(unsorted.windows(2).any(|w| w[0] != w[1]), "alpha-unsorted gave the same image in every order");
}

/// One transparent organ and an opaque block beside it; `interior` adds a second, inner shell to the
/// transparent organ (thesis Figure 24).
fn scene(interior: bool) -> OrganSet {
    let mut shell = cube(Vec3::ZERO, Vec3::splat(30.0), 0);
    if interior {
        shell.append(&cube(Vec3::ZERO, Vec3::splat(15.0), 0));
    }
    let mut back = cube(Vec3::ZERO, Vec3::splat(20.0), 0);
    for p in &mut back.positions {
        p[1] += 60.0;
    }
    back.compute_normals();
    OrganSet {
        title: "shells".into(),
        organs: vec![
            Organ::new("shell".into(), "shell".into(), [0.9, 0.6, 0.3], shell),
            Organ::new("back".into(), "back".into(), [0.3, 0.5, 0.9], back),
        ],
        ..Default::default()
    }
}

#[test]
fn screendoor_shows_only_the_outermost_layer() {
    let gpu = gpu();
    let image = |interior: bool, mode| {
        let set = scene(interior);
        let renderer = Renderer::new(&gpu.device, &set).unwrap();
        let mut layout = Layout::new(&set);
        layout.organs[0].opacity = 0.5;
        let camera = Camera::orbit(&scene(false).bounds(), 20.0, 15.0);
        render(gpu, &renderer, &set, &layout, &camera, mode, None)
    };
    let differing = |mode| {
        let (a, b) = (image(false, mode), image(true, mode));
        a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count()
    };
    assert_eq!(differing(TransparencyMode::Screendoor), 0, "the inner shell shows through the outer one");
    // Blending shows the inner shell: the comparison can fail.
    assert!(differing(TransparencyMode::AlphaSorted) > 200);
}
