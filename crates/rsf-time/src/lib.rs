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

use rsf_fem::{spmv_add, SparseMatrix};

/// Errors of the time integrators.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
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
    /// Invalid parameter (e.g. negative radiation damping).
    #[error("invalid parameter {name} = {value}: {requirement}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is required.
        requirement: &'static str,
    },
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Displacement, velocity and acceleration at one time level (node-major, equal lengths).
#[derive(Debug, Clone, PartialEq, Default)]
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

    /// `ℓ_n` into `out` from the load `F(t_n)` and the previous state.
    ///
    /// # Errors
    /// [`Error::InvalidTimeStep`], [`Error::MissingMass`] if `mass` is `None` but
    /// [`uses_mass`](Self::uses_mass), [`Error::DimensionMismatch`].
    fn right_hand_side(
        &self,
        tau: f64,
        mass: Option<&SparseMatrix>,
        stiffness: &SparseMatrix,
        load: &[f64],
        prev: &Kinematics,
        out: &mut [f64],
    ) -> Result<()>;

    /// The new state from the previous one and the new velocity `v_new`
    /// (`next.v = v_new`; `u`, `a` per the scheme). `next` must have the right lengths.
    fn advance(&self, tau: f64, prev: &Kinematics, v_new: &[f64], next: &mut Kinematics);
}

/// `out_j ← out_j + s Σ_i A_ij (x_i + β y_i)` for a **symmetric** CSC matrix `A` (column
/// `j` read as row `j`): one pass over `A` for a linear combination of two vectors, without
/// a temporary.
fn sym_spmv_add_combination(
    a: &SparseMatrix,
    s: f64,
    x: &[f64],
    beta: f64,
    y: &[f64],
    out: &mut [f64],
) {
    for (j, oj) in out.iter_mut().enumerate() {
        let mut acc = 0.0;
        for (&i, &v) in a.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
            acc += v * (x[i] + beta * y[i]);
        }
        *oj += s * acc;
    }
}

fn check_lengths(n: usize, load: &[f64], prev: &Kinematics, out: &[f64]) -> Result<()> {
    for (what, got) in [
        ("load", load.len()),
        ("u", prev.u.len()),
        ("v", prev.v.len()),
        ("a", prev.a.len()),
        ("output", out.len()),
    ] {
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
    fn right_hand_side(
        &self,
        tau: f64,
        mass: Option<&SparseMatrix>,
        stiffness: &SparseMatrix,
        load: &[f64],
        prev: &Kinematics,
        out: &mut [f64],
    ) -> Result<()> {
        check_time_step(tau)?;
        let m = mass.ok_or(Error::MissingMass("Newmark"))?;
        check_lengths(stiffness.nrows(), load, prev, out)?;
        out.copy_from_slice(load);
        sym_spmv_add_combination(stiffness, -1.0, &prev.u, 0.5 * tau, &prev.v, out);
        sym_spmv_add_combination(m, 1.0, &prev.a, 2.0 / tau, &prev.v, out);
        Ok(())
    }
    fn advance(&self, tau: f64, prev: &Kinematics, v_new: &[f64], next: &mut Kinematics) {
        for i in 0..v_new.len() {
            next.a[i] = (2.0 / tau) * (v_new[i] - prev.v[i]) - prev.a[i];
            next.u[i] = prev.u[i] + 0.5 * tau * (v_new[i] + prev.v[i]);
            next.v[i] = v_new[i];
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
    fn right_hand_side(
        &self,
        tau: f64,
        mass: Option<&SparseMatrix>,
        stiffness: &SparseMatrix,
        load: &[f64],
        prev: &Kinematics,
        out: &mut [f64],
    ) -> Result<()> {
        check_time_step(tau)?;
        let m = mass.ok_or(Error::MissingMass("backward Euler"))?;
        check_lengths(stiffness.nrows(), load, prev, out)?;
        out.copy_from_slice(load);
        spmv_add(stiffness.as_ref(), -1.0, &prev.u, out);
        spmv_add(m.as_ref(), 1.0 / tau, &prev.v, out);
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
    pub fn new() -> Self {
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
            Err(Error::InvalidParameter {
                name: "radiation damping eta",
                value: eta,
                requirement: "finite and >= 0 (Pa s/m)",
            })
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
    fn right_hand_side(
        &self,
        tau: f64,
        _mass: Option<&SparseMatrix>,
        stiffness: &SparseMatrix,
        load: &[f64],
        prev: &Kinematics,
        out: &mut [f64],
    ) -> Result<()> {
        check_time_step(tau)?;
        check_lengths(stiffness.nrows(), load, prev, out)?;
        out.copy_from_slice(load);
        spmv_add(stiffness.as_ref(), -1.0, &prev.u, out);
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
