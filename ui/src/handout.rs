//! PDF handouts: a title page, then a page per figure with its heading and text, through `krilla`.
//! Lesson handouts (`vbrain lesson pdf`), quiz worksheets with their answer key (`vbrain quiz
//! --pdf`) and the viewer's *File > Export PDF handout...* are all a [`Handout`].
//!
//! - Page coordinates are PDF points (1/72 inch), origin top left, y down, as krilla lays them out.
//! - Text is DejaVu Sans (regular, bold, oblique; ui/fonts, Bitstream Vera licence), embedded and
//!   subset; it covers Latin names' accents and Greek.
//! - A text is Markdown as captions use it: paragraphs between blank lines, `- ` items, `**bold**`
//!   and `*italics*`.
//! - Figures are placed at [`FIGURE_DPI`]: [`figure_pixels`] says what size to render them.

use anyhow::{anyhow, Result};
use image::RgbaImage;
use krilla::geom::{Point, Size, Transform};
use krilla::page::PageSettings;
use krilla::text::{Font, TextDirection};
use krilla::Document;

const REGULAR: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");
const BOLD: &[u8] = include_bytes!("../fonts/DejaVuSans-Bold.ttf");
const OBLIQUE: &[u8] = include_bytes!("../fonts/DejaVuSans-Oblique.ttf");

/// Figures are rendered for this many pixels an inch of paper.
pub const FIGURE_DPI: f32 = 200.0;
/// Page margins, points.
const MARGIN: f32 = 56.0;
/// Body text size, points.
const BODY: f32 = 10.5;
/// The most of a page's text area a figure takes, by height.
const FIGURE_SHARE: f32 = 0.6;

/// A paper size.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Paper {
    A4,
    Letter,
}

impl Paper {
    /// Width and height in points.
    pub fn size(self) -> [f32; 2] {
        match self {
            Paper::A4 => [595.28, 841.89],
            Paper::Letter => [612.0, 792.0],
        }
    }
}

/// One page: a heading, an optional figure, and Markdown text below it.
pub struct Sheet {
    pub heading: String,
    pub figure: Option<RgbaImage>,
    pub text: String,
}

/// A handout: a title page (title and lines under it), then its sheets.
pub struct Handout {
    pub title: String,
    pub subtitle: Vec<String>,
    pub sheets: Vec<Sheet>,
}

/// The pixel size to render a figure of aspect `aspect` (width / height) for `paper`.
pub fn figure_pixels(paper: Paper, aspect: f32) -> [u32; 2] {
    let [w, h] = figure_points(paper, aspect);
    let px = |pt: f32| ((pt / 72.0 * FIGURE_DPI).round() as u32).max(16);
    [px(w), px(h)]
}

/// A figure's size on the page in points: the text width, or less to keep within its share.
fn figure_points(paper: Paper, aspect: f32) -> [f32; 2] {
    let [pw, ph] = paper.size();
    let width = pw - 2.0 * MARGIN;
    let most = (ph - 2.0 * MARGIN) * FIGURE_SHARE;
    let height = width / aspect;
    if height > most {
        [most * aspect, most]
    } else {
        [width, height]
    }
}

/// The lines crediting a set's sources, for a title page.
pub fn attribution(set: &vbrain::organ_set::OrganSet) -> Vec<String> {
    let mut lines = vec![format!("*{}*", set.title)];
    for s in &set.sources {
        lines.push(format!("{} ({}): {}", s.name, s.licence, s.attribution));
    }
    lines.push("Made with vbrain".to_string());
    lines
}

/// A lesson's handout: a title page with the set's attribution, then a page per step with its
/// figure (labels `forced` or the step's own, drawn at print resolution), title and caption.
/// `progress(done, steps)` after each step; false stops with an error.
pub fn of_lesson(
    studio: &mut crate::studio::Studio,
    lesson: &vbrain::lesson::Lesson,
    forced: Option<&vbrain::labels::Which>,
    paper: Paper,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<Handout> {
    let size = figure_pixels(paper, 4.0 / 3.0);
    let mut sheets = Vec::new();
    for (k, step) in lesson.steps.iter().enumerate() {
        let frame = crate::studio::StepFrame::new(studio, step, forced, size, None)?;
        let (figure, _) = frame.draw(studio, None)?;
        sheets.push(Sheet {
            heading: format!("{}. {}", k + 1, step.title),
            figure: Some(figure),
            text: step.caption.clone(),
        });
        if !progress(k + 1, lesson.steps.len()) {
            anyhow::bail!("cancelled");
        }
    }
    Ok(Handout { title: lesson.title.clone(), subtitle: attribution(studio.set), sheets })
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Style {
    Regular,
    Bold,
    Italic,
}

/// The three faces: for krilla to draw, and for ab_glyph to measure.
struct Faces {
    draw: [Font; 3],
    measure: [ab_glyph::FontRef<'static>; 3],
}

impl Faces {
    fn load() -> Result<Faces> {
        let font = |b: &'static [u8]| Font::new(b.into(), 0).ok_or_else(|| anyhow!("the handout font does not load"));
        let measure = |b: &'static [u8]| ab_glyph::FontRef::try_from_slice(b).map_err(|e| anyhow!("handout font: {e}"));
        Ok(Faces {
            draw: [font(REGULAR)?, font(BOLD)?, font(OBLIQUE)?],
            measure: [measure(REGULAR)?, measure(BOLD)?, measure(OBLIQUE)?],
        })
    }

    fn index(style: Style) -> usize {
        match style {
            Style::Regular => 0,
            Style::Bold => 1,
            Style::Italic => 2,
        }
    }

    /// The width of `text` in `style` at `size` points.
    fn width(&self, text: &str, style: Style, size: f32) -> f32 {
        use ab_glyph::Font as _;
        let f = &self.measure[Self::index(style)];
        let em = f.units_per_em().unwrap_or(2048.0);
        text.chars().map(|c| f.h_advance_unscaled(f.glyph_id(c))).sum::<f32>() / em * size
    }
}

/// A word: runs of text in their styles, drawn without space between them ("**frontal**,").
type Word = Vec<(String, Style)>;

/// A Markdown paragraph's words; `item` for a list item.
struct Paragraph {
    words: Vec<Word>,
    item: bool,
}

/// `text`'s paragraphs and items, with `**bold**` and `*italics*` as styles.
fn paragraphs(text: &str) -> Vec<Paragraph> {
    let mut out = Vec::new();
    for block in text.split("\n\n") {
        let mut current: Option<Paragraph> = None;
        for line in block.lines() {
            let (item, line) = match line.trim_start().strip_prefix("- ") {
                Some(rest) => (true, rest),
                None => (false, line),
            };
            if item || current.is_none() {
                out.extend(current.take());
                current = Some(Paragraph { words: Vec::new(), item });
            }
            if let Some(p) = current.as_mut() {
                p.words.extend(styled_words(line));
            }
        }
        out.extend(current);
    }
    out.retain(|p| !p.words.is_empty());
    out
}

/// The words of one line of Markdown, each as runs in their styles.
fn styled_words(line: &str) -> Vec<Word> {
    let mut words: Vec<Word> = Vec::new();
    let mut word: Word = Vec::new();
    let mut run = String::new();
    let mut style = Style::Regular;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        let toggle = match c {
            '*' if chars.peek() == Some(&'*') => {
                chars.next();
                Some(Style::Bold)
            }
            '*' => Some(Style::Italic),
            _ => None,
        };
        if let Some(t) = toggle {
            if !run.is_empty() {
                word.push((std::mem::take(&mut run), style));
            }
            style = if style == t { Style::Regular } else { t };
        } else if c.is_whitespace() {
            if !run.is_empty() {
                word.push((std::mem::take(&mut run), style));
            }
            if !word.is_empty() {
                words.push(std::mem::take(&mut word));
            }
        } else {
            run.push(c);
        }
    }
    if !run.is_empty() {
        word.push((run, style));
    }
    if !word.is_empty() {
        words.push(word);
    }
    words
}

/// `text`'s words, all in `style`.
fn plain_words(text: &str, style: Style) -> Vec<Word> {
    text.split_whitespace().map(|w| vec![(w.to_string(), style)]).collect()
}

/// A placed run: x, text, style.
type Placed = (f32, String, Style);

/// Lines of words at most `width` points wide at `size`: per line its runs and their x.
fn wrap(faces: &Faces, words: &[Word], width: f32, size: f32) -> Vec<Vec<Placed>> {
    let space = faces.width(" ", Style::Regular, size);
    let mut lines: Vec<Vec<Placed>> = Vec::new();
    let mut line: Vec<Placed> = Vec::new();
    let mut x = 0.0;
    for word in words {
        let w: f32 = word.iter().map(|(t, s)| faces.width(t, *s, size)).sum();
        let mut at = if line.is_empty() { 0.0 } else { x + space };
        if at + w > width && !line.is_empty() {
            lines.push(std::mem::take(&mut line));
            at = 0.0;
        }
        for (text, style) in word {
            line.push((at, text.clone(), *style));
            at += faces.width(text, *style, size);
        }
        x = at;
    }
    lines.push(line);
    lines
}

/// What a page shows, laid out: lines of text and figures, in points.
enum Mark<'h> {
    /// A line's runs from `x` at baseline `y`, `size` points high.
    Text {
        line: Vec<Placed>,
        x: f32,
        y: f32,
        size: f32,
    },
    Figure {
        image: &'h RgbaImage,
        x: f32,
        y: f32,
        w: f32,
        h: f32,
    },
}

/// Lays `handout` out on pages of `paper`: text that runs past a page's foot goes on to the next.
fn lay_out<'h>(handout: &'h Handout, paper: Paper, faces: &Faces) -> Vec<Vec<Mark<'h>>> {
    let [pw, ph] = paper.size();
    let text_width = pw - 2.0 * MARGIN;
    let mut pages: Vec<Vec<Mark>> = Vec::new();

    // The title page.
    let mut marks = Vec::new();
    let mut y = ph * 0.33;
    for line in wrap(faces, &plain_words(&handout.title, Style::Bold), text_width, 26.0) {
        y += 26.0 * 1.3;
        marks.push(Mark::Text { line, x: MARGIN, y, size: 26.0 });
    }
    y += 18.0;
    for text in &handout.subtitle {
        for line in wrap(faces, &styled_words(text), text_width, 11.0) {
            y += 11.0 * 1.45;
            marks.push(Mark::Text { line, x: MARGIN, y, size: 11.0 });
        }
    }
    pages.push(marks);

    for sheet in &handout.sheets {
        let mut marks = Vec::new();
        let mut y = MARGIN;
        for line in wrap(faces, &plain_words(&sheet.heading, Style::Bold), text_width, 16.0) {
            y += 16.0 * 1.3;
            marks.push(Mark::Text { line, x: MARGIN, y, size: 16.0 });
        }
        y += 10.0;
        if let Some(image) = &sheet.figure {
            let [w, h] = figure_points(paper, image.width() as f32 / image.height() as f32);
            marks.push(Mark::Figure { image, x: MARGIN + (text_width - w) / 2.0, y, w, h });
            y += h + 14.0;
        }
        for p in paragraphs(&sheet.text) {
            let indent = if p.item { 14.0 } else { 0.0 };
            for (k, line) in wrap(faces, &p.words, text_width - indent, BODY).into_iter().enumerate() {
                y += BODY * 1.45;
                if y > ph - MARGIN {
                    pages.push(std::mem::take(&mut marks));
                    y = MARGIN + BODY * 1.45;
                }
                if p.item && k == 0 {
                    let bullet = vec![(0.0, "\u{2022}".to_string(), Style::Regular)];
                    marks.push(Mark::Text { line: bullet, x: MARGIN + 3.0, y, size: BODY });
                }
                marks.push(Mark::Text { line, x: MARGIN + indent, y, size: BODY });
            }
            y += BODY * 0.6;
        }
        pages.push(marks);
    }
    pages
}

/// Writes `handout` on `paper` as PDF bytes.
pub fn pdf(handout: &Handout, paper: Paper) -> Result<Vec<u8>> {
    let faces = Faces::load()?;
    let [pw, ph] = paper.size();
    let mut document = Document::new();
    document.set_metadata(krilla::metadata::Metadata::new().title(handout.title.clone()).creator("vbrain".into()));
    for marks in lay_out(handout, paper, &faces) {
        let mut page = document.start_page_with(PageSettings::from_wh(pw, ph).ok_or_else(|| anyhow!("paper size"))?);
        let mut surface = page.surface();
        for mark in marks {
            match mark {
                Mark::Text { line, x, y, size } => draw_line(&mut surface, &faces, &line, x, y, size),
                Mark::Figure { image, x, y, w, h } => {
                    let picture =
                        krilla::image::Image::from_rgba8(image.as_raw().clone(), image.width(), image.height());
                    surface.push_transform(&Transform::from_translate(x, y));
                    surface.draw_image(picture, Size::from_wh(w, h).ok_or_else(|| anyhow!("figure size"))?);
                    surface.pop();
                }
            }
        }
        surface.finish();
        page.finish();
    }
    document.finish().map_err(|e| anyhow!("PDF: {e:?}"))
}

/// Draws one wrapped line at baseline `y` from `x`.
fn draw_line(surface: &mut krilla::surface::Surface, faces: &Faces, line: &[Placed], x: f32, y: f32, size: f32) {
    for (at, text, style) in line {
        let font = faces.draw[Faces::index(*style)].clone();
        surface.draw_text(Point::from_xy(x + at, y), font, size, text, false, TextDirection::Auto);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markdown_keeps_items_bold_and_italics() {
        let p = paragraphs("The **central sulcus** runs *down*.\n\n- one item\n- two **bold**\nmore");
        assert_eq!(p.len(), 3);
        assert!(!p[0].item && p[1].item && p[2].item);
        assert_eq!(p[0].words[1], vec![("central".to_string(), Style::Bold)]);
        // Punctuation after a styled word stays on it, unspaced.
        assert_eq!(p[0].words[4], vec![("down".to_string(), Style::Italic), (".".to_string(), Style::Regular)]);
        assert_eq!(p[2].words.last().unwrap()[0].0, "more");
    }

    #[test]
    fn wrapped_lines_fit_their_width() {
        let faces = Faces::load().unwrap();
        let words = styled_words(&"gyrus cinguli pars opercularis ".repeat(20));
        let lines = wrap(&faces, &words, 200.0, BODY);
        assert!(lines.len() > 5);
        for line in &lines {
            let (x, w, s) = line.last().unwrap();
            assert!(*x >= 0.0);
            assert!(x + faces.width(w, *s, BODY) <= 200.0 + 1e-3);
        }
    }

    #[test]
    fn long_text_goes_on_to_more_pages() {
        let faces = Faces::load().unwrap();
        let text = (1..=150).map(|k| format!("- answer {k}")).collect::<Vec<_>>().join("\n");
        let handout = Handout {
            title: "Key".into(),
            subtitle: Vec::new(),
            sheets: vec![Sheet { heading: "Answer key".into(), figure: None, text }],
        };
        let pages = lay_out(&handout, Paper::A4, &faces);
        assert!(pages.len() >= 3, "{} pages", pages.len());
        let last_y = |marks: &Vec<Mark>| {
            marks
                .iter()
                .map(|m| match m {
                    Mark::Text { y, .. } => *y,
                    _ => 0.0,
                })
                .fold(0.0, f32::max)
        };
        for page in &pages {
            assert!(last_y(page) <= Paper::A4.size()[1] - MARGIN);
        }
        let lines: usize = pages
            .iter()
            .map(|p| p.iter().filter(|m| matches!(m, Mark::Text { x, .. } if *x == MARGIN + 14.0)).count())
            .sum();
        assert_eq!(lines, 150);
    }
}
