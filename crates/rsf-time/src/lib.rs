//! Time integrators for the velocity formulation of rate-and-state friction problems
//! (Pipping, Sander & Kornhuber §3; docs/math.md §2).
//!
//! Every integrator turns the equation of motion `M ü + K u + ∂Φ(u̇) ∋ F` at `t_n` into the
//! **velocity problem** `minimise ½ vᵀAv − ℓ_nᵀv + Φ(v)` with
//! `A = c_M M + c_K K` ([`VelocityIntegrator::coefficients`]) and the right-hand side
//! `ℓ_n` ([`VelocityIntegrator::right_hand_side`]); after the solve, the displacement and
//! acceleration follow from the new velocity ([`VelocityIntegrator::advance`]).
//!
//! | integrator | `A` | order |
//! |---|---|---|
//! | [`Newmark`] (β = ¼, γ = ½), eqs. (3.1)–(3.4) | `(2/τ) M + (τ/2) K` | 2, conserves energy |
//! | [`BackwardEuler`] | `(1/τ) M + τ K` | 1, dissipative |
//! | [`Quasistatic`] (backward Euler, no inertia) | `τ K` (+ radiation damping) | 1 |
//!
//! Units: `u` in m, `v` in m/s, `a` in m/s², `τ` in s; `M` in kg (per unit thickness in
//! 2D), `K` in N/m, loads in N. Vectors are node-major (rsf-fem's convention).
//!
//! ```
//! use rsf_time::{Newmark, VelocityIntegrator};
//! let (c_m, c_k) = Newmark.coefficients(1e-3);
//! assert_eq!((c_m, c_k), (2e3, 5e-4));
//! ```
#![warn(missing_docs)]

pub mod adaptive;
mod choice;
pub mod krylov;
mod load;
pub mod rosenbrock;
pub mod runge_kutta;
pub mod stabilized;
pub mod stepper;
#[cfg(test)]
mod test_systems;

pub use adaptive::{ControllerState, StepControl, TAU_MIN_FLOOR, TOLERANCE_RANGE};
pub use choice::Integrator;
pub use krylov::JacobianBlocks;
pub use load::{LoadOperator, LOAD_PARALLEL_MIN_ROWS};
pub use rosenbrock::{Rosenbrock, RosenbrockOptions, RosenbrockStep};
pub use runge_kutta::{
    EmbeddedRungeKutta, OdeSystem, RungeKuttaOptions, RungeKuttaState, RungeKuttaStep, Tableau,
    BOGACKI_SHAMPINE_32, DORMAND_PRINCE_54,
};
pub use stabilized::{rkc_stages, Rkc2, RkcOptions, RkcState, RkcStep};
pub use stepper::{
    AutoOptions, OdeIntegrator, OdeStep, OdeStepper, StabilizedMemory, StepperMode, StepperStats,
};

use rsf_linalg::SparseMatrix;

/// Errors of the time integrators.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The time step is not finite and positive.
    #[error("time step τ = {0} s must be finite and > 0")]
    InvalidTimeStep(f64),
    /// The integrator needs a mass matrix and none was given.
    #[error("{0} needs the mass matrix")]
    MissingMass(&'static str),
    /// A vector has the wrong length.
    #[error("{what} has length {got}, expected {expected}")]
    DimensionMismatch {
        /// Which vector.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
    /// An adaptive step failed or was rejected at the smallest allowed time step.
    #[error("time step τ = {tau:e} s cannot shrink further (tau_min = {tau_min:e} s)")]
    StepTooSmall {
        /// The step that failed (s).
        tau: f64,
        /// The smallest allowed step (s).
        tau_min: f64,
    },
    /// The rate function of an ODE system refused the stages of an adaptive step as
    /// outside its domain ([`OdeSystem::outside_domain`]) too often, or a refusal would
    /// take the step below its smallest size: no smaller step keeps the trial points
    /// inside (docs/reliability.md, "Trial points outside the domain").
    #[error(
        "the step from t = {time:e} s had {refusals} attempt(s) refused as outside the \
         system's domain, the last with dt = {dt:e} s ({reason}); lower dt_min or raise \
         max_refusals if a smaller step may stay inside, else the model leaves its domain \
         there"
    )]
    #[non_exhaustive]
    TrialPointRefused {
        /// Time of the accepted point the step starts from (s).
        time: f64,
        /// The last step tried (s).
        dt: f64,
        /// Refused attempts of this step.
        refusals: usize,
        /// The last refusal's message (the system's error).
        reason: String,
    },
    /// A linear solve of an implicit step ([`Rosenbrock`]) did not reach its tolerance
    /// within its iterations, and the step cannot shrink further (a smaller step makes
    /// the system easier: this says the problem's Jacobian is beyond the solver at any
    /// step the options allow).
    #[error(
        "the linear solve of an implicit step from t = {time:e} s with dt = {dt:e} s did not \
         converge: residual {residual:e} (in units of the error tolerance) after {iterations} \
         GMRES iterations, and the step cannot shrink below dt_min; raise \
         max_krylov_iterations or lower dt_min"
    )]
    LinearSolveFailed {
        /// Time of the step's start (s).
        time: f64,
        /// The last step tried (s).
        dt: f64,
        /// GMRES iterations of the failed solve.
        iterations: usize,
        /// Its last residual norm (weighted Euclidean, in units of the tolerance).
        residual: f64,
    },
    /// Invalid parameter (e.g. negative radiation damping).
    #[error("invalid parameter {name} = {}: {requirement}", rsf_numeric::written(*value))]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is required.
        requirement: &'static str,
    },
    /// A name that is not one of a choice's names.
    #[error(transparent)]
    UnknownName(#[from] rsf_numeric::UnknownName),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Displacement, velocity and acceleration at one time level (node-major, equal lengths).
#[derive(Debug, Clone, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Kinematics {
    /// Displacement `u` (m).
    pub u: Vec<f64>,
    /// Velocity `v = u̇` (m/s).
    pub v: Vec<f64>,
    /// Acceleration `a = ü` (m/s²); unused (zero) for quasistatic integrators.
    pub a: Vec<f64>,
}

impl Kinematics {
    /// All three fields zero, of length `n`.
    pub fn zeros(n: usize) -> Self {
        Self {
            u: vec![0.0; n],
            v: vec![0.0; n],
            a: vec![0.0; n],
        }
    }

    /// Number of dofs.
    pub fn len(&self) -> usize {
        self.u.len()
    }

    /// Whether there are no dofs.
    pub fn is_empty(&self) -> bool {
        self.u.is_empty()
    }
}

/// Checks `τ`.
///
/// # Errors
/// [`Error::InvalidTimeStep`] unless `τ` is finite and positive.
pub fn check_time_step(tau: f64) -> Result<()> {
    if tau.is_finite() && tau > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidTimeStep(tau))
    }
}

/// A one-step integrator for the velocity (docs/math.md §2). Implementations are stateless
/// descriptions; the state lives in [`Kinematics`].
pub trait VelocityIntegrator: Clone + Send + Sync {
    /// Short name ("newmark", "backward-euler", "quasistatic").
    fn name(&self) -> &'static str;

    /// Whether the mass matrix enters (`c_M ≠ 0`); a quasistatic scene never assembles `M`.
    fn uses_mass(&self) -> bool;

    /// `(c_M, c_K)` with `A = c_M M + c_K K` for the time step `tau` (s).
    fn coefficients(&self, tau: f64) -> (f64, f64);

    /// Radiation damping `η` (Pa·s/m): the scene adds `η/2 · V²` per unit area of the
    /// frictional boundary to the friction potential (i.e. `η w_p` on the tangential
    /// diagonal). Default 0.
    fn radiation_damping(&self) -> f64 {
        0.0
    }

    /// The right-hand side in the form `ℓ_n = F + M w_M − K w_K`: writes `w_M` and `w_K`
    /// (each of length `n`) from the previous state. `w_M` is ignored when
    /// [`uses_mass`](Self::uses_mass) is false. This is what an integrator must describe;
    /// [`LoadOperator`] applies it in one pass over the matrices.
    ///
    /// # Errors
    /// [`Error::InvalidTimeStep`], [`Error::DimensionMismatch`].
    fn load_combinations(
        &self,
        tau: f64,
        prev: &Kinematics,
        w_mass: &mut [f64],
        w_stiffness: &mut [f64],
    ) -> Result<()>;

    /// `ℓ_n` into `out` from the matrices, the load `F(t_n)` and the previous state (a
    /// convenience that allocates two work vectors; time loops use [`LoadOperator`]).
    ///
    /// # Errors
    /// [`Error::InvalidTimeStep`], [`Error::MissingMass`] if `mass` is `None` but
    /// [`uses_mass`](Self::uses_mass), [`Error::DimensionMismatch`].
    fn right_hand_side(
        &self,
        tau: f64,
        matrices: SystemMatrices<'_>,
        load: &[f64],
        prev: &Kinematics,
        out: &mut [f64],
    ) -> Result<()> {
        let SystemMatrices { mass, stiffness } = matrices;
        check_time_step(tau)?;
        let lengths = [
            ("load", load.len()),
            ("u", prev.u.len()),
            ("v", prev.v.len()),
            ("a", prev.a.len()),
            ("output", out.len()),
        ];
        check_lengths(stiffness.nrows(), lengths)?;
        let mass = match (mass, self.uses_mass()) {
            (Some(m), true) => Some(m),
            (None, true) => return Err(Error::MissingMass(self.name())),
            (_, false) => None,
        };
        let op = LoadOperator::new(mass, stiffness)?;
        let n = out.len();
        let (mut wm, mut wk) = (vec![0.0; n], vec![0.0; n]);
        self.load_combinations(tau, prev, &mut wm, &mut wk)?;
        op.apply(load, &wm, &wk, out);
        Ok(())
    }

    /// The new state from the previous one and the new velocity `v_new`
    /// (`next.v = v_new`; `u`, `a` per the scheme). `next` must have the right lengths.
    fn advance(&self, tau: f64, prev: &Kinematics, v_new: &[f64], next: &mut Kinematics);

    /// An estimate of the local truncation error of the displacement of the step from
    /// `prev` to `next` (m, per dof, into `out`), for adaptive time steps
    /// ([`adaptive`]). Default: the first-order estimate `(τ/2)(v_n − v_{n−1})` of
    /// `u_n = u_{n−1} + τ v_n`; [`Newmark`] overrides it.
    fn displacement_error(&self, tau: f64, prev: &Kinematics, next: &Kinematics, out: &mut [f64]) {
        for ((o, vn), vp) in out.iter_mut().zip(&next.v).zip(&prev.v) {
            *o = 0.5 * tau * (vn - vp);
        }
    }
}

/// The matrices of a velocity problem: the mass matrix `M` (if assembled; quasistatic
/// problems have none) and the stiffness matrix `K`, both `n × n`, symmetric, both
/// triangles stored.
#[derive(Debug, Clone, Copy)]
pub struct SystemMatrices<'a> {
    /// `M` (kg, or kg/m per unit thickness in 2D), if any.
    pub mass: Option<&'a SparseMatrix>,
    /// `K` (N/m).
    pub stiffness: &'a SparseMatrix,
}

impl<'a> SystemMatrices<'a> {
    /// `M` (if any) and `K`.
    pub fn new(mass: Option<&'a SparseMatrix>, stiffness: &'a SparseMatrix) -> Self {
        Self { mass, stiffness }
    }
}

/// Checks that the work vectors of [`VelocityIntegrator::load_combinations`] and the
/// state's `v` and `a` have the length of its `u`.
fn check_work(prev: &Kinematics, w_mass: &[f64], w_stiffness: &[f64]) -> Result<()> {
    check_lengths(
        prev.u.len(),
        [
            ("v", prev.v.len()),
            ("a", prev.a.len()),
            ("w_mass", w_mass.len()),
            ("w_stiffness", w_stiffness.len()),
        ],
    )
}

/// Checks that every `(what, length)` of `lengths` is `n`.
///
/// # Errors
/// [`Error::DimensionMismatch`] naming the first that is not.
fn check_lengths<const K: usize>(n: usize, lengths: [(&'static str, usize); K]) -> Result<()> {
    for (what, got) in lengths {
        if got != n {
            return Err(Error::DimensionMismatch {
                what,
                expected: n,
                got,
            });
        }
    }
    Ok(())
}

/// `Err(`[`Error::InvalidParameter`]`)` of `name`, its `value` and what is required.
pub(crate) fn invalid<T>(name: &'static str, value: f64, requirement: &'static str) -> Result<T> {
    Err(Error::InvalidParameter {
        name,
        value,
        requirement,
    })
}

/// Newmark's trapezoidal rule (β = ¼, γ = ½) in velocity form, eqs. (3.1)–(3.4):
/// `a_n = (2/τ)(v_n − v_{n−1}) − a_{n−1}`, `u_n = u_{n−1} + (τ/2)(v_n + v_{n−1})`.
/// Second order; conserves the discrete energy `½vᵀMv + ½uᵀKu` for linear problems.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Newmark;

impl VelocityIntegrator for Newmark {
    fn name(&self) -> &'static str {
        "newmark"
    }
    fn uses_mass(&self) -> bool {
        true
    }
    fn coefficients(&self, tau: f64) -> (f64, f64) {
        (2.0 / tau, 0.5 * tau)
    }
    /// `ℓ_n = F + M((2/τ) v_{n−1} + a_{n−1}) − K(u_{n−1} + (τ/2) v_{n−1})`.
    fn load_combinations(
        &self,
        tau: f64,
        prev: &Kinematics,
        w_mass: &mut [f64],
        w_stiffness: &mut [f64],
    ) -> Result<()> {
        check_time_step(tau)?;
        check_work(prev, w_mass, w_stiffness)?;
        for i in 0..prev.len() {
            w_mass[i] = (2.0 / tau) * prev.v[i] + prev.a[i];
            w_stiffness[i] = prev.u[i] + 0.5 * tau * prev.v[i];
        }
        Ok(())
    }
    fn advance(&self, tau: f64, prev: &Kinematics, v_new: &[f64], next: &mut Kinematics) {
        for i in 0..v_new.len() {
            next.a[i] = (2.0 / tau) * (v_new[i] - prev.v[i]) - prev.a[i];
            next.u[i] = prev.u[i] + 0.5 * tau * (v_new[i] + prev.v[i]);
            next.v[i] = v_new[i];
        }
    }
    /// `(τ²/12)(a_n − a_{n−1})`: the trapezoidal rule's local error `−τ³/12 · ȧ` with
    /// `ȧ ≈ (a_n − a_{n−1})/τ`.
    fn displacement_error(&self, tau: f64, prev: &Kinematics, next: &Kinematics, out: &mut [f64]) {
        let c = tau * tau / 12.0;
        for ((o, an), ap) in out.iter_mut().zip(&next.a).zip(&prev.a) {
            *o = c * (an - ap);
        }
    }
}

/// Backward (implicit) Euler for the velocity: `u_n = u_{n−1} + τ v_n`,
/// `a_n = (v_n − v_{n−1})/τ`. First order, dissipative (paper Fig. 6.4).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BackwardEuler;

impl VelocityIntegrator for BackwardEuler {
    fn name(&self) -> &'static str {
        "backward-euler"
    }
    fn uses_mass(&self) -> bool {
        true
    }
    fn coefficients(&self, tau: f64) -> (f64, f64) {
        (1.0 / tau, tau)
    }
    /// `ℓ_n = F + (1/τ) M v_{n−1} − K u_{n−1}`.
    fn load_combinations(
        &self,
        tau: f64,
        prev: &Kinematics,
        w_mass: &mut [f64],
        w_stiffness: &mut [f64],
    ) -> Result<()> {
        check_time_step(tau)?;
        check_work(prev, w_mass, w_stiffness)?;
        for i in 0..prev.len() {
            w_mass[i] = prev.v[i] / tau;
            w_stiffness[i] = prev.u[i];
        }
        Ok(())
    }
    fn advance(&self, tau: f64, prev: &Kinematics, v_new: &[f64], next: &mut Kinematics) {
        for i in 0..v_new.len() {
            next.a[i] = (v_new[i] - prev.v[i]) / tau;
            next.u[i] = prev.u[i] + tau * v_new[i];
            next.v[i] = v_new[i];
        }
    }
}

/// Quasistatic backward Euler: inertia dropped (`K u_n + ∂Φ(v_n) ∋ F`,
/// `u_n = u_{n−1} + τ v_n`), optionally with radiation damping `η/2 · V²` per unit area of
/// the frictional boundary (the quasi-dynamic approximation). `A = τ K`; never touches `M`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Quasistatic {
    eta: f64,
}

impl Quasistatic {
    /// Without radiation damping.
    pub const fn new() -> Self {
        Self { eta: 0.0 }
    }

    /// With radiation damping `η` (Pa·s/m), e.g. `η = G/(2 c_s)`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] unless `η` is finite and `≥ 0`.
    pub fn with_radiation_damping(eta: f64) -> Result<Self> {
        if eta.is_finite() && eta >= 0.0 {
            Ok(Self { eta })
        } else {
            invalid("radiation damping eta", eta, "finite and >= 0 (Pa s/m)")
        }
    }
}

impl VelocityIntegrator for Quasistatic {
    fn name(&self) -> &'static str {
        "quasistatic"
    }
    fn uses_mass(&self) -> bool {
        false
    }
    fn coefficients(&self, tau: f64) -> (f64, f64) {
        (0.0, tau)
    }
    fn radiation_damping(&self) -> f64 {
        self.eta
    }
    /// `ℓ_n = F − K u_{n−1}`.
    fn load_combinations(
        &self,
        tau: f64,
        prev: &Kinematics,
        w_mass: &mut [f64],
        w_stiffness: &mut [f64],
    ) -> Result<()> {
        check_time_step(tau)?;
        check_work(prev, w_mass, w_stiffness)?;
        w_mass.fill(0.0);
        w_stiffness.copy_from_slice(&prev.u);
        Ok(())
    }
    fn advance(&self, tau: f64, prev: &Kinematics, v_new: &[f64], next: &mut Kinematics) {
        for i in 0..v_new.len() {
            next.a[i] = 0.0;
            next.u[i] = prev.u[i] + tau * v_new[i];
            next.v[i] = v_new[i];
        }
    }
}
