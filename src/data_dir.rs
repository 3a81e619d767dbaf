//! Where vbrain's data lives once installed: the one answer to "where is the default organ set",
//! for the viewer and every command.
//!
//! - A *data folder* holds the default set as `brain/` (its lessons in `brain/lessons/`).
//! - Looked up in this order, the first that holds a set winning:
//!   1. `$VBRAIN_DATA` (a data folder, or a set's own folder);
//!   2. `../share/vbrain/` beside the executable (the layout of the Debian package and of the
//!      unpacked archive, `bin/vbrain` + `share/vbrain/brain/`);
//!   3. `share/vbrain/` beside the executable (the Windows zip, `vbrain.exe` + `share/vbrain/`);
//!   4. on Unix, `$XDG_DATA_HOME/vbrain` (default `~/.local/share/vbrain`), then each of
//!      `$XDG_DATA_DIRS` + `/vbrain` (default `/usr/local/share:/usr/share`);
//!   5. `organs/` under the working directory, for development in a checkout.
//! - Never the path the binary was built at: an installed binary runs with its checkout gone.
//! - [`candidates`] is pure (it takes the environment as values); [`default_set`] reads the
//!   process's environment and the file system.

use std::fmt;
use std::path::{Path, PathBuf};

/// The environment variable naming a data folder (or a set) ahead of every other place.
pub const ENV: &str = "VBRAIN_DATA";

/// The default set's folder name inside a data folder.
pub const DEFAULT_SET: &str = "brain";

/// What the lookup reads from the process: the variables and paths it depends on.
#[derive(Clone, Debug, Default)]
pub struct Environment {
    /// `$VBRAIN_DATA`.
    pub vbrain_data: Option<PathBuf>,
    /// The running executable.
    pub exe: Option<PathBuf>,
    /// `$XDG_DATA_HOME`.
    pub xdg_data_home: Option<PathBuf>,
    /// `$XDG_DATA_DIRS`, unsplit.
    pub xdg_data_dirs: Option<String>,
    /// `$HOME`.
    pub home: Option<PathBuf>,
    /// The working directory.
    pub cwd: Option<PathBuf>,
}

impl Environment {
    /// This process's environment. Empty variables count as unset, as the XDG specification says.
    pub fn current() -> Environment {
        let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
        Environment {
            vbrain_data: var(ENV).map(PathBuf::from),
            exe: std::env::current_exe().ok(),
            xdg_data_home: var("XDG_DATA_HOME").map(PathBuf::from),
            xdg_data_dirs: var("XDG_DATA_DIRS").map(|v| v.to_string_lossy().into_owned()),
            home: var("HOME").map(PathBuf::from),
            cwd: std::env::current_dir().ok(),
        }
    }
}

/// The default set's candidate folders, in the order they are tried (see the module header).
pub fn candidates(env: &Environment) -> Vec<PathBuf> {
    let mut out = Vec::new();
    if let Some(dir) = &env.vbrain_data {
        // Either a set itself or a data folder holding one.
        out.push(dir.clone());
        out.push(dir.join(DEFAULT_SET));
    }
    if let Some(exe_dir) = env.exe.as_deref().and_then(Path::parent) {
        out.push(exe_dir.join("..").join("share").join("vbrain").join(DEFAULT_SET));
        out.push(exe_dir.join("share").join("vbrain").join(DEFAULT_SET));
    }
    if cfg!(unix) {
        let home_data = env.xdg_data_home.clone().or_else(|| env.home.as_ref().map(|h| h.join(".local/share")));
        if let Some(dir) = home_data {
            out.push(dir.join("vbrain").join(DEFAULT_SET));
        }
        let dirs = env.xdg_data_dirs.as_deref().unwrap_or("/usr/local/share:/usr/share");
        for dir in dirs.split(':').filter(|d| !d.is_empty()) {
            out.push(Path::new(dir).join("vbrain").join(DEFAULT_SET));
        }
    }
    if let Some(cwd) = &env.cwd {
        out.push(cwd.join("organs").join(DEFAULT_SET));
    }
    out
}

/// Whether `dir` holds an organ set (its manifest).
pub fn is_set(dir: &Path) -> bool {
    dir.join("organset.json").is_file()
}

/// No default set was found: the places looked, in order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct NotFound {
    pub looked: Vec<PathBuf>,
}

impl fmt::Display for NotFound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "no default organ set found; looked in:")?;
        for place in &self.looked {
            writeln!(f, "  {}", place.display())?;
        }
        write!(f, "set {ENV} to a folder holding `{DEFAULT_SET}/`, or give a set's path")
    }
}

impl std::error::Error for NotFound {}

/// The first candidate that holds a set.
pub fn find_in(env: &Environment) -> Result<PathBuf, NotFound> {
    let looked = candidates(env);
    match looked.iter().find(|dir| is_set(dir)) {
        Some(dir) => Ok(normalize(dir)),
        None => Err(NotFound { looked }),
    }
}

/// The default set for this process.
pub fn default_set() -> Result<PathBuf, NotFound> {
    find_in(&Environment::current())
}

/// The path as given, or the default set.
pub fn set_or_default(given: Option<&Path>) -> Result<PathBuf, NotFound> {
    match given {
        Some(path) => Ok(path.to_path_buf()),
        None => default_set(),
    }
}

/// A lesson by file path, or by name among the default set's lessons (`cortex` is
/// `brain/lessons/cortex.vblesson`). A path that exists, or one with a folder or an extension,
/// is taken as given.
pub fn lesson(name_or_path: &Path) -> Result<PathBuf, LessonNotFound> {
    let plain_name = name_or_path.components().count() == 1 && name_or_path.extension().is_none();
    if name_or_path.exists() || !plain_name {
        return Ok(name_or_path.to_path_buf());
    }
    let set = default_set().map_err(|e| LessonNotFound { name: name_or_path.to_path_buf(), set: Err(e) })?;
    let file = set.join("lessons").join(name_or_path).with_extension("vblesson");
    if file.is_file() {
        Ok(file)
    } else {
        Err(LessonNotFound { name: name_or_path.to_path_buf(), set: Ok(set) })
    }
}

/// A set's lesson files (`lessons/*.vblesson`), sorted.
pub fn lesson_files(set: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(set.join("lessons"))
        .into_iter()
        .flatten()
        .flatten()
        .map(|entry| entry.path())
        .filter(|p| p.extension().is_some_and(|e| e == "vblesson"))
        .collect();
    files.sort();
    files
}

/// The names of a set's lessons (their file names without `.vblesson`), sorted.
pub fn lesson_names(set: &Path) -> Vec<String> {
    lesson_files(set).iter().filter_map(|p| p.file_stem().map(|s| s.to_string_lossy().into_owned())).collect()
}

/// A lesson named that is neither a file nor one of the default set's lessons.
#[derive(Debug)]
pub struct LessonNotFound {
    pub name: PathBuf,
    /// The default set looked in, or why there is none.
    pub set: Result<PathBuf, NotFound>,
}

impl fmt::Display for LessonNotFound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = self.name.display();
        match &self.set {
            Ok(set) => {
                let names = lesson_names(set);
                write!(
                    f,
                    "no lesson file {name}, and the default set ({}) has no lesson of that name; its lessons: {}",
                    set.display(),
                    if names.is_empty() { "none".to_string() } else { names.join(", ") }
                )
            }
            Err(e) => write!(f, "no lesson file {name}, and {e}"),
        }
    }
}

impl std::error::Error for LessonNotFound {}

/// `a/b/../c` as `a/c`, lexically, so messages and titles show the folder a user would type.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::ParentDir if out.file_name().is_some() => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env() -> Environment {
        Environment {
            vbrain_data: None,
            exe: Some("/opt/vb/bin/vbrain".into()),
            xdg_data_home: None,
            xdg_data_dirs: None,
            home: Some("/home/u".into()),
            cwd: Some("/work".into()),
        }
    }

    #[test]
    fn places_come_in_the_documented_order() {
        let mut e = env();
        e.vbrain_data = Some("/data".into());
        let got = candidates(&e);
        let mut want: Vec<PathBuf> = vec![
            "/data".into(),
            "/data/brain".into(),
            "/opt/vb/bin/../share/vbrain/brain".into(),
            "/opt/vb/bin/share/vbrain/brain".into(),
        ];
        if cfg!(unix) {
            want.extend([
                "/home/u/.local/share/vbrain/brain".into(),
                "/usr/local/share/vbrain/brain".into(),
                "/usr/share/vbrain/brain".into(),
            ]);
        }
        want.push("/work/organs/brain".into());
        assert_eq!(got, want);
    }

    #[cfg(unix)]
    #[test]
    fn xdg_variables_replace_their_defaults() {
        let mut e = env();
        e.xdg_data_home = Some("/x/home".into());
        e.xdg_data_dirs = Some("/a::/b".into());
        let got = candidates(&e);
        assert!(got.contains(&"/x/home/vbrain/brain".into()));
        assert!(got.contains(&"/a/vbrain/brain".into()) && got.contains(&"/b/vbrain/brain".into()));
        assert!(!got.iter().any(|p| p.starts_with("/usr") || p.starts_with("/home/u")), "{got:?}");
    }

    #[test]
    fn the_first_place_holding_a_set_wins() {
        let root = tempfile::tempdir().unwrap_or_else(|e| panic!("{e}"));
        let prefix = root.path().join("pkg");
        let exe = prefix.join("bin/vbrain");
        let cwd = root.path().join("work");
        std::fs::create_dir_all(prefix.join("bin")).unwrap_or_else(|e| panic!("{e}"));
        for set in [prefix.join("share/vbrain/brain"), cwd.join("organs/brain")] {
            std::fs::create_dir_all(&set).unwrap_or_else(|e| panic!("{e}"));
            std::fs::write(set.join("organset.json"), "{}").unwrap_or_else(|e| panic!("{e}"));
        }
        let e =
            Environment { exe: Some(exe), cwd: Some(cwd.clone()), xdg_data_dirs: Some("/nonexistent".into()), ..env() };
        assert_eq!(find_in(&e), Ok(prefix.join("share/vbrain/brain")));
        let e = Environment { exe: None, ..e };
        assert_eq!(find_in(&e), Ok(cwd.join("organs/brain")));
        let e = Environment { cwd: None, ..e };
        let err = find_in(&e).err().unwrap_or_else(|| panic!("found a set where none is"));
        assert!(err.to_string().contains("/nonexistent/vbrain/brain"), "{err}");
        assert!(err.to_string().contains(ENV), "{err}");
    }

    #[test]
    fn paths_with_a_folder_or_an_extension_are_taken_as_given() {
        for given in ["x/cortex", "cortex.vblesson"] {
            assert_eq!(lesson(Path::new(given)).ok(), Some(PathBuf::from(given)));
        }
    }
}
