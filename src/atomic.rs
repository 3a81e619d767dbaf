//! Atomic writes, so that a crash or a full disk leaves either the old file or folder or the new
//! one, never half of one.
//!
//! - A file is written as a temporary file beside the target, flushed to disk, then renamed.
//! - A folder is written whole into a staging folder beside it, which then takes its place.
//! - What a killed run left (`.NAME.PID.tmp` files, `.NAME.staging-PID` folders of a process no
//!   longer running) is removed by the next write of the same name.

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
    remove_stale(&dir, &name.to_string_lossy());
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

/// Removes, from `dir`, the temporary files and staging folders of writes of `name` by processes
/// no longer running (a killed export, say). Only where running processes can be told (`/proc`).
fn remove_stale(dir: &Path, name: &str) {
    let proc = Path::new("/proc");
    if !proc.join("self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let prefix = format!(".{name}.");
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(rest) = file.to_str().and_then(|f| f.strip_prefix(&prefix)) else { continue };
        let pid = rest.strip_suffix(".tmp").or_else(|| rest.strip_prefix("staging-"));
        let Some(pid) = pid.filter(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit())) else { continue };
        if pid != std::process::id().to_string() && !proc.join(pid).exists() {
            let path = entry.path();
            let _ = if path.is_dir() { std::fs::remove_dir_all(&path) } else { std::fs::remove_file(&path) };
        }
    }
}

/// How many entries the folder `dir` holds (0 where it does not exist); an error where `dir` is
/// not a folder. Commands that replace a folder ask before replacing one that holds anything.
pub fn folder_entries(dir: &Path) -> Result<usize> {
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(0),
        Err(e) => Err(Error::io(dir, e)),
        Ok(m) if !m.is_dir() => Err(Error::parse(dir, None, "exists and is not a folder")),
        Ok(_) => Ok(std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?.count()),
    }
}

/// Writes the folder `dir` whole: `fill` writes into an empty staging folder beside it, which then
/// takes `dir`'s place. An existing `dir` is moved aside first and removed only once the new one
/// is in place; if `fill` or a move fails, `dir` is as it was and the staging folder is gone.
/// `fill`'s errors are the caller's own type (one this module's errors convert into).
pub fn write_folder<E: From<Error>>(
    dir: &Path,
    fill: impl FnOnce(&Path) -> std::result::Result<(), E>,
) -> std::result::Result<(), E> {
    let parent = match dir.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = dir.file_name().ok_or_else(|| Error::NotAFileName { path: dir.to_path_buf() })?.to_string_lossy();
    std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
    remove_stale(&parent, &name);
    let staging = parent.join(format!(".{name}.staging-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&staging);
    std::fs::create_dir(&staging).map_err(|e| Error::io(&staging, e))?;
    let placed = fill(&staging).and_then(|()| {
        into_place(&staging, dir, &parent.join(format!(".{name}.old-{}", std::process::id()))).map_err(E::from)
    });
    if placed.is_err() {
        let _ = std::fs::remove_dir_all(&staging);
    }
    placed
}

/// Moves the folder `staging` to `dir`; an existing `dir` is moved to `old` first and removed once
/// the new one is in place (or moved back if that fails).
fn into_place(staging: &Path, dir: &Path, old: &Path) -> Result<()> {
    if !dir.exists() {
        return std::fs::rename(staging, dir).map_err(|e| Error::io(dir, e));
    }
    let _ = std::fs::remove_dir_all(old);
    std::fs::rename(dir, old).map_err(|e| Error::io(dir, e))?;
    if let Err(e) = std::fs::rename(staging, dir) {
        let _ = std::fs::rename(old, dir);
        return Err(Error::io(dir, e));
    }
    let _ = std::fs::remove_dir_all(old);
    Ok(())
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
    fn what_a_killed_run_left_goes_with_the_next_write() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        // A process id no Linux system hands out (above the largest pid_max).
        let dead = 4_194_305u32;
        std::fs::write(d.join(format!(".x.png.{dead}.tmp")), b"half").unwrap();
        std::fs::create_dir(d.join(format!(".out.staging-{dead}"))).unwrap();
        std::fs::write(d.join(".x.png.notes.tmp"), b"someone else's").unwrap();
        std::fs::write(d.join(format!(".y.png.{dead}.tmp")), b"another name's").unwrap();
        write(&d.join("x.png"), |w| w.write_all(b"png")).unwrap();
        write_folder(&d.join("out"), |s| std::fs::write(s.join("a"), b"a").map_err(|e| Error::io(s, e))).unwrap();
        let mut left: Vec<String> =
            std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        left.sort();
        assert_eq!(left, [".x.png.notes.tmp", &format!(".y.png.{dead}.tmp"), "out", "x.png"]);
    }

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

    #[test]
    fn a_folder_is_replaced_whole_or_not_at_all() {
        let dir = tempfile::tempdir().unwrap();
        let set = dir.path().join("set");
        assert_eq!(folder_entries(&set).unwrap(), 0);
        write_folder(&set, |d| write(&d.join("a"), |w| w.write_all(b"1"))).unwrap();
        assert_eq!(folder_entries(&set).unwrap(), 1);
        // A failing fill leaves the old folder as it was, and nothing beside it.
        let failed = write_folder(&set, |d| {
            write(&d.join("b"), |w| w.write_all(b"2"))?;
            Err(Error::parse(d, None, "disk full"))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(set.join("a")).ok().as_deref(), Some(&b"1"[..]));
        assert!(!set.join("b").exists());
        assert_eq!(std::fs::read_dir(dir.path()).map(|d| d.count()).unwrap_or(0), 1);
        // A fill that succeeds replaces the folder: the old files are gone.
        write_folder(&set, |d| write(&d.join("b"), |w| w.write_all(b"2"))).unwrap();
        assert!(!set.join("a").exists() && set.join("b").exists());
        assert_eq!(std::fs::read_dir(dir.path()).map(|d| d.count()).unwrap_or(0), 1);
        assert!(folder_entries(&set.join("b")).is_err(), "a file is not a folder");
    }
}
