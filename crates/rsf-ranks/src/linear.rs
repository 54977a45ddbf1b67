//! Linear block Gauss–Seidel, the node update of the distributed sweep's tests and
//! measurements: on a rank's owned rows ([`BlockGaussSeidel`]) and its one-process
//! reference, the coloured sweep of the whole matrix ([`ColouredGaussSeidel`]).

use faer::sparse::SparseColMatRef;

use crate::block::{load, masked_inverse, mul_vec, sub_mul_vec, Block};
use crate::bsr::BlockCsr;
use crate::colouring::Colouring;
use crate::error::Result;
use crate::local_rows::LocalRows;
use rsf_linalg::{Parallelism, ProblemError};

/// The update of node `p` on its free components,
/// `x_p + S_p (b − Σ_{q≠p} A_pq x_q − A_pp x_p)` with `S_p` the inverse of the free
/// sub-block of `A_pp`, the row summed in `row`'s order.
fn update<'a, const D: usize>(
    b: [f64; D],
    diag: &Block<D>,
    inverse: &Block<D>,
    row: impl Iterator<Item = (usize, &'a Block<D>)>,
    x: &[f64],
    p: usize,
) -> [f64; D] {
    let mut s = b;
    for (q, blk) in row {
        sub_mul_vec(&mut s, blk, &load::<D>(x, q));
    }
    let mut xp = load::<D>(x, p);
    sub_mul_vec(&mut s, diag, &xp);
    let d = mul_vec(inverse, &s);
    for c in 0..D {
        xp[c] += d[c];
    }
    xp
}

/// The free components of node `p` of a dof mask.
fn free<const D: usize>(fixed: &[bool], p: usize) -> [bool; D] {
    std::array::from_fn(|c| !fixed[D * p + c])
}

/// Linear block Gauss–Seidel on one rank's owned rows: the node update to give
/// [`DistributedSweep::sweep`](crate::DistributedSweep::sweep), the same arithmetic as
/// [`ColouredGaussSeidel`]'s (a node's row summed in global column order, as
/// [`LocalRows::neighbours`] gives it), so that the distributed sweeps have its bits.
#[derive(Debug, Clone)]
pub struct BlockGaussSeidel<const D: usize> {
    /// The inverse of each owned node's free diagonal sub-block (zero on fixed components).
    inverse: Vec<Block<D>>,
    /// The owned nodes' right-hand side (`D` per owned node).
    b: Vec<f64>,
}

impl<const D: usize> BlockGaussSeidel<D> {
    /// The update on `rows` with the local right-hand side `b` and the local mask of fixed
    /// dofs `fixed` (each at least `D · rows.owned()` long, owned nodes first as in a local
    /// vector; ghost entries, if given, are not read).
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `b` or `fixed` is shorter than `D · rows.owned()`.
    pub fn new(rows: &LocalRows<D>, b: &[f64], fixed: &[bool]) -> Result<Self> {
        let owned = D * rows.owned();
        for (what, len) in [("b (local)", b.len()), ("fixed (local)", fixed.len())] {
            if len < owned {
                return Err(ProblemError::DimensionMismatch {
                    what,
                    expected: owned,
                    got: len,
                }
                .into());
            }
        }
        let inverse = (0..rows.owned())
            .map(|p| masked_inverse(rows.diag(p), &free(fixed, p)))
            .collect();
        Ok(Self {
            inverse,
            b: b[..owned].to_vec(),
        })
    }

    /// Recomputes owned node `p`'s local solve from its new diagonal block `diag` and its
    /// fixed components (`fixed`, `D` flags).
    ///
    /// # Panics
    /// If `p` is not an owned node of the rows this update was made for.
    pub fn set_node(&mut self, p: usize, diag: &Block<D>, fixed: &[bool]) {
        self.inverse[p] = masked_inverse(diag, &free(fixed, 0));
    }

    /// The owned nodes' right-hand side (`D · rows.owned()` values), to change between
    /// sweeps (a multigrid level's right-hand side changes every cycle).
    pub fn rhs_mut(&mut self) -> &mut [f64] {
        &mut self.b
    }

    /// The owned nodes' right-hand side.
    pub fn rhs(&self) -> &[f64] {
        &self.b
    }

    /// The new block of owned node `p` from the local vector `x` (its ghosts current), as
    /// [`DistributedSweep::sweep`](crate::DistributedSweep::sweep) calls it.
    ///
    /// # Panics
    /// If `p ≥ rows.owned()`, `rows` are not the rows this update was made for (of fewer
    /// owned nodes), or `x` is shorter than `D · rows.len()`.
    pub fn update(&self, rows: &LocalRows<D>, p: usize, x: &[f64]) -> [f64; D] {
        update(
            load::<D>(&self.b, p),
            rows.diag(p),
            &self.inverse[p],
            rows.neighbours(p),
            x,
            p,
        )
    }
}

/// The one-process reference of [`BlockGaussSeidel`] on ranks: coloured linear block
/// Gauss–Seidel sweeps of the whole symmetric-pattern matrix `a` (`D n × D n`, node-major)
/// in the order of a [`Colouring`] on one thread, with a right-hand side and fixed dofs
/// left as they are. Each node's row is summed in increasing column order.
#[derive(Debug, Clone)]
pub struct ColouredGaussSeidel<const D: usize> {
    a: BlockCsr<D>,
    inverse: Vec<Block<D>>,
    b: Vec<f64>,
    colouring: Colouring,
    scratch: Vec<[f64; D]>,
}

impl<const D: usize> ColouredGaussSeidel<D> {
    /// The sweeps of `a` with right-hand side `b` and the fixed dofs `fixed` (both length
    /// `D n`) in the order of `colouring` (a colouring of `a`'s node graph).
    ///
    /// # Errors
    /// [`ProblemError::InvalidMatrix`] as [`Colouring::new`]; [`ProblemError::DimensionMismatch`]
    /// if `b`, `fixed` or `colouring` does not have the matrix's size.
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        b: &[f64],
        colouring: &Colouring,
    ) -> Result<Self> {
        Self::of_blocks(BlockCsr::<D>::from_symmetric(a)?, fixed, b, colouring)
    }

    /// [`new`](Self::new) of a block matrix.
    pub fn of_blocks(
        a: BlockCsr<D>,
        fixed: &[bool],
        b: &[f64],
        colouring: &Colouring,
    ) -> Result<Self> {
        let n = a.nodes();
        for (what, expected, got) in [
            ("b", D * n, b.len()),
            ("fixed", D * n, fixed.len()),
            ("colouring (one colour per node)", n, colouring.num_nodes()),
        ] {
            ProblemError::check_length(what, expected, got)?;
        }
        let inverse = (0..n)
            .map(|p| masked_inverse(&a.diag[p], &free(fixed, p)))
            .collect();
        Ok(Self {
            a,
            inverse,
            b: b.to_vec(),
            colouring: colouring.clone(),
            scratch: vec![[0.0; D]; colouring.max_colour_len()],
        })
    }

    /// The right-hand side (`D n` values), to change between sweeps.
    pub fn rhs_mut(&mut self) -> &mut [f64] {
        &mut self.b
    }

    /// The residual `r = b − A x` by rows (diagonal block, then the off-diagonal blocks in
    /// increasing column order: the arithmetic of [`LocalRows::residual`] and of the
    /// multigrid's residual by rows), one thread.
    ///
    /// # Panics
    /// If `x` or `r` is not `D n` long.
    pub fn residual(&self, x: &[f64], r: &mut [f64]) {
        assert_eq!(x.len(), self.a.n(), "x has D values per node");
        self.a.residual_rows(&self.b, x, r, Parallelism::SEQ);
    }

    /// One sweep of `x` (length `D n`): increasing colours, or decreasing when `reverse`.
    /// Allocation-free.
    ///
    /// # Panics
    /// If `x` is not `D n` long.
    pub fn sweep(&mut self, x: &mut [f64], reverse: bool) {
        assert_eq!(x.len(), D * self.a.nodes(), "x has D values per node");
        let Self {
            a,
            inverse,
            b,
            colouring,
            scratch,
        } = self;
        colouring.sweep(x, reverse, scratch, Parallelism::SEQ, |p, x| {
            update(
                load::<D>(b, p),
                &a.diag[p],
                &inverse[p],
                a.neighbours(p),
                x,
                p,
            )
        });
    }
}
