//! `vbrain bench-sections`: what sectional anatomy costs (issue: sectional anatomy).
//!
//! - Slice panes: one 512 x 512 pane ([`crate::slice_figure::draw`]: organ ownership, the MRI,
//!   outlines, side letters) redrawn at `frames` coronal positions across the organs shown, as a
//!   crosshair drag redraws it; median and slowest, milliseconds of CPU.
//! - Cut faces: the default layout cut coronally through its middle, seen from the front at
//!   `size`, drawn with coloured cut faces and with the MRI on them, alternately, `frames` times
//!   each after a warm-up (each read back, so the frame has finished); the medians and their ratio.

use crate::slice_figure::{self, Options};
use anyhow::Result;
use std::time::Instant;
use vbrain::camera::View;
use vbrain::clip::{ClipPlane, CutFace, CutFaceShows, Section};
use vbrain::layout::Layout;
use vbrain::mri::slice::{Axis, Pane, SlicePlane};
use vbrain::navigation::Navigator;
use vbrain::organ_set::OrganSet;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};

/// The pane side the target is stated for.
pub const PANE: u32 = 512;

#[derive(Debug, serde::Serialize)]
pub struct Report {
    pub pane_px: u32,
    pub slice_ms_median: f64,
    pub slice_ms_max: f64,
    pub size: [u32; 2],
    pub colour_faces_ms: f64,
    pub mri_faces_ms: f64,
    /// MRI faces over coloured faces.
    pub mri_over_colour: f64,
    pub adapter: String,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// Runs both measurements over `set` (which should have an MRI) with `frames` of each.
pub fn run(set: &OrganSet, frames: usize, size: [u32; 2]) -> Result<Report> {
    let layout = Layout::new(set);
    let bounds = slice_figure::shown_bounds(set, &layout);
    let options = Options {
        outlines: true,
        labels: crate::annotate::Labels::None,
        window: Default::default(),
        letters: true,
        highlight: None,
    };
    let mut slice_ms = Vec::with_capacity(frames);
    for k in 0..frames {
        let t = (k as f32 + 0.5) / frames as f32;
        let at = bounds.min[1] + t * (bounds.max[1] - bounds.min[1]);
        let pane = Pane::fit(SlicePlane { axis: Axis::Coronal, at }, &bounds, PANE, PANE, true);
        let started = Instant::now();
        let (image, _) = slice_figure::draw(set, &layout, &pane, &options);
        slice_ms.push(started.elapsed().as_secs_f64() * 1000.0);
        std::hint::black_box(image);
    }
    let slice_ms_max = slice_ms.iter().copied().fold(0.0, f64::max);

    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, set)?;
    let mut target = Target::new(&gpu.device, size[0], size[1])?;
    let home = layout.bounds(set);
    let (azimuth, elevation) = View::Anterior.angles();
    let camera = Navigator::framing(&home, azimuth, elevation).camera(&home);
    let plane = ClipPlane::new(glam::Vec3::Y, home.center().y).ok_or_else(|| anyhow::anyhow!("no plane"))?;
    let section =
        |show| Section { planes: vec![plane], faces: CutFace { show, ..Default::default() }, ..Default::default() };
    let (colour, mri) = (section(CutFaceShows::Colour), section(CutFaceShows::Mri));
    let mut shoot = |section: &Section| -> Result<f64> {
        let frame = FrameInput { section, ..FrameInput::new(set, &camera, &layout) };
        let started = Instant::now();
        renderer.render(&gpu.device, &gpu.queue, &mut target, &frame)?;
        target.read_color(&gpu.device, &gpu.queue)?;
        Ok(started.elapsed().as_secs_f64() * 1000.0)
    };
    shoot(&colour)?;
    shoot(&mri)?;
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for _ in 0..frames {
        a.push(shoot(&colour)?);
        b.push(shoot(&mri)?);
    }
    let (colour_faces_ms, mri_faces_ms) = (median(a), median(b));
    Ok(Report {
        pane_px: PANE,
        slice_ms_median: median(slice_ms),
        slice_ms_max,
        size,
        colour_faces_ms,
        mri_faces_ms,
        mri_over_colour: mri_faces_ms / colour_faces_ms.max(1e-9),
        adapter: gpu.adapter_description(),
    })
}
