//! The fault's Schur complement `S` column by column, from static solves (issue 70, item
//! 3; docs/three-d.md, "Columns of S by solves"): column `j` of `S = K_FF − K_FI K_II⁻¹ K_IF`
//! is `(K u)_F` for the `u` with a unit slip at the `j`-th slip unknown, zero at the other
//! slip unknowns and at the model's fixed dofs, and `K u = 0` on the rest — one static
//! problem per column, solved by the model's [`StaticSolver`] (multigrid on the model's
//! refinement hierarchy, memory linear in the dofs; or the sparse Cholesky factor of the
//! interior). Any subset of the columns can be asked for (a process its own), and the
//! columns feed the ℋ-matrix's construction from columns
//! ([`SchurColumns::hierarchical`]), which holds two batches of them at a time, never `S`.

use std::sync::Mutex;
use std::time::Instant;

use faer::MatMut;
use rsf_fem::SparseMatrix;
use rsf_hmatrix::{ColumnsError, HMatrix, HOptions, Points};

use super::equilibrium::{StaticOptions, StaticSolver};
use super::Model;
use crate::error::{invalid, Error, Result};

/// The columns of a model's fault Schur complement `S` (the slip → traction operator of
/// the fault ODE's finite-element kernel, N/m per m of slip, in the model's unknowns) by
/// one static solve per column: no factor of the volume is formed with
/// [`StaticMethod::Multigrid`](super::StaticMethod::Multigrid), so the memory is the
/// model's matrices, the hierarchy and the columns asked for.
///
/// The slip unknowns are the free components of the frictional boundary's nodes, node by
/// node (the order of the fault ODE's unknowns and of [`rsf_direct::SchurOnly`]'s
/// interface): `m` of them ([`dim`](Self::dim)). A column solved by multigrid carries the
/// solver's error: multigrid stops when the energy norm of its last correction is at most
/// the stopping test's tolerance ([`StaticOptions::stopping`]; by default a relative
/// [`EQUILIBRIUM_MULTIGRID_TOLERANCE`](super::EQUILIBRIUM_MULTIGRID_TOLERANCE)), and the
/// column's error is of that order relative to `S`'s diagonal (measured in
/// `tests/suite/schur_columns.rs`).
///
/// ```
/// use rsf::fem::cuboid;
/// use rsf::model::{SchurColumns, StaticMethod, StaticOptions};
/// use rsf::{Material, ModelBuilder, Part};
/// // A 2 m cube refined once (a hierarchy for multigrid), the bottom clamped, a buried
/// // square fault in the plane x = 0.
/// let model = ModelBuilder::refined(cuboid([-1.0; 3], [2.0; 3], [5; 3])?, 1)?
///     .material(Material::new(1e10, 0.25, 2700.0))
///     .without_mass()
///     .dirichlet(Part::predicate("bottom", |x| x[2] < -1.0 + 1e-9), [0.0; 3])
///     .internal_fault_polygon(
///         "fault",
///         &[[0.0, -0.5, -0.5], [0.0, 0.5, -0.5], [0.0, 0.5, 0.5], [0.0, -0.5, 0.5]],
///     )
///     .build()?;
/// let columns = SchurColumns::new(&model, StaticOptions::method(StaticMethod::Multigrid))?;
/// let m = columns.dim();
/// let mut s = rsf::faer::Mat::<f64>::zeros(m, 2);
/// columns.columns(&[0, 1], s.as_mut())?;
/// // A unit slip is resisted (S is positive definite on the slip unknowns).
/// assert!(s[(0, 0)] > 0.0 && s[(1, 1)] > 0.0);
/// // S is symmetric: S_01 = S_10 to the solver's tolerance.
/// assert!((s[(0, 1)] - s[(1, 0)]).abs() < 1e-8 * s[(0, 0)]);
/// # Ok::<(), rsf::Error>(())
/// ```
pub struct SchurColumns<'a, const D: usize, const C: usize> {
    model: &'a Model<D, C>,
    interface: Vec<usize>,
    work: Mutex<Work<C>>,
}

/// The solver and its work vector, and what it did.
struct Work<const C: usize> {
    solver: StaticSolver<C>,
    u: Vec<f64>,
    report: SchurColumnsReport,
}

/// What a [`SchurColumns`] has done so far.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SchurColumnsReport {
    /// Columns computed (static solves).
    pub columns: usize,
    /// Multigrid iterations over all solves (0 for the direct solver).
    pub iterations: usize,
    /// Most multigrid iterations of one solve.
    pub max_iterations: usize,
    /// Wall time of the solves and products (s).
    pub seconds: f64,
}

impl<'a, const D: usize, const C: usize> SchurColumns<'a, D, C> {
    /// Sets up the static solver of `model` with its slip unknowns held (multigrid's
    /// hierarchy, or the Cholesky factor of the interior, as `options` says).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `frictional_boundary` for a model without free
    /// slip unknowns, named `columns` for a model of some columns; as
    /// [`StaticSolver::new`] (multigrid without a hierarchy, a model of some columns, `K`
    /// not positive definite on the interior, multigrid's options).
    pub fn new(model: &'a Model<D, C>, options: StaticOptions) -> Result<Self> {
        if model.columns.is_some() {
            return Err(invalid(
                "columns",
                "a model of some columns holds only part of K: S's columns need K whole",
            ));
        }
        let interface: Vec<usize> = model
            .frictional_boundary
            .nodes
            .iter()
            .flat_map(|&p| C * p..C * p + C)
            .filter(|&i| !model.fixed[i])
            .collect();
        if interface.is_empty() {
            return Err(invalid(
                "frictional_boundary",
                "has no free slip unknowns: S has no columns",
            ));
        }
        let mut held = model.fixed.clone();
        for &i in &interface {
            held[i] = true;
        }
        let n = model.num_dofs();
        let solver = StaticSolver::<C>::of::<D>(
            &model.stiffness,
            &held,
            vec![0.0; n],
            &model.prolongations,
            options,
        )?;
        Ok(Self {
            model,
            interface,
            work: Mutex::new(Work {
                solver,
                u: vec![0.0; n],
                report: SchurColumnsReport::default(),
            }),
        })
    }

    /// `m`, the number of slip unknowns (`S` is `m × m`).
    pub fn dim(&self) -> usize {
        self.interface.len()
    }

    /// The model dof of each slip unknown (length `m`, increasing).
    pub fn interface_dofs(&self) -> &[usize] {
        &self.interface
    }

    /// The solver in use.
    pub fn method(&self) -> super::StaticMethod {
        self.lock().solver.method()
    }

    /// What was done so far (columns, multigrid iterations, time).
    pub fn report(&self) -> SchurColumnsReport {
        self.lock().report
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Work<C>> {
        // A panic in another caller leaves the work vector to be reset anyway.
        self.work
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Columns `cols` of `S` (indices of slip unknowns, any order, `< m`) into `out`
    /// (`m × cols.len()`, column `k` of `out` is column `cols[k]` of `S`). One static solve
    /// per column; calls from several threads take turns.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `cols` for an index `≥ m` or an `out` of another
    /// shape; [`Error::Solver`] if multigrid does not converge (its iterations and last
    /// correction) or stops at its time limit; [`Error::Fem`] from the direct solve.
    pub fn columns(&self, cols: &[usize], mut out: MatMut<'_, f64>) -> Result<()> {
        let m = self.dim();
        if out.nrows() != m || out.ncols() != cols.len() {
            return Err(invalid(
                "cols",
                format!(
                    "an output of {} × {} for {} columns of an S of {m} rows",
                    out.nrows(),
                    out.ncols(),
                    cols.len()
                ),
            ));
        }
        if let Some(&j) = cols.iter().find(|&&j| j >= m) {
            return Err(invalid(
                "cols",
                format!("column {j} of an S of {m} columns"),
            ));
        }
        let clock = Instant::now();
        let mut work = self.lock();
        let Work { solver, u, report } = &mut *work;
        for (k, &j) in cols.iter().enumerate() {
            u.fill(0.0);
            u[self.interface[j]] = 1.0;
            let solved = solver.solve(u)?;
            if let Some(r) = solved {
                report.iterations += r.iterations;
                report.max_iterations = report.max_iterations.max(r.iterations);
            }
            report.columns += 1;
            for (i, &dof) in self.interface.iter().enumerate() {
                out[(i, k)] = row_times(&self.model.stiffness, dof, u);
            }
        }
        report.seconds += clock.elapsed().as_secs_f64();
        Ok(())
    }

    /// `S` whole (`m × m`): every column, [`columns`](Self::columns) in one call.
    ///
    /// # Errors
    /// As [`columns`](Self::columns).
    pub fn dense(&self) -> Result<faer::Mat<f64>> {
        let m = self.dim();
        let mut s = faer::Mat::zeros(m, m);
        let all: Vec<usize> = (0..m).collect();
        self.columns(&all, s.as_mut())?;
        Ok(s)
    }

    /// `S` compressed into an ℋ-matrix as its columns come
    /// ([`HMatrix::from_symmetric_columns`]: two batches of columns held at a time, never
    /// `S` whole; every column is computed once), its points the slip unknowns' nodes, the
    /// components of a node interleaved as the fault ODE's kernel has them. `options`'
    /// `components` is set from the interface (the slip components per node).
    ///
    /// # Errors
    /// As [`columns`](Self::columns) for a column's solve; [`Error::HMatrix`] for invalid
    /// options, a non-finite entry or an SVD that does not converge.
    pub fn hierarchical(&self, options: &HOptions) -> Result<HMatrix> {
        let points = interface_points(self.model, &self.interface)?;
        let options = HOptions {
            components: components_per_node(&self.interface, C),
            ..options.clone()
        };
        HMatrix::from_symmetric_columns(|cols, out| self.columns(cols, out), &points, &options)
            .map_err(|e| match e {
                ColumnsError::Oracle { source, .. } => source,
                ColumnsError::HMatrix(e) => Error::HMatrix(e),
                e => invalid("options", e.to_string()),
            })
    }
}

/// The number of condensed unknowns of every node if it is the same for all (the slip's
/// two tangential components on a 3-D fault), else 1: the interleaved components the
/// cross approximation treats block by block (rsf-hmatrix's `HOptions::components`, so
/// that a component block that decouples is not missed).
pub(crate) fn components_per_node(interface: &[usize], c: usize) -> usize {
    let mut counts = interface
        .chunk_by(|a, b| a / c == b / c)
        .map(<[usize]>::len);
    match counts.next() {
        Some(first) if counts.all(|k| k == first) => first,
        _ => 1,
    }
}

/// One point per condensed unknown: its node's coordinates (m), so that a node's
/// components are coincident points, never separated by the admissibility condition.
pub(crate) fn interface_points<const D: usize, const C: usize>(
    model: &Model<D, C>,
    interface: &[usize],
) -> Result<Points> {
    let coords: Vec<[f64; D]> = interface
        .iter()
        .map(|&dof| model.vertices[dof / C])
        .collect();
    Ok(Points::from_array(&coords)?)
}

/// `(K u)_i` for a symmetric `K` stored by columns: column `i`'s dot product with `u`.
fn row_times(k: &SparseMatrix, i: usize, u: &[f64]) -> f64 {
    let k = k.as_ref();
    let rows = k.row_idx_of_col_raw(i);
    let values = k.val_of_col(i);
    rows.iter().zip(values).map(|(&r, v)| v * u[r]).sum()
}

impl<const D: usize, const C: usize> std::fmt::Debug for SchurColumns<'_, D, C> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SchurColumns")
            .field("dim", &self.dim())
            .field("dofs", &self.model.num_dofs())
            .field("report", &self.report())
            .finish_non_exhaustive()
    }
}
