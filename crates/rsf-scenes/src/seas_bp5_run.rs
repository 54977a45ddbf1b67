//! A run of BP5 as every front end sets it up — the program `seas_bp5`'s flags and its
//! `--config` file's keys, the Python package's `rsf.seas_bp5` keywords: the settings, their
//! defaults and ranges (one place for every front end, [`RunConfig`]), the files' headers
//! and the fingerprint a checkpoint of the run carries, so that a checkpoint of either
//! front end resumes in the other (docs/design.md, "One run configuration"). The
//! description's friction and loading parameters (`sigma_n`, `a0`, `a_max`, `b0`, `l`,
//! `l_nucleation`, `f0`, `v0`, `v_p`, `v_init`, `v_i`) are settings too; the other
//! parameters of [`SeasBp5`] (the medium, the geometry) are the scene's (Python's
//! keywords).

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{FaultKernel, FaultOdeOptions, InteriorOrdering, OdeIntegrator};
use rsf_seas::{SeasLayout, SeasSampling, SeasSetup};

#[cfg(feature = "clap")]
use crate::run_config::TOLERANCE_HELP;
use crate::run_config::{as_setting, check_ranges, RunConfig};
#[cfg(feature = "clap")]
use crate::seas_square_run::INTEGRATOR_HELP;
use crate::{invalid, FaultZone, SeasBp5, SeasBp5Grid, SeasBp5Mesh};

/// The file of the Schur-only elimination's checkpoints in a run's folder (its finished
/// state kept: a resume of the run reads it instead of eliminating again).
pub const BP5_SETUP_FILE: &str = "setup.bin";

/// The ranges of a BP5 run's settings (closed intervals) and the flags' help texts: the
/// program's flags, its `--config` keys and the Python keywords of the same names check
/// them. The friction's are wide: values a run can take, not the description's.
pub mod bp5_ranges {
    use crate::setting_range;

    setting_range!(pub END_YEARS, END_YEARS_HELP = "End time (years)", [1e-9, 1e5]);
    /// `domain_km` (km) of the finite-element kernel: beyond `1.5 l_f/2`.
    pub const DOMAIN_KM: (f64, f64) = (75.0, 1e4);
    /// `ratio` of the finite-element kernel: the growth of the spacing.
    pub const RATIO: (f64, f64) = (1.0, 2.0);
    /// `epsilon`: the ℋ-matrix's relative accuracy.
    pub const EPSILON: (f64, f64) = (
        rsf::fault_ode::MIN_KERNEL_EPSILON,
        rsf::fault_ode::MAX_KERNEL_EPSILON,
    );
    setting_range!(
        pub SIGMA_N,
        SIGMA_N_HELP = "Effective normal stress σ̄_n (Pa) [description: 25e6]",
        [1e3, 1e10]
    );
    setting_range!(
        pub A0,
        A0_HELP = "Direct effect a in the velocity-weakening core [description: 0.004]",
        [1e-5, 1]
    );
    setting_range!(
        pub A_MAX,
        A_MAX_HELP = "Direct effect a outside the core (velocity strengthening) [description: 0.04]",
        [1e-5, 1]
    );
    setting_range!(
        pub B0,
        B0_HELP = "Evolution effect b, uniform [description: 0.03]",
        [1e-5, 1]
    );
    setting_range!(
        pub L,
        L_HELP = "Characteristic slip distance L (m) outside the nucleation patch [description: 0.14]",
        [1e-6, 1e3]
    );
    setting_range!(
        pub L_NUCLEATION,
        L_NUCLEATION_HELP = "Characteristic slip distance L (m) in the nucleation patch [description: 0.13]",
        [1e-6, 1e3]
    );
    setting_range!(
        pub F0,
        F0_HELP = "Reference friction coefficient f₀ [description: 0.6]",
        [0, 10]
    );
    setting_range!(
        pub V0,
        V0_HELP = "Reference slip rate V₀ (m/s) [description: 1e-6]",
        [1e-15, 1e3]
    );
    setting_range!(
        pub V_P,
        V_P_HELP = "Plate rate V_p (m/s), along +x₂ [description: 1e-9]",
        [1e-15, 1]
    );
    setting_range!(
        pub V_INIT,
        V_INIT_HELP = "Initial slip rate V_init (m/s) outside the nucleation patch [description: 1e-9]",
        [1e-20, 10]
    );
    setting_range!(
        pub V_I,
        V_I_HELP = "Initial slip rate V_i (m/s) in the nucleation patch [description: 0.03]",
        [1e-20, 10]
    );
}
use bp5_ranges as r;

/// The elastic operator of a BP5 run: `okada` or `fe`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp5Kernel {
    /// Okada's half-space, a fault alone, back slip (the default).
    #[default]
    Okada,
    /// The finite-element volume model condensed onto the fault.
    Fe,
}

/// How the finite-element kernel condenses the volume onto the fault: `schur-only` or
/// `factor`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp5Condensation {
    /// The Schur complement alone, by an elimination that keeps no factor column
    /// (checkpointed in the run's folder as [`BP5_SETUP_FILE`]; the default).
    #[default]
    SchurOnly,
    /// The volume's whole sparse Cholesky factor, kept for the run.
    Factor,
}

/// The friction and loading settings: each a field of both [`SeasBp5Run`] and [`SeasBp5`]
/// of the same name, listed once here (the copy both ways and the ranges).
macro_rules! friction {
    ($($field:ident: $range:path),* $(,)?) => {
        impl SeasBp5Run {
            /// `scene` with this run's friction and loading parameters and fault zone.
            pub fn scene_with(&self, scene: SeasBp5) -> SeasBp5 {
                SeasBp5 {
                    $($field: self.$field,)*
                    fault_zone: self.fault_zone(),
                    ..scene
                }
            }

            /// This run with the friction and loading parameters of `scene` (a front end
            /// that reads the scene's fields, Python's keywords).
            pub fn with_friction_of(self, scene: &SeasBp5) -> Self {
                Self {
                    $($field: scene.$field,)*
                    ..self
                }
            }

            /// The names of the friction's settings (fields of the scene too).
            const FRICTION: &[&str] = &[$(stringify!($field)),*];

            /// The friction's settings against their ranges.
            fn check_friction(&self) -> rsf::Result<()> {
                check_ranges(&[$((stringify!($field), self.$field, $range, "")),*])
            }
        }
    };
}

friction!(
    sigma_n: r::SIGMA_N,
    a0: r::A0,
    a_max: r::A_MAX,
    b0: r::B0,
    l: r::L,
    l_nucleation: r::L_NUCLEATION,
    f0: r::F0,
    v0: r::V0,
    v_p: r::V_P,
    v_init: r::V_INIT,
    v_i: r::V_I,
);

/// The settings of a BP5 run (the program's flags and `--config` keys, Python's
/// keywords). [`Default`] is the program's defaults: Okada's kernel on 2 km cells, 1800
/// years, tolerance 1e-6, ε 1e-6, the description's friction. The finite-element kernel's
/// settings are `None` unless given (a graded box of ±400 km grown by 1.3, condensed by
/// the Schur-only elimination; `ordering` the front end's: nested dissection where METIS
/// is built, else AMD — [`SeasBp5Run::resolved`]) and refused with Okada's kernel, which
/// has no volume.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct SeasBp5Run {
    /// The elastic operator: `okada` (a fault alone in a half-space, boundary elements)
    /// or `fe` (the finite-element volume model condensed onto the fault).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp5Run::default().kernel))]
    pub kernel: Bp5Kernel,
    /// Cell size on the fault (m); must divide l_f = 100 km and W_f = 40 km (both kernels:
    /// the graded mesh puts nodes at x₂ = ±l_f/2 as the cells do).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().dx, allow_negative_numbers = true))]
    pub dx: f64,
    /// `fe`: distance from the fault to the box's far faces, and its depth (km) [default:
    /// 400], in [75, 1e4]; the graded box's root cubes (edge dx·2^k ≤ 64 km) within the
    /// mesh's cell limit too (about 3000 km at --dx 2000: a larger box is refused naming
    /// --domain-km).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub domain_km: Option<f64>,
    /// `fe`: growth of the spacing away from the rate-and-state region [default: 1.3], in
    /// [1, 2] (the graded mesh at 1 grows nowhere: its cells are refused naming --dx,
    /// --ratio and --domain-km).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// `fe`: the volume's mesh, `graded` (an octree of Kuhn cubes refined towards the
    /// fault's rate-and-state region and the stations, growing in every direction) or
    /// `tensor` (a tensor grid graded axis by axis) [default: graded].
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<SeasBp5Mesh>,
    /// `fe`: a compliant fault zone of this total width (km) around the rate-and-state
    /// region (`|x₁| ≤ width/2`; a whole number of `2 dx`), not part of the benchmark
    /// (docs/seas-bp5.md, "A compliant fault zone"); needs `--fault-zone-rigidity`.
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fault_zone_width_km: Option<f64>,
    /// `fe`: the fault zone's shear modulus over the host's, in (0, 1].
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fault_zone_rigidity: Option<f64>,
    /// `fe`: how the volume is condensed onto the fault: `schur-only` (the Schur complement
    /// alone, no factor kept; its elimination checkpointed in `--out`) or `factor` (the
    /// volume's whole factor held through the run) [default: schur-only].
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub condensation: Option<Bp5Condensation>,
    /// `fe`: fill-reducing ordering of the volume's factor, `nested-dissection` (METIS;
    /// the default where it is built, as in the examples: at 1 km a set-up of 53 s and
    /// 1.9 GB against AMD's 412 s and 7.3 GB) or `amd` (the default of a build without
    /// METIS). Part of the fingerprint: the operator changes by round-off.
    #[cfg_attr(feature = "clap", arg(long))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ordering: Option<InteriorOrdering>,
    /// End time (years).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().end_years, allow_negative_numbers = true, help = r::END_YEARS_HELP))]
    pub end_years: f64,
    /// Tolerance of the fault ODE (local error per step: tolerance · L in slip, tolerance
    /// in ln θ).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().tolerance, allow_negative_numbers = true, help = TOLERANCE_HELP))]
    pub tolerance: f64,
    /// The fault ODE's integrator.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp5Run::default().integrator, help = INTEGRATOR_HELP))]
    pub integrator: OdeIntegrator,
    /// Relative accuracy ε of the ℋ-matrix (used above 4 096 unknowns, Δx < 2 km), in
    /// [1e-14, 1e-2] (below, the entries' round-off cannot meet it).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().epsilon, allow_negative_numbers = true))]
    pub epsilon: f64,
    /// Effective normal stress σ̄_n (Pa).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().sigma_n, allow_negative_numbers = true, help = r::SIGMA_N_HELP))]
    pub sigma_n: f64,
    /// Direct effect a in the velocity-weakening core.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().a0, allow_negative_numbers = true, help = r::A0_HELP))]
    pub a0: f64,
    /// Direct effect a outside the core (velocity strengthening).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().a_max, allow_negative_numbers = true, help = r::A_MAX_HELP))]
    pub a_max: f64,
    /// Evolution effect b (uniform).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().b0, allow_negative_numbers = true, help = r::B0_HELP))]
    pub b0: f64,
    /// Characteristic slip distance L (m) outside the nucleation patch.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().l, allow_negative_numbers = true, help = r::L_HELP))]
    pub l: f64,
    /// L (m) in the nucleation patch.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().l_nucleation, allow_negative_numbers = true, help = r::L_NUCLEATION_HELP))]
    pub l_nucleation: f64,
    /// Reference friction coefficient f₀.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().f0, allow_negative_numbers = true, help = r::F0_HELP))]
    pub f0: f64,
    /// Reference slip rate V₀ (m/s).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().v0, allow_negative_numbers = true, help = r::V0_HELP))]
    pub v0: f64,
    /// Plate rate V_p (m/s), along +x₂.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().v_p, allow_negative_numbers = true, help = r::V_P_HELP))]
    pub v_p: f64,
    /// Initial slip rate V_init (m/s) outside the nucleation patch.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().v_init, allow_negative_numbers = true, help = r::V_INIT_HELP))]
    pub v_init: f64,
    /// Initial slip rate V_i (m/s) in the nucleation patch.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp5Run::default().v_i, allow_negative_numbers = true, help = r::V_I_HELP))]
    pub v_i: f64,
}

impl Default for SeasBp5Run {
    fn default() -> Self {
        let run = Self {
            kernel: Bp5Kernel::Okada,
            dx: 2000.0,
            domain_km: None,
            ratio: None,
            mesh: None,
            fault_zone_width_km: None,
            fault_zone_rigidity: None,
            condensation: None,
            ordering: None,
            end_years: 1800.0,
            // Tolerance 1e-4 (issue 84): on Okada's kernel at 1 km the pair's event times
            // are 2.4e-8 and its peak slip rate 1.1e-5 off a 1e-8 reference over 300
            // years, at 0.57× the CPU of 1e-6 (docs/work-precision.md, "The fault ODE's
            // integrators"). `auto` at 1e-4 is the cheapest there on both kernels: 0.91×
            // the pair's CPU on Okada's at 1 km (event times 1.8e-6 off), 0.61× the pair's
            // evaluations with the volume at 1 km (rupture starts within 4.1e-6 of the
            // pair's), where the pair's steps are held by stability (docs/seas-bp5.md,
            // "Default tolerance").
            tolerance: 1e-4,
            integrator: OdeIntegrator::Auto,
            epsilon: 1e-6,
            sigma_n: 0.0,
            a0: 0.0,
            a_max: 0.0,
            b0: 0.0,
            l: 0.0,
            l_nucleation: 0.0,
            f0: 0.0,
            v0: 0.0,
            v_p: 0.0,
            v_init: 0.0,
            v_i: 0.0,
        };
        // The description's friction (Table 1), the scene's.
        run.with_friction_of(&SeasBp5::default())
    }
}

impl SeasBp5Run {
    /// The finite-element box's half-width (km): the setting, or 400.
    pub fn domain_km(&self) -> f64 {
        self.domain_km.unwrap_or(400.0)
    }

    /// The finite-element mesh's growth: the setting, or 1.3.
    pub fn ratio(&self) -> f64 {
        self.ratio.unwrap_or(1.3)
    }

    /// The finite-element mesh: the setting, or the graded octree.
    pub fn mesh(&self) -> SeasBp5Mesh {
        self.mesh.unwrap_or(SeasBp5Mesh::Graded)
    }

    /// The finite-element condensation: the setting, or the Schur-only elimination.
    pub fn condensation(&self) -> Bp5Condensation {
        self.condensation.unwrap_or_default()
    }

    /// The volume's ordering: the setting, or `default` (the front end's: nested
    /// dissection where METIS is built, else AMD).
    pub fn ordering_or(&self, default: InteriorOrdering) -> InteriorOrdering {
        self.ordering.unwrap_or(default)
    }

    /// The run as it runs: with the finite-element kernel every setting of the volume
    /// given (its default where unset; the ordering `ordering`, the front end's default,
    /// where unset) — what the fingerprint and `summary.json` record.
    pub fn resolved(&self, ordering: InteriorOrdering) -> Self {
        match self.kernel {
            Bp5Kernel::Okada => *self,
            Bp5Kernel::Fe => Self {
                domain_km: Some(self.domain_km()),
                ratio: Some(self.ratio()),
                mesh: Some(self.mesh()),
                condensation: Some(self.condensation()),
                ordering: Some(self.ordering_or(ordering)),
                ..*self
            },
        }
    }

    /// The compliant fault zone of `fault_zone_width_km` (km) and `fault_zone_rigidity`
    /// (`None` unless both are set; [`validate_with`](Self::validate_with) refuses one
    /// without the other).
    pub fn fault_zone(&self) -> Option<FaultZone> {
        match (self.fault_zone_width_km, self.fault_zone_rigidity) {
            (Some(width), Some(rigidity_ratio)) => Some(FaultZone {
                half_width: 0.5 * width * 1e3,
                rigidity_ratio,
            }),
            _ => None,
        }
    }

    /// The scene: BP5 with this run's friction and fault zone.
    pub fn scene(&self) -> SeasBp5 {
        self.scene_with(SeasBp5::default())
    }

    /// The finite-element grid of `bp5` (its fault zone's slab meshed at `dx`).
    pub fn grid(&self, bp5: &SeasBp5) -> SeasBp5Grid {
        SeasBp5Grid {
            dx: self.dx,
            domain: self.domain_km() * 1e3,
            ratio: self.ratio(),
            mesh: self.mesh(),
            near_fault: bp5.fault_zone.map_or(0.0, |z| z.half_width),
        }
    }

    /// Checks every setting against its range ([`bp5_ranges`]; the box's only for the
    /// finite-element kernel), the settings of the volume given with Okada's kernel, the
    /// fault zone's two settings together, the scene `base` with this run's friction
    /// ([`scene_with`](Self::scene_with)), `dx` against the fault ([`SeasBp5::cells`]), the
    /// tolerance and ε.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named by the setting (the Python keyword; the flag
    /// with `--` and dashes) or the scene's field.
    pub fn validate_with(&self, base: SeasBp5) -> rsf::Result<()> {
        check_ranges(&[("end_years", self.end_years, r::END_YEARS, "years")])?;
        self.check_friction()?;
        self.check_volume_given()?;
        match (self.fault_zone_width_km, self.fault_zone_rigidity) {
            (Some(_), None) => {
                return Err(invalid(
                    "fault_zone_rigidity",
                    "needed with fault_zone_width_km: the zone's shear modulus over the host's",
                ))
            }
            (None, Some(_)) => {
                return Err(invalid(
                    "fault_zone_width_km",
                    "needed with fault_zone_rigidity: the zone's total width (km)",
                ))
            }
            _ => {}
        }
        let bp5 = self.scene_with(base);
        bp5.validate().map_err(|e| match e {
            rsf::Error::InvalidParameter { name, reason } => match name.as_str() {
                "fault_zone.half_width" => invalid(
                    "fault_zone_width_km",
                    format!(
                        "{}: {reason}",
                        rsf_numeric::written(self.fault_zone_width_km.unwrap_or(0.0))
                    ),
                ),
                "fault_zone.rigidity_ratio" => invalid("fault_zone_rigidity", reason),
                _ => invalid(&name, reason),
            },
            e => e,
        })?;
        bp5.cells(self.dx)?;
        as_setting("tolerance", bp5.fault_ode_options(self.tolerance))?;
        check_ranges(&[("epsilon", self.epsilon, r::EPSILON, "a relative accuracy")])?;
        as_setting("epsilon", bp5.half_space(self.epsilon))?;
        if self.kernel == Bp5Kernel::Fe {
            check_ranges(&[
                (
                    "domain_km",
                    self.domain_km(),
                    r::DOMAIN_KM,
                    "km: 1.5 l_f/2 and more",
                ),
                ("ratio", self.ratio(), r::RATIO, "the growth of the spacing"),
            ])?;
        }
        Ok(())
    }

    /// Refuses a setting of the finite-element kernel with Okada's (which has no volume:
    /// it would be ignored).
    fn check_volume_given(&self) -> rsf::Result<()> {
        if self.kernel == Bp5Kernel::Fe {
            return Ok(());
        }
        let text = |x: Option<f64>| x.map(rsf_numeric::written);
        let name = |v: Option<String>| v.map(|v| v.trim_matches('"').to_owned());
        let json = |v: serde_json::Value| name((!v.is_null()).then(|| v.to_string()));
        let given = [
            ("domain_km", text(self.domain_km)),
            ("ratio", text(self.ratio)),
            ("ordering", self.ordering.map(|o| o.to_string())),
            ("mesh", json(serde_json::json!(self.mesh))),
            ("condensation", json(serde_json::json!(self.condensation))),
            ("fault_zone_width_km", text(self.fault_zone_width_km)),
            ("fault_zone_rigidity", text(self.fault_zone_rigidity)),
        ];
        match given.into_iter().find_map(|(n, v)| Some((n, v?))) {
            Some((name, value)) => Err(invalid(
                name,
                format!(
                    "{value}: a setting of the finite-element kernel: it needs --kernel fe \
                     (kernel = \"fe\"; the Okada kernel has no volume), without it it would \
                     be ignored"
                ),
            )),
            None => Ok(()),
        }
    }

    /// The fault ODE's options of this run of `bp5` on `threads` threads: the scene's for
    /// the tolerance, the run's integrator. The finite-element kernel adds
    /// [`volume_options`](Self::volume_options) once its model is built.
    ///
    /// # Errors
    /// An invalid tolerance (named `tolerance`).
    pub fn fault_ode_options(&self, bp5: &SeasBp5, threads: usize) -> rsf::Result<FaultOdeOptions> {
        let mut options = as_setting("tolerance", bp5.fault_ode_options(self.tolerance))?;
        options.parallelism = rsf::Parallelism::rayon(threads);
        options.integrator = self.integrator;
        Ok(options)
    }

    /// `options` for the finite-element kernel's model of `slip_unknowns` unknowns on the
    /// fault: its condensed operator an ℋ-matrix of accuracy `epsilon` above 4 096 of
    /// them (dense below), the volume's factor ordered by `ordering` (of a run
    /// [`resolved`](Self::resolved) by the front end; AMD where unset).
    pub fn volume_options(
        &self,
        options: FaultOdeOptions,
        slip_unknowns: usize,
    ) -> FaultOdeOptions {
        FaultOdeOptions {
            kernel: if slip_unknowns > 4096 {
                FaultKernel::hierarchical(self.epsilon)
            } else {
                options.kernel
            },
            ordering: self.ordering_or(InteriorOrdering::Amd),
            ..options
        }
    }

    /// The headers of the run's files (`modeler`, `date` as the front end gives them).
    pub fn seas_setup(&self, bp5: &SeasBp5, modeler: String, date: String) -> SeasSetup {
        SeasSetup {
            problem: "SEAS Benchmark BP5-QD".into(),
            modeler,
            date,
            element_size: self.dx,
            stations: Vec::new(),
            depth_axis: 2,
            depth_down: false,
            sigma_n: bp5.sigma_n,
            profile_spacing: self.dx,
            sampling: SeasSampling::default(),
            layout: SeasLayout::default(),
            surface_stations: Vec::new(),
        }
    }

    /// The fingerprint of a checkpoint of this run of `bp5` (the scene of
    /// [`scene_with`](Self::scene_with)): every setting, those of the volume resolved
    /// with the finite-element kernel (Okada's has none: a checkpoint of a build with
    /// METIS resumes in one without), then the scene's other parameters as `scene.NAME`
    /// (the friction is the run's settings, named once).
    /// `ordering` is the front end's default.
    pub fn fingerprint_with(&self, bp5: &SeasBp5, ordering: InteriorOrdering) -> Fingerprint {
        let mut f = crate::run_config::with_scene(
            Fingerprint::of_serialized(&self.resolved(ordering)),
            bp5,
        );
        // The friction once, as the run's settings (`b0`, not `scene.b0` too: one name for
        // `--allow-change`).
        f.0.retain(|(k, _)| {
            k.strip_prefix("scene.")
                .is_none_or(|field| !Self::FRICTION.contains(&field))
        });
        f
    }
}

impl RunConfig for SeasBp5Run {
    /// [`validate_with`](Self::validate_with) the benchmark's scene.
    fn validate(&self) -> rsf::Result<()> {
        self.validate_with(SeasBp5::default())
    }

    /// [`fingerprint_with`](Self::fingerprint_with) this run's scene, AMD the ordering
    /// where unset (a front end with METIS resolves it first: [`resolved`](Self::resolved)).
    fn fingerprint(&self) -> Fingerprint {
        self.fingerprint_with(&self.scene(), InteriorOrdering::Amd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults validate and hold the description's friction; every range and the
    /// scene's `dx` refuse by the setting's name; the box is checked with the
    /// finite-element kernel alone, and refused with Okada's.
    #[test]
    fn refusals_name_the_setting() {
        let run = SeasBp5Run::default();
        assert!(run.validate().is_ok());
        assert_eq!(run.scene(), SeasBp5::default());
        let name = |r: SeasBp5Run| crate::refused_name(r.validate());
        assert_eq!(name(SeasBp5Run { dx: 3000.0, ..run }), "dx");
        assert_eq!(
            name(SeasBp5Run {
                end_years: -1.0,
                ..run
            }),
            "end_years"
        );
        assert_eq!(
            name(SeasBp5Run {
                epsilon: 0.5,
                ..run
            }),
            "epsilon"
        );
        assert_eq!(
            name(SeasBp5Run {
                tolerance: 0.0,
                ..run
            }),
            "tolerance"
        );
        assert_eq!(name(SeasBp5Run { b0: 0.0, ..run }), "b0");
        assert_eq!(name(SeasBp5Run { v_i: 1e3, ..run }), "v_i");
        assert_eq!(
            name(SeasBp5Run {
                domain_km: Some(400.0),
                ..run
            }),
            "domain_km"
        );
        let fe = SeasBp5Run {
            kernel: Bp5Kernel::Fe,
            ..run
        };
        assert!(fe.validate().is_ok());
        assert_eq!(
            name(SeasBp5Run {
                domain_km: Some(50.0),
                ..fe
            }),
            "domain_km"
        );
        assert_eq!(
            name(SeasBp5Run {
                ratio: Some(3.0),
                ..fe
            }),
            "ratio"
        );
        assert_eq!(
            name(SeasBp5Run {
                fault_zone_width_km: Some(4.0),
                ..fe
            }),
            "fault_zone_rigidity"
        );
    }

    /// The mesh and the condensation are in the finite-element run's fingerprint, not in
    /// Okada's (which refuses them); a default left unset and set to its value are one
    /// run; the friction is in both.
    #[test]
    fn the_fingerprint_holds_what_the_kernel_reads() {
        let okada = SeasBp5Run::default();
        let fe = SeasBp5Run {
            kernel: Bp5Kernel::Fe,
            ..okada
        };
        let factor = SeasBp5Run {
            condensation: Some(Bp5Condensation::Factor),
            ..fe
        };
        assert_ne!(factor.fingerprint(), fe.fingerprint());
        let nd = SeasBp5Run {
            ordering: Some(InteriorOrdering::NestedDissection),
            ..fe
        };
        assert_ne!(nd.fingerprint(), fe.fingerprint());
        assert_eq!(
            fe.fingerprint_with(&fe.scene(), InteriorOrdering::NestedDissection),
            nd.fingerprint()
        );
        let explicit = SeasBp5Run {
            domain_km: Some(400.0),
            ratio: Some(1.3),
            mesh: Some(SeasBp5Mesh::Graded),
            condensation: Some(Bp5Condensation::SchurOnly),
            ..fe
        };
        assert_eq!(explicit.fingerprint(), fe.fingerprint());
        let weaker = SeasBp5Run { b0: 0.02, ..okada };
        assert_ne!(weaker.fingerprint(), okada.fingerprint());
        assert_eq!(weaker.scene().b0, 0.02);
        // The friction is named once (`--allow-change b0` allows the change whole).
        let differing: Vec<_> = weaker
            .fingerprint()
            .0
            .into_iter()
            .zip(okada.fingerprint().0)
            .filter(|(a, b)| a != b)
            .map(|(a, _)| a.0)
            .collect();
        assert_eq!(differing, ["b0"]);
    }
}
