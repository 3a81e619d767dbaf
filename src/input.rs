//! Reading the user's files with limits checked at the door.
//!
//! - Every file vbrain reads goes through [`read`] (or [`check_file`] where a library reads it).
//! - Refused before reading a byte: what is not a regular file (a folder, a FIFO, a device) and
//!   what is larger than the limit of its kind.
//! - [`inside`] refuses a path of a set that leaves the set's folder by any means (`..`, an
//!   absolute path or a symbolic link).
//! - What reading an input will take in memory is estimated first and compared with
//!   [`available_memory`] (refused above 80 % of it) by the readers that can tell.

use crate::error::{Error, Result};
use std::io::Read;
use std::path::{Path, PathBuf};

/// The kinds of file vbrain reads, each with its largest size in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// An `.obj` or `.vbo` mesh: 1 GiB.
    Mesh,
    /// `organset.json` or `occluders.json`: 64 MiB.
    Manifest,
    /// A scene (`.vbscene`) or lesson (`.vblesson`): 16 MiB.
    Document,
    /// A label table (CSV or FreeSurfer LUT): 16 MiB.
    LabelTable,
    /// A NIfTI label volume, `.nii` or `.nii.gz`: 4 GiB.
    Volume,
}

impl Kind {
    /// The largest file of this kind vbrain reads, in bytes.
    pub fn limit(self) -> u64 {
        match self {
            Kind::Mesh => 1 << 30,
            Kind::Manifest => 64 << 20,
            Kind::Document | Kind::LabelTable => 16 << 20,
            Kind::Volume => 4 << 30,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Kind::Mesh => "mesh",
            Kind::Manifest => "manifest",
            Kind::Document => "scene or lesson",
            Kind::LabelTable => "label table",
            Kind::Volume => "label volume",
        }
    }
}

/// Checks that `path` is a regular file (following symbolic links) no larger than `kind`'s limit;
/// gives its size.
pub fn check_file(path: &Path, kind: Kind) -> Result<u64> {
    let meta = std::fs::metadata(path).map_err(|e| match path.symlink_metadata() {
        Ok(link) if link.file_type().is_symlink() && e.kind() == std::io::ErrorKind::NotFound => {
            Error::parse(path, None, "is a link to nothing (its target does not exist)")
        }
        _ => Error::io(path, e),
    })?;
    if meta.is_dir() {
        return Err(Error::parse(path, None, format!("is a folder, not a {} file", kind.name())));
    }
    if !meta.is_file() {
        return Err(Error::parse(
            path,
            None,
            format!("is not a regular file (a device or pipe?); a {} must be", kind.name()),
        ));
    }
    if meta.len() > kind.limit() {
        return Err(Error::parse(
            path,
            None,
            format!("{} bytes is larger than a {} vbrain reads ({} MiB)", meta.len(), kind.name(), kind.limit() >> 20),
        ));
    }
    Ok(meta.len())
}

/// Reads a file of `kind` whole, after [`check_file`]. A file that grows past the limit while it
/// is read is refused too.
pub fn read(path: &Path, kind: Kind) -> Result<Vec<u8>> {
    let len = check_file(path, kind)?;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(kind.limit() + 1).read_to_end(&mut bytes).map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > kind.limit() {
        return Err(Error::parse(
            path,
            None,
            format!("grew past the {} MiB limit while being read", kind.limit() >> 20),
        ));
    }
    Ok(bytes)
}

/// Reads a UTF-8 text file of `kind`, without a leading byte-order mark.
pub fn read_text(path: &Path, kind: Kind) -> Result<String> {
    let text = String::from_utf8(read(path, kind)?).map_err(|e| {
        let line = 1 + e.as_bytes()[..e.utf8_error().valid_up_to()].iter().filter(|&&b| b == b'\n').count();
        Error::parse(path, Some(line), format!("not UTF-8 text (a {} is)", kind.name()))
    })?;
    // A byte-order mark (as some editors on Windows write) is not part of the text.
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_string(),
        None => text,
    })
}

/// `dir.join(relative)`, refused where it resolves (through `..` or symbolic links) outside `dir`.
/// `relative` must already have passed the manifest's textual check; this catches links.
pub fn inside(dir: &Path, relative: &str) -> Result<PathBuf> {
    let path = dir.join(relative);
    let root = dir.canonicalize().map_err(|e| Error::io(dir, e))?;
    // A file that does not exist cannot lead outside; its read reports it.
    match path.canonicalize() {
        Ok(real) if !real.starts_with(&root) => Err(Error::parse(
            &path,
            None,
            format!("leads outside the set's folder (to {}); a set's files must lie inside it", real.display()),
        )),
        _ => Ok(path),
    }
}

/// The memory the system can give this process now (Linux's `MemAvailable`), where it says.
pub fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Refuses work on `path` that would take about `bytes` of memory where more than 80 % of the
/// available memory would go to it (where the system says what is available).
pub fn fits_in_memory(path: &Path, bytes: u64, what: &str) -> Result<()> {
    match available_memory() {
        Some(available) if bytes > available / 10 * 8 => Err(Error::parse(
            path,
            None,
            format!(
                "{what} would take about {:.1} GiB of memory and {:.1} GiB is available",
                bytes as f64 / (1u64 << 30) as f64,
                available as f64 / (1u64 << 30) as f64
            ),
        )),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_beyond_the_available_memory_is_refused_with_its_file() {
        let Some(available) = available_memory() else { return };
        let path = Path::new("huge.obj");
        assert!(fits_in_memory(path, available / 2, "reading it").is_ok());
        let e = fits_in_memory(path, available, "reading its triangles").unwrap_err().to_string();
        assert!(e.contains("huge.obj") && e.contains("GiB"), "{e}");
    }

    #[test]
    fn refuses_folders_pipes_large_files_and_links_outside() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        assert!(read(d, Kind::Mesh).unwrap_err().to_string().contains("is a folder"));
        std::fs::write(d.join("a.obj"), "v 0 0 0\n").unwrap();
        assert_eq!(read(&d.join("a.obj"), Kind::Mesh).unwrap(), b"v 0 0 0\n");
        assert!(read(Path::new("/dev/null"), Kind::Mesh).unwrap_err().to_string().contains("not a regular file"));
        let big = std::fs::File::create(d.join("big.csv")).unwrap();
        big.set_len(Kind::LabelTable.limit() + 1).unwrap();
        assert!(read(&d.join("big.csv"), Kind::LabelTable).unwrap_err().to_string().contains("larger than"));
        std::fs::write(d.join("bad.txt"), b"ok\n\xff").unwrap();
        let e = read_text(&d.join("bad.txt"), Kind::Document).unwrap_err().to_string();
        assert!(e.contains("bad.txt:2") && e.contains("UTF-8"), "{e}");

        let set = d.join("set");
        std::fs::create_dir(&set).unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink(d.join("a.obj"), set.join("out.obj")).unwrap();
        std::fs::write(set.join("in.obj"), "").unwrap();
        assert!(inside(&set, "in.obj").is_ok());
        assert!(inside(&set, "missing.obj").is_ok());
        #[cfg(unix)]
        assert!(inside(&set, "out.obj").unwrap_err().to_string().contains("outside the set's folder"));
    }
}
