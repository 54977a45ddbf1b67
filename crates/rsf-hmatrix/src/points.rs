//! Validated point sets (one point per unknown).

use crate::error::Error;

/// A set of points in dimension 1, 2 or 3, one per unknown of the matrix: point `i` is the
/// position of unknown `i` (row and column `i`).
///
/// For the fault operator condensed onto the fault, whose unknowns are the free components
/// of the frictional nodes in order (`C` components per node, component-minor), the caller
/// repeats each node's coordinates once per free component, so that the points are in the
/// unknowns' order. Coincident points are allowed (they are never separated by the
/// admissibility condition: their blocks stay dense), and coincident points with
/// consecutive indices stay in one leaf cluster (so in one part of
/// [`HMatrix::split_rows`](crate::HMatrix::split_rows)).
#[derive(Debug, Clone, PartialEq)]
pub struct Points {
    coords: Vec<f64>,
    dim: usize,
}

impl Points {
    /// Points from a flat slice of coordinates, point-major (`coords[dim * i + c]` is
    /// coordinate `c` of point `i`), in the unit of length of the caller.
    ///
    /// # Errors
    /// [`Error::Dimension`] unless `1 ≤ dim ≤ 3`; [`Error::CoordinateCount`] if the length
    /// is not a multiple of `dim`; [`Error::NonFiniteCoordinate`] for NaN or infinity.
    pub fn new(coords: &[f64], dim: usize) -> Result<Self, Error> {
        if !(1..=3).contains(&dim) {
            return Err(Error::Dimension(dim));
        }
        if coords.len() % dim != 0 {
            return Err(Error::CoordinateCount {
                len: coords.len(),
                dim,
            });
        }
        if let Some(k) = coords.iter().position(|c| !c.is_finite()) {
            return Err(Error::NonFiniteCoordinate {
                point: k / dim,
                component: k % dim,
            });
        }
        Ok(Self {
            coords: coords.to_vec(),
            dim,
        })
    }

    /// Points from an array of fixed-size coordinates.
    ///
    /// # Errors
    /// As [`Points::new`].
    pub fn from_array<const D: usize>(points: &[[f64; D]]) -> Result<Self, Error> {
        Self::new(points.as_flattened(), D)
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.coords.len() / self.dim
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }

    /// The dimension (1, 2 or 3).
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The coordinates of point `i`.
    ///
    /// # Panics
    /// If `i ≥ len()`.
    pub fn point(&self, i: usize) -> &[f64] {
        &self.coords[self.dim * i..self.dim * (i + 1)]
    }
}
