//! Colour maps of `log10` of a positive field on a rectangular grid of samples (PNG via
//! `plotters`): the slip-rate space–time map of the 2-D slider and the fault-plane
//! snapshot of the 3-D slider.

use std::path::Path;

use plotters::prelude::*;

use crate::{cell_bounds, init_fonts, range, FieldMap, PlotResult};

/// Axes and colour range of a [`log_heat_map`].
pub struct HeatMapAxes<'a> {
    /// Caption (the colour range is appended).
    pub title: &'a str,
    /// Label of the horizontal axis.
    pub x_label: &'a str,
    /// Label of the vertical axis.
    pub y_label: &'a str,
    /// Colour range `[lo, hi]` in log10 units: blue at `lo`, red at `hi` (clamped).
    pub log10_range: (f64, f64),
}

/// Map of `log10 map.values[iy][ix]` (PNG, `size` pixels) over the increasing sample
/// coordinates `map.xs` (columns) and `map.ys` (rows); each sample fills the cell up to the
/// midpoints to its neighbours ([`cell_bounds`]). Non-positive values are drawn at the
/// bottom of the colour range.
///
/// # Errors
/// Drawing or file errors.
///
/// # Panics
/// If `values` has fewer than `ys.len()` rows or a row fewer than `xs.len()` entries.
pub fn log_heat_map(
    path: &Path,
    size: (u32, u32),
    axes: &HeatMapAxes<'_>,
    map: &FieldMap<'_>,
) -> PlotResult {
    let FieldMap { xs, ys, values } = *map;
    init_fonts();
    let (lo, hi) = axes.log10_range;
    crate::draw_png(path, size, |root| {
        root.fill(&WHITE)?;
        let (x0, x1) = range(xs.iter().copied());
        let (y0, y1) = range(ys.iter().copied());
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "{} (colour: log10 slip rate, {lo:.0} … {hi:.0})",
                    axes.title
                ),
                ("sans-serif", 20),
            )
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc(axes.x_label)
            .y_desc(axes.y_label)
            .label_style(("sans-serif", 15))
            .draw()?;
        chart.draw_series((0..ys.len()).flat_map(|iy| {
            (0..xs.len()).map(move |ix| {
                let (ya, yb) = cell_bounds(ys, iy);
                let (xa, xb) = cell_bounds(xs, ix);
                let v = values[iy][ix].max(1e-300).log10();
                let s = ((v - lo) / (hi - lo)).clamp(0.0, 1.0);
                let color = HSLColor((1.0 - s) * 0.66, 0.9, 0.5);
                Rectangle::new([(xa, ya), (xb, yb)], color.filled())
            })
        }))?;
        Ok(())
    })
}
