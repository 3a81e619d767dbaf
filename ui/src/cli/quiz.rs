//! `vbrain quiz`: a worksheet for class from the same renderer as the viewer. Per question a PNG
//! (`DIR/q01.png`, ...) from a camera that shows the structure (the organs hiding it faded, as the
//! viewer's quiz does), `DIR/questions.md` and `DIR/answers.md`. A "name" question outlines the
//! structure and labels it A, with four names to choose from; a "locate" question labels the
//! structure and the three structures nearest it that the picture shows A to D, and asks which
//! letter it is.
//!
//! - Each picture frames the whole brain, centred, from the side of the question's structure,
//!   with room beside it for the letters ([`crate::studio::FILL_LABELLED`]).
//! - Letters are [`LETTER_SHARE`] of the picture's height, larger than names, legible in class.

use super::common::{database, open_set};
use super::QuizArgs;
use crate::annotate::Labels;
use crate::handout::{Handout, Sheet};
use anyhow::{anyhow, Result};
use serde_json::json;
use vbrain::cull::{CullSettings, Culler};
use vbrain::layout::Layout;
use vbrain::navigation::Navigator;
use vbrain::quiz::{self, Kind, Spec};
use vbrain::render::{FrameInput, GpuContext, Renderer, Target};

/// A worksheet letter's height as a share of the picture's height.
pub const LETTER_SHARE: f32 = 0.05;

/// The letter of choice `k`.
fn letter(k: usize) -> String {
    char::from(b'A' + (k % 26) as u8).to_string()
}

pub fn run(args: &QuizArgs) -> Result<bool> {
    let path = vbrain::data_dir::set_or_default(args.set.as_deref())?;
    let set = open_set(&path)?;
    let scope = quiz::scope(&set, args.group.as_deref()).map_err(|e| anyhow!(e))?;
    let spec = Spec { scope, questions: args.questions, mode: args.mode, seed: args.seed };
    let generated = quiz::generate(&set, &spec).map_err(|e| anyhow!(e))?;
    if let Some(note) = &generated.note {
        eprintln!("note: {note}");
    }
    use super::outputs::{self, Kind as Out};
    outputs::folder(&args.out, args.force, &[&path])?;
    let pdf = args.pdf.as_ref().map(|p| outputs::file(p, Out::New("pdf"), args.force, &[&path])).transpose()?;
    outputs::apart(&args.pdf.iter().map(std::path::PathBuf::as_path).collect::<Vec<_>>(), &[&args.out])?;
    // The folder's files, written together once every question is drawn.
    let mut files: Vec<(String, Vec<u8>)> = Vec::new();
    let gpu = GpuContext::headless()?;
    let renderer = Renderer::new(&gpu.device, &set)?;
    let mut target = Target::new(&gpu.device, args.size.width, args.size.height)?;
    let mut culler = Culler::new(database(&path, &set));
    let base = Layout::new(&set);
    let home = base.bounds(&set);
    let title = match &args.group {
        Some(g) => format!("{}: {g}", set.title),
        None => set.title.clone(),
    };
    let mut questions_md = format!("# Quiz: {title}\n\nSeed {}, {} questions.\n", args.seed, generated.questions.len());
    let mut answers_md = format!("# Answers: {title}\n\nSeed {}.\n\n", args.seed);
    let mut listed = Vec::new();
    let mut sheets = Vec::new();
    for (k, q) in generated.questions.iter().enumerate() {
        let mut q = q.clone();
        let (mut image, seen) = match q.slice {
            Some(plane) => {
                slice_picture(&set, &mut q, plane, [args.size.width, args.size.height], args.seed ^ (k as u64 + 1))
            }
            None => {
                let side = quiz::camera(&set, &base, q.organ);
                let nav = Navigator::fitting(
                    &home,
                    side.azimuth,
                    side.elevation,
                    target.aspect(),
                    crate::studio::FILL_LABELLED,
                );
                let camera = nav.camera(&home);
                let ids = |layout: &Layout| {
                    let frame = FrameInput::new(&set, &camera, layout);
                    renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame, crate::annotate::PICK_OPACITY);
                    target.read_ids(&gpu.device, &gpu.queue).unwrap_or_default()
                };
                let (layout, _) = quiz::reveal(q.organ, &base, ids);
                // A locate question's letters go on the structure and the nearest others seen beside it.
                if q.kind == Kind::Locate {
                    letters_on_what_shows(&set, &mut q, &ids(&layout), args.seed ^ (k as u64 + 1));
                }
                let (draw, _) = culler.cull(&set, &layout, &camera, target.aspect(), &CullSettings::default());
                let highlight = if q.kind == Kind::Locate { Vec::new() } else { vec![q.organ] };
                let frame = FrameInput {
                    draw: Some(&draw),
                    background: crate::background_linear(crate::background_srgb(), false),
                    highlight: &highlight,
                    ..FrameInput::new(&set, &camera, &layout)
                };
                renderer.render(&gpu.device, &gpu.queue, &mut target, &frame)?;
                let image = target.read_color(&gpu.device, &gpu.queue)?;
                renderer.render_ids(&gpu.device, &gpu.queue, &target, &frame, crate::annotate::PICK_OPACITY);
                let seen = target.read_ids(&gpu.device, &gpu.queue)?;
                (image, seen)
            }
        };
        let (labels, name): (Labels, Box<dyn Fn(usize) -> String>) = match q.kind {
            Kind::Name | Kind::Supply => (Labels::Chosen(vec![q.organ]), Box::new(|_| "A".to_string())),
            Kind::Locate => {
                let choices = q.choices.clone();
                let name = move |o: usize| choices.iter().position(|&c| c == o).map_or(String::new(), letter);
                (Labels::Chosen(q.choices.clone()), Box::new(name))
            }
        };
        let px = (args.size.height as f32 * LETTER_SHARE).max(14.0);
        let placed = crate::annotate::draw_sized(&mut image, &seen, &labels, name, px);
        let file = format!("q{:02}.png", k + 1);
        let mut png = Vec::new();
        image.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
        files.push((file.clone(), png));
        let answer = &set.organs[q.organ].name;
        let question_start = questions_md.len();
        match q.kind {
            Kind::Name => {
                questions_md.push_str(&format!(
                    "\n## {}. Name structure A{}\n\n![Question {}]({file})\n\n",
                    k + 1,
                    on_slice(&q),
                    k + 1
                ));
                for (c, &o) in q.choices.iter().enumerate() {
                    questions_md.push_str(&format!("- ({}) {}\n", letter(c).to_lowercase(), set.organs[o].name));
                }
                let right = q.choices.iter().position(|&c| c == q.organ).map_or(String::new(), letter);
                answers_md.push_str(&format!("{}. ({}) {answer}\n", k + 1, right.to_lowercase()));
            }
            Kind::Supply => {
                let arteries = set.territories.as_ref().map_or(&[][..], |t| t.arteries.as_slice());
                let artery = |k: usize| arteries.get(k).map_or(String::new(), |a| format!("{} ({})", a.name, a.short));
                let prompt = quiz::supply_prompt(k).replace("the outlined region", "region A");
                questions_md.push_str(&format!("\n## {}. {prompt}\n\n![Question {}]({file})\n\n", k + 1, k + 1));
                for (c, &a) in q.choices.iter().enumerate() {
                    questions_md.push_str(&format!("- ({}) {}\n", letter(c).to_lowercase(), artery(a)));
                }
                let supplier = quiz::supplier(&set, q.organ);
                let right = q.choices.iter().position(|&c| Some(c) == supplier).map_or(String::new(), letter);
                let answer = supplier.map(artery).unwrap_or_default();
                answers_md.push_str(&format!(
                    "{}. ({}) {answer} ({})\n",
                    k + 1,
                    right.to_lowercase(),
                    set.organs[q.organ].name
                ));
            }
            Kind::Locate => {
                let shown: Vec<String> = q
                    .choices
                    .iter()
                    .enumerate()
                    .filter(|(_, o)| placed.iter().any(|p| p.organ == **o))
                    .map(|(c, _)| letter(c))
                    .collect();
                questions_md.push_str(&format!(
                    "\n## {}. Which letter marks the {}{}?\n\n![Question {}]({file})\n\nLetters: {}\n",
                    k + 1,
                    vbrain::quiz::lower_first(answer),
                    on_slice(&q),
                    k + 1,
                    shown.join(", ")
                ));
                let right = q.choices.iter().position(|&c| c == q.organ).map_or(String::new(), letter);
                answers_md.push_str(&format!("{}. {right}: {answer}\n", k + 1));
            }
        }
        // The worksheet page: the question's Markdown less its picture line, which is the figure.
        let added = questions_md[question_start..].to_string();
        let mut lines = added.lines().filter(|l| !l.trim().is_empty());
        let heading = lines.next().unwrap_or_default().trim_start_matches("## ").to_string();
        let text: Vec<&str> = lines.filter(|l| !l.starts_with("![")).collect();
        sheets.push(Sheet { heading, figure: Some(image), text: text.join("\n") });
        let kind = serde_json::to_value(q.kind)?;
        let choices: Vec<&str> = match (q.kind, &set.territories) {
            (Kind::Supply, Some(t)) => {
                q.choices.iter().filter_map(|&c| t.arteries.get(c)).map(|a| a.key.as_str()).collect()
            }
            _ => q.choices.iter().map(|&c| set.organs[c].id.as_str()).collect(),
        };
        let slice = q.slice.map(|p| json!({"plane": p.axis.name(), "at_mm": p.at}));
        listed.push(json!({
            "kind": kind, "organ": set.organs[q.organ].id, "choices": choices, "image": args.out.join(&file),
            "slice": slice,
        }));
    }
    files.push(("questions.md".into(), questions_md.into_bytes()));
    files.push(("answers.md".into(), answers_md.clone().into_bytes()));
    vbrain::atomic::write_folder::<vbrain::Error>(&args.out, |staging| {
        for (name, bytes) in &files {
            vbrain::atomic::write_new(&staging.join(name), |w| w.write_all(bytes))?;
        }
        Ok(())
    })?;
    if let Some(pdf) = &pdf {
        let key = answers_md.lines().filter(|l| l.starts_with(|c: char| c.is_ascii_digit()));
        sheets.push(Sheet {
            heading: "Answer key".into(),
            figure: None,
            text: key.map(|l| format!("- {l}")).collect::<Vec<_>>().join("\n"),
        });
        let task = match args.mode {
            quiz::Mode::Supply => "Give the artery whose territory holds the region marked A.",
            _ => "Name the structure marked A, or give the letter that marks the structure named.",
        };
        let mut subtitle = vec![format!("{} questions. {task}", listed.len())];
        subtitle.extend(crate::handout::attribution(&set));
        let handout = Handout { title: format!("Quiz: {title}"), subtitle, sheets };
        let bytes = crate::handout::pdf(&handout, args.paper)?;
        pdf.write(|w| w.write_all(&bytes))?;
    }
    if args.report.json {
        println!("{}", serde_json::to_string_pretty(&json!({"questions": listed, "note": generated.note}))?);
    } else {
        println!("{} questions written to {}", listed.len(), args.out.display());
    }
    Ok(true)
}

/// " on this coronal slice (y = -10 mm)" for a slice question, else nothing.
fn on_slice(q: &quiz::Question) -> String {
    q.slice.map_or(String::new(), |p| {
        let side = match p.axis {
            vbrain::mri::slice::Axis::Sagittal => "anterior on the left",
            _ => "the patient's right on the left",
        };
        format!(" on this {} slice ({} = {} mm, {side})", p.axis.name(), p.axis.coordinate(), p.at)
    })
}

/// A slice question's picture ([`crate::slice_figure`]): the MRI with every organ shown by default
/// outlined, a name question's structure outlined boldly; a locate question's choices become the
/// structure and the three nearest others on the slice. Returns the picture and its ID buffer.
fn slice_picture(
    set: &vbrain::organ_set::OrganSet,
    q: &mut quiz::Question,
    plane: vbrain::mri::slice::SlicePlane,
    size: [u32; 2],
    seed: u64,
) -> (image::RgbaImage, Vec<u32>) {
    let layout = Layout::new(set);
    let bounds = crate::slice_figure::shown_bounds(set, &layout);
    let pane = vbrain::mri::slice::Pane::fit(plane, &bounds, size[0], size[1], true);
    let options = crate::slice_figure::Options {
        outlines: true,
        labels: Labels::None,
        window: Default::default(),
        letters: true,
        highlight: (q.kind == Kind::Name).then_some(q.organ),
    };
    let (image, ids) = crate::slice_figure::draw(set, &layout, &pane, &options);
    if q.kind == Kind::Locate {
        letters_on_what_shows(set, q, &ids, seed);
    }
    (image, ids)
}

/// A locate question's letters: its structure and the nearest others that the picture's ID
/// buffer `ids` shows, drawn with `seed`.
fn letters_on_what_shows(set: &vbrain::organ_set::OrganSet, q: &mut quiz::Question, ids: &[u32], seed: u64) {
    let mut shown: Vec<usize> = ids.iter().filter(|&&id| id > 0).map(|&id| id as usize - 1).collect();
    shown.sort_unstable();
    shown.dedup();
    let mut rng = vbrain::rng::XorShift::seeded(seed);
    q.choices = quiz::choices(set, q.organ, &shown, &mut rng);
    q.choices.retain(|o| shown.contains(o));
}
