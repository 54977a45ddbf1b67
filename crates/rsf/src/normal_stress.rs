//! Normal stress that changes with slip on a fault inside the body (docs/faults-inside.md
//! "Normal stress", docs/math.md §15): the slip → normal-traction operator of the
//! condensed problem and the friction laws scaled by the current normal stress.

use faer::Mat;
use rsf_direct::Condensation;
use rsf_friction::FrictionLaw;
use rsf_linalg::Parallelism;
use rsf_numeric::normal_component;

use crate::error::{invalid, Error, Result};
use crate::fault_kernel::{compress, Kernel};
use crate::fault_operator::{FaultKernel, KernelReport};
use crate::model::Model;
use crate::observe::FaultTractions;

/// How a fault's normal stress `σ̄_n` (Pa, compressive positive) is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum NormalStress {
    /// The laws' own `σ̄_n` ([`FrictionLaw::normal_stress`]), fixed in time: the paper's
    /// model and every boundary fault (the default).
    #[default]
    Fixed,
    /// On a fault inside the body (vector field): `σ̄_n = σ̄_n⁰ + Δσ_n`, `σ̄_n⁰` the laws'
    /// and `Δσ_n` the change of the normal traction since `t = 0` that the slip and the
    /// loading cause (the reaction that keeps the fault closed). The friction of node `k`
    /// is its law's potential scaled by `σ̄_n,k/σ̄_n⁰,k`: the law must be proportional to
    /// its normal stress ([`FrictionLaw::proportional_to_normal_stress`]).
    FromSlip,
}

/// The laws' normal stresses `σ̄_n⁰` for a normal stress from slip (`None` for
/// [`NormalStress::Fixed`]).
///
/// # Errors
/// [`Error::InvalidParameter`] named `normal_stress` without an internal fault, for a
/// scalar field, or for a law without a positive normal stress it is proportional to.
fn initial_normal_stress<const D: usize, const C: usize, L: FrictionLaw>(
    choice: NormalStress,
    model: &Model<D, C>,
    laws: &[L],
) -> Result<Option<Vec<f64>>> {
    if choice == NormalStress::Fixed {
        return Ok(None);
    }
    if model.internal_fault.is_none() || C != D || C == 1 {
        return Err(invalid(
            "normal_stress",
            "NormalStress::FromSlip needs a fault inside the body of a vector (plane \
             strain or 3-D) model (ModelBuilder::internal_fault, \
             internal_fault_polygon): a boundary fault's normal stress is prescribed, \
             an antiplane model has none",
        ));
    }
    laws.iter()
        .enumerate()
        .map(|(k, law)| match law.normal_stress() {
            Some(s) if law.proportional_to_normal_stress() && s > 0.0 && s.is_finite() => Ok(s),
            _ => Err(invalid(
                "normal_stress",
                format!(
                    "the law of frictional node {k} has no positive normal stress it is \
                     proportional to (FrictionLaw::normal_stress, \
                     FrictionLaw::proportional_to_normal_stress)"
                ),
            )),
        })
        .collect::<Result<Vec<f64>>>()
        .map(Some)
}

/// The normal stress of every frictional node as an affine function of the condensed
/// unknowns `u_F` and the integrated loading `G(t)`:
/// `σ̄_n,k = σ̄_n⁰,k − (G(t) a_k + (S_N (u_F − u_F⁰))_k)/w_k`, where `S_N` (`nodes × m`)
/// maps the condensed unknowns to the reactions at the tied normal jumps and `a` is the
/// reaction of a unit loading with the condensed unknowns held.
pub(crate) struct NormalCoupling {
    /// `S_N`, dense or compressed ([`compress`](Self::compress)).
    s_n: Kernel,
    /// `u_F − u_F⁰` (scratch for the compressed product).
    du: Vec<f64>,
    loading: Vec<f64>,
    u_f0: Vec<f64>,
    g0: f64,
    sigma0: Vec<f64>,
    weights: Vec<f64>,
}

impl NormalCoupling {
    /// The coupling of `model`'s internal fault (`C = D` = 2 or 3) condensed by `cond` onto the
    /// frictional nodes' free components, with the laws' `σ̄_n⁰`; `None` for
    /// [`NormalStress::Fixed`].
    ///
    /// `velocity_factor`: the Dirichlet velocity factors (length `n`); `big_g0` = `G(0)`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] named `normal_stress` without an internal fault, for a
    /// scalar field, or for a law without a normal stress or not proportional to it;
    /// condensation errors.
    pub(crate) fn new<const D: usize, const C: usize, L: FrictionLaw>(
        choice: NormalStress,
        model: &Model<D, C>,
        cond: &mut Condensation<C>,
        laws: &[L],
        velocity_factor: &[f64],
        big_g0: f64,
    ) -> Result<Option<Self>> {
        let Some(sigma0) = initial_normal_stress(choice, model, laws)? else {
            return Ok(None);
        };
        let fb = &model.frictional_boundary;
        let n = model.num_dofs();
        let m = cond.dim();
        // The reaction at node k's tied normal jump of a field `x` is row k of `rows` applied
        // to `x`: (K x)_N, column N of the symmetric K (no load: the load's part is constant
        // and drops out of the change).
        let k = model.stiffness.as_ref();
        let rows: Vec<Vec<(usize, f64)>> = fb
            .nodes
            .iter()
            .map(|&p| {
                let dof = C * p + normal_component(C);
                k.row_idx_of_col(dof)
                    .zip(k.val_of_col(dof))
                    .map(|(i, &v)| (i, v))
                    .collect()
            })
            .collect();
        // S_N's columns: the reactions of the harmonic extensions of the unit interface
        // vectors, many extensions per sweep over the factor.
        let s_n = cond.extension_functionals(&rows)?;
        let zeros = vec![0.0; n];
        let mut g = vec![0.0; m];
        let mut x = vec![0.0; n];
        // A unit of integrated loading with the condensed unknowns held at 0.
        cond.condense(&zeros, velocity_factor, &mut g)?;
        x.copy_from_slice(velocity_factor);
        for &dof in cond.interface_dofs() {
            x[dof] = 0.0;
        }
        cond.extend(&mut x)?;
        let loading = rows
            .iter()
            .map(|row| row.iter().map(|&(i, v)| v * x[i]).sum())
            .collect();
        let u_f0 = cond
            .interface_dofs()
            .iter()
            .map(|&dof| model.initial_displacement[dof])
            .collect();
        Ok(Some(Self {
            s_n: Kernel::Dense(s_n),
            du: vec![0.0; m],
            loading,
            u_f0,
            g0: big_g0,
            sigma0,
            weights: fb.weights.clone(),
        }))
    }

    /// `S_N` as the fault ODE's `kind` of kernel (its points: the condensed unknowns'
    /// nodes, which are the rows' too where every frictional node has one free component,
    /// as on a 2-D fault inside the body with its normal tied): the report of the
    /// compression, `None` where `S_N` stays dense (a dense `kind`, or rows and columns on
    /// different points).
    ///
    /// # Errors
    /// The compression's errors.
    pub(crate) fn compress<const D: usize, const C: usize>(
        &mut self,
        model: &Model<D, C>,
        cond: &Condensation<C>,
        kind: FaultKernel,
    ) -> Result<Option<KernelReport>> {
        let fb = &model.frictional_boundary;
        let same_points = cond.interface_dofs().len() == fb.len()
            && cond
                .interface_dofs()
                .iter()
                .zip(&fb.nodes)
                .all(|(&dof, &p)| dof / C == p);
        if matches!(kind, FaultKernel::Dense) || !same_points {
            return Ok(None);
        }
        let Kernel::Dense(dense) =
            std::mem::replace(&mut self.s_n, Kernel::Dense(Mat::zeros(0, 0)))
        else {
            return Ok(None);
        };
        let (kernel, report) = compress(dense, model, cond, kind)?;
        self.s_n = kernel;
        Ok(Some(report))
    }

    /// The laws' normal stresses `σ̄_n⁰` (Pa).
    pub(crate) fn initial(&self) -> &[f64] {
        &self.sigma0
    }

    /// Writes `σ̄_n,k` (Pa) at integrated loading `big_g` and condensed unknowns `u_f`
    /// (length `m`) into `sigma` (one per frictional node).
    ///
    /// # Errors
    /// [`Error::NormalStressNotPositive`] where the slip would open the fault
    /// (`σ̄_n ≤ 0`) or the value is not finite.
    pub(crate) fn evaluate(
        &mut self,
        time: f64,
        big_g: f64,
        u_f: &[f64],
        sigma: &mut [f64],
        par: Parallelism,
    ) -> Result<()> {
        let dg = big_g - self.g0;
        // The reactions r = dg a + S_N (u_F − u_F⁰) accumulated in `sigma`.
        for (s, a) in sigma.iter_mut().zip(&self.loading) {
            *s = dg * a;
        }
        match &mut self.s_n {
            // Column by column (contiguous in S_N; each node's sum in the order of the
            // columns).
            Kernel::Dense(s_n) => {
                for (i, (u, u0)) in u_f.iter().zip(&self.u_f0).enumerate() {
                    let du = u - u0;
                    for (s, c) in sigma.iter_mut().zip(s_n.col(i).iter()) {
                        *s += c * du;
                    }
                }
            }
            Kernel::Hierarchical(h) => {
                for ((d, u), u0) in self.du.iter_mut().zip(u_f).zip(&self.u_f0) {
                    *d = u - u0;
                }
                match h.apply_add(&self.du, sigma, 1.0, par.faer()) {
                    // A trial stage that blew up: NaN, refused below as for dense.
                    Err(rsf_hmatrix::Error::NonFiniteInput(_)) => sigma.fill(f64::NAN),
                    other => other.map_err(Error::from)?,
                }
            }
        }
        for (k, s) in sigma.iter_mut().enumerate() {
            let r = *s;
            *s = self.sigma0[k] - r / self.weights[k];
            if !(*s > 0.0 && s.is_finite()) {
                return Err(Error::NormalStressNotPositive {
                    node: k,
                    time,
                    sigma_n: *s,
                });
            }
        }
        Ok(())
    }
}

/// The tractions observers see with a changing normal stress: each law's scaled by
/// `σ̄_n/σ̄_n⁰` at the last accepted step.
#[derive(Debug, Clone)]
pub(crate) struct ScaledTractions<L> {
    pub(crate) laws: Vec<L>,
    pub(crate) sigma0: Vec<f64>,
    pub(crate) sigma: Vec<f64>,
}

impl<L: FrictionLaw> FaultTractions for ScaledTractions<L> {
    fn shear_traction(&self, k: usize, slip_rate: f64, alpha: f64) -> f64 {
        use rsf_friction::ConvexPotential;
        self.sigma[k] / self.sigma0[k] * self.laws[k].potential(alpha).slope(slip_rate)
    }
    fn normal_traction(&self, k: usize) -> Option<f64> {
        Some(self.sigma[k])
    }
}

/// The normal stress of the implicit scheme, from the whole field of an iterate:
/// `σ̄_n,k = σ̄_n⁰,k − (r_N,k − r_N,k(0))/w_k` with the reactions
/// `r_N = (M a + K u − F)_N` at the tied normal jumps (dashpots of absorbing parts are
/// not included: they act on the outer boundary, not on the fault's split nodes).
#[derive(Debug, Clone)]
pub(crate) struct NormalReactions {
    dofs: Vec<usize>,
    r0: Vec<f64>,
    sigma0: Vec<f64>,
    weights: Vec<f64>,
}

impl NormalReactions {
    /// The reactions of `model` with its `laws`, relative to the `initial` kinematics;
    /// `None` for [`NormalStress::Fixed`].
    ///
    /// # Errors
    /// As [`NormalCoupling::new`]'s checks.
    pub(crate) fn new<const D: usize, const C: usize, L: FrictionLaw>(
        choice: NormalStress,
        model: &Model<D, C>,
        laws: &[L],
        initial: &rsf_time::Kinematics,
    ) -> Result<Option<Self>> {
        let Some(sigma0) = initial_normal_stress(choice, model, laws)? else {
            return Ok(None);
        };
        let fb = &model.frictional_boundary;
        let mut this = Self {
            dofs: fb
                .nodes
                .iter()
                .map(|&p| C * p + normal_component(C))
                .collect(),
            r0: vec![0.0; fb.len()],
            sigma0,
            weights: fb.weights.clone(),
        };
        let mut r0 = vec![0.0; fb.len()];
        this.reactions(model, initial, &mut r0);
        this.r0 = r0;
        Ok(Some(this))
    }

    /// The laws' normal stresses `σ̄_n⁰` (Pa).
    pub(crate) fn initial(&self) -> &[f64] {
        &self.sigma0
    }

    fn reactions<const D: usize, const C: usize>(
        &self,
        model: &Model<D, C>,
        kin: &rsf_time::Kinematics,
        out: &mut [f64],
    ) {
        let row = |a: &crate::fem::SparseMatrix, x: &[f64], dof: usize| -> f64 {
            a.row_idx_of_col(dof)
                .zip(a.val_of_col(dof))
                .map(|(i, v)| v * x[i])
                .sum()
        };
        for (o, &dof) in out.iter_mut().zip(&self.dofs) {
            let mut r = row(&model.stiffness, &kin.u, dof) - model.load[dof];
            if let Some(m) = &model.mass {
                r += row(m, &kin.a, dof);
            }
            *o = r;
        }
    }

    /// Writes `σ̄_n,k` (Pa) of the kinematics `kin` at `time` into `sigma` and the scaled
    /// weights `w_k σ̄_n,k/σ̄_n⁰,k` into `weights`.
    ///
    /// # Errors
    /// [`Error::NormalStressNotPositive`] where `σ̄_n ≤ 0` or not finite.
    pub(crate) fn evaluate<const D: usize, const C: usize>(
        &self,
        model: &Model<D, C>,
        kin: &rsf_time::Kinematics,
        time: f64,
        sigma: &mut [f64],
        weights: &mut [f64],
    ) -> Result<()> {
        self.reactions(model, kin, sigma);
        for (k, s) in sigma.iter_mut().enumerate() {
            *s = self.sigma0[k] - (*s - self.r0[k]) / self.weights[k];
            if !(*s > 0.0 && s.is_finite()) {
                return Err(Error::NormalStressNotPositive {
                    node: k,
                    time,
                    sigma_n: *s,
                });
            }
            weights[k] = self.weights[k] * (*s / self.sigma0[k]);
        }
        Ok(())
    }
}
