//! Labels drawn into a rendered image, for `vbrain render --labels` and exports: anchors and
//! placement from [`vbrain::labels`], then for each a dot on the organ, a leader line and the
//! organ's name in light text on a dark plate (legible on any background); and the legend of a
//! lobe or territory colouring.
//!
//! - Coordinates are screen pixels, origin top left, y down.
//! - Sizes follow the image's height, so a 4096-pixel export has the same figure as a 1024-pixel
//!   one.
//! - Text uses egui's fonts (Ubuntu Light, then Hack for what it lacks); a character neither has
//!   is drawn as a box, never a panic.

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

/// With every organ seen labelled, the most of the organs' pixels that label plates may cover in
/// all: labels go to the organs largest on screen (the largest always) until their plates would
/// pass this share. Organs chosen one by one are all labelled.
pub const LABEL_SHARE: f32 = 0.25;

/// Lays out the labels of `which` organs over an ID buffer `size` pixels (organ index + 1 per
/// pixel): text `px` pixels high ([`text_px`] of the height for a figure), each name
/// `text_width(organ)` pixels wide; anchors of the `previous` frame's labels are kept where they
/// still fit (see [`anchors_near`]). With [`Labels::All`], the organs largest on screen are
/// labelled first, until the plates would cover [`LABEL_SHARE`] of the organs' pixels, so a small
/// view gets fewer labels.
pub fn lay_out(
    ids: &[u32],
    size: [u32; 2],
    which: &Labels,
    previous: &[Laid],
    px: f32,
    text_width: impl Fn(usize) -> f32,
) -> Vec<Laid> {
    let (w, h) = (size[0] as usize, size[1] as usize);
    let previous: Vec<Anchor> =
        previous.iter().map(|l| Anchor { organ: l.placed.organ, at: l.placed.anchor, pixels: 0 }).collect();
    let mut found: Vec<_> =
        anchors_near(ids, w, h, &previous).into_iter().filter(|a| which.wants(a.organ) && a.pixels >= 4).collect();
    let Some(sil) = vbrain::labels::silhouette(ids, w).filter(|_| !found.is_empty()) else { return Vec::new() };
    let size_of = |organ: usize| [text_width(organ) + 2.0 * PAD * px, px * 1.25];
    if *which == Labels::All {
        let mut budget = ids.iter().filter(|&&id| id > 0).count() as f32 * LABEL_SHARE;
        found.sort_by_key(|a| std::cmp::Reverse(a.pixels));
        let mut first = true;
        found.retain(|a| {
            let [width, height] = size_of(a.organ);
            let keep = first || width * height <= budget;
            if keep {
                budget -= width * height;
            }
            first = false;
            keep
        });
    }
    let sizes: Vec<[f32; 2]> = found.iter().map(|a| size_of(a.organ)).collect();
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

/// Draws `s` with its baseline starting at `at`, `px` high, in `colour`; a character no font has
/// is a box.
fn text(image: &mut RgbaImage, fonts: &[FontRef], s: &str, at: [f32; 2], px: f32, colour: [u8; 3]) {
    let (glyphs, _) = shape(fonts, s, px);
    for (f, id, x) in glyphs {
        let origin = ab_glyph::point(at[0] + x, at[1]);
        let glyph = id.with_scale_and_position(PxScale::from(px), origin);
        match fonts.get(f).and_then(|font| font.outline_glyph(glyph)) {
            Some(outline) => {
                let b = outline.px_bounds();
                outline
                    .draw(|gx, gy, c| blend(image, b.min.x as i64 + gx as i64, b.min.y as i64 + gy as i64, colour, c));
            }
            None if id.0 == 0 => {
                let (x0, y0) = (origin.x + px * 0.1, at[1] - px * 0.7);
                let rect = [[x0, y0], [x0 + px * 0.4, y0], [x0 + px * 0.4, at[1]], [x0, at[1]]];
                for e in 0..4 {
                    line(image, rect[e], rect[(e + 1) % 4], px / 20.0, colour, 1.0);
                }
            }
            None => {}
        }
    }
}

/// A short mark (a side letter of a slice, "R"), `px` high, centred on `centre`: light on a dark
/// disc, legible on any image.
pub fn letter(image: &mut RgbaImage, mark: &str, centre: [f32; 2], px: f32) {
    let fonts = fonts();
    let (_, width) = shape(&fonts, mark, px);
    disc(image, centre, px * 0.75, [20, 22, 28], 0.8);
    text(image, &fonts, mark, [centre[0] - width / 2.0, centre[1] + px * 0.36], px, [255, 235, 120]);
}

/// The legend of a colouring (lobes or arterial territories, [`vbrain::colouring::legend`]) in the
/// bottom left corner: a swatch and a name a row on a dark plate, `px` high text, smaller where the
/// rows would take more than 60 % of the image's height.
pub fn legend(image: &mut RgbaImage, entries: &[(String, [f32; 3])], px: f32) {
    if entries.is_empty() {
        return;
    }
    let fonts = fonts();
    let px = px.min(image.height() as f32 * 0.6 / (1.35 * entries.len() as f32)).max(6.0);
    let row = px * 1.35;
    let width = entries.iter().map(|(name, _)| shape(&fonts, name, px).1).fold(0.0, f32::max) + px * 2.2;
    let height = row * entries.len() as f32 + px * 0.6;
    let (x0, y0) = (px * 0.6, image.height() as f32 - height - px * 0.6);
    for y in y0 as i64..(y0 + height).ceil() as i64 {
        for x in x0 as i64..(x0 + width).ceil() as i64 {
            blend(image, x, y, [20, 22, 28], 0.78);
        }
    }
    for (k, (name, colour)) in entries.iter().enumerate() {
        let top = y0 + px * 0.3 + row * k as f32;
        let rgb = colour.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8);
        for y in (top + px * 0.2) as i64..(top + px * 1.1) as i64 {
            for x in (x0 + px * 0.4) as i64..(x0 + px * 1.3) as i64 {
                blend(image, x, y, rgb, 1.0);
            }
        }
        text(image, &fonts, name, [x0 + px * 1.7, top + px * 0.98], px, [245, 245, 240]);
    }
}

/// A caption's text as lines `width` pixels wide at `px`: the title's lines (`true`), then the
/// caption's, its Markdown (`**bold**`, `*italics*`, `- ` items, blank lines between paragraphs)
/// turned into plain text.
pub fn caption_lines(title: &str, caption: &str, width: f32, px: f32) -> Vec<(String, bool)> {
    let fonts = fonts();
    let title_px = px * 1.3;
    let wrap = |paragraph: &str, px: f32| -> Vec<String> {
        let mut lines = vec![String::new()];
        for word in paragraph.split_whitespace() {
            let last = lines.len() - 1;
            let joined = if lines[last].is_empty() { word.to_string() } else { format!("{} {word}", lines[last]) };
            if shape(&fonts, &joined, px).1 <= width || lines[last].is_empty() {
                lines[last] = joined;
            } else {
                lines.push(word.to_string());
            }
        }
        lines
    };
    let mut out: Vec<(String, bool)> = wrap(title, title_px).into_iter().map(|l| (l, true)).collect();
    for paragraph in caption.replace("**", "").replace('*', "").split("\n\n") {
        out.push((String::new(), false));
        for item in paragraph.lines() {
            let item = match item.trim_start().strip_prefix("- ") {
                Some(rest) => format!("\u{2022} {rest}"),
                None => item.to_string(),
            };
            out.extend(wrap(&item, px).into_iter().map(|l| (l, false)));
        }
    }
    out
}

/// The height in pixels of the band [`caption`] draws for `lines` at `px`.
pub fn caption_height(lines: &[(String, bool)], px: f32) -> u32 {
    let rows: f32 = lines.iter().map(|(_, title)| if *title { 1.3 } else { 1.0 }).sum();
    (rows * px * 1.35 + px * 1.5).ceil() as u32
}

/// `figure` with a band of `lines` ([`caption_lines`]) below it, `px` high, light on dark.
pub fn caption(figure: &RgbaImage, lines: &[(String, bool)], px: f32) -> RgbaImage {
    let band = caption_height(lines, px);
    let mut out = RgbaImage::from_pixel(figure.width(), figure.height() + band, image::Rgba([14, 16, 22, 255]));
    image::imageops::replace(&mut out, figure, 0, 0);
    let fonts = fonts();
    let mut y = figure.height() as f32 + px * 0.75;
    for (line, title) in lines {
        let size = if *title { px * 1.3 } else { px };
        y += size * 1.35;
        text(
            &mut out,
            &fonts,
            line,
            [px, y - size * 0.35],
            size,
            if *title { [255, 255, 255] } else { [225, 225, 220] },
        );
    }
    out
}

/// Draws labels of `which` organs, named by `name`, onto `image`, from the ID buffer `ids` of the
/// same size (organ index + 1 per pixel), text [`text_px`] high. Returns the labels placed.
pub fn draw(image: &mut RgbaImage, ids: &[u32], which: &Labels, name: impl Fn(usize) -> String) -> Vec<Placed> {
    let px = text_px(image.height());
    draw_sized(image, ids, which, name, px)
}

/// [`draw`] with text `px` pixels high (a worksheet's letters are larger than names).
pub fn draw_sized(
    image: &mut RgbaImage,
    ids: &[u32],
    which: &Labels,
    name: impl Fn(usize) -> String,
    px: f32,
) -> Vec<Placed> {
    let fonts = fonts();
    let laid = lay_out(ids, [image.width(), image.height()], which, &[], px, |o| shape(&fonts, &name(o), px).1);
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
        text(image, &fonts, &name(p.organ), [p.rect[0] + PAD * px, p.rect[1] + px * 0.98], px, [245, 245, 240]);
    }
    laid.into_iter().map(|l| l.placed).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgba;

    #[test]
    fn labels_cover_at_most_a_quarter_of_the_organs_largest_first() {
        // 40 organs in a 200 x 160 block of a 400 x 240 view: every name would cover far more.
        let (w, h) = (400u32, 240u32);
        let mut ids = vec![0u32; (w * h) as usize];
        for y in 40..200 {
            for x in 100..300 {
                // Organ k + 1 in column band k: wider bands on the left, so sizes differ.
                let k = ((x - 100) as f32).sqrt() as u32 * 3 + (y - 40) / 60;
                ids[(y * w + x) as usize] = k + 1;
            }
        }
        let brain = ids.iter().filter(|&&i| i > 0).count() as f32;
        let px = text_px(h);
        let laid = lay_out(&ids, [w, h], &Labels::All, &[], px, |_| px * 8.0);
        let covered: f32 =
            laid.iter().map(|l| (l.placed.rect[2] - l.placed.rect[0]) * (l.placed.rect[3] - l.placed.rect[1])).sum();
        assert!(!laid.is_empty() && covered <= brain * LABEL_SHARE + 1.0, "{covered} of {brain}");
        let pixels = |o: usize| ids.iter().filter(|&&i| i as usize == o + 1).count();
        let smallest_labelled = laid.iter().map(|l| pixels(l.placed.organ)).min().unwrap_or(0);
        let organs = ids.iter().copied().max().unwrap_or(0) as usize;
        let largest_left_out =
            (0..organs).filter(|&o| !laid.iter().any(|l| l.placed.organ == o)).map(pixels).max().unwrap_or(0);
        assert!(laid.len() < organs, "every organ labelled in a small view");
        assert!(
            smallest_labelled + 50 >= largest_left_out,
            "{smallest_labelled} labelled, {largest_left_out} left out"
        );
    }

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
        let placed = draw(&mut image, &ids, &Labels::Chosen(vec![0, 1]), |o| names[o].to_string());
        assert_eq!(placed.len(), 2, "both organs labelled");
        let dark = image.pixels().filter(|p| p[0] < 100).count();
        assert!(dark > 200, "the plates are drawn on a light background too ({dark} dark pixels)");
    }
}
