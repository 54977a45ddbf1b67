//! The error-against-CPU-time panels of a study.

use std::path::Path;

use rsf_programs::{Labels, PanelLayout, Series};

use crate::common::Res;

/// One labelled line of a plot: `(label, [(seconds, error)])`.
pub(crate) type Line = (String, Vec<(f64, f64)>);

/// One plotted point: method label, seconds, the three errors.
pub(crate) type Point = (String, f64, [Option<f64>; 3]);

/// Error-vs-seconds panels (a), (b), (c) [+ extra], one line per method, log–log.
pub(crate) fn plot_panels(
    path: &Path,
    title: &str,
    points: &[Point],
    extra: Option<(&str, Vec<Line>)>,
) -> Res<()> {
    let mut labels: Vec<String> = Vec::new();
    for p in points {
        if !labels.contains(&p.0) {
            labels.push(p.0.clone());
        }
    }
    let names = [
        "(a) u_x(x0, 0.6T) - u_x(x0, 0)",
        "(b) first slip-event time",
        "(c) RMS ln slip rate, [T/4, 0.6T]",
    ];
    let mut data: Vec<Vec<Line>> = (0..3)
        .map(|q| {
            labels
                .iter()
                .map(|l| {
                    let pts = points
                        .iter()
                        .filter(|p| &p.0 == l)
                        .filter_map(|p| p.2[q].filter(|e| *e > 0.0).map(|e| (p.1, e)))
                        .map(|(s, e)| (s.log10(), e.log10()))
                        .collect();
                    (l.clone(), pts)
                })
                .collect()
        })
        .collect();
    let mut titles: Vec<&str> = names.to_vec();
    if let Some((name, series)) = extra {
        titles.push(name);
        data.push(
            series
                .into_iter()
                .map(|(l, p)| {
                    let p = p
                        .into_iter()
                        .filter(|q| q.1 > 0.0)
                        .map(|(s, e)| (s.log10(), e.log10()))
                        .collect();
                    (l, p)
                })
                .collect(),
        );
    }
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in data.iter().flatten() {
        for p in &s.1 {
            x0 = x0.min(p.0);
            x1 = x1.max(p.0);
        }
    }
    let pad = 0.05 * (x1 - x0).max(0.1);
    let series: Vec<Vec<Series<'_>>> = data.iter().map(|panel| Series::labelled(panel)).collect();
    let panels: Vec<(&str, &[Series<'_>])> = titles
        .iter()
        .zip(&series)
        .map(|(t, s)| (*t, s.as_slice()))
        .collect();
    Series::panels(
        path,
        &Labels {
            title,
            x: "log10 CPU time (s)",
            y: "log10 relative error",
        },
        &panels,
        &PanelLayout {
            columns: true,
            log_y: false,
            x_range: (x0 - pad, x1 + pad),
            y_range: None,
        },
    )
}
