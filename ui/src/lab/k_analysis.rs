//! The k analysis of `vbrain bench-transparency` (Callahan 2005, Fig. 4.7 and Table 4.2): per
//! bench view, the share of pixels that need k <= 2, 3..=6 and > 6 k-buffer slots for an exact
//! result.
//!
//! - A pixel needs as many slots as it has faded fragments in front of the opaque organs (then no
//!   drawing order can make it wrong); the stream's rough sort often makes fewer do.
//! - Shares are of the pixels with at least one faded fragment, in per cent.

use anyhow::Result;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// One view's shares.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KShares {
    pub view: String,
    pub transparent_organs: usize,
    /// Pixels with at least one faded fragment.
    pub pixels: usize,
    pub k_at_most_2: f64,
    pub k_3_to_6: f64,
    pub k_over_6: f64,
    /// The most fragments of any pixel.
    pub most: u32,
}

/// The shares of `counts` (faded fragments per pixel).
pub fn shares(view: &str, transparent_organs: usize, counts: &[u32]) -> KShares {
    let seen: Vec<u32> = counts.iter().copied().filter(|&c| c > 0).collect();
    let share =
        |keep: fn(u32) -> bool| 100.0 * seen.iter().filter(|&&c| keep(c)).count() as f64 / seen.len().max(1) as f64;
    KShares {
        view: view.into(),
        transparent_organs,
        pixels: seen.len(),
        k_at_most_2: share(|c| c <= 2),
        k_3_to_6: share(|c| (3..=6).contains(&c)),
        k_over_6: share(|c| c > 6),
        most: seen.iter().copied().max().unwrap_or(0),
    }
}

/// Writes `kbuffer-k.csv` and `kbuffer-k.png` into `out`; returns their paths.
pub fn write(out: &Path, rows: &[KShares]) -> Result<(PathBuf, PathBuf)> {
    let csv = out.join("kbuffer-k.csv");
    vbrain::atomic::write(&csv, |w| {
        writeln!(w, "view,transparent_organs,pixels,k_at_most_2_percent,k_3_to_6_percent,k_over_6_percent,most")?;
        for r in rows {
            writeln!(
                w,
                "{},{},{},{:.2},{:.2},{:.2},{}",
                vbrain::lab::csv_field(&r.view),
                r.transparent_organs,
                r.pixels,
                r.k_at_most_2,
                r.k_3_to_6,
                r.k_over_6,
                r.most
            )?;
        }
        Ok(())
    })?;
    let plot = out.join("kbuffer-k.png");
    let series = |name: &str, colour, value: fn(&KShares) -> f64| super::plot::Series {
        name: name.into(),
        colour,
        points: rows.iter().map(|r| (r.transparent_organs as f64, value(r))).collect(),
    };
    super::plot::write(
        &plot,
        800,
        340,
        &[super::plot::Panel {
            title: "k-buffer slots a pixel needs for an exact result (% of pixels with faded organs)".into(),
            x_label: "transparent organs in the view".into(),
            series: vec![
                series("k <= 2", (40, 160, 80), |r| r.k_at_most_2),
                series("k 3-6", (230, 150, 30), |r| r.k_3_to_6),
                series("k > 6", (200, 40, 40), |r| r.k_over_6),
            ],
        }],
    )?;
    Ok((csv, plot))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_count_only_pixels_with_faded_fragments() {
        let s = shares("v", 3, &[0, 0, 1, 2, 3, 6, 7, 12]);
        assert_eq!((s.pixels, s.most), (6, 12));
        assert!((s.k_at_most_2 - 100.0 / 3.0).abs() < 1e-9);
        assert!((s.k_3_to_6 - 100.0 / 3.0).abs() < 1e-9);
        assert!((s.k_over_6 - 100.0 / 3.0).abs() < 1e-9);
        assert_eq!(shares("empty", 0, &[0, 0]).k_at_most_2, 0.0);
    }
}
