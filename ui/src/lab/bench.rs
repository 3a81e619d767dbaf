//! The culling benchmark behind `vbrain bench`: the thesis's Virtual Brain run (camera orbiting
//! the set) over the listed culling modes.
//!
//! - Reports a summary, a CSV of every frame, a PNG plot like thesis Figure 22 (culled % and
//!   frame time per frame) and, with `--json`, a machine-readable summary keyed by mode.

use anyhow::{bail, Result};
use serde_json::json;
use std::path::Path;
use vbrain::cull::{CullMode, CullSettings};
use vbrain::lab::bench::{self, FrameRecord};

pub struct BenchOptions<'a> {
    pub frames: usize,
    pub size: (u32, u32),
    pub modes: &'a [CullMode],
    pub route: vbrain::lab::bench::Route,
    pub json: bool,
    pub out: &'a Path,
    pub settings: CullSettings,
    /// How faded organs are drawn in every frame.
    pub transparency: vbrain::transparency::TransparencySettings,
    /// The set's pre-computed occluders.
    pub database: Option<vbrain::cull::database::Database>,
    /// Clip planes cutting every frame.
    pub section: vbrain::clip::Section,
}

pub fn run(set: &vbrain::organ_set::OrganSet, layout: &vbrain::layout::Layout, opts: &BenchOptions) -> Result<()> {
    let modes = opts.modes;
    if modes.is_empty() {
        bail!("no culling mode given");
    }
    if opts.frames == 0 {
        bail!("--frames must be at least 1");
    }
    super::output_folder(opts.out)?;
    let gpu = vbrain::render::GpuContext::headless()?;
    let bar = indicatif::ProgressBar::new((opts.frames * modes.len()) as u64);
    let records = bench::run(
        &gpu,
        set,
        layout,
        &bench::Run {
            size: [opts.size.0, opts.size.1],
            frames: opts.frames,
            modes,
            settings: opts.settings,
            transparency: opts.transparency,
            route: opts.route,
            database: opts.database.as_ref(),
            section: &opts.section,
        },
        &mut |d, _| bar.set_position(d as u64),
    )?;
    bar.finish_and_clear();
    let csv = opts.out.join("bench.csv");
    vbrain::atomic::write(&csv, |w| write_csv(&records, w))?;
    let plot = opts.out.join("bench.png");
    write_plot(&records, modes, &plot)?;
    let triangles = set.triangle_count();
    let drawn_triangles = records.first().map(|r| r.triangles).unwrap_or(0);
    if opts.json {
        let mut out = serde_json::Map::new();
        let none = modes.contains(&CullMode::None).then(|| bench::summarise(&records, CullMode::None));
        for &m in modes {
            let s = bench::summarise(&records, m);
            let mut value = serde_json::to_value(s)?;
            if let (Some(none), serde_json::Value::Object(fields)) = (&none, &mut value) {
                fields.insert("break_even_ns_per_triangle".into(), json!(bench::break_even_ns(&s, none)));
            }
            out.insert(m.name().into(), value);
        }
        let none_draw = none.as_ref().and_then(bench::draw_ns_per_triangle);
        out.insert("draw_ns_per_triangle".into(), json!(none_draw));
        out.insert("triangles".into(), json!(triangles));
        out.insert("triangles_drawn_organs".into(), json!(drawn_triangles));
        out.insert("frames".into(), json!(opts.frames));
        out.insert("route".into(), json!(opts.route.name()));
        out.insert("size".into(), json!([opts.size.0, opts.size.1]));
        out.insert("transparency".into(), json!(opts.transparency.mode.name()));
        out.insert("subsamples".into(), json!(opts.transparency.subsamples));
        out.insert("adapter".into(), json!(gpu.adapter_description()));
        out.insert("csv".into(), json!(csv));
        out.insert("plot".into(), json!(plot));
        println!("{}", serde_json::to_string_pretty(&serde_json::Value::Object(out))?);
    } else {
        println!(
            "{} frames at {}x{}, {} triangles in drawn organs, faded ones as {} ({} sub-samples), on {}",
            opts.frames,
            opts.size.0,
            opts.size.1,
            drawn_triangles,
            opts.transparency.mode.name(),
            opts.transparency.subsamples,
            gpu.adapter_description()
        );
        println!(
            "{:<10} {:>14} {:>13} {:>11} {:>12} {:>11} {:>15}",
            "mode", "median frame", "median cull", "occluders", "mean culled", "max culled", "hidden culled"
        );
        for &m in modes {
            let s = bench::summarise(&records, m);
            println!(
                "{:<10} {:>11.2} ms {:>10.3} ms {:>8.3} ms {:>10.1} % {:>9.1} % {:>13.1} %",
                m.name(),
                s.median_frame_ms,
                s.median_cull_ms,
                s.median_occluders_ms,
                s.mean_culled_percent,
                s.max_culled_percent,
                s.hidden_leaves_culled_percent
            );
        }
        if let Some(none) = modes.contains(&CullMode::None).then(|| bench::summarise(&records, CullMode::None)) {
            let here = bench::draw_ns_per_triangle(&none).unwrap_or(0.0);
            for &m in modes.iter().filter(|&&m| m != CullMode::None) {
                if let Some(ns) = bench::break_even_ns(&bench::summarise(&records, m), &none) {
                    let verdict = if here > ns { "pays here" } else { "does not pay here" };
                    println!(
                        "{}: pays while a triangle takes over {ns:.1} ns to draw; this adapter takes {here:.1} ns ({verdict})",
                        m.name()
                    );
                }
            }
        }
        println!("wrote {} and {}", csv.display(), plot.display());
    }
    Ok(())
}

fn write_csv(records: &[FrameRecord], w: &mut dyn std::io::Write) -> std::io::Result<()> {
    writeln!(w, "mode,frame,cull_ms,occluders_ms,frame_ms,gpu_ms,triangles,triangles_drawn,culled_percent,occluder_source,occluder_leaves,occluder_triangles,nodes_tested,back_face_culled,clip_culled,inside_culled,exact_hidden_leaves,culled_hidden_leaves,exact_hidden_triangles")?;
    for r in records {
        writeln!(
            w,
            "{},{},{:.4},{:.4},{:.4},{},{},{},{:.3},{},{},{},{},{},{},{},{},{},{}",
            r.mode.name(),
            r.frame,
            r.cull_ms,
            r.occluders_ms,
            r.frame_ms,
            r.gpu_ms.map_or(String::new(), |g| format!("{g:.4}")),
            r.triangles,
            r.triangles_drawn,
            r.culled_percent,
            r.source.map_or("", |s| match s {
                vbrain::cull::OccluderSource::ProjectedSize => "ps",
                vbrain::cull::OccluderSource::Mos => "mos",
            }),
            r.occluder_leaves,
            r.occluder_triangles,
            r.nodes_tested,
            r.back_face_culled,
            r.clip_culled,
            r.inside_culled,
            r.exact_hidden_leaves,
            r.culled_hidden_leaves,
            r.exact_hidden_triangles
        )?;
    }
    Ok(())
}

fn colour(mode: CullMode) -> (u8, u8, u8) {
    match mode {
        CullMode::None => (90, 90, 90),
        CullMode::Frustum => (40, 110, 200),
        CullMode::Occlusion => (220, 70, 40),
    }
}

/// Two panels over the frames: culled percent (top) and frame time (bottom), one line per mode.
fn write_plot(records: &[FrameRecord], modes: &[CullMode], path: &Path) -> Result<()> {
    type Value = fn(&FrameRecord) -> f64;
    let panel = |title: &str, value: Value| super::plot::Panel {
        title: title.into(),
        x_label: "frame".into(),
        series: modes
            .iter()
            .map(|&m| super::plot::Series {
                name: m.name().into(),
                colour: colour(m),
                points: records.iter().filter(|r| r.mode == m).map(|r| (r.frame as f64, value(r))).collect(),
            })
            .collect(),
    };
    let panels = [panel("culled triangles (%)", |r| r.culled_percent), panel("frame time (ms)", |r| r.frame_ms)];
    super::plot::write(path, 1000, 360, &panels)
}
