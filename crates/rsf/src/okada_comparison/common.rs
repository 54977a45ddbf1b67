//! What every comparison shares: the medium, the solver, the errors measured, the graded
//! grid lines.

use rsf_fem::geometric_grading;
use rsf_linalg::Parallelism;
use rsf_nonsmooth::Stopping;

use super::error::Result;
use crate::model::{Material, StaticMethod, StaticOptions};

/// Shear modulus μ (Pa).
pub const MU: f64 = 3e10;
/// Poisson's ratio ν.
pub const NU: f64 = 0.25;
/// The slip of the uniform cases (m).
pub const SLIP: f64 = 1.0;
/// The relative energy-norm correction at which [`Solver::Multigrid`] stops.
pub const MULTIGRID_TOLERANCE: f64 = 1e-10;

/// The model's material: μ = [`MU`], ν = [`NU`] (the density is not used: no mass).
pub(crate) fn material() -> Material {
    Material::new(2.0 * MU * (1.0 + NU), NU, 2700.0)
}

/// How the static problem is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solver {
    /// The direct solver on the finest mesh (its factor's memory grows like the vertices
    /// to the power 4/3 and more).
    Direct,
    /// Multigrid on the refinement hierarchy ([`StaticMethod::Multigrid`]: a Gauss–Seidel
    /// sweep and conjugate gradients preconditioned by V-cycles per iteration, to a
    /// relative correction of [`MULTIGRID_TOLERANCE`] in the energy norm, at most 500
    /// iterations, on every core): memory linear in the vertices.
    Multigrid,
}

impl Solver {
    /// The builder's options of the static solve.
    pub(crate) fn options(self) -> StaticOptions {
        match self {
            Solver::Direct => StaticOptions::method(StaticMethod::Direct),
            Solver::Multigrid => StaticOptions::method(StaticMethod::Multigrid)
                .with_stopping(Stopping {
                    absolute: 0.0,
                    relative: MULTIGRID_TOLERANCE,
                    max_iterations: 500,
                })
                .with_parallelism(Parallelism::default()),
        }
    }
}

/// The comparison of one mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Errors {
    /// The cell size on the fault (m; along strike: the grid's spacing).
    pub h: f64,
    /// Vertices of the model.
    pub vertices: usize,
    /// max over the surface window of `|u_FE − u_Okada|`, relative to max `|u_Okada|`
    /// there.
    pub surface: f64,
    /// max over the inner fault nodes of `|t_FE − σ n|`, relative to max `|σ n|` there
    /// (`n` the plus side's outward normal).
    pub traction: f64,
    /// max deviation of the model's jump `u⁺ − u⁻` from the prescribed slip (m).
    pub jump: f64,
}

/// `n` intervals of `spacing` each from `start` upwards, then graded intervals (the
/// grading by `ratio` of the coarsest mesh from `h0`, each interval split into `2^level`)
/// to `end`.
pub(crate) fn band_and_grading(
    start: f64,
    spacing: f64,
    n: usize,
    (h0, level, ratio): (f64, u32, f64),
    end: f64,
) -> Result<Vec<f64>> {
    let mut c: Vec<f64> = (0..=n).map(|i| start + i as f64 * spacing).collect();
    let last = c[n];
    if end - last > 1e-9 * h0 {
        let graded = geometric_grading(h0, 0.0, ratio, end - last)?;
        let parts = 1usize << level;
        for w in graded.windows(2) {
            for k in 1..=parts {
                c.push(last + w[0] + (w[1] - w[0]) * k as f64 / parts as f64);
            }
        }
    }
    Ok(c)
}

/// Lines from `below` to `above` through the band `[lo, hi]` (m): spacing `spacing` from
/// one cell below `lo` to one cell above `hi` (`hi − lo` a whole number of `spacing`), then
/// graded outwards on both sides as [`band_and_grading`].
pub(crate) fn band_lines(
    (lo, hi): (f64, f64),
    spacing: f64,
    grading: (f64, u32, f64),
    (below, above): (f64, f64),
) -> Result<Vec<f64>> {
    let n = ((hi - lo) / spacing).round() as usize + 2;
    let start = lo - spacing;
    let up = band_and_grading(start, spacing, n, grading, above)?;
    let down = band_and_grading(0.0, spacing, 0, grading, start - below)?;
    let mut c: Vec<f64> = down[1..].iter().rev().map(|d| start - d).collect();
    c.extend(&up);
    Ok(c)
}
