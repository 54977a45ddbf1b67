//! The post-step: the extra kept dofs `P` eliminated again densely from `S_KK`, leaving
//! the Schur complement on the blocks' free components `F`, their condensed right-hand
//! sides, and the rows of the extension at `P`.
//! ([`KeptSchur::onto_interface`] has the formulas.)

use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::reborrow::IntoConst;
use faer::{Mat, Par};

use super::packed::{cholesky, cholesky_scratch, sub_gram_rows, try_zeros, PackedSymmetric, PANEL};
use super::{KeptSchur, SchurOnlyReport};
use crate::error::{Error, Result};
use rsf_nonsmooth::ProblemError;

/// The rows of the extension at the extra kept dofs: `x_P = o + E x_F` with
/// `E = −S_PP⁻¹ S_PF` (`|P| × |F|`, row-major) and, per right-hand side, the offset
/// `o = S_PP⁻¹ g_P` (the extension of that right-hand side with `x_F = 0`).
#[derive(Clone, PartialEq)]
pub struct ExtraRows {
    dofs: Vec<usize>,
    nf: usize,
    matrix: Vec<f64>,
    offsets: Vec<Vec<f64>>,
}

impl std::fmt::Debug for ExtraRows {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ExtraRows")
            .field("dofs", &self.dofs)
            .field("interface_len", &self.nf)
            .field("rhs", &self.offsets.len())
            .finish_non_exhaustive()
    }
}

impl ExtraRows {
    /// The extra dofs `P`, in the order of the rows.
    pub fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    /// `|P|`.
    pub fn len(&self) -> usize {
        self.dofs.len()
    }

    /// Whether there are no extra dofs.
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// Row `i` of `E` (length `|F|`): `∂x_{P_i}/∂x_F`.
    ///
    /// # Panics
    /// If `i ≥ |P|`.
    pub fn row(&self, i: usize) -> &[f64] {
        &self.matrix[i * self.nf..(i + 1) * self.nf]
    }

    /// `E`, row-major (`|P| × |F|`).
    pub fn matrix(&self) -> &[f64] {
        &self.matrix
    }

    /// The offset `o` of right-hand side `k` (length `|P|`).
    ///
    /// # Panics
    /// If `k` is not below the number of right-hand sides.
    pub fn offset(&self, k: usize) -> &[f64] {
        &self.offsets[k]
    }

    /// `out = o_k + E x_F` (`o_k` the offset of right-hand side `k`, or none) for the
    /// interface values `x_f` (length `|F|`), `out` of length `|P|`.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] for other lengths, [`ProblemError::InvalidOption`] for a
    /// `k` out of range.
    pub fn extend(&self, k: Option<usize>, x_f: &[f64], out: &mut [f64]) -> Result<()> {
        for (what, expected, got) in [
            ("interface values", self.nf, x_f.len()),
            ("extra values", self.len(), out.len()),
        ] {
            ProblemError::check_length(what, expected, got)?;
        }
        let offset = match k {
            Some(k) => Some(self.offsets.get(k).ok_or_else(|| {
                ProblemError::InvalidOption(format!(
                    "right-hand side {k} of {}",
                    self.offsets.len()
                ))
            })?),
            None => None,
        };
        for (i, o) in out.iter_mut().enumerate() {
            let mut s = offset.map_or(0.0, |v| v[i]);
            for (e, x) in self.row(i).iter().zip(x_f) {
                s += e * x;
            }
            *o = s;
        }
        Ok(())
    }
}

/// The Schur complement on the blocks' free components alone, from
/// [`KeptSchur::onto_interface`]: `S_F` (packed rows), the condensed right-hand sides
/// `g_F`, and the [`ExtraRows`] that give the extra dofs from `x_F`.
#[derive(Clone)]
pub struct InterfaceSchur {
    s: PackedSymmetric,
    g: Vec<Vec<f64>>,
    interface: Vec<usize>,
    extras: ExtraRows,
    report: SchurOnlyReport,
}

impl std::fmt::Debug for InterfaceSchur {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InterfaceSchur")
            .field("dim", &self.interface.len())
            .field("extras", &self.extras)
            .field("report", &self.report)
            .finish_non_exhaustive()
    }
}

impl InterfaceSchur {
    /// `|F|`.
    pub fn dim(&self) -> usize {
        self.interface.len()
    }

    /// The dofs of `F` in the order of `S_F`
    /// ([`Condensation::interface_dofs`](crate::Condensation::interface_dofs)' order).
    pub fn interface_dofs(&self) -> &[usize] {
        &self.interface
    }

    /// `S_F = A_FF − A_FR' A_R'R'⁻¹ A_R'F` with `R'` every free dof outside `F`
    /// (packed rows, `|F| × |F|`).
    pub fn schur(&self) -> &PackedSymmetric {
        &self.s
    }

    /// `S_F`, by value.
    pub fn into_schur(self) -> PackedSymmetric {
        self.s
    }

    /// The condensed right-hand sides on `F` (one of length `|F|` each).
    pub fn condensed_rhs(&self) -> &[Vec<f64>] {
        &self.g
    }

    /// The extension rows at the extra dofs.
    pub fn extras(&self) -> &ExtraRows {
        &self.extras
    }

    /// The elimination's report.
    pub fn report(&self) -> &SchurOnlyReport {
        &self.report
    }
}

impl KeptSchur {
    /// Eliminates the extra dofs `P` from `S_KK` densely: with `S_PP = L Lᵀ` and
    /// `W = L⁻¹ S_PF` (`|P| × |F|`),
    ///
    /// ```text
    /// S_F = S_FF − S_FP S_PP⁻¹ S_PF = S_FF − Wᵀ W,      g_F ← g_F − Wᵀ z,  z = L⁻¹ g_P,
    /// x_P = S_PP⁻¹ (g_P − S_PF x_F) = L⁻ᵀ z − L⁻ᵀ W x_F,
    /// ```
    ///
    /// so that `S_F`, `g_F` are the condensation's onto the blocks alone (the Schur
    /// complement of `S_PP` in `S_KK` is that of `A_{R∪P}` in `A`) and `x_P` is what
    /// [`Condensation::extend`](crate::Condensation::extend) gives at `P`
    /// ([`ExtraRows`]). `S_F` reuses `S_KK`'s storage (its leading block);
    /// `O(|F|² |P|)` operations.
    ///
    /// # Errors
    /// [`Error::NonPositivePivot`] (at a dof of `P`) if `S_PP` is not numerically
    /// positive definite; [`Error::OutOfMemory`] if a buffer cannot be allocated.
    pub fn onto_interface(self) -> Result<InterfaceSchur> {
        let KeptSchur {
            mut s,
            mut g,
            mut kept,
            nf,
            report,
        } = self;
        let nk = kept.len();
        let np = nk - nf;
        let extra_dofs = kept.split_off(nf);
        let nrhs = g.len();
        if np == 0 {
            return Ok(InterfaceSchur {
                s,
                g,
                interface: kept,
                extras: ExtraRows {
                    dofs: extra_dofs,
                    nf,
                    matrix: Vec::new(),
                    offsets: vec![Vec::new(); nrhs],
                },
                report,
            });
        }
        // L (np × np) with S_PP = L Lᵀ.
        let mut l = Mat::from_fn(
            np,
            np,
            |i, j| {
                if i >= j {
                    s.entry(nf + i, nf + j)
                } else {
                    0.0
                }
            },
        );
        cholesky(l.as_mut(), &mut cholesky_scratch(np)?).map_err(|k| Error::NonPositivePivot {
            what: "S_PP, the extra kept dofs' block of the Schur complement",
            dof: extra_dofs[k],
        })?;
        // W = L⁻¹ S_PF, stored transposed (|F| × np, column-major: row j of Wᵀ is the
        // column j of W).
        let mut wt_buf = try_zeros(nf * np, "the extras' coupling W")?;
        let mut w = faer::MatMut::from_column_major_slice_mut(&mut wt_buf, np, nf);
        for i in 0..np {
            let row = s.row(nf + i);
            for j in 0..nf {
                w[(i, j)] = row[j];
            }
        }
        solve_lower_triangular_in_place(l.as_ref(), w.as_mut(), Par::Seq);
        let w = w.into_const();
        // S_F = S_FF − Wᵀ W on the leading block (a prefix of the packed rows).
        s.truncate(nf);
        let idx: Vec<u32> = (0..nf as u32).collect();
        let mut tmp = try_zeros(nf * PANEL, "the extras' update panel")?;
        sub_gram_rows(s.rows_mut(), &idx, w.transpose(), &mut tmp);
        drop(tmp);
        // g_F −= Wᵀ z with z = L⁻¹ g_P; offsets L⁻ᵀ z.
        let mut offsets = Vec::with_capacity(nrhs);
        for gk in &mut g {
            let mut z = Mat::from_fn(np, 1, |i, _| gk[nf + i]);
            solve_lower_triangular_in_place(l.as_ref(), z.as_mut(), Par::Seq);
            for (j, gj) in gk[..nf].iter_mut().enumerate() {
                let mut acc = 0.0;
                for i in 0..np {
                    acc += w[(i, j)] * z[(i, 0)];
                }
                *gj -= acc;
            }
            solve_upper_triangular_in_place(l.transpose(), z.as_mut(), Par::Seq);
            offsets.push((0..np).map(|i| z[(i, 0)]).collect());
            gk.truncate(nf);
        }
        // E = −L⁻ᵀ W, row-major.
        let mut e = Mat::from_fn(np, nf, |i, j| w[(i, j)]);
        drop(wt_buf);
        solve_upper_triangular_in_place(l.transpose(), e.as_mut(), Par::Seq);
        let mut matrix = try_zeros(np * nf, "the extension rows")?;
        for i in 0..np {
            for j in 0..nf {
                matrix[i * nf + j] = -e[(i, j)];
            }
        }
        if !s.packed_rows().iter().all(|v| v.is_finite()) || !matrix.iter().all(|v| v.is_finite()) {
            return Err(ProblemError::NonFinite("the Schur complement on the interface").into());
        }
        Ok(InterfaceSchur {
            s,
            g,
            interface: kept,
            extras: ExtraRows {
                dofs: extra_dofs,
                nf,
                matrix,
                offsets,
            },
            report,
        })
    }
}
