//! Entries of the Schur complement `S = L_F L_Fᵀ` one at a time from the factor's
//! interface block, for operators built from entries (adaptive cross approximation of an
//! ℋ-matrix) without the dense `m × m` matrix (docs/math.md §8, §13).

use super::condensation::Condensation;

/// The interface block `L_F` (lower triangular, `m × m`) of a [`Condensation`]'s factor,
/// stored as packed rows, giving any entry `S_ij = Σ_{k ≤ min(i, j)} L_ik L_jk` of the
/// Schur complement in `O(min(i, j))` operations: `m(m + 1)/2` f64 (half of one dense
/// `S`). Rows and columns in the order of
/// [`Condensation::interface_dofs`].
#[derive(Debug, Clone)]
pub struct SchurEntries {
    m: usize,
    rows: Vec<f64>,
}

impl SchurEntries {
    /// Number `m` of condensed unknowns.
    pub fn dim(&self) -> usize {
        self.m
    }

    /// Bytes held (8 per stored f64).
    pub fn bytes(&self) -> usize {
        8 * self.rows.len()
    }

    /// Row `i` of `L_F` up to the diagonal (length `i + 1`).
    fn row(&self, i: usize) -> &[f64] {
        let start = i * (i + 1) / 2;
        &self.rows[start..start + i + 1]
    }

    /// `S_ij` (symmetric: the same sum for `S_ji`).
    ///
    /// # Panics
    /// If `i` or `j` is not below [`dim`](Self::dim).
    pub fn entry(&self, i: usize, j: usize) -> f64 {
        assert!(
            i < self.m && j < self.m,
            "entry ({i}, {j}) of an {0} × {0} S",
            self.m
        );
        let k = i.min(j) + 1;
        dot(&self.row(i)[..k], &self.row(j)[..k])
    }
}

/// `Σ a_k b_k` in four interleaved partial sums (vectorisable; a fixed order, so the same
/// bits every call).
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (ca.remainder(), cb.remainder());
    for (x, y) in ca.zip(cb) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    let mut sum = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (x, y) in ra.iter().zip(rb) {
        sum += x * y;
    }
    sum
}

impl<const D: usize> Condensation<D> {
    /// The Schur complement's entries one at a time ([`SchurEntries`]): a copy of the
    /// factor's interface block, `m(m + 1)/2` f64, instead of the `m²` of
    /// [`schur_complement`](Self::schur_complement) (and none of its dense products).
    pub fn schur_entries(&self) -> SchurEntries {
        SchurEntries {
            m: self.dim(),
            rows: self.factor.interface_rows(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::partial_cholesky::tests::grid;
    use super::*;

    /// Every entry from the packed factor equals the dense Schur complement's (the same
    /// sums in another order: to round-off), on a grid condensed onto a column of nodes.
    #[test]
    fn entries_are_the_dense_schur_complements() {
        let m = 12;
        let a = grid(m);
        let n = a.nrows;
        let blocks: Vec<usize> = (0..m).map(|j| m / 2 + m * j).collect();
        let cond = Condensation::<1>::build(&a, &vec![false; n], &blocks, None).unwrap();
        let dense = cond.schur_complement();
        let entries = cond.schur_entries();
        let k = cond.dim();
        assert_eq!(entries.dim(), k);
        assert_eq!(entries.bytes(), 8 * k * (k + 1) / 2);
        let scale = dense.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        let mut worst = 0.0f64;
        for j in 0..k {
            for i in 0..k {
                worst = worst.max((entries.entry(i, j) - dense[j * k + i]).abs());
                assert_eq!(entries.entry(i, j).to_bits(), entries.entry(j, i).to_bits());
            }
        }
        assert!(worst <= 1e-13 * scale, "{worst:e} of {scale:e}");
    }
}
