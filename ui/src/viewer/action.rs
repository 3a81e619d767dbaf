//! What the viewer's components ask for.
//!
//! - A component reads the scene and returns actions: scene changes as [`Edit`]s, everything else
//!   (open, import, export, camera, selection, windows, notifications) as commands.
//! - [`crate::viewer::App::perform`] carries them out in order, in one place.

use glam::Vec3;
use std::path::PathBuf;
use vbrain::camera::View;
use vbrain::edit::Edit;
use vbrain::lesson::LessonEdit;

#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Change the layout (one undoable step; while a pointer button is down, edits of one slider
    /// or drag merge into one).
    Edit(Edit),
    Undo,
    Redo,
    /// The scene file.
    Document(DocumentAction),
    /// The lesson: opening, following and authoring it.
    Lesson(LessonAction),
    /// The quiz under way, or its setup.
    Quiz(QuizAction),
    /// The cross-section: planes, the slice panes' crosshair, organs kept whole.
    Section(SectionAction),
    Select(Option<usize>),
    /// A click in the view on this organ (or nothing): selects it, or answers a quiz's question.
    Pick(Option<usize>),
    /// The arterial territory at the point a click picked (it follows its [`Action::Pick`]).
    Supply(Option<u8>),
    /// Label an organ or not (the chosen-labels mode).
    Label {
        organ: usize,
        on: bool,
    },
    /// Open a set (one folder or file), a scene file (`.vbscene`, then its set) or several mesh
    /// files, off the UI thread.
    Open(Vec<PathBuf>),
    /// Open a window.
    Show(Window),
    /// Open the import window on this label volume.
    ImportVolume(PathBuf),
    /// Import a label volume into an organ set, off the UI thread, then open it.
    Import(ImportRequest),
    /// Render the current view at `size` into the file `path` (as typed: `.png` added if missing).
    Export {
        path: String,
        size: [u32; 2],
    },
    /// Write the scene as a glTF model into the file `path` (as typed: `.glb` added if missing),
    /// or as a web page into the folder `path`: of the current view, or with `lesson` of the open
    /// lesson, its steps and captions.
    ExportModel {
        kind: ModelKind,
        path: String,
        lesson: bool,
    },
    /// Stop the export running in the background; it leaves no file.
    CancelJob,
    /// Camera to a standard view of the set.
    View(View),
    ResetCamera,
    /// Walk-through camera on or off.
    ToggleFly,
    /// Camera framing one organ.
    Frame(usize),
    Notify {
        text: String,
        error: bool,
    },
    /// An error notification, unless the same text is shown already (for problems that repeat
    /// every frame).
    NotifyOnce(String),
    /// Dismiss one notification, or all with `None`.
    Dismiss(Option<usize>),
    Quit,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Window {
    OpenSet,
    OpenMeshes,
    Import,
    Export,
    ExportModel(ModelKind),
    Sections,
    Quiz,
    About,
}

/// What a model export writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModelKind {
    /// A binary glTF file.
    Gltf,
    /// A folder with a web page that opens in any browser.
    Web,
    /// An Anki deck (.apkg) of the structures shown.
    Anki,
    /// A SCORM 1.2 package (.zip) of the open lesson's page, asking its quiz.
    Scorm,
    /// A video (.mp4, .webm or .gif): the view turned around, or the open lesson played.
    Video,
    /// A PDF handout: the view with its labels, or the open lesson's steps.
    Pdf,
}

/// A label volume to import, with its label table, output folder and triangle budget.
#[derive(Clone, Debug, PartialEq)]
pub struct ImportRequest {
    pub volume: PathBuf,
    pub labels: PathBuf,
    pub out: PathBuf,
    pub triangles: usize,
}

/// What the scene file's component asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum DocumentAction {
    /// Save the scene: to its file, or (`as_new`, or none yet) ask where.
    Save { as_new: bool },
    /// Save the scene to this file (`.vbscene`).
    SaveTo(PathBuf),
}

/// What the lesson panel and the lesson shortcuts ask for.
#[derive(Clone, Debug, PartialEq)]
pub enum LessonAction {
    /// Open a lesson (`.vblesson`) at its first step.
    Open(PathBuf),
    /// Show step k (0-based) of the open lesson.
    Step(usize),
    /// Close the lesson (asking first if it has unsaved changes).
    Close,
    /// A new lesson over the open set, its first step the current view.
    New,
    /// Change the lesson (one undoable step).
    Edit(LessonEdit),
    /// A step from the current view after the current one, or (`replace`) into the current one.
    AddStep { replace: bool },
    /// Save the lesson: to its file, or (`as_new`, or a new lesson) ask where.
    Save { as_new: bool },
    /// Save the lesson to this file (`.vblesson`).
    SaveTo(PathBuf),
}

/// What the Quiz panel asks for.
#[derive(Clone, Debug, PartialEq)]
pub enum QuizAction {
    /// Start a quiz as the Quiz panel sets it up.
    Start,
    /// Start the open lesson's quiz.
    Lesson,
    /// Answer a name question with typed text.
    Answer(String),
    /// Answer a name question with one of its choices (an organ).
    Pick(usize),
    /// The next question (or the review after the last).
    Next,
    /// Fly to a missed question's structure, labelled.
    Review(usize),
    /// Write the quiz's answers as CSV to this file.
    Export(String),
    /// Back to the quiz setup.
    Again,
    /// Leave the quiz.
    Close,
}

/// What the Sections panel, the plane handles and the slice panes ask for.
#[derive(Clone, Debug, PartialEq)]
pub enum SectionAction {
    /// Keep an organ whole where clip planes cut (or cut it again).
    KeepWhole { organ: usize, whole: bool },
    /// Move the slice panes' crosshair to this point (world millimetres); the section planes that
    /// are on follow it.
    SlicePoint(glam::Vec3),
    /// Move a clip plane of the Sections window (its slot) along its normal, millimetres.
    MovePlane { slot: usize, mm: f32 },
}

/// Which control: 0 axial, 1 coronal, 2 sagittal, 3 oblique.
pub type Slot = usize;

/// Where a plane's handle sits (world millimetres) and which way it moves the plane.
/// (The Sections panel makes them; the viewport draws and drags them.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Handle {
    pub slot: Slot,
    pub at: Vec3,
    /// Unit normal: dragging along it moves the plane to larger positions.
    pub normal: Vec3,
}
