//! The mask experiment behind `vbrain masks` (thesis Figures 19 and 20) for white-noise,
//! pixel-tree, tabular and compensated tabular masks: faulty pixels per stacking level.
//!
//! - Per level, min/mean/max over the trials: printed, as CSV and as a PNG plot, and with
//!   `--json` as one object.

use anyhow::{bail, Result};
use serde_json::json;
use std::path::Path;
use vbrain::lab::masks::{self as experiment, Experiment};
use vbrain::transparency::MaskMethod;

pub struct MasksOptions<'a> {
    pub experiment: Experiment,
    pub out: &'a Path,
    pub json: bool,
}

fn colour(m: MaskMethod) -> (u8, u8, u8) {
    match m {
        MaskMethod::WhiteNoise => (120, 120, 120),
        MaskMethod::PixelTree => (40, 110, 200),
        MaskMethod::Tabular => (230, 150, 30),
        MaskMethod::TabularNec => (200, 40, 40),
    }
}

pub fn run(opts: &MasksOptions) -> Result<()> {
    let e = &opts.experiment;
    if e.n == 0 || e.n > vbrain::transparency::mask::MAX_SUBSAMPLES {
        bail!("mask of {} sub-samples outside 1..=1024", e.n);
    }
    if e.objects == 0 || e.trials == 0 {
        bail!("--objects and --trials must be at least 1");
    }
    if e.alpha.is_some_and(|a| !(0.0..=1.0).contains(&a)) {
        bail!("--alpha outside 0..1");
    }
    super::output_folder(opts.out)?;
    let bar = indicatif::ProgressBar::new(e.trials as u64);
    let started = std::time::Instant::now();
    let outcome = experiment::run(e, &MaskMethod::ALL, |t| bar.set_position(t as u64));
    bar.finish_and_clear();
    let seconds = started.elapsed().as_secs_f64();
    let csv = opts.out.join("masks.csv");
    vbrain::atomic::write(&csv, |w| {
        writeln!(w, "method,level,min_faulty,mean_faulty,max_faulty")?;
        for (m, s) in &outcome.methods {
            for l in 0..s.mean_faulty_per_level.len() {
                writeln!(
                    w,
                    "{},{},{:.3},{:.4},{:.3}",
                    m.name(),
                    l + 1,
                    s.min_faulty_per_level[l],
                    s.mean_faulty_per_level[l],
                    s.max_faulty_per_level[l]
                )?;
            }
        }
        Ok(())
    })?;
    let plot = opts.out.join("masks.png");
    let panel = |title: &str, pick: fn(&experiment::LevelStats) -> &Vec<f64>| super::plot::Panel {
        title: title.into(),
        x_label: "stacking level (1 = nearest)".into(),
        series: outcome
            .methods
            .iter()
            .map(|(m, s)| super::plot::Series {
                name: m.name().into(),
                colour: colour(*m),
                points: pick(s).iter().enumerate().map(|(l, &v)| ((l + 1) as f64, v)).collect(),
            })
            .collect(),
    };
    let side = (e.n as f64).sqrt();
    let what = format!("{side}x{side} masks, {} objects, {} trials", e.objects, e.trials);
    super::plot::write(
        &plot,
        1000,
        340,
        &[
            panel(&format!("maximum faulty pixels ({what})"), |s| &s.max_faulty_per_level),
            panel("mean faulty pixels", |s| &s.mean_faulty_per_level),
        ],
    )?;
    if opts.json {
        let methods: serde_json::Map<String, serde_json::Value> = outcome
            .methods
            .iter()
            .map(|(m, s)| Ok((m.name().to_string(), serde_json::to_value(s)?)))
            .collect::<Result<_>>()?;
        let out = json!({
            "mask_subsamples": e.n, "objects": e.objects, "trials": e.trials, "alpha": e.alpha, "k": e.k,
            "methods": methods, "tabular_row_entries": outcome.tabular_row_entries,
            "csv": csv, "plot": plot, "seconds": seconds,
        });
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!("{what}, K = {}, in {seconds:.1} s", e.k);
        println!("faulty pixels per stacking level (1 = nearest), min / mean / max over the trials:");
        print!("{:>5}", "level");
        for (m, _) in &outcome.methods {
            print!(" {:>22}", m.name());
        }
        println!();
        for l in 0..e.objects {
            print!("{:>5}", l + 1);
            for (_, s) in &outcome.methods {
                let cell = format!(
                    "{:.0} / {:.2} / {:.0}",
                    s.min_faulty_per_level[l], s.mean_faulty_per_level[l], s.max_faulty_per_level[l]
                );
                print!(" {cell:>22}");
            }
            println!();
        }
        let worst = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        print!("{:>5}", "worst");
        for (_, s) in &outcome.methods {
            let cell = format!("{:.2} / {:.0}", worst(&s.mean_faulty_per_level), worst(&s.max_faulty_per_level));
            print!(" {cell:>22}");
        }
        println!();
        println!("tabular row entries after the last mask: {}", outcome.tabular_row_entries);
        println!("wrote {} and {}", csv.display(), plot.display());
    }
    Ok(())
}
