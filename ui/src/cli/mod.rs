//! The headless commands of `vbrain`: their clap definitions here, one file per command with its
//! `run`.
//!
//! - Each prints a human summary, or with `--json` one JSON object on stdout.
//! - Errors go to stderr and make the exit status non-zero: 2 for arguments clap refuses, 1 for
//!   the rest.
//! - Values are checked while parsing ([`values`]); what needs the organ set (organ ids) is
//!   checked once it is open ([`common`]).

mod anki;
mod bench;
mod bench_sections;
mod bench_transparency;
mod city;
pub mod common;
mod export;
mod import;
mod info;
mod lesson;
mod lod;
mod manual;
mod masks;
mod occluders;
pub mod outputs;
mod quiz;
mod render;
mod scale;
mod slice;
mod stand_ins;
pub mod values;
mod video;
pub use lesson::LessonPdfArgs;
pub use video::VideoArgs;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use values::{Orbit, OrganOpacity, RouteFrame, Size};
use vbrain::camera::View;
use vbrain::cull::{CullMode, CullSettings, Selection};
use vbrain::lab::bench::Route;
use vbrain::transparency::TransparencyMode;

#[derive(Parser)]
#[command(name = "vbrain", version = crate::VERSION, about = "Explore the brain as a set of organs: viewer and headless tools")]
pub struct Args {
    /// Organ set folder, .obj/.vbo file or folder of them to open in the viewer (default: organs/brain)
    pub path: Option<PathBuf>,
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Subcommand)]
pub enum Command {
    /// List the organs of a set: triangles per organ and bounds
    Info(InfoArgs),
    /// Render a set to a PNG through the viewer's renderer
    Render(RenderArgs),
    /// Lessons: step-by-step views of a set with captions
    #[command(subcommand)]
    Lesson(LessonCommand),
    /// A quiz worksheet: per question a picture of the structure, questions.md and answers.md
    /// (with --json: {"questions": [{"kind", "organ", "choices", "image"}...]})
    Quiz(QuizArgs),
    /// An Anki deck (.apkg) of the set's structures: per structure and view a "name it" card and
    /// two image-occlusion cards with masks shaped like the structure
    Anki(AnkiArgs),
    /// A video for slides (.gif, .mp4 or .webm): a set or scene turned around (--turntable), or a
    /// lesson played step by step
    Video(VideoArgs),
    /// A slice of the set as radiology shows it: its MRI with each organ's outline in its
    /// colour, side letters and labels, as a PNG (a set without MRI shows its organs filled)
    Slice(slice::SliceArgs),
    /// Turn a label volume (NIfTI) and its label table into an organ set
    Import(ImportArgs),
    /// Benchmark culling: the camera orbits the set; each mode runs over the same frames (writes
    /// bench.csv and bench.png into --out)
    Bench(BenchArgs),
    /// The mask experiment of thesis Figures 19/20: faulty pixels per stacking level per mask method
    /// (writes masks.csv and masks.png into --out)
    Masks(masks::MasksArgs),
    /// Compare the transparency modes against the exact reference on views with 1 to 99
    /// transparent organs; also time mask regeneration at 1920x1080 (writes transparency.csv,
    /// transparency.png and transparency-sheet.png into --out)
    BenchTransparency(bench_transparency::BenchTransparencyArgs),
    /// What sectional anatomy costs: a 512x512 slice pane's redraw, and a frame with the MRI on
    /// its cut faces against one with coloured cut faces
    BenchSections(bench_sections::BenchSectionsArgs),
    /// Minimum occluder sets (thesis §3.2): pre-compute occluders per viewpoint for the set's
    /// layout into occluders.json beside it, or with --experiment compare occluder selections
    /// (writing occluders.csv and occluders.png into --out)
    Occluders(OccludersArgs),
    /// Generate the synthetic city of the occluder experiments (about 300,000 triangles)
    City(CityArgs),
    /// Write a denser copy of a set (each triangle subdivided), for benchmarks
    Scale(ScaleArgs),
    /// Build occluder stand-ins: for each closed organ, a coarse mesh verified to lie inside it,
    /// which occlusion culling rasterises in its place (written as meshes/ID.occluder.vbo); and
    /// for each solid, the faces inside it (meshes/SOLID.hidden.json)
    StandIns(StandInsArgs),
    /// Build each organ's levels of detail (meshes/ID.lod, about a quarter and a sixteenth of its
    /// triangles), which the viewer draws while the view moves
    Lod(lod::LodArgs),
    /// Export a scene, set or lesson as glTF 2.0 (.glb) for Blender, slides and web viewers (the
    /// organs it shows, with names, colours, opacities, transforms, groups and info, cut by its
    /// planes) or as a web page that opens in any browser
    Export(ExportArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish or powershell) to standard output
    Completions(CompletionsArgs),
    /// Write the manual pages (vbrain.1 and one per command) into a folder, for packaging
    #[command(hide = true)]
    Manual(ManualArgs),
}

#[derive(clap::Args)]
pub struct CompletionsArgs {
    /// The shell
    pub shell: clap_complete::Shell,
}

#[derive(clap::Args)]
pub struct ManualArgs {
    /// Output folder (created if missing; existing pages are replaced)
    #[arg(long)]
    pub out: PathBuf,
}

#[derive(clap::Args)]
pub struct InfoArgs {
    /// Organ set (folder, manifest, mesh files) [default: the default brain]
    pub path: Option<PathBuf>,
    #[command(flatten)]
    pub report: Report,
}

/// `--show`, `--hide` and `--opacity`: changes to a set's default layout, by organ id or group
/// ("Frontal lobe" is both frontal lobes, "Left hemisphere/Frontal lobe" one).
/// `--out` and `--force` of the commands that write an organ set.
#[derive(clap::Args, Clone, Debug)]
pub struct SetOut {
    /// Output folder for the organ set
    #[arg(long)]
    pub out: PathBuf,
    /// Write into --out even where it already holds files
    #[arg(long)]
    pub force: bool,
}

/// Where an experiment writes its results (CSV files and plots, named in the command's
/// description), shared by the experiments.
#[derive(clap::Args)]
pub struct ExperimentOut {
    /// Folder for the experiment's results
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Write into --out even where it holds files no vbrain experiment wrote (only the
    /// experiment's own files are replaced)
    #[arg(long)]
    pub force: bool,
}

impl ExperimentOut {
    /// Checks the folder before the experiment runs ([`outputs::experiment_folder`]).
    pub fn check(&self) -> anyhow::Result<()> {
        outputs::experiment_folder(&self.out, self.force)
    }
}

/// `--json`, shared by every command.
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct Report {
    /// Print what the command did as JSON on standard output, instead of lines of text
    #[arg(long)]
    pub json: bool,
}

#[derive(clap::Args)]
pub struct LayoutArgs {
    /// Show organs hidden by default (e.g. skull), by id or group
    #[arg(long, num_args = 1..)]
    pub show: Vec<String>,
    /// Hide organs by id or group (repeatable)
    #[arg(long, num_args = 1..)]
    pub hide: Vec<String>,
    /// Set opacity, ID=A, GROUP=A or all=A with A in 0..1 (repeatable)
    #[arg(long, num_args = 1.., value_parser = values::organ_opacity)]
    pub opacity: Vec<OrganOpacity>,
}

/// `--clip`, `--caps` and `--whole`: a cross-section, each option replacing a scene's own.
#[derive(clap::Args)]
pub struct SectionArgs {
    /// Cut the set: axial=MM, coronal=MM or sagittal=MM remove what lies superior, anterior or right
    /// of that position (world RAS, millimetres; add :flip to keep that side), NX,NY,NZ,D removes
    /// points where n.p > D (repeatable, up to 4)
    #[arg(long, allow_hyphen_values = true, value_parser = values::clip_plane)]
    pub clip: Vec<vbrain::clip::ClipPlane>,
    /// Solid cut faces where a plane cuts a closed organ: on or off [default: the scene's, else on]
    #[arg(long, value_parser = values::on_off)]
    pub caps: Option<bool>,
    /// What solid cut faces show: colour (the organ's), mri (the set's MRI) or tinted (the MRI
    /// tinted by the organ's colour) [default: the scene's, else colour]
    #[arg(long, value_parser = values::cut_face())]
    pub cut_face: Option<vbrain::clip::CutFaceShows>,
    /// The MRI's window and level on cut faces, WINDOW,LEVEL, on its intensities normalised to
    /// 0..1 [default: the scene's, else 0.9,0.6]
    #[arg(long, value_parser = values::window)]
    pub window: Option<vbrain::mri::Window>,
    /// Organs (ids or groups, separated by commas) the clip planes do not cut [default: the
    /// scene's, else none]
    #[arg(long, value_delimiter = ',')]
    pub whole: Vec<String>,
}

#[derive(clap::Args)]
#[group(id = "camera", multiple = false)]
pub struct CameraArgs {
    /// Standard view (any case)
    #[arg(long, ignore_case = true, value_parser = values::view())]
    pub view: Option<View>,
    /// Orbit AZ,EL in degrees from the anterior view (azimuth toward the right, elevation upward)
    #[arg(long, allow_hyphen_values = true, value_parser = values::orbit)]
    pub orbit: Option<Orbit>,
    /// Camera of a bench route instead, ROUTE:FRAME of 120 (e.g. best:0; routes: orbit, best,
    /// average, worst)
    #[arg(long, value_parser = values::route_frame)]
    pub route: Option<RouteFrame>,
}

#[derive(Subcommand)]
pub enum LessonCommand {
    /// Write one PNG per step (DIR/01.png, ...) and DIR/lesson.md with the captions and images
    Render(LessonRenderArgs),
    /// Write a PDF handout: a title page, then a page per step with its figure, title and caption
    Pdf(LessonPdfArgs),
}

#[derive(clap::Args)]
pub struct QuizArgs {
    /// Organ set [default: the default brain]
    pub set: Option<PathBuf>,
    /// Only this group's organs (an id or a group path such as "Basal ganglia")
    #[arg(long)]
    pub group: Option<String>,
    /// Questions, 1..=200 (at most one per structure in scope)
    #[arg(long, default_value_t = 10, value_parser = count(1, 200))]
    pub questions: usize,
    /// Seed: the same seed gives the same quiz
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// locate (which letter is it?), name (what is A?), mixed, mri (both by turns, each on an
    /// MRI slice through the structure with outlines), or supply (which artery supplies region A?
    /// for sets with arterial territories)
    #[arg(long, default_value = "mixed", value_parser = values::quiz_mode)]
    pub mode: vbrain::quiz::Mode,
    /// Output folder
    #[arg(long)]
    pub out: PathBuf,
    /// Image size, WxH
    #[arg(long, default_value = "1024x768", value_parser = values::size)]
    pub size: Size,
    /// Also write the worksheet as a PDF, a page per question, then the answer key on its own page
    #[arg(long)]
    pub pdf: Option<PathBuf>,
    /// The PDF's paper size
    #[arg(long, value_enum, default_value = "a4")]
    pub paper: crate::handout::Paper,
    /// Replace --out's folder whole even where it already holds files, and --pdf if it exists
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
pub struct AnkiArgs {
    /// An organ set (its structures), a scene (.vbscene: those it shows), or a lesson (.vblesson
    /// or the name of one of the default brain's lessons: those its steps highlight, and its
    /// quiz's questions) [default: the default brain]
    pub set: Option<PathBuf>,
    /// Only this group's organs (an id or a group path such as "Basal ganglia")
    #[arg(long)]
    pub group: Option<String>,
    /// Views per structure (its best: where most of it shows), 1..=4
    #[arg(long, default_value_t = 2, value_parser = count(1, 4))]
    pub views: usize,
    /// The deck file to write (.apkg)
    #[arg(long)]
    pub out: PathBuf,
    /// Replace --out if it exists
    #[arg(long)]
    pub force: bool,
    /// Card picture size, WxH
    #[arg(long, default_value = "768x768", value_parser = values::size)]
    pub size: Size,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
pub struct LessonRenderArgs {
    /// Lesson file (.vblesson), or the name of one of the default brain's lessons (cortex,
    /// deep-nuclei, ventricles)
    pub lesson: PathBuf,
    /// Output folder
    #[arg(long)]
    pub out: PathBuf,
    /// Image size, WxH (with --caption, the caption's band included)
    #[arg(long, default_value = "1024x768", value_parser = values::size)]
    pub size: Size,
    /// Labels in every picture instead of each step's own: none, selected (the organs a step
    /// highlights), all (every organ seen) or ids and groups separated by commas
    #[arg(long)]
    pub labels: Option<String>,
    /// Put each step's title and caption in its picture, in a band below the figure
    #[arg(long)]
    pub caption: bool,
    /// Replace --out's folder whole even where it already holds files
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub report: Report,
}

/// The picture a command writes: its PNG file and its size.
#[derive(clap::Args)]
pub struct PictureArgs {
    /// Output PNG file
    #[arg(long)]
    pub out: PathBuf,
    /// Replace --out even where it is not a PNG image
    #[arg(long)]
    pub force: bool,
    /// Image size, WxH (a slice figure: at most 4096x4096)
    #[arg(long, default_value = "1024x1024", value_parser = values::size)]
    pub size: Size,
}

#[derive(clap::Args)]
pub struct RenderArgs {
    /// Organ set (default: the set of --scene)
    pub path: Option<PathBuf>,
    #[command(flatten)]
    pub picture: PictureArgs,
    /// Render a saved scene (.vbscene): its set, camera, organs and render settings; the other
    /// options given override it
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Write the scene this renders (set, camera, organs, render settings) to this file
    #[arg(long)]
    pub save_scene: Option<PathBuf>,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub layout: LayoutArgs,
    /// Outline organs by id or group, seen through what is in front (as a lesson step highlights)
    #[arg(long, num_args = 1..)]
    pub highlight: Vec<String>,
    #[command(flatten)]
    pub section: SectionArgs,
    /// Name organs with leader-line labels beside the brain: none, selected (a scene's selection),
    /// all (every organ seen) or ID,ID,... (ids or groups) [default: the scene's, else none]
    #[arg(long)]
    pub labels: Option<String>,
    /// What colours the organs: organ (their own colours), lobe, or territory (the set's arterial
    /// territories, per vertex) [default: the scene's, else organ]
    #[arg(long, value_parser = values::colour_by())]
    pub colour_by: Option<vbrain::layout::ColourBy>,
    /// Transparent background instead of the viewer's dark grey
    #[arg(long)]
    pub transparent: bool,
    /// Culling (the image is the same; only the work differs) [default: occlusion]
    #[arg(long, value_parser = values::cull_mode())]
    pub cull: Option<CullMode>,
    /// Show what culling removed in colour through a translucent grey model (thesis Figure 21)
    #[arg(long)]
    pub debug_culled: bool,
    /// Draw each organ at its level of detail K, 0..=2 (as the viewer's moving frames do), where
    /// that level has fewer triangles than culling keeps of it; 0 is the full meshes
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u8).range(0..=2))]
    pub lod: u8,
    /// Transparency: how faded organs are drawn [default: screendoor]
    #[arg(long, value_parser = values::transparency_mode())]
    pub transparency: Option<TransparencyMode>,
    /// Screen-door sub-samples per pixel: 4, 8, 16, 32 or 64 [default: 64]
    #[arg(long, value_parser = values::subsamples)]
    pub subsamples: Option<usize>,
    /// Screen-door mask region side in pixels, 4..=256 [default: 32]
    #[arg(long, value_parser = region())]
    pub region: Option<u32>,
    /// Most nearest organs whose depth order the masks' error compensation follows (no more than
    /// log2(sub-samples) - 1 are), 1..=64 [default: 8]
    #[arg(long, value_parser = k())]
    pub k: Option<usize>,
    /// The k-buffer's fragments kept per pixel (`--transparency kbuffer`), 2..=8 [default: 8]
    #[arg(long, value_parser = kbuffer_k())]
    pub kbuffer: Option<usize>,
    /// Most layers `peel` and `dual-peel` peel, 1..=64 [default: 8]
    #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=vbrain::transparency::MAX_PEEL_LAYERS as u64))]
    pub layers: Option<usize>,
    /// Draw the organs in an order shuffled by this seed (screen-door gives the same image)
    #[arg(long)]
    pub draw_order_seed: Option<u64>,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
pub struct ImportArgs {
    /// Label volume, .nii or .nii.gz
    pub volume: PathBuf,
    /// Label table: CSV `index,name` or a FreeSurfer colour look-up table
    #[arg(long)]
    pub labels: PathBuf,
    #[command(flatten)]
    pub out: SetOut,
    /// Triangle budget for the whole set, 100..=20000000
    #[arg(long, default_value_t = 200_000, value_parser = count(100, 20_000_000))]
    pub triangles: usize,
    /// Smoothing iterations (Taubin), 0..=1000
    #[arg(long, default_value_t = 10, value_parser = count(0, 1000))]
    pub smooth: usize,
    /// Title of the new set (default: the volume's file name)
    #[arg(long)]
    pub title: Option<String>,
    /// Neighbouring organs share their boundary surfaces (one multi-label surface net, smoothed
    /// and decimated as one), so no gap or sliver shows between them
    #[arg(long)]
    pub seamless: bool,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
pub struct BenchArgs {
    pub path: PathBuf,
    /// Frames of the orbit (the thesis: 475), 1..=100000
    #[arg(long, default_value_t = 475, value_parser = count(1, 100_000))]
    pub frames: usize,
    /// Image size, WxH
    #[arg(long, default_value = "512x512", value_parser = values::size)]
    pub size: Size,
    /// Culling modes to compare, comma-separated
    #[arg(long, default_value = "none,frustum,occlusion", value_delimiter = ',', action = clap::ArgAction::Set,
          value_parser = values::cull_mode_in_list())]
    pub cull: Vec<CullMode>,
    #[command(flatten)]
    pub layout: LayoutArgs,
    /// Occluder triangle budget per frame (triangles facing the eye), 1..=10000000
    #[arg(long, default_value_t = CullSettings::default().occluder_triangles, value_parser = count(1, 10_000_000))]
    pub occluder_triangles: usize,
    /// Culling raster size, WxH, each side 16..=2048
    #[arg(long, default_value = "128x128", value_parser = values::raster_size)]
    pub raster: Size,
    /// Camera path: orbit (the Virtual Brain run) or a city walkthrough route: best, average, worst
    #[arg(long, default_value = "orbit", value_parser = values::route())]
    pub route: Route,
    /// Occluder selection: auto (pre-computed sets while the layout is unchanged), projected-size
    /// (or ps) or mos
    #[arg(long, default_value = "auto", value_parser = values::selection())]
    pub selection: Selection,
    /// Most occluder leaves per frame (the thesis's city runs: 64), 1..=1048576
    #[arg(long, value_parser = count(1, 1 << 20))]
    pub occluders: Option<usize>,
    /// Transparency: how faded organs are drawn [default: screendoor]
    #[arg(long, value_parser = values::transparency_mode())]
    pub transparency: Option<TransparencyMode>,
    /// Screen-door sub-samples per pixel of every frame: 4, 8, 16, 32 or 64 (4 per pass)
    /// [default: 64]
    #[arg(long, value_parser = values::subsamples)]
    pub subsamples: Option<usize>,
    /// The k-buffer's fragments kept per pixel (`--transparency kbuffer`), 2..=8 [default: 8]
    #[arg(long, value_parser = kbuffer_k())]
    pub kbuffer: Option<usize>,
    /// Cut the set, as `render --clip` does (with solid cut faces; repeatable, up to 4)
    #[arg(long, allow_hyphen_values = true, value_parser = values::clip_plane)]
    pub clip: Vec<vbrain::clip::ClipPlane>,
    /// Level of detail instead of culling: time moving frames at full detail, with each organ's
    /// level from its projected size (area), with every organ at level 1 or 2, at each smaller
    /// render scale the viewer uses, and as the viewer chooses (auto), each with its error
    #[arg(long)]
    pub lod: bool,
    #[command(flatten)]
    pub results: ExperimentOut,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
pub struct OccludersArgs {
    pub path: PathBuf,
    /// Directions of the viewpoint grid on a sphere around the set (each at two distances),
    /// 1..=4096
    #[arg(long, default_value_t = 32, value_parser = count(1, 4096))]
    pub grid: usize,
    /// Most occluders kept per viewpoint, 1..=4096
    #[arg(long, default_value_t = 128, value_parser = count(1, 4096))]
    pub limit: usize,
    /// Culling raster side, pixels, 16..=2048
    #[arg(long, default_value_t = 128, value_parser = count(16, 2048))]
    pub raster: usize,
    /// Show organs hidden by default (e.g. skull), by id or group
    #[arg(long, num_args = 1..)]
    pub show: Vec<String>,
    /// Hide organs by id or group
    #[arg(long, num_args = 1..)]
    pub hide: Vec<String>,
    /// Run the occluder-selection experiment (thesis Figure 14) instead: culled % against the
    /// number of occluders for projected size, first hit and minimum occluder sets
    #[arg(long)]
    pub experiment: bool,
    /// Experiment viewpoints: orbit (four views around the set) or frames of a city route (best,
    /// average, worst)
    #[arg(long, default_value = "orbit", value_parser = values::route())]
    pub views: Route,
    /// Experiment ID-render size (square), for first hit and projected size, 16..=4096
    #[arg(long, default_value_t = 512, value_parser = count(16, 4096))]
    pub image: usize,
    #[command(flatten)]
    pub results: ExperimentOut,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
pub struct CityArgs {
    #[command(flatten)]
    pub out: SetOut,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
pub struct ScaleArgs {
    pub set: PathBuf,
    /// Density factor K, 1..=10000: each triangle becomes n*n with n = round(sqrt(K)); a factor
    /// whose copy would not fit in memory is refused before any work
    #[arg(long, value_parser = values::float_in(1.0, 10_000.0))]
    pub factor: f64,
    #[command(flatten)]
    pub out: SetOut,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
#[command(group(clap::ArgGroup::new("output").required(true).multiple(true).args(["gltf", "web", "scorm"])))]
pub struct ExportArgs {
    /// A scene (.vbscene), a lesson (.vblesson) or an organ set (folder, manifest, mesh files)
    /// [default: the default brain]
    pub path: Option<PathBuf>,
    /// The binary glTF file to write (a lesson's first step)
    #[arg(long)]
    pub gltf: Option<PathBuf>,
    /// A folder for a web page that opens in any browser, from a file or a server: index.html,
    /// the model and the vendored three.js (a lesson's page has its steps)
    #[arg(long)]
    pub web: Option<PathBuf>,
    /// A SCORM 1.2 package (.zip) of the page and its quiz, for a course's learning platform
    /// (Moodle, Canvas, Blackboard): the page reports the score and passed or failed
    #[arg(long)]
    pub scorm: Option<PathBuf>,
    /// Ask a quiz of this many questions in the page (a set or scene; a lesson asks its own),
    /// 1..=100
    #[arg(long, value_parser = count(1, 100))]
    pub quiz: Option<usize>,
    /// The seed of --quiz's questions
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The share of the quiz that passes, in per cent, 0..=100 [default: the lesson's, else 70]
    #[arg(long, value_parser = values::f32_in(0.0, 100.0))]
    pub pass_mark: Option<f32>,
    /// Replace --gltf or --scorm where it exists, or write into --web where it holds files
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub layout: LayoutArgs,
    /// What colours the organs: organ, lobe, or territory (vertex colours in the model)
    /// [default: the scene's, else organ]
    #[arg(long, value_parser = values::colour_by())]
    pub colour_by: Option<vbrain::layout::ColourBy>,
    #[command(flatten)]
    pub section: SectionArgs,
    #[command(flatten)]
    pub report: Report,
}

#[derive(clap::Args)]
pub struct StandInsArgs {
    pub path: PathBuf,
    /// Stand-in triangles as a share of the organ's, 0.001..=1
    #[arg(long, default_value_t = 0.0625, value_parser = values::float_in(0.001, 1.0))]
    pub ratio: f64,
    /// Most inward offset of the stand-in from the surface, millimetres, 0.01..=50
    #[arg(long, default_value_t = 2.0, value_parser = values::f32_in(0.01, 50.0))]
    pub offset: f32,
    /// Organs with fewer triangles get none, 4..=100000000
    #[arg(long, default_value_t = 2048, value_parser = count(4, 100_000_000))]
    pub min_triangles: usize,
    /// Triangles of each solid's stand-in (a solid: organs the manifest lists as filling one),
    /// 4..=1000000
    #[arg(long, default_value_t = 4096, value_parser = count(4, 1_000_000))]
    pub solid_triangles: usize,
    /// Most inward offset of a solid's stand-in, millimetres (deeper than an organ's: a solid's
    /// folded surface simplifies with fewer triangles left out there), 0.01..=50
    #[arg(long, default_value_t = 4.0, value_parser = values::f32_in(0.01, 50.0))]
    pub solid_offset: f32,
    /// Solids (by id) whose faces inside are not kept, so culling draws them; the default brain
    /// leaves out `brain` (see its README)
    #[arg(long, num_args = 1..)]
    pub no_faces_inside: Vec<String>,
    /// Output folder (default: the set's own folder)
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write into --out even where it already holds files
    #[arg(long)]
    pub force: bool,
    #[command(flatten)]
    pub report: Report,
}

/// A screen-door mask region side in pixels, in [`vbrain::transparency::REGION_PX`].
fn region() -> clap::builder::RangedU64ValueParser<u32> {
    let r = vbrain::transparency::REGION_PX;
    clap::builder::RangedU64ValueParser::new().range(u64::from(*r.start())..=u64::from(*r.end()))
}

/// K, the nearest organs error compensation favours, in [`vbrain::transparency::K_RANGE`].
fn k() -> clap::builder::RangedU64ValueParser<usize> {
    let r = vbrain::transparency::K_RANGE;
    count(*r.start() as u64, *r.end() as u64)
}

/// The k-buffer's slots per pixel, in [`vbrain::transparency::KBUFFER_K`].
fn kbuffer_k() -> clap::builder::RangedU64ValueParser<usize> {
    let r = vbrain::transparency::KBUFFER_K;
    count(*r.start() as u64, *r.end() as u64)
}

/// A count a user types, in `lo..=hi` (each option's help states its bounds).
fn count(lo: u64, hi: u64) -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(lo..=hi)
}

/// Runs one command and gives the exit status.
pub fn run(command: Command) -> std::process::ExitCode {
    match run_command(command) {
        Ok(true) => std::process::ExitCode::SUCCESS,
        Ok(false) => std::process::ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

/// Runs one command; `Ok(false)` means it finished but reported errors (e.g. broken organs).
fn run_command(command: Command) -> anyhow::Result<bool> {
    match command {
        Command::Info(args) => info::run(&args),
        Command::Render(args) => render::run(&args),
        Command::Slice(args) => slice::run(&args),
        Command::Lesson(LessonCommand::Render(args)) => lesson::render(&args),
        Command::Lesson(LessonCommand::Pdf(args)) => lesson::pdf(&args),
        Command::Quiz(args) => quiz::run(&args),
        Command::Anki(args) => anki::run(&args),
        Command::Video(args) => video::run(&args),
        Command::Import(args) => import::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Masks(args) => masks::run(&args),
        Command::BenchTransparency(args) => bench_transparency::run(&args),
        Command::BenchSections(args) => bench_sections::run(&args),
        Command::Occluders(args) => occluders::run(&args),
        Command::City(args) => city::run(&args),
        Command::Scale(args) => scale::run(&args),
        Command::StandIns(args) => stand_ins::run(&args),
        Command::Lod(args) => lod::run(&args),
        Command::Export(args) => export::run(&args),
        Command::Completions(args) => manual::completions(&args),
        Command::Manual(args) => manual::pages(&args),
    }
}
