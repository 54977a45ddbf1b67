//! The run configurations of SEAS BP7 and BP8 (a square fault in a whole space): the
//! programs `seas_bp7` and `seas_bp8` derive their flags from them, read them from TOML
//! (`--config`), fingerprint their checkpoints and write `summary.json`'s `settings` with
//! them ([`RunConfig`], docs/reliability.md "One run configuration").

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::OdeIntegrator;
use rsf_seas::{SeasLayout, SeasSampling, SeasSetup};

use crate::invalid;
use crate::run_config::{check_ranges, RunConfig};
use crate::seas_bp7::{Bp7Law, SeasBp7};
use crate::seas_bp8::{Bp8Overpressure, Bp8Source, SeasBp8, BP8_SECONDS_PER_DAY};

/// `--help` of the fault ODE's integrator (the programs' `--integrator`).
pub const INTEGRATOR_HELP: &str = "The fault ODE's integrator: auto (Dormand–Prince 5(4) \
    while accuracy sets its step, the stabilised RKC2 while stability would), rkc (RKC2 \
    throughout), rosenbrock (the linearly implicit ROS34PW2 throughout), dormand-prince or \
    bogacki-shampine (the explicit pairs throughout); docs/math.md §12";

/// Seconds per year of BP7's `end_years` (365.25 days).
const SECONDS_PER_YEAR: f64 = 365.25 * 86_400.0;

/// The ranges of the square's settings, the same for BP7 and BP8.
pub mod square_ranges {
    use crate::setting_range;

    setting_range!(
        pub DX,
        DX_HELP = "Cell size on the fault (m), dividing 2 l_f = 800 m into whole cells (2 to 160 cells a side); at most l_f",
        [5, 400]
    );
    setting_range!(
        pub TOLERANCE,
        TOLERANCE_HELP = "Tolerance of the fault ODE (local error per step: tolerance · D_RS in slip, tolerance in ln θ)",
        [1e-12, 0.1]
    );
    setting_range!(
        pub STATION_INTERVAL,
        STATION_INTERVAL_HELP = "Seconds between station and `global.dat` rows (0: a row at every accepted step, the default)",
        [0, 1e7]
    );
    setting_range!(
        pub BP7_END_YEARS,
        BP7_END_YEARS_HELP = "End time (years of 365.25 days)",
        [1e-9, 1000]
    );
    setting_range!(
        pub BP7_D_RS,
        BP7_D_RS_HELP = "Characteristic slip distance D_RS (mm; docs/seas-bp7.md: 0.50 or 0.53)",
        [0.01, 100]
    );
    setting_range!(pub BP8_END_DAYS, BP8_END_DAYS_HELP = "End time (days)", [1e-6, 3650]);
    setting_range!(
        pub BP8_SIGMA_MIN,
        BP8_SIGMA_MIN_HELP = "`overpressure = floor`: the least effective normal stress (MPa; at most half of σ̄₀ = 25 MPa); the floor acts below twice this [default: 1]",
        [1e-3, 12.5]
    );
    setting_range!(
        pub FE_DOMAIN_KM,
        FE_DOMAIN_KM_HELP = "`kernel = fe`: half-width of the clamped box (km; at least 2 l_f = 0.8 km, rounded up to whole root cubes) [default: 6.4]",
        [0.8, 1000]
    );
    setting_range!(
        pub FE_RATIO,
        FE_RATIO_HELP = "`kernel = fe`: growth of the cells away from the square, dx + (ratio − 1)·distance [default: 1.2]",
        [1.01, 2]
    );
    setting_range!(
        pub BP8_PROFILE_INTERVAL,
        BP8_PROFILE_INTERVAL_HELP = "Seconds between profile rows (the description's hourly by default)",
        [60, 1e7]
    );
}
use square_ranges as r;

/// The rule every square's `dx` obeys: it divides `2 l_f` into whole cells.
fn check_cells(cells: rsf::Result<Vec<[f64; 2]>>, dx: f64, l_f: f64) -> rsf::Result<usize> {
    cells.map(|c| c.len()).map_err(|_| {
        invalid(
            "dx",
            format!(
                "{}: must divide 2 l_f = {} m",
                rsf_numeric::written(dx),
                rsf_numeric::number(2.0 * l_f)
            ),
        )
    })
}

/// The settings of a run of SEAS BP7-QD (the program `seas_bp7`'s flags, the keys of its
/// `--config` file, the fields of its checkpoints' fingerprint). [`Default`] is the
/// description's: the aging law, 10 m cells, 10 years, `D_RS = 0.50 mm`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct SeasBp7Run {
    /// The elastic operator: bem (the whole space's boundary elements) or fe (a
    /// finite-element box).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp7Run::default().kernel))]
    #[serde(skip_serializing_if = "SquareKernel::is_bem")]
    pub kernel: SquareKernel,
    /// `kernel = fe`: the box's half-width (km; [`SQUARE_FE_DOMAIN_KM`] if unset).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::FE_DOMAIN_KM_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub domain_km: Option<f64>,
    /// `kernel = fe`: the cells' growth ([`SQUARE_FE_RATIO`] if unset).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::FE_RATIO_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// The state law: aging (BP7-QD-A) or slip (BP7-QD-S).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp7Run::default().law))]
    pub law: Bp7Law,
    /// End time (years of 365.25 days).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp7Run::default().end_years, allow_negative_numbers = true, help = r::BP7_END_YEARS_HELP))]
    pub end_years: f64,
    /// Cell size (m), dividing `2 l_f = 800 m`.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp7Run::default().dx, allow_negative_numbers = true, help = r::DX_HELP))]
    pub dx: f64,
    /// `D_RS` (mm).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp7Run::default().d_rs, allow_negative_numbers = true, help = r::BP7_D_RS_HELP))]
    pub d_rs: f64,
    /// The fault ODE's tolerance.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp7Run::default().tolerance, allow_negative_numbers = true, help = r::TOLERANCE_HELP))]
    pub tolerance: f64,
    /// Seconds between station rows (0: every accepted step).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp7Run::default().station_interval, allow_negative_numbers = true, help = r::STATION_INTERVAL_HELP))]
    pub station_interval: f64,
    /// The fault ODE's integrator.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp7Run::default().integrator, help = INTEGRATOR_HELP))]
    pub integrator: OdeIntegrator,
}

impl Default for SeasBp7Run {
    fn default() -> Self {
        Self {
            kernel: SquareKernel::Bem,
            domain_km: None,
            ratio: None,
            law: Bp7Law::Aging,
            end_years: 10.0,
            dx: 10.0,
            d_rs: SeasBp7::default().d_rs * 1e3,
            tolerance: 1e-7,
            station_interval: 0.0,
            integrator: OdeIntegrator::Auto,
        }
    }
}

impl SeasBp7Run {
    /// The scene: [`SeasBp7::default`] with this run's `D_RS`.
    pub fn scene(&self) -> SeasBp7 {
        SeasBp7 {
            d_rs: self.d_rs * 1e-3,
            ..SeasBp7::default()
        }
    }

    /// The end time (s).
    pub fn end_seconds(&self) -> f64 {
        self.end_years * SECONDS_PER_YEAR
    }

    /// The files' headers and sampling of this run, by `modeler` on `date`
    /// (`YYYY-MM-DD`): a station row at every accepted step, or every
    /// `station_interval` seconds.
    pub fn seas_setup(&self, modeler: String, date: String) -> SeasSetup {
        let sampling = if self.station_interval == 0.0 {
            SeasSampling {
                every_step: true,
                ..SeasSampling::default()
            }
        } else {
            SeasSampling {
                station_quiet: self.station_interval,
                ..SeasSampling::default()
            }
        };
        square_setup(
            format!("SEAS Benchmark BP7-QD-{}", self.law.name()),
            (modeler, date),
            (self.dx, self.scene().sigma_n),
            sampling,
        )
    }

    /// The fault's cells (the rule `dx` divides `2 l_f`).
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx`.
    pub fn cells(&self) -> rsf::Result<usize> {
        let bp7 = self.scene();
        check_cells(bp7.cells(self.dx), self.dx, bp7.l_f)
    }

    /// The finite-element box with `kernel = fe` (`None` with the boundary elements).
    ///
    /// # Errors
    /// As [`SeasBp8Run::volume_grid`].
    pub fn volume_grid(&self) -> rsf::Result<Option<crate::SquareVolumeGrid>> {
        square_volume_grid(
            self.kernel,
            self.dx,
            (self.domain_km, self.ratio),
            self.scene().l_f,
        )
    }
}

impl RunConfig for SeasBp7Run {
    fn validate(&self) -> rsf::Result<()> {
        check_ranges(&[
            ("end_years", self.end_years, r::BP7_END_YEARS, "years"),
            ("d_rs", self.d_rs, r::BP7_D_RS, "mm"),
            ("dx", self.dx, r::DX, "m"),
        ])?;
        self.cells()?;
        self.volume_grid()?;
        check_ranges(&[
            ("tolerance", self.tolerance, r::TOLERANCE, ""),
            (
                "station_interval",
                self.station_interval,
                r::STATION_INTERVAL,
                "s",
            ),
        ])
    }

    /// Every setting, then the scene's parameters as `scene.NAME`.
    fn fingerprint(&self) -> Fingerprint {
        crate::run_config::with_scene(Fingerprint::of_serialized(self), &self.scene())
    }
}

/// The headers of a square's files: `problem`, `(modeler, date)`, the cell `dx` (m) as
/// the element size and the profiles' spacing, `sigma_n` (Pa), `sampling`; the strike–dip
/// layout (depth along x₃, downwards), no stations along dip.
fn square_setup(
    problem: String,
    (modeler, date): (String, String),
    (dx, sigma_n): (f64, f64),
    sampling: SeasSampling,
) -> SeasSetup {
    SeasSetup {
        problem,
        modeler,
        date,
        element_size: dx,
        stations: Vec::new(),
        depth_axis: 2,
        depth_down: true,
        sigma_n,
        profile_spacing: dx,
        sampling,
        layout: SeasLayout::default(),
        surface_stations: Vec::new(),
    }
}

/// The elastic operator of a square fault in a whole space.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum SquareKernel {
    /// The whole space's boundary elements on square cells, applied by FFTs
    /// (`rsf::halfspace_operator::WholeSpaceGrid`): exact up to round-off.
    #[default]
    Bem,
    /// A finite-element box condensed onto the fault's nodes
    /// ([`SquareVolumeGrid`](crate::SquareVolumeGrid): clamped faces, graded towards the
    /// square; docs/seas-bp8.md "The finite-element volume").
    Fe,
}

impl SquareKernel {
    /// Whether this is the default (left out of the fingerprint and TOML, so that the
    /// boundary-element runs keep theirs).
    fn is_bem(&self) -> bool {
        *self == Self::Bem
    }
}

/// The finite-element box of a square's run: `kernel`, `domain_km`, `ratio` as set;
/// refuses the box's settings without `kernel = fe`.
fn square_volume_grid(
    kernel: SquareKernel,
    dx: f64,
    (domain_km, ratio): (Option<f64>, Option<f64>),
    l_f: f64,
) -> rsf::Result<Option<crate::SquareVolumeGrid>> {
    if kernel == SquareKernel::Bem {
        for (name, value) in [("domain_km", domain_km), ("ratio", ratio)] {
            if let Some(v) = value {
                return Err(invalid(
                    name,
                    format!(
                        "{}: a setting of `kernel = fe` (the finite-element box): with the \
                         boundary elements it would be ignored",
                        rsf_numeric::written(v)
                    ),
                ));
            }
        }
        return Ok(None);
    }
    let domain_km = domain_km.unwrap_or(SQUARE_FE_DOMAIN_KM);
    let ratio = ratio.unwrap_or(SQUARE_FE_RATIO);
    check_ranges(&[
        ("domain_km", domain_km, r::FE_DOMAIN_KM, "km"),
        ("ratio", ratio, r::FE_RATIO, ""),
    ])?;
    let grid = crate::SquareVolumeGrid {
        dx,
        domain: domain_km * 1e3,
        ratio,
    };
    grid.check(l_f)?;
    Ok(Some(grid))
}

/// `domain_km`'s default: 6.4 km, 16 l_f (docs/seas-bp8.md, "The finite-element volume").
pub const SQUARE_FE_DOMAIN_KM: f64 = 6.4;

/// `ratio`'s default (docs/seas-bp8.md, "The finite-element volume").
pub const SQUARE_FE_RATIO: f64 = 1.2;

/// Where BP8's pore pressure would reach the normal stress (docs/seas-bp8.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp8OverpressureRule {
    /// The effective normal stress held above `sigma_min` by a smooth floor.
    #[default]
    Floor,
    /// The run stops where the effective normal stress would reach 0.
    Refuse,
}

/// The settings of a run of SEAS BP8-QD (the program `seas_bp8`'s flags, the keys of its
/// `--config` file, the fields of its checkpoints' fingerprint). [`Default`] is the
/// description's: the Gaussian source, 10 m cells, 30 days, the floor at 1 MPa.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct SeasBp8Run {
    /// The elastic operator: bem (the whole space's boundary elements) or fe (a
    /// finite-element box).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp8Run::default().kernel))]
    #[serde(skip_serializing_if = "SquareKernel::is_bem")]
    pub kernel: SquareKernel,
    /// `kernel = fe`: the box's half-width (km; [`SQUARE_FE_DOMAIN_KM`] if unset).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::FE_DOMAIN_KM_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub domain_km: Option<f64>,
    /// `kernel = fe`: the cells' growth ([`SQUARE_FE_RATIO`] if unset).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::FE_RATIO_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ratio: Option<f64>,
    /// The injection's source: gs (a Gaussian) or pw (a Peaceman well).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp8Run::default().source))]
    pub source: Bp8Source,
    /// End time (days).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp8Run::default().end_days, allow_negative_numbers = true, help = r::BP8_END_DAYS_HELP))]
    pub end_days: f64,
    /// Cell size (m), dividing `2 l_f = 800 m`.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp8Run::default().dx, allow_negative_numbers = true, help = r::DX_HELP))]
    pub dx: f64,
    /// The fault ODE's tolerance.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp8Run::default().tolerance, allow_negative_numbers = true, help = r::TOLERANCE_HELP))]
    pub tolerance: f64,
    /// Where the pressure would reach the normal stress (docs/seas-bp8.md).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp8Run::default().overpressure))]
    pub overpressure: Bp8OverpressureRule,
    /// `overpressure = floor`: the least effective normal stress (MPa; 1 if unset).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::BP8_SIGMA_MIN_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma_min: Option<f64>,
    /// Seconds between station rows (0: every accepted step).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp8Run::default().station_interval, allow_negative_numbers = true, help = r::STATION_INTERVAL_HELP))]
    pub station_interval: f64,
    /// Seconds between profile rows.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp8Run::default().profile_interval, allow_negative_numbers = true, help = r::BP8_PROFILE_INTERVAL_HELP))]
    pub profile_interval: f64,
    /// The fault ODE's integrator.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp8Run::default().integrator, help = INTEGRATOR_HELP))]
    pub integrator: OdeIntegrator,
}

impl Default for SeasBp8Run {
    fn default() -> Self {
        Self {
            kernel: SquareKernel::Bem,
            domain_km: None,
            ratio: None,
            source: Bp8Source::Gaussian,
            end_days: 30.0,
            dx: 10.0,
            tolerance: 1e-7,
            overpressure: Bp8OverpressureRule::Floor,
            sigma_min: None,
            station_interval: 0.0,
            profile_interval: 3600.0,
            integrator: OdeIntegrator::Auto,
        }
    }
}

impl SeasBp8Run {
    /// The policy where the pressure would reach the normal stress (`sigma_min` in Pa).
    pub fn overpressure(&self) -> Bp8Overpressure {
        match self.overpressure {
            Bp8OverpressureRule::Refuse => Bp8Overpressure::Refuse,
            Bp8OverpressureRule::Floor => Bp8Overpressure::Floor {
                sigma_min: self.sigma_min.unwrap_or(1.0) * 1e6,
            },
        }
    }

    /// The end time (s).
    pub fn end_seconds(&self) -> f64 {
        self.end_days * BP8_SECONDS_PER_DAY
    }

    /// The files' headers and sampling of this run, by `modeler` on `date`
    /// (`YYYY-MM-DD`): station rows every `station_interval` seconds (0: every accepted
    /// step), profile rows every `profile_interval` seconds.
    pub fn seas_setup(&self, modeler: String, date: String) -> SeasSetup {
        square_setup(
            format!("SEAS Benchmark BP8-QD-{}", self.source.name()),
            (modeler, date),
            (self.dx, SeasBp8::default().sigma_n),
            SeasSampling {
                every_step: self.station_interval == 0.0,
                station_quiet: self.station_interval,
                station_event: self.station_interval,
                profile_quiet: self.profile_interval,
                profile_event: self.profile_interval,
                ..SeasSampling::default()
            },
        )
    }

    /// The fault's cells (the rule `dx` divides `2 l_f`).
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx`.
    pub fn cells(&self) -> rsf::Result<usize> {
        let bp8 = SeasBp8::default();
        check_cells(bp8.cells(self.dx), self.dx, bp8.l_f)
    }

    /// The finite-element box with `kernel = fe` (`None` with the boundary elements).
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `domain_km` or `ratio`: out of range, or set
    /// without `kernel = fe`; as [`SquareVolumeGrid::check`](crate::SquareVolumeGrid::check).
    pub fn volume_grid(&self) -> rsf::Result<Option<crate::SquareVolumeGrid>> {
        square_volume_grid(
            self.kernel,
            self.dx,
            (self.domain_km, self.ratio),
            SeasBp8::default().l_f,
        )
    }
}

impl RunConfig for SeasBp8Run {
    fn validate(&self) -> rsf::Result<()> {
        check_ranges(&[
            ("end_days", self.end_days, r::BP8_END_DAYS, "days"),
            ("dx", self.dx, r::DX, "m"),
        ])?;
        self.cells()?;
        self.volume_grid()?;
        check_ranges(&[("tolerance", self.tolerance, r::TOLERANCE, "")])?;
        match (self.overpressure, self.sigma_min) {
            (Bp8OverpressureRule::Refuse, Some(s)) => {
                return Err(invalid(
                    "sigma_min",
                    format!(
                        "{}: a setting of `overpressure = floor`: with `refuse` it would be \
                         ignored",
                        rsf_numeric::written(s)
                    ),
                ))
            }
            (Bp8OverpressureRule::Floor, Some(s)) => {
                check_ranges(&[("sigma_min", s, r::BP8_SIGMA_MIN, "MPa, at most half of σ̄₀")])?
            }
            _ => {}
        }
        check_ranges(&[
            (
                "station_interval",
                self.station_interval,
                r::STATION_INTERVAL,
                "s",
            ),
            (
                "profile_interval",
                self.profile_interval,
                r::BP8_PROFILE_INTERVAL,
                "s",
            ),
        ])
    }

    /// Every setting, then the scene's parameters as `scene.NAME`.
    fn fingerprint(&self) -> Fingerprint {
        crate::run_config::with_scene(Fingerprint::of_serialized(self), &SeasBp8::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ranges' upper bounds are the scenes' `l_f` and half BP8's `σ̄₀` (written as
    /// literals for `--help`).
    #[test]
    fn the_bounds_are_the_scenes() {
        assert_eq!(r::DX.1, SeasBp7::default().l_f);
        assert_eq!(r::DX.1, SeasBp8::default().l_f);
        assert_eq!(r::BP8_SIGMA_MIN.1, 0.5 * SeasBp8::default().sigma_n / 1e6);
    }

    /// The defaults validate, and `D_RS`'s default is the scene's.
    #[test]
    fn the_defaults_are_valid() {
        SeasBp7Run::default().validate().unwrap();
        SeasBp8Run::default().validate().unwrap();
        assert_eq!(SeasBp7Run::default().scene(), SeasBp7::default());
    }
}
