//! The text of the BP5 files: their columns, the data rows' number format, the file
//! names, and the file being written (its rows so far).

use std::path::PathBuf;

use std::fmt::Write as _;

use rsf::observe::{seas_header, seas_number, SeasSetup};

pub(super) const FAULT_COLUMNS: [(&str, &str); 8] = [
    ("t", "Time (s)"),
    ("slip_2", "Slip_2 (m)"),
    ("slip_3", "Slip_3 (m)"),
    ("slip_rate_2", "Slip_rate_2 (log10 m/s)"),
    ("slip_rate_3", "Slip_rate_3 (log10 m/s)"),
    ("shear_stress_2", "Shear_stress_2 (MPa)"),
    ("shear_stress_3", "Shear_stress_3 (MPa)"),
    ("state", "State (log10 s)"),
];

pub(super) const BODY_COLUMNS: [(&str, &str); 7] = [
    ("t", "Time (s)"),
    ("disp_1", "Displacement_1 (m)"),
    ("disp_2", "Displacement_2 (m)"),
    ("disp_3", "Displacement_3 (m)"),
    ("vel_1", "Velocity_1 (m/s)"),
    ("vel_2", "Velocity_2 (m/s)"),
    ("vel_3", "Velocity_3 (m/s)"),
];

pub(super) const GLOBAL_COLUMNS: [(&str, &str); 3] = [
    ("t", "Time (s)"),
    ("max_slip_rate", "Max slip rate (log10 m/s)"),
    ("moment_rate", "Moment rate (N-m/s)"),
];

/// The smallest slip rate component written (m/s): `log10` of a component below it is
/// written as `log10` of it (the benchmark's convention for a zero component).
pub const SLIP_RATE_FLOOR: f64 = 1e-20;

/// A file: its path, header location line and rows so far.
pub(super) struct File {
    pub(super) path: PathBuf,
    pub(super) location: String,
    pub(super) columns: &'static [(&'static str, &'static str)],
    pub(super) rows: String,
    /// For a profile: the name of its coordinate (`x2` or `x3`); its first data row holds
    /// the positions.
    pub(super) coordinate: Option<&'static str>,
}

/// A slip or shear-stress profile (component 2) along dip or strike.
pub(super) struct Profile {
    pub(super) file: File,
    /// `true`: slip₂ (m); `false`: shear stress₂ (MPa).
    pub(super) slip: bool,
    /// The nodes around every point and their bilinear weights.
    pub(super) points: Vec<[(usize, f64); 4]>,
}

pub(super) const SLIP_PROFILE_COLUMNS: [(&str, &str); 3] = [
    ("t", "Time (s)"),
    ("max_slip_rate", "Max slip rate (log10 m/s)"),
    (
        "slip_2",
        "Slip_2 (m) at the positions (m) of the first data row, one column each",
    ),
];

pub(super) const STRESS_PROFILE_COLUMNS: [(&str, &str); 3] = [
    ("t", "Time (s)"),
    ("max_slip_rate", "Max slip rate (log10 m/s)"),
    (
        "shear_stress_2",
        "Shear_stress_2 (MPa) at the positions (m) of the first data row, one column each",
    ),
];

/// The slip rate (m/s) from which a node counts as rupturing in `rupture.dat`.
pub const RUPTURE_THRESHOLD: f64 = 1e-3;

/// The time written in `rupture.dat` for a node that did not rupture (s; far beyond any
/// run: the times are absolute, from the start of the run).
pub const NEVER_RUPTURED: f64 = 1e20;

/// A data row: the time as `%21.13E`, every value as `%14.6E`.
pub(super) fn write_row(rows: &mut String, t: f64, values: &[f64]) {
    rows.push_str(&seas_number(t, 13, 21));
    for &x in values {
        rows.push(' ');
        rows.push_str(&seas_number(x, 6, 14));
    }
    rows.push('\n');
}

/// `fltst_strk±XXdp±YY` of the on-fault station at `(x₂, x₃)` km.
pub(super) fn fault_station_name(strike: f64, depth: f64) -> String {
    format!("fltst_strk{}dp{}", signed(strike), signed(depth))
}

/// `blkst_strk±XXfn±YYdp±ZZ` of the off-fault station at `(x₂, x₁, x₃)` km.
pub(super) fn body_station_name(strike: f64, normal: f64, depth: f64) -> String {
    format!(
        "blkst_strk{}fn{}dp{}",
        signed(strike),
        signed(normal),
        signed(depth)
    )
}

/// `+08`, `-16`, `+00`: the benchmark's signed two-digit kilometres.
pub(super) fn signed(km: f64) -> String {
    format!(
        "{}{:02}",
        if km < 0.0 { '-' } else { '+' },
        km.abs().round() as i64
    )
}

impl File {
    /// The file's header: the SEAS lines of `setup` (`steps` the smallest and largest
    /// step so far, `rows` the data rows), one `# Column #k` line per column, the field
    /// lines (a profile's coordinate line first).
    pub(super) fn header(
        &self,
        setup: &SeasSetup,
        steps: Option<(f64, f64)>,
        rows: usize,
    ) -> String {
        let mut h = seas_header(setup, &self.location, steps, rows);
        for (i, (_, description)) in self.columns.iter().enumerate() {
            let _ = write!(h, "\n# Column #{} = {description}", i + 1);
        }
        if let Some(coordinate) = self.coordinate {
            let _ = write!(
                h,
                "\n# The first data row is 0 0 followed by the positions {coordinate} (m); \
                 every other row is a time.\n# The two lines below list the names of the data \
                 fields:\n{coordinate}\n"
            );
        } else {
            h.push_str("\n# The line below lists the names of the data fields:\n");
        }
        let names: Vec<&str> = self.columns.iter().map(|(n, _)| *n).collect();
        h.push_str(&names.join(" "));
        h.push('\n');
        h
    }
}
