//! A few vertices off Γ_F in a run condensed onto the fault: their displacement and velocity
//! as affine functions of the fault's unknowns, without the whole field's sparse solves.
//!
//! The condensed run's field off Γ_F is the extension `x_R = A_RR⁻¹ (b̃_R − A_RF x_F)`
//! ([`Condensation::extend`]), with `b̃ = b − A_{·,fixed} x_fixed`. For one interior dof `r`
//! it is `x_r = c(b, x_fixed)_r + P_r · x_F` with the row `P_r = −(A_RR⁻¹ A_RF)_r`, which by
//! the symmetry of `A` is the condensed right-hand side of the unit load `e_r` with the
//! fixed dofs at 0: `P_rᵀ = −A_FR A_RR⁻¹ e_r` (one forward sweep). The fixed dofs of a
//! condensed run are their initial values plus the Dirichlet factors times the integrated
//! loading `G(t)` (displacement) or the loading speed `ġ(t)` (velocity), so
//!
//! ```text
//! u_r = c0_r + G(t) c1_r + P_r · u_F,     v_r = ġ(t) c1_r + P_r · v_F,
//! ```
//!
//! `c0` the extension of the load with the initial fixed values and `x_F = 0`, `c1` that of
//! no load with the Dirichlet factors and `x_F = 0`.

use rsf_direct::Condensation;

use crate::error::{invalid, Result};
use crate::model::Model;

/// The dofs a probe of `vertices` (sorted, no repeats) computes: the free dofs of the
/// vertices (of both blocks of a split vertex's pair: its value reads mean and jump) that
/// are not condensed onto (`interface`), increasing.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `volume_vertices`
/// for a vertex that is not the model's.
pub(crate) fn probe_dofs<const D: usize, const C: usize>(
    model: &Model<D, C>,
    interface: &[usize],
    vertices: &[usize],
) -> Result<Vec<usize>> {
    let nv = model.vertices.len();
    if let Some(&v) = vertices.iter().find(|&&v| v >= nv) {
        return Err(invalid(
            "volume_vertices",
            format!("vertex {v} is not one of the model's {nv}"),
        ));
    }
    let mut in_interface = vec![false; model.num_dofs()];
    for &dof in interface {
        in_interface[dof] = true;
    }
    let mut blocks: Vec<usize> = vertices
        .iter()
        .flat_map(
            |&v| match model.internal_fault.as_ref().and_then(|f| f.pair_of(v)) {
                Some((minus, plus)) => vec![minus, plus],
                None => vec![v],
            },
        )
        .collect();
    blocks.sort_unstable();
    blocks.dedup();
    Ok(blocks
        .iter()
        .flat_map(|&p| C * p..C * p + C)
        .filter(|&i| !model.fixed[i] && !in_interface[i])
        .collect())
}

/// The rows of the extension operator at the watched vertices' dofs.
#[derive(Debug, Clone)]
pub(crate) struct VolumeProbe {
    /// The vertices asked for (sorted), to recognise the same request.
    vertices: Vec<usize>,
    /// The interior dofs computed (the asked vertices' and, at a split vertex, its pair's).
    dofs: Vec<usize>,
    /// `P` row-major (`dofs.len() × m`).
    rows: Vec<f64>,
    c0: Vec<f64>,
    c1: Vec<f64>,
}

impl VolumeProbe {
    /// The probe of `vertices` (sorted, no repeats) of `model` condensed by `cond`;
    /// `velocity_factor` the Dirichlet factors (length `n`, 0 off the Dirichlet dofs).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) named `volume_vertices`
    /// for a vertex that is not the model's; condensation errors.
    pub(crate) fn new<const D: usize, const C: usize>(
        model: &Model<D, C>,
        cond: &mut Condensation<C>,
        vertices: &[usize],
        velocity_factor: &[f64],
    ) -> Result<Self> {
        let n = model.num_dofs();
        let m = cond.dim();
        let dofs = probe_dofs(model, cond.interface_dofs(), vertices)?;
        let zeros = vec![0.0; n];
        let mut unit = vec![0.0; n];
        let mut g = vec![0.0; m];
        let mut rows = Vec::with_capacity(dofs.len() * m);
        for &r in &dofs {
            unit[r] = 1.0;
            cond.condense(&unit, &zeros, &mut g)?;
            unit[r] = 0.0;
            rows.extend_from_slice(&g);
        }
        let mut extension = |b: &[f64], fixed: &[f64]| -> Result<Vec<f64>> {
            cond.condense(b, fixed, &mut g)?;
            let mut x = fixed.to_vec();
            for &dof in cond.interface_dofs() {
                x[dof] = 0.0;
            }
            cond.extend(&mut x)?;
            Ok(dofs.iter().map(|&r| x[r]).collect())
        };
        let c0 = extension(&model.load, &model.initial_displacement)?;
        let c1 = extension(&zeros, velocity_factor)?;
        Ok(Self {
            vertices: vertices.to_vec(),
            dofs,
            rows,
            c0,
            c1,
        })
    }

    /// The probe of `vertices` from rows computed elsewhere (a Schur complement that kept
    /// the probe's dofs, [`rsf_direct::ExtraRows`]): `dofs` those of [`probe_dofs`], `rows`
    /// `P` row-major (`dofs.len() × m`), `c0` and `c1` the extensions of the load with the
    /// initial fixed values and of the unit Dirichlet velocities (module docs).
    pub(crate) fn from_rows(
        vertices: &[usize],
        dofs: Vec<usize>,
        rows: Vec<f64>,
        c0: Vec<f64>,
        c1: Vec<f64>,
    ) -> Self {
        debug_assert!(c0.len() == dofs.len() && c1.len() == dofs.len());
        debug_assert!(dofs.is_empty() || rows.len() % dofs.len() == 0);
        Self {
            vertices: vertices.to_vec(),
            dofs,
            rows,
            c0,
            c1,
        }
    }

    /// The vertices this probe computes (sorted).
    pub(crate) fn vertices(&self) -> &[usize] {
        &self.vertices
    }

    /// Whether this probe computes exactly `vertices`.
    pub(crate) fn watches(&self, vertices: &[usize]) -> bool {
        self.vertices == vertices
    }

    /// Writes the watched dofs of `u` and `v` (length `n`) from the fault's unknowns `u_f`
    /// and rates `v_f` (length `m`), the integrated loading `big_g` and its speed.
    #[expect(
        clippy::too_many_arguments,
        reason = "the fault's unknowns and rates, the loading and its speed in, the watched displacement and velocity out"
    )]
    pub(crate) fn fill(
        &self,
        u_f: &[f64],
        v_f: &[f64],
        big_g: f64,
        speed: f64,
        u: &mut [f64],
        v: &mut [f64],
    ) {
        let m = u_f.len();
        for (i, &dof) in self.dofs.iter().enumerate() {
            let row = &self.rows[i * m..(i + 1) * m];
            let (mut ur, mut vr) = (0.0, 0.0);
            for ((p, a), b) in row.iter().zip(u_f).zip(v_f) {
                ur += p * a;
                vr += p * b;
            }
            u[dof] = self.c0[i] + big_g * self.c1[i] + ur;
            v[dof] = speed * self.c1[i] + vr;
        }
    }
}
