//! The scene's checks: every parameter valid ([`SliderScene::validate`]) and plausible
//! ([`SliderScene::check_plausible`]).

use super::{SliderScene, TimeStep, ALPHA_RANGE};

use rsf_time::VelocityIntegrator;

use crate::invalid;
use rsf::Result;
use rsf_numeric::written;

impl SliderScene {
    /// Checks every parameter, naming the first invalid one.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](rsf::Error::InvalidParameter) or the friction crate's parameter error.
    pub fn validate(&self) -> Result<()> {
        let pos = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(invalid(name, format!("{v} must be finite and > 0")))
            }
        };
        if self.level > 10 {
            return Err(invalid(
                "level",
                format!("{} is beyond what fits in memory (≤ 10)", self.level),
            ));
        }
        if self.steps == 0 {
            return Err(invalid("steps", "must be at least 1"));
        }
        pos("end_time_s", self.end_time_s)?;
        pos("density_kg_per_m2", self.density_kg_per_m2)?;
        pos("youngs_modulus_pa", self.youngs_modulus_pa)?;
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(invalid(
                "poisson_ratio",
                format!("{} must be in (-1, 0.5)", self.poisson_ratio),
            ));
        }
        if !(self.gravity_m_per_s2.is_finite() && self.gravity_m_per_s2 >= 0.0) {
            return Err(invalid(
                "gravity_m_per_s2",
                format!("{} must be finite and >= 0", written(self.gravity_m_per_s2)),
            ));
        }
        if !self.loading_velocity_m_per_s.is_finite() {
            return Err(invalid("loading_velocity_m_per_s", "must be finite"));
        }
        if !(self.ramp_fraction >= 0.0 && self.ramp_fraction <= 1.0) {
            return Err(invalid(
                "ramp_fraction",
                format!("{} must be in [0, 1]", written(self.ramp_fraction)),
            ));
        }
        if !self.alpha0.is_finite() {
            return Err(invalid("alpha0", "must be finite"));
        }
        pos("fixed_point_tolerance", self.fixed_point_tolerance)?;
        pos("solver_tolerance", self.solver_tolerance)?;
        if self.absorbing_sides && !self.integrator.uses_mass() {
            return Err(invalid(
                "absorbing_sides",
                format!(
                    "absorbing ends need an integrator with inertia; `{}` has none (no waves \
                     to absorb)",
                    self.integrator
                ),
            ));
        }
        self.check_plausible()?;
        if self.fixed_point_max_iterations == 0 {
            return Err(invalid("fixed_point_max_iterations", "must be at least 1"));
        }
        self.rate_state_params()
            .validate()
            .map_err(Self::friction_key)?;
        self.step_control()?;
        // The initial step as the scene's fields give it: its integrator coefficients
        // (e.g. 2/τ of Newmark) must be finite.
        let tau = self.initial_tau();
        let (c_m, c_k) = self.integrator.coefficients(tau);
        if !(c_m.is_finite() && c_k.is_finite()) {
            return Err(invalid(
                match self.time_step {
                    TimeStep::Adaptive(_) => "time_step.initial_tau_s",
                    TimeStep::Fixed {} => "steps",
                },
                format!(
                    "the initial step τ = {tau:e} s gives non-finite coefficients of the \
                     time-step matrix c_M M + c_K K (c_M = {c_m:e}, c_K = {c_k:e})"
                ),
            ));
        }
        Ok(())
    }

    /// The physical plausibility checks of [`validate`](Self::validate) (docs/reliability.md,
    /// "What is validated"): values that are finite but meaningless, or whose problem
    /// cannot be solved in double precision, are refused with the admissible range and
    /// the reason. The bounds are wide (every material from foam to diamond, runs up to
    /// centuries); a value outside them is a mistake of units or of a digit.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](rsf::Error::InvalidParameter) naming the field.
    pub fn check_plausible(&self) -> Result<()> {
        let in_range = |name: &str, v: f64, (lo, hi): (f64, f64), reason: &str| {
            if v >= lo && v <= hi {
                Ok(())
            } else {
                Err(invalid(
                    name,
                    format!(
                        "{} is outside the admissible range [{lo:e}, {hi:e}]: {reason}",
                        written(v)
                    ),
                ))
            }
        };
        in_range(
            "mu0",
            self.mu0,
            (0.0, f64::MAX),
            "a negative friction coefficient has no physical meaning (μ₀ ≥ 0)",
        )?;
        if !self.allow_negative_b {
            in_range(
                "b",
                self.b,
                (0.0, f64::MAX),
                "the state effect b of rate-and-state friction is ≥ 0 (b − a < 0 is \
                 velocity strengthening; a negative b has no physical meaning; set \
                 `allow_negative_b = true` to run it deliberately)",
            )?;
        }
        in_range(
            "alpha0",
            self.alpha0,
            ALPHA_RANGE,
            "the initial state θ₀ = exp(α₀) s must be a normal double (it overflows or \
             underflows outside)",
        )?;
        in_range(
            "youngs_modulus_pa",
            self.youngs_modulus_pa,
            (1e3, 1e13),
            "from soft foams (kPa) to beyond diamond (TPa); outside, the displacements \
             (≈ load · length / E) leave the range in which the assembled problem is \
             well-conditioned in double precision",
        )?;
        in_range(
            "density_kg_per_m2",
            self.density_kg_per_m2,
            (1e-3, 1e7),
            "a density outside it makes the mass matrix and the body force differ from the \
             stiffness by more than double precision resolves at the scene's time steps",
        )?;
        in_range(
            "end_time_s",
            self.end_time_s,
            (0.0, 1e10),
            "up to ≈ 300 years: beyond, times and loading displacements v_load · T lose the \
             digits of the steps",
        )?;
        in_range(
            "loading_velocity_m_per_s",
            self.loading_velocity_m_per_s,
            (-1e3, 1e3),
            "beyond 1 km/s either way the quasi-static shear of the scene is meaningless",
        )?;
        let eps = f64::EPSILON;
        for (name, tol) in [
            ("fixed_point_tolerance", self.fixed_point_tolerance),
            ("solver_tolerance", self.solver_tolerance),
        ] {
            if !(tol > eps && tol < 1.0) {
                return Err(invalid(
                    name,
                    format!(
                        "{tol:e} is outside the admissible range ({eps:e}, 1): a relative \
                         tolerance ≥ 1 accepts anything, one ≤ the machine epsilon can never be met"
                    ),
                ));
            }
        }
        Ok(())
    }
}
