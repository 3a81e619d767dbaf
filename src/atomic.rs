//! Atomic file writes: write a temporary file beside the target, flush it to disk, then rename it.
//! A crash or a full disk leaves either the old file or the new one, never half of one.

use crate::error::{Error, Result};
use std::io::Write;
use std::path::Path;

/// Writes `path` atomically with what `fill` writes, replacing any existing file.
pub fn write(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    write_impl(path, fill, true)
}

/// Writes `path` atomically, failing if it already exists (never silently overwrites).
pub fn write_new(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    write_impl(path, fill, false)
}

fn write_impl(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>, replace: bool) -> Result<()> {
    let io = |e| Error::io(path, e);
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path.file_name().ok_or_else(|| Error::NotAFileName { path: path.to_path_buf() })?;
    let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        if replace {
            std::fs::rename(&tmp, path)
        } else {
            // hard_link fails if the target exists, which makes the no-overwrite check race-free.
            std::fs::hard_link(&tmp, path).and_then(|()| std::fs::remove_file(&tmp))
        }
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io)
}

/// Writes `image` as a PNG file, atomically; with `replace` false an existing file is refused.
pub fn write_png(path: &Path, image: &image::RgbaImage, replace: bool) -> Result<()> {
    let mut bytes = Vec::new();
    image
        .write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| Error::Encode { path: path.to_path_buf(), message: e.to_string() })?;
    let fill = |w: &mut dyn Write| w.write_all(&bytes);
    if replace {
        write(path, fill)
    } else {
        write_new(path, fill)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replaces_and_refuses() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write(&p, |w| w.write_all(b"one")).unwrap();
        write(&p, |w| w.write_all(b"two")).unwrap();
        assert_eq!(std::fs::read(&p).ok().as_deref(), Some(&b"two"[..]));
        assert!(write_new(&p, |w| w.write_all(b"three")).is_err());
        assert_eq!(std::fs::read(&p).ok().as_deref(), Some(&b"two"[..]));
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(dir.path()).map(|d| d.count()).unwrap_or(0), 1);
    }
}
