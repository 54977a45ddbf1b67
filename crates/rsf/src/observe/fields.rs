//! The fields of a step at every mesh vertex, as the frame writers store them (VTU frames,
//! HDF5 fields): displacement and velocity as Cartesian 3-vectors, the fault's scalars and
//! slip at Γ_F's vertices (NaN elsewhere).

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

/// A frame's point data at every mesh vertex: name, components (3: a vector, 1: a scalar)
/// and values, vertex-major.
pub(crate) fn point_fields<const D: usize>(
    s: &StepView<'_, D>,
) -> Vec<(&'static str, usize, Vec<f64>)> {
    let m = s.model;
    let n = m.vertices.len();
    vec![
        (
            "displacement",
            3,
            padded::<D>(&global(m, &s.state.kinematics.u), n),
        ),
        (
            "velocity",
            3,
            padded::<D>(&global(m, &s.state.kinematics.v), n),
        ),
        ("slip_rate", 1, fault_scalars(s, n, |k| s.slip_rate(k))),
        ("state_alpha", 1, state_field(s, n)),
        ("slip", 3, slip_field(s, n)),
        (
            "shear_traction",
            1,
            fault_scalars(s, n, |k| s.shear_traction(k)),
        ),
        (
            "normal_traction",
            1,
            fault_scalars(s, n, |k| s.normal_traction(k).unwrap_or(f64::NAN)),
        ),
    ]
}
