//! Exact condensation of a sparse symmetric positive definite matrix onto the free
//! components of some blocks (docs/math.md §8): the dense Schur complement, condensed
//! right-hand sides, and the interior of a solution from its interface values.

use faer::sparse::SparseColMatRef;
use rsf_linalg::Parallelism;

use super::ordering::InteriorOrdering;
use super::partial_cholesky::PartialCholesky;
use crate::error::Result;
use rsf_linalg::Csc;
use rsf_nonsmooth::BlockedMatrix;
use rsf_nonsmooth::ProblemError;

/// The condensation of `A` (`n × n`, symmetric, positive definite on its free dofs) onto
/// the free components `F` of a set of blocks (nodes; `D` components each): with `R` the
/// other free dofs,
///
/// ```text
/// S = A_FF − A_FR A_RR⁻¹ A_RF,      g = b_F − A_FR A_RR⁻¹ b_R
/// ```
///
/// where `b` is a right-hand side from which the fixed dofs' columns times their values are
/// subtracted. `A x = b` on the free dofs is equivalent to `S x_F = g` and
/// `x_R = A_RR⁻¹ (b_R − A_RF x_F)`. This is what the [`DirectSolver`](crate::DirectSolver)
/// solves its nonsmooth problems on; it is public for other uses of the condensed
/// operator, e.g. integrating the quasi-dynamic equations of a fault in time.
///
/// Costs: the set-up factorises `A` on `R ∪ F` once (a sparse Cholesky factor with `F`
/// eliminated last, nested dissection of `R`); [`condense`](Self::condense) is one forward
/// sweep and [`extend`](Self::extend) one backward sweep over the factor, `O(nnz(L))`;
/// the sweeps of a large interior run on two threads if its [`Parallelism`] allows
/// ([`with_parallelism`](Self::with_parallelism), default [`Parallelism::default`]; the
/// same bits whatever it is).
pub struct Condensation<const D: usize> {
    blocks: Vec<usize>,
    pub(super) factor: PartialCholesky,
    /// Elimination position ↦ dof.
    pub(super) order: Vec<usize>,
    /// Dof ↦ elimination position (`usize::MAX` for fixed dofs).
    pub(super) pos: Vec<usize>,
    /// Fixed dofs with their column entries on free rows as (elimination position, A_ij).
    fixed_cols: Vec<(usize, Vec<(usize, f64)>)>,
    /// The dof of each condensed unknown, in order (the free components of the blocks).
    interface: Vec<usize>,
    /// The free components of each block.
    pub(super) free: Vec<[bool; D]>,
    /// Scratch in elimination order: after [`condense`](Self::condense), `[L_RR⁻¹ b̃_R; g]`.
    pub(super) y: Vec<f64>,
}

impl<const D: usize> std::fmt::Debug for Condensation<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Condensation")
            .field("n", &self.pos.len())
            .field("blocks", &self.blocks.len())
            .field("dim", &self.interface.len())
            .finish_non_exhaustive()
    }
}

impl<const D: usize> Condensation<D> {
    /// The condensation of `a` (`n × n`, symmetric, both triangles stored, positive
    /// definite on the free dofs; `n` a multiple of `D`) with fixed dofs `fixed` (length
    /// `n`) onto the free components of `blocks` (node indices, strictly increasing).
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] / [`ProblemError::DimensionMismatch`] for invalid shapes or
    /// pattern; [`ProblemError::InvalidOption`] for blocks out of range or not increasing;
    /// [`ProblemError::NotPositiveDefinite`] if `a` is not positive definite on the free dofs.
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        blocks: &[usize],
    ) -> Result<Self> {
        Self::with_ordering(a, fixed, blocks, InteriorOrdering::Amd)
    }

    /// [`new`](Self::new) with the interior ordered by `ordering` ([`InteriorOrdering`]):
    /// the same condensation up to round-off, another factor (its fill, set-up time and
    /// memory). [`InteriorOrdering::Amd`] is [`new`](Self::new), bit for bit.
    ///
    /// # Errors
    /// As [`new`](Self::new); [`Error::FeatureDisabled`](crate::Error::FeatureDisabled) for
    /// [`InteriorOrdering::NestedDissection`] in a build without the feature `metis`.
    pub fn with_ordering(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        blocks: &[usize],
        ordering: InteriorOrdering,
    ) -> Result<Self> {
        let BlockedMatrix { a, fixed } = BlockedMatrix::<D>::new(Csc::from_faer(a)?, fixed)?;
        Self::build_ordered(&a, &fixed, blocks, None, ordering)
    }

    /// The condensation of `a` (checked by the caller) onto `blocks`; with `previous`, a
    /// factor of a matrix with the same pattern for the same blocks, whose analysis is
    /// reused if the pattern matches.
    pub(super) fn build(
        a: &Csc,
        fixed: &[bool],
        blocks: &[usize],
        previous: Option<&PartialCholesky>,
    ) -> Result<Self> {
        Self::build_ordered(a, fixed, blocks, previous, InteriorOrdering::Amd)
    }

    /// [`build`](Self::build) with the interior ordered by `ordering` (for a new
    /// analysis; a reused one keeps its order).
    fn build_ordered(
        a: &Csc,
        fixed: &[bool],
        blocks: &[usize],
        previous: Option<&PartialCholesky>,
        ordering: InteriorOrdering,
    ) -> Result<Self> {
        let n = a.nrows;
        let (interior, interface) = split_dofs::<D>(n, fixed, blocks)?;
        let (factor, order) = match previous {
            Some(p) if p.analysed_for(a, &interior, &interface) => {
                (p.refactor(a)?, p.order().to_vec())
            }
            _ => PartialCholesky::with_ordering(a, &interior, &interface, (ordering, D))?,
        };
        let mut pos = vec![usize::MAX; n];
        for (k, &i) in order.iter().enumerate() {
            pos[i] = k;
        }
        let fixed_cols = (0..n)
            .filter(|&j| fixed[j])
            .map(|j| {
                let (rows, vals) = a.col(j);
                let entries = rows
                    .iter()
                    .zip(vals)
                    .filter(|(&i, _)| pos[i] != usize::MAX)
                    .map(|(&i, &v)| (pos[i], v))
                    .collect();
                (j, entries)
            })
            .filter(|(_, e): &(usize, Vec<(usize, f64)>)| !e.is_empty())
            .collect();
        let free = blocks
            .iter()
            .map(|&p| {
                let mut f = [false; D];
                for (c, fc) in f.iter_mut().enumerate() {
                    *fc = !fixed[D * p + c];
                }
                f
            })
            .collect();
        Ok(Self {
            blocks: blocks.to_vec(),
            y: vec![0.0; order.len()],
            factor,
            order,
            pos,
            fixed_cols,
            interface,
            free,
        })
    }

    /// The same condensation with the parallelism `par` for its sweeps (two halves of the
    /// interior on two threads from [`INTERIOR_PARALLEL_MIN`](crate::INTERIOR_PARALLEL_MIN)
    /// interior unknowns on, when `par` has more than one; results do not depend on it).
    pub fn with_parallelism(mut self, par: Parallelism) -> Self {
        self.factor.set_parallelism(par);
        self
    }

    /// The parallelism of the sweeps.
    pub fn parallelism(&self) -> Parallelism {
        self.factor.parallelism()
    }

    /// The blocks condensed onto.
    pub fn blocks(&self) -> &[usize] {
        &self.blocks
    }

    /// Number of condensed unknowns `m = |F|` (the free components of the blocks).
    pub fn dim(&self) -> usize {
        self.interface.len()
    }

    /// The dof of each condensed unknown (length [`dim`](Self::dim)), in block order and
    /// component order within a block.
    pub fn interface_dofs(&self) -> &[usize] {
        &self.interface
    }

    /// Entries of the sparse factor.
    pub fn factor_nnz(&self) -> usize {
        self.factor.nnz()
    }

    /// The Schur complement `S` (`m × m`, symmetric, column-major), rows and columns in the
    /// order of [`interface_dofs`](Self::interface_dofs).
    pub fn schur_complement(&self) -> Vec<f64> {
        self.factor.schur_complement()
    }

    /// The condensed right-hand side `g` (length `m`) of `b` (length `n`) with the fixed
    /// dofs at their values in `x` (length `n`; its free entries are not read):
    /// `g = b̃_F − A_FR A_RR⁻¹ b̃_R`, `b̃ = b − A_{·,fixed} x_fixed`. Keeps what
    /// [`extend`](Self::extend) needs for the same `b` and `x_fixed`.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] for lengths other than `n`, `n`, `m`.
    pub fn condense(&mut self, b: &[f64], x: &[f64], g: &mut [f64]) -> Result<()> {
        let n = self.pos.len();
        check_len("right-hand side", n, b.len())?;
        check_len("fixed values", n, x.len())?;
        check_len("condensed right-hand side", self.interface.len(), g.len())?;
        self.condense_in_place(b, x);
        g.copy_from_slice(&self.y[self.factor.nr..]);
        Ok(())
    }

    /// [`condense`](Self::condense) without checks, leaving `g` in `y[nr..]`.
    pub(super) fn condense_in_place(&mut self, b: &[f64], x: &[f64]) {
        for (k, &i) in self.order.iter().enumerate() {
            self.y[k] = b[i];
        }
        for (j, entries) in &self.fixed_cols {
            let xj = x[*j];
            if xj != 0.0 {
                for &(k, aij) in entries {
                    self.y[k] -= aij * xj;
                }
            }
        }
        self.factor.forward_interior(&mut self.y);
    }

    /// Completes a solution after [`condense`](Self::condense) of `b` and `x_fixed`: reads
    /// the interface values from `x` (length `n`), writes `x_R = A_RR⁻¹(b̃_R − A_RF x_F)`
    /// into it (interface and fixed entries unchanged).
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] for a length other than `n`; [`ProblemError::NonFinite`]
    /// if the result is not finite.
    pub fn extend(&mut self, x: &mut [f64]) -> Result<()> {
        let n = self.pos.len();
        check_len("solution", n, x.len())?;
        let nr = self.factor.nr;
        for (i, &dof) in self.interface.iter().enumerate() {
            self.y[nr + i] = x[dof];
        }
        self.factor.backward_interior(&mut self.y);
        for (k, &i) in self.order.iter().enumerate().take(nr) {
            x[i] = self.y[k];
        }
        if self.y[..nr].iter().any(|v| !v.is_finite()) {
            return Err(ProblemError::NonFinite("condensed solution's interior").into());
        }
        Ok(())
    }
    /// The extension of interface values alone (the discrete A-harmonic extension): reads
    /// the interface values from `x` (length `n`) and writes `x_R = −A_RR⁻¹ A_RF x_F` into
    /// it (interface and fixed entries unchanged). The same bits as
    /// [`condense`](Self::condense) of `b = 0` with the fixed dofs at 0 followed by
    /// [`extend`](Self::extend), without that forward sweep (its result is zero): half the
    /// work of a column of an operator built one interface unknown at a time.
    ///
    /// # Errors
    /// As [`extend`](Self::extend).
    pub fn extend_homogeneous(&mut self, x: &mut [f64]) -> Result<()> {
        let nr = self.factor.nr;
        self.y[..nr].fill(0.0);
        self.extend(x)
    }
}

fn check_len(what: &'static str, expected: usize, got: usize) -> Result<()> {
    Ok(ProblemError::check_length(what, expected, got)?)
}

/// The interior (free dofs outside the blocks) and the interface (free components of the
/// blocks, block by block) of a condensation onto `blocks` of a problem with `n` dofs.
///
/// # Errors
/// [`ProblemError::InvalidOption`] for blocks out of range or not strictly increasing.
pub(super) fn split_dofs<const D: usize>(
    n: usize,
    fixed: &[bool],
    blocks: &[usize],
) -> Result<(Vec<usize>, Vec<usize>)> {
    if blocks.windows(2).any(|w| w[0] >= w[1]) || blocks.last().is_some_and(|&p| p >= n / D) {
        return Err(ProblemError::InvalidOption(format!(
            "active blocks must be strictly increasing node indices below {}",
            n / D
        ))
        .into());
    }
    let mut in_block = vec![false; n];
    for &p in blocks {
        in_block[D * p..D * p + D].fill(true);
    }
    let interior: Vec<usize> = (0..n).filter(|&i| !in_block[i] && !fixed[i]).collect();
    let interface: Vec<usize> = blocks
        .iter()
        .flat_map(|&p| (0..D).map(move |c| D * p + c))
        .filter(|&i| !fixed[i])
        .collect();
    Ok((interior, interface))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::partial_cholesky::tests::grid;

    /// The `m × m` grid Laplacian ([`grid`]) with its first column of nodes fixed,
    /// condensed onto the nodes `blocks`: `(A, fixed, blocks, condensation)`.
    pub(crate) fn fixed_column_grid(
        m: usize,
        blocks: std::ops::Range<usize>,
    ) -> (Csc, Vec<bool>, Vec<usize>, Condensation<1>) {
        let a = grid(m);
        let fixed: Vec<bool> = (0..a.nrows).map(|j| j % m == 0).collect();
        let blocks: Vec<usize> = blocks.collect();
        let cond = Condensation::<1>::build(&a, &fixed, &blocks, None).unwrap();
        (a, fixed, blocks, cond)
    }

    /// Dense Cholesky solve of an SPD system (faer's dense `LLᵀ`: the reference, independent
    /// of the sparse factor).
    fn dense_solve(a: Vec<Vec<f64>>, b: Vec<f64>) -> Vec<f64> {
        use faer::linalg::solvers::Solve;
        let n = b.len();
        let llt = faer::Mat::from_fn(n, n, |i, j| a[i][j])
            .llt(faer::Side::Lower)
            .unwrap();
        let x = llt.solve(faer::Col::from_fn(n, |i| b[i]));
        x.iter().copied().collect()
    }

    /// On a 12 × 12 grid Laplacian with the first column fixed at non-zero values and the
    /// bottom row's other nodes condensed onto: `S x_F = g` holds for the solution of the
    /// full system (solved densely), `extend` reproduces its interior, and `S` equals the
    /// dense Schur complement.
    #[test]
    fn condensed_system_and_extension_reproduce_the_full_solve() {
        let m = 12;
        let (a, fixed, blocks, mut cond) = fixed_column_grid(m, 1..m);
        let n = a.nrows;
        let b: Vec<f64> = (0..n).map(|i| ((i * 7919) % 13) as f64 - 6.0).collect();
        let x_fixed: Vec<f64> = (0..n)
            .map(|i| if fixed[i] { 0.5 + (i / m) as f64 } else { 0.0 })
            .collect();
        assert_eq!(cond.dim(), m - 1);
        assert_eq!(cond.interface_dofs(), &blocks[..]);
        // Dense reference on the free dofs.
        let free: Vec<usize> = (0..n).filter(|&i| !fixed[i]).collect();
        let dense = |i: usize, j: usize| a.position(i, j).map_or(0.0, |p| a.val[p]);
        let af: Vec<Vec<f64>> = free
            .iter()
            .map(|&i| free.iter().map(|&j| dense(i, j)).collect())
            .collect();
        let bf: Vec<f64> = free
            .iter()
            .map(|&i| {
                b[i] - (0..n)
                    .filter(|&j| fixed[j])
                    .map(|j| dense(i, j) * x_fixed[j])
                    .sum::<f64>()
            })
            .collect();
        let xf = dense_solve(af, bf);
        let mut x = x_fixed.clone();
        for (k, &i) in free.iter().enumerate() {
            x[i] = xf[k];
        }
        let mut g = vec![0.0; cond.dim()];
        cond.condense(&b, &x_fixed, &mut g).unwrap();
        let s = cond.schur_complement();
        let mf = cond.dim();
        for i in 0..mf {
            let sx: f64 = (0..mf).map(|j| s[j * mf + i] * x[blocks[j]]).sum();
            assert!(
                (sx - g[i]).abs() < 1e-12 * g.iter().fold(1.0_f64, |t, v| t.max(v.abs())),
                "row {i}: {sx} vs {g:?}"
            );
        }
        let mut y = x_fixed.clone();
        for &p in &blocks {
            y[p] = x[p];
        }
        cond.extend(&mut y).unwrap();
        let err = x
            .iter()
            .zip(&y)
            .fold(0.0_f64, |t, (p, q)| t.max((p - q).abs()));
        assert!(
            err < 1e-12 * x.iter().fold(1.0_f64, |t, v| t.max(v.abs())),
            "max |Δx| = {err:e}"
        );
        // S against the dense Schur complement A_FF − A_FR A_RR⁻¹ A_RF, column by column.
        let rest: Vec<usize> = free
            .iter()
            .copied()
            .filter(|i| !blocks.contains(i))
            .collect();
        let arr: Vec<Vec<f64>> = rest
            .iter()
            .map(|&i| rest.iter().map(|&j| dense(i, j)).collect())
            .collect();
        for (jj, &j) in blocks.iter().enumerate() {
            let col = dense_solve(arr.clone(), rest.iter().map(|&i| dense(i, j)).collect());
            for (ii, &i) in blocks.iter().enumerate() {
                let sij = dense(i, j)
                    - rest
                        .iter()
                        .zip(&col)
                        .map(|(&r, c)| dense(i, r) * c)
                        .sum::<f64>();
                assert!((sij - s[jj * mf + ii]).abs() < 1e-12 * 5.0, "S[{ii},{jj}]");
            }
        }
        // Lengths are checked.
        assert!(cond.condense(&b[1..], &x_fixed, &mut g).is_err());
        assert!(cond.extend(&mut y[1..]).is_err());
    }

    /// `extend_homogeneous` is `condense(0, 0)` then `extend`, bit for bit, after another
    /// condensation left its own values behind, and it is the harmonic extension: the
    /// residual of the full system vanishes on the interior.
    #[test]
    fn homogeneous_extension_is_the_extension_of_zero_data() {
        let (a, fixed, blocks, mut cond) = fixed_column_grid(10, 1..10);
        let n = a.nrows;
        let b: Vec<f64> = (0..n).map(|i| (i % 7) as f64 - 3.0).collect();
        let x_fixed: Vec<f64> = (0..n).map(|i| if fixed[i] { 1.5 } else { 0.0 }).collect();
        let zeros = vec![0.0; n];
        let mut g = vec![0.0; cond.dim()];
        for (k, &dof) in blocks.iter().enumerate() {
            // Something else in the scratch first.
            cond.condense(&b, &x_fixed, &mut g).unwrap();
            let mut x = vec![0.0; n];
            x[dof] = 1.0 + k as f64;
            let mut reference = x.clone();
            cond.extend_homogeneous(&mut x).unwrap();
            cond.condense(&zeros, &zeros, &mut g).unwrap();
            cond.extend(&mut reference).unwrap();
            assert!(
                x.iter()
                    .zip(&reference)
                    .all(|(p, q)| p.to_bits() == q.to_bits()),
                "column {k}"
            );
            // (A x)_i = 0 on the interior (free, not interface).
            for i in (0..n).filter(|&i| !fixed[i] && !blocks.contains(&i)) {
                let (rows, vals) = a.col(i);
                let r: f64 = rows.iter().zip(vals).map(|(&j, v)| v * x[j]).sum();
                assert!(r.abs() < 1e-12 * (1.0 + k as f64), "row {i}: {r:e}");
            }
        }
    }
}
