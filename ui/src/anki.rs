//! Anki decks of a set's structures, for students who review with Anki. Per structure in scope,
//! from its best views (where most of it shows once the organs hiding it are faded, as the quiz
//! reveals deep targets), three notes:
//! - *name it*: the structure outlined; the back names it (Latin name, synonyms, the teaching
//!   text) beside the same figure labelled;
//! - *image occlusion, hide one*: the structure covered by a mask shaped exactly like what shows of
//!   it (from the organ-ID buffer, not a rectangle); the back uncovers it, outlined;
//! - *image occlusion, hide all, guess one*: the structure and its nearest neighbours in the
//!   picture all covered, the one asked in red; the back uncovers it.
//!
//! - Identifiers are stable: note GUIDs derive from the set's title, the organ's id, the card kind
//!   and the view; deck and model ids from their names. Importing a new export updates the notes
//!   (and keeps their reviews) instead of adding duplicates.
//! - Decks and tags follow the set's groups (`vbrain::TITLE::Cerebrum::Frontal lobe`, tag
//!   `vbrain::Cerebrum::Frontal_lobe`); media names carry a hash of the set's title.
//! - Text reaches the cards HTML-escaped ([`html`]); pictures are PNGs in screen pixels.

use crate::annotate::{self, Labels};
use anyhow::{anyhow, bail, Result};
use genanki_rs::{Deck, Field, Model, Note, Package, Template};
use image::RgbaImage;
use std::path::{Path, PathBuf};
use vbrain::camera::View;
use vbrain::cull::{CullSettings, Culler};
use vbrain::layout::Layout;
use vbrain::navigation::Navigator;
use vbrain::organ_set::OrganSet;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};

/// The mask over the structure asked, and over the others in "hide all".
const ASKED: [u8; 3] = [224, 68, 62];
const OTHERS: [u8; 3] = [120, 150, 190];
/// Side of the small images that choose the views (the same aspect as the cards').
const SCOUT_PX: u32 = 160;
/// Neighbours covered besides the structure in "hide all, guess one".
const NEIGHBOURS: usize = 3;

/// What a deck holds.
pub struct DeckOptions {
    /// Organs in scope.
    pub scope: Vec<usize>,
    /// Card pictures, pixels.
    pub size: (u32, u32),
    /// Views per structure, 1..=4.
    pub views: usize,
}

/// What was written: notes per kind, and structures that no view shows.
#[derive(Debug, Default, serde::Serialize)]
pub struct DeckReport {
    pub structures: usize,
    pub notes: usize,
    pub media: usize,
    pub unseen: Vec<String>,
}

/// FNV-1a, 64 bits: stable across runs, machines and versions (unlike std's hasher).
fn fnv(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3))
}

/// An Anki id (deck or model) from a name: positive, stable.
pub fn stable_id(name: &str) -> i64 {
    (fnv(name) >> 2) as i64 + 1
}

/// A note's GUID: the set, the organ, the card kind and the view.
pub fn guid(set_title: &str, organ: &str, kind: &str, view: usize) -> String {
    format!("vb{:016x}", fnv(&format!("{set_title}\u{1f}{organ}\u{1f}{kind}\u{1f}{view}")))
}

/// Text as HTML: `&`, `<`, `>`, `"` and `'` escaped, line breaks as `<br>`.
pub fn html(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            '\n' => out.push_str("<br>"),
            c => out.push(c),
        }
    }
    out
}

/// A group path as a deck name under `vbrain::TITLE` (Anki splits decks at `::`).
pub fn deck_name(set_title: &str, group: &str) -> String {
    let clean = |s: &str| s.replace("::", ":");
    let mut name = format!("vbrain::{}", clean(set_title));
    for part in group.split('/').filter(|p| !p.is_empty()) {
        name.push_str("::");
        name.push_str(&clean(part));
    }
    name
}

/// A group path as an Anki tag (no spaces).
pub fn tag(group: &str) -> String {
    let parts: Vec<String> = group.split('/').filter(|p| !p.is_empty()).map(|p| p.replace(' ', "_")).collect();
    format!("vbrain::{}", parts.join("::"))
}

fn models() -> (Model, Model) {
    let css = ".card { font-family: sans-serif; font-size: 20px; text-align: center; color: #222; background: #fff; }\n\
               img { max-width: 100%; } .latin { font-style: italic; color: #555; } .info { text-align: left; font-size: 16px; margin: 1em auto; max-width: 40em; }";
    let name_it = Model::new(
        stable_id("vbrain name it"),
        "vbrain name it",
        ["Name", "Latin", "Synonyms", "Info", "Outlined", "Labelled"].map(Field::new).to_vec(),
        vec![Template::new("Name it")
            .qfmt("{{Outlined}}<div>Name the outlined structure.</div>")
            .afmt("{{Labelled}}<hr id=answer><b>{{Name}}</b><div class=latin>{{Latin}}</div><div>{{Synonyms}}</div><div class=info>{{Info}}</div>")],
    )
    .css(css);
    let occlusion = Model::new(
        stable_id("vbrain image occlusion"),
        "vbrain image occlusion",
        ["Name", "Latin", "Info", "Masked", "Uncovered", "Kind"].map(Field::new).to_vec(),
        vec![Template::new("Occlusion").qfmt("{{Masked}}<div>What lies under the red mask?</div>").afmt(
            "{{Uncovered}}<hr id=answer><b>{{Name}}</b><div class=latin>{{Latin}}</div><div class=info>{{Info}}</div>",
        )],
    )
    .css(css);
    (name_it, occlusion)
}

/// `image` with the pixels of each `(organ, colour)` in `ids` (organ + 1 per pixel) painted over.
pub fn cover(image: &RgbaImage, ids: &[u32], masks: &[(usize, [u8; 3])]) -> RgbaImage {
    let mut out = image.clone();
    for (p, &id) in out.pixels_mut().zip(ids) {
        if let Some((_, c)) = masks.iter().find(|(o, _)| id as usize == o + 1) {
            *p = image::Rgba([c[0], c[1], c[2], 255]);
        }
    }
    out
}

/// Builds the deck of `opts.scope` and returns the .apkg's bytes; `progress(done, total)` hears
/// of each structure.
pub fn build(
    set: &OrganSet,
    database: Option<vbrain::cull::database::Database>,
    opts: &DeckOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(Vec<u8>, DeckReport)> {
    if opts.scope.is_empty() {
        bail!("no structures in scope");
    }
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, set)?;
    let (w, h) = opts.size;
    let target = Target::new(&gpu.device, w, h)?;
    let scout = Target::new(&gpu.device, SCOUT_PX, (SCOUT_PX * h / w.max(1)).max(16))?;
    let mut culler = Culler::new(database);
    let base = Layout::new(set);
    let home = base.bounds(set);
    let media_dir = tempfile::tempdir()?;
    let set_key = format!("{:08x}", fnv(&set.title) as u32);
    let (name_it, occlusion) = models();
    let (mut decks, mut deck_names): (Vec<Deck>, Vec<String>) = (Vec::new(), Vec::new());
    let mut media: Vec<PathBuf> = Vec::new();
    let mut report = DeckReport { structures: opts.scope.len(), ..Default::default() };
    let ids_of = |target: &Target, camera: &vbrain::camera::Camera, layout: &Layout| {
        let frame = FrameInput::new(set, camera, layout);
        renderer.render_ids(&gpu.device, &gpu.queue, target, &frame, annotate::PICK_OPACITY);
        target.read_ids(&gpu.device, &gpu.queue).unwrap_or_default()
    };
    for (done, &organ) in opts.scope.iter().enumerate() {
        let o = &set.organs[organ];
        // Candidate views: the quiz's side view, then the six standard ones; ranked by how many
        // of the structure's pixels show once what hides it is faded.
        let side = vbrain::quiz::camera(set, &base, organ);
        let mut angles = vec![(side.azimuth, side.elevation)];
        angles.extend(View::ALL.iter().map(|v| v.angles()));
        let mut ranked: Vec<(usize, (f32, f32), Layout)> = Vec::new();
        for &(az, el) in &angles {
            let nav = Navigator::fitting(&home, az, el, scout.aspect(), crate::studio::FILL_LABELLED);
            let camera = nav.camera(&home);
            let (layout, _) = vbrain::quiz::reveal(organ, &base, |l| ids_of(&scout, &camera, l));
            let shown = ids_of(&scout, &camera, &layout).iter().filter(|&&id| id as usize == organ + 1).count();
            if shown > 0 && !ranked.iter().any(|r| r.1 == (az, el)) {
                ranked.push((shown, (az, el), layout));
            }
        }
        ranked.sort_by_key(|r| std::cmp::Reverse(r.0));
        if ranked.is_empty() {
            report.unseen.push(o.name.clone());
            progress(done + 1, opts.scope.len());
            continue;
        }
        let deck_title = deck_name(&set.title, &o.group);
        let deck_at = match deck_names.iter().position(|d| *d == deck_title) {
            Some(i) => i,
            None => {
                decks.push(Deck::new(
                    stable_id(&deck_title),
                    &deck_title,
                    &format!("From vbrain: {}", html(&set.title)),
                ));
                deck_names.push(deck_title);
                decks.len() - 1
            }
        };
        for (view, (_, (az, el), layout)) in ranked.into_iter().take(opts.views.max(1)).enumerate() {
            let nav = Navigator::fitting(&home, az, el, target.aspect(), crate::studio::FILL_LABELLED);
            let camera = nav.camera(&home);
            let (draw, _) = culler.cull(set, &layout, &camera, target.aspect(), &CullSettings::default());
            let shot = |highlight: &[usize]| -> Result<(RgbaImage, Vec<u32>)> {
                let frame = FrameInput {
                    draw: Some(&draw),
                    background: crate::background_linear(crate::background_srgb(), false),
                    highlight,
                    ..FrameInput::new(set, &camera, &layout)
                };
                renderer.render(&gpu.device, &gpu.queue, &target, &frame)?;
                let image = target.read_color(&gpu.device, &gpu.queue)?;
                renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame, annotate::PICK_OPACITY);
                Ok((image, target.read_ids(&gpu.device, &gpu.queue)?))
            };
            let (plain, seen) = shot(&[])?;
            let (outlined, _) = shot(&[organ])?;
            let mut labelled = outlined.clone();
            let px = annotate::text_px(h) * 1.3;
            annotate::draw_sized(
                &mut labelled,
                &seen,
                &Labels::Chosen(vec![organ]),
                |i| set.organs[i].name.clone(),
                px,
            );
            let mut shown: Vec<usize> = seen.iter().filter(|&&id| id > 0).map(|&id| id as usize - 1).collect();
            shown.sort_unstable();
            shown.dedup();
            let mut rng = vbrain::rng::XorShift::seeded(fnv(&o.id));
            let mut neighbours = vbrain::quiz::choices(set, organ, &shown, &mut rng);
            neighbours.retain(|&n| n != organ && shown.contains(&n));
            neighbours.truncate(NEIGHBOURS);
            let mut all: Vec<(usize, [u8; 3])> = vec![(organ, ASKED)];
            all.extend(neighbours.iter().map(|&n| (n, OTHERS)));
            let images = [
                ("outlined", outlined),
                ("labelled", labelled),
                ("hide-one", cover(&plain, &seen, &[(organ, ASKED)])),
                ("hide-all", cover(&plain, &seen, &all)),
            ];
            let file = |kind: &str| format!("vbrain-{set_key}-{}-v{}-{kind}.png", o.id, view + 1);
            for (kind, image) in &images {
                let path = media_dir.path().join(file(kind));
                image.save(&path).map_err(|e| anyhow!("{}: {e}", path.display()))?;
                media.push(path);
            }
            let img = |kind: &str| format!("<img src=\"{}\">", html(&file(kind)));
            let (name, latin, info) = (html(&o.name), html(o.latin.as_deref().unwrap_or("")), html(&o.info));
            let synonyms = html(&o.synonyms.join(", "));
            let tags = [tag(&o.group)];
            let deck = &mut decks[deck_at];
            deck.add_note(
                Note::new(name_it.clone(), vec![&name, &latin, &synonyms, &info, &img("outlined"), &img("labelled")])?
                    .guid(guid(&set.title, &o.id, "name", view))
                    .tags(tags.clone()),
            );
            for (kind, masked) in [("hide one", "hide-one"), ("hide all, guess one", "hide-all")] {
                deck.add_note(
                    Note::new(occlusion.clone(), vec![&name, &latin, &info, &img(masked), &img("outlined"), kind])?
                        .guid(guid(&set.title, &o.id, masked, view))
                        .tags(tags.clone()),
                );
            }
            report.notes += 3;
        }
        progress(done + 1, opts.scope.len());
    }
    if decks.is_empty() {
        bail!("no structure in scope shows from any view: {}", report.unseen.join(", "));
    }
    report.media = media.len();
    let paths: Vec<&str> = media.iter().filter_map(|p| p.to_str()).collect();
    let mut package = Package::new(decks, paths)?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    package.write(&mut bytes)?;
    Ok((bytes.into_inner(), report))
}

/// Writes the deck's bytes to `out` (refusing an existing file unless `force`).
pub fn write(out: &Path, bytes: &[u8], force: bool) -> Result<()> {
    let fill = |w: &mut dyn std::io::Write| w.write_all(bytes);
    if force {
        vbrain::atomic::write(out, fill)?;
    } else {
        vbrain::atomic::write_new(out, fill).map_err(|e| anyhow!("{e} (use --force to replace it)"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_stable_and_distinct() {
        assert_eq!(guid("Brain", "insula_l", "name", 0), guid("Brain", "insula_l", "name", 0));
        assert_ne!(guid("Brain", "insula_l", "name", 0), guid("Brain", "insula_l", "name", 1));
        assert_ne!(guid("Brain", "insula_l", "name", 0), guid("Brain", "insula_r", "name", 0));
        assert!(stable_id("a") > 0 && stable_id("a") != stable_id("b"));
        // FNV-1a of "a", a published test vector.
        assert_eq!(fnv("a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn names_become_markup_free_decks_and_tags() {
        assert_eq!(html("<script>&\"x\"]]>'"), "&lt;script&gt;&amp;&quot;x&quot;]]&gt;&#39;");
        assert_eq!(deck_name("Brain", "Cerebrum/Frontal lobe"), "vbrain::Brain::Cerebrum::Frontal lobe");
        assert_eq!(deck_name("A::B", ""), "vbrain::A:B");
        assert_eq!(tag("Cerebrum/Frontal lobe"), "vbrain::Cerebrum::Frontal_lobe");
    }

    #[test]
    fn covering_paints_exactly_the_organs_pixels() {
        let image = RgbaImage::from_pixel(3, 1, image::Rgba([1, 2, 3, 255]));
        let out = cover(&image, &[0, 2, 3], &[(1, ASKED), (2, OTHERS)]);
        assert_eq!(out.get_pixel(0, 0).0, [1, 2, 3, 255]);
        assert_eq!(out.get_pixel(1, 0).0[..3], ASKED);
        assert_eq!(out.get_pixel(2, 0).0[..3], OTHERS);
    }
}
