//! A run of BP3 as every front end sets it up — the program `seas_bp3`'s flags and its
//! `--config` file's keys, the Python package's `rsf.seas_bp3` keywords: the settings, their
//! defaults and ranges (one place for every front end, [`RunConfig`]), the fault ODE's
//! options and the fingerprint a checkpoint of the run carries, so that a checkpoint of
//! either front end resumes in the other (docs/design.md, "One run configuration").

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{FaultKernel, FaultOdeOptions, OdeIntegrator};

use crate::run_config::{as_setting, check_ranges, fault_kernel, KernelChoice, RunConfig};
#[cfg(feature = "clap")]
use crate::run_config::{KERNEL_EPSILON_HELP, KERNEL_HELP, TOLERANCE_HELP};
#[cfg(feature = "clap")]
use crate::seas_square_run::INTEGRATOR_HELP;
use crate::{invalid, SeasBp1, SeasBp3, SeasBp3Grid};

/// The smallest step (s) of BP3's fault ODE: below the SEAS scenes' 1e-6 s, for the
/// normal stress's changes within an event (the program's value since BP3 first ran).
pub const BP3_DT_MIN: f64 = 1e-8;

/// The ranges of a BP3 run's settings and the flags' help texts (closed intervals, but
/// `DIP`'s upper end, which is open): the program's flags and the Python keywords of the
/// same names check them.
pub mod bp3_ranges {
    use crate::setting_range;

    /// `dip` (degrees), in `[1, 90)`: below 1° the fault is a flat detachment whose cells
    /// along the fault thin towards degenerate (measured: 1e-5° degenerates).
    pub const DIP: (f64, f64) = (1.0, 90.0);
    /// `--help` of `dip`.
    pub const DIP_HELP: &str = "Dip ψ (degrees): 60 (thrust) or 30 (normal); in [1, 90) (below 1°, a flat detachment, the mesh's cells along the fault thin towards degenerate)";
    setting_range!(pub END_YEARS, END_YEARS_HELP = "End time (years)", [1e-9, 1e5]);
    setting_range!(
        pub DX,
        DX_HELP = "Element size along the fault (m); at most W_f/4 = 10 km",
        [1e-3, 1e4]
    );
    setting_range!(
        pub DOMAIN_KM,
        DOMAIN_KM_HELP = "Half-width L of the box across the fault (km); its depth is L sin ψ, which must reach beyond 1.5 W_f = 60 km. The default moves the first event by < 0.1 yr against a box twice as large (docs/seas-bp3.md)",
        [60.00006, 1e5]
    );
    setting_range!(
        pub RATIO,
        RATIO_HELP = "Growth of the elements away from the fault and below W_f. The default is within 0.2 yr of a ratio of 1.0125 in the first event; 1.1 puts the normal fault's 2.9 yr early (docs/seas-bp3.md, \"Mesh grading\")",
        [1, 2]
    );
}
use bp3_ranges as r;

/// The settings of a BP3 run (the program's flags and `--config` keys, Python's
/// keywords). [`Default`] is the program's defaults: the thrust (60°), 500 m elements in a
/// ±1600 km box graded by 1.025, tolerance 1e-7, the ℋ-kernel matching it, 300 years.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct SeasBp3Run {
    /// Dip ψ (degrees): below 45° the normal fault (slip negative), else the thrust.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp3Run::default().dip, allow_negative_numbers = true, help = r::DIP_HELP))]
    pub dip: f64,
    /// The end time (years of [`rsf_seas::SECONDS_PER_YEAR`]).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp3Run::default().end_years, allow_negative_numbers = true, help = r::END_YEARS_HELP))]
    pub end_years: f64,
    /// Element size along the fault (m).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp3Run::default().dx, allow_negative_numbers = true, help = r::DX_HELP))]
    pub dx: f64,
    /// Half-width `L` of the box across the fault (km).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp3Run::default().domain_km, allow_negative_numbers = true, help = r::DOMAIN_KM_HELP))]
    pub domain_km: f64,
    /// Growth of the elements away from the fault.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp3Run::default().ratio, allow_negative_numbers = true, help = r::RATIO_HELP))]
    pub ratio: f64,
    /// Tolerance of the fault ODE, in `(f64::EPSILON, 1)`.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp3Run::default().tolerance, allow_negative_numbers = true, help = TOLERANCE_HELP))]
    pub tolerance: f64,
    /// The operators condensed onto the fault: `hierarchical` (the default) or `dense`.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp3Run::default().kernel, help = KERNEL_HELP))]
    pub kernel: KernelChoice,
    /// Relative accuracy of the hierarchical kernel (default: the tolerance, within its
    /// range).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = KERNEL_EPSILON_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kernel_epsilon: Option<f64>,
    /// The fault ODE's integrator.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp3Run::default().integrator, help = INTEGRATOR_HELP))]
    pub integrator: OdeIntegrator,
}

impl Default for SeasBp3Run {
    fn default() -> Self {
        Self {
            dip: 60.0,
            end_years: 300.0,
            dx: 500.0,
            domain_km: SeasBp3Grid::default().domain / 1e3,
            ratio: SeasBp3Grid::default().ratio,
            tolerance: 1e-7,
            kernel: KernelChoice::Hierarchical,
            kernel_epsilon: None,
            integrator: OdeIntegrator::Auto,
        }
    }
}

impl SeasBp3Run {
    /// The scene of `params` (BP1's table, which BP3 shares) at this run's dip: the normal
    /// fault below 45°, the thrust from it.
    pub fn scene(&self, params: SeasBp1) -> SeasBp3 {
        let case = if self.dip < 45.0 {
            SeasBp3::normal()
        } else {
            SeasBp3::thrust()
        };
        SeasBp3 {
            params,
            dip_degrees: self.dip,
            ..case
        }
    }

    /// The mesh's grid.
    pub fn grid(&self) -> SeasBp3Grid {
        SeasBp3Grid {
            dx: self.dx,
            domain: self.domain_km * 1e3,
            ratio: self.ratio,
        }
    }

    /// The fault kernel of the settings ([`fault_kernel`]).
    ///
    /// # Errors
    /// `kernel_epsilon` refused.
    pub fn fault_kernel(&self) -> rsf::Result<FaultKernel> {
        fault_kernel(self.kernel, self.kernel_epsilon, self.tolerance)
    }

    /// Checks every setting against its range ([`bp3_ranges`]), the tolerance (the
    /// fault ODE's options of `params`, BP1's table) and the kernel.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named by the setting (the Python keyword; the flag
    /// with `--` and dashes).
    pub fn validate_with(&self, params: &SeasBp1) -> rsf::Result<()> {
        if !(self.dip >= r::DIP.0 && self.dip < r::DIP.1) {
            return Err(invalid(
                "dip",
                format!(
                    "{}: must be in [1, 90) degrees: below 1° the fault is a flat detachment, \
                     whose cells along the fault thin towards degenerate",
                    rsf_numeric::written(self.dip)
                ),
            ));
        }
        check_ranges(&[
            ("end_years", self.end_years, r::END_YEARS, "years"),
            ("dx", self.dx, r::DX, "m: at most W_f/4"),
            (
                "domain_km",
                self.domain_km,
                r::DOMAIN_KM,
                "km: the box must reach 1.5 W_f down the fault",
            ),
            ("ratio", self.ratio, r::RATIO, "the growth of the elements"),
        ])?;
        as_setting("tolerance", params.fault_ode_options(self.tolerance))?;
        self.fault_kernel().map(|_| ())
    }

    /// The fault ODE's options of this run of `bp3` on `threads` threads: the scene's for
    /// the tolerance, steps from [`BP3_DT_MIN`], the run's kernel and integrator.
    ///
    /// # Errors
    /// An invalid tolerance (named `tolerance`) or kernel accuracy (`kernel_epsilon`).
    pub fn fault_ode_options(&self, bp3: &SeasBp3, threads: usize) -> rsf::Result<FaultOdeOptions> {
        let mut options = as_setting("tolerance", bp3.params.fault_ode_options(self.tolerance))?;
        options.runge_kutta.dt_min = BP3_DT_MIN;
        options.kernel = self.fault_kernel()?;
        options.integrator = self.integrator;
        options.parallelism = rsf::Parallelism::rayon(threads);
        Ok(options)
    }

    /// The fingerprint of a checkpoint of this run with the scene's parameters `params`
    /// (BP1's table): every setting, then the parameters as `scene.NAME`.
    pub fn fingerprint_with(&self, params: &SeasBp1) -> Fingerprint {
        crate::run_config::with_scene(Fingerprint::of_serialized(self), params)
    }
}

impl RunConfig for SeasBp3Run {
    /// [`validate_with`](Self::validate_with) BP1's table.
    fn validate(&self) -> rsf::Result<()> {
        self.validate_with(&SeasBp1::default())
    }

    /// Every setting, then BP1's table as `scene.NAME`
    /// ([`fingerprint_with`](Self::fingerprint_with)).
    fn fingerprint(&self) -> Fingerprint {
        self.fingerprint_with(&SeasBp1::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults validate and are the scene's grid's box; the dip chooses the case.
    #[test]
    fn the_defaults_validate_and_the_dip_chooses_the_case() {
        let run = SeasBp3Run::default();
        let bp3 = run.scene(SeasBp1::default());
        assert!(run.validate().is_ok());
        assert!(!bp3.normal_faulting);
        assert_eq!(run.grid().domain, SeasBp3Grid::default().domain);
        let normal = SeasBp3Run { dip: 30.0, ..run }.scene(SeasBp1::default());
        assert!(normal.normal_faulting);
        assert_eq!(normal.dip_degrees, 30.0);
    }

    /// Every range refuses by the setting's name; the dip, the integrator and the kernel
    /// are in the fingerprint.
    #[test]
    fn refusals_name_the_setting_and_the_fingerprint_holds_the_settings() {
        let run = SeasBp3Run::default();
        let name = |r: SeasBp3Run| crate::refused_name(r.validate());
        assert_eq!(name(SeasBp3Run { dip: 90.0, ..run }), "dip");
        assert_eq!(name(SeasBp3Run { dip: 0.5, ..run }), "dip");
        assert_eq!(name(SeasBp3Run { dx: 2e4, ..run }), "dx");
        assert_eq!(
            name(SeasBp3Run {
                domain_km: 60.0,
                ..run
            }),
            "domain_km"
        );
        assert_eq!(
            name(SeasBp3Run {
                ratio: f64::NAN,
                ..run
            }),
            "ratio"
        );
        assert_eq!(
            name(SeasBp3Run {
                end_years: 0.0,
                ..run
            }),
            "end_years"
        );
        assert_eq!(
            name(SeasBp3Run {
                tolerance: 2.0,
                ..run
            }),
            "tolerance"
        );
        let f = run.fingerprint();
        for other in [
            SeasBp3Run { dip: 59.0, ..run },
            SeasBp3Run {
                integrator: OdeIntegrator::Rkc,
                ..run
            },
            SeasBp3Run {
                kernel: KernelChoice::Dense,
                ..run
            },
        ] {
            assert_ne!(other.fingerprint(), f);
        }
    }

    /// `dx`'s and `domain_km`'s bounds are the scene's W_f/4 and just beyond 1.5 W_f
    /// (the ranges are written as literals, for `--help`).
    #[test]
    fn the_bounds_are_the_scenes() {
        let w_f = SeasBp1::default().w_f;
        assert_eq!(r::DX.1, w_f / 4.0);
        let least = 1.5 * w_f / 1e3;
        assert!(r::DOMAIN_KM.0 > least && r::DOMAIN_KM.0 < least * 1.00001);
    }
}
