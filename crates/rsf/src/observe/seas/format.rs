//! The text of the SEAS files: C-style number formats, the `#` header lines and field-list
//! lines, the date of a run.

use super::setup::{ProfileQuantity, SeasLayout, SeasSetup};

/// The two field-list lines of a profile of `quantity` in `layout`: the coordinate (`z` or
/// `xd`, whose values the first data row holds), then `t max_slip_rate` and the quantity.
pub(super) fn profile_field_lines(layout: &SeasLayout, quantity: ProfileQuantity) -> [String; 2] {
    [
        layout.coordinate().1.to_owned(),
        format!("t max_slip_rate {}", quantity.field()),
    ]
}

/// The field-list line of a station file (after its `#` lines).
pub(super) fn station_field_line(layout: &SeasLayout) -> String {
    layout
        .station_columns()
        .iter()
        .map(|(name, _)| *name)
        .collect::<Vec<_>>()
        .join(" ")
}

/// Formats `x` as C's `%W.PE` (`1.2345E+03`), right-aligned in `width`: the SEAS
/// files' number format (e.g. `c_exp(t, 13, 21)` for a time column, `c_exp(x, 6, 14)`
/// for the others).
pub fn c_exp(x: f64, precision: usize, width: usize) -> String {
    let s = format!("{x:.precision$E}");
    let (mantissa, exponent) = s.split_once('E').unwrap_or((&s, "0"));
    let e: i32 = exponent.parse().unwrap_or(0);
    let sign = if e < 0 { '-' } else { '+' };
    format!(
        "{:>width$}",
        format!("{mantissa}E{sign}{:02}", e.unsigned_abs())
    )
}

/// The header lines every file shares (`#` lines): problem, author, date, code, version,
/// element size, location, and the run's smallest and largest time step (`steps`,
/// `(τ_min, τ_max)` once a step was taken) and the data rows in the file
/// (`num_time_steps`, the benchmark's name for it). Only `setup`'s `problem`, `modeler`,
/// `date` and `element_size` are read.
pub fn common_header(
    setup: &SeasSetup,
    location: &str,
    steps: Option<(f64, f64)>,
    rows: usize,
) -> String {
    let mut h = format!(
        "# This is the file header:\n# problem={}\n# author={}\n# date={}\n# code=rsf\n\
         # code_version={}\n# element_size={} m\n# location={location}",
        setup.problem,
        setup.modeler,
        setup.date,
        env!("CARGO_PKG_VERSION"),
        setup.element_size
    );
    if let Some((lo, hi)) = steps {
        h.push_str(&format!(
            "\n# minimum_time_step={lo:e}\n# maximum_time_step={hi:e}"
        ));
    }
    h.push_str(&format!("\n# num_time_steps={rows}"));
    h
}

/// A station file's header: the shared lines, one `# Column #k` line per column, the
/// field-list line.
pub(super) fn station_header(
    setup: &SeasSetup,
    depth: f64,
    steps: Option<(f64, f64)>,
    rows: usize,
) -> String {
    let mut h = common_header(
        setup,
        &format!(
            "on fault, {} km {}",
            depth / 1e3,
            setup.layout.coordinate().0
        ),
        steps,
        rows,
    );
    for (i, (_, description)) in setup.layout.station_columns().iter().enumerate() {
        h.push_str(&format!("\n# Column #{} = {description}", i + 1));
    }
    h.push_str("\n# The line below lists the names of the data fields:\n");
    h.push_str(&station_field_line(&setup.layout));
    h
}

/// The header of a profile file of `quantity` (`devol.dat`, `slip.dat`,
/// `shear_stress.dat`, `normal_stress.dat`): the shared lines, the columns' descriptions,
/// the two field-list lines (the first data row, `0 0` and the positions, follows).
pub(super) fn profile_header(
    setup: &SeasSetup,
    quantity: ProfileQuantity,
    steps: Option<(f64, f64)>,
    rows: usize,
) -> String {
    let (word, symbol) = setup.layout.coordinate();
    let plural = if word == "depth" {
        "depths"
    } else {
        "down-dip distances"
    };
    let mut h = common_header(
        setup,
        &format!(
            "{} profiles along the fault's {word} {symbol}",
            quantity.field()
        ),
        steps,
        rows,
    );
    h.push_str(&format!(
        "\n# Column #1 = Time (s)\n# Column #2 = Max slip rate on the fault (log10 m/s)\n\
         # Column #3 = {} at the {plural} {symbol} (m) of the first data row, one column per {word}\n\
         # The first data row is 0 0 followed by the {plural} {symbol} (m); every other row is a time.\n\
         # The two lines below list the names of the data fields:",
        quantity.description()
    ));
    for line in profile_field_lines(&setup.layout, quantity) {
        h.push('\n');
        h.push_str(&line);
    }
    h
}

/// The columns of a station off the fault with a field of `components` components: `t`,
/// `disp_1 …`, `vel_1 …`, with their descriptions (`depth_axis` the vertical component,
/// positive down, for a vector field).
pub(super) fn surface_columns(components: usize, depth_axis: usize) -> Vec<(String, String)> {
    let what = |c: usize| match components {
        1 => "the field's component".to_owned(),
        _ if c == depth_axis => "vertical, positive down".to_owned(),
        2 => "horizontal".to_owned(),
        _ => format!("along x{}", c + 1),
    };
    let column = |name: &str, unit: &str, c: usize| {
        (
            format!("{}_{}", name, c + 1),
            format!(
                "{} {}, {} ({unit})",
                if name == "disp" {
                    "Displacement"
                } else {
                    "Velocity"
                },
                c + 1,
                what(c)
            ),
        )
    };
    std::iter::once(("t".to_owned(), "Time (s)".to_owned()))
        .chain((0..components).map(|c| column("disp", "m", c)))
        .chain((0..components).map(|c| column("vel", "m/s", c)))
        .collect()
}

/// The field-list line of a station off the fault.
pub(super) fn surface_field_line(components: usize, depth_axis: usize) -> String {
    surface_columns(components, depth_axis)
        .into_iter()
        .map(|(name, _)| name)
        .collect::<Vec<_>>()
        .join(" ")
}

/// The header of a station off the fault at `position` (m) with a field of `components`
/// components.
pub(super) fn surface_header(
    setup: &SeasSetup,
    position: &[f64],
    components: usize,
    steps: Option<(f64, f64)>,
    rows: usize,
) -> String {
    let at = position
        .iter()
        .map(|x| format!("{} km", x / 1e3))
        .collect::<Vec<_>>()
        .join(", ");
    let mut h = common_header(setup, &format!("off fault, ({at})"), steps, rows);
    for (i, (_, description)) in surface_columns(components, setup.depth_axis)
        .iter()
        .enumerate()
    {
        h.push_str(&format!("\n# Column #{} = {description}", i + 1));
    }
    h.push_str("\n# The line below lists the names of the data fields:\n");
    h.push_str(&surface_field_line(components, setup.depth_axis));
    h
}

/// Today's date in UTC as `YYYY-MM-DD`, for [`SeasSetup::date`] (from the system clock).
pub fn utc_date_today() -> String {
    jiff::tz::Offset::UTC
        .to_datetime(jiff::Timestamp::now())
        .date()
        .to_string()
}

/// Whether `s` is a calendar date `YYYY-MM-DD` of the proleptic Gregorian calendar (a
/// day the month has: `2023-02-31` is not one, `2024-02-29` is).
pub fn is_iso_date(s: &str) -> bool {
    s.len() == 10 && s.parse::<jiff::civil::Date>().is_ok()
}

#[cfg(test)]
mod tests {
    use super::{c_exp, is_iso_date, utc_date_today};

    #[test]
    fn calendar_dates() {
        assert!(is_iso_date(&utc_date_today()));
        for good in ["2024-02-29", "2000-02-29", "2026-11-24", "1970-01-01"] {
            assert!(is_iso_date(good), "{good:?}");
        }
        for bad in [
            "2023-02-31",
            "2023-02-29",
            "1900-02-29",
            "2026-04-31",
            "2026-13-01",
            "2026-1-01",
            "26-11-24",
            "2026-11-24\n",
            "2026/11/24",
            "",
        ] {
            assert!(!is_iso_date(bad), "{bad:?}");
        }
    }

    #[test]
    fn c_style_exponents() {
        assert_eq!(c_exp(1234.5, 3, 10), " 1.234E+03");
        assert_eq!(c_exp(-0.00012, 2, 9), "-1.20E-04");
        assert_eq!(c_exp(0.0, 1, 7), "0.0E+00");
        assert_eq!(c_exp(1e-100, 0, 7), " 1E-100");
    }
}
