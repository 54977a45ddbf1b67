//! What a strike–dip output writes, one description per benchmark: the stations on and
//! off the fault, the profiles, the columns of `global.dat`, the pressure columns, the
//! rupture times and the catalogue — BP5's (a half-space, km), BP7's and BP8's (a square
//! fault in a whole space, m).

use super::stations::{
    SEAS_BP5_BODY_STATIONS, SEAS_BP5_FAULT_STATIONS, SEAS_BP7_BODY_STATIONS,
    SEAS_BP7_FAULT_STATIONS, SEAS_BP8_FAULT_STATIONS,
};
use super::text::Quantity;
use super::text::{body_station_name, fault_station_name, metre_name};

/// A station on the fault: its file, position `(x₂, x₃)` (m, `x₃` down) and location line.
#[derive(Debug, Clone)]
pub(super) struct FaultStationSpec {
    pub(super) name: String,
    pub(super) at: [f64; 2],
    pub(super) location: String,
}

/// A station off the fault: its file and location line (its motion's source is given
/// apart).
#[derive(Debug, Clone)]
pub(super) struct BodyStationSpec {
    pub(super) name: String,
    pub(super) location: String,
}

/// A profile: its file, quantity, coordinate (`x2`, `x3`), the positions its first row
/// lists and the fault points `(x₂, x₃)` (m) they are, and its location line.
#[derive(Debug, Clone)]
pub(super) struct ProfileSpec {
    pub(super) file: String,
    pub(super) quantity: Quantity,
    pub(super) coordinate: &'static str,
    pub(super) positions: Vec<f64>,
    pub(super) points: Vec<[f64; 2]>,
    pub(super) location: String,
}

/// Where `global.dat`'s maximum slip rate and moment rate are taken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum GlobalSpec {
    /// Over every node: `t max_slip_rate moment_rate` (BP5, BP8).
    Whole,
    /// Over the disc of radius `outer` (m) about `(0, 0)`, and a fourth column, the moment
    /// rate over the disc of radius `inner` (BP7: 1.5 R_VW and the velocity-weakening
    /// disc R_VW).
    Discs {
        /// Radius of the disc of the maximum and the first moment rate (m).
        outer: f64,
        /// Radius of the disc of the second moment rate (m).
        inner: f64,
    },
}

/// The benchmark's files: what the output writes.
#[derive(Debug, Clone)]
pub(super) struct Spec {
    pub(super) fault_stations: Vec<FaultStationSpec>,
    pub(super) body_stations: Vec<BodyStationSpec>,
    pub(super) profiles: Vec<ProfileSpec>,
    /// Whether the profiles' field names have a line each (BP7, BP8).
    pub(super) name_per_line: bool,
    /// Whether the station rows carry `pore_pressure darcy_vel_2 darcy_vel_3` before the
    /// state (BP8).
    pub(super) pressure_columns: bool,
    pub(super) global: GlobalSpec,
    /// `rupture.dat`, and whether its times count after the first event only (BP5: the
    /// nucleation patch's) or from the start (BP7).
    pub(super) rupture: Option<bool>,
    /// Whether `events.csv` is written.
    pub(super) catalogue: bool,
    /// The observer's name.
    pub(super) name: &'static str,
}

/// The points of the line `x₃ = depth` (`along_strike`) or `x₂ = 0` at `positions`.
fn line(positions: &[f64], along_strike: bool, depth: f64) -> Vec<[f64; 2]> {
    positions
        .iter()
        .map(|&x| if along_strike { [x, depth] } else { [0.0, x] })
        .collect()
}

/// BP5's files: stations in km (`fltst_strk±XXdp±YY`, `blkst_…`), slip and stress
/// profiles along dip at `x₂ = 0` and along strike at `x₃ = 10 km` at the grid's
/// `along_dip` and `along_strike` positions, `rupture.dat` after the first event, the
/// catalogue.
pub(super) fn bp5(along_dip: &[f64], along_strike: &[f64]) -> Spec {
    let mut profiles = Vec::new();
    for slip in [true, false] {
        for dip in [true, false] {
            let (name, quantity) = if slip {
                ("slip_2", Quantity::Slip2)
            } else {
                ("stress_2", Quantity::Stress2)
            };
            let (positions, coordinate, location) = if dip {
                (along_dip, "x3", format!("{name} along dip at x2 = 0 km"))
            } else {
                (
                    along_strike,
                    "x2",
                    format!("{name} along strike at x3 = 10 km"),
                )
            };
            profiles.push(ProfileSpec {
                file: format!("{name}_{}.dat", if dip { "depth" } else { "strike" }),
                quantity,
                coordinate,
                positions: positions.to_vec(),
                points: line(positions, !dip, 10e3),
                location,
            });
        }
    }
    Spec {
        fault_stations: SEAS_BP5_FAULT_STATIONS
            .iter()
            .map(|&(s, d)| FaultStationSpec {
                name: fault_station_name(s, d),
                at: [s * 1e3, d * 1e3],
                location: format!("on fault, {s} km along strike, {d} km down-dip"),
            })
            .collect(),
        body_stations: SEAS_BP5_BODY_STATIONS
            .iter()
            .map(|&(s, n, d)| BodyStationSpec {
                name: body_station_name(s, n, d),
                location: format!(
                    "off fault, {s} km along strike, {n} km normal to the fault, {d} km depth"
                ),
            })
            .collect(),
        profiles,
        name_per_line: false,
        pressure_columns: false,
        global: GlobalSpec::Whole,
        rupture: Some(true),
        catalogue: true,
        name: "SEAS BP5 output",
    }
}

/// The 81 positions `−400, −390, …, 400` m of BP7's and BP8's profiles.
pub(super) fn square_profile_positions() -> Vec<f64> {
    (0..=80).map(|i| -400.0 + 10.0 * i as f64).collect()
}

/// The profiles of a square fault along depth (`x₂ = 0`) and strike (`x₃ = 0`) at the
/// 81 positions, for each quantity: `{quantity}_depth.dat`, `{quantity}_strike.dat`.
fn square_profiles(quantities: &[Quantity]) -> Vec<ProfileSpec> {
    let positions = square_profile_positions();
    let mut out = Vec::new();
    for &q in quantities {
        let name = q.column().0;
        for dip in [true, false] {
            out.push(ProfileSpec {
                file: format!("{name}_{}.dat", if dip { "depth" } else { "strike" }),
                quantity: q,
                coordinate: if dip { "x3" } else { "x2" },
                positions: positions.clone(),
                points: line(&positions, !dip, 0.0),
                location: if dip {
                    format!("{name} along x3 at x2 = 0 m")
                } else {
                    format!("{name} along x2 at x3 = 0 m")
                },
            });
        }
    }
    out
}

/// The on-fault stations `(x₂, x₃)` (m) named `fltst_strk±XXXdp±YYY`.
fn square_fault_stations(stations: &[(f64, f64)]) -> Vec<FaultStationSpec> {
    stations
        .iter()
        .map(|&(s, d)| FaultStationSpec {
            name: format!("fltst_strk{}dp{}", metre_name(s), metre_name(d)),
            at: [s, d],
            location: format!("on fault, x2 = {s} m, x3 = {d} m"),
        })
        .collect()
}

/// BP8's files: nine on-fault stations with the pressure columns, `global.dat`, ten
/// profiles (slip, shear stress, both components, and pore pressure, along depth and
/// strike), no rupture times, no catalogue (velocity strengthening: no event).
pub(super) fn bp8() -> Spec {
    Spec {
        fault_stations: square_fault_stations(&SEAS_BP8_FAULT_STATIONS),
        body_stations: Vec::new(),
        profiles: square_profiles(&[
            Quantity::Slip2,
            Quantity::Slip3,
            Quantity::Stress2,
            Quantity::Stress3,
            Quantity::Pressure,
        ]),
        name_per_line: true,
        pressure_columns: true,
        global: GlobalSpec::Whole,
        rupture: None,
        catalogue: false,
        name: "SEAS BP8 output",
    }
}

/// BP7's files: thirteen on-fault and six off-fault stations, `global.dat` of four
/// columns (the moment rate over the disc of radius `1.5 r_vw` and over the
/// velocity-weakening disc), slip and shear stress along depth and strike, rupture times
/// from the start, the catalogue.
pub(super) fn bp7(r_vw: f64) -> Spec {
    Spec {
        fault_stations: square_fault_stations(&SEAS_BP7_FAULT_STATIONS),
        body_stations: SEAS_BP7_BODY_STATIONS
            .iter()
            .map(|&(s, n, d)| BodyStationSpec {
                name: format!(
                    "blkst_strk{}fn{}dp{}",
                    metre_name(s),
                    metre_name(n),
                    metre_name(d)
                ),
                location: format!("off fault, x2 = {s} m, x1 = {n} m, x3 = {d} m"),
            })
            .collect(),
        profiles: square_profiles(&[Quantity::Slip2, Quantity::Stress2]),
        name_per_line: true,
        pressure_columns: false,
        global: GlobalSpec::Discs {
            outer: 1.5 * r_vw,
            inner: r_vw,
        },
        rupture: Some(false),
        catalogue: true,
        name: "SEAS BP7 output",
    }
}
