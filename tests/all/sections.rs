//! Cross-sections on a real adapter: a closed sphere cut through its centre shows a solid disc of
//! its own colour (the cut face), picked as the sphere; with caps off, kept whole, or faded, it
//! shows what those should.

use crate::common::gpu;
use glam::Vec3;
use vbrain::camera::{Camera, View};
use vbrain::clip::{ClipPlane, Section};
use vbrain::layout::Layout;
use vbrain::mesh::Mesh;
use vbrain::organ_set::{Organ, OrganSet};
use vbrain::render::{linear_to_srgb, FrameInput, Renderer, Target};

#[test]
fn a_sphere_cut_through_its_centre_shows_a_solid_disc() {
    let gpu = gpu();
    let colour = [0.8, 0.3, 0.2];
    let set = OrganSet {
        organs: vec![Organ::new("ball".into(), "Ball".into(), colour, Mesh::uv_sphere(20.0, 24, 48))],
        ..Default::default()
    };
    assert!(set.organs[0].closed(), "the test sphere is closed");
    let renderer = Renderer::new(&gpu.device, &set).unwrap();
    let mut target = Target::new(&gpu.device, 128, 128).unwrap();
    let camera = Camera::view(&Layout::new(&set).bounds(&set), View::Superior);
    let axial = [ClipPlane::parse("axial=0").unwrap()];
    let mut shoot = |layout: &Layout, caps: bool, whole: &[usize]| {
        let section = Section { planes: axial.to_vec(), caps, whole: whole.to_vec(), ..Default::default() };
        let frame = FrameInput {
            background: [0.0, 0.0, 0.0, 1.0],
            section: &section,
            ..FrameInput::new(&set, &camera, layout)
        };
        renderer.render(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
        renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame, 0.25);
        (target.read_color(&gpu.device, &gpu.queue).unwrap(), target.read_ids(&gpu.device, &gpu.queue).unwrap())
    };
    // The cut face: flat, 0.82 of the organ's colour (in linear light), over the whole disc.
    let cap = colour.map(|c| (linear_to_srgb(vbrain::render::srgb_to_linear(c) * 0.82) * 255.0).round() as i32);
    let is_cap = |p: &image::Rgba<u8>| (0..3).all(|k| (p[k] as i32 - cap[k]).abs() <= 2);
    let layout = Layout::new(&set);
    let (image, ids) = shoot(&layout, true, &[]);
    let centre = image.get_pixel(64, 64);
    assert!(is_cap(centre), "the centre shows the cut face {cap:?}, not {centre:?}");
    let disc = image.pixels().filter(|p| is_cap(p)).count();
    let lit = image.pixels().filter(|p| p[0] > 8 || p[1] > 8 || p[2] > 8).count();
    assert!(disc as f64 > 0.95 * lit as f64, "{disc} of {lit} lit pixels are the cut face: a solid disc");
    assert_eq!(ids[64 * 128 + 64], 1, "clicking the cut face picks the sphere");

    // Without caps the cut sphere is a hollow shell: seen from above, the background shows.
    let (hollow, _) = shoot(&layout, false, &[]);
    assert_eq!(hollow.get_pixel(64, 64).0, [0, 0, 0, 255]);

    // An organ kept whole ("do not cut") shows its lit top, neither cut face nor background.
    let (whole, _) = shoot(&layout, true, &[0]);
    let top = whole.get_pixel(64, 64);
    assert!(!is_cap(top) && top[0] > 100, "kept whole, the sphere is not cut: {top:?}");

    // Faded, the cut face is faded too (screen-door): neither the solid face nor the background.
    let mut faded = layout.clone();
    faded.organs[0].opacity = 0.5;
    let (image, _) = shoot(&faded, true, &[]);
    let p = image.get_pixel(64, 64);
    assert!(!is_cap(p) && p[0] > 40, "a faded cut face lets the background through: {p:?}");
}

/// A sphere of radius 20 with an MRI on a 1 mm grid over it: dark, but bright in the block
/// x 5..12, y -12..-5 (every z). Cut axially, its cut face shows the volume where it is.
#[test]
fn the_mri_shows_on_the_cut_face_where_its_voxels_are_and_moves_with_its_organ() {
    use vbrain::clip::{CutFace, CutFaceShows};
    use vbrain::mri::{Mri, Window};
    let gpu = gpu();
    let mut set = OrganSet {
        organs: vec![Organ::new("ball".into(), "Ball".into(), [0.8, 0.3, 0.2], Mesh::uv_sphere(20.0, 24, 48))],
        ..Default::default()
    };
    let n = 41;
    let values: Vec<f32> = (0..n * n * n)
        .map(|i| {
            let (x, y) = ((i % n) as f32 - 20.0, ((i / n) % n) as f32 - 20.0);
            if (5.0..=12.0).contains(&x) && (-12.0..=-5.0).contains(&y) {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let to_world = glam::Mat4::from_translation(Vec3::splat(-20.0));
    set.mri = Some(std::sync::Arc::new(Mri::from_values([n, n, n], to_world, &values).unwrap()));
    let renderer = Renderer::new(&gpu.device, &set).unwrap();
    let size = 160;
    let mut target = Target::new(&gpu.device, size, size).unwrap();
    let camera = Camera::view(
        &Layout::new(&set).bounds(&set).union(vbrain::mesh::Bounds { min: [-40.0; 3], max: [40.0; 3] }),
        View::Superior,
    );
    let pixel = |p: Vec3| {
        let c = camera.view_projection(1.0).project_point3(p);
        (((c.x + 1.0) / 2.0 * size as f32) as u32, ((1.0 - c.y) / 2.0 * size as f32) as u32)
    };
    let mut shoot = |layout: &Layout, show: CutFaceShows| {
        let faces = CutFace { show, window: Window::new(1.0, 0.5).unwrap() };
        let section = Section { planes: vec![ClipPlane::parse("axial=0").unwrap()], caps: true, faces, whole: vec![] };
        let frame = FrameInput {
            background: [0.0, 0.0, 0.0, 1.0],
            section: &section,
            ..FrameInput::new(&set, &camera, layout)
        };
        renderer.render(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
        target.read_color(&gpu.device, &gpu.queue).unwrap()
    };
    let layout = Layout::new(&set);
    let image = shoot(&layout, CutFaceShows::Mri);
    let (bright, dark) = (Vec3::new(8.5, -8.5, 0.0), Vec3::new(-8.5, 8.5, 0.0));
    let at = |image: &image::RgbaImage, p: Vec3| {
        let (x, y) = pixel(p);
        image.get_pixel(x, y).0
    };
    let b = at(&image, bright);
    assert!(b[0] > 230 && b[0] == b[1] && b[1] == b[2], "the block is white on the cut face: {b:?}");
    let d = at(&image, dark);
    assert!(d[0] < 10 && d[0] == d[2], "elsewhere the cut face is black: {d:?}");
    // Tinted: the block in the organ's hue; organ colour: the flat cut face, no block.
    let t = at(&shoot(&layout, CutFaceShows::Tinted), bright);
    assert!(t[0] > t[1] && t[1] > 60, "tinted by the organ's red: {t:?}");
    let c = at(&shoot(&layout, CutFaceShows::Colour), bright);
    assert_eq!(c, at(&shoot(&layout, CutFaceShows::Colour), dark), "a flat colour without the MRI");
    // The MRI moves with its organ: moved 10 mm along -x, the block's pixel is dark and the
    // point 10 mm to its -x side is bright.
    let mut moved = layout.clone();
    moved.organs[0].transform.translation = Vec3::new(-10.0, 0.0, 0.0);
    let image = shoot(&moved, CutFaceShows::Mri);
    assert!(at(&image, bright)[0] < 10 && at(&image, bright + Vec3::new(-10.0, 0.0, 0.0))[0] > 230);
}
