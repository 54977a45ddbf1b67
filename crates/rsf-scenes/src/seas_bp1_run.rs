//! A run of BP1 as every front end sets it up — the program `seas_bp1`'s flags and its
//! `--config` file's keys, the Python package's `rsf.seas_bp1` keywords: the settings, their
//! defaults and ranges (one place for every front end, [`RunConfig`]), the method they
//! choose and the fingerprint a checkpoint of the run carries, so that a checkpoint of
//! either front end resumes in the other (docs/design.md, "One run configuration"). Every
//! parameter of the description's Table 1 (/work/shared/benchmarks' restatement of Erickson
//! et al. 2020, docs/seas-bp1.md) is a setting: the grid's `dz`, `end_years`, and the
//! scene's [`SeasBp1`] fields of the same names (`sigma_n`, `a0`, `a_max`, `b0`, `d_c`,
//! `v_p`, `v_init`, `v0`, `f0`, `rho`, `c_s`, `h_top`, `h_transition`, `w_f`; SI units).
//! The characteristic slip distance keeps BP1's `d_c` (the description's D_c and the
//! Python keyword since the package's first release), where BP5's description writes L.

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{FaultKernel, FaultOdeOptions, OdeIntegrator};
use rsf::MethodKind;
use rsf_seas::SeasSampling;

use crate::run_config::{as_setting, check_ranges, fault_kernel, KernelChoice, RunConfig};
#[cfg(feature = "clap")]
use crate::run_config::{KERNEL_EPSILON_HELP, KERNEL_HELP};
#[cfg(feature = "clap")]
use crate::seas_square_run::INTEGRATOR_HELP;
use crate::{invalid, SeasBp1, SeasBp1Far, SeasBp1Grid};

/// The ranges of a BP1 run's settings and the flags' help texts (closed intervals): the
/// program's flags, its `--config` keys and the Python keywords of the same names check
/// them. The scene's are wide: values a run can take, not the description's (in
/// brackets).
pub mod bp1_ranges {
    use crate::setting_range;

    setting_range!(pub END_YEARS, END_YEARS_HELP = "Simulated time (years)", [1e-9, 1e5]);
    setting_range!(
        pub RATIO,
        RATIO_HELP = "Growth ratio of the mesh spacing away from the fault",
        [1, 2]
    );
    setting_range!(
        pub STATE_CHANGE_CAP,
        STATE_CHANGE_CAP_HELP = "Largest state change per step ξ (τ ≲ ξ D_c / V in slip); 0 for none",
        [0, 1e3]
    );
    setting_range!(
        pub FIXED_POINT_TOLERANCE,
        FIXED_POINT_TOLERANCE_HELP = "Tolerance of the fixed point iteration of each step (energy norm of the velocity correction; the paper's 1e-10 by default)",
        [1e-300, 1e3]
    );
    setting_range!(
        pub DYNAMIC_FIXED_POINT_TOLERANCE,
        DYNAMIC_FIXED_POINT_TOLERANCE_HELP = "Fixed point tolerance of the dynamic phases (energy norm of K + M, absolute): during an event ‖v‖ is about 1e6 in this norm, so 1e-6 is 1e-12 relative; the paper's 1e-10 lies below the round-off of the corrections (they stagnate near 1e-9)",
        [1e-300, 1e3]
    );
    setting_range!(
        pub EVENT_QUIET_TIME,
        EVENT_QUIET_TIME_HELP = "An event ends when the largest slip rate has stayed below 1e-3 m/s for this long (s); default 0 (the benchmark's definition), 60 with `--inertia` and reflecting far boundaries (`--absorbing none`: waves reflected by the domain's boundaries lift the slip rate over the threshold for fractions of a second after a rupture)",
        [0, 1e9]
    );
    setting_range!(
        pub SWITCH_TO_DYNAMIC,
        SWITCH_TO_DYNAMIC_HELP = "Switch to the dynamic method when the largest slip rate reaches this (m/s); default 1e-2 (docs/seas-bp1-fd.md: with absorbing boundaries 1e-3 / 1e-4 left the afterslip below a rupture to the dynamic step for hours). Needs `--inertia`",
        [1e-12, 1e2]
    );
    setting_range!(
        pub SWITCH_TO_QUASI_DYNAMIC,
        SWITCH_TO_QUASI_DYNAMIC_HELP = "Switch back to the quasi-dynamic method when it falls below this (m/s); default 1e-3 (docs/seas-bp1-fd.md). Needs `--inertia`",
        [1e-12, 1e2]
    );
    setting_range!(pub RHO, RHO_HELP = "Density ρ (kg/m³) [description: 2670]", [1, 1e5]);
    setting_range!(
        pub C_S,
        C_S_HELP = "Shear wave speed c_s (m/s) [description: 3464]",
        [1, 1e5]
    );
    setting_range!(
        pub SIGMA_N,
        SIGMA_N_HELP = "Effective normal stress σ_n (Pa) [description: 50e6]",
        [1e3, 1e10]
    );
    setting_range!(
        pub A0,
        A0_HELP = "Direct effect a above H [description: 0.010]",
        [1e-5, 1]
    );
    setting_range!(
        pub A_MAX,
        A_MAX_HELP = "Direct effect a below H + h [description: 0.025]",
        [1e-5, 1]
    );
    setting_range!(
        pub B0,
        B0_HELP = "Evolution effect b, uniform [description: 0.015]",
        [1e-5, 1]
    );
    setting_range!(
        pub D_C,
        D_C_HELP = "Characteristic slip distance D_c (m) [description: 0.008]",
        [1e-6, 1e3]
    );
    setting_range!(
        pub V_P,
        V_P_HELP = "Plate rate V_p (m/s): creep below W_f and the far side's loading [description: 1e-9]",
        [1e-15, 1]
    );
    setting_range!(
        pub V_INIT,
        V_INIT_HELP = "Initial slip rate V_init (m/s) [description: 1e-9]",
        [1e-20, 10]
    );
    setting_range!(
        pub V0,
        V0_HELP = "Reference slip rate V₀ (m/s) [description: 1e-6]",
        [1e-15, 1e3]
    );
    setting_range!(
        pub F0,
        F0_HELP = "Reference friction coefficient f₀ [description: 0.6]",
        [0, 10]
    );
    setting_range!(
        pub H_TOP,
        H_TOP_HELP = "Depth H of the velocity-weakening zone (m) [description: 15e3]",
        [1, 1e6]
    );
    setting_range!(
        pub H_TRANSITION,
        H_TRANSITION_HELP = "Width h of the transition of a (m) [description: 3e3]",
        [1, 1e6]
    );
}
use bp1_ranges as r;

/// The time integration of a BP1 run: `runge-kutta` or `implicit`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp1Scheme {
    /// The quasi-dynamic equations condensed onto the fault ([`rsf::FaultOde`]), the
    /// default; with `inertia`, switching to the dynamic implicit scheme during events.
    #[default]
    RungeKutta,
    /// The paper's scheme: backward Euler with the fixed point of velocity and state.
    Implicit,
}

/// The far boundaries of a fully dynamic BP1 run (docs/seas-bp1-fd.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp1Absorbing {
    /// The far side moves with the plate, the bottom is free: both reflect.
    None,
    /// Absorbing in the dynamic phases of the switching run only.
    Dynamic,
    /// The absorbing model throughout.
    All,
}

/// The integrator of the dynamic phases of a BP1 run with inertia.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp1DynamicIntegrator {
    /// Trapezoidal Newmark (energy conserving), the default.
    #[default]
    Newmark,
    /// Backward Euler (first order, damps high frequencies).
    BackwardEuler,
}

/// The scene's parameters: each a field of both [`SeasBp1Run`] and [`SeasBp1`] of the
/// same name, listed once here (the copy both ways and the ranges).
macro_rules! scene_params {
    ($($field:ident: $range:expr, $unit:literal),* $(,)?) => {
        impl SeasBp1Run {
            /// The scene of this run's parameters.
            pub fn scene(&self) -> SeasBp1 {
                SeasBp1 {
                    $($field: self.$field,)*
                }
            }

            /// This run with the parameters of `scene` (a front end that reads the
            /// scene's fields).
            pub fn with_scene(self, scene: &SeasBp1) -> Self {
                Self {
                    $($field: scene.$field,)*
                    ..self
                }
            }

            /// The scene's parameters against their ranges (`w_f` against the grid's).
            fn check_scene(&self) -> rsf::Result<()> {
                check_ranges(&[$((stringify!($field), self.$field, $range, $unit)),*])
            }
        }
    };
}

scene_params!(
    rho: r::RHO, "kg/m³",
    c_s: r::C_S, "m/s",
    sigma_n: r::SIGMA_N, "Pa",
    a0: r::A0, "",
    a_max: r::A_MAX, "",
    b0: r::B0, "",
    d_c: r::D_C, "m",
    v_p: r::V_P, "m/s",
    v_init: r::V_INIT, "m/s",
    v0: r::V0, "m/s",
    f0: r::F0, "",
    h_top: r::H_TOP, "m",
    h_transition: r::H_TRANSITION, "m",
    w_f: (1.0, 1e6), "m",
);

/// The settings of a BP1 run (the program's flags and `--config` keys, Python's
/// keywords). [`Default`] is the program's: BP1-QD on 25 m cells in a 400 km square graded
/// by 1.05, the fault ODE's Runge–Kutta run at tolerance 1e-6 with the ℋ-kernel matching
/// it, 3000 years, the description's parameters. The settings of the fully dynamic run
/// whose defaults depend on `inertia` (`absorbing`, the switching thresholds, the dynamic
/// step, the quiet time of an event) are `None` unless given; [`resolved`](Self::resolved)
/// fills them as the run uses them, and the fingerprint and the summary record that.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct SeasBp1Run {
    /// Simulated time (years of [`rsf_seas::SECONDS_PER_YEAR`]).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().end_years, allow_negative_numbers = true, help = r::END_YEARS_HELP))]
    pub end_years: f64,
    /// Element size on the fault (m); must divide W_f into whole cells.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().dz, allow_negative_numbers = true))]
    pub dz: f64,
    /// Side of the square domain (km); must exceed W_f.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().domain_km, allow_negative_numbers = true))]
    pub domain_km: f64,
    /// Growth ratio of the mesh spacing away from the fault.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().ratio, allow_negative_numbers = true, help = r::RATIO_HELP))]
    pub ratio: f64,
    /// Relative tolerance of the adaptive steps (`--scheme implicit`, or the dynamic phases
    /// with `--inertia`), in (2.220446049250313e-16, 1) (open: from f64::EPSILON, which
    /// can never be met, to 1, which accepts any step).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().tolerance, allow_negative_numbers = true))]
    pub tolerance: f64,
    /// Fully dynamic (BP1-FD): with the default scheme, Newmark with inertia and no
    /// radiation damping at fixed steps `--dynamic-tau` while the largest slip rate is
    /// above the switching thresholds, the quasi-dynamic Runge–Kutta run in between; with
    /// `--scheme implicit`, adaptive Newmark throughout.
    #[cfg_attr(feature = "clap", arg(long))]
    pub inertia: bool,
    /// Far boundaries of the fully dynamic runs (docs/seas-bp1-fd.md): `none` (the far
    /// side moves with the plate, the bottom is free: both reflect), `dynamic`
    /// (absorbing — Lysmer–Kuhlemeyer dashpots against the motion relative to the far
    /// field at V_p/2 on the far side and the bottom — in the dynamic phases of the
    /// switching run, the quasi-dynamic phases as `none`), `all` (the absorbing model
    /// throughout: the implicit scheme, or both phases of the switching run, whose fault
    /// ODE sees the absorbing parts traction-free). Needs `--inertia`; default `all` (the
    /// converged set-up of docs/seas-bp1-fd.md), `none` without `--inertia`.
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub absorbing: Option<Bp1Absorbing>,
    /// The integrator with inertia (`--inertia`): `newmark` (trapezoidal, energy
    /// conserving, the default) or `backward-euler` (first order, damps high frequencies;
    /// docs/seas-bp1-fd.md).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp1Run::default().dynamic_integrator))]
    pub dynamic_integrator: Bp1DynamicIntegrator,
    /// Time step of the dynamic phases (s); default a quarter of the time a shear wave
    /// takes to cross an element on the fault, Δz/(4 c_s) (docs/seas-bp1.md: Δz/(2 c_s)
    /// gets the first event but not the recurrence).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dynamic_tau: Option<f64>,
    /// Slip rate (m/s) at which the switching run turns dynamic.
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::SWITCH_TO_DYNAMIC_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub switch_to_dynamic: Option<f64>,
    /// The quiet time (s) that ends an event.
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::EVENT_QUIET_TIME_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub event_quiet_time: Option<f64>,
    /// Slip rate (m/s) at which the switching run turns quasi-dynamic again.
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::SWITCH_TO_QUASI_DYNAMIC_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub switch_to_quasi_dynamic: Option<f64>,
    /// Fixed point tolerance of the dynamic phases.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().dynamic_fixed_point_tolerance, allow_negative_numbers = true, help = r::DYNAMIC_FIXED_POINT_TOLERANCE_HELP))]
    pub dynamic_fixed_point_tolerance: f64,
    /// A station row at every accepted step (default: thinned as the benchmark suggests).
    #[cfg_attr(feature = "clap", arg(long))]
    pub every_step: bool,
    /// Largest state change per step ξ of the implicit scheme; 0 for none.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().state_change_cap, allow_negative_numbers = true, help = r::STATE_CHANGE_CAP_HELP))]
    pub state_change_cap: f64,
    /// Tolerance of the implicit scheme's fixed point iteration.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().fixed_point_tolerance, allow_negative_numbers = true, help = r::FIXED_POINT_TOLERANCE_HELP))]
    pub fixed_point_tolerance: f64,
    /// Set up the solver for every step size (default: once, the quasistatic problem
    /// scaled by 1/τ).
    #[cfg_attr(feature = "clap", arg(long))]
    pub setup_per_time_step: bool,
    /// Time integration: `runge-kutta` (quasi-dynamic equations condensed onto the fault,
    /// `--integrator`'s, the default) or `implicit` (the paper's scheme: backward Euler
    /// with the fixed point of velocity and state, the only one with `--inertia`).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp1Run::default().scheme))]
    pub scheme: Bp1Scheme,
    /// Tolerance of the Runge–Kutta steps (local error per step relative to D_c in slip,
    /// absolute in ln θ), in (2.220446049250313e-16, 1) (open: from f64::EPSILON to 1).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().rk_tolerance, allow_negative_numbers = true))]
    pub rk_tolerance: f64,
    /// The Runge–Kutta run's operators condensed onto the fault: `hierarchical` (the
    /// default) or `dense`.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp1Run::default().kernel, help = KERNEL_HELP))]
    pub kernel: KernelChoice,
    /// Relative accuracy of the hierarchical kernel (default: `rk_tolerance`, within its
    /// range).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = KERNEL_EPSILON_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kernel_epsilon: Option<f64>,
    /// The fault ODE's integrator.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp1Run::default().integrator, help = INTEGRATOR_HELP))]
    pub integrator: OdeIntegrator,
    /// Density ρ (kg/m³).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().rho, allow_negative_numbers = true, help = r::RHO_HELP))]
    pub rho: f64,
    /// Shear wave speed c_s (m/s).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().c_s, allow_negative_numbers = true, help = r::C_S_HELP))]
    pub c_s: f64,
    /// Effective normal stress σ_n (Pa).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().sigma_n, allow_negative_numbers = true, help = r::SIGMA_N_HELP))]
    pub sigma_n: f64,
    /// Direct effect a above `h_top`.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().a0, allow_negative_numbers = true, help = r::A0_HELP))]
    pub a0: f64,
    /// Direct effect a below `h_top + h_transition`.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().a_max, allow_negative_numbers = true, help = r::A_MAX_HELP))]
    pub a_max: f64,
    /// Evolution effect b (uniform).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().b0, allow_negative_numbers = true, help = r::B0_HELP))]
    pub b0: f64,
    /// Characteristic slip distance D_c (m).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().d_c, allow_negative_numbers = true, help = r::D_C_HELP))]
    pub d_c: f64,
    /// Plate rate V_p (m/s).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().v_p, allow_negative_numbers = true, help = r::V_P_HELP))]
    pub v_p: f64,
    /// Initial slip rate V_init (m/s).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().v_init, allow_negative_numbers = true, help = r::V_INIT_HELP))]
    pub v_init: f64,
    /// Reference slip rate V₀ (m/s).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().v0, allow_negative_numbers = true, help = r::V0_HELP))]
    pub v0: f64,
    /// Reference friction coefficient f₀.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().f0, allow_negative_numbers = true, help = r::F0_HELP))]
    pub f0: f64,
    /// Depth H of the velocity-weakening zone (m).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().h_top, allow_negative_numbers = true, help = r::H_TOP_HELP))]
    pub h_top: f64,
    /// Width h of the transition of a (m).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().h_transition, allow_negative_numbers = true, help = r::H_TRANSITION_HELP))]
    pub h_transition: f64,
    /// Depth W_f of the frictional fault (m) [description: 40e3], creep at V_p below; a
    /// whole number of `--dz` cells, less than the domain.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp1Run::default().w_f, allow_negative_numbers = true))]
    pub w_f: f64,
}

impl Default for SeasBp1Run {
    fn default() -> Self {
        let run = Self {
            end_years: 3000.0,
            dz: 25.0,
            domain_km: 400.0,
            ratio: 1.05,
            tolerance: 1e-3,
            inertia: false,
            absorbing: None,
            dynamic_integrator: Bp1DynamicIntegrator::Newmark,
            dynamic_tau: None,
            switch_to_dynamic: None,
            event_quiet_time: None,
            switch_to_quasi_dynamic: None,
            dynamic_fixed_point_tolerance: 1e-6,
            every_step: false,
            state_change_cap: 0.5,
            fixed_point_tolerance: 1e-10,
            setup_per_time_step: false,
            scheme: Bp1Scheme::RungeKutta,
            // The pair at 1e-4 (issue 84): on BP1 at Δz = 25 m its event times are
            // 1.5e-6 off a 1e-8 reference in 300 years (`auto` at 1e-6: 3.8e-6) at 0.64×
            // the CPU of `auto` at 1e-6 (docs/seas-bp1.md, "Default tolerance").
            rk_tolerance: 1e-4,
            kernel: KernelChoice::Hierarchical,
            kernel_epsilon: None,
            integrator: OdeIntegrator::DormandPrince,
            rho: 0.0,
            c_s: 0.0,
            sigma_n: 0.0,
            a0: 0.0,
            a_max: 0.0,
            b0: 0.0,
            d_c: 0.0,
            v_p: 0.0,
            v_init: 0.0,
            v0: 0.0,
            f0: 0.0,
            h_top: 0.0,
            h_transition: 0.0,
            w_f: 0.0,
        };
        run.with_scene(&SeasBp1::default())
    }
}

impl SeasBp1Run {
    /// The mesh's grid.
    pub fn grid(&self) -> SeasBp1Grid {
        SeasBp1Grid {
            dz: self.dz,
            domain: self.domain_km * 1e3,
            ratio: self.ratio,
        }
    }

    /// The method the settings choose: the implicit scheme, the fault ODE (BP1-QD's
    /// default) or, with `inertia`, the switching run.
    pub fn method(&self) -> MethodKind {
        match (self.scheme, self.inertia) {
            (Bp1Scheme::Implicit, _) => MethodKind::Implicit,
            (Bp1Scheme::RungeKutta, false) => MethodKind::FaultOde,
            (Bp1Scheme::RungeKutta, true) => MethodKind::Switching,
        }
    }

    /// This run with every setting whose default depends on another filled as the run
    /// uses it: `absorbing` (`all` with inertia, else `none`), `event_quiet_time` (60 s
    /// with inertia and reflecting boundaries, else 0), and for the switching run the
    /// thresholds (1e-2 and 1e-3 m/s, docs/seas-bp1-fd.md) and `dynamic_tau` (Δz/(4 c_s)).
    pub fn resolved(&self) -> Self {
        let mut run = *self;
        let absorbing = run.absorbing.unwrap_or(if run.inertia {
            Bp1Absorbing::All
        } else {
            Bp1Absorbing::None
        });
        run.absorbing = Some(absorbing);
        run.event_quiet_time = Some(run.event_quiet_time.unwrap_or(
            if run.inertia && absorbing == Bp1Absorbing::None {
                60.0
            } else {
                0.0
            },
        ));
        if run.method() == MethodKind::Switching {
            run.switch_to_dynamic = Some(run.switch_to_dynamic.unwrap_or(1e-2));
            run.switch_to_quasi_dynamic = Some(run.switch_to_quasi_dynamic.unwrap_or(1e-3));
            run.dynamic_tau = Some(run.dynamic_tau.unwrap_or(0.25 * run.dz / run.c_s));
        }
        run
    }

    /// The far boundary of the model with (`true`) or without absorbing faces.
    pub fn far(absorbing: bool) -> SeasBp1Far {
        if absorbing {
            SeasBp1Far::Absorbing
        } else {
            SeasBp1Far::Dirichlet
        }
    }

    /// The files' sampling: every step or the benchmark's, and the quiet time that ends
    /// an event (resolved).
    pub fn sampling(&self) -> SeasSampling {
        SeasSampling {
            every_step: self.every_step,
            event_quiet_time: self.resolved().event_quiet_time.unwrap_or(0.0),
            ..SeasSampling::default()
        }
    }

    /// The fault kernel of the settings ([`fault_kernel`] at `rk_tolerance`).
    ///
    /// # Errors
    /// `kernel_epsilon` refused.
    pub fn fault_kernel(&self) -> rsf::Result<FaultKernel> {
        fault_kernel(self.kernel, self.kernel_epsilon, self.rk_tolerance)
    }

    /// The fault ODE's options of the run on `threads` threads: the scene's at
    /// `rk_tolerance`, the run's kernel and integrator.
    ///
    /// # Errors
    /// An invalid tolerance (named `rk_tolerance`) or kernel accuracy (`kernel_epsilon`).
    pub fn fault_ode_options(&self, threads: usize) -> rsf::Result<FaultOdeOptions> {
        let options = as_setting(
            "rk_tolerance",
            self.scene().fault_ode_options(self.rk_tolerance),
        )?;
        let options = FaultOdeOptions {
            kernel: self.fault_kernel()?,
            integrator: self.integrator,
            parallelism: rsf::Parallelism::rayon(threads),
            ..options
        };
        options.validate()?;
        Ok(options)
    }

    /// The time a shear wave takes to cross an element on the fault, Δz/c_s (s).
    pub fn crossing_time(&self) -> f64 {
        self.dz / self.c_s
    }

    /// Refuses the settings the chosen method would ignore: the fully dynamic run's
    /// without `inertia`, the implicit scheme's with the default fault ODE (issue 87: a
    /// flag that does nothing is refused naming the flag that would use it).
    fn refuse_ignored(&self) -> rsf::Result<()> {
        let d = Self::default();
        let ignored =
            |name: &str, value: String, why: &str| Err(invalid(name, format!("{value}: {why}")));
        if !self.inertia {
            let needs = "a setting of the fully dynamic run: it needs --inertia (BP1-FD), \
                         without it it would be ignored";
            let written = |x: Option<f64>| x.map(rsf_numeric::written);
            for (name, given) in [
                (
                    "absorbing",
                    self.absorbing
                        .filter(|a| *a != Bp1Absorbing::None)
                        .map(|a| format!("{a:?}").to_lowercase()),
                ),
                ("dynamic_tau", written(self.dynamic_tau)),
                ("switch_to_dynamic", written(self.switch_to_dynamic)),
                (
                    "switch_to_quasi_dynamic",
                    written(self.switch_to_quasi_dynamic),
                ),
                (
                    "dynamic_integrator",
                    (self.dynamic_integrator != d.dynamic_integrator)
                        .then(|| "backward-euler".to_owned()),
                ),
                // Issue 87's probe: `--dynamic-fixed-point-tolerance 1e-300` ran without
                // --inertia, the value never used.
                (
                    "dynamic_fixed_point_tolerance",
                    (self.dynamic_fixed_point_tolerance != d.dynamic_fixed_point_tolerance)
                        .then(|| rsf_numeric::written(self.dynamic_fixed_point_tolerance)),
                ),
            ] {
                if let Some(value) = given {
                    return ignored(name, value, needs);
                }
            }
        }
        // The settings of the implicit scheme are ignored by the default one (the fault
        // ODE's Runge–Kutta run without inertia): refused when given (issue 87:
        // `--tolerance 1e-8` gave byte-identical files while summary.json recorded it).
        if self.method() == MethodKind::FaultOde {
            let why = "a setting of the implicit scheme (--scheme implicit, or the dynamic \
                       phases with --inertia); the default scheme, the fault ODE's \
                       Runge–Kutta run, would ignore it — its tolerance is --rk-tolerance";
            for (name, value, default) in [
                ("tolerance", self.tolerance, d.tolerance),
                (
                    "state_change_cap",
                    self.state_change_cap,
                    d.state_change_cap,
                ),
                (
                    "fixed_point_tolerance",
                    self.fixed_point_tolerance,
                    d.fixed_point_tolerance,
                ),
            ] {
                if value != default {
                    return ignored(name, rsf_numeric::written(value), why);
                }
            }
            if self.setup_per_time_step {
                return ignored("setup_per_time_step", "true".into(), why);
            }
        }
        if self.absorbing == Some(Bp1Absorbing::Dynamic) && self.scheme == Bp1Scheme::Implicit {
            return ignored(
                "absorbing",
                "dynamic".into(),
                "the implicit scheme has one model (use all)",
            );
        }
        Ok(())
    }

    /// The dynamic step against the crossing time Δz/c_s: below a thousandth of it a step
    /// resolves nothing more, and a dynamic phase of a minute would take hundreds of
    /// millions of steps (issue 74: `--dynamic-tau 1e-9` ran without bound).
    fn check_dynamic_tau(&self) -> rsf::Result<()> {
        let crossing = self.crossing_time();
        match self.dynamic_tau {
            Some(tau) => check_ranges(&[(
                "dynamic_tau",
                tau,
                (1e-3 * crossing, crossing),
                &format!(
                    "s: at most the {crossing:.3e} s a shear wave takes to cross an element \
                     of the fault (Δz/c_s), a longer step does not resolve the rupture; at \
                     least a thousandth of it, a shorter one resolves nothing more and an \
                     event would take without bound"
                ),
            )]),
            None => Ok(()),
        }
    }
}

impl RunConfig for SeasBp1Run {
    /// Checks every setting: the ranges ([`bp1_ranges`]), the scene and its grid (`dz`
    /// dividing W_f, the domain beyond it), the methods' tolerances and kernel, and the
    /// settings the chosen method would ignore.
    fn validate(&self) -> rsf::Result<()> {
        check_ranges(&[
            ("end_years", self.end_years, r::END_YEARS, "years"),
            (
                "state_change_cap",
                self.state_change_cap,
                r::STATE_CHANGE_CAP,
                "0: no cap",
            ),
            (
                "fixed_point_tolerance",
                self.fixed_point_tolerance,
                r::FIXED_POINT_TOLERANCE,
                "an absolute tolerance",
            ),
            (
                "dynamic_fixed_point_tolerance",
                self.dynamic_fixed_point_tolerance,
                r::DYNAMIC_FIXED_POINT_TOLERANCE,
                "an absolute tolerance",
            ),
            ("ratio", self.ratio, r::RATIO, "the growth of the spacing"),
        ])?;
        let optional = [
            (
                "switch_to_dynamic",
                self.switch_to_dynamic,
                r::SWITCH_TO_DYNAMIC,
                "m/s: a slip rate",
            ),
            (
                "switch_to_quasi_dynamic",
                self.switch_to_quasi_dynamic,
                r::SWITCH_TO_QUASI_DYNAMIC,
                "m/s: a slip rate",
            ),
            (
                "event_quiet_time",
                self.event_quiet_time,
                r::EVENT_QUIET_TIME,
                "s",
            ),
        ];
        for (name, value, range, unit) in optional {
            if let Some(v) = value {
                check_ranges(&[(name, v, range, unit)])?;
            }
        }
        self.check_scene()?;
        let scene = self.scene();
        // The grid's fields named as the settings (`domain` is `domain_km`).
        scene.estimate(&self.grid()).map_err(|e| match e {
            rsf::Error::InvalidParameter { name, reason } if name == "domain" => {
                invalid("domain_km", reason)
            }
            e => e,
        })?;
        // The implicit scheme's step control checks its tolerance (an error of its own
        // kind, named here as the setting).
        scene.step_control(self.tolerance).map_err(|e| match e {
            rsf::Error::InvalidParameter { reason, .. } => invalid("tolerance", reason),
            e => invalid(
                "tolerance",
                format!("{}: {e}", rsf_numeric::written(self.tolerance)),
            ),
        })?;
        as_setting("rk_tolerance", scene.fault_ode_options(self.rk_tolerance))?;
        self.fault_kernel()?;
        self.refuse_ignored()?;
        self.check_dynamic_tau()
    }

    /// Every setting, resolved ([`resolved`](Self::resolved)), then the checkpoint format.
    fn fingerprint(&self) -> Fingerprint {
        Fingerprint::of_serialized(&self.resolved())
            .with("format", rsf::checkpoint::CHECKPOINT_FORMAT)
    }

    /// The settings, resolved.
    fn summary(&self) -> serde_json::Value {
        serde_json::to_value(self.resolved()).unwrap_or(serde_json::Value::Null)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults validate and are the description's scene; `resolved` fills the fully
    /// dynamic defaults only where they are used.
    #[test]
    fn the_defaults_are_the_descriptions() {
        let run = SeasBp1Run::default();
        run.validate().unwrap();
        assert_eq!(run.scene(), SeasBp1::default());
        assert_eq!(run.method(), MethodKind::FaultOde);
        let qd = run.resolved();
        assert_eq!(qd.absorbing, Some(Bp1Absorbing::None));
        assert_eq!(qd.switch_to_dynamic, None);
        let fd = SeasBp1Run {
            inertia: true,
            ..run
        };
        fd.validate().unwrap();
        let fd = fd.resolved();
        assert_eq!(fd.absorbing, Some(Bp1Absorbing::All));
        assert_eq!(fd.switch_to_dynamic, Some(1e-2));
        assert_eq!(fd.dynamic_tau, Some(0.25 * 25.0 / SeasBp1::default().c_s));
        // A setting left unset and the same set to its resolved value are one run.
        assert_eq!(fd.fingerprint(), fd.resolved().fingerprint());
    }

    /// The settings a method ignores are refused by name.
    #[test]
    fn ignored_settings_are_refused_by_name() {
        let run = SeasBp1Run::default();
        let name = |r: SeasBp1Run| crate::refused_name(r.validate());
        assert_eq!(
            name(SeasBp1Run {
                tolerance: 1e-8,
                ..run
            }),
            "tolerance"
        );
        assert_eq!(
            name(SeasBp1Run {
                dynamic_tau: Some(0.01),
                ..run
            }),
            "dynamic_tau"
        );
        assert_eq!(
            name(SeasBp1Run {
                absorbing: Some(Bp1Absorbing::Dynamic),
                scheme: Bp1Scheme::Implicit,
                inertia: true,
                ..run
            }),
            "absorbing"
        );
        assert_eq!(name(SeasBp1Run { dz: 30.0, ..run }), "dz");
        assert_eq!(
            name(SeasBp1Run {
                domain_km: 30.0,
                ..run
            }),
            "domain_km"
        );
        assert_eq!(name(SeasBp1Run { a0: 0.0, ..run }), "a0");
    }
}
