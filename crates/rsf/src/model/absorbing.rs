//! Absorbing (Lysmer–Kuhlemeyer) boundaries: dashpots on named boundary parts that let
//! waves leave a truncated domain (docs/math.md "Absorbing boundaries").

use rsf_fem::{BoundaryPart, SimplexMesh, SparseMatrix};

use crate::error::{Error, Result};

/// Lysmer–Kuhlemeyer dashpots on the absorbing parts Γ_A of a [`Model`](crate::Model)
/// (docs/math.md "Absorbing boundaries"): the traction
/// `t = −ρc_p ((v − v_far)·n) n − ρc_s ((v − v_far) − ((v − v_far)·n) n)` (a scalar field:
/// `t = −ρc_s (v − v_far)`), exact for plane waves at normal incidence, with a far field
/// moving at `v_far(t) = w · g(t)` (`g` the model's loading history, `w` the part's
/// velocity; `w = 0`: the far field at rest).
///
/// Discretised lumped on the nodes of Γ_A: per facet `f` (measure `|f|`, outer unit normal
/// `n_f`) each of its `D` vertices gets `|f|/D · ρ(c_p n_f n_fᵀ + c_s (I − n_f n_fᵀ))` on its
/// diagonal block. The equation of motion becomes `M a + C v + K u = F + g(t) C w`; the
/// velocity problem of a step gains `C` in its matrix (`(2/τ)M + C + (τ/2)K` for Newmark,
/// `M/τ + C + τK` for backward Euler, on every multigrid level through the Galerkin
/// products) and `g(t_n) C w` on its right-hand side. Built by
/// [`ModelBuilder::absorbing_boundary`](crate::ModelBuilder::absorbing_boundary); a
/// quasistatic integrator refuses a model with absorbing parts, the fault ODE (no inertia,
/// no waves in the volume) treats them as traction-free (their force, `ρc |v − v_far|`,
/// is dropped).
#[derive(Debug, Clone)]
pub struct AbsorbingBoundary {
    /// The names of the absorbing parts, in the order given to the builder.
    pub parts: Vec<String>,
    /// The dashpot matrix `C` (`n × n`, `n = C · nodes`, node-major; N·s/m, per unit
    /// thickness in 2D): symmetric positive semi-definite, non-zero only in the diagonal
    /// blocks of the nodes of Γ_A, stored on the pattern of the stiffness matrix, in model
    /// coordinates (the slip factor and the model's change of variables,
    /// [`Model::transform`](crate::Model::transform), applied as to `M` and `K`).
    pub damping: SparseMatrix,
    /// `C w`: the dashpots' force of the far-field motion at `g(t) = 1` (N, length `n`,
    /// model coordinates); the right-hand side of a step at `t_n` gains `g(t_n) C w`.
    /// Empty when every part's far field is at rest.
    pub far_field_force: Vec<f64>,
}

impl AbsorbingBoundary {
    /// Checks the shapes against a model of `n` dofs with stiffness `stiffness`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `absorbing` for a damping matrix of another size
    /// or pattern than `stiffness`, a far-field force of another length (neither empty nor
    /// `n`), or a non-finite or negative diagonal entry.
    pub(crate) fn validate(&self, stiffness: &SparseMatrix) -> Result<()> {
        let n = stiffness.nrows();
        let c = &self.damping;
        if c.nrows() != n
            || c.ncols() != n
            || c.symbolic().col_ptr() != stiffness.symbolic().col_ptr()
            || c.symbolic().row_idx() != stiffness.symbolic().row_idx()
        {
            return Err(crate::error::invalid(
                "absorbing",
                format!(
                    "the damping matrix ({}x{}) must have the size ({n}x{n}) and pattern of \
                     the stiffness matrix",
                    c.nrows(),
                    c.ncols()
                ),
            ));
        }
        if !(self.far_field_force.is_empty() || self.far_field_force.len() == n) {
            return Err(crate::error::invalid(
                "absorbing",
                format!(
                    "far_field_force has length {}, expected 0 or {n}",
                    self.far_field_force.len()
                ),
            ));
        }
        if let Some(x) = c
            .val()
            .iter()
            .chain(&self.far_field_force)
            .find(|x| !x.is_finite())
        {
            return Err(crate::error::invalid(
                "absorbing",
                format!("a non-finite entry ({x}) of the damping or its far-field force"),
            ));
        }
        let d = crate::model::conditioning::diagonal(c);
        if let Some(i) = (0..n).find(|&i| d[i] < 0.0) {
            return Err(crate::error::invalid(
                "absorbing",
                format!(
                    "diagonal entry {i} of the damping is {:e}: dashpots are positive \
                     semi-definite",
                    d[i]
                ),
            ));
        }
        Ok(())
    }
}

/// The dashpot block of a facet with outer unit normal `n` (Pa·s/m): `z_p n nᵀ + z_s (I −
/// n nᵀ)` for a vector field (`C = D`), `z_s` for a scalar one (`C = 1`).
pub(crate) fn dashpot_block<const D: usize, const C: usize>(
    n: &[f64; D],
    [z_p, z_s]: [f64; 2],
) -> [[f64; C]; C] {
    std::array::from_fn(|r| {
        std::array::from_fn(|c| {
            if C == 1 {
                z_s
            } else {
                let nn = n[r] * n[c];
                z_p * nn + z_s * (if r == c { 1.0 } else { 0.0 } - nn)
            }
        })
    })
}

/// One absorbing part resolved on the mesh, with its impedances and far-field velocity.
pub(crate) struct ResolvedPart<'a, const D: usize, const C: usize> {
    pub part: &'a BoundaryPart<D>,
    /// `(ρc_p, ρc_s)` (Pa·s/m) of each of the part's facets (in `part.facets()` order).
    pub impedances: &'a [[f64; 2]],
    /// The far-field velocity `w` (m/s, Cartesian, of the unscaled field).
    pub velocity: [f64; C],
}

/// The lumped dashpot matrix (Cartesian, unscaled) on the pattern of `stiffness`, and
/// `C w` (empty if every `w` is 0). With `columns` (one flag per vertex; `stiffness` then
/// holds only those nodes' columns) the matrix gets only the kept nodes' blocks, each with
/// the bits of the whole matrix's; `C w` is whole either way.
///
/// # Errors
/// [`Error::InvalidParameter`] named `absorbing` if the stiffness matrix lacks an entry
/// of a node's diagonal block (an internal invariant of assembled matrices).
pub(crate) fn assemble<const D: usize, const C: usize>(
    mesh: &SimplexMesh<D>,
    parts: &[ResolvedPart<'_, D, C>],
    stiffness: &SparseMatrix,
    columns: Option<&[bool]>,
) -> Result<(SparseMatrix, Vec<f64>)> {
    let n = stiffness.nrows();
    let moving = parts.iter().any(|p| p.velocity.iter().any(|&w| w != 0.0));
    let mut far = if moving { vec![0.0; n] } else { Vec::new() };
    let (cp, ri) = (
        stiffness.symbolic().col_ptr(),
        stiffness.symbolic().row_idx(),
    );
    let mut vals = vec![0.0; ri.len()];
    for rp in parts {
        for (&f, &impedances) in rp.part.facets().iter().zip(rp.impedances) {
            let share = mesh.boundary_facet_measure(f) / D as f64;
            let z = dashpot_block::<D, C>(&mesh.boundary_facet_normal(f), impedances);
            for &p in mesh.boundary_facet(f) {
                let held = columns.is_none_or(|keep| keep[p]);
                for (c, zc) in (0..C).map(|c| (c, z.map(|row| row[c]))) {
                    let j = C * p + c;
                    let col = &ri[cp[j]..cp[j + 1]];
                    for (r, zrc) in zc.iter().enumerate().filter(|_| held) {
                        let i = C * p + r;
                        let k = col.binary_search(&i).map_err(|_| {
                            crate::error::invalid(
                                "absorbing",
                                format!("the stiffness matrix has no entry ({i}, {j})"),
                            )
                        })?;
                        vals[cp[j] + k] += share * zrc;
                    }
                    if moving {
                        // (C w)_i = Σ_c C_ic w_c, by columns.
                        for (r, zrc) in zc.iter().enumerate() {
                            far[C * p + r] += share * zrc * rp.velocity[c];
                        }
                    }
                }
            }
        }
    }
    let symbolic = stiffness
        .symbolic()
        .to_owned()
        .map_err(|e| Error::Fem(rsf_fem::Error::Faer(format!("{e:?}"))))?;
    Ok((SparseMatrix::new(symbolic, vals), far))
}
