//! Transparency on rendered images (lavapipe in CI): screen-door's image does not depend on the
//! order organs are drawn in, and a transparent organ shows only its outermost layer; peeling and
//! the k-buffer match the exact reference where they have layers or slots enough, and the k-buffer
//! does not depend on the drawing order where its k slots hold every fragment.

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
    let mut target = Target::new(&gpu.device, 160, 128).unwrap();
    let transparency = TransparencySettings { mode, subsamples: 16, ..Default::default() };
    let frame = FrameInput {
        background: [0.0, 0.0, 0.0, 1.0],
        transparency,
        draw_order: order,
        ..FrameInput::new(set, camera, layout)
    };
    renderer.render(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
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

/// Cubes of these half sides, one inside the other, and an opaque block beyond them (seen from
/// behind), last.
fn nested_shells(halves: &[f32]) -> OrganSet {
    let mut organs = Vec::new();
    for (i, &half) in halves.iter().enumerate() {
        let id = format!("shell{i}");
        organs.push(Organ::new(
            id.clone(),
            id,
            [0.9, 0.6 - 0.15 * i as f32, 0.3],
            cube(Vec3::ZERO, Vec3::splat(half), 0),
        ));
    }
    let mut back = cube(Vec3::ZERO, Vec3::splat(20.0), 0);
    for p in &mut back.positions {
        p[1] += 60.0;
    }
    back.compute_normals();
    organs.push(Organ::new("back".into(), "back".into(), [0.3, 0.5, 0.9], back));
    OrganSet { title: "nested shells".into(), organs, ..Default::default() }
}

/// Nested transparent shells (three cubes, one inside the other, all faded) in front of an opaque
/// block: the peeling modes must match the exact reference, and stop early once every layer is in.
#[test]
fn peeling_matches_exact_on_nested_shells() {
    let gpu = gpu();
    let set = nested_shells(&[30.0, 20.0, 10.0]);
    let renderer = Renderer::new(&gpu.device, &set).unwrap();
    let mut layout = Layout::new(&set);
    for (s, a) in layout.organs.iter_mut().zip([0.4, 0.5, 0.6]) {
        s.opacity = a;
    }
    // From behind: the block lies beyond the shells.
    let camera = Camera::orbit(&set.bounds(), 200.0, 15.0);
    let mut target = Target::new(&gpu.device, 160, 128).unwrap();
    let mut shot = |mode, peel_layers| {
        let transparency = TransparencySettings { mode, peel_layers, ..Default::default() };
        let frame =
            FrameInput { background: [0.0, 0.0, 0.0, 1.0], transparency, ..FrameInput::new(&set, &camera, &layout) };
        let stats = renderer.render(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
        (target.read_color(&gpu.device, &gpu.queue).unwrap(), stats.passes)
    };
    let mean_error = |a: &image::RgbaImage, b: &image::RgbaImage| {
        let sum: u64 = a
            .pixels()
            .zip(b.pixels())
            .map(|(x, y)| (0..3).map(|k| x[k].abs_diff(y[k])).max().unwrap_or(0) as u64)
            .sum();
        sum as f64 / (a.width() * a.height()) as f64
    };
    let (exact, _) = shot(TransparencyMode::Exact, 8);
    assert!(exact.pixels().filter(|p| p[0] > 40).count() > 2000, "the shells are not in the picture");
    // Three layers: the cubes are closed, so their back faces are culled.
    for mode in [TransparencyMode::Peel, TransparencyMode::DualPeel] {
        let (image, passes) = shot(mode, 16);
        let e = mean_error(&image, &exact);
        assert!(e < 0.6, "{}: mean error {e:.3} against exact", mode.name());
        // The occlusion query stops it long before the cap of 16: the opaque pass and 4 layers, or
        // the opaque pass, 2 dual passes and the final one.
        assert!(passes <= 5, "{}: {passes} passes for six layers", mode.name());
        // With two layers the innermost shell is missing: the comparison can fail.
        let off = |a: &image::RgbaImage| {
            a.pixels().zip(exact.pixels()).filter(|(x, y)| (0..3).any(|k| x[k].abs_diff(y[k]) > 8)).count()
        };
        let (all, few) = (off(&image), off(&shot(mode, 2).0));
        assert!(few > 200 && few > 10 * all, "{}: {few} pixels off with two layers, {all} with all", mode.name());
    }
}

/// Progressive refinement: the first still frame draws the interactive passes, each further call
/// for the same frame one more, until the image holds every sub-sample and matches the image
/// drawn at once (to rounding); a change starts it again. Another view drawn between the calls,
/// into its own target, leaves the refinement where it was (each target keeps its own).
#[test]
fn refinement_converges_to_the_full_image() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let mut layout = Layout::new(set);
    for (i, s) in layout.organs.iter_mut().enumerate() {
        s.opacity = [0.3, 0.5, 1.0][i % 3];
    }
    let camera = Camera::orbit(&layout.bounds(set), 35.0, 10.0);
    let mut other = Target::new(&gpu.device, 160, 128).unwrap();
    let frame = FrameInput { background: [0.0, 0.0, 0.0, 1.0], ..FrameInput::new(set, &camera, &layout) };
    renderer.render(&gpu.device, &gpu.queue, &mut other, &frame).unwrap();
    let full = other.read_color(&gpu.device, &gpu.queue).unwrap();
    // A target that does not show this frame yet.
    let mut target = Target::new(&gpu.device, 160, 128).unwrap();
    let refined = FrameInput { refine: true, ..frame };
    let mut side = camera;
    side.eye += Vec3::new(0.0, 30.0, 0.0);
    let mut done = Vec::new();
    for _ in 0..16 {
        let stats = renderer.render(&gpu.device, &gpu.queue, &mut target, &refined).unwrap();
        assert_eq!(stats.subsamples_total, 64);
        done.push(stats.subsamples_done);
        // Another view, refined too, into another target.
        renderer.render(&gpu.device, &gpu.queue, &mut other, &FrameInput { camera: &side, ..refined }).unwrap();
    }
    assert_eq!(done[..3], [16, 20, 24], "interactive passes first, then one a call");
    assert_eq!(done[15], 64, "converged after 13 calls: {done:?}");
    let image = target.read_color(&gpu.device, &gpu.queue).unwrap();
    let worst =
        full.pixels().zip(image.pixels()).map(|(a, b)| (0..4).map(|k| a[k].abs_diff(b[k])).max().unwrap_or(0)).max();
    assert!(worst <= Some(1), "refined image differs from the full one by {worst:?}");
    let mut moved = camera;
    moved.eye += Vec3::new(1.0, 0.0, 0.0);
    let stats =
        renderer.render(&gpu.device, &gpu.queue, &mut target, &FrameInput { camera: &moved, ..refined }).unwrap();
    assert_eq!(stats.subsamples_done, 16, "a new view starts again");
}

/// The k-buffer on four nested shells: with slots for every layer it matches the exact reference;
/// drawn unsorted (a draw order given) with too few slots, the overflow's order shows.
#[test]
fn kbuffer_matches_exact_on_nested_shells() {
    let gpu = gpu();
    let mut set = nested_shells(&[30.0, 26.0, 22.0, 18.0]);
    // Far apart in colour, so that the order of the inner two shows.
    for (o, c) in set.organs.iter_mut().zip([[0.9, 0.9, 0.9], [0.9, 0.6, 0.3], [0.1, 0.9, 0.1], [0.9, 0.1, 0.9]]) {
        o.colour = c;
    }
    let renderer = Renderer::new(&gpu.device, &set).unwrap();
    let mut layout = Layout::new(&set);
    for (s, a) in layout.organs.iter_mut().zip([0.4, 0.5, 0.6, 0.7]) {
        s.opacity = a;
    }
    let camera = Camera::orbit(&set.bounds(), 200.0, 15.0);
    let mut target = Target::new(&gpu.device, 160, 128).unwrap();
    // Outermost (nearest) shell first.
    let front_to_back = [0, 1, 2, 3, 4];
    let shot = |target: &mut Target, mode, kbuffer, order: Option<&[usize]>| {
        let transparency = TransparencySettings { mode, kbuffer, ..Default::default() };
        let frame = FrameInput {
            background: [0.0, 0.0, 0.0, 1.0],
            transparency,
            draw_order: order,
            ..FrameInput::new(&set, &camera, &layout)
        };
        renderer.render(&gpu.device, &gpu.queue, target, &frame).unwrap();
        target.read_color(&gpu.device, &gpu.queue).unwrap()
    };
    let exact = shot(&mut target, TransparencyMode::Exact, 8, None);
    let off = |a: &image::RgbaImage| {
        a.pixels().zip(exact.pixels()).filter(|(x, y)| (0..3).any(|k| x[k].abs_diff(y[k]) > 8)).count()
    };
    let kbuffer = shot(&mut target, TransparencyMode::KBuffer, 4, None);
    let counts = renderer.fragment_counts(&gpu.device, &gpu.queue, &target).unwrap().unwrap();
    assert_eq!(counts.iter().max(), Some(&4), "four shells: at most four faded fragments a pixel");
    // Off only at the shells' edges: the k-buffer samples a pixel once, the reference 16 times.
    let edges = off(&kbuffer);
    let mean_error = |a: &image::RgbaImage| {
        let sum: u64 = a
            .pixels()
            .zip(exact.pixels())
            .map(|(x, y)| (0..3).map(|k| x[k].abs_diff(y[k])).max().unwrap_or(0) as u64)
            .sum();
        sum as f64 / (a.width() * a.height()) as f64
    };
    assert!(mean_error(&kbuffer) < 1.0, "mean error {:.3} with a slot for every layer", mean_error(&kbuffer));
    // Sorted back to front, two slots suffice too: the overflow is blended in order.
    assert!(off(&shot(&mut target, TransparencyMode::KBuffer, 2, None)) <= edges + edges / 10);
    // Drawn front to back with two slots, the two farther shells overflow and are blended in the
    // wrong order (the innermost over the third): wrong where all four overlap. The comparison
    // can fail.
    let wrong = off(&shot(&mut target, TransparencyMode::KBuffer, 2, Some(&front_to_back)));
    assert!(wrong > 1000 && wrong > 3 * edges, "{wrong} pixels off front to back with two slots, {edges} sorted");
    // With four slots the order does not matter.
    assert!(off(&shot(&mut target, TransparencyMode::KBuffer, 4, Some(&front_to_back))) <= edges);
}

/// The k-buffer on the brain, every organ faded, drawn unsorted in shuffled organ orders: every
/// pixel whose faded fragments fit in its k slots is the same in every order.
#[test]
fn kbuffer_does_not_depend_on_draw_order_where_k_suffices() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let mut layout = Layout::new(set);
    for (i, s) in layout.organs.iter_mut().enumerate() {
        s.opacity = [0.3, 0.5, 0.7, 0.45][i % 4];
    }
    let camera = Camera::orbit(&layout.bounds(set), 35.0, 10.0);
    let k = 4;
    let mut target = Target::new(&gpu.device, 160, 128).unwrap();
    let mut shot = |order: &[usize]| {
        let transparency = TransparencySettings { mode: TransparencyMode::KBuffer, kbuffer: k, ..Default::default() };
        let frame = FrameInput {
            background: [0.0, 0.0, 0.0, 1.0],
            transparency,
            draw_order: Some(order),
            ..FrameInput::new(set, &camera, &layout)
        };
        renderer.render(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
        let counts = renderer.fragment_counts(&gpu.device, &gpu.queue, &target).unwrap().unwrap();
        (target.read_color(&gpu.device, &gpu.queue).unwrap(), counts)
    };
    let n = set.organs.len();
    let (base, counts) = shot(&XorShift::permutation(n, 1));
    let fits = counts.iter().filter(|&&c| c > 0 && c <= k as u32).count();
    let over = counts.iter().filter(|&&c| c > k as u32).count();
    assert!(fits > 300 && over > 100, "{fits} pixels within k, {over} beyond: not a test of both");
    let mut differ_beyond = 0;
    for seed in 2..5 {
        let (image, again) = shot(&XorShift::permutation(n, seed));
        assert_eq!(again, counts, "the fragment counts depend on the order");
        for ((a, b), &c) in base.pixels().zip(image.pixels()).zip(&counts) {
            if c <= k as u32 {
                assert_eq!(a, b, "draw order seed {seed} changed a pixel with {c} fragments");
            } else {
                differ_beyond += usize::from(a != b);
            }
        }
    }
    // Beyond k the order shows: the comparison can fail.
    assert!(differ_beyond > 0, "no pixel beyond k changed with the order");
}
