//! The initial equilibrium `K u₀ = F` (free dofs; fixed dofs 0) of a model being built:
//! by sparse Cholesky (faer), or — for a large 3-D model with a refinement hierarchy,
//! where the factor's fill (`O(n^{4/3})` values) is the memory wall — by linear multigrid
//! (TNNMG without nonlinearity) on the model's prolongations (docs/scaling.md).

use rsf_fem::{ConstrainedSystem, SparseMatrix};
use rsf_nonsmooth::{NoNonlinearity, NonsmoothSolver, Stopping};
use rsf_tnnmg::{Tnnmg, TnnmgOptions};

use crate::error::{Error, Result};

/// Largest number of dofs of a 3-D model whose initial equilibrium is solved by sparse
/// Cholesky; larger 3-D models with a hierarchy use multigrid. Measured on the 3-D slider:
/// the factorisation at j = 4 (70 227 dofs) fits in the run's 745 MB, at j = 5 (530 000
/// dofs) it held 15.5 GB and had not finished after 9 min (docs/scaling.md).
pub const EQUILIBRIUM_DIRECT_MAX_DOFS_3D: usize = 250_000;

/// Relative tolerance of the multigrid equilibrium: the energy norm of the last correction
/// at most this multiple of `‖u₀‖_K`.
pub const EQUILIBRIUM_MULTIGRID_TOLERANCE: f64 = 1e-13;

/// The initial equilibrium's linear system `K u₀ = F` (free dofs; `u₀ = 0` on the fixed
/// ones) as a model builder hands it to the solver of
/// [`ModelBuilder::build_columns`](crate::ModelBuilder::build_columns), in the model's
/// unknowns (nodal frames, slip factor applied), `n = C · vertices` dofs node-major.
#[derive(Debug, Clone, Copy)]
pub struct EquilibriumSystem<'a> {
    /// `K` (`n × n`, N/m): the whole matrix for
    /// [`ModelBuilder::build`](crate::ModelBuilder::build), only the kept nodes' columns
    /// ([`columns`](Self::columns)) for [`build_columns`](crate::ModelBuilder::build_columns)
    /// (a process's part of a distributed matrix; symmetric, so a column is a row).
    pub stiffness: &'a rsf_fem::SparseMatrix,
    /// The kept nodes (one flag per vertex), `None` for a whole `stiffness`.
    pub columns: Option<&'a [bool]>,
    /// Per dof (`n`): constrained (`u₀ = 0` there).
    pub fixed: &'a [bool],
    /// `F` (`n` entries, N): the whole load on every process.
    pub load: &'a [f64],
    /// The hierarchy's prolongations, coarse to fine, the finest onto the model's unknowns
    /// (whole matrices; may be empty).
    pub prolongations: &'a [SparseMatrix],
}

/// `u₀` with `K u₀ = F` on the free dofs, 0 on the fixed ones.
///
/// # Errors
/// [`Error::Equilibrium`] if `K` is not positive definite on the free dofs (Cholesky);
/// [`Error::Solver`] if multigrid does not converge in 500 iterations; [`Error::Fem`].
pub(crate) fn solve<const D: usize, const C: usize>(
    stiffness: &SparseMatrix,
    fixed: &[bool],
    load: &[f64],
    prolongations: &[SparseMatrix],
) -> Result<Vec<f64>> {
    let n = load.len();
    if D == 3 && n > EQUILIBRIUM_DIRECT_MAX_DOFS_3D && !prolongations.is_empty() {
        return multigrid::<C>(stiffness, fixed, load, prolongations);
    }
    let mut u0 = vec![0.0; n];
    ConstrainedSystem::new(stiffness.as_ref(), fixed)
        .and_then(|mut s| s.solve(load, &mut u0))
        .map_err(|e| match e {
            rsf_fem::Error::NotPositiveDefinite { .. } => Error::Equilibrium(e),
            e => Error::Fem(e),
        })?;
    Ok(u0)
}

/// The multigrid branch of [`solve`]: TNNMG without nonlinearity (linear V-cycles on the
/// prolongations), stopped by the energy norm of `K`.
fn multigrid<const C: usize>(
    stiffness: &SparseMatrix,
    fixed: &[bool],
    load: &[f64],
    prolongations: &[SparseMatrix],
) -> Result<Vec<f64>> {
    let options = multigrid_options();
    let k = stiffness.as_ref();
    let mut mg = Tnnmg::<C>::new(k, fixed, prolongations, Some(k), options)?;
    let mut u0 = vec![0.0; load.len()];
    mg.solve(load, &NoNonlinearity, &mut u0)?;
    Ok(u0)
}

/// `u₀` with `K u₀ = F` on the free dofs (0 on the fixed ones), solved on the ranks of a
/// job by [`DistributedTnnmg`](rsf_tnnmg::distributed::DistributedTnnmg) without
/// nonlinearity (linear V-cycles on `prolongations`, stopped as the one-process multigrid
/// branch: the energy norm of the last correction at most
/// [`EQUILIBRIUM_MULTIGRID_TOLERANCE`] times `‖u₀‖_K`, at most 500 iterations): what a
/// model whose ranks hold only their own columns of `K` (`ModelBuilder` on ranks) solves,
/// at every size (sparse Cholesky would need `K` whole). Of `stiffness` each rank reads
/// only the columns of the nodes it owns (`ranks.owner`); `load` and `fixed` are whole
/// (length `n`), and so is the result, with the same bits on every rank and at every rank
/// count. It takes one transport from `ranks` (every rank calls this in the same order).
/// Collective.
///
/// # Errors
/// [`Error::Solver`] if the multigrid does not converge in 500 iterations, or as
/// `DistributedTnnmg::new` for the matrix and the partition (on every rank);
/// [`Error::InvalidParameter`] named `tnnmg.cycle_index` as
/// [`TnnmgOnRanks::options`](crate::method::TnnmgOnRanks::options).
pub fn equilibrium_on_ranks<const C: usize>(
    stiffness: &SparseMatrix,
    fixed: &[bool],
    load: &[f64],
    prolongations: &[SparseMatrix],
    ranks: &crate::method::TnnmgOnRanks,
) -> Result<Vec<f64>> {
    let options = crate::method::TnnmgOnRanks::options(&multigrid_options())?;
    let ps: Vec<_> = prolongations.iter().map(|p| p.as_ref()).collect();
    let mut mg = rsf_tnnmg::distributed::DistributedTnnmg::<C>::new(
        stiffness.as_ref(),
        fixed,
        &ps,
        None,
        options,
        &ranks.owner,
        (ranks.transport)(),
    )?;
    let mut u0 = vec![0.0; load.len()];
    mg.solve(load, &NoNonlinearity, &mut u0)?;
    Ok(u0)
}

/// The stopping test of the multigrid branches.
fn multigrid_options() -> TnnmgOptions {
    TnnmgOptions {
        stopping: Stopping {
            absolute: 0.0,
            relative: EQUILIBRIUM_MULTIGRID_TOLERANCE,
            max_iterations: 500,
        },
        ..TnnmgOptions::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Multigrid and Cholesky give the same equilibrium of the 3-D slider (level 2, where
    /// the builder uses Cholesky), to the multigrid tolerance in the energy norm.
    #[test]
    fn multigrid_equals_cholesky_on_the_3d_slider() {
        let model = rsf_scenes::Slider3dScene::default().build_model().unwrap();
        assert!(model.num_dofs() <= EQUILIBRIUM_DIRECT_MAX_DOFS_3D);
        let direct = &model.initial_displacement;
        let mg = multigrid::<3>(
            &model.stiffness,
            &model.fixed,
            &model.load,
            &model.prolongations,
        )
        .unwrap();
        let k_norm = |x: &[f64]| {
            let mut y = vec![0.0; x.len()];
            rsf_fem::spmv_add(model.stiffness.as_ref(), 1.0, x, &mut y);
            x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>().sqrt()
        };
        let diff: Vec<f64> = direct.iter().zip(&mg).map(|(a, b)| a - b).collect();
        let rel = k_norm(&diff) / k_norm(direct);
        println!("‖u_mg − u_chol‖_K / ‖u_chol‖_K = {rel:e}");
        assert!(rel > 0.0 && rel <= 1e-11, "{rel:e}");
    }
}
