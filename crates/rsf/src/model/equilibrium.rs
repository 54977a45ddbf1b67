//! The static problem `K u = F` (free dofs; the fixed ones at their held values: 0, a
//! Dirichlet part's displacement, a prescribed slip), the initial equilibrium `u₀` of a
//! model being built and [`StaticSolver`]'s: by sparse Cholesky (faer), or — for a large
//! 3-D model with a refinement hierarchy, where the factor's fill (`O(n^{4/3})` values) is
//! the memory wall — by linear multigrid (TNNMG without nonlinearity) on the model's
//! prolongations (docs/scaling.md), watched if asked ([`SolveWatch`]: progress and a time
//! limit).

use rsf_fem::{ConstrainedSystem, SparseMatrix};
use rsf_linalg::Parallelism;
use rsf_nonsmooth::{NoNonlinearity, NonsmoothSolver, SolveReport, SolveWatch, Stopping};
use rsf_tnnmg::{Tnnmg, TnnmgOptions};

use super::Model;
use crate::error::{check_len, invalid, Error, Result};

/// Largest number of dofs of a 3-D model whose initial equilibrium is solved by sparse
/// Cholesky; larger 3-D models with a hierarchy use multigrid. Measured on the 3-D slider:
/// the factorisation at j = 4 (70 227 dofs) fits in the run's 745 MB, at j = 5 (530 000
/// dofs) it held 15.5 GB and had not finished after 9 min (docs/scaling.md).
pub const EQUILIBRIUM_DIRECT_MAX_DOFS_3D: usize = 250_000;

/// Relative tolerance of the multigrid equilibrium: the energy norm of the last correction
/// at most this multiple of `‖u₀‖_K`.
pub const EQUILIBRIUM_MULTIGRID_TOLERANCE: f64 = 1e-13;

/// The initial equilibrium's linear system `K u₀ = F` (free dofs; `u₀ = 0` on the fixed
/// ones: a model of some columns has no held displacements) as a model builder hands it to the solver of
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

/// Which solver a [`StaticSolver`] (and a model's initial equilibrium) uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StaticMethod {
    /// Sparse Cholesky, except for a 3-D model of more than
    /// [`EQUILIBRIUM_DIRECT_MAX_DOFS_3D`] dofs with a refinement hierarchy: multigrid.
    #[default]
    Auto,
    /// Sparse Cholesky of `K` on the free dofs (faer): memory `O(n^{4/3})` in 3-D.
    Direct,
    /// Linear multigrid on the model's prolongations (TNNMG without nonlinearity: a
    /// Gauss–Seidel sweep and conjugate gradients preconditioned by V(2,2)-cycles per
    /// iteration), stopped by the energy norm of `K`: memory linear in the dofs; needs a
    /// hierarchy.
    Multigrid,
}

/// How the static problem `K u = F` is solved ([`StaticSolver`],
/// [`ModelBuilder::equilibrium_solver`](crate::ModelBuilder::equilibrium_solver)).
#[derive(Debug)]
pub struct StaticOptions {
    /// The solver (default [`StaticMethod::Auto`]).
    pub method: StaticMethod,
    /// Multigrid's stopping test: the energy norm of the last correction, and the
    /// iteration cap (`None`: relative [`EQUILIBRIUM_MULTIGRID_TOLERANCE`] of `‖u‖_K`, 500
    /// iterations). Beyond the cap the solve fails with [`Error::Solver`]
    /// (`rsf_tnnmg::Error::NotConverged`: the iterations and the last correction).
    pub stopping: Option<Stopping>,
    /// Multigrid's progress reports and time limit (`None`: unwatched, the iteration cap
    /// alone). At the limit the solve fails with [`Error::Solver`]
    /// (`rsf_tnnmg::Error::TimeLimit`: the iterations, the last correction, the time).
    /// The direct solver is one factorisation and reports nothing.
    pub watch: Option<SolveWatch>,
    /// Multigrid's threads (default [`Parallelism::SEQ`]; the iterates do not depend on
    /// them, `rsf_tnnmg::Tnnmg::with_parallelism`).
    pub parallelism: Parallelism,
}

impl Default for StaticOptions {
    /// [`StaticMethod::Auto`], multigrid to a relative
    /// [`EQUILIBRIUM_MULTIGRID_TOLERANCE`] in at most 500 iterations, unwatched, on one
    /// thread.
    fn default() -> Self {
        Self {
            method: StaticMethod::Auto,
            stopping: None,
            watch: None,
            parallelism: Parallelism::SEQ,
        }
    }
}

impl StaticOptions {
    /// The default options with `method`.
    pub fn method(method: StaticMethod) -> Self {
        Self {
            method,
            ..Self::default()
        }
    }

    /// The same options with multigrid's stopping test.
    pub fn with_stopping(mut self, stopping: Stopping) -> Self {
        self.stopping = Some(stopping);
        self
    }

    /// The same options with multigrid on `parallelism`'s threads.
    pub fn with_parallelism(mut self, parallelism: Parallelism) -> Self {
        self.parallelism = parallelism;
        self
    }

    /// The same options with multigrid watched by `watch`.
    pub fn with_watch(mut self, watch: SolveWatch) -> Self {
        self.watch = Some(watch);
        self
    }
}

/// The static problem of a model set up once and solved for any held values: `u` with
/// `K u = F` on the free dofs and the given values on the fixed ones (Dirichlet data, the
/// prescribed jumps of a fault inside the body, in the model's unknowns) — e.g. the fields
/// of several slips on one fault (Green's functions), one [`solve`](Self::solve) each. A
/// model's own static problem is solved when it is built
/// ([`Model::initial_displacement`]); this solves it again, or with other data.
///
/// ```
/// use rsf::fem::cuboid;
/// use rsf::model::{PrescribedSlip, StaticOptions, StaticSolver};
/// use rsf::{Material, ModelBuilder, Part};
/// let model = ModelBuilder::new(cuboid([0.0; 3], [1.0; 3], [5, 5, 5])?)
///     .material(Material::new(1e10, 0.25, 2700.0))
///     .without_mass()
///     .dirichlet(Part::predicate("bottom", |x| x[2] < 1e-9), [0.0; 3])
///     .dirichlet(Part::predicate("top", |x| x[2] > 1.0 - 1e-9), [0.0; 3])
///     // A model needs a fault: a buried square with zero slip (the displacement stays
///     // continuous across it).
///     .internal_fault_polygon(
///         "fault",
///         &[[0.5, 0.25, 0.25], [0.5, 0.75, 0.25], [0.5, 0.75, 0.75], [0.5, 0.25, 0.75]],
///     )
///     .internal_slip_at(|_| Some(PrescribedSlip::InFrame([0.0, 0.0])))
///     .build()?;
/// let mut solver = StaticSolver::new(&model, StaticOptions::default())?;
/// // The top held 1 mm along x.
/// let mut u = vec![0.0; model.num_dofs()];
/// for (p, x) in model.vertices.iter().enumerate() {
///     if x[2] > 1.0 - 1e-9 {
///         u[3 * p] = 1e-3;
///     }
/// }
/// solver.solve(&mut u)?;
/// let middle = model.nearest_node(&[0.25, 0.5, 0.5])?;
/// assert!((u[3 * middle] - 5e-4).abs() < 2e-4);
/// # Ok::<(), rsf::Error>(())
/// ```
pub struct StaticSolver<const C: usize> {
    inner: Inner<C>,
    load: Vec<f64>,
}

/// The solver behind a [`StaticSolver`].
enum Inner<const C: usize> {
    Direct(Box<ConstrainedSystem>),
    Multigrid(Box<Tnnmg<C>>),
}

impl<const C: usize> StaticSolver<C> {
    /// Sets up the solver of `model`'s static problem: its stiffness with its fixed dofs
    /// and its load (the Cholesky factor, or the multigrid hierarchy on its prolongations).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `static_solver` for [`StaticMethod::Multigrid`]
    /// on a model without prolongations, named `columns` for a model of some columns
    /// ([`Model::columns`]); [`Error::Equilibrium`] if `K` is not positive definite on the
    /// free dofs (Cholesky); [`Error::Solver`] for multigrid's set-up and options.
    pub fn new<const D: usize>(model: &Model<D, C>, options: StaticOptions) -> Result<Self> {
        if model.columns.is_some() {
            return Err(invalid(
                "columns",
                "a model of some columns holds only part of K: its static problem is \
                 solved on its ranks",
            ));
        }
        Self::of::<D>(
            &model.stiffness,
            &model.fixed,
            model.load.clone(),
            &model.prolongations,
            options,
        )
    }

    /// [`new`](Self::new) on the parts of a model being built.
    pub(crate) fn of<const D: usize>(
        stiffness: &SparseMatrix,
        fixed: &[bool],
        load: Vec<f64>,
        prolongations: &[SparseMatrix],
        options: StaticOptions,
    ) -> Result<Self> {
        let n = load.len();
        let multigrid = match options.method {
            StaticMethod::Auto => {
                D == 3 && n > EQUILIBRIUM_DIRECT_MAX_DOFS_3D && !prolongations.is_empty()
            }
            StaticMethod::Direct => false,
            StaticMethod::Multigrid => {
                if prolongations.is_empty() {
                    return Err(invalid(
                        "static_solver",
                        "multigrid needs a refinement hierarchy (the model has no \
                         prolongations: build it with ModelBuilder::refined or \
                         from_hierarchy)",
                    ));
                }
                true
            }
        };
        let inner = if multigrid {
            let mut opts = multigrid_options();
            if let Some(stopping) = options.stopping {
                opts.stopping = stopping;
            }
            let k = stiffness.as_ref();
            let mut mg = Tnnmg::<C>::new(k, fixed, prolongations, Some(k), opts)?;
            if let Some(watch) = options.watch {
                mg = mg.with_watch(watch);
            }
            if options.parallelism.is_parallel() {
                mg = mg.with_parallelism(options.parallelism);
            }
            Inner::Multigrid(Box::new(mg))
        } else {
            let system =
                ConstrainedSystem::new(stiffness.as_ref(), fixed).map_err(|e| match e {
                    rsf_fem::Error::NotPositiveDefinite { .. } => Error::Equilibrium(e),
                    e => Error::Fem(e),
                })?;
            Inner::Direct(Box::new(system))
        };
        Ok(Self { inner, load })
    }

    /// The solver in use ([`StaticMethod::Direct`] or [`StaticMethod::Multigrid`]).
    pub fn method(&self) -> StaticMethod {
        match self.inner {
            Inner::Direct(_) => StaticMethod::Direct,
            Inner::Multigrid(_) => StaticMethod::Multigrid,
        }
    }

    /// Solves `K u = F` on the free dofs: on entry the fixed entries of `u` (model
    /// unknowns, `C` per vertex) hold their values — held displacements, prescribed jumps —
    /// and the free entries multigrid's initial iterate (the direct solver ignores them);
    /// on exit the free entries solve the problem. Returns multigrid's report (`None` for
    /// the direct solver).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `u` for another length than the model's dofs;
    /// [`Error::Fem`] from the direct solve; [`Error::Solver`] for multigrid's
    /// non-convergence within its iteration cap or time limit (both say the iterations and
    /// the last correction) or a non-finite `u`.
    pub fn solve(&mut self, u: &mut [f64]) -> Result<Option<SolveReport>> {
        check_len("u", u.len(), self.load.len(), |len, expected| {
            format!("has {len} entries, the model {expected} dofs")
        })?;
        match &mut self.inner {
            Inner::Direct(s) => {
                s.solve(&self.load, u)?;
                Ok(None)
            }
            Inner::Multigrid(mg) => Ok(Some(mg.solve(&self.load, &NoNonlinearity, u)?)),
        }
    }
}

/// `u₀` with `K u₀ = F` on the free dofs, `held` on the fixed ones (0 for `None`), by
/// `options` ([`StaticOptions`]; the default: Cholesky, or multigrid for a large 3-D model
/// with a hierarchy).
///
/// # Errors
/// As [`StaticSolver::new`] and [`StaticSolver::solve`].
pub(crate) fn solve<const D: usize, const C: usize>(
    stiffness: &SparseMatrix,
    fixed: &[bool],
    load: &[f64],
    prolongations: &[SparseMatrix],
    held: Option<&[f64]>,
    options: StaticOptions,
) -> Result<Vec<f64>> {
    let n = load.len();
    let mut u0 = held.map_or_else(|| vec![0.0; n], <[f64]>::to_vec);
    StaticSolver::<C>::of::<D>(stiffness, fixed, load.to_vec(), prolongations, options)?
        .solve(&mut u0)?;
    Ok(u0)
}

/// `u₀` with `K u₀ = F` on the free dofs (0 on the fixed ones), solved on the ranks of a
/// job by [`DistributedTnnmg`](rsf_tnnmg::distributed::DistributedTnnmg) without
/// nonlinearity (linear V-cycles on `prolongations`, stopped as the one-process multigrid
/// branch: the energy norm of the last correction at most
/// [`EQUILIBRIUM_MULTIGRID_TOLERANCE`] times `‖u₀‖_K`, at most 500 iterations): what a
/// model whose ranks hold only their own columns of `K` (`ModelBuilder` on ranks) solves,
/// at every size (sparse Cholesky would need `K` whole). `owner` is fine node `p`'s rank
/// (length the node count; the owner vector of a
/// [`TnnmgOnRanks`](crate::method::TnnmgOnRanks)) and `transport` this rank's end of a
/// fresh group of the job's ranks (one call of its transport factory: every rank calls
/// this in the same order). Of `stiffness` each rank reads only the columns of the nodes
/// it owns; `load` and `fixed` are whole (length `n`), and so is the result, with the same
/// bits on every rank and at every rank count. Collective.
///
/// # Errors
/// [`Error::Solver`] if the multigrid does not converge in 500 iterations, or as
/// `DistributedTnnmg::new` for the matrix and the partition (on every rank).
pub fn equilibrium_on_ranks<const C: usize>(
    stiffness: &SparseMatrix,
    fixed: &[bool],
    load: &[f64],
    prolongations: &[SparseMatrix],
    (owner, transport): (&[usize], Box<dyn rsf_ranks::RankGroup>),
) -> Result<Vec<f64>> {
    let options = rsf_tnnmg::distributed::DistributedTnnmgOptions::from_tnnmg(&multigrid_options())
        .expect("the multigrid branches run V-cycles");
    let ps: Vec<_> = prolongations.iter().map(|p| p.as_ref()).collect();
    let mut mg = rsf_tnnmg::distributed::DistributedTnnmg::<C>::new(
        stiffness.as_ref(),
        fixed,
        &ps,
        None,
        options,
        owner,
        transport,
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
        let mut mg = vec![0.0; model.num_dofs()];
        // The scene's model is of the `rsf` that `rsf-scenes` links (another crate instance
        // in this unit test): its parts, not the model, go in.
        let mut solver = StaticSolver::<3>::of::<3>(
            &model.stiffness,
            &model.fixed,
            model.load.clone(),
            &model.prolongations,
            StaticOptions::method(StaticMethod::Multigrid),
        )
        .unwrap();
        assert_eq!(solver.method(), StaticMethod::Multigrid);
        solver.solve(&mut mg).unwrap();
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
