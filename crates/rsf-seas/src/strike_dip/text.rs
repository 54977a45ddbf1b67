//! The text of the BP5 files: their columns, the file names, and the file being written
//! (its rows so far).

use crate::text::File;

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

/// BP8's columns of the pore pressure and the Darcy velocity.
const PRESSURE_COLUMNS: [(&str, &str); 3] = [
    ("pore_pressure", "Pore_pressure (MPa)"),
    ("darcy_vel_2", "Darcy_vel_2 (m/s)"),
    ("darcy_vel_3", "Darcy_vel_3 (m/s)"),
];

/// BP8's station columns: BP5's and the pressure's before the state.
pub(super) const PRESSURE_FAULT_COLUMNS: [(&str, &str); 11] = {
    let [t, slip_2, slip_3, v_2, v_3, tau_2, tau_3, state] = FAULT_COLUMNS;
    let [p, darcy_2, darcy_3] = PRESSURE_COLUMNS;
    [
        t, slip_2, slip_3, v_2, v_3, tau_2, tau_3, p, darcy_2, darcy_3, state,
    ]
};

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

/// A profile along dip or strike.
pub(super) struct Profile {
    pub(super) file: File,
    pub(super) quantity: Quantity,
    /// The nodes around every point and their bilinear weights.
    pub(super) points: Vec<[(usize, f64); 4]>,
    /// The points as model points (for the pressure field).
    pub(super) model_points: Vec<[f64; 3]>,
}

/// A profile's columns: the time, the maximum slip rate and the quantity at the positions.
pub(super) fn profile_columns(quantity: Quantity) -> [(String, String); 3] {
    let (name, description) = quantity.column();
    [
        ("t".into(), "Time (s)".into()),
        ("max_slip_rate".into(), "Max slip rate (log10 m/s)".into()),
        (
            name.into(),
            format!("{description} at the positions (m) of the first data row, one column each"),
        ),
    ]
}

/// The slip rate (m/s) from which a node counts as rupturing in `rupture.dat`.
pub const RUPTURE_THRESHOLD: f64 = 1e-3;

/// The time written in `rupture.dat` for a node that did not rupture (s; far beyond any
/// run: the times are absolute, from the start of the run).
pub const NEVER_RUPTURED: f64 = 1e20;

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

/// `+000`, `-200`, `+050`: BP7's and BP8's signed three-digit metres.
pub(super) fn metre_name(m: f64) -> String {
    format!(
        "{}{:03}",
        if m < 0.0 { '-' } else { '+' },
        m.abs().round() as i64
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

/// What a profile or a station column holds at a fault node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Quantity {
    /// `slip_2` (m).
    Slip2,
    /// `slip_3` (m).
    Slip3,
    /// `shear_stress_2` (MPa).
    Stress2,
    /// `shear_stress_3` (MPa).
    Stress3,
    /// `pore_pressure` (MPa): the run's pressure field at the position.
    Pressure,
}

impl Quantity {
    /// The column's field name and description.
    pub(super) fn column(self) -> (&'static str, &'static str) {
        match self {
            Self::Slip2 => ("slip_2", "Slip_2 (m)"),
            Self::Slip3 => ("slip_3", "Slip_3 (m)"),
            Self::Stress2 => ("shear_stress_2", "Shear_stress_2 (MPa)"),
            Self::Stress3 => ("shear_stress_3", "Shear_stress_3 (MPa)"),
            Self::Pressure => ("pore_pressure", "Pore_pressure (MPa)"),
        }
    }
}
