//! The offscreen renderer on a real adapter (lavapipe in CI): the default brain renders, hiding and
//! fading organs changes the image, the ID buffer names the organ under a pixel, model transforms
//! move organs. With no adapter the test fails and says what to install.

use crate::common::{default_database, default_set, gpu};
use glam::Vec3;
use vbrain::camera::{Camera, View};
use vbrain::layout::Layout;
use vbrain::organ_set::OrganSet;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};
use vbrain::transparency::{TransparencyMode, TransparencySettings};

struct Shot {
    image: image::RgbaImage,
    ids: Vec<u32>,
}

fn shoot(
    gpu: &GpuContext,
    renderer: &Renderer,
    set: &OrganSet,
    layout: &Layout,
    view: View,
    background: [f32; 4],
) -> Shot {
    let mut target = Target::new(&gpu.device, 160, 128).unwrap();
    let camera = Camera::view(&Layout::new(set).bounds(set), view);
    let frame = FrameInput { background, ..FrameInput::new(set, &camera, layout) };
    renderer.render(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
    renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame, 0.25);
    Shot {
        image: target.read_color(&gpu.device, &gpu.queue).unwrap(),
        ids: target.read_ids(&gpu.device, &gpu.queue).unwrap(),
    }
}

fn count(ids: &[u32], organ: usize) -> usize {
    ids.iter().filter(|&&i| i == organ as u32 + 1).count()
}

#[test]
fn default_brain_hide_fade_pick_move() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let layout = Layout::new(set);
    let dark = [0.0, 0.0, 0.0, 1.0];
    let base = shoot(gpu, &renderer, set, &layout, View::Left, dark);
    let lit = base.image.pixels().filter(|p| p[0] > 10 || p[1] > 10 || p[2] > 10).count();
    let total = (base.image.width() * base.image.height()) as usize;
    assert!(lit > total / 5, "only {lit} of {total} pixels show the brain");
    // Colour and ID agree: a pixel is lit exactly where some organ's ID is.
    let covered = base.ids.iter().filter(|&&i| i != 0).count();
    assert!((covered as f64 - lit as f64).abs() < total as f64 * 0.02, "{covered} IDs vs {lit} lit pixels");

    // From the left, the left precentral gyrus is in view; hidden, it is gone and what lay beneath shows.
    let frontal = set.find("precentral_l").unwrap();
    assert!(count(&base.ids, frontal) > 300);
    let mut hidden = layout.clone();
    hidden.organs[frontal].visible = false;
    let shot = shoot(gpu, &renderer, set, &hidden, View::Left, dark);
    assert_eq!(count(&shot.ids, frontal), 0);
    assert_ne!(shot.image, base.image);
    let white = set.find("white_matter_l").unwrap();
    assert!(count(&shot.ids, white) > count(&base.ids, white) + 100);

    // Faded to 0.2 it is still drawn (blended) but no longer picked, and the colour changes.
    let mut faded = layout.clone();
    faded.organs[frontal].opacity = 0.2;
    let shot = shoot(gpu, &renderer, set, &faded, View::Left, dark);
    assert_eq!(count(&shot.ids, frontal), 0);
    let i = base.ids.iter().position(|&id| id == frontal as u32 + 1).unwrap();
    let (x, y) = ((i % 160) as u32, (i / 160) as u32);
    assert_ne!(shot.image.get_pixel(x, y), base.image.get_pixel(x, y));

    // Moved 60 mm up, the pons shows up higher in the image.
    let stem = set.find("pons").unwrap();
    let mean_row = |ids: &[u32]| {
        let rows: Vec<usize> =
            ids.iter().enumerate().filter(|(_, &id)| id == stem as u32 + 1).map(|(i, _)| i / 160).collect();
        rows.iter().sum::<usize>() as f64 / rows.len().max(1) as f64
    };
    let mut moved = layout.clone();
    moved.organs[stem].transform.translation = Vec3::new(0.0, 0.0, 60.0);
    let isolated: Vec<_> = (0..set.organs.len()).map(|i| i == stem).collect();
    for (s, &keep) in moved.organs.iter_mut().zip(&isolated) {
        s.visible = keep;
    }
    let mut still = moved.clone();
    still.organs[stem].transform.translation = Vec3::ZERO;
    let up = shoot(gpu, &renderer, set, &moved, View::Anterior, dark);
    let down = shoot(gpu, &renderer, set, &still, View::Anterior, dark);
    assert!(mean_row(&up.ids) + 10.0 < mean_row(&down.ids), "{} vs {}", mean_row(&up.ids), mean_row(&down.ids));
}

#[test]
fn gpu_time_is_measured_when_asked_where_the_adapter_has_timestamps() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let mut layout = Layout::new(set);
    let shown = layout.organs.iter().position(|s| s.is_drawn()).unwrap();
    layout.organs[shown].opacity = 0.5;
    let mut target = Target::new(&gpu.device, 64, 64).unwrap();
    let camera = Camera::view(&layout.bounds(set), View::Left);
    let timers = gpu.adapter.features().contains(vbrain::render::GPU_TIMER_FEATURES);
    // Screen-door submits once; depth peeling submits a pass at a time, all inside the span.
    for mode in [TransparencyMode::Screendoor, TransparencyMode::Peel] {
        let transparency = TransparencySettings { mode, ..Default::default() };
        let frame = FrameInput { transparency, ..FrameInput::new(set, &camera, &layout) };
        assert!(frame.has_transparent());
        let untimed = renderer.render(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
        assert_eq!(untimed.gpu_ms, None, "{mode:?}: not asked for");
        let timed = FrameInput { time_gpu: true, ..frame };
        let ms = renderer.render(&gpu.device, &gpu.queue, &mut target, &timed).unwrap().gpu_ms;
        match ms {
            Some(ms) => assert!(timers && ms.is_finite() && ms > 0.0, "{mode:?}: {ms} ms"),
            None => assert!(!timers, "{mode:?}: the adapter has timestamp queries but no time came back"),
        }
    }
}

#[test]
fn transparent_background_and_empty_scene() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let mut layout = Layout::new(set);
    let shot = shoot(gpu, &renderer, set, &layout, View::Superior, [0.0; 4]);
    assert_eq!(shot.image.get_pixel(0, 0)[3], 0, "corner should be transparent");
    assert_eq!(shot.image.get_pixel(80, 64)[3], 255, "centre should be opaque brain");
    layout.organs.iter_mut().for_each(|s| s.visible = false);
    let empty = shoot(gpu, &renderer, set, &layout, View::Superior, [0.0; 4]);
    assert!(empty.ids.iter().all(|&i| i == 0));
    assert!(empty.image.pixels().all(|p| p[3] == 0));
}

#[test]
fn culling_debug_view_colours_what_was_culled() {
    use vbrain::cull::{CullMode, CullSettings, Culler};
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let mut layout = Layout::new(set);
    layout.organs[set.find("skull").unwrap()].visible = true;
    let mut target = Target::new(&gpu.device, 160, 128).unwrap();
    let aspect = target.aspect();
    let camera = Camera::orbit(&layout.bounds(set), 30.0, 15.0);
    // Saturated pixels: culled triangles drawn in colour; the grey model has none.
    let mut coloured = |draw: &vbrain::cull::DrawList| {
        let frame =
            FrameInput { draw: Some(draw), background: [0.0, 0.0, 0.0, 1.0], ..FrameInput::new(set, &camera, &layout) };
        renderer.render_cull_debug(&gpu.device, &gpu.queue, &mut target, &frame).unwrap();
        let img = target.read_color(&gpu.device, &gpu.queue).unwrap();
        img.pixels().filter(|p| p[0].max(p[1]).max(p[2]) - p[0].min(p[1]).min(p[2]) > 40).count()
    };
    let mut culler = Culler::new(default_database());
    let none = CullSettings { mode: CullMode::None, ..Default::default() };
    let (nothing_culled, _) = culler.cull(set, &layout, &camera, aspect, &none);
    let (occluded, stats) = culler.cull(set, &layout, &camera, aspect, &CullSettings::default());
    assert!(stats.occlusion_culled > 0);
    assert_eq!(coloured(&nothing_culled), 0);
    assert!(coloured(&occluded) > 200, "culled triangles should show in colour");
}

/// Seamless cortex: from the sides, above, front and back, with everything shown, the white matter
/// shows nowhere between the gyri (at most 0.1 % of the brain's pixels; 0 when this was written).
/// Single-sampled ID pixels at 512x512, so a sliver one pixel wide counts. The interhemispheric
/// fissure (the middle 8 % of the image from above, the front and the back) is left out: there the
/// medial wall, which has no cortex (as in FreeSurfer's surfaces), and the corpus callosum show,
/// as in a real brain.
#[test]
fn no_white_matter_shows_between_the_gyri() {
    let gpu = gpu();
    let set = default_set();
    let renderer = Renderer::new(&gpu.device, set).unwrap();
    let layout = Layout::new(set);
    let target = Target::new(&gpu.device, 512, 512).unwrap();
    let white: Vec<u32> = ["white_matter_l", "white_matter_r"].map(|id| set.find(id).unwrap() as u32 + 1).to_vec();
    for view in [View::Left, View::Right, View::Superior, View::Anterior, View::Posterior] {
        let camera = Camera::view(&layout.bounds(set), view);
        let frame = FrameInput::new(set, &camera, &layout);
        renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame, 0.25);
        let ids = target.read_ids(&gpu.device, &gpu.queue).unwrap();
        let brain = ids.iter().filter(|&&i| i != 0).count();
        let midline = matches!(view, View::Superior | View::Anterior | View::Posterior);
        let in_fissure = |k: usize| midline && ((k % 512) as i32 - 256).abs() < 20;
        let wm = ids.iter().enumerate().filter(|(k, i)| white.contains(i) && !in_fissure(*k)).count();
        assert!(brain > 50_000, "{view:?}: {brain} brain pixels");
        assert!(wm * 1000 < brain, "{view:?}: white matter shows in {wm} of {brain} brain pixels");
    }
}

/// The outline pass: the pixels the selected organ does not cover, within two pixels of one it
/// does (as the ID buffer has them), turn sky blue; for a highlighted organ amber. Every other
/// pixel, inside the silhouette or away from it, is left as the frame drew it.
#[test]
fn outlines_ring_the_silhouette_in_their_colours() {
    use vbrain::organ_set::Organ;
    let gpu = gpu();
    let sphere = vbrain::mesh::Mesh::uv_sphere(20.0, 24, 48);
    let set = OrganSet { organs: vec![Organ::new("s".into(), "S".into(), [0.5; 3], sphere)], ..Default::default() };
    let renderer = Renderer::new(&gpu.device, &set).unwrap();
    let layout = Layout::new(&set);
    let camera = Camera::view(&layout.bounds(&set), View::Anterior);
    let mut target = Target::new(&gpu.device, 128, 96).unwrap();
    let base = FrameInput { background: [0.0, 0.0, 0.0, 1.0], ..FrameInput::new(&set, &camera, &layout) };
    let mut shoot = |f: &FrameInput| {
        renderer.render(&gpu.device, &gpu.queue, &mut target, f).unwrap();
        target.read_color(&gpu.device, &gpu.queue).unwrap()
    };
    let plain = shoot(&base);
    let selected = shoot(&FrameInput { selection: Some(0), ..base });
    let highlighted = shoot(&FrameInput { highlight: &[0], ..base });
    renderer.render_ids(&gpu.device, &gpu.queue, &target, &base, 0.0);
    let ids = target.read_ids(&gpu.device, &gpu.queue).unwrap();
    let (w, h) = (128i32, 96i32);
    let covered = |x: i32, y: i32| x >= 0 && y >= 0 && x < w && y < h && ids[(y * w + x) as usize] != 0;
    let ring = |x: i32, y: i32| {
        !covered(x, y)
            && (-2..=2).any(|dy: i32| (-2..=2).any(|dx: i32| dx * dx + dy * dy <= 5 && covered(x + dx, y + dy)))
    };
    assert!(covered(64, 48), "the sphere covers the centre");
    for (image, colour, what) in [(&selected, [80, 220, 255], "selection"), (&highlighted, [255, 190, 0], "highlight")]
    {
        let mut ringed = 0;
        for y in 0..h {
            for x in 0..w {
                let (got, before) = (image.get_pixel(x as u32, y as u32), plain.get_pixel(x as u32, y as u32));
                if ring(x, y) {
                    let off = (0..3).map(|k| got[k].abs_diff(colour[k])).max().unwrap_or(0);
                    assert!(off <= 2, "{what}: ring pixel ({x}, {y}) is {got:?}, not {colour:?}");
                    ringed += 1;
                } else {
                    assert_eq!(got, before, "{what}: pixel ({x}, {y}) off the ring changed");
                }
            }
        }
        assert!(ringed > 150, "{what}: a ring of {ringed} pixels around a sphere 40 mm across");
    }
}
