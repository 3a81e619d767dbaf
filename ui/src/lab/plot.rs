//! Line charts for the benchmark commands: stacked panels, one line per series.
//!
//! - Written as a PNG, atomically.
//! - Text uses egui's bundled font, so no system fonts are needed.

use anyhow::{anyhow, Result};
use plotters::prelude::*;
use std::path::Path;

pub struct Series {
    pub name: String,
    pub colour: (u8, u8, u8),
    pub points: Vec<(f64, f64)>,
}

pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub series: Vec<Series>,
}

/// Draws `panels` one above the other into a `width` x (`panel_height` x panels) PNG.
pub fn write(path: &Path, width: u32, panel_height: u32, panels: &[Panel]) -> Result<()> {
    static FONT: std::sync::Once = std::sync::Once::new();
    FONT.call_once(|| {
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT);
    });
    let (w, h) = (width, panel_height * panels.len().max(1) as u32);
    let mut buf = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow!("plot: {e}"))?;
        for (area, panel) in root.split_evenly((panels.len().max(1), 1)).iter().zip(panels) {
            let points = || panel.series.iter().flat_map(|s| s.points.iter());
            let x_max = points().map(|p| p.0).fold(1.0, f64::max);
            let x_min = points().map(|p| p.0).fold(x_max, f64::min).min(0.0);
            let y_max = points().map(|p| p.1).fold(1e-9, f64::max) * 1.1;
            let mut chart = ChartBuilder::on(area)
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(56)
                .caption(&panel.title, ("sans-serif", 20))
                .build_cartesian_2d(x_min..x_max, 0.0..y_max)
                .map_err(|e| anyhow!("plot: {e}"))?;
            chart
                .configure_mesh()
                .x_desc(&panel.x_label)
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(|e| anyhow!("plot: {e}"))?;
            for s in &panel.series {
                let c = RGBColor(s.colour.0, s.colour.1, s.colour.2);
                chart
                    .draw_series(LineSeries::new(s.points.iter().copied(), c.stroke_width(2)))
                    .map_err(|e| anyhow!("plot: {e}"))?
                    .label(&s.name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .draw()
                .map_err(|e| anyhow!("plot: {e}"))?;
        }
        root.present().map_err(|e| anyhow!("plot: {e}"))?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).ok_or_else(|| anyhow!("plot buffer"))?;
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
    vbrain::atomic::write(path, |w| w.write_all(&png))?;
    Ok(())
}
