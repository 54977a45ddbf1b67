//! The library's dislocation kernels at points, as numpy arrays (docs/python.md,
//! "Dislocation kernels"): Okada's rectangle of any strike and dip, Nikkhoo & Walter's
//! triangle, each in a half-space or the whole space — for checks against other
//! implementations and for Green's functions of your own.

use numpy::{IntoPyArray, PyArray2, PyArray3, PyArrayMethods};
use pyo3::prelude::*;
use rsf::halfspace::{Element, Medium, RectangleElement, Space, Triangle};

use crate::errors::invalid;

/// The points of an `(n, 3)` array-like, refused naming `name` otherwise.
fn points(name: &str, points: &Bound<'_, PyAny>) -> PyResult<Vec<[f64; 3]>> {
    Ok(crate::arrays::reals_2d(name, points, Some(3))?
        .rows()
        .into_iter()
        .map(|r| [r[0], r[1], r[2]])
        .collect())
}

fn space_of(space: &str) -> PyResult<Space> {
    match space {
        "half" | "half-space" | "halfspace" => Ok(Space::HalfSpace),
        "whole" | "whole-space" | "full" => Ok(Space::WholeSpace),
        other => Err(invalid(
            "space",
            format!("\"half\" or \"whole\", not {other:?}"),
        )),
    }
}

type Arrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray3<f64>>);

/// Displacement and stress of `element`'s `slip` at every point, released GIL.
fn evaluate<'py>(
    py: Python<'py>,
    element: &(dyn Element + Sync),
    at: &[[f64; 3]],
    slip: [f64; 3],
    (mu, nu): (f64, f64),
    space: Space,
) -> PyResult<Arrays<'py>> {
    let medium = Medium::from_shear_poisson(mu, nu).map_err(|e| invalid("mu, nu", e))?;
    if let Some(s) = slip.iter().find(|s| !s.is_finite()) {
        return Err(invalid("slip", format!("{s} is not finite")));
    }
    let n = at.len();
    let result = py.detach(|| -> Result<(Vec<f64>, Vec<f64>), String> {
        let (mut u, mut s) = (Vec::with_capacity(3 * n), Vec::with_capacity(9 * n));
        for (p, x) in at.iter().enumerate() {
            let r = element
                .unit_responses(&medium, space, *x)
                .map_err(|e| format!("point {p} {x:?}: {e}"))?;
            let grad: [[f64; 3]; 3] = std::array::from_fn(|i| {
                std::array::from_fn(|j| (0..3).map(|k| slip[k] * r[k].grad[i][j]).sum())
            });
            u.extend((0..3).map(|i| (0..3).map(|k| slip[k] * r[k].u[i]).sum::<f64>()));
            s.extend(medium.stress(&grad).iter().flatten());
        }
        Ok((u, s))
    });
    let (u, s) = result.map_err(|e| invalid("points", e))?;
    Ok((
        u.into_pyarray(py).reshape([n, 3])?,
        s.into_pyarray(py).reshape([n, 3, 3])?,
    ))
}

/// Displacement (m, shape `(n, 3)`) and stress (Pa, shape `(n, 3, 3)`, tension
/// positive) at `points` (m, shape `(n, 3)`; `z` up, the half-space `z ≤ 0`) of a
/// rectangular dislocation (Okada 1992): centre `centre` (m), the strike direction
/// `(cos φ, sin φ, 0)` at `strike` = φ (degrees counter-clockwise from `+x`), `dip`
/// (degrees, Okada's: the hanging wall the side the normal `e_s × e_d` points to),
/// `length` along strike and `width` along dip (m), slip `[strike, dip, opening]` (m, the
/// hanging wall's motion relative to the footwall), shear modulus `mu` (Pa) and Poisson's
/// ratio `nu`, in `space` "half" or "whole".
#[pyfunction]
#[pyo3(signature = (points, centre, strike, dip, length, width, slip, mu, nu, space = "half"))]
#[expect(
    clippy::too_many_arguments,
    reason = "a Python function's keyword arguments: the rectangle's parameters by name"
)]
pub(crate) fn rectangle_deformation<'py>(
    py: Python<'py>,
    points: &Bound<'_, PyAny>,
    centre: [f64; 3],
    strike: f64,
    dip: f64,
    length: f64,
    width: f64,
    slip: [f64; 3],
    mu: f64,
    nu: f64,
    space: &str,
) -> PyResult<Arrays<'py>> {
    let element = RectangleElement::new(centre, strike, dip, length, width)
        .map_err(|e| invalid("rectangle", e))?;
    let space = space_of(space)?;
    element
        .check_space(space)
        .map_err(|e| invalid("rectangle", e))?;
    evaluate(
        py,
        &element,
        &self::points("points", points)?,
        slip,
        (mu, nu),
        space,
    )
}

/// Displacement (m, shape `(n, 3)`) and stress (Pa, shape `(n, 3, 3)`, tension
/// positive) at `points` (m, shape `(n, 3)`; `z` up) of a triangular dislocation
/// (Nikkhoo & Walter 2015) of `vertices` (m, shape `(3, 3)`), slip `[strike, dip,
/// opening]` (m) in the triangle's frame (normal `(P2 − P1) × (P3 − P1)`, strike
/// `e_z × n`, up dip `n × e_s`; the slip of the side the normal points into, as cutde's),
/// shear modulus `mu` (Pa) and Poisson's ratio `nu`, in `space` "half" or "whole".
#[pyfunction]
#[pyo3(signature = (points, vertices, slip, mu, nu, space = "half"))]
#[expect(
    clippy::too_many_arguments,
    reason = "a Python function's keyword arguments (and the interpreter's token)"
)]
pub(crate) fn triangle_deformation<'py>(
    py: Python<'py>,
    points: &Bound<'_, PyAny>,
    vertices: &Bound<'_, PyAny>,
    slip: [f64; 3],
    mu: f64,
    nu: f64,
    space: &str,
) -> PyResult<Arrays<'py>> {
    let v = self::points("vertices", vertices)?;
    let v: [[f64; 3]; 3] = v
        .try_into()
        .map_err(|_| invalid("vertices", "shape (3, 3)"))?;
    let triangle = Triangle::new(v).map_err(|e| invalid("vertices", e))?;
    let space = space_of(space)?;
    triangle
        .check_space(space)
        .map_err(|e| invalid("vertices", e))?;
    evaluate(
        py,
        &triangle,
        &self::points("points", points)?,
        slip,
        (mu, nu),
        space,
    )
}
