//! The overview figure of a SEAS benchmark run from its slip profiles.

use std::path::Path;

use plotters::prelude::*;
use rsf_seas::SECONDS_PER_YEAR;

/// `overview.png` in `dir`: slip profiles (every 5 years between events in blue, every
/// second during events in red, as in the benchmark descriptions' figures) against the
/// position along the fault (`axis`, km, downwards), and the maximum slip rate on the fault
/// against time, both from the slip profile file `profile` (`devol.dat`, `slip.dat`) in
/// `dir`; `events` for the caption. Absolute slip (a normal fault's is negative).
///
/// # Errors
/// A missing or malformed profile file; drawing errors.
pub fn seas_overview(
    dir: &Path,
    profile: &str,
    axis: &str,
    events: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    crate::init_fonts();
    let text = std::fs::read_to_string(dir.join(profile))?;
    let mut lines = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip_while(|l| !l.starts_with("0 0"));
    let depths: Vec<f64> = lines
        .next()
        .ok_or_else(|| format!("{profile} has no row of positions"))?
        .split_whitespace()
        .skip(2)
        .map(|x| x.parse::<f64>().map(|z| z / 1e3))
        .collect::<Result<_, _>>()?;
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split_whitespace().map(|x| x.parse::<f64>()).collect())
        .collect::<Result<_, _>>()?;
    let slip_max = rows
        .iter()
        .flat_map(|r| r[2..].iter().map(|x| x.abs()))
        .fold(1e-3, f64::max);
    let path = dir.join("overview.png");
    crate::draw_png(&path, (1200, 600), |root| {
        root.fill(&WHITE)?;
        let (left, right) = root.split_horizontally(600);
        let mut chart = ChartBuilder::on(&left)
            .caption(
                "slip (blue: every 5 yr, red: every 1 s in events)",
                ("sans-serif", 16),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(
                0.0..slip_max * 1.02,
                -depths.last().copied().unwrap_or(40.0)..0.0,
            )?;
        chart
            .configure_mesh()
            .x_desc("slip (m)")
            .y_desc(axis)
            .y_label_formatter(&|y| format!("{:.0}", -y))
            .draw()?;
        for r in &rows {
            let colour = if r[1] >= (1e-3f64).log10() { RED } else { BLUE };
            chart.draw_series(LineSeries::new(
                r[2..].iter().zip(&depths).map(|(&s, &z)| (s.abs(), -z)),
                colour.stroke_width(1),
            ))?;
        }
        let t_max = rows.last().map_or(1.0, |r| r[0] / SECONDS_PER_YEAR);
        let mut chart = ChartBuilder::on(&right)
            .caption(
                format!("max slip rate; {events} events"),
                ("sans-serif", 16),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..t_max.max(1e-9), -13.0..1.0)?;
        chart
            .configure_mesh()
            .x_desc("time (years)")
            .y_desc("log10 max slip rate (m/s)")
            .draw()?;
        chart.draw_series(LineSeries::new(
            rows.iter()
                .map(|r| (r[0] / SECONDS_PER_YEAR, r[1].max(-13.0))),
            BLACK.stroke_width(1),
        ))?;
        Ok(())
    })
}
