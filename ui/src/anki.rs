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
//! - A lesson's quiz adds a note per question, drawn from the question's own view: *name it*
//!   (the structure outlined) or *find it* (the name asked, the figure outlined on the back).
//! - Identifiers are stable: note GUIDs derive from the set's title, the organ's id, the card kind
//!   and the view; deck and model ids from their names. Importing a new export updates the notes
//!   (and keeps their reviews) instead of adding duplicates.
//! - Decks and tags follow the set's groups (`vbrain::TITLE::Cerebrum::Frontal lobe`, tag
//!   `vbrain::Cerebrum::Frontal_lobe`); media names carry a hash of the set's title.
//! - Text reaches the cards HTML-escaped ([`html`]); pictures are PNGs in screen pixels.
//! - Views are chosen from small culled organ-ID renders; each chosen view is drawn once, faded
//!   organs through the k-buffer (one pass however many are faded), its outline added after.

use crate::annotate::{self, Labels};
use anyhow::{anyhow, bail, Result};
use genanki_rs::{Deck, Field, Model, Note, Package, Template};
use image::RgbaImage;
use std::path::{Path, PathBuf};
use vbrain::camera::View;
use vbrain::clip::Section;
use vbrain::cull::{CullSettings, Culler};
use vbrain::layout::Layout;
use vbrain::navigation::Navigator;
use vbrain::organ_set::OrganSet;
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};
use vbrain::transparency::{TransparencyMode, TransparencySettings};

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
    /// A lesson's quiz, as cards from each question's own view: the lesson's title and questions.
    pub lesson: Option<(String, Vec<LessonQuestion>)>,
}

/// A question of a lesson's quiz: what it asks and the view it starts from (a step's layout,
/// camera and cut, or the default layout seen from the structure's side).
pub struct LessonQuestion {
    pub kind: vbrain::quiz::Kind,
    pub organ: usize,
    pub layout: Layout,
    pub navigator: Navigator,
    pub section: Section,
}

impl LessonQuestion {
    /// The questions of `lesson`'s quiz over `set`.
    pub fn of(lesson: &vbrain::lesson::Lesson, set: &OrganSet) -> Result<Vec<LessonQuestion>> {
        let questions = lesson.questions(set).map_err(|e| anyhow!(e))?;
        Ok(questions
            .into_iter()
            .enumerate()
            .map(|(k, q)| match lesson.question_view(k, set) {
                Some(step) => LessonQuestion {
                    kind: q.kind,
                    organ: q.organ,
                    layout: step.layout,
                    navigator: step.navigator,
                    section: step.section,
                },
                None => {
                    let (layout, navigator) = vbrain::quiz::side_view(set, q.organ);
                    LessonQuestion { kind: q.kind, organ: q.organ, layout, navigator, section: Section::default() }
                }
            })
            .collect())
    }
}

/// What was written: notes per kind, and structures that no view shows.
#[derive(Debug, Default, serde::Serialize)]
pub struct DeckReport {
    pub structures: usize,
    pub notes: usize,
    /// Of the notes, those of a lesson's quiz questions.
    pub questions: usize,
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

/// Text as HTML: `&`, `<`, `>`, `"` and `'` escaped, control characters as spaces, line breaks as
/// `<br>`.
pub fn html(text: &str) -> String {
    vbrain::web_page::escape_markup(text).replace('\n', "<br>")
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

fn models() -> (Model, Model, Model) {
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
    let find_it = Model::new(
        stable_id("vbrain find it"),
        "vbrain find it",
        ["Name", "Latin", "Info", "Plain", "Outlined"].map(Field::new).to_vec(),
        vec![Template::new("Find it").qfmt("{{Plain}}<div>Where is the <b>{{Name}}</b>?</div>").afmt(
            "{{Outlined}}<hr id=answer><b>{{Name}}</b><div class=latin>{{Latin}}</div><div class=info>{{Info}}</div>",
        )],
    )
    .css(css);
    (name_it, occlusion, find_it)
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

/// A view a structure may be shown from: its pixels seen as the set is laid out, and alone (0
/// where not needed); its azimuth and elevation; its camera.
struct Candidate {
    shows: (usize, usize),
    angles: (f32, f32),
    camera: vbrain::camera::Camera,
}

/// Builds the deck of `opts.scope` and returns the .apkg's bytes; `progress(done, total)` hears
/// of each structure.
pub fn build(
    set: &OrganSet,
    database: Option<vbrain::cull::database::Database>,
    opts: &DeckOptions,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(Vec<u8>, DeckReport)> {
    if opts.scope.is_empty() && opts.lesson.as_ref().is_none_or(|(_, q)| q.is_empty()) {
        bail!("no structures in scope");
    }
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, set)?;
    let (w, h) = opts.size;
    let mut target = Target::new(&gpu.device, w, h)?;
    let aspect = target.aspect();
    let scout = Target::new(&gpu.device, SCOUT_PX, (SCOUT_PX * h / w.max(1)).max(16))?;
    let mut culler = Culler::new(database);
    let base = Layout::new(set);
    let home = base.bounds(set);
    let media_dir = tempfile::tempdir()?;
    let set_key = format!("{:08x}", fnv(&set.title) as u32);
    let (name_it, occlusion, find_it) = models();
    let (mut decks, mut deck_names): (Vec<Deck>, Vec<String>) = (Vec::new(), Vec::new());
    let mut media: Vec<PathBuf> = Vec::new();
    let mut report = DeckReport { structures: opts.scope.len(), ..Default::default() };
    // Pictures are PNG-encoded on a thread of their own while the next ones are drawn.
    let (encode, pictures) = std::sync::mpsc::sync_channel::<(PathBuf, RgbaImage)>(8);
    let encoder = std::thread::spawn(move || -> Result<()> {
        for (path, image) in pictures {
            image.save(&path).map_err(|e| anyhow!("{}: {e}", path.display()))?;
        }
        Ok(())
    });
    // Queues a picture for the encoder and keeps its path; false once the encoder has stopped
    // (its error comes back when it is joined, below).
    let mut queue = |name: String, image: RgbaImage| {
        let path = media_dir.path().join(name);
        media.push(path.clone());
        encode.send((path, image)).is_ok()
    };
    // Organ IDs of a layout, culled (culling changes no pixel); faint organs are see-through.
    let ids_of = |target: &Target, camera: &vbrain::camera::Camera, layout: &Layout| {
        let (draw, _) = vbrain::cull::cull(set, layout, camera, target.aspect(), &CullSettings::default());
        let frame = FrameInput { draw: Some(&draw), ..FrameInput::new(set, camera, layout) };
        renderer.render_ids(&gpu.device, &gpu.queue, target, &frame, annotate::PICK_OPACITY);
        target.read_ids(&gpu.device, &gpu.queue).unwrap_or_default()
    };
    // One view of `organ`: the frame plain, then outlined (the outline drawn over it), and its
    // organ IDs.
    let mut draw = |camera: &vbrain::camera::Camera, layout: &Layout, section: &Section, organ: usize| {
        let plain = FrameInput {
            background: crate::background_linear(crate::background_srgb(), false),
            transparency: TransparencySettings { mode: TransparencyMode::KBuffer, ..Default::default() },
            section,
            ..FrameInput::new(set, camera, layout)
        };
        let (draw, _) = culler.cull_frame(&renderer.cull_input(&plain, &target), &CullSettings::default());
        let frame = |highlight| FrameInput { draw: Some(&draw), highlight, ..plain };
        renderer.render(&gpu.device, &gpu.queue, &mut target, &frame(&[]))?;
        let plain = target.read_color(&gpu.device, &gpu.queue)?;
        let asked = [organ];
        renderer.render_outlines(&gpu.device, &gpu.queue, &target, &frame(&asked));
        let outlined = target.read_color(&gpu.device, &gpu.queue)?;
        renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame(&[]), annotate::PICK_OPACITY);
        anyhow::Ok((plain, outlined, target.read_ids(&gpu.device, &gpu.queue)?))
    };
    let mut at_rest: std::collections::HashMap<(u32, u32), Vec<u32>> = std::collections::HashMap::new();
    for (done, &organ) in opts.scope.iter().enumerate() {
        let o = &set.organs[organ];
        // Candidate views: the quiz's side view, then the six standard ones; tried in the order
        // of how much of the structure shows as the set is laid out, then of its size alone. The
        // first `views` where it shows once what hides it is faded are its best.
        let side = vbrain::quiz::camera(set, &base, organ);
        let side = (side.azimuth, side.elevation);
        let mut angles = vec![side];
        angles.extend(View::ALL.iter().map(|v| v.angles()).filter(|&a| a != side));
        let mut alone = base.clone();
        for (k, s) in alone.organs.iter_mut().enumerate() {
            s.visible = k == organ;
            s.opacity = 1.0;
        }
        let count = |ids: &[u32]| ids.iter().filter(|&&id| id as usize == organ + 1).count();
        let mut candidates: Vec<Candidate> = Vec::new();
        for &(az, el) in &angles {
            let camera = Navigator::fitting(&home, az, el, scout.aspect(), crate::studio::FILL_LABELLED).camera(&home);
            let rest = at_rest.entry((az.to_bits(), el.to_bits())).or_insert_with(|| ids_of(&scout, &camera, &base));
            candidates.push(Candidate { shows: (count(rest), 0), angles: (az, el), camera });
        }
        // Its size alone matters only where it shows in fewer views than are asked for.
        if candidates.iter().filter(|c| c.shows.0 > 0).count() < opts.views.max(1) {
            for c in &mut candidates {
                c.shows.1 = count(&ids_of(&scout, &c.camera, &alone));
            }
        }
        candidates.sort_by_key(|c| std::cmp::Reverse(c.shows));
        let mut ranked: Vec<(usize, (f32, f32), Layout)> = Vec::new();
        for Candidate { angles: (az, el), camera, .. } in candidates {
            if ranked.len() == opts.views.max(1) {
                break;
            }
            // The set as laid out was drawn above: reveals start there, and many end there.
            let mut ids = |l: &Layout| match l == &base {
                true => at_rest[&(az.to_bits(), el.to_bits())].clone(),
                false => ids_of(&scout, &camera, l),
            };
            let (layout, _) = vbrain::quiz::reveal(organ, &base, &mut ids);
            let shown = count(&ids(&layout));
            if shown > 0 {
                ranked.push((shown, (az, el), layout));
            }
        }
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
            let nav = Navigator::fitting(&home, az, el, aspect, crate::studio::FILL_LABELLED);
            let (plain, outlined, seen) = draw(&nav.camera(&home), &layout, &Section::default(), organ)?;
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
            for (kind, image) in images {
                if !queue(file(kind), image) {
                    break;
                }
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
    if let Some((title, questions)) = &opts.lesson {
        let deck_title = deck_name(&set.title, &format!("Lessons/{}", title.replace('/', "-")));
        let mut deck = Deck::new(stable_id(&deck_title), &deck_title, &format!("From vbrain: {}", html(title)));
        let lesson_key = format!("{:08x}", fnv(title) as u32);
        for (k, q) in questions.iter().enumerate() {
            let o = &set.organs[q.organ];
            let scout_camera = vbrain::web_page::camera(set, &q.layout, &q.navigator);
            let (layout, _) = vbrain::quiz::reveal(q.organ, &q.layout, |l| ids_of(&scout, &scout_camera, l));
            let camera = vbrain::web_page::camera(set, &layout, &q.navigator);
            let (plain, outlined, seen) = draw(&camera, &layout, &q.section, q.organ)?;
            if !seen.contains(&(q.organ as u32 + 1)) {
                report.unseen.push(format!("{} (question {} of the lesson)", o.name, k + 1));
                continue;
            }
            let file = |kind: &str| format!("vbrain-{set_key}-lesson-{lesson_key}-q{}-{kind}.png", k + 1);
            for (kind, image) in [("plain", plain), ("outlined", outlined)] {
                if !queue(file(kind), image) {
                    break;
                }
            }
            let img = |kind: &str| format!("<img src=\"{}\">", html(&file(kind)));
            let (name, latin, info) = (html(&o.name), html(o.latin.as_deref().unwrap_or("")), html(&o.info));
            let note = match q.kind {
                vbrain::quiz::Kind::Name => {
                    let synonyms = html(&o.synonyms.join(", "));
                    Note::new(
                        name_it.clone(),
                        vec![&name, &latin, &synonyms, &info, &img("outlined"), &img("outlined")],
                    )?
                }
                vbrain::quiz::Kind::Locate => {
                    Note::new(find_it.clone(), vec![&name, &latin, &info, &img("plain"), &img("outlined")])?
                }
                // Lessons ask no supply questions (Lesson::parse refuses them).
                vbrain::quiz::Kind::Supply => continue,
            };
            let id = format!("lesson {title} question {}", k + 1);
            deck.add_note(note.guid(guid(&set.title, &id, &o.id, 0)).tags([tag(&o.group), "vbrain::lesson".into()]));
            report.notes += 1;
            report.questions += 1;
        }
        if report.questions > 0 {
            decks.push(deck);
        }
    }
    drop(encode);
    encoder.join().map_err(|_| anyhow!("the picture encoder stopped"))??;
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
