//! The paper's model problem (§6.1, Table 6.1; docs/math.md §6) as a scene: a 5 m × 1 m
//! elastic block sheared over a rigid surface, as TOML-readable parameters.

use serde::{Deserialize, Serialize};

use rsf_fem::Diagonal;
use rsf_friction::{DieterichRuina, RateStateParams};
use rsf_state::{BuiltinStateLaw, StateLawKind};
use rsf_time::{Integrator, StepControl};
use rsf_tnnmg::SmootherOrder;

use crate::invalid;
use rsf::checkpoint::{Fingerprint, CHECKPOINT_FORMAT};
use rsf::method::StateIntegrator;
use rsf::method::{FixedPointScheme, InnerSolves};
use rsf::Material;
use rsf::Result;
use rsf::Simulation;
use rsf::SimulationBuilder;
use rsf::SolverKind;
use rsf::TimeFunction;

pub(crate) mod build;
mod checks;
mod number;

use number::short_number;

/// The simulation a scene builds: Dieterich–Ruina friction, a built-in state law and a
/// built-in integrator, both chosen at run time.
pub type SceneSimulation<const D: usize> =
    Simulation<D, DieterichRuina, BuiltinStateLaw, Integrator>;

/// The builder of a [`SceneSimulation`].
pub type SceneSimulationBuilder<const D: usize> =
    SimulationBuilder<D, DieterichRuina, BuiltinStateLaw, Integrator>;

/// How a scene steps in time (`time_step` in TOML). The fixed step τ = T/N is the default
/// (the paper's figures); `{ kind = "adaptive", tolerance = … }` selects adaptive steps
/// with error control (docs/math.md §9).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum TimeStep {
    /// Fixed τ = `end_time_s / steps` (a struct variant so that fields given with it are
    /// rejected).
    Fixed {},
    /// Adaptive steps starting from τ = `end_time_s / steps` (or `initial_tau_s`).
    Adaptive(AdaptiveTimeStep),
}

impl Default for TimeStep {
    fn default() -> Self {
        Self::Fixed {}
    }
}

/// Options of adaptive time steps in a scene (the fields of [`StepControl`] with defaults
/// suited to the slider; only `tolerance` is required in TOML).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptiveTimeStep {
    /// Relative tolerance ([`StepControl::tolerance`]): on the displacement `u − u₀` and,
    /// as an absolute one, on the state α = ln θ.
    pub tolerance: f64,
    /// Initial (and reference) step τ_ref of the ladder τ_ref·2^k (s); default
    /// `end_time_s / steps`; clamped to `[tau_min_s, tau_max_s]`.
    /// (`initial_step_s`, its name before issue 22, is accepted in scene files.)
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        alias = "initial_step_s"
    )]
    pub initial_tau_s: Option<f64>,
    /// Smallest step (s).
    #[serde(default = "defaults::tau_min")]
    pub tau_min_s: f64,
    /// Largest step (s).
    #[serde(default = "defaults::tau_max")]
    pub tau_max_s: f64,
    /// Displacement scale (m): the absolute displacement tolerance is `tolerance` times
    /// this; default the characteristic slip distance `l_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub displacement_scale_m: Option<f64>,
    /// State scale θ_s (s): the absolute tolerance on the state θ is `tolerance` times this
    /// ([`StepControl::state_atol`]), so the state test is `|δθ| ≤ tolerance · (θ + θ_s)`;
    /// default `l_m / |loading_velocity_m_per_s|`, the state of steady sliding at the
    /// loading rate (0 without loading; docs/math.md §9); `0` for a purely relative test.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub state_scale_s: Option<f64>,
    /// Safety factor of the step proposal, (0, 1].
    #[serde(default = "defaults::safety")]
    pub safety: f64,
    /// Smallest factor by which a step shrinks, (0, 1).
    #[serde(default = "defaults::min_factor")]
    pub min_factor: f64,
    /// Largest factor by which a step grows, > 1.
    #[serde(default = "defaults::max_factor")]
    pub max_factor: f64,
    /// ξ of the physical cap (the state changes by at most ξ per step); `inf` for none.
    #[serde(default = "defaults::state_change_cap")]
    pub state_change_cap: f64,
    /// Slip-rate floor V_f (m/s) of the slip test (the relative error of each step's slip
    /// at each fault node, `(Δ ln(V + V_f))²/12 ≤ tolerance`); `inf` switches it off.
    #[serde(default = "defaults::slip_rate_floor")]
    pub slip_rate_floor_mps: f64,
    /// Local extrapolation of the state (docs/math.md §9).
    #[serde(default = "defaults::state_extrapolation")]
    pub state_extrapolation: bool,
}

mod defaults {
    pub fn tau_min() -> f64 {
        1e-9
    }
    pub fn tau_max() -> f64 {
        0.1
    }
    pub fn safety() -> f64 {
        0.9
    }
    pub fn min_factor() -> f64 {
        0.2
    }
    pub fn max_factor() -> f64 {
        2.0
    }
    pub fn state_change_cap() -> f64 {
        0.5
    }
    pub fn slip_rate_floor() -> f64 {
        1e-9
    }
    pub fn state_extrapolation() -> bool {
        true
    }
}

impl AdaptiveTimeStep {
    /// Tolerance `tolerance`, every other option at its default (τ in [1e-9, 0.1] s,
    /// displacement scale `l_m`, state scale `l_m / loading_velocity_m_per_s`, safety 0.9,
    /// factors [0.2, 2], ξ = 0.5, slip-rate floor 1e-9 m/s, local extrapolation of the
    /// state).
    pub fn new(tolerance: f64) -> Self {
        Self {
            tolerance,
            initial_tau_s: None,
            tau_min_s: defaults::tau_min(),
            tau_max_s: defaults::tau_max(),
            displacement_scale_m: None,
            state_scale_s: None,
            safety: defaults::safety(),
            min_factor: defaults::min_factor(),
            max_factor: defaults::max_factor(),
            state_change_cap: defaults::state_change_cap(),
            slip_rate_floor_mps: defaults::slip_rate_floor(),
            state_extrapolation: defaults::state_extrapolation(),
        }
    }
}

/// The paper's slider scene (Table 6.1). Every field has a default (the paper's value);
/// a TOML scene file may set any subset. Unknown fields are rejected with their name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct SliderScene {
    /// Uniform refinement level j of the 2 × 6-vertex coarse grid, in [0, 10] (paper:
    /// 2…8; 4 for the time series; beyond 10, the mesh does not fit in memory).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().level, value_name = "J"))]
    pub level: usize,
    /// Number of time steps N (τ = T/N); with adaptive steps, τ = T/N is the initial step.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().steps, value_parser = crate::run_config::step_count, value_name = "N"))]
    pub steps: usize,
    /// Fixed (default) or adaptive time steps.
    #[cfg_attr(feature = "clap", arg(long, default_value = "{ kind = \"fixed\" }", value_parser = crate::run_config::toml_setting::<TimeStep>, value_name = "TABLE"))]
    pub time_step: TimeStep,
    /// Final time T (s): positive, at most 1e10 (beyond, the time loses the digits of the
    /// steps); the step T/N must give finite coefficients of the step's matrix.
    #[cfg_attr(feature = "clap", arg(long, visible_alias = "end-time", default_value_t = SliderScene::default().end_time_s, value_name = "T"))]
    pub end_time_s: f64,
    /// Density ρ (kg/m², per unit thickness), in [1e-3, 1e7].
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().density_kg_per_m2))]
    pub density_kg_per_m2: f64,
    /// Young's modulus E (Pa = N/m² ; the paper's N/m per unit thickness), in [1e3, 1e13].
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().youngs_modulus_pa))]
    pub youngs_modulus_pa: f64,
    /// Poisson ratio ν (plane strain), in (-1, 0.5).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().poisson_ratio))]
    pub poisson_ratio: f64,
    /// Gravitational acceleration g (m/s² = N/kg), in [0, inf); body force (0, −ρ g).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().gravity_m_per_s2))]
    pub gravity_m_per_s2: f64,
    /// Prescribed normal stress σ̄_n on Γ_F (Pa), in (0, inf).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().sigma_n_pa))]
    pub sigma_n_pa: f64,
    /// Reference friction coefficient μ0, in [0, inf).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().mu0))]
    pub mu0: f64,
    /// Direct-effect parameter a, in (0, inf).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().a))]
    pub a: f64,
    /// Evolution-effect parameter b, in [0, inf) (any finite value with
    /// `allow_negative_b`).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().b))]
    pub b: f64,
    /// Accept a negative `b` (`allow_negative_b = true` in TOML; default `false`). A
    /// negative evolution effect has no physical meaning in rate-and-state friction, and
    /// `b < 0` is much more often a sign error than a deliberate study, so it is refused
    /// unless asked for. Written (and so part of the checkpoint fingerprint,
    /// [`fingerprint`](Self::fingerprint)) only when `true`: scenes and checkpoints of
    /// earlier versions, without the field, keep their fingerprint.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    #[cfg_attr(feature = "clap", arg(long))]
    pub allow_negative_b: bool,
    /// Reference slip rate V0 (m/s), in (0, inf).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().v0_m_per_s))]
    pub v0_m_per_s: f64,
    /// Characteristic slip distance L (m), in (0, inf).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().l_m))]
    pub l_m: f64,
    /// Loading velocity of Γ_D after the ramp (m/s), in [-1000, 1000].
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().loading_velocity_m_per_s))]
    pub loading_velocity_m_per_s: f64,
    /// Ramp duration as a fraction of T, in [0, 1] (paper: ¼).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().ramp_fraction))]
    pub ramp_fraction: f64,
    /// Initial state α_0 = ln θ_0 (θ in s) on Γ_F, in [-708, 709] (θ₀ a normal double).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().alpha0))]
    pub alpha0: f64,
    /// State law (`aging` or `slip`; the aliases `dieterich` and `ruina` are accepted).
    #[cfg_attr(feature = "clap", arg(long, visible_alias = "law", value_enum, default_value_t = SliderScene::default().state_law))]
    pub state_law: StateLawKind,
    /// How a step advances the state: `"backward-euler"` (default, the paper's) or
    /// `"constant-slip-rate"` ([`StateIntegrator`]).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SliderScene::default().state_integrator))]
    pub state_integrator: StateIntegrator,
    /// Velocity integrator.
    #[cfg_attr(feature = "clap", arg(long, default_value = "newmark", value_parser = crate::run_config::toml_setting::<Integrator>, value_name = "INTEGRATOR"))]
    pub integrator: Integrator,
    /// Velocity solver.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SliderScene::default().solver))]
    pub solver: SolverKind,
    /// Fixed point scheme.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SliderScene::default().fixed_point))]
    pub fixed_point: FixedPointScheme,
    /// Fixed point tolerance (energy norm, paper 1e-10), in (2.220446049250313e-16, 1).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().fixed_point_tolerance))]
    pub fixed_point_tolerance: f64,
    /// Fixed point iteration budget per step (at least 1).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().fixed_point_max_iterations))]
    pub fixed_point_max_iterations: usize,
    /// How accurately each fixed point iteration's velocity problem is solved
    /// ([`InnerSolves`]; default `"exact"`, the paper's; the 3-D slider's default is
    /// `"by-solver"`). Written only when not `"exact"`: scenes and checkpoints without the
    /// field keep their fingerprint.
    #[serde(default, skip_serializing_if = "InnerSolves::is_exact")]
    #[cfg_attr(feature = "clap", arg(long, default_value = "exact", value_parser = crate::run_config::toml_setting::<InnerSolves>, value_name = "RULE"))]
    pub fixed_point_inner_solves: InnerSolves,
    /// The node order of TNNMG's smoothers ([`SmootherOrder`]: `"lexicographic"`,
    /// `"multicolour"` or `"red-black-chunks"`; the other solvers ignore it). Default
    /// `"lexicographic"` (sequential; the paper's figures and every 2-D trajectory); the 3-D
    /// slider's default is `"red-black-chunks"` (the sweeps on
    /// [`SolverOptions::parallelism`](rsf::method::SolverOptions::parallelism)'s threads, bit-identical for every thread count,
    /// other round-off than lexicographic; docs/scaling.md). Written only when not
    /// `"lexicographic"`: scenes and checkpoints without the field keep their fingerprint.
    #[serde(default, skip_serializing_if = "is_lexicographic")]
    #[cfg_attr(feature = "clap", arg(long, visible_alias = "smoother", default_value_t = SliderScene::default().tnnmg_smoother, value_name = "ORDER"))]
    pub tnnmg_smoother: SmootherOrder,
    /// Velocity solver tolerance (energy norm, absolute; paper 1e-10), in
    /// (2.220446049250313e-16, 1).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SliderScene::default().solver_tolerance))]
    pub solver_tolerance: f64,
    /// Coarse grid diagonal.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SliderScene::default().diagonal))]
    pub diagonal: Diagonal,
    /// The block's ends `x = 0` and `x = 5` m ([`TAG_NEUMANN`](rsf_fem::TAG_NEUMANN), traction-free in the paper)
    /// absorb waves instead of reflecting them: Lysmer–Kuhlemeyer dashpots of impedance
    /// ρc_p (normal) and ρc_s (tangential) against the velocity
    /// ([`ModelBuilder::absorbing_boundary`](rsf::ModelBuilder::absorbing_boundary), docs/math.md "Absorbing boundaries"), as if
    /// the block went on in x. Needs an integrator with inertia. Default `false` (the
    /// paper's scene); written only when `true`, so scenes and checkpoints without the
    /// field keep their fingerprint. Used by [`build_model`](Self::build_model) and the
    /// 3-D slider; on a mesh of one's own, add `absorbing_boundary(part)` to the builder
    /// [`physics`](Self::physics) returns.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    #[cfg_attr(feature = "clap", arg(long))]
    pub absorbing_sides: bool,
}

impl Default for SliderScene {
    fn default() -> Self {
        Self {
            level: 4,
            steps: 10_000,
            time_step: TimeStep::Fixed {},
            end_time_s: 15.0,
            density_kg_per_m2: 5e3,
            youngs_modulus_pa: 5e7,
            poisson_ratio: 0.3,
            gravity_m_per_s2: 9.81,
            sigma_n_pa: 49_050.0,
            mu0: 0.6,
            a: 0.010,
            b: 0.015,
            allow_negative_b: false,
            v0_m_per_s: 1e-6,
            l_m: 1e-5,
            loading_velocity_m_per_s: 2e-4,
            ramp_fraction: 0.25,
            alpha0: -10.0,
            state_law: StateLawKind::Aging,
            state_integrator: StateIntegrator::BackwardEuler,
            integrator: Integrator::Newmark,
            solver: SolverKind::Auto,
            fixed_point: FixedPointScheme::Anderson,
            fixed_point_tolerance: 1e-10,
            fixed_point_max_iterations: 100,
            fixed_point_inner_solves: InnerSolves::Exact,
            tnnmg_smoother: SmootherOrder::Lexicographic,
            solver_tolerance: 1e-10,
            diagonal: Diagonal::Forward,
            absorbing_sides: false,
        }
    }
}

/// `skip_serializing_if` of [`SliderScene::tnnmg_smoother`]: the default order is not
/// written.
fn is_lexicographic(order: &SmootherOrder) -> bool {
    *order == SmootherOrder::Lexicographic
}

/// The admissible initial states α₀ = ln θ₀ (θ₀ in s): those with θ₀ = exp(α₀) a normal
/// double, `[ln f64::MIN_POSITIVE, ln f64::MAX]` rounded inwards.
pub const ALPHA_RANGE: (f64, f64) = (-708.0, 709.0);

/// The centre of Γ_F, `x0 = (2.5, 0)` m, where the paper records its time series.
pub const SLIDER_CENTRE: [f64; 2] = [2.5, 0.0];

impl SliderScene {
    /// Parses a TOML scene (fields as in this struct; unknown fields are an error).
    ///
    /// # Errors
    /// [`Error::SceneFile`](rsf::Error::SceneFile) with the line, column and the parser's message (it names
    /// unknown fields; long values excerpted).
    pub fn from_toml(text: &str) -> Result<Self> {
        toml::from_str(text).map_err(|e| crate::scene_file::toml_error(text, &e))
    }

    /// Reads a TOML scene file ([`from_toml`](Self::from_toml)).
    ///
    /// # Errors
    /// [`Error::SceneFile`](rsf::Error::SceneFile) naming the path: it cannot be read, or as
    /// [`from_toml`](Self::from_toml).
    pub fn read(path: impl AsRef<std::path::Path>) -> Result<Self> {
        crate::scene_file::read(path.as_ref(), Self::from_toml)
    }

    /// The time step τ = T/N (s).
    pub fn tau(&self) -> f64 {
        self.end_time_s / self.steps as f64
    }

    /// The initial time step (s): for adaptive steps `initial_tau_s` if set, else
    /// [`tau`](Self::tau), clamped to `[tau_min_s, tau_max_s]` (where the controller
    /// starts); for fixed steps [`tau`](Self::tau).
    pub fn initial_tau(&self) -> f64 {
        match self.time_step {
            TimeStep::Adaptive(a) => {
                let t = a.initial_tau_s.unwrap_or_else(|| self.tau());
                // The controller starts at the initial step clamped to the bounds; valid
                // bounds only (`clamp` needs lo ≤ hi; invalid ones are errors of
                // `step_control`).
                if a.tau_min_s <= a.tau_max_s {
                    t.clamp(a.tau_min_s, a.tau_max_s)
                } else {
                    t
                }
            }
            TimeStep::Fixed {} => self.tau(),
        }
    }

    /// The step control of adaptive time steps (`None` for fixed steps).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](rsf::Error::InvalidParameter) naming the first invalid option
    /// (`time_step.<field>`): the controller's checks ([`StepControl::validate`]: the
    /// tolerance in (ε, 1), `tau_min_s` a normal double, …), and `tau_min_s ≥ ε ·
    /// end_time_s`, below which a step at the end of the run does not advance time.
    pub fn step_control(&self) -> Result<Option<StepControl>> {
        let TimeStep::Adaptive(a) = self.time_step else {
            return Ok(None);
        };
        // The scales of the absolute tolerances (m and s), checked here so that the error
        // names the scale, not the product with the tolerance.
        let checked_scale = |name: &str, x: f64| {
            if x.is_finite() && x >= 0.0 {
                Ok(x)
            } else {
                Err(invalid(
                    &format!("time_step.{name}"),
                    format!("{x} must be finite and >= 0"),
                ))
            }
        };
        let scale = checked_scale(
            "displacement_scale_m",
            a.displacement_scale_m.unwrap_or(self.l_m),
        )?;
        let state_scale = checked_scale(
            "state_scale_s",
            match a.state_scale_s {
                Some(s) => s,
                None if self.loading_velocity_m_per_s != 0.0 => {
                    self.l_m / self.loading_velocity_m_per_s.abs()
                }
                None => 0.0,
            },
        )?;
        if let Some(t) = a.initial_tau_s {
            if !(t.is_finite() && t > 0.0) {
                return Err(invalid(
                    "time_step.initial_tau_s",
                    format!("{t} must be finite and > 0"),
                ));
            }
        }
        for (name, x) in [
            ("state_change_cap", a.state_change_cap),
            ("slip_rate_floor_mps", a.slip_rate_floor_mps),
        ] {
            // Finite values are checked with the controller's options below; `+inf` is
            // "off".
            if x.is_nan() || x == f64::NEG_INFINITY {
                return Err(invalid(
                    &format!("time_step.{name}"),
                    format!("{x} must be > 0 (inf switches it off)"),
                ));
            }
        }
        let control = StepControl {
            tolerance: a.tolerance,
            displacement_atol: a.tolerance * scale,
            state_atol: a.tolerance * state_scale,
            safety: a.safety,
            min_factor: a.min_factor,
            max_factor: a.max_factor,
            tau_min: a.tau_min_s,
            tau_max: a.tau_max_s,
            state_change_cap: a.state_change_cap.is_finite().then_some(a.state_change_cap),
            slip_rate_floor: a
                .slip_rate_floor_mps
                .is_finite()
                .then_some(a.slip_rate_floor_mps),
            state_extrapolation: a.state_extrapolation,
        };
        control.validate().map_err(|e| match e {
            rsf_time::Error::InvalidParameter {
                name,
                value,
                requirement,
            } => invalid(
                &format!(
                    "time_step.{}",
                    match name {
                        "tau_min" => "tau_min_s",
                        "tau_max" => "tau_max_s",
                        "displacement_atol" => "displacement_scale_m",
                        "state_atol" => "state_scale_s",
                        "slip_rate_floor" => "slip_rate_floor_mps",
                        other => other,
                    }
                ),
                // `{:e}` for huge or tiny values (f64::MAX has 309 digits in `{}`).
                format!("{} must be {requirement}", short_number(value)),
            ),
            other => other.into(),
        })?;
        // A step of τ_min at t ≈ T must advance time: ulp(t) ≤ ε·t ≤ ε·T (docs/reliability.md).
        let resolvable = f64::EPSILON * self.end_time_s;
        if a.tau_min_s < resolvable {
            return Err(invalid(
                "time_step.tau_min_s",
                format!(
                    "{:e} s is below ε · end_time_s = {resolvable:e} s: a step that short \
                     does not advance the time t ≈ T in double precision (the run would \
                     never end)",
                    a.tau_min_s
                ),
            ));
        }
        Ok(Some(control))
    }

    /// The fingerprint of this scene for checkpoints ([`Fingerprint`]): every field as
    /// TOML names it (nested ones as `time_step.tolerance`) with its value, and the
    /// checkpoint format. A checkpoint continues a run only if they agree
    /// ([`Fingerprint::check`]).
    pub fn fingerprint(&self) -> Fingerprint {
        Fingerprint::of_serialized(self).with("format", CHECKPOINT_FORMAT)
    }

    /// The rate-and-state parameters of Γ_F.
    pub fn rate_state_params(&self) -> RateStateParams {
        RateStateParams {
            mu0: self.mu0,
            a: self.a,
            b: self.b,
            v0: self.v0_m_per_s,
            l: self.l_m,
            sigma_n: self.sigma_n_pa,
        }
    }

    /// The material of the block (plane strain).
    pub fn material(&self) -> Material {
        Material {
            youngs_modulus: self.youngs_modulus_pa,
            poisson_ratio: self.poisson_ratio,
            density: self.density_kg_per_m2,
        }
    }

    /// End of the loading ramp `ramp_fraction · T` (s).
    pub fn ramp_end_s(&self) -> f64 {
        self.ramp_fraction * self.end_time_s
    }

    /// The loading history of Γ_D: the ramp to 1 over [`ramp_end_s`](Self::ramp_end_s).
    pub fn loading(&self) -> TimeFunction {
        TimeFunction::ramp(self.ramp_end_s())
    }

    /// The friction law of Γ_F (uniform Dieterich–Ruina with [`rate_state_params`](Self::rate_state_params)).
    ///
    /// # Errors
    /// The friction crate's parameter error.
    pub fn friction_law(&self) -> Result<DieterichRuina> {
        DieterichRuina::new(self.rate_state_params()).map_err(Self::friction_key)
    }

    /// A friction parameter's error named as the scene's key (`v0` → `v0_m_per_s`, …).
    fn friction_key(e: rsf_friction::Error) -> rsf::Error {
        let rsf_friction::Error::InvalidParameter {
            name,
            value,
            requirement,
        } = e
        else {
            return e.into();
        };
        let key = match name {
            "v0" => "v0_m_per_s",
            "l" => "l_m",
            "sigma_n" => "sigma_n_pa",
            other => other,
        };
        invalid(key, format!("{value:e}: {requirement}"))
    }
}

/// The slider's run configuration (docs/design.md, "One run configuration"): the scene's
/// fields are at once the flags of the slider programs (`level` is `--level`;
/// `end_time_s` also `--end-time`, `state_law` also `--law`, `tnnmg_smoother` also
/// `--smoother`), the keys of their `--scene`/`--config` file and Python's keywords of
/// `rsf.slider`; the fingerprint is [`SliderScene::fingerprint`].
impl crate::RunConfig for SliderScene {
    fn validate(&self) -> Result<()> {
        SliderScene::validate(self)
    }

    fn fingerprint(&self) -> Fingerprint {
        SliderScene::fingerprint(self)
    }
}

/// The scene itself (what the slider programs' flags read and change, whichever scene).
impl AsRef<SliderScene> for SliderScene {
    fn as_ref(&self) -> &SliderScene {
        self
    }
}

/// The scene itself.
impl AsMut<SliderScene> for SliderScene {
    fn as_mut(&mut self) -> &mut SliderScene {
        self
    }
}
