//! Labels drawn into a rendered image (screen pixels, origin top left, y down), for `vbrain
//! render --labels` and exports: anchors and placement from [`vbrain::labels`], then for each a
//! dot on the organ, a leader line and the organ's name in light text on a dark plate (legible on
//! any background). Sizes follow the image's height, so a 4096-pixel export has the same figure
//! as a 1024-pixel one. Text uses egui's fonts (Ubuntu Light, then Hack for what it lacks); a
//! character neither has is drawn as a box, never a panic.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};
use image::RgbaImage;
use vbrain::labels::{anchors_near, place, Anchor, Placed, Which};

/// Which organs get labels.
#[derive(Clone, Debug, PartialEq)]
pub enum Labels {
    None,
    /// Every organ seen.
    All,
    /// These organs (indices), where seen.
    Chosen(Vec<usize>),
}

impl Labels {
    /// The organs `which` names in `set`, with `selected` the selection (names the set lacks are
    /// skipped).
    pub fn of(which: &Which, set: &vbrain::organ_set::OrganSet, selected: Option<usize>) -> Labels {
        match which {
            Which::None => Labels::None,
            Which::All => Labels::All,
            Which::Selected => Labels::Chosen(selected.into_iter().collect()),
            Which::Chosen(names) => Labels::Chosen(Which::chosen(names, set).0),
        }
    }

    /// Does it label organ `o`?
    pub fn wants(&self, o: usize) -> bool {
        match self {
            Labels::None => false,
            Labels::All => true,
            Labels::Chosen(list) => list.contains(&o),
        }
    }
}

/// A label laid out: its placement and where its leader line meets its plate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Laid {
    pub placed: Placed,
    pub end: [f32; 2],
}

/// Padding inside a label's plate, in text heights.
pub const PAD: f32 = 0.3;

/// Lays out the labels of `which` organs over an ID buffer `size` pixels (organ index + 1 per
/// pixel): text [`text_px`] of its height, each name `text_width(organ)` pixels wide; anchors of
/// the `previous` frame's labels are kept where they still fit (see [`anchors_near`]).
pub fn lay_out(
    ids: &[u32],
    size: [u32; 2],
    which: &Labels,
    previous: &[Laid],
    text_width: impl Fn(usize) -> f32,
) -> Vec<Laid> {
    let (w, h) = (size[0] as usize, size[1] as usize);
    let previous: Vec<Anchor> =
        previous.iter().map(|l| Anchor { organ: l.placed.organ, at: l.placed.anchor, pixels: 0 }).collect();
    let found: Vec<_> =
        anchors_near(ids, w, h, &previous).into_iter().filter(|a| which.wants(a.organ) && a.pixels >= 4).collect();
    let Some(sil) = vbrain::labels::silhouette(ids, w).filter(|_| !found.is_empty()) else { return Vec::new() };
    let px = text_px(size[1]);
    let sizes: Vec<[f32; 2]> = found.iter().map(|a| [text_width(a.organ) + 2.0 * PAD * px, px * 1.25]).collect();
    place(&found, &sizes, sil, [w as f32, h as f32], px * 0.35)
        .into_iter()
        .map(|p| {
            let left = p.rect[2] <= p.anchor[0];
            Laid { placed: p, end: [if left { p.rect[2] } else { p.rect[0] }, (p.rect[1] + p.rect[3]) / 2.0] }
        })
        .collect()
}

/// Labels name what is seen through organs fainter than this, as clicks reach through them.
pub const PICK_OPACITY: f32 = 0.5;

/// Text height in pixels for an image `height` pixels high.
pub fn text_px(height: u32) -> f32 {
    (height as f32 * 0.024).max(11.0)
}

fn fonts() -> Vec<FontRef<'static>> {
    [epaint_default_fonts::UBUNTU_LIGHT, epaint_default_fonts::HACK_REGULAR]
        .iter()
        .filter_map(|bytes| FontRef::try_from_slice(bytes).ok())
        .collect()
}

/// A run of glyphs: (font index, glyph id, x) per character, and the run's width.
fn shape(fonts: &[FontRef], text: &str, px: f32) -> (Vec<(usize, ab_glyph::GlyphId, f32)>, f32) {
    let mut x = 0.0;
    let mut out = Vec::new();
    for c in text.chars() {
        let found = fonts.iter().enumerate().find(|(_, f)| f.glyph_id(c).0 != 0);
        let (k, id) = found.map_or((0, ab_glyph::GlyphId(0)), |(k, f)| (k, f.glyph_id(c)));
        out.push((k, id, x));
        x += fonts.get(k).map_or(px * 0.5, |f| f.as_scaled(PxScale::from(px)).h_advance(id));
    }
    (out, x)
}

fn blend(image: &mut RgbaImage, x: i64, y: i64, colour: [u8; 3], alpha: f32) {
    if x < 0 || y < 0 || x >= image.width() as i64 || y >= image.height() as i64 || alpha <= 0.0 {
        return;
    }
    let p = image.get_pixel_mut(x as u32, y as u32);
    let a = alpha.min(1.0);
    for k in 0..3 {
        p[k] = (p[k] as f32 * (1.0 - a) + colour[k] as f32 * a).round() as u8;
    }
    p[3] = p[3].max((a * 255.0) as u8);
}

/// A disc of `radius` at `c`, anti-aliased.
fn disc(image: &mut RgbaImage, c: [f32; 2], radius: f32, colour: [u8; 3], alpha: f32) {
    let r = radius.ceil() as i64 + 1;
    for y in (c[1] as i64 - r)..=(c[1] as i64 + r) {
        for x in (c[0] as i64 - r)..=(c[0] as i64 + r) {
            let d = ((x as f32 + 0.5 - c[0]).powi(2) + (y as f32 + 0.5 - c[1]).powi(2)).sqrt();
            blend(image, x, y, colour, alpha * (radius + 0.5 - d).clamp(0.0, 1.0));
        }
    }
}

/// A line from `a` to `b`, `width` pixels wide.
fn line(image: &mut RgbaImage, a: [f32; 2], b: [f32; 2], width: f32, colour: [u8; 3], alpha: f32) {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len = (dx * dx + dy * dy).sqrt().max(1e-3);
    let (x0, x1) = (a[0].min(b[0]) - width, a[0].max(b[0]) + width);
    let (y0, y1) = (a[1].min(b[1]) - width, a[1].max(b[1]) + width);
    for y in y0.floor() as i64..=y1.ceil() as i64 {
        for x in x0.floor() as i64..=x1.ceil() as i64 {
            let (px, py) = (x as f32 + 0.5 - a[0], y as f32 + 0.5 - a[1]);
            let t = ((px * dx + py * dy) / (len * len)).clamp(0.0, 1.0);
            let d = ((px - t * dx).powi(2) + (py - t * dy).powi(2)).sqrt();
            blend(image, x, y, colour, alpha * (width / 2.0 + 0.5 - d).clamp(0.0, 1.0));
        }
    }
}

/// Draws labels of `which` organs, named by `name`, onto `image`, from the ID buffer `ids` of the
/// same size (organ index + 1 per pixel). Returns the labels placed.
pub fn draw(image: &mut RgbaImage, ids: &[u32], which: &Labels, name: impl Fn(usize) -> String) -> Vec<Placed> {
    let fonts = fonts();
    let px = text_px(image.height());
    let laid = lay_out(ids, [image.width(), image.height()], which, &[], |o| shape(&fonts, &name(o), px).1);
    let scale = px / 20.0;
    for Laid { placed: p, end } in &laid {
        let (p, end) = (*p, *end);
        line(image, p.anchor, end, 3.0 * scale, [0, 0, 0], 0.6);
        line(image, p.anchor, end, 1.4 * scale, [255, 255, 255], 0.95);
        disc(image, p.anchor, 3.2 * scale, [0, 0, 0], 0.7);
        disc(image, p.anchor, 2.2 * scale, [255, 255, 255], 1.0);
        for y in p.rect[1] as i64..p.rect[3].ceil() as i64 {
            for x in p.rect[0] as i64..p.rect[2].ceil() as i64 {
                blend(image, x, y, [20, 22, 28], 0.78);
            }
        }
        let pad = PAD * px;
        let (glyphs, _) = shape(&fonts, &name(p.organ), px);
        let baseline = p.rect[1] + px * 0.98;
        for (f, id, x) in glyphs {
            let origin = ab_glyph::point(p.rect[0] + pad + x, baseline);
            let glyph = id.with_scale_and_position(PxScale::from(px), origin);
            match fonts.get(f).and_then(|font| font.outline_glyph(glyph)) {
                Some(outline) => {
                    let b = outline.px_bounds();
                    outline.draw(|gx, gy, c| {
                        blend(image, b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64, [245, 245, 240], c)
                    });
                }
                None if id.0 == 0 => {
                    // No font has it: a box where it goes.
                    let (x0, y0) = (origin.x + px * 0.1, baseline - px * 0.7);
                    let rect = [[x0, y0], [x0 + px * 0.4, y0], [x0 + px * 0.4, baseline], [x0, baseline]];
                    for e in 0..4 {
                        line(image, rect[e], rect[(e + 1) % 4], scale, [245, 245, 240], 1.0);
                    }
                }
                None => {}
            }
        }
    }
    laid.into_iter().map(|l| l.placed).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgba;

    #[test]
    fn any_name_draws_and_stays_in_the_image() {
        let (w, h) = (200u32, 120u32);
        let mut ids = vec![0u32; (w * h) as usize];
        for y in 30..90 {
            for x in 70..130 {
                ids[(y * w + x) as usize] = if x < 100 { 1 } else { 2 };
            }
        }
        let mut image = RgbaImage::from_pixel(w, h, Rgba([255, 255, 255, 255]));
        let names = ["Gyrus précentralis", "中央前回 \u{10FFFF}"];
        let placed = draw(&mut image, &ids, &Labels::All, |o| names[o].to_string());
        assert_eq!(placed.len(), 2, "both organs labelled");
        let dark = image.pixels().filter(|p| p[0] < 100).count();
        assert!(dark > 200, "the plates are drawn on a light background too ({dark} dark pixels)");
    }
}
