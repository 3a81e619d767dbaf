//! Stills of a set drawn as the viewer draws them, for the commands that make figures one after
//! another (lesson pictures, handouts, videos): one GPU context, renderer and culler for all, and
//! per picture a view (camera, layout, highlights, section, labels) rendered and labelled.
//!
//! - Images are sRGB RGBA, origin top left, y down; labels are drawn into them at `px` pixels high.
//! - A step's caption band below its figure takes at most [`CAPTION_SHARE`] of the picture.
//! - A lesson step seen from its angles (no camera of its own) frames the brain whole and centred
//!   ([`Studio::step_navigator`]), so every command shows a step alike.

use crate::annotate::Labels;
use anyhow::Result;
use image::RgbaImage;
use vbrain::clip::Section;
use vbrain::cull::database::Database;
use vbrain::cull::{CullSettings, Culler};
use vbrain::layout::Layout;
use vbrain::lesson::{Step, StepView};
use vbrain::mesh::Bounds;
use vbrain::navigation::Navigator;
use vbrain::organ_set::OrganSet;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};

/// The share of the half-width and half-height a step's brain fills ([`Navigator::fitting`]).
pub const FILL: [f32; 2] = [0.85, 0.85];
/// The same where labels are drawn: room for their columns beside the brain.
pub const FILL_LABELLED: [f32; 2] = [0.62, 0.85];

/// What one picture shows.
pub struct Shot<'a> {
    pub navigator: Navigator,
    pub layout: &'a Layout,
    pub highlight: &'a [usize],
    pub section: &'a Section,
    pub labels: &'a Labels,
    /// Label text height in pixels.
    pub px: f32,
}

/// A set's renderer, ready for many pictures.
pub struct Studio<'s> {
    pub set: &'s OrganSet,
    gpu: GpuContext,
    renderer: Renderer,
    culler: Culler,
    /// The set's default layout's bounds: cameras frame these and what is drawn.
    home: Bounds,
    /// The target of the last picture's size, kept for the next picture of that size.
    target: Option<Target>,
}

impl<'s> Studio<'s> {
    /// A studio for `set`, culling with its pre-computed occluders `database` where given.
    pub fn new(set: &'s OrganSet, database: Option<Database>) -> Result<Studio<'s>> {
        let gpu = GpuContext::headless()?;
        let renderer = Renderer::new(&gpu.device, set)?;
        let culler = Culler::new(database);
        Ok(Studio { set, gpu, renderer, culler, home: Layout::new(set).bounds(set), target: None })
    }

    /// The camera of lesson step `step` (its view `view`) in a picture of aspect `aspect`.
    pub fn step_navigator(&self, step: &Step, view: &StepView, aspect: f32, labelled: bool) -> Navigator {
        match step.camera {
            Some(_) => view.navigator,
            None => {
                let fill = if labelled { FILL_LABELLED } else { FILL };
                let [az, el] = step.view;
                let fitted = Navigator::fitting(&self.home, az, el, aspect, fill);
                Navigator { distance: fitted.distance * step.zoom, ..fitted }
            }
        }
    }

    /// `shot` rendered `size` pixels large and labelled: the image and the labels placed.
    pub fn shoot(&mut self, size: [u32; 2], shot: &Shot) -> Result<(RgbaImage, usize)> {
        let (gpu, renderer, set) = (&self.gpu, &self.renderer, self.set);
        // The last picture's target if it has this size (it keeps what the renderer keeps).
        let target = match self.target.take() {
            Some(t) if [t.width, t.height] == size => t,
            _ => Target::new(&gpu.device, size[0], size[1])?,
        };
        let target = self.target.insert(target);
        let camera = shot.navigator.camera(&shot.layout.bounds(set).union(self.home));
        let frame = FrameInput {
            background: crate::background_linear(crate::background_srgb(), false),
            highlight: shot.highlight,
            section: shot.section,
            ..FrameInput::new(set, &camera, shot.layout)
        };
        let (draw, _) = self.culler.cull_frame(&renderer.cull_input(&frame, target), &CullSettings::default());
        let frame = FrameInput { draw: Some(&draw), ..frame };
        renderer.render(&gpu.device, &gpu.queue, target, &frame)?;
        let mut image = target.read_color(&gpu.device, &gpu.queue)?;
        crate::annotate::legend(&mut image, &vbrain::colouring::legend(set, shot.layout), shot.px * 0.8);
        let mut placed = 0;
        if *shot.labels != Labels::None {
            renderer.render_ids(&gpu.device, &gpu.queue, target, &frame, crate::annotate::PICK_OPACITY);
            let ids = target.read_ids(&gpu.device, &gpu.queue)?;
            let name = |o: usize| set.organs[o].name.clone();
            placed = crate::annotate::draw_sized(&mut image, &ids, shot.labels, name, shot.px).len();
        }
        Ok((image, placed))
    }
}

/// The most of a picture's height its caption band takes; longer captions end in "…".
const CAPTION_SHARE: f32 = 0.45;

/// A step's title and caption as the lines of its band in a picture `width` x `height` pixels,
/// cut to [`CAPTION_SHARE`] of its height (the last line kept ending in "…").
pub fn caption_lines(step: &Step, width: u32, height: u32) -> Vec<(String, bool)> {
    let px = crate::annotate::text_px(height);
    let mut lines = crate::annotate::caption_lines(&step.title, &step.caption, width as f32 - 2.0 * px, px);
    let most = height as f32 * CAPTION_SHARE;
    let mut cut = false;
    while lines.len() > 1 && crate::annotate::caption_height(&lines, px) as f32 > most {
        lines.pop();
        cut = true;
    }
    if let (true, Some((last, _))) = (cut, lines.last_mut()) {
        last.push('\u{2026}');
    }
    lines
}

/// The labels step view `view` asks for, or `forced` instead; a step's "selected" organs are the
/// ones it highlights.
pub fn step_labels(set: &OrganSet, view: &StepView, forced: Option<&vbrain::labels::Which>) -> Labels {
    use vbrain::labels::Which;
    match forced.or(view.labels.as_ref()) {
        Some(Which::Selected) => Labels::Chosen(view.highlight.clone()),
        Some(which) => Labels::of(which, set, None),
        None => Labels::None,
    }
}

/// A lesson step ready to draw, still or on the way from another view: its view, labels, camera
/// and target, and its caption band (title and caption lines) below the figure.
pub struct StepFrame {
    pub view: StepView,
    pub labels: Labels,
    pub navigator: Navigator,
    /// The figure's size in pixels (the picture less the caption band).
    size: [u32; 2],
    lines: Option<Vec<(String, bool)>>,
    px: f32,
}

impl StepFrame {
    /// Step `step` in a picture `size` pixels (its caption band, given `lines`, inside that
    /// size), its labels `forced` or its own.
    pub fn new(
        studio: &mut Studio,
        step: &Step,
        forced: Option<&vbrain::labels::Which>,
        size: [u32; 2],
        lines: Option<Vec<(String, bool)>>,
    ) -> Result<StepFrame> {
        let [width, height] = size;
        let view = step.view(studio.set);
        let labels = step_labels(studio.set, &view, forced);
        let px = crate::annotate::text_px(height);
        let band = lines.as_ref().map_or(0, |l| crate::annotate::caption_height(l, px));
        let size = [width, height.saturating_sub(band).max(1)];
        let aspect = size[0] as f32 / size[1] as f32;
        let navigator = studio.step_navigator(step, &view, aspect, labels != Labels::None);
        Ok(StepFrame { view, labels, navigator, size, lines, px })
    }

    /// The step drawn with its labels and caption; with `between` = (camera, layout) some way
    /// from another view, that view is drawn instead, without labels (they would jump as it moves).
    pub fn draw(&self, studio: &mut Studio, between: Option<(Navigator, &Layout)>) -> Result<(RgbaImage, usize)> {
        let none = Labels::None;
        let (navigator, layout, labels) = match between {
            Some((n, l)) => (n, l, &none),
            None => (self.navigator, &self.view.layout, &self.labels),
        };
        let shot = Shot {
            navigator,
            layout,
            highlight: &self.view.highlight,
            section: &self.view.section,
            labels,
            px: self.px,
        };
        let (mut image, placed) = studio.shoot(self.size, &shot)?;
        if let Some(lines) = &self.lines {
            image = crate::annotate::caption(&image, lines, self.px);
        }
        Ok((image, placed))
    }
}
