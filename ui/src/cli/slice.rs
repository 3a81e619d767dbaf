//! `vbrain slice`: one axis-aligned slice of a set as a radiology-style figure (PNG): the set's
//! MRI with organ outlines, side letters and labels ([`crate::slice_figure`]).
//!
//! - The plane's position is in world RAS millimetres; the display is radiological unless
//!   `--neurological` (the patient's right on the right).
//! - A set without an MRI shows its organs filled in their colours.
//! - A figure has at most 4096x4096 pixels; a file that is not a PNG image is not replaced
//!   without `--force`.

use super::common::{apply_layout_args, open_set, organs};
use super::{values, LayoutArgs, Report};
use crate::annotate::Labels;
use anyhow::{anyhow, bail, Result};
use serde_json::json;
use std::path::PathBuf;
use vbrain::labels::Which;
use vbrain::layout::Layout;
use vbrain::mri::slice::{Pane, MAX_PIXELS};

#[derive(clap::Args)]
pub struct SliceArgs {
    /// Organ set [default: the default brain]
    pub path: Option<PathBuf>,
    /// The slice: axial=MM, coronal=MM or sagittal=MM (world RAS, millimetres)
    #[arg(long, allow_hyphen_values = true, value_parser = values::slice_plane)]
    pub plane: vbrain::mri::slice::SlicePlane,
    #[command(flatten)]
    pub picture: super::PictureArgs,
    /// Draw each organ's outline in its colour
    #[arg(long)]
    pub outlines: bool,
    /// Name organs with leader-line labels: none, all (the largest on the slice) or ID,ID,... (ids
    /// or groups) [default: none]
    #[arg(long)]
    pub labels: Option<String>,
    /// Neurological display (the patient's right on the right) instead of radiological
    #[arg(long)]
    pub neurological: bool,
    /// The MRI's window and level, WINDOW,LEVEL, on its intensities normalised to 0..1
    /// [default: 0.9,0.6]
    #[arg(long, value_parser = values::window)]
    pub window: Option<vbrain::mri::Window>,
    #[command(flatten)]
    pub layout: LayoutArgs,
    #[command(flatten)]
    pub report: Report,
}

pub fn run(args: &SliceArgs) -> Result<bool> {
    let inputs: Vec<&std::path::Path> = args.path.iter().map(PathBuf::as_path).collect();
    let picture = super::outputs::file(&args.picture.out, super::outputs::Kind::Png, args.picture.force, &inputs)?;
    let (width, height) = (args.picture.size.width, args.picture.size.height);
    if width as usize * height as usize > MAX_PIXELS {
        bail!("--size {width}x{height}: a slice figure has at most {MAX_PIXELS} pixels (4096x4096)");
    }
    let path: PathBuf = match &args.path {
        Some(p) => p.clone(),
        None => vbrain::data_dir::default_set()?,
    };
    let set = open_set(&path)?;
    let mut layout = Layout::new(&set);
    apply_layout_args(&set, &mut layout, &args.layout)?;
    let which = Which::parse(args.labels.as_deref().unwrap_or(""));
    if let Which::Chosen(names) = &which {
        for key in names {
            organs(&set, key).map_err(|e| anyhow!("--labels: {e}"))?;
        }
    }
    if set.mri.is_none() {
        eprintln!("note: {} has no MRI; the slice shows its organs filled in their colours", path.display());
    }
    // The pane frames the organs shown, at rest, so slices of one layout line up.
    let bounds = crate::slice_figure::shown_bounds(&set, &layout);
    if bounds.is_empty() {
        bail!("no organ is shown: nothing to frame (see --show)");
    }
    let pane = Pane::fit(args.plane, &bounds, width, height, !args.neurological);
    let options = crate::slice_figure::Options {
        outlines: args.outlines,
        labels: Labels::of(&which, &set, None),
        window: args.window.unwrap_or_default(),
        letters: true,
        highlight: None,
    };
    let (image, ids) = crate::slice_figure::draw(&set, &layout, &pane, &options);
    picture.write_png(&image)?;
    let mut seen: Vec<usize> = ids.iter().filter(|&&i| i > 0).map(|&i| i as usize - 1).collect();
    seen.sort_unstable();
    seen.dedup();
    let caption = crate::slice_figure::caption(&pane);
    if args.report.json {
        let organs: Vec<&str> = seen.iter().map(|&o| set.organs[o].id.as_str()).collect();
        let out = json!({
            "out": args.picture.out, "width": width, "height": height, "plane": pane.plane.axis.name(),
            "at_mm": pane.plane.at, "radiological": pane.radiological, "mri": set.mri.is_some(),
            "mm_per_pixel": pane.mm_per_px, "centre_mm": pane.centre, "organs": organs, "caption": caption,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!("{}: {width}x{height}, {caption}, {} organs cut", args.picture.out.display(), seen.len());
    }
    Ok(true)
}
