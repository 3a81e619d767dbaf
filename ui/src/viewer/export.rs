//! Screenshot export: the current view rendered offscreen at the asked size through the same
//! renderer as the viewport (never an upscaled screen grab), written as PNG atomically, never over an
//! existing file.

use anyhow::{bail, Result};
use std::path::{Path, PathBuf};
use vbrain::render::{FrameInput, Renderer, Target};

/// The largest exported side, in pixels.
pub const MAX_SIDE: u32 = 8192;

/// `<set>-YYYYMMDD-HHMMSS.png` for the set's title and a time (UTC).
pub fn default_file_name(title: &str, now: std::time::SystemTime) -> String {
    let secs = now.duration_since(std::time::UNIX_EPOCH).map(|d| d.as_secs()).unwrap_or(0);
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    // Civil date from days since 1970-01-01 (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    let slug = vbrain::organ_set::slug(title);
    format!("{slug}-{year:04}{month:02}{day:02}-{:02}{:02}{:02}.png", rem / 3600, rem % 3600 / 60, rem % 60)
}

/// `path` if it does not exist, else the first free `name-2.png`, `name-3.png`, ...
pub fn unused_path(path: &Path) -> PathBuf {
    if !path.exists() {
        return path.to_path_buf();
    }
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let ext = path.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_else(|| "png".into());
    (2..).map(|n| path.with_file_name(format!("{stem}-{n}.{ext}"))).find(|p| !p.exists()).unwrap_or_default()
}

/// Renders `frame` (a still: full screen-door masks) at `size` and writes a PNG to `path` (or, if
/// that exists, to the next free name, which is returned).
pub fn export(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    renderer: &Renderer,
    frame: &FrameInput,
    size: [u32; 2],
    path: &Path,
) -> Result<PathBuf> {
    let [w, h] = size;
    if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE {
        bail!("screenshot size {w}x{h} outside 1..={MAX_SIDE}");
    }
    let target = Target::new(device, w, h)?;
    renderer.render(device, queue, &target, &FrameInput { moving: false, ..*frame })?;
    let image = target.read_color(device, queue)?;
    let path = unused_path(path);
    vbrain::atomic::write_png(&path, &image, false)?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names() {
        let t = std::time::UNIX_EPOCH + std::time::Duration::from_secs(1_795_305_600 + 3 * 3600 + 4 * 60 + 5);
        assert_eq!(default_file_name("Human brain (MNI152)", t), "human_brain_mni152-20261122-030405.png");
        let leap = std::time::UNIX_EPOCH + std::time::Duration::from_secs(951_782_400); // 2000-02-29
        assert!(default_file_name("x", leap).starts_with("x-20000229-"));
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.png");
        assert_eq!(unused_path(&p), p);
        std::fs::write(&p, b"x").unwrap();
        assert_eq!(unused_path(&p), dir.path().join("a-2.png"));
    }
}
