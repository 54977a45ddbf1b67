//! The options of the direct solver and the constants of its set-up.

use rsf_nonsmooth::Stopping;

/// Options of [`DirectSolver`](super::DirectSolver).
#[derive(Debug, Clone, PartialEq)]
pub struct DirectOptions {
    /// Stopping test of [`NonsmoothSolver::solve`](rsf_nonsmooth::NonsmoothSolver::solve): energy norm of the correction of an
    /// iteration of the condensed problem (the norm of its discrete harmonic extension in
    /// the energy norm, see [`DirectSolver::with_energy_norm`](super::DirectSolver::with_energy_norm)). Default: absolute 1e-13,
    /// relative 1e-13, 200 iterations.
    pub stopping: Stopping,
    /// A block enters the Newton step of the condensed iteration while its nonlinearity's
    /// Hessian is at most this multiple of the diagonal of the Schur complement; stiffer
    /// blocks are left to the Gauss–Seidel sweep, which contracts them by about the inverse
    /// of this ratio per iteration. Default 1e3.
    pub soft_ratio: f64,
    /// Largest memory (bytes) for the harmonic extension `Z` and `E Z` (`2 n |F|` values)
    /// held at once while forming `N = Zᵀ E Z` ([`DirectSolver::with_energy_norm`](super::DirectSolver::with_energy_norm)): above
    /// it `N` is formed block by block of columns (`Zᵀ (E Z_b)` by one more forward sweep
    /// per column, `O(n)` memory per thread), the same matrix up to round-off in the order
    /// of its sums. Default 4e9 bytes (`n |F| ≤ 2.5e8`: every problem for which the
    /// automatic solver choice picked this solver before the block-by-block form existed
    /// keeps its bits).
    pub max_extension_bytes: usize,
}

impl Default for DirectOptions {
    fn default() -> Self {
        Self {
            stopping: Stopping {
                absolute: 1e-13,
                relative: 1e-13,
                max_iterations: 200,
            },
            soft_ratio: 1e3,
            max_extension_bytes: 4_000_000_000,
        }
    }
}

impl DirectOptions {
    /// Whether the set-up holds the harmonic extension `Z` and `E Z` at once (`2 n |F|`
    /// values for `n` unknowns in the factor, `nf = |F|` of them on the interface) or
    /// forms `N` block by block ([`max_extension_bytes`](Self::max_extension_bytes)).
    pub(super) fn stores_extension(&self, n: usize, nf: usize) -> bool {
        2.0 * 8.0 * n as f64 * nf as f64 <= self.max_extension_bytes as f64
    }
}

/// Right-hand sides per backward sweep of the harmonic extension: the factor is read once
/// per block. Set-up of the direct solver (`cargo bench --bench velocity_solvers --
/// direct_setup`, reusing the analysis) with one right-hand side per sweep against blocks
/// of 32: see docs/performance.md.
pub(super) const HARMONIC_BLOCK: usize = 32;
