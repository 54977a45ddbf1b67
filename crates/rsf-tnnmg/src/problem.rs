//! The quadratic part `½ vᵀAv − bᵀv` with its constraints, shared by all solvers.

use faer::sparse::SparseColMatRef;

use crate::chunks::{ChunkedSweep, Smoothing};
use crate::error::Result;
use crate::Parallelism;
use rsf_linalg::Csc;
use rsf_nonsmooth::ProblemError;
use rsf_nonsmooth::{BlockNonlinearity, BlockedMatrix};
use rsf_ranks::block::{load, masked_inverse, mul_vec, sub_mul_vec, Block};
use rsf_ranks::bsr::{BlockCsr, SweepOrder};
use rsf_ranks::Colouring;

/// The chunked nonlinear smoother of TNNMG: the sweeper (its red–black chunked order), the
/// number of sweeps and the threads ([`NodalProblem::nonlinear_gauss_seidel_chunked`]).
pub(crate) struct ChunkedSmoother<'a, const D: usize> {
    /// The sweeper built on the problem's matrix.
    pub sweeper: &'a mut ChunkedSweep<D>,
    /// Number of sweeps.
    pub sweeps: usize,
    /// The threads of the chunks of one colour.
    pub par: Parallelism,
}

/// The quadratic part in node-block storage, for the iterative solvers: `A` as
/// [`BlockCsr`], the fixed mask, and per node the local solve of the linear block
/// Gauss–Seidel step on the free components (computed once).
#[derive(Debug, Clone)]
pub(crate) struct NodalProblem<const D: usize> {
    pub a: BlockCsr<D>,
    pub fixed: Vec<bool>,
    free: Vec<[bool; D]>,
    /// `masked_inverse` of each diagonal block on the free components.
    inverse: Vec<Block<D>>,
}

impl<const D: usize> NodalProblem<D> {
    /// Validates (as [`BlockedMatrix::new`]) and blocks `a`.
    ///
    /// # Errors
    /// As [`BlockedMatrix::new`]; non-finite entries.
    pub fn new(a: SparseColMatRef<'_, usize, f64>, fixed: &[bool]) -> Result<Self> {
        let m = BlockedMatrix::<D>::new(Csc::from_faer(a)?, fixed)?;
        let a = BlockCsr::<D>::from_csc(&m.a)?;
        let free: Vec<[bool; D]> = (0..a.nodes())
            .map(|p| std::array::from_fn(|c| !fixed[D * p + c]))
            .collect();
        let inverse = (0..a.nodes())
            .map(|p| masked_inverse(&a.diag[p], &free[p]))
            .collect();
        Ok(Self {
            a,
            fixed: m.fixed,
            free,
            inverse,
        })
    }

    #[inline]
    pub fn n(&self) -> usize {
        self.a.n()
    }

    /// `J(v) = ½ vᵀAv − bᵀv + Σ φ_k(v_{p_k})`.
    pub fn energy<N: BlockNonlinearity<D>>(&self, b: &[f64], nl: &N, v: &[f64]) -> f64 {
        let quad = 0.5 * self.a.quadratic_form(v) - dot(b, v);
        let phi: f64 = nl
            .active_blocks()
            .iter()
            .enumerate()
            .map(|(k, &p)| nl.value(k, &load::<D>(v, p)))
            .sum();
        quad + phi
    }

    /// One nonlinear block Gauss–Seidel sweep (forward, or backward when `reverse`):
    /// each node block is minimised exactly with the others fixed (the nonlinear ones by
    /// `blocks.nl`); `w` is scratch of length `n`, 0 on entry and on return (see
    /// [`BlockCsr::sweep`]).
    pub fn nonlinear_gauss_seidel<N: BlockNonlinearity<D>>(
        &self,
        b: &[f64],
        blocks: ActiveBlocks<'_, N>,
        v: &mut [f64],
        w: &mut [f64],
        reverse: bool,
    ) {
        let a = &self.a;
        a.sweep(b, v, w, SweepOrder::from_x(reverse), |p, s, x| {
            self.local_update(blocks, p, s, x)
        });
    }

    /// `sweeps` forward nonlinear block Gauss–Seidel sweeps in the red–black chunked order
    /// of `chunked` (built on this problem's matrix), each node block minimised exactly as
    /// in [`nonlinear_gauss_seidel`](Self::nonlinear_gauss_seidel); the chunks of one
    /// colour on `par`'s threads, bit-identical for every thread count. Afterwards `b − A v`
    /// in `res`.
    pub(crate) fn nonlinear_gauss_seidel_chunked<N: BlockNonlinearity<D>>(
        &self,
        b: &[f64],
        blocks: ActiveBlocks<'_, N>,
        v: &mut [f64],
        res: &mut [f64],
        smoother: ChunkedSmoother<'_, D>,
    ) {
        let ChunkedSmoother {
            sweeper,
            sweeps,
            par,
        } = smoother;
        let local = |p: usize, _: &Block<D>, s: &[f64; D], x: &mut [f64; D]| {
            self.local_update(blocks, p, s, x)
        };
        let smoothing = Smoothing {
            sweeps,
            order: SweepOrder::from_x(false),
            par,
            local,
        };
        sweeper.smooth(v, b, Some(res), smoothing);
    }

    /// The exact minimisation of block `p` with the others fixed: `s = b_p − Σ_{q≠p}
    /// A_pq v_q` is the block right-hand side with the off-block coupling, `x` holds `v_p`
    /// and receives the update.
    #[inline(always)]
    fn local_update<N: BlockNonlinearity<D>>(
        &self,
        blocks: ActiveBlocks<'_, N>,
        p: usize,
        s: &[f64; D],
        x: &mut [f64; D],
    ) {
        let ActiveBlocks { nl, active_of } = blocks;
        let node = NodeBlocks {
            diag: &self.a.diag[p],
            inverse: &self.inverse[p],
            free: &self.free[p],
        };
        node_update(nl, active_of[p], node, s, x);
    }

    /// One multi-colour nonlinear block Gauss–Seidel sweep: colour by colour
    /// (increasing colours), each node block of a colour minimised
    /// exactly with all others fixed, as [`nonlinear_gauss_seidel`](Self::nonlinear_gauss_seidel).
    /// The nodes of one colour are not adjacent, so their updates read only other colours'
    /// values: they are computed into `scratch` (at least
    /// [`Colouring::max_colour_len`] blocks) in at most `par.threads()` contiguous chunks
    /// and then written into `v`. Every node's arithmetic (full row in increasing column
    /// order, then the local solve) is the same for any split: bit-identical results for
    /// every thread count.
    #[expect(
        clippy::too_many_arguments,
        reason = "one smoother sweep: the problem's data, the colouring, the threads and the scratch it reuses"
    )]
    pub(crate) fn nonlinear_gauss_seidel_coloured<N: BlockNonlinearity<D>>(
        &self,
        b: &[f64],
        blocks: ActiveBlocks<'_, N>,
        v: &mut [f64],
        colouring: &Colouring,
        par: Parallelism,
        scratch: &mut [[f64; D]],
    ) {
        colouring.sweep(v, false, scratch, par, |p, v| {
            let s = coupled_rhs(load::<D>(b, p), self.a.neighbours(p), v);
            let mut x = load::<D>(v, p);
            self.local_update(blocks, p, &s, &mut x);
            x
        });
    }
}

/// What the node update of the nonlinear Gauss–Seidel sweeps reads of one node: its
/// diagonal block `A_pp`, the `masked_inverse` of it on the free components, and the free
/// components.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeBlocks<'a, const D: usize> {
    pub diag: &'a Block<D>,
    pub inverse: &'a Block<D>,
    pub free: &'a [bool; D],
}

/// The exact minimisation of one node block with the others fixed, the node update of
/// every nonlinear Gauss–Seidel sweep (one process, and on ranks): `s = b_p − Σ_{q≠p}
/// A_pq v_q` is the block right-hand side with the off-block coupling, `x` holds `v_p` and
/// receives the update. `k` is the node's position in `nl.active_blocks()` (`usize::MAX`
/// for a linear node, solved exactly on its free components).
#[inline(always)]
pub(crate) fn node_update<const D: usize, N: BlockNonlinearity<D>>(
    nl: &N,
    k: usize,
    node: NodeBlocks<'_, D>,
    s: &[f64; D],
    x: &mut [f64; D],
) {
    if k != usize::MAX {
        nl.minimize_block(k, node.diag, s, node.free, x);
    } else {
        // Linear block: exact solve on the free components (the fixed ones keep
        // their values; their coupling enters through A_pp x).
        let mut r = *s;
        sub_mul_vec(&mut r, node.diag, x);
        let d = mul_vec(node.inverse, &r);
        for c in 0..D {
            x[c] += d[c];
        }
    }
}

/// The block right-hand side with the off-block coupling of a node, `s = b_p − Σ_{q≠p}
/// A_pq x_q`, its row `row` (`(q, A_pq)`, increasing global columns) summed in order: what
/// the multi-colour nonlinear sweeps (one process, and on ranks) hand to [`node_update`].
#[inline(always)]
pub(crate) fn coupled_rhs<'a, const D: usize>(
    b: [f64; D],
    row: impl Iterator<Item = (usize, &'a Block<D>)>,
    x: &[f64],
) -> [f64; D] {
    let mut s = b;
    for (q, blk) in row {
        sub_mul_vec(&mut s, blk, &load::<D>(x, q));
    }
    s
}

/// The nonlinear blocks of a sweep: the nonlinearity and, per node `p`, the position
/// `active_of[p]` of its block in `nl.active_blocks()` (`usize::MAX` for a linear node).
#[derive(Debug)]
pub(crate) struct ActiveBlocks<'a, N> {
    pub nl: &'a N,
    pub active_of: &'a [usize],
}

impl<N> Clone for ActiveBlocks<'_, N> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<N> Copy for ActiveBlocks<'_, N> {}

#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Fills `active_of` (length = number of nodes) from the nonlinearity's active list.
pub(crate) fn active_map<const D: usize, N: BlockNonlinearity<D>>(
    nl: &N,
    nodes: usize,
    active_of: &mut Vec<usize>,
) -> Result<()> {
    active_of.clear();
    active_of.resize(nodes, usize::MAX);
    let mut last = None;
    for (k, &p) in nl.active_blocks().iter().enumerate() {
        if p >= nodes || last.is_some_and(|l| l >= p) {
            return Err(ProblemError::InvalidOption(format!(
                "active blocks must be strictly increasing node indices below {nodes} (got {p})"
            ))
            .into());
        }
        last = Some(p);
        active_of[p] = k;
    }
    Ok(())
}
