//! Where commands write: every output is checked here before the work starts, by one rule.
//!
//! - A file output is refused where it is a folder or one of the command's inputs. Where it
//!   exists, it is replaced only if it is of the command's own kind (a PNG image for a picture, a
//!   vbrain scene for `--save-scene`), or with `--force`.
//! - A file that did not exist at the check is created exclusively at the end: a second run that
//!   writes the same new name fails, and does not replace the first run's file.
//! - A folder output is refused where it holds one of the inputs (with `--force` too: a writer
//!   never takes its input as its output), where it is not a folder, or where it already holds
//!   anything, unless `--force`. It is written whole, staged beside and moved into place
//!   ([`vbrain::atomic::write_folder`]), so `--force` replaces the folder, never mixes into it.
//! - The outputs of one run never lie inside one another (a model inside a page's folder).
//! - An experiment's folder (`bench`, `masks`, ...) is its own once an experiment has written it
//!   (a [`crate::lab::EXPERIMENT_MARK`] file inside says so): later runs replace their files
//!   there. A folder that holds anything else is refused unless `--force`; the experiments never
//!   touch the other files in it.

use anyhow::{bail, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// What an existing file must be for a command to replace it without `--force`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A PNG image (pictures).
    Png,
    /// A vbrain scene (`--save-scene`).
    Scene,
    /// Nothing: any existing file needs `--force`. The extension names the kind for messages.
    New(&'static str),
}

/// A file output, checked.
#[derive(Debug)]
pub struct OutFile {
    path: PathBuf,
    /// It existed at the check (and may be replaced); otherwise it is created exclusively.
    existed: bool,
}

impl OutFile {
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes the file atomically with what `fill` writes.
    pub fn write(&self, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
        let written = if self.existed {
            vbrain::atomic::write(&self.path, fill)
        } else {
            vbrain::atomic::write_new(&self.path, fill)
        };
        written.map_err(|e| self.explain(e))
    }

    /// Writes `image` as a PNG file atomically.
    pub fn write_png(&self, image: &image::RgbaImage) -> Result<()> {
        vbrain::atomic::write_png(&self.path, image, self.existed).map_err(|e| self.explain(e))
    }

    fn explain(&self, e: vbrain::Error) -> anyhow::Error {
        if !self.existed && self.path.exists() {
            return anyhow::anyhow!(
                "{}: was created by something else while this ran; it is left as it is (give --force to replace it)",
                self.path.display()
            );
        }
        anyhow::anyhow!(e)
    }
}

/// Checks the file output `path` of a command that reads `inputs`.
pub fn file(path: &Path, kind: Kind, force: bool, inputs: &[&Path]) -> Result<OutFile> {
    let extension = match kind {
        Kind::Png => "png",
        Kind::Scene => "vbscene",
        Kind::New(e) => e,
    };
    if path.is_dir() {
        bail!("{}: is a folder; give a file name ending in .{extension}", path.display());
    }
    if let Some(input) = inputs.iter().find(|i| same_file(path, i)) {
        bail!("{}: is what this command reads ({}); give another file to write", path.display(), input.display());
    }
    // A link to nothing exists too: it is not created anew.
    let existed = path.symlink_metadata().is_ok();
    if existed && !force {
        let ours = match kind {
            Kind::Png => is_png(path),
            Kind::Scene => vbrain::scene_file::SceneFile::load(path).is_ok(),
            Kind::New(_) => false,
        };
        if !ours {
            let what = match kind {
                Kind::Png => "exists and is not a PNG image",
                Kind::Scene => "exists and is not a vbrain scene",
                Kind::New(_) => "already exists",
            };
            bail!("{}: {what}; give --force to replace it", path.display());
        }
    }
    Ok(OutFile { path: path.to_path_buf(), existed })
}

/// Checks the folder output `dir` of a command that reads `inputs`.
pub fn folder(dir: &Path, force: bool, inputs: &[&Path]) -> Result<()> {
    if let Some(input) = inputs.iter().find(|i| holds(dir, i)) {
        bail!("{}: holds what this command reads ({}); give another folder to write", dir.display(), input.display());
    }
    let held = vbrain::atomic::folder_entries(dir)?;
    if held > 0 && !force {
        bail!(
            "{}: already holds {held} files or folders; give --force to replace them, or a new folder",
            dir.display()
        );
    }
    Ok(())
}

/// Checks the folder of an experiment's results (the experiment makes and marks it,
/// [`crate::lab::output_folder`], once its own arguments are checked).
pub fn experiment_folder(dir: &Path, force: bool) -> Result<()> {
    let held = vbrain::atomic::folder_entries(dir)?;
    if held > 0 && !force && !dir.join(crate::lab::EXPERIMENT_MARK).is_file() {
        bail!(
            "{}: already holds {held} files or folders that no vbrain experiment wrote; give --force to write \
             there anyway (only the experiment's own files are replaced), or a new folder",
            dir.display()
        );
    }
    Ok(())
}

/// Refuses outputs of one run that lie inside one another: a file inside a folder output, or one
/// folder output inside another (each folder is replaced whole).
pub fn apart(files: &[&Path], folders: &[&Path]) -> Result<()> {
    for (i, dir) in folders.iter().enumerate() {
        let inside = files.iter().chain(folders.iter().take(i)).chain(folders.iter().skip(i + 1));
        if let Some(other) = inside.into_iter().find(|o| within(dir, o)) {
            bail!(
                "{}: lies inside {}, which this command writes whole; give them apart",
                other.display(),
                dir.display()
            );
        }
    }
    Ok(())
}

/// Do `a` and `b` name one existing file?
fn same_file(a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
}

/// Does the folder `dir` hold the existing `input` (at any depth), or is it `input`?
fn holds(dir: &Path, input: &Path) -> bool {
    matches!((dir.canonicalize(), input.canonicalize()), (Ok(d), Ok(i)) if i.starts_with(&d))
}

/// Does `path` lie at or below `dir`, whether or not either exists? (Each is resolved as far as it
/// exists, the rest taken as written.)
fn within(dir: &Path, path: &Path) -> bool {
    resolved(path).starts_with(resolved(dir))
}

/// `path` made absolute, with the longest existing prefix resolved (links, `..`).
fn resolved(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut rest = Vec::new();
    let mut head = absolute.as_path();
    loop {
        if let Ok(real) = head.canonicalize() {
            return rest.iter().rev().fold(real, |p, part| p.join(part));
        }
        match (head.parent(), head.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                head = parent;
            }
            _ => return absolute,
        }
    }
}

fn is_png(path: &Path) -> bool {
    const SIGNATURE: &[u8] = b"\x89PNG\r\n\x1a\n";
    let mut head = [0u8; 8];
    std::fs::File::open(path)
        .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut head))
        .is_ok_and(|()| head == SIGNATURE)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outputs_inside_one_another_are_refused_whether_or_not_they_exist() {
        let dir = tempfile::tempdir().unwrap();
        let page = dir.path().join("page");
        let model = page.join("m.glb");
        assert!(apart(&[&model], &[&page]).is_err(), "a model inside the page's folder");
        assert!(apart(&[&dir.path().join("m.glb")], &[&page]).is_ok());
        assert!(apart(&[], &[&page, &page.join("sub")]).is_err(), "one folder inside another");
        // Spelt another way: through `..`.
        let odd = page.join("x").join("..").join("m.glb");
        assert!(apart(&[&odd], &[&page]).is_err());
    }

    #[test]
    fn a_folder_holding_an_input_is_refused_even_with_force() {
        let dir = tempfile::tempdir().unwrap();
        let set = dir.path().join("set");
        std::fs::create_dir(&set).unwrap();
        std::fs::write(set.join("organset.json"), "{}").unwrap();
        assert!(folder(&set, true, &[&set]).is_err(), "the input itself");
        assert!(folder(dir.path(), true, &[&set]).is_err(), "a folder above the input");
        assert!(folder(&dir.path().join("new"), false, &[&set]).is_ok());
        assert!(folder(&set, true, &[]).is_ok(), "another command's folder, with --force");
        assert!(folder(&set, false, &[]).is_err(), "and without it");
    }

    #[test]
    fn a_new_file_is_created_exclusively() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a.pdf");
        let checked = file(&out, Kind::New("pdf"), false, &[]).unwrap();
        // Another run creates the file between this one's check and its write.
        std::fs::write(&out, b"theirs").unwrap();
        let err = checked.write(|w| w.write_all(b"ours")).unwrap_err().to_string();
        assert!(err.contains("created by something else"), "{err}");
        assert_eq!(std::fs::read(&out).unwrap(), b"theirs");
        assert!(file(&out, Kind::New("pdf"), false, &[]).is_err(), "exists now");
        assert!(file(&out, Kind::New("pdf"), true, &[&out]).is_err(), "its own input, even with --force");
    }
}
