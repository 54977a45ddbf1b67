//! A run of BP3 as every front end sets it up — the program `seas_bp3`'s flags and the
//! Python package's `rsf.seas_bp3` keywords: the settings, their defaults and ranges (one
//! place for both front ends), the fault ODE's options and the fingerprint a checkpoint
//! of the run carries, so that a checkpoint of either front end resumes in the other
//! (docs/reliability.md, "Round 5").

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{integrator_fingerprint, FaultKernel, FaultOdeOptions, OdeIntegrator};

use crate::{check_ranges, invalid, SeasBp1, SeasBp3, SeasBp3Grid};

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

/// The settings of a BP3 run (the program's flags, Python's keywords). [`Default`] is the
/// program's defaults: the thrust (60°), 500 m elements in a ±1600 km box graded by
/// 1.025, tolerance 1e-7, the ℋ-kernel matching it, 300 years.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeasBp3Run {
    /// Dip ψ (degrees): below 45° the normal fault (slip negative), else the thrust.
    pub dip: f64,
    /// Element size along the fault (m).
    pub dx: f64,
    /// Half-width `L` of the box across the fault (km).
    pub domain_km: f64,
    /// Growth of the elements away from the fault.
    pub ratio: f64,
    /// Tolerance of the fault ODE, in `(f64::EPSILON, 1)`.
    pub tolerance: f64,
    /// The fault's operator.
    pub kernel: FaultKernel,
    /// The fault ODE's integrator.
    pub integrator: OdeIntegrator,
    /// The end time (years of [`rsf_seas::SECONDS_PER_YEAR`]).
    pub end_years: f64,
}

impl Default for SeasBp3Run {
    fn default() -> Self {
        let tolerance = 1e-7;
        Self {
            dip: 60.0,
            dx: 500.0,
            domain_km: SeasBp3Grid::default().domain / 1e3,
            ratio: SeasBp3Grid::default().ratio,
            tolerance,
            kernel: FaultKernel::matching(tolerance),
            integrator: OdeIntegrator::Auto,
            end_years: 300.0,
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

    /// Checks every setting against its range ([`bp3_ranges`]), the tolerance (the
    /// fault ODE's options of `bp3`) and the kernel.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named by the setting (the Python keyword; the flag
    /// with `--` and dashes).
    pub fn validate(&self, bp3: &SeasBp3) -> rsf::Result<()> {
        use bp3_ranges as r;
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
        bp3.params.fault_ode_options(self.tolerance)?;
        self.kernel.validate()
    }

    /// The fault ODE's options of this run of `bp3` on `threads` threads: the scene's for
    /// the tolerance, steps from [`BP3_DT_MIN`], the run's kernel and integrator.
    ///
    /// # Errors
    /// An invalid tolerance (named `tolerance`).
    pub fn fault_ode_options(&self, bp3: &SeasBp3, threads: usize) -> rsf::Result<FaultOdeOptions> {
        let mut options = bp3.params.fault_ode_options(self.tolerance)?;
        options.runge_kutta.dt_min = BP3_DT_MIN;
        options.kernel = self.kernel;
        options.integrator = self.integrator;
        options.parallelism = rsf::Parallelism::rayon(threads);
        Ok(options)
    }

    /// The fingerprint of a checkpoint of this run of `bp3`: the scene's parameters, the
    /// dip and the case, the grid, the end, the tolerance, the kernel and the integrator.
    pub fn fingerprint(&self, bp3: &SeasBp3) -> Fingerprint {
        let f = Fingerprint::of_serialized(&bp3.params)
            .with("dip_degrees", self.dip)
            .with("normal_faulting", bp3.normal_faulting)
            .with("dx", self.dx)
            .with("domain_km", self.domain_km)
            .with("ratio", self.ratio)
            .with("end_years", self.end_years)
            .with("tolerance", self.tolerance)
            .with("kernel", self.kernel);
        integrator_fingerprint(f, self.integrator)
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
        assert!(run.validate(&bp3).is_ok());
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
        let bp3 = run.scene(SeasBp1::default());
        let name = |r: SeasBp3Run| match r.validate(&bp3) {
            Err(rsf::Error::InvalidParameter { name, .. }) => name,
            other => panic!("{other:?}"),
        };
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
        let f = run.fingerprint(&bp3);
        for other in [
            SeasBp3Run { dip: 59.0, ..run },
            SeasBp3Run {
                integrator: OdeIntegrator::Rkc,
                ..run
            },
            SeasBp3Run {
                kernel: FaultKernel::Dense,
                ..run
            },
        ] {
            assert_ne!(other.fingerprint(&other.scene(SeasBp1::default())), f);
        }
    }
}
