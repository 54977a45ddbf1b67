//! Linear functionals of the harmonic extensions of a condensation's unit interface
//! vectors, many extensions per backward sweep: what an operator built one interface
//! unknown at a time (a fault's slip → normal-traction operator, say) needs, without a
//! sweep over the whole factor per unknown.

use faer::Mat;
use rayon::prelude::*;

use super::condensation::Condensation;
use crate::error::Result;
use rsf_nonsmooth::ProblemError;

/// Scratch of one thread: the block's extensions (row-major, `n × r`, elimination order)
/// and the sweep's temporary.
type Scratch = (Vec<f64>, Vec<f64>);

/// Memory of one thread's block of extensions: at most this many `f64` (256 MiB).
const BLOCK_VALUES: usize = 1 << 25;

/// Most extensions per block (the factor is read once per block).
const MAX_BLOCK: usize = 32;

impl<const D: usize> Condensation<D> {
    /// The functionals `functionals` (each a sparse row: `(dof, coefficient)` pairs, dofs
    /// below `n`) of the harmonic extensions of the unit interface vectors: `out[(r, i)] =
    /// Σ_(d, c) c · x⁽ⁱ⁾_d`, summed in the order the pairs are given, where `x⁽ⁱ⁾`
    /// (length `n`) is what [`extend_homogeneous`](Self::extend_homogeneous) makes of `e_i`
    /// (1 at the `i`-th of [`interface_dofs`](Self::interface_dofs), zero at the other
    /// interface and the fixed dofs). Shape `functionals.len() × dim`.
    ///
    /// The same bits as `extend_homogeneous` column by column followed by those sums,
    /// whatever the blocking and the threads: blocks of up to 32 extensions share one
    /// backward sweep (each column's arithmetic is a single sweep's), the blocks split over
    /// the threads of [`parallelism`](Self::parallelism) for a large interior. Memory: at
    /// most 256 MiB of extensions per thread.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] for a dof of `n` or more; [`ProblemError::NonFinite`] if
    /// an extension is not finite.
    pub fn extension_functionals(&self, functionals: &[Vec<(usize, f64)>]) -> Result<Mat<f64>> {
        let block = (BLOCK_VALUES / self.factor.n.max(1)).clamp(1, MAX_BLOCK);
        let tasks = self.factor.interior_par().threads();
        self.extension_functionals_in(functionals, block, tasks)
    }

    /// [`extension_functionals`](Self::extension_functionals) with `block` extensions per
    /// sweep (≥ 1) in `tasks` groups of blocks (≥ 1; in parallel if more than one).
    fn extension_functionals_in(
        &self,
        functionals: &[Vec<(usize, f64)>],
        block: usize,
        tasks: usize,
    ) -> Result<Mat<f64>> {
        // Free dofs (elimination positions) `n`, of which `nr` interior; dofs in all.
        let (n, nr, dofs) = (self.factor.n, self.factor.nr, self.pos.len());
        let m = self.dim();
        let nf = functionals.len();
        // Each pair's elimination position (usize::MAX for a fixed dof: the value 0).
        let mut rows = Vec::with_capacity(nf);
        for f in functionals {
            let mut row = Vec::with_capacity(f.len());
            for &(dof, c) in f {
                if dof >= dofs {
                    return Err(ProblemError::DimensionMismatch {
                        what: "functional's dof",
                        expected: dofs,
                        got: dof,
                    }
                    .into());
                }
                row.push((self.pos[dof], c));
            }
            rows.push(row);
        }
        if m == 0 || nf == 0 {
            return Ok(Mat::zeros(nf, m));
        }
        let mut out = vec![0.0; nf * m];
        let per = m.div_ceil(block).div_ceil(tasks);
        let one_block = |(ext, tmp): &mut Scratch, f0: usize, cols: &mut [f64]| -> Result<()> {
            let r = cols.len() / nf;
            ext.clear();
            ext.resize(n * r, 0.0);
            for k in 0..r {
                ext[(nr + f0 + k) * r + k] = 1.0;
            }
            self.factor.backward_interior_rows(ext, r, tmp);
            if ext[..nr * r].iter().any(|v| !v.is_finite()) {
                return Err(ProblemError::NonFinite("condensed solution's interior").into());
            }
            for (k, col) in cols.chunks_mut(nf).enumerate() {
                for (o, row) in col.iter_mut().zip(&rows) {
                    *o = row
                        .iter()
                        .map(|&(p, c)| {
                            let x = if p == usize::MAX { 0.0 } else { ext[p * r + k] };
                            c * x
                        })
                        .sum();
                }
            }
            Ok(())
        };
        let group = |(g, cols): (usize, &mut [f64])| -> Result<()> {
            let mut scratch: Scratch = (Vec::new(), Vec::new());
            for (b, c) in cols.chunks_mut(nf * block).enumerate() {
                one_block(&mut scratch, (g * per + b) * block, c)?;
            }
            Ok(())
        };
        if tasks > 1 {
            out.par_chunks_mut(per * block * nf)
                .enumerate()
                .try_for_each(group)?;
        } else {
            group((0, &mut out[..]))?;
        }
        Ok(Mat::from_fn(nf, m, |r, i| out[i * nf + r]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::condensation::tests::fixed_column_grid;

    /// Every entry has the bits of `extend_homogeneous` column by column and the sums in
    /// the given order, for blocks of one and of several columns (a last block shorter),
    /// in one group and in several on rayon's threads; a fixed dof reads as zero.
    #[test]
    fn functionals_have_the_bits_of_one_extension_per_column() {
        let side = 14;
        let (a, _, _, mut cond) = fixed_column_grid(side, 2 * side + 1..3 * side);
        let n = a.nrows;
        let functionals: Vec<Vec<(usize, f64)>> = (0..9)
            .map(|r| {
                (0..n)
                    .filter(|d| (d * 7 + r * 13) % 11 == 0)
                    .map(|d| (d, 1.0 - 0.37 * (d % 5) as f64))
                    .chain([(r * side, 0.5)])
                    .collect()
            })
            .collect();
        let m = cond.dim();
        let mut reference = vec![vec![0.0; m]; functionals.len()];
        for (i, &dof) in cond.interface_dofs().to_vec().iter().enumerate() {
            let mut x = vec![0.0; n];
            x[dof] = 1.0;
            cond.extend_homogeneous(&mut x).unwrap();
            for (r, f) in functionals.iter().enumerate() {
                reference[r][i] = f.iter().map(|&(d, c)| c * x[d]).sum();
            }
        }
        assert!(reference.iter().flatten().any(|&v| v != 0.0));
        for (block, tasks) in [(1, 1), (4, 1), (32, 1), (3, 2), (5, 3)] {
            let got = cond
                .extension_functionals_in(&functionals, block, tasks)
                .unwrap();
            for (r, row) in reference.iter().enumerate() {
                for (i, &v) in row.iter().enumerate() {
                    assert_eq!(
                        got[(r, i)].to_bits(),
                        v.to_bits(),
                        "({r}, {i}), {block}, {tasks}"
                    );
                }
            }
        }
        let whole = cond.extension_functionals(&functionals).unwrap();
        assert_eq!(whole.nrows(), functionals.len());
        assert_eq!(whole.ncols(), m);
        let bad = vec![vec![(a.nrows, 1.0)]];
        assert!(matches!(
            cond.extension_functionals(&bad),
            Err(crate::Error::Problem(
                ProblemError::DimensionMismatch { .. }
            ))
        ));
    }
}
