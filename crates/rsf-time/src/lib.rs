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
pub mod rosenbrock;
pub mod runge_kutta;
pub mod stabilized;
pub mod stepper;
#[cfg(test)]
mod test_systems;

pub use adaptive::{ControllerState, StepControl, TAU_MIN_FLOOR, TOLERANCE_RANGE};
pub use choice::Integrator;
pub use krylov::JacobianBlocks;
pub use rosenbrock::{Rosenbrock, RosenbrockOptions, RosenbrockStep};
pub use runge_kutta::{
    EmbeddedRungeKutta, OdeSystem, RungeKuttaOptions, RungeKuttaState, RungeKuttaStep, Tableau,
    BOGACKI_SHAMPINE_32, DORMAND_PRINCE_54,
};
pub use stabilized::{rkc_stages, Rkc2, RkcOptions, RkcState, RkcStep};
pub use stepper::{
    AutoOptions, OdeIntegrator, OdeStep, OdeStepper, StabilizedMemory, StepperMode, StepperStats,
};

use rsf_linalg::Parallelism;
use rsf_linalg::SparseMatrix;

/// Fewest rows for which [`LoadOperator::apply`] splits its rows in two halves on two
/// threads (if its [`Parallelism`] allows): below, waking the second thread costs more
/// than the half pass it takes over (the main job at j = 4, 2754 rows, ran 2.5 % slower
/// on two threads than on one).
pub const LOAD_PARALLEL_MIN_ROWS: usize = 5000;

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
        check_lengths(stiffness.nrows(), load, prev, out)?;
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

fn check_work(prev: &Kinematics, w_mass: &[f64], w_stiffness: &[f64]) -> Result<()> {
    let n = prev.u.len();
    for (what, got) in [
        ("v", prev.v.len()),
        ("a", prev.a.len()),
        ("w_mass", w_mass.len()),
        ("w_stiffness", w_stiffness.len()),
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
