//! Reference kernels with a known low-rank far field, for tests, benches and comparisons.

use crate::error::Error;
use crate::points::Points;

/// The antiplane boundary-element operator of a vertical strike-slip fault in a
/// homogeneous half-space (the SEAS BP1 geometry), on `n` cells of height `h` from the
/// free surface down, cell centres at depth `z_i = (i + ½) h`:
///
/// ```text
/// K(z, ζ) = μ/(2π) [ 1/(z − ζ − h/2) − 1/(z − ζ + h/2)
///                  − 1/(z + ζ − h/2) + 1/(z + ζ + h/2) ]
/// ```
///
/// is the shear stress at depth `z` from unit slip on the cell `[ζ − h/2, ζ + h/2]` (two
/// screw dislocations of opposite sign) with its image across the free surface (the
/// second bracket, `ζ → −ζ`). `K` is symmetric, negative on the diagonal (`−4/h` scaled
/// by `μ/(2π)`, less the image), positive off the diagonal, and negative definite: slip on
/// a cell relaxes the stress on itself. Units: `μ` in Pa, `h` in m, `K` in Pa/m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AntiplaneHalfSpace {
    mu: f64,
    h: f64,
    n: usize,
}

impl AntiplaneHalfSpace {
    /// `n` cells of height `h` (m), shear modulus `mu` (Pa).
    ///
    /// # Errors
    /// [`Error::Option`] unless `mu` and `h` are finite and positive.
    pub fn new(n: usize, h: f64, mu: f64) -> Result<Self, Error> {
        for (name, value) in [("h", h), ("mu", mu)] {
            if !(value.is_finite() && value > 0.0) {
                return Err(Error::Option {
                    name,
                    value,
                    expected: "finite and > 0",
                });
            }
        }
        Ok(Self { mu, h, n })
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether there are no cells.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Depth of the centre of cell `i` (m).
    pub fn depth(&self, i: usize) -> f64 {
        (i as f64 + 0.5) * self.h
    }

    /// The cell centres as 1-D points.
    pub fn points(&self) -> Points {
        let z: Vec<f64> = (0..self.n).map(|i| self.depth(i)).collect();
        // Finite by construction (h finite, i < n).
        Points::new(&z, 1).unwrap_or_else(|_| unreachable!("finite depths"))
    }

    /// Entry `K(z_i, z_j)` (Pa/m).
    pub fn entry(&self, i: usize, j: usize) -> f64 {
        let (z, zeta, hh) = (self.depth(i), self.depth(j), 0.5 * self.h);
        let d = z - zeta;
        let s = z + zeta;
        self.mu / (2.0 * std::f64::consts::PI)
            * ((1.0 / (d - hh) - 1.0 / (d + hh)) - (1.0 / (s - hh) - 1.0 / (s + hh)))
    }
}
