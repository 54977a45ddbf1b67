//! What SEAS BP7 and BP8 share: a square fault `|x₂|, |x₃| ≤ l_f` in the plane `x₁ = 0`
//! of a homogeneous whole space, cut into square cells of side `Δx` — a fault alone whose
//! operator is [`WholeSpaceGrid`]'s (the whole space's rectangles, applied by FFTs).
//!
//! Coordinates are the benchmarks' own: the model's `(x, y, z)` is `(x₁, x₂, x₃)` (`x₃`
//! positive down; in a whole space no direction is up), the plus side `x₁ > 0`, and a
//! cell's two slip unknowns its `slip₂`, `slip₃` (the plus side's motion along `+x₂`,
//! `+x₃` relative to the minus side's).

use rsf::halfspace::Medium;
use rsf::halfspace_operator::WholeSpaceGrid;
use rsf::{Model, Result};

use crate::invalid;

/// The problem builder of BP7's and BP8's square (3-D, three components): the regularised
/// law, a built-in state law (aging or slip), quasi-dynamic.
pub(crate) type SquareProblemBuilder = rsf::SimulationBuilder<
    3,
    rsf_friction::AsinhLaw,
    rsf_state::BuiltinStateLaw,
    rsf::Integrator,
    3,
>;

/// Most cells along each side of a square fault (a 5 m grid of BP8's 800 m square).
pub const MAX_SQUARE_CELLS: usize = 160;

/// The cells' centres `(x₂, x₃)` (m) of the square `|x₂|, |x₃| ≤ half` cut into cells of
/// side `dx`: `x₂` fastest, from `x₃ = −half` on.
///
/// # Errors
/// [`rsf::Error::InvalidParameter`] named `dx` unless it is positive, divides `2 half`
/// into whole cells (to 1e-9 relative), into at least 2 and at most
/// [`MAX_SQUARE_CELLS`] per side.
pub fn square_cells(half: f64, dx: f64) -> Result<Vec<[f64; 2]>> {
    let n = 2.0 * half / dx;
    if !(dx.is_finite() && dx > 0.0 && n >= 2.0 && (n - n.round()).abs() <= 1e-9 * n)
        || n.round() as usize > MAX_SQUARE_CELLS
    {
        return Err(invalid(
            "dx",
            format!(
                "{} m must divide 2 l_f = {} m into 2 to {MAX_SQUARE_CELLS} whole cells",
                rsf_numeric::written(dx),
                rsf_numeric::number(2.0 * half)
            ),
        ));
    }
    let n = n.round() as usize;
    let at = |i: usize| -half + (i as f64 + 0.5) * dx;
    Ok((0..n)
        .flat_map(|j| (0..n).map(move |i| [at(i), at(j)]))
        .collect())
}

/// The fault alone on `cells` (from [`square_cells`]) of side `dx`: one vertex per cell
/// at `(0, x₂, x₃)`, of weight `dx²`, the normal `x` fixed, the load `dx² τ⁰` with
/// `tau0(x₂, x₃) = (τ⁰₂, τ⁰₃)` (Pa) in the free `y`, `z`.
///
/// # Errors
/// Those of [`Model::fault_only`].
pub fn square_model(
    cells: &[[f64; 2]],
    dx: f64,
    tau0: impl Fn(f64, f64) -> [f64; 2],
) -> Result<Model<3, 3>> {
    let centres = cells.iter().map(|c| [0.0, c[0], c[1]]).collect();
    let area = dx * dx;
    let mut model = Model::fault_only(centres, &vec![area; cells.len()], 0)?;
    for (k, c) in cells.iter().enumerate() {
        let t = tau0(c[0], c[1]);
        model.load[3 * k + 1] = area * t[0];
        model.load[3 * k + 2] = area * t[1];
    }
    Ok(model)
}

/// The whole space's operator of a square fault alone ([`WholeSpaceGrid::fault_alone`]).
///
/// # Errors
/// The operator's errors, as [`rsf::Error::InvalidParameter`] named `whole_space`.
pub fn square_operator(model: &Model<3, 3>, medium: Medium) -> Result<WholeSpaceGrid> {
    WholeSpaceGrid::fault_alone(model, medium).map_err(|e| invalid("whole_space", e.to_string()))
}

/// `ln θ` (θ in s) of the regularised law `f = a asinh(V/(2V₀) exp((f₀ + b ln(V₀θ/L))/a))`
/// at the friction coefficient `f` and slip rate `v` (m/s):
/// `ln(L/V₀) + (a/b) ln((2V₀/V) sinh(f/a)) − f₀/b`, with `ln sinh` in an overflow-safe
/// form.
pub(crate) fn ln_theta_at(params: &rsf_friction::RateStateParams, f: f64, v: f64) -> f64 {
    let x = f / params.a;
    // ln sinh x without overflow: x + ln((1 − e^{−2x})/2).
    let ln_sinh = x + (0.5 * (-(-2.0 * x).exp_m1())).ln();
    let ln_arg = (2.0 * params.v0 / v).ln() + ln_sinh;
    (params.l / params.v0).ln() + params.a / params.b * ln_arg - params.mu0 / params.b
}
