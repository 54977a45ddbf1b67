//! The load operator `ℓ = F + M w_M − K w_K` of the velocity problems' right-hand sides
//! ([`LoadOperator`]).

use rsf_linalg::{Parallelism, SparseMatrix};

use crate::{Error, Result};

/// Fewest rows for which [`LoadOperator::apply`] splits its rows in two halves on two
/// threads (if its [`Parallelism`] allows): below, waking the second thread costs more
/// than the half pass it takes over (the main job at j = 4, 2754 rows, ran 2.5 % slower
/// on two threads than on one).
pub const LOAD_PARALLEL_MIN_ROWS: usize = 5000;

/// `ℓ = F + M w_M − K w_K` for symmetric `M` (optional) and `K`, evaluated row by row in
/// one pass when `M` and `K` share their pattern (as assembled by rsf-fem): per stored
/// entry one `u32` row index and the two values, no temporary vector. From
/// [`LOAD_PARALLEL_MIN_ROWS`] rows on, the two halves of the rows run on two threads if
/// its [`Parallelism`] allows ([`with_parallelism`](Self::with_parallelism); default
/// [`Parallelism::default`]).
#[derive(Debug, Clone)]
pub struct LoadOperator {
    n: usize,
    col_ptr: Vec<usize>,
    rows: Vec<u32>,
    /// `(M_ij, K_ij)` per stored entry (`M_ij = 0` without mass or off M's pattern).
    values: Vec<[f64; 2]>,
    /// `paired[j]`: rows `j` and `j + 1` have the same pattern (the two components of a
    /// node in a vector-valued FE matrix) and are evaluated together.
    paired: Vec<bool>,
    /// Threads of [`apply`](Self::apply).
    par: Parallelism,
    /// The rows evaluated ([`for_rows`](Self::for_rows)); `None`: all.
    rows_kept: Option<Vec<bool>>,
}

impl LoadOperator {
    /// From `M` (if the scheme uses it) and `K`, both `n × n`, symmetric (both triangles
    /// stored). The pattern is the union of both patterns.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for non-square or mismatched shapes or `n ≥ 2³²`.
    pub fn new(mass: Option<&SparseMatrix>, stiffness: &SparseMatrix) -> Result<Self> {
        Self::build(mass, stiffness, None)
    }

    /// The operator of [`new`](Self::new) holding only the rows `i` with `keep[i]` (length
    /// `n`): what one rank of a job whose ranks share the rows keeps (its owned rows: the
    /// memory of its share). [`apply`](Self::apply) computes those rows with the bits of
    /// the whole operator's (each row's sums are the same) and writes NaN into the others,
    /// which the caller fills from their owners (an all-gather).
    ///
    /// # Errors
    /// As [`new`](Self::new); [`Error::DimensionMismatch`] if `keep` is not `n` long.
    pub fn for_rows(
        mass: Option<&SparseMatrix>,
        stiffness: &SparseMatrix,
        keep: &[bool],
    ) -> Result<Self> {
        if keep.len() != stiffness.nrows() {
            return Err(Error::DimensionMismatch {
                what: "rows kept",
                expected: stiffness.nrows(),
                got: keep.len(),
            });
        }
        Self::build(mass, stiffness, Some(keep))
    }

    fn build(
        mass: Option<&SparseMatrix>,
        stiffness: &SparseMatrix,
        keep: Option<&[bool]>,
    ) -> Result<Self> {
        let n = stiffness.nrows();
        let square = |m: &SparseMatrix| m.nrows() == n && m.ncols() == n;
        if !square(stiffness) || mass.is_some_and(|m| !square(m)) || n >= u32::MAX as usize {
            return Err(Error::DimensionMismatch {
                what: "mass/stiffness matrix",
                expected: n,
                got: mass.map_or(stiffness.ncols(), |m| m.ncols()),
            });
        }
        let kept = |j: usize| keep.is_none_or(|k| k[j]);
        // Row j of the symmetric operator is column j.
        let nnz: usize = (0..n)
            .filter(|&j| kept(j))
            .map(|j| stiffness.row_idx_of_col_raw(j).len())
            .sum();
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut rows = Vec::with_capacity(nnz);
        let mut values: Vec<[f64; 2]> = Vec::with_capacity(nnz);
        col_ptr.push(0);
        let mut merged: Vec<(usize, f64, f64)> = Vec::new();
        for j in 0..n {
            merged.clear();
            if !kept(j) {
                col_ptr.push(rows.len());
                continue;
            }
            for (&i, &k) in stiffness
                .row_idx_of_col_raw(j)
                .iter()
                .zip(stiffness.val_of_col(j))
            {
                merged.push((i, 0.0, k));
            }
            if let Some(m) = mass {
                for (&i, &mv) in m.row_idx_of_col_raw(j).iter().zip(m.val_of_col(j)) {
                    merged.push((i, mv, 0.0));
                }
            }
            merged.sort_by_key(|e| e.0);
            for &(i, mv, k) in &merged {
                if rows.len() > col_ptr[j] && *rows.last().expect("nonempty") == i as u32 {
                    let last = values.last_mut().expect("nonempty");
                    last[0] += mv;
                    last[1] += k;
                } else {
                    rows.push(i as u32);
                    values.push([mv, k]);
                }
            }
            col_ptr.push(rows.len());
        }
        let pattern = |j: usize| &rows[col_ptr[j]..col_ptr[j + 1]];
        let mut paired = vec![false; n];
        let mut j = 0;
        while j + 1 < n {
            if kept(j) && kept(j + 1) && pattern(j) == pattern(j + 1) {
                paired[j] = true;
                j += 2;
            } else {
                j += 1;
            }
        }
        Ok(Self {
            n,
            col_ptr,
            rows,
            values,
            paired,
            par: Parallelism::default(),
            rows_kept: keep.map(<[bool]>::to_vec),
        })
    }

    /// The same operator with the parallelism `par` for [`apply`](Self::apply) (its two
    /// halves of the rows on two threads from [`LOAD_PARALLEL_MIN_ROWS`] rows on when
    /// `par` has more than one; the same bits whatever `par`).
    pub fn with_parallelism(mut self, par: Parallelism) -> Self {
        self.par = par;
        self
    }

    /// The parallelism of [`apply`](Self::apply).
    pub fn parallelism(&self) -> Parallelism {
        self.par
    }

    /// `out = load + M w_mass − K w_stiffness` (all of length `n`). The two halves of the
    /// rows run on two threads when the operator's [`Parallelism`] has more than one and
    /// `n ≥` [`LOAD_PARALLEL_MIN_ROWS`]; every row's arithmetic is the same either way, so
    /// the result does not depend on the number of threads.
    ///
    /// # Panics
    /// If a length differs from `n` (internal invariant of callers).
    pub fn apply(&self, load: &[f64], w_mass: &[f64], w_stiffness: &[f64], out: &mut [f64]) {
        let n = self.n;
        assert!(load.len() == n && w_mass.len() == n && w_stiffness.len() == n && out.len() == n);
        // The halves split between rows, never inside a pair.
        let mut half = n / 2;
        if half > 0 && self.paired[half - 1] {
            half += 1;
        }
        let (lo, hi) = out.split_at_mut(half);
        let rows = |first: usize, out: &mut [f64]| {
            let mut k = 0;
            while k < out.len() {
                let j = first + k;
                let range = self.col_ptr[j]..self.col_ptr[j + 1];
                // Two partial sums per row for the two matrices; a pair of rows with one
                // pattern is summed together (four independent dependency chains, one
                // gather of `w` for both). Each row's sums are the same either way.
                if self.paired[j] {
                    let next = self.col_ptr[j + 1]..self.col_ptr[j + 2];
                    let (mut sm0, mut sk0, mut sm1, mut sk1) = (0.0, 0.0, 0.0, 0.0);
                    for ((&i, &[m0, k0]), &[m1, k1]) in self.rows[range.clone()]
                        .iter()
                        .zip(&self.values[range])
                        .zip(&self.values[next])
                    {
                        let i = i as usize;
                        let (wm, wk) = (w_mass[i], w_stiffness[i]);
                        sm0 += m0 * wm;
                        sk0 += k0 * wk;
                        sm1 += m1 * wm;
                        sk1 += k1 * wk;
                    }
                    out[k] = load[j] + sm0 - sk0;
                    out[k + 1] = load[j + 1] + sm1 - sk1;
                    k += 2;
                } else {
                    let (mut sm, mut sk) = (0.0, 0.0);
                    for (&i, &[mv, kv]) in self.rows[range.clone()].iter().zip(&self.values[range])
                    {
                        let i = i as usize;
                        sm += mv * w_mass[i];
                        sk += kv * w_stiffness[i];
                    }
                    out[k] = load[j] + sm - sk;
                    k += 1;
                }
            }
        };
        // Each half compiled for the machine's SIMD level (pulp, chosen at run time); the
        // order of the floating-point operations is fixed, so are the results.
        let simd_rows = |first: usize, out: &mut [f64]| {
            pulp::Arch::new().dispatch(|| rows(first, out));
        };
        // Two threads from LOAD_PARALLEL_MIN_ROWS rows on (see there).
        let par = if n >= LOAD_PARALLEL_MIN_ROWS {
            self.par
        } else {
            Parallelism::SEQ
        };
        par.join(|| simd_rows(0, lo), || simd_rows(half, hi));
        if let Some(keep) = &self.rows_kept {
            for (o, _) in out.iter_mut().zip(keep).filter(|(_, &k)| !k) {
                *o = f64::NAN;
            }
        }
    }

    /// The rows [`apply`](Self::apply) computes (`None`: all; see
    /// [`for_rows`](Self::for_rows)).
    pub fn rows_kept(&self) -> Option<&[bool]> {
        self.rows_kept.as_deref()
    }
}

#[cfg(test)]
mod tests {
    use super::{LoadOperator, Parallelism, LOAD_PARALLEL_MIN_ROWS};
    use rsf_fem::{pipping_slider_coarse, Assembler, Diagonal, LinearElasticity, MeshHierarchy};

    /// `M` and `K` of the Pipping slider's mesh refined `refinements` times (plane strain).
    fn slider_matrices(refinements: usize) -> (rsf_fem::SparseMatrix, rsf_fem::SparseMatrix) {
        let h =
            MeshHierarchy::refine_uniformly(pipping_slider_coarse(Diagonal::Forward), refinements);
        let mesh = h.finest();
        let asm = Assembler::new(mesh).unwrap();
        let mat = LinearElasticity::plane_strain(5e7, 0.3).unwrap();
        (
            asm.mass(mesh, 5e3).unwrap(),
            asm.stiffness(mesh, &mat).unwrap(),
        )
    }

    /// The rows of a node evaluated as a pair give the bits of the rows evaluated one by one.
    #[test]
    fn paired_rows_have_the_bits_of_single_rows() {
        let (m, k) = slider_matrices(1);
        let n = k.nrows();
        let op = LoadOperator::new(Some(&m), &k).unwrap();
        assert!(op.paired.iter().filter(|&&p| p).count() == n / 2);
        let single = LoadOperator {
            paired: vec![false; n],
            ..op.clone()
        };
        let wave = |s: f64| -> Vec<f64> { (0..n).map(|i| (s * i as f64).sin() * 1e-3).collect() };
        let (load, wm, wk) = (wave(0.3), wave(1.7), wave(2.9));
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        op.apply(&load, &wm, &wk, &mut a);
        single.apply(&load, &wm, &wk, &mut b);
        assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
    }

    /// An operator of some rows (a rank's share, [`LoadOperator::for_rows`]): its rows have
    /// the whole operator's bits, the others are NaN; its storage holds only its rows'
    /// entries, so that the shares of two complementary sets of rows hold the whole's; a
    /// `keep` of the wrong length is refused.
    #[test]
    fn an_operator_of_some_rows_has_the_whole_operators_bits_on_them() {
        let (m, k) = slider_matrices(2);
        let n = k.nrows();
        let whole = LoadOperator::new(Some(&m), &k).unwrap();
        let wave = |s: f64| -> Vec<f64> { (0..n).map(|i| (s * i as f64).sin() * 1e-3).collect() };
        let (load, wm, wk) = (wave(0.3), wave(1.7), wave(2.9));
        let mut reference = vec![0.0; n];
        whole.apply(&load, &wm, &wk, &mut reference);
        // Nodes (pairs of rows) in a pattern unrelated to the numbering, and a lone row.
        let keep: Vec<bool> = (0..n).map(|i| (i / 2) % 3 == 1 || i == 7).collect();
        let other: Vec<bool> = keep.iter().map(|k| !k).collect();
        let mut stored = 0;
        for keep in [&keep, &other] {
            let part = LoadOperator::for_rows(Some(&m), &k, keep).unwrap();
            assert_eq!(part.rows_kept(), Some(keep.as_slice()));
            stored += part.values.len();
            let mut out = vec![0.0; n];
            part.apply(&load, &wm, &wk, &mut out);
            for i in 0..n {
                if keep[i] {
                    assert_eq!(out[i].to_bits(), reference[i].to_bits(), "row {i}");
                } else {
                    assert!(out[i].is_nan(), "row {i} is not the part's");
                }
            }
        }
        assert_eq!(stored, whole.values.len());
        assert!(LoadOperator::for_rows(Some(&m), &k, &keep[1..]).is_err());
    }

    /// Above the threshold, every parallelism gives the bits of one thread (the two halves
    /// of the rows split between nodes), with the global pool and with a pool of one thread.
    #[test]
    fn rows_are_bit_identical_for_every_thread_count() {
        let (m, k) = slider_matrices(5);
        let n = k.nrows();
        assert!(n >= LOAD_PARALLEL_MIN_ROWS, "{n} rows: below the threshold");
        let wave = |s: f64| -> Vec<f64> { (0..n).map(|i| (s * i as f64).sin() * 1e-3).collect() };
        let (load, wm, wk) = (wave(0.3), wave(1.7), wave(2.9));
        let bits = |par: Parallelism| {
            let op = LoadOperator::new(Some(&m), &k)
                .unwrap()
                .with_parallelism(par);
            assert_eq!(op.parallelism(), par);
            let mut out = vec![0.0; n];
            op.apply(&load, &wm, &wk, &mut out);
            out.iter().map(|x| x.to_bits()).collect::<Vec<u64>>()
        };
        let reference = bits(Parallelism::SEQ);
        for par in [
            Parallelism::rayon(1),
            Parallelism::rayon(2),
            Parallelism::rayon(4),
        ] {
            assert_eq!(bits(par), reference, "{par:?}");
        }
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        assert_eq!(one.install(|| bits(Parallelism::rayon(2))), reference);
    }
}
