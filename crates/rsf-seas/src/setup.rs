//! What a SEAS output is asked to write: the headers' problem, author, date and element
//! size, its sampling, and for an output along dip its stations and layout (BP1 or BP3), the
//! benchmark's columns, the events of its catalogue.

use rsf::model::FaultSide;

/// Seconds per year (365.25 days), the unit of the benchmark's output intervals (the
/// library's, [`rsf::observe::SECONDS_PER_YEAR`]).
pub use rsf::observe::SECONDS_PER_YEAR;

/// When rows are written: every accepted step, or thinned to the benchmark's suggestion
/// (a station row at most every `station_quiet` s between events and every
/// `station_event` s during them; a slip profile every `profile_quiet` / `profile_event`
/// s). A step belongs to an event when the maximum slip rate on the fault is at least
/// `event_threshold` (m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeasSampling {
    /// Write a station row at every step (ignores the station intervals).
    pub every_step: bool,
    /// Station interval between events (s); 0.1 yr.
    pub station_quiet: f64,
    /// Station interval during events (s); 0.1 s.
    pub station_event: f64,
    /// Profile interval between events (s); 5 yr.
    pub profile_quiet: f64,
    /// Profile interval during events (s); 1 s.
    pub profile_event: f64,
    /// Slip rate (m/s) from which a step belongs to an event; 1e-3 m/s.
    pub event_threshold: f64,
    /// An event ends at the first step below the threshold after which the slip rate
    /// stays below it for this long (s); default 0: at the first step below (the
    /// benchmark's definition). A fully dynamic run in a domain with reflecting
    /// boundaries has waves that lift the slip rate back over the threshold for fractions
    /// of a second after the rupture; a quiet time of a minute keeps them in the event.
    pub event_quiet_time: f64,
}

impl Default for SeasSampling {
    fn default() -> Self {
        Self {
            every_step: false,
            station_quiet: 0.1 * SECONDS_PER_YEAR,
            station_event: 0.1,
            profile_quiet: 5.0 * SECONDS_PER_YEAR,
            profile_event: 1.0,
            event_threshold: 1e-3,
            event_quiet_time: 0.0,
        }
    }
}

/// What a [`SeasOutput`](crate::SeasOutput) writes and where its numbers come from.
#[derive(Debug, Clone, PartialEq)]
pub struct SeasSetup {
    /// Problem name for the headers, e.g. `SEAS Benchmark BP1-QD`.
    pub problem: String,
    /// Who ran the model, for the headers' `author` line (the benchmark's "modeler").
    pub modeler: String,
    /// Date of the run for the headers, `YYYY-MM-DD` (e.g. [`utc_date_today`](crate::utc_date_today)).
    pub date: String,
    /// Element size on the fault (m), for the headers.
    pub element_size: f64,
    /// Stations as `(file name, position in m)`, each at the frictional node nearest that
    /// position along the fault — its depth for BP1 (e.g. `SEAS_BP1_STATION_DEPTHS` with
    /// `SeasBp1::station_name`), its down-dip distance for [`SeasLayout::Bp3`].
    pub stations: Vec<(String, f64)>,
    /// The coordinate that is depth (`1` for BP1's `(x, z)` mesh) …
    pub depth_axis: usize,
    /// … and whether it grows downwards (`true` for BP1: depth = `x[depth_axis]`; else
    /// depth = `−x[depth_axis]`).
    pub depth_down: bool,
    /// Normal stress σ_n (Pa): the shear stress column is `σ_n μ(V, α)`.
    pub sigma_n: f64,
    /// Depth spacing of the slip profiles (m): the profile holds the frictional nodes at
    /// least this far apart in depth, from the surface down.
    pub profile_spacing: f64,
    /// When rows are written.
    pub sampling: SeasSampling,
    /// Which benchmark's files: BP1's (the default) or BP3's.
    pub layout: SeasLayout,
    /// Stations off the fault (BP3's eight on the free surface,
    /// `SeasBp3::surface_stations`): displacement and velocity, rows at the on-fault
    /// stations' times. Empty for BP1.
    pub surface_stations: Vec<SeasSurfaceStation>,
}

/// A station off the fault (BP3's `srfst_fn…`): the displacement and velocity of the mesh
/// vertex nearest `position`, written as `t disp_1 … vel_1 …` (m, m/s; the component along
/// the depth axis positive down; the displacement is the change since the start).
#[derive(Debug, Clone, PartialEq)]
pub struct SeasSurfaceStation {
    /// File name, e.g. `srfst_fn+08`.
    pub name: String,
    /// Position (m), one coordinate per space dimension.
    pub position: Vec<f64>,
    /// Where the nearest vertex is a split vertex of a fault inside the body (the fault's
    /// trace on the surface): the copy on this side (BP3's `0⁻` and `0⁺` stations).
    pub side: FaultSide,
}

/// Which benchmark's files a [`SeasOutput`](crate::SeasOutput) writes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum SeasLayout {
    /// BP1: stations and profiles by depth, five station columns (the shear stress
    /// `σ_n μ(V, α)` with [`SeasSetup::sigma_n`]), the slip profiles `devol.dat`.
    #[default]
    Bp1,
    /// BP3 (a vector model with a fault inside the body, dipping `dip_degrees`):
    /// stations and profiles by down-dip distance `x_d = depth / sin ψ`, six station
    /// columns (the run's shear and normal stress, signed slip: the jump's tangential
    /// component), the slip profiles `slip.dat` (field line `xd`).
    Bp3 {
        /// Dip ψ (degrees).
        dip_degrees: f64,
    },
}

impl SeasLayout {
    /// The station columns `(field name, description)`.
    pub fn station_columns(&self) -> &'static [(&'static str, &'static str)] {
        match self {
            Self::Bp1 => &SEAS_BP1_STATION_COLUMNS,
            Self::Bp3 { .. } => &SEAS_BP3_STATION_COLUMNS,
        }
    }

    /// The slip profiles' file name.
    pub fn profile_file(&self) -> &'static str {
        match self {
            Self::Bp1 => "devol.dat",
            Self::Bp3 { .. } => "slip.dat",
        }
    }

    /// Every profile file's name: the slip profiles' ([`profile_file`](Self::profile_file)),
    /// and for BP3 `shear_stress.dat` and `normal_stress.dat` (the run's stresses, MPa,
    /// the shear stress signed with the slip rate).
    pub fn profile_files(&self) -> Vec<&'static str> {
        self.profiles()
            .iter()
            .map(|&q| match q {
                ProfileQuantity::Slip => self.profile_file(),
                ProfileQuantity::ShearStress => "shear_stress.dat",
                ProfileQuantity::NormalStress => "normal_stress.dat",
            })
            .collect()
    }

    /// What the profile files hold, in the order of [`profile_files`](Self::profile_files).
    pub(crate) fn profiles(&self) -> &'static [ProfileQuantity] {
        match self {
            Self::Bp1 => &[ProfileQuantity::Slip],
            Self::Bp3 { .. } => &[
                ProfileQuantity::Slip,
                ProfileQuantity::ShearStress,
                ProfileQuantity::NormalStress,
            ],
        }
    }

    /// The position along the fault of a point at `depth` (m): the depth (BP1) or the
    /// down-dip distance (BP3).
    pub(crate) fn along(&self, depth: f64) -> f64 {
        match self {
            Self::Bp1 => depth,
            Self::Bp3 { dip_degrees } => depth / dip_degrees.to_radians().sin(),
        }
    }

    /// The name of that position in the headers: `(word, symbol)`.
    pub(crate) fn coordinate(&self) -> (&'static str, &'static str) {
        match self {
            Self::Bp1 => ("depth", "z"),
            Self::Bp3 { .. } => ("down-dip distance", "xd"),
        }
    }
}

/// One event of the catalogue: from where the maximum slip rate on the fault rises to the
/// threshold to where it falls below it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeasEvent {
    /// Start time (s): the first step with max V ≥ threshold.
    pub t_start: f64,
    /// End time (s): the first step after the start with max V < threshold (NaN while the
    /// event lasts).
    pub t_end: f64,
    /// Depth (m) of the node of maximum slip rate at the start.
    pub hypocentre_depth: f64,
    /// Largest slip rate on the fault during the event (m/s).
    pub peak_slip_rate: f64,
    /// Slip at the surface station during the event (m).
    pub surface_slip: f64,
}

/// The columns of a BP1 station file: field name and its `# Column #k` description
/// (the benchmark's units: s, m, log10 m/s, MPa, log10 s). The field-list line is the
/// names joined by spaces.
pub const SEAS_BP1_STATION_COLUMNS: [(&str, &str); 5] = [
    ("t", "Time (s)"),
    ("slip", "Slip (m)"),
    ("slip_rate", "Slip rate (log10 m/s)"),
    ("shear_stress", "Shear stress (MPa)"),
    ("state", "State (log10 s)"),
];

/// The station files' columns of BP3: BP1's with the normal stress.
pub const SEAS_BP3_STATION_COLUMNS: [(&str, &str); 6] = [
    ("t", "Time (s)"),
    ("slip", "Slip (m)"),
    ("slip_rate", "Slip rate (log10 m/s)"),
    ("shear_stress", "Shear stress (MPa)"),
    ("normal_stress", "Normal stress (MPa)"),
    ("state", "State (log10 s)"),
];

/// What a profile file holds along the fault: BP1's `devol.dat` and BP3's `slip.dat` the
/// slip, BP3's `shear_stress.dat` and `normal_stress.dat` the stresses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ProfileQuantity {
    /// Slip (m).
    Slip,
    /// Shear stress (MPa), signed with the slip rate.
    ShearStress,
    /// Normal stress (MPa), compressive positive.
    NormalStress,
}

impl ProfileQuantity {
    /// The field name (the second field-list line ends with it).
    pub(crate) fn field(self) -> &'static str {
        match self {
            Self::Slip => "slip",
            Self::ShearStress => "shear_stress",
            Self::NormalStress => "normal_stress",
        }
    }

    /// The description in the `# Column #3` line.
    pub(crate) fn description(self) -> &'static str {
        match self {
            Self::Slip => "Slip (m)",
            Self::ShearStress => "Shear stress (MPa)",
            Self::NormalStress => "Normal stress (MPa)",
        }
    }
}
