//! The programs of the rsf workspace — the paper's slider in 2-D and 3-D, the SEAS
//! benchmarks — and what they share: command-line parsing ([`cli`], clap), run folders,
//! the guard every program runs under, the statistics and figures of slider runs (PNG via
//! `plotters`). Not a library for users — the libraries are the `rsf*` crates; running,
//! recording and event detection are theirs; plotting lives here so that they never
//! depend on it.
//!
//! Features: `seas` (on by default) — the SEAS programs ([`seas_bp1`], [`seas_bp3`],
//! [`seas_bp5`], [`seas_bp6`], [`seas_bp7`], [`seas_bp8`]) and the fault network of [`stepover`]; without it the crate builds the slider's programs alone
//! (the workspace's main job does); `metis` — METIS's nested dissection.

use std::path::Path;

use plotters::prelude::*;

#[cfg(feature = "seas")]
pub mod bp5_pair;
pub mod cli;
pub mod config;
#[cfg(test)]
mod config_round_trip;
#[cfg(all(test, feature = "seas"))]
mod config_tests;
mod curved;
mod defaults;
pub mod distributed_sweep;
pub mod estimates;
pub mod fields;
mod flag_ranges;
pub mod guard;
mod heat_map;
pub mod memory;
#[cfg(feature = "seas")]
pub mod network;
pub mod on_ranks;
mod own_model;
mod panels;
pub mod pipping_slider;
mod process;
mod run;
pub mod run_folder;
mod seas_args;
#[cfg(feature = "seas")]
pub mod seas_bp1;
#[cfg(feature = "seas")]
pub mod seas_bp3;
#[cfg(feature = "seas")]
pub mod seas_bp5;
#[cfg(feature = "seas")]
pub mod seas_bp6;
#[cfg(feature = "seas")]
pub mod seas_bp7;
#[cfg(feature = "seas")]
pub mod seas_bp8;
#[cfg(feature = "seas")]
mod seas_overview;
pub mod session;
pub mod slider_3d;
#[cfg(feature = "seas")]
mod square_fault;
#[cfg(feature = "seas")]
pub mod stepover;
#[cfg(feature = "seas")]
pub use cli::SeasHeaderArgs;
pub use cli::{
    describe_method, describe_time_step, FrameArgs, IntegratorArgs, KernelArg, KernelArgs,
    PaperFigures, PaperSlider, PaperSlider3d, PaperSliderAt, ProgramScene, ResumeArgs, SliderArgs,
};
pub use curved::max_slip_rate_figure;
pub use heat_map::{log_heat_map, HeatMapAxes};
pub use own_model::{print_run, run_with_series, OwnRun, OwnRunArgs};
pub use panels::PanelLayout;
pub use process::{main_on_threads, main_with};
pub use run::{
    cpu_seconds, fit_exponent, fit_exponents, machine, old_wall_time, stats, step_control_json,
    write_summary, SliderRun, SliderStats,
};
pub use run_folder::FolderArgs;
#[cfg(feature = "seas")]
pub use seas_overview::seas_overview;
#[cfg(feature = "seas")]
pub use square_fault::volume_memory;

static FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// Registers the bundled DejaVu Sans as plotters' "sans-serif" (no system fonts needed).
pub fn init_fonts() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .map_err(|_| ())
            .expect("bundled font is valid");
    });
}

/// One line of a plot.
pub struct Series<'a> {
    /// Legend label.
    pub label: &'a str,
    /// Points `(x, y)`.
    pub points: &'a [(f64, f64)],
}

impl<'a> Series<'a> {
    /// A single unlabelled series, as a one-element list for the plot functions.
    pub fn alone(points: &'a [(f64, f64)]) -> [Series<'a>; 1] {
        [Series { label: "", points }]
    }

    /// One series per `(label, points)` of `lines`, in their order (a panel of
    /// [`Series::panels`], or a [`line_plot`]).
    pub fn labelled<L: AsRef<str>>(lines: &'a [(L, Vec<(f64, f64)>)]) -> Vec<Series<'a>> {
        lines
            .iter()
            .map(|(label, points)| Series {
                label: label.as_ref(),
                points,
            })
            .collect()
    }
}

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(0, 0, 0),
];

type PlotResult = Result<(), Box<dyn std::error::Error>>;

/// The drawing area of a figure: an RGB canvas in memory (plotters' bitmap backend).
pub type Canvas<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Draws a figure of `size` pixels (width, height) with `draw` on an RGB [`Canvas`] in
/// memory and writes it to `path` as an 8-bit RGB PNG file (crate `png`: plotters' own file
/// output pulls in the whole `image` crate, decoders included, which nothing else here
/// uses).
///
/// # Errors
/// What `draw` returns; the file cannot be written: `cannot write the figure `PATH`: …`.
pub fn draw_png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Canvas<'_>) -> PlotResult,
) -> PlotResult {
    let (width, height) = size;
    let mut rgb = vec![0u8; 3 * width as usize * height as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        draw(&root)?;
        root.present()?;
    }
    write_png(path, size, &rgb)
        .map_err(|e| format!("cannot write the figure `{}`: {e}", path.display()).into())
}

/// Writes `rgb` (`3 · width · height` bytes, rows from the top) to `path` as a PNG file.
fn write_png(
    path: &Path,
    (width, height): (u32, u32),
    rgb: &[u8],
) -> Result<(), png::EncodingError> {
    let file = std::io::BufWriter::new(std::fs::File::create(path)?);
    let mut encoder = png::Encoder::new(file, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()
}

fn range(points: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = points
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi > lo {
        (lo, hi)
    } else {
        (
            lo - 0.5 * lo.abs().max(1e-300),
            hi + 0.5 * hi.abs().max(1e-300),
        )
    }
}

/// The caption and axis labels of a figure.
#[derive(Debug, Clone, Copy)]
pub struct Labels<'a> {
    /// Caption.
    pub title: &'a str,
    /// Label of the horizontal axis.
    pub x: &'a str,
    /// Label of the vertical axis.
    pub y: &'a str,
}

/// Samples of a field on a rectangular grid: `values[iy][ix]` at the increasing
/// coordinates `xs` (columns) and `ys` (rows).
#[derive(Debug, Clone, Copy)]
pub struct FieldMap<'a> {
    /// Column coordinates.
    pub xs: &'a [f64],
    /// Row coordinates.
    pub ys: &'a [f64],
    /// One row of values per `ys` entry, one value per `xs` entry.
    pub values: &'a [Vec<f64>],
}

/// A chart of plain coordinates (x and y in f64) on a [`Canvas`].
type PlainChart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// The chart of a one-panel figure on `root` (filled white first): `title` in 22 px, a
/// margin of 15 px, 45 px below for the x labels and 80 px left for the y labels, over
/// `x` × `y`.
///
/// # Errors
/// Drawing errors.
fn titled_chart<'a, 'b>(
    root: &'a Canvas<'b>,
    title: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
) -> Result<PlainChart<'a, 'b>, Box<dyn std::error::Error>> {
    root.fill(&WHITE)?;
    Ok(ChartBuilder::on(root)
        .caption(title, ("sans-serif", 22))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(80)
        .build_cartesian_2d(x, y)?)
}

/// An axis's label `label`, `log10 label` where it is plotted as log10 (`log`).
fn axis_label(label: &str, log: bool) -> String {
    if log {
        format!("log10 {label}")
    } else {
        label.to_string()
    }
}

/// Draws `points` into `chart` as a line of `color`, `width` px wide, named `label` in the
/// legend (a stroke of 20 px, 2 px wide).
///
/// # Errors
/// Drawing errors.
fn draw_line(
    chart: &mut PlainChart<'_, '_>,
    points: impl IntoIterator<Item = (f64, f64)>,
    (color, width): (RGBColor, u32),
    label: &str,
) -> PlotResult {
    chart
        .draw_series(LineSeries::new(points, color.stroke_width(width)))?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    Ok(())
}

/// Draws the legend of `chart`: white at 80 %, a black border, labels in `size` px.
///
/// # Errors
/// Drawing errors.
fn draw_legend<'a, 'b: 'a>(chart: &mut PlainChart<'a, 'b>, size: u32) -> PlotResult {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", size))
        .draw()?;
    Ok(())
}

/// Line plot (PNG, 1000×600). With `log_y` (`log_x`), y (x) is plotted as log10 and
/// labelled so.
///
/// # Errors
/// Drawing or file errors.
pub fn line_plot(
    path: &Path,
    labels: &Labels<'_>,
    series: &[Series<'_>],
    log_y: bool,
    log_x: bool,
) -> PlotResult {
    let Labels {
        title,
        x: x_label,
        y: y_label,
    } = *labels;
    init_fonts();
    let tf = |v: f64, log: bool| if log { v.max(1e-300).log10() } else { v };
    let (x0, x1) = range(
        series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| tf(p.0, log_x))),
    );
    let (y0, y1) = range(
        series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| tf(p.1, log_y))),
    );
    crate::draw_png(path, (1000, 600), |root| {
        let mut chart = titled_chart(root, title, x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc(axis_label(x_label, log_x))
            .y_desc(axis_label(y_label, log_y))
            .label_style(("sans-serif", 15))
            .draw()?;
        for (i, s) in series.iter().enumerate() {
            let points = s.points.iter().map(|p| (tf(p.0, log_x), tf(p.1, log_y)));
            draw_line(&mut chart, points, (COLORS[i % COLORS.len()], 2), s.label)?;
        }
        if series.len() > 1 || !series[0].label.is_empty() {
            draw_legend(&mut chart, 15)?;
        }
        Ok(())
    })
}

/// Edges `(a, b)` of the cell around sample `i` of the increasing coordinates `v`: the
/// midpoints to its neighbours (the sample itself at either end).
pub fn cell_bounds(v: &[f64], i: usize) -> (f64, f64) {
    let a = if i > 0 { 0.5 * (v[i] + v[i - 1]) } else { v[0] };
    let b = if i + 1 < v.len() {
        0.5 * (v[i] + v[i + 1])
    } else {
        v[i]
    };
    (a, b)
}

/// Space–time map of `log10 value` (rows `map.ys`: times, columns `map.xs`: positions
/// along the frictional boundary), PNG 1000×600, colour from blue (low) to red (high) over
/// `[lo, hi]` in log10 units.
///
/// # Errors
/// Drawing or file errors.
pub fn space_time_map(
    path: &Path,
    title: &str,
    map: &FieldMap<'_>,
    log10_range: (f64, f64),
) -> PlotResult {
    let axes = HeatMapAxes {
        title,
        x_label: "x on the frictional boundary (m)",
        y_label: "t (s)",
        log10_range,
    };
    log_heat_map(path, (1000, 600), &axes, map)
}

/// Bytes of a memory budget given in GiB by the command-line flag `flag` (for
/// `rsf::method::SolverOptions::memory_budget_bytes`).
///
/// # Errors
/// A message naming the flag if `gib` is not positive and finite.
pub fn memory_budget_bytes(flag: &str, gib: f64) -> Result<usize, String> {
    if !(gib.is_finite() && gib > 0.0) {
        return Err(format!(
            "{flag} must be positive and finite, got {}",
            rsf_numeric::written(gib)
        ));
    }
    Ok((gib * (1u64 << 30) as f64) as usize)
}
