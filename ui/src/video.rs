//! Videos of a set for slides: a turntable around a view's target (elevation kept), or a lesson
//! played, each step eased in as the viewer eases it ([`vbrain::transition`]) and held. The CLI
//! (`vbrain video`) and the viewer (*File > Export video...*) both call [`write()`].
//!
//! - Frames are sRGB RGBA, `size` pixels, top row first; time runs at `fps` frames a second.
//! - GIF through the `gif` crate (a palette of 256 colours per frame, NeuQuant); MP4 (H.264) and
//!   WebM (VP9) through a system `ffmpeg`, fed raw frames on its standard input.
//! - The file is written beside the output under a temporary name and renamed when complete: a
//!   cancelled or failed export leaves nothing.

use crate::annotate::Labels;
use crate::studio::{Shot, StepFrame, Studio};
use anyhow::{anyhow, bail, Context, Result};
use image::RgbaImage;
use std::io::Write;
use std::path::Path;
use vbrain::clip::Section;
use vbrain::layout::Layout;
use vbrain::navigation::Navigator;

/// The most frames a video may have (20 minutes at 30 frames a second).
pub const MAX_FRAMES: usize = 36_000;
/// The largest side of a video frame, in pixels.
pub const MAX_SIDE: u32 = 3840;
/// The most frames a second (GIF's delays are in hundredths of a second, and players slow
/// anything faster than 50).
pub const MAX_FPS: u32 = 60;

/// A video file format, named by the output's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Gif,
    Mp4,
    Webm,
}

impl Format {
    pub const EXTENSIONS: &'static str = ".gif, .mp4 (H.264) or .webm (VP9)";

    /// The format `path`'s extension names (any case).
    pub fn of(path: &Path) -> Result<Format> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        Ok(match ext.as_str() {
            "gif" => Format::Gif,
            "mp4" => Format::Mp4,
            "webm" => Format::Webm,
            _ => bail!(
                "{}: not a video format vbrain writes; give a file ending in {}",
                path.display(),
                Self::EXTENSIONS
            ),
        })
    }
}

/// A view turned around its target.
pub struct Turntable {
    pub navigator: Navigator,
    pub layout: Layout,
    pub highlight: Vec<usize>,
    pub section: Section,
    pub labels: Labels,
    /// The turn over the whole video, in degrees (toward the right when positive).
    pub degrees: f32,
    pub seconds: f32,
}

/// A lesson played: per step its frame (camera, layout, caption) and how long it is held.
pub struct Played {
    pub steps: Vec<StepFrame>,
    /// Seconds each step is held once it has arrived.
    pub hold: f32,
}

/// What a video shows.
pub enum Plan {
    Turntable(Turntable),
    Lesson(Played),
}

/// Frames of a step's change from the one before, at `fps`.
fn easing_frames(fps: u32) -> usize {
    (vbrain::transition::DURATION * fps as f64).round() as usize
}

fn hold_frames(hold: f32, fps: u32) -> usize {
    ((hold * fps as f32).round() as usize).max(1)
}

impl Plan {
    /// The number of frames at `fps`.
    pub fn frames(&self, fps: u32) -> usize {
        match self {
            Plan::Turntable(t) => ((t.seconds * fps as f32).round() as usize).max(1),
            Plan::Lesson(p) => {
                let steps = p.steps.len();
                steps * hold_frames(p.hold, fps) + steps.saturating_sub(1) * easing_frames(fps)
            }
        }
    }

    /// Refuses a plan whose frame count or size is out of bounds, before any work.
    pub fn check(&self, size: [u32; 2], fps: u32, format: Format) -> Result<usize> {
        if !(1..=MAX_FPS).contains(&fps) || (format == Format::Gif && fps > 50) {
            bail!("{fps} frames a second: give 1..={} ({} for a GIF)", MAX_FPS, 50);
        }
        if size[0] > MAX_SIDE || size[1] > MAX_SIDE || size[0] < 16 || size[1] < 16 {
            bail!("{}x{}: a video's sides are 16..={MAX_SIDE} pixels", size[0], size[1]);
        }
        if format != Format::Gif && (size[0] % 2 == 1 || size[1] % 2 == 1) {
            bail!("{}x{}: MP4 and WebM need even sides", size[0], size[1]);
        }
        let frames = self.frames(fps);
        if frames > MAX_FRAMES {
            bail!("{frames} frames: a video has at most {MAX_FRAMES}; shorten it or lower --fps");
        }
        if let Plan::Lesson(p) = self {
            if p.steps.is_empty() {
                bail!("the lesson has no steps");
            }
        }
        Ok(frames)
    }

    /// Frame `k` at `fps`, rendered by `studio`.
    pub fn frame(&self, studio: &mut Studio, k: usize, fps: u32, size: [u32; 2]) -> Result<RgbaImage> {
        match self {
            Plan::Turntable(t) => {
                let n = self.frames(fps);
                let turn =
                    if n > 1 && t.degrees.abs() < 360.0 { k as f32 / (n - 1) as f32 } else { k as f32 / n as f32 };
                let navigator = Navigator { azimuth: t.navigator.azimuth + t.degrees * turn, ..t.navigator };
                let px = crate::annotate::text_px(size[1]);
                let shot = Shot {
                    navigator,
                    layout: &t.layout,
                    highlight: &t.highlight,
                    section: &t.section,
                    labels: &t.labels,
                    px,
                };
                Ok(studio.shoot(size, &shot)?.0)
            }
            Plan::Lesson(p) => {
                let (hold, ease) = (hold_frames(p.hold, fps), easing_frames(fps));
                // Step 0 is held; each later step eases in from the one before, then is held.
                let (step, into) = if k < hold {
                    (0, k + ease)
                } else {
                    let rest = k - hold;
                    (1 + rest / (ease + hold), rest % (ease + hold))
                };
                let frame = &p.steps[step.min(p.steps.len() - 1)];
                if into < ease {
                    let from = &p.steps[step - 1];
                    let t = vbrain::transition::ease((into + 1) as f32 / (ease + 1) as f32);
                    let navigator = vbrain::transition::navigator(&from.navigator, &frame.navigator, t);
                    let layout = vbrain::transition::layout(&from.view.layout, &frame.view.layout, t);
                    Ok(frame.draw(studio, Some((navigator, &layout)))?.0)
                } else {
                    Ok(frame.draw(studio, None)?.0)
                }
            }
        }
    }
}

/// What [`write()`] did.
pub struct Written {
    pub frames: usize,
    /// Seconds spent rendering frames and in all.
    pub render_s: f64,
    pub total_s: f64,
}

/// Writes `plan` as a video `size` pixels at `fps` to `out` (format by extension), replacing an
/// existing file only with `replace`. `progress(done, frames)` is called after each frame; when
/// it returns false the export stops and leaves nothing.
pub fn write(
    studio: &mut Studio,
    plan: &Plan,
    size: [u32; 2],
    fps: u32,
    out: &Path,
    replace: bool,
    progress: &mut dyn FnMut(usize, usize) -> bool,
) -> Result<Written> {
    let format = Format::of(out)?;
    let frames = plan.check(size, fps, format)?;
    if out.is_dir() {
        bail!("{}: is a folder; give a file name ending in {}", out.display(), Format::EXTENSIONS);
    }
    if out.exists() && !replace {
        bail!("{}: exists; give --force to replace it", out.display());
    }
    let dir = match out.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    builder.prefix(".vbrain-video-").suffix(".part");
    // Readable by others, as every other file vbrain writes (a temporary file is private).
    #[cfg(unix)]
    builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o644));
    let temp = builder.tempfile_in(dir).with_context(|| format!("{}: cannot write beside it", out.display()))?;
    let started = std::time::Instant::now();
    let mut render_s = 0.0;
    let file = temp.reopen().with_context(|| format!("{}", temp.path().display()))?;
    let mut sink: Box<dyn Sink> = match format {
        Format::Gif => Box::new(GifSink::new(file, size, fps)?),
        Format::Mp4 | Format::Webm => Box::new(Ffmpeg::start(format, temp.path(), size, fps)?),
    };
    for k in 0..frames {
        let t = std::time::Instant::now();
        let image = plan.frame(studio, k, fps, size)?;
        render_s += t.elapsed().as_secs_f64();
        sink.push(image)?;
        if !progress(k + 1, frames) {
            drop(sink);
            bail!("cancelled; {} was not written", out.display());
        }
    }
    sink.finish()?;
    if replace {
        temp.persist(out).map_err(|e| anyhow!("{}: {}", out.display(), e.error))?;
    } else {
        temp.persist_noclobber(out).map_err(|e| anyhow!("{}: {}", out.display(), e.error))?;
    }
    Ok(Written { frames, render_s, total_s: started.elapsed().as_secs_f64() })
}

/// Renders `plan`'s frames and drops them: the seconds it took, the baseline that encoding's
/// cost is measured against (`vbrain video --render-only`).
pub fn render_only(studio: &mut Studio, plan: &Plan, size: [u32; 2], fps: u32, format: Format) -> Result<f64> {
    let frames = plan.check(size, fps, format)?;
    let started = std::time::Instant::now();
    for k in 0..frames {
        std::hint::black_box(plan.frame(studio, k, fps, size)?);
    }
    Ok(started.elapsed().as_secs_f64())
}

/// Where frames go.
trait Sink {
    fn push(&mut self, frame: RgbaImage) -> Result<()>;
    fn finish(self: Box<Self>) -> Result<()>;
}

/// GIF frames quantised and written on a thread of their own, while the next frame renders.
struct GifSink {
    frames: Option<std::sync::mpsc::SyncSender<RgbaImage>>,
    worker: Option<std::thread::JoinHandle<Result<()>>>,
}

impl GifSink {
    fn new(file: std::fs::File, size: [u32; 2], fps: u32) -> Result<GifSink> {
        let (w, h) = (u16::try_from(size[0])?, u16::try_from(size[1])?);
        let (send, receive) = std::sync::mpsc::sync_channel::<RgbaImage>(2);
        let worker = std::thread::spawn(move || -> Result<()> {
            let mut encoder = gif::Encoder::new(std::io::BufWriter::new(file), w, h, &[])?;
            encoder.set_repeat(gif::Repeat::Infinite)?;
            for (k, image) in receive.into_iter().enumerate() {
                let mut rgba = image.into_raw();
                let mut frame = gif::Frame::from_rgba_speed(w, h, &mut rgba, 10);
                // Delays in hundredths of a second, rounded so that the whole keeps time.
                let at = |k: usize| (k as f64 * 100.0 / fps as f64).round() as u16;
                frame.delay = at(k + 1) - at(k);
                encoder.write_frame(&frame)?;
            }
            encoder.into_inner()?.flush()?;
            Ok(())
        });
        Ok(GifSink { frames: Some(send), worker: Some(worker) })
    }

    fn join(&mut self) -> Result<()> {
        self.frames = None;
        match self.worker.take().map(|w| w.join()) {
            Some(Ok(result)) => result,
            Some(Err(_)) => bail!("the GIF encoder stopped"),
            None => Ok(()),
        }
    }
}

impl Sink for GifSink {
    fn push(&mut self, frame: RgbaImage) -> Result<()> {
        let sent = self.frames.as_ref().is_some_and(|s| s.send(frame).is_ok());
        if !sent {
            // The worker ended early: its error says why.
            self.join()?;
            bail!("the GIF encoder stopped");
        }
        Ok(())
    }

    fn finish(mut self: Box<Self>) -> Result<()> {
        self.join()
    }
}

impl Drop for GifSink {
    fn drop(&mut self) {
        let _ = self.join();
    }
}

/// A system ffmpeg encoding raw RGBA frames from its standard input.
struct Ffmpeg {
    child: std::process::Child,
}

impl Ffmpeg {
    fn start(format: Format, out: &Path, size: [u32; 2], fps: u32) -> Result<Ffmpeg> {
        let codec: &[&str] = match format {
            Format::Mp4 => {
                &["-c:v", "libx264", "-preset", "medium", "-crf", "18", "-movflags", "+faststart", "-f", "mp4"]
            }
            _ => &[
                "-c:v",
                "libvpx-vp9",
                "-crf",
                "30",
                "-b:v",
                "0",
                "-row-mt",
                "1",
                "-deadline",
                "good",
                "-cpu-used",
                "4",
                "-f",
                "webm",
            ],
        };
        let child = std::process::Command::new(ffmpeg())
            .args(["-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba"])
            .args(["-s", &format!("{}x{}", size[0], size[1]), "-framerate", &fps.to_string(), "-i", "-"])
            .args(codec)
            .args(["-pix_fmt", "yuv420p"])
            .arg(out)
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .map_err(|e| {
                anyhow!(
                    "MP4 and WebM are encoded by ffmpeg, which could not be started ({e}); install it \
                     (Debian and Ubuntu: sudo apt-get install ffmpeg) or write a .gif"
                )
            })?;
        Ok(Ffmpeg { child })
    }

    fn failure(&mut self) -> anyhow::Error {
        let mut said = String::new();
        if let Some(mut e) = self.child.stderr.take() {
            let _ = std::io::Read::read_to_string(&mut e, &mut said);
        }
        let _ = self.child.wait();
        anyhow!("ffmpeg failed: {}", said.trim())
    }
}

/// The ffmpeg to run: `$FFMPEG`, else `ffmpeg` on the PATH.
fn ffmpeg() -> std::ffi::OsString {
    std::env::var_os("FFMPEG").unwrap_or_else(|| "ffmpeg".into())
}

impl Sink for Ffmpeg {
    fn push(&mut self, frame: RgbaImage) -> Result<()> {
        let written = self.child.stdin.as_mut().map(|i| i.write_all(frame.as_raw()));
        match written {
            Some(Ok(())) => Ok(()),
            _ => Err(self.failure()),
        }
    }

    fn finish(mut self: Box<Self>) -> Result<()> {
        drop(self.child.stdin.take());
        let status = self.child.wait()?;
        if !status.success() {
            return Err(self.failure());
        }
        Ok(())
    }
}

impl Drop for Ffmpeg {
    fn drop(&mut self) {
        if let Ok(None) = self.child.try_wait() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}
