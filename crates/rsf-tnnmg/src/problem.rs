//! The quadratic part `½ vᵀAv − bᵀv` with its constraints, shared by all solvers.

use crate::block::{load, solve_spd_masked, store};
use crate::csc::Csc;
use crate::error::{Error, Result};
use crate::nonlinearity::BlockNonlinearity;

/// Sentinel for a structurally absent entry of a node block.
const ABSENT: usize = usize::MAX;

/// A symmetric positive definite matrix with node-block structure and a fixed-dof mask.
#[derive(Debug, Clone)]
pub(crate) struct BlockedMatrix<const D: usize> {
    pub a: Csc,
    /// Positions of the D×D diagonal block entries of each node (ABSENT if not stored).
    pub block_pos: Vec<[[usize; D]; D]>,
    pub fixed: Vec<bool>,
}

impl<const D: usize> BlockedMatrix<D> {
    pub fn new(a: Csc, fixed: &[bool]) -> Result<Self> {
        a.check_symmetric_pattern()?;
        let n = a.nrows;
        if n % D != 0 {
            return Err(Error::InvalidMatrix(format!(
                "dimension {n} is not a multiple of the block size {D}"
            )));
        }
        if fixed.len() != n {
            return Err(Error::DimensionMismatch {
                what: "fixed mask",
                expected: n,
                got: fixed.len(),
            });
        }
        for (i, p) in a.diagonal_positions()?.into_iter().enumerate() {
            if !fixed[i] && a.val[p] <= 0.0 {
                return Err(Error::NotPositiveDefinite(
                    "non-positive diagonal entry on a free dof",
                ));
            }
        }
        let block_pos = (0..n / D)
            .map(|p| {
                let mut pos = [[ABSENT; D]; D];
                for (r, row) in pos.iter_mut().enumerate() {
                    for (c, e) in row.iter_mut().enumerate() {
                        *e = a.position(D * p + r, D * p + c).unwrap_or(ABSENT);
                    }
                }
                pos
            })
            .collect();
        Ok(Self {
            a,
            block_pos,
            fixed: fixed.to_vec(),
        })
    }

    #[inline]
    pub fn n(&self) -> usize {
        self.a.nrows
    }

    #[inline]
    pub fn block(&self, p: usize) -> [[f64; D]; D] {
        let mut out = [[0.0; D]; D];
        for r in 0..D {
            for c in 0..D {
                let k = self.block_pos[p][r][c];
                if k != ABSENT {
                    out[r][c] = self.a.val[k];
                }
            }
        }
        out
    }

    #[inline]
    pub fn free_mask(&self, p: usize) -> [bool; D] {
        let mut f = [false; D];
        for c in 0..D {
            f[c] = !self.fixed[D * p + c];
        }
        f
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
    /// each node block is minimised exactly with the others fixed. `active_of[p]` is the
    /// position of node `p` in `nl.active_blocks()` or `usize::MAX`.
    pub fn nonlinear_gauss_seidel<N: BlockNonlinearity<D>>(
        &self,
        b: &[f64],
        nl: &N,
        active_of: &[usize],
        v: &mut [f64],
        reverse: bool,
    ) {
        let nodes = self.n() / D;
        for q in 0..nodes {
            let p = if reverse { nodes - 1 - q } else { q };
            let free = self.free_mask(p);
            if !free.iter().any(|&f| f) {
                continue;
            }
            let a_pp = self.block(p);
            let mut x = load::<D>(v, p);
            // r_p = b_p − (A v)_p + A_pp v_p: the right-hand side with off-block coupling.
            let mut r = [0.0; D];
            for c in 0..D {
                let i = D * p + c;
                let mut s = b[i] - self.a.sym_row_dot(i, v);
                for c2 in 0..D {
                    s += a_pp[c][c2] * x[c2];
                }
                r[c] = s;
            }
            let k = active_of[p];
            if k != usize::MAX {
                nl.minimize_block(k, &a_pp, &r, &free, &mut x);
            } else {
                // Linear block: move the fixed components' coupling to the right-hand side.
                let mut rf = r;
                for c in 0..D {
                    if free[c] {
                        for c2 in 0..D {
                            if !free[c2] {
                                rf[c] -= a_pp[c][c2] * x[c2];
                            }
                        }
                    }
                }
                let ok = solve_spd_masked(&a_pp, &rf, &free, &mut x);
                debug_assert!(ok, "free diagonal block not SPD");
            }
            store(v, p, &x);
        }
    }
}

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
            return Err(Error::InvalidOption(format!(
                "active blocks must be strictly increasing node indices below {nodes} (got {p})"
            )));
        }
        last = Some(p);
        active_of[p] = k;
    }
    Ok(())
}
