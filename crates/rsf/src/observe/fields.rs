//! The fields of a step at every mesh vertex, as the frame writers store them
//! ([`VtuFrames`](crate::observe::VtuFrames) with the feature `vtk`, and the HDF5 fields of
//! the crate `rsf-hdf5`): displacement and velocity as Cartesian 3-vectors, the fault's
//! scalars and slip at Γ_F's vertices (NaN elsewhere). [`point_fields`] computes them,
//! [`POINT_FIELDS`] names them.

use super::StepView;
use crate::model::Model;

/// The node-major `x` (`D` components per vertex, `n` vertices) as 3-vectors, zero-padded.
fn padded<const D: usize>(x: &[f64], n: usize) -> Vec<f64> {
    let mut out = vec![0.0; 3 * n];
    for p in 0..n {
        for c in 0..D.min(3) {
            out[3 * p + c] = x[D * p + c];
        }
    }
    out
}

/// α = ln θ at the frictional nodes, NaN elsewhere (no state there; ParaView draws NaN
/// in its "NaN colour"); all NaN when the friction law has no state.
fn state_field<const D: usize>(s: &StepView<'_, D>, n: usize) -> Vec<f64> {
    let mut out = vec![f64::NAN; n];
    for (&p, &a) in s.model.frictional_boundary.nodes.iter().zip(&s.state.alpha) {
        out[p] = a;
    }
    out
}

/// A node-major vector of the model in Cartesian components (nodal frames rotated back,
/// an internal fault's two sides).
fn global<const D: usize>(m: &Model<D>, x: &[f64]) -> Vec<f64> {
    m.to_cartesian(x)
        .expect("the state vectors match the model")
}

/// `f(k)` at the `k`-th frictional node, NaN elsewhere.
fn fault_scalars<const D: usize>(
    s: &StepView<'_, D>,
    n: usize,
    f: impl Fn(usize) -> f64,
) -> Vec<f64> {
    let mut out = vec![f64::NAN; n];
    for (k, &p) in s.model.frictional_boundary.nodes.iter().enumerate() {
        out[p] = f(k);
    }
    out
}

/// The slip (m, Cartesian 3-vectors, zero-padded) on Γ_F, NaN elsewhere.
fn slip_field<const D: usize>(s: &StepView<'_, D>, n: usize) -> Vec<f64> {
    let mut out = vec![f64::NAN; 3 * n];
    for (k, &p) in s.model.frictional_boundary.nodes.iter().enumerate() {
        let slip = s.slip(k);
        for c in 0..3 {
            out[3 * p + c] = if c < D { slip[c] } else { 0.0 };
        }
    }
    out
}

/// The point fields of a frame, in the order [`point_fields`] gives them: name, components
/// (3: a Cartesian 3-vector, zero-padded in 1-D and 2-D; 1: a scalar) and unit.
///
/// - `displacement` (m) and `velocity` (m/s) at every vertex, Cartesian components (rotated
///   back from the nodal frames of a slanted fault; an internal fault's two sides);
/// - on Γ_F only (NaN at the other vertices): `slip_rate` (m/s, [`StepView::slip_rate`]),
///   `state_alpha` (α = ln θ, θ in s; NaN everywhere for a law without state), `slip` (m,
///   a 3-vector, [`StepView::slip`]), `shear_traction` and `normal_traction` (Pa,
///   [`StepView::shear_traction`], [`StepView::normal_traction`]; NaN where the law has no
///   `σ̄_n`), and `fault`: the vertex's fault, an index into the model's
///   `frictional_boundary.fault_names` (0 for a model of one fault; a network's faults
///   told apart by value, their names in the frame index: `frames.pvd`'s comment, the
///   HDF5 dataset's attribute `fault_names`).
pub const POINT_FIELDS: [(&str, usize, &str); 8] = [
    ("displacement", 3, "m"),
    ("velocity", 3, "m/s"),
    ("slip_rate", 1, "m/s"),
    ("state_alpha", 1, "1"),
    ("slip", 3, "m"),
    ("shear_traction", 1, "Pa"),
    ("normal_traction", 1, "Pa"),
    ("fault", 1, "1"),
];

/// One point field of a frame at every mesh vertex ([`point_fields`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PointField {
    /// Its name, as [`POINT_FIELDS`] lists it.
    pub name: &'static str,
    /// Components per vertex: 3 (a Cartesian 3-vector) or 1 (a scalar).
    pub components: usize,
    /// The values, vertex-major: `components` values per mesh vertex (length
    /// `components × model.vertices.len()`), in [`POINT_FIELDS`]' unit.
    pub values: Vec<f64>,
}

/// The point fields of the step `s` at every mesh vertex, in the order and units of
/// [`POINT_FIELDS`]: what every frame writer stores, so that their files agree bit for bit.
/// Allocates the fields (one frame's worth); call it for the steps that are written.
///
/// # Panics
/// If the state's vectors do not match the model (an internal invariant of a run's
/// [`StepView`]).
pub fn point_fields<const D: usize>(s: &StepView<'_, D>) -> Vec<PointField> {
    let m = s.model;
    let n = m.vertices.len();
    let values = [
        padded::<D>(&global(m, &s.state.kinematics.u), n),
        padded::<D>(&global(m, &s.state.kinematics.v), n),
        fault_scalars(s, n, |k| s.slip_rate(k)),
        state_field(s, n),
        slip_field(s, n),
        fault_scalars(s, n, |k| s.shear_traction(k)),
        fault_scalars(s, n, |k| s.normal_traction(k).unwrap_or(f64::NAN)),
        fault_scalars(s, n, |k| m.frictional_boundary.fault_of[k] as f64),
    ];
    POINT_FIELDS
        .iter()
        .zip(values)
        .map(|(&(name, components, _), values)| PointField {
            name,
            components,
            values,
        })
        .collect()
}
