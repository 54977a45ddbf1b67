//! What the strike–dip layout of BP5 is laid on: the benchmark's stations and the fault's
//! rate-and-state region with the physics its files need.

/// BP5's on-fault stations `(x₂, x₃)` (km along strike, km depth).
pub const SEAS_BP5_FAULT_STATIONS: [(f64, f64); 10] = [
    (-36.0, 0.0),
    (-16.0, 0.0),
    (0.0, 0.0),
    (16.0, 0.0),
    (36.0, 0.0),
    (-24.0, 10.0),
    (-16.0, 10.0),
    (0.0, 10.0),
    (16.0, 10.0),
    (0.0, 22.0),
];

/// BP5's off-fault stations `(x₂, x₁, x₃)` (km along strike, km normal to the fault, km
/// depth).
pub const SEAS_BP5_BODY_STATIONS: [(f64, f64, f64); 9] = [
    (-16.0, 8.0, 0.0),
    (0.0, 8.0, 0.0),
    (16.0, 8.0, 0.0),
    (0.0, 16.0, 0.0),
    (0.0, 32.0, 0.0),
    (0.0, 48.0, 0.0),
    (0.0, 8.0, 10.0),
    (0.0, 16.0, 10.0),
    (0.0, 32.0, 10.0),
];

/// BP8's on-fault stations `(x₂, x₃)` (m; `x₃` positive down), in the description's
/// order (§4.1).
pub const SEAS_BP8_FAULT_STATIONS: [(f64, f64); 9] = [
    (0.0, 0.0),
    (-200.0, 0.0),
    (0.0, 200.0),
    (200.0, 0.0),
    (0.0, -200.0),
    (-200.0, -200.0),
    (-200.0, 200.0),
    (200.0, -200.0),
    (200.0, 200.0),
];

/// BP7's on-fault stations `(x₂, x₃)` (m; `x₃` positive down), as the implementations
/// list them (docs/seas-bp7.md, "Output").
pub const SEAS_BP7_FAULT_STATIONS: [(f64, f64); 13] = [
    (0.0, 0.0),
    (-100.0, 0.0),
    (0.0, 100.0),
    (100.0, 0.0),
    (0.0, -100.0),
    (-100.0, -100.0),
    (-100.0, 100.0),
    (100.0, -100.0),
    (100.0, 100.0),
    (-300.0, 0.0),
    (0.0, 300.0),
    (300.0, 0.0),
    (0.0, -300.0),
];

/// BP7's off-fault stations `(x₂, x₁, x₃)` (m along strike, m normal to the fault, m
/// along `x₃`, positive down).
pub const SEAS_BP7_BODY_STATIONS: [(f64, f64, f64); 6] = [
    (0.0, 200.0, 0.0),
    (0.0, 400.0, 0.0),
    (-300.0, 400.0, 0.0),
    (0.0, 400.0, 300.0),
    (300.0, 400.0, 0.0),
    (0.0, 400.0, -300.0),
];

/// BP7's off-fault stations ([`SEAS_BP7_BODY_STATIONS`]) as model points
/// `(x₁, x₂, x₃)` (m): a square fault's model has the benchmark's coordinates.
pub fn bp7_body_station_points() -> Vec<[f64; 3]> {
    SEAS_BP7_BODY_STATIONS
        .iter()
        .map(|&(s, n, d)| [n, s, d])
        .collect()
}

/// The off-fault stations of BP5 ([`SEAS_BP5_BODY_STATIONS`]) as model points
/// `(x₁, x₂, −x₃)` (m): the model's `z` points up, the free surface is `z = 0`.
pub fn bp5_body_station_points() -> Vec<[f64; 3]> {
    SEAS_BP5_BODY_STATIONS
        .iter()
        .map(|&(s, n, d)| [n * 1e3, s * 1e3, -d * 1e3])
        .collect()
}

/// The fault of a strike–dip output ([`SeasBp5Output`](crate::SeasBp5Output)): its
/// rate-and-state region, `length` along strike centred on `x₂ = 0` and `width` down dip
/// from the surface (BP5) or centred on `x₃ = 0` (a square fault in a whole space, BP7
/// and BP8), which the output's grid fills, and what the files need of the physics (the
/// moment rate, the shear stress `friction + ηV`, the plate's motion of the stations off
/// the fault). `rsf_scenes::SeasBp5::output_fault` gives BP5's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrikeDipFault {
    /// Length of the rate-and-state region along strike (m).
    pub length: f64,
    /// Width of the rate-and-state region down dip (m).
    pub width: f64,
    /// Shear modulus μ (Pa).
    pub shear_modulus: f64,
    /// Radiation damping η (Pa·s/m).
    pub radiation_damping: f64,
    /// Plate rate V_p (m/s).
    pub plate_rate: f64,
}
