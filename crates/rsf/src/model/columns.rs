//! A model of some columns ([`Model::columns`], built by
//! [`ModelBuilder::build_columns`](crate::ModelBuilder::build_columns)): its consistency
//! and its comparison with the whole model.

use rsf_fem::SparseMatrix;

use super::Model;
use crate::error::{check_len, invalid, Result};

impl<const D: usize, const C: usize> Model<D, C> {
    /// Of a model of some columns ([`columns`](Self::columns)): one flag per vertex, and no
    /// entry in a column of a node not kept (of `K`, `M`, the energy norm, the dashpots).
    pub(crate) fn validate_columns(&self) -> Result<()> {
        let Some(keep) = &self.columns else {
            return Ok(());
        };
        check_len(
            "columns",
            keep.len(),
            self.vertices.len(),
            |len, expected| format!("has {len} flags, the model {expected} vertices"),
        )?;
        for (name, m) in self.matrices() {
            let cp = m.symbolic().col_ptr();
            if let Some(j) = (0..m.ncols()).find(|&j| !keep[j / C] && cp[j + 1] > cp[j]) {
                return Err(invalid(
                    name,
                    format!(
                        "column {j} has entries, but node {} is not among the model's columns",
                        j / C
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The matrices by name: `stiffness`, `energy_norm`, `mass` and the absorbing
    /// `damping` if present.
    fn matrices(&self) -> impl Iterator<Item = (&'static str, &SparseMatrix)> {
        [
            ("stiffness", Some(&self.stiffness)),
            ("energy_norm", Some(&self.energy_norm)),
            ("mass", self.mass.as_ref()),
            ("damping", self.absorbing.as_ref().map(|a| &a.damping)),
        ]
        .into_iter()
        .filter_map(|(name, m)| Some((name, m?)))
    }

    /// Checks that this model is `whole`'s part on its columns, bit for bit: every kept
    /// column ([`columns`](Self::columns); all of them for a whole model) of the stiffness,
    /// mass, energy norm and dashpots has `whole`'s rows and value bits and every other
    /// column is empty; the vectors (load, constraints, Dirichlet dofs and factors — not the
    /// loading history —, far-field force, `u₀`), the prolongations (pattern and bits), the frictional boundary, the frames,
    /// the vertices and cells are `whole`'s. For a process's model
    /// ([`ModelBuilder::build_columns`](crate::ModelBuilder::build_columns)) against the
    /// one-process model.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named after the first
    /// field that differs (`stiffness`, `energy_norm`, `mass`, `damping`, `load`, …), or
    /// `columns` if `whole` is itself a model of some columns or the flags' number is not
    /// the vertices'; this model's [`validate`](Self::validate) errors are not repeated
    /// here.
    pub fn check_part_of(&self, whole: &Model<D, C>) -> Result<()> {
        if whole.columns.is_some() {
            return Err(invalid(
                "columns",
                "the whole model holds only some columns",
            ));
        }
        let n = self.vertices.len();
        let all = vec![true; n];
        let keep = self.columns.as_deref().unwrap_or(&all);
        if keep.len() != n || whole.vertices.len() != n {
            return Err(invalid(
                "columns",
                format!(
                    "{} flags, {n} vertices, the whole model {} vertices",
                    keep.len(),
                    whole.vertices.len()
                ),
            ));
        }
        let names = |m: &Self| m.matrices().map(|(name, _)| name).collect::<Vec<_>>();
        if names(self) != names(whole) {
            return Err(invalid(
                "mass",
                format!(
                    "matrices {:?}, the whole model's {:?}",
                    names(self),
                    names(whole)
                ),
            ));
        }
        for ((name, part), (_, w)) in self.matrices().zip(whole.matrices()) {
            same_columns(name, w, part, keep, C)?;
        }
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let far = |m: &Self| m.absorbing.as_ref().map(|a| bits(&a.far_field_force));
        let parts = |m: &Self| m.absorbing.as_ref().map(|a| a.parts.clone());
        let checks = [
            ("vertices", self.vertices == whole.vertices),
            ("cells", self.cells == whole.cells),
            ("load", bits(&self.load) == bits(&whole.load)),
            ("fixed", self.fixed == whole.fixed),
            (
                "dirichlet",
                self.dirichlet.dofs == whole.dirichlet.dofs
                    && bits(&self.dirichlet.factors) == bits(&whole.dirichlet.factors),
            ),
            (
                "initial_displacement",
                bits(&self.initial_displacement) == bits(&whole.initial_displacement),
            ),
            (
                "frictional_boundary",
                self.frictional_boundary == whole.frictional_boundary,
            ),
            ("frames", self.frames == whole.frames),
            (
                "absorbing",
                far(self) == far(whole) && parts(self) == parts(whole),
            ),
            (
                "internal_fault",
                self.internal_fault.is_none() && whole.internal_fault.is_none(),
            ),
        ];
        if let Some((name, _)) = checks.iter().find(|(_, same)| !same) {
            return Err(invalid(name, "differs from the whole model's"));
        }
        if self.prolongations.len() != whole.prolongations.len() {
            return Err(invalid("prolongations", "another number of levels"));
        }
        for (p, w) in self.prolongations.iter().zip(&whole.prolongations) {
            same_columns("prolongations", w, p, &vec![true; w.ncols()], 1)?;
        }
        Ok(())
    }
}

/// Every column of `part` of a node with `keep[node]` (`c` columns per node) has the rows
/// and value bits of `whole`'s, every other column is empty, the shapes agree.
fn same_columns(
    name: &str,
    whole: &SparseMatrix,
    part: &SparseMatrix,
    keep: &[bool],
    c: usize,
) -> Result<()> {
    if (part.nrows(), part.ncols()) != (whole.nrows(), whole.ncols())
        || keep.len() * c != whole.ncols()
    {
        return Err(invalid(
            name,
            format!(
                "is {}x{}, the whole model's {}x{}",
                part.nrows(),
                part.ncols(),
                whole.nrows(),
                whole.ncols()
            ),
        ));
    }
    let bits = |a: &[f64]| a.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    for j in 0..whole.ncols() {
        let same = if keep[j / c] {
            part.row_idx_of_col_raw(j) == whole.row_idx_of_col_raw(j)
                && bits(part.val_of_col(j)) == bits(whole.val_of_col(j))
        } else {
            part.row_idx_of_col_raw(j).is_empty()
        };
        if !same {
            let what = if keep[j / c] {
                "differs from the whole model's"
            } else {
                "has entries, but its node is not kept"
            };
            return Err(invalid(name, format!("column {j} {what}")));
        }
    }
    Ok(())
}
