//! Multi-panel figures with min/max thinning of long series.

use std::path::Path;

/// How [`Series::panels`](crate::Series::panels) lays out its panels.
#[derive(Debug, Clone, Copy)]
pub struct PanelLayout {
    /// Side by side (else stacked).
    pub columns: bool,
    /// y plotted as log10.
    pub log_y: bool,
    /// The x range shared by all panels.
    pub x_range: (f64, f64),
    /// The y range shared by all panels (else each panel's own).
    pub y_range: Option<(f64, f64)>,
}

impl crate::Series<'_> {
    /// Several plots in one PNG under `labels` (caption and the axis labels of every panel):
    /// side by side (`layout.columns`) or stacked, one per `(panel title, series)`, sharing
    /// the x range `layout.x_range` and (if given) the y range. With `layout.log_y` the y
    /// values are plotted as log10. Long series are thinned to a
    /// min/max envelope per pixel column so that peaks survive and the file stays small;
    /// series of at most 100 points (measurements) get a marker at every point.
    ///
    /// # Errors
    /// Drawing or file errors.
    pub fn panels(
        path: &Path,
        labels: &crate::Labels<'_>,
        panels: &[(&str, &[crate::Series<'_>])],
        layout: &PanelLayout,
    ) -> Result<(), Box<dyn std::error::Error>> {
        let crate::Labels {
            title,
            x: x_label,
            y: y_label,
        } = *labels;
        let PanelLayout {
            columns,
            log_y,
            x_range,
            y_range,
        } = *layout;
        use plotters::prelude::*;
        crate::init_fonts();
        let n = panels.len().max(1);
        let (w, h) = if columns {
            ((400 * n as u32 + 100).max(1000), 450)
        } else {
            (1000, 220 * n as u32 + 60)
        };
        let colors = [
            RGBColor(31, 119, 180),
            RGBColor(214, 39, 40),
            RGBColor(44, 160, 44),
            RGBColor(255, 127, 14),
        ];
        let ty = |v: f64| {
            if log_y {
                v.abs().max(1e-300).log10()
            } else {
                v
            }
        };
        let thinned: Vec<Vec<Vec<(f64, f64)>>> = panels
            .iter()
            .map(|(_, ss)| {
                ss.iter()
                    .map(|s| envelope(s.points, x_range, 1200, ty))
                    .collect()
            })
            .collect();
        let (y0, y1) = y_range.map_or_else(
            || {
                let (lo, hi) = thinned
                    .iter()
                    .flatten()
                    .flatten()
                    .filter(|p| p.1.is_finite())
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                        (l.min(p.1), h.max(p.1))
                    });
                if lo < hi {
                    (lo, hi)
                } else {
                    (lo - 1.0, lo + 1.0)
                }
            },
            |(a, b)| (ty(a), ty(b)),
        );
        crate::draw_png(path, (w, h), |root| {
            root.fill(&WHITE)?;
            let root = root.titled(title, ("sans-serif", 20))?;
            let areas = if columns {
                root.split_evenly((1, n))
            } else {
                root.split_evenly((n, 1))
            };
            for (i, ((name, ss), area)) in panels.iter().zip(&areas).enumerate() {
                let mut chart = ChartBuilder::on(area)
                    .caption(*name, ("sans-serif", 16))
                    .margin(8)
                    .x_label_area_size(if columns || i + 1 == n { 40 } else { 25 })
                    .y_label_area_size(70)
                    .build_cartesian_2d(x_range.0..x_range.1, y0..y1)?;
                let yl = crate::axis_label(y_label, log_y);
                chart
                    .configure_mesh()
                    .x_desc(if columns || i + 1 == n { x_label } else { "" })
                    .y_desc(if columns && i > 0 { String::new() } else { yl })
                    .x_labels(6)
                    .y_labels(6)
                    .label_style(("sans-serif", 13))
                    .draw()?;
                for (k, s) in ss.iter().enumerate() {
                    let color = colors[k % colors.len()];
                    let points = thinned[i][k].iter().copied();
                    crate::draw_line(&mut chart, points, (color, 1), s.label)?;
                    // Short series are measurements (one point per run): mark each point.
                    if thinned[i][k].len() <= MARKED_POINTS {
                        chart.draw_series(
                            thinned[i][k]
                                .iter()
                                .map(|&p| Circle::new(p, 2, color.filled())),
                        )?;
                    }
                }
                if ss.len() > 1 {
                    crate::draw_legend(&mut chart, 13)?;
                }
            }
            Ok(())
        })
    }
}

/// Series of at most this many points get a marker at every point.
const MARKED_POINTS: usize = 100;

/// Points of `points` inside `x_range`, y mapped by `ty`, thinned to the first, minimum,
/// maximum and last point of each of `bins` equal x bins (order kept).
fn envelope(
    points: &[(f64, f64)],
    x_range: (f64, f64),
    bins: usize,
    ty: impl Fn(f64) -> f64,
) -> Vec<(f64, f64)> {
    let inside: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.0 >= x_range.0 && p.0 <= x_range.1)
        .map(|p| (p.0, ty(p.1)))
        .collect();
    if inside.len() <= 4 * bins {
        return inside;
    }
    let width = (x_range.1 - x_range.0) / bins as f64;
    let mut out = Vec::with_capacity(4 * bins);
    let mut i = 0;
    while i < inside.len() {
        let b = ((inside[i].0 - x_range.0) / width).floor();
        let mut j = i;
        while j < inside.len() && ((inside[j].0 - x_range.0) / width).floor() == b {
            j += 1;
        }
        let bin = &inside[i..j];
        let (mut lo, mut hi) = (0, 0);
        for (k, p) in bin.iter().enumerate() {
            if p.1 < bin[lo].1 {
                lo = k;
            }
            if p.1 > bin[hi].1 {
                hi = k;
            }
        }
        let mut picks = [0, lo.min(hi), lo.max(hi), bin.len() - 1];
        picks.sort_unstable();
        let mut last = usize::MAX;
        for k in picks {
            if k != last {
                out.push(bin[k]);
                last = k;
            }
        }
        i = j;
    }
    out
}
