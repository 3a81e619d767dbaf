//! Errors of the core.
//!
//! - Every error that comes from a file names the file, and the line where there is one.
//! - The GPU's failures are errors too (no adapter, no device, out of memory, a target or buffer
//!   too large).

use std::path::PathBuf;

/// An error of the core: reading or writing one file, or the GPU.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("{}{}: {message}", path.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Parse { path: PathBuf, line: Option<usize>, message: String },
    /// The OS error is part of the message and deliberately not a `source`, so that a chain of
    /// causes (`{:#}`) prints it once.
    #[error("{}: {error}", path.display())]
    Io { path: PathBuf, error: std::io::Error },
    #[error("{}: cannot encode: {message}", path.display())]
    Encode { path: PathBuf, message: String },
    #[error("{}: not a file name", path.display())]
    NotAFileName { path: PathBuf },
    #[error("{}: {problem}", path.display())]
    OccluderDb { path: PathBuf, problem: DbProblem },
    #[error("no label of the table occurs in the volume")]
    NoLabels,
    #[error("{}: the organ loader panicked", path.display())]
    LoaderPanicked { path: PathBuf },
    /// No GPU adapter could be opened; `tried` says what was tried and how it failed.
    #[error("{help} ({tried})", help = NO_ADAPTER_HELP)]
    NoAdapter { tried: String },
    #[error("could not open the GPU device of {adapter}: {message}")]
    Device { adapter: String, message: String },
    /// A wgpu operation (poll, buffer mapping, read-back) failed.
    #[error("GPU {operation}: {message}")]
    Gpu { operation: &'static str, message: String },
    #[error("{what}: out of GPU memory; choose a smaller image size")]
    GpuMemory { what: &'static str },
    #[error(
        "image size {width}x{height} needs about {:.1} GiB of render targets, more than the {:.1} GiB \
         this GPU can give; choose a smaller size",
        *bytes as f64 / (1u64 << 30) as f64,
        *budget as f64 / (1u64 << 30) as f64
    )]
    TargetMemory { width: u32, height: u32, bytes: u64, budget: u64 },
    #[error("image size {width}x{height} outside 1..={max} pixels per side")]
    ImageSize { width: u32, height: u32, max: u32 },
    #[error("organ \"{organ}\" needs a {bytes}-byte buffer; this GPU allows {max}")]
    BufferTooLarge { organ: String, bytes: u64, max: u64 },
}

impl Error {
    pub fn parse(path: impl Into<PathBuf>, line: Option<usize>, message: impl Into<String>) -> Self {
        Error::Parse { path: path.into(), line, message: message.into() }
    }

    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Error::Io { path: path.into(), error: source }
    }

    pub(crate) fn gpu(operation: &'static str, message: impl std::fmt::Display) -> Self {
        Error::Gpu { operation, message: message.to_string() }
    }
}

/// What to install when no adapter is found.
pub const NO_ADAPTER_HELP: &str = "no GPU adapter found (Vulkan, Metal, DX12 or OpenGL). On a machine without a GPU, \
install Mesa's software Vulkan driver (lavapipe): on Debian or Ubuntu `apt-get install mesa-vulkan-drivers`";

/// Why an occluder database beside a set is not used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum DbProblem {
    #[error("version {found} (this vbrain reads {reads}); run `vbrain occluders` again")]
    Version { found: u32, reads: u32 },
    #[error("stale (the organs changed since it was made); run `vbrain occluders` again")]
    Stale,
    #[error("names leaves the set does not have")]
    UnknownLeaves,
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
