//! One PNG per scene: frame time (÷ the `none` frame) against relative RMSE
//! and against FLIP, log–log, one colour per method, the counts written
//! beside the points, and the Pareto front of time against RMSE drawn.

use super::report::pareto_front;
use super::scenes::{Config, Scene};
use super::Row;
use anyhow::{anyhow, Context as _, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

const SIZE: (u32, u32) = (1400, 620);
const FONT: &str = "sans-serif";

/// Registers egui's embedded Ubuntu Light as plotters' sans-serif (no
/// system fonts are needed).
pub(crate) fn register_font() -> Result<()> {
    static DONE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, epaint_default_fonts::UBUNTU_LIGHT)
            .is_ok()
    });
    ok.then_some(())
        .ok_or_else(|| anyhow!("the chart font did not load"))
}

/// The series a row belongs to, and its colour: the method's id with its
/// configuration's series text, in the configuration's colour or the
/// method's own (the registry's: `MethodInfo::bench`, `colour`).
fn series(c: Config) -> (String, RGBColor) {
    let (text, colour) = c.knob.series;
    let [r, g, b] = colour.unwrap_or(c.method.sss().colour);
    (format!("{}{text}", c.method.id()), RGBColor(r, g, b))
}

/// An axis label with three significant digits and no float noise.
fn significant(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn log_range(values: impl Iterator<Item = f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo.is_finite() {
        lo / 1.4..hi * 1.4
    } else {
        1e-4..1.0
    }
}

fn panel(
    area: &DrawingArea<BitMapBackend, Shift>,
    rows: &[&Row],
    y_desc: &str,
    y: fn(&Row) -> f64,
    front: bool,
) -> Result<()> {
    let plotted = || rows.iter().filter(|r| !r.config.method.sss().ground_truth);
    let x_range = log_range(plotted().map(|r| r.frame_ratio()));
    let y_range = log_range(plotted().map(|r| y(r)));
    let mut chart = ChartBuilder::on(area)
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(x_range.log_scale(), y_range.log_scale())
        .map_err(|e| anyhow!("{e}"))?;
    chart
        .configure_mesh()
        .x_desc("frame time ÷ `none` frame (same run)")
        .y_desc(y_desc)
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .x_label_formatter(&|v| significant(*v))
        .y_label_formatter(&|v| significant(*v))
        .max_light_lines(4)
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    let points: Vec<&Row> = rows
        .iter()
        .copied()
        .filter(|r| y(r) > 0.0 && !r.config.method.sss().ground_truth)
        .collect();
    if front {
        let line: Vec<(f64, f64)> = pareto_front(&points)
            .iter()
            .map(|r| (r.frame_ratio(), y(r)))
            .collect();
        chart
            .draw_series(LineSeries::new(line, BLACK.stroke_width(2)))
            .map_err(|e| anyhow!("{e}"))?
            .label("Pareto front (time vs RMSE)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK.stroke_width(2)));
    }
    let mut names: Vec<String> = Vec::new();
    for r in &points {
        let (name, colour) = series(r.config);
        let first = !names.contains(&name);
        // The count sits beside its dot (pixel offsets from the point).
        let count = match r.config.count() {
            0 => String::new(),
            n => n.to_string(),
        };
        let dot = chart
            .draw_series(std::iter::once(
                EmptyElement::at((r.frame_ratio(), y(r)))
                    + Circle::new((0, 0), 5, colour.filled())
                    + Text::new(count, (7, -14), (FONT, 13).into_font().color(&colour)),
            ))
            .map_err(|e| anyhow!("{e}"))?;
        if first {
            names.push(name.clone());
            dot.label(name.as_str())
                .legend(move |(x, y)| Circle::new((x + 9, y), 5, colour.filled()));
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// Draws `scene`'s chart into `path` (PNG, written atomically).
pub fn write(path: &Path, scene: &Scene, rows: &[Row]) -> Result<()> {
    register_font()?;
    let rows: Vec<&Row> = rows.iter().filter(|r| r.scene == scene.id).collect();
    let mut buffer = vec![255u8; (SIZE.0 * SIZE.1 * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, SIZE).into_drawing_area();
        let root = root
            .titled(&format!("{}: run time against error", scene.id), (FONT, 24))
            .map_err(|e| anyhow!("{e}"))?;
        let (left, right) = root.split_horizontally(SIZE.0 / 2);
        panel(
            &left,
            &rows,
            "relative RMSE (linear HDR, SSS pixels)",
            |r| r.rel_rmse,
            true,
        )?;
        panel(
            &right,
            &rows,
            "mean FLIP (SSS pixels)",
            |r| r.flip_sss,
            false,
        )?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    let img = image::RgbImage::from_raw(SIZE.0, SIZE.1, buffer).context("chart buffer size")?;
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)?;
    crate::fsutil::write_atomic(path, &png).with_context(|| format!("writing {}", path.display()))
}
