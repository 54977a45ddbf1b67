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
/// from the surface, which the output's grid fills, and what the files need of the
/// physics (the moment rate, the shear stress `friction + ηV`, the plate's motion of the
/// stations off the fault). `rsf_scenes::SeasBp5::output_fault` gives BP5's.
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
