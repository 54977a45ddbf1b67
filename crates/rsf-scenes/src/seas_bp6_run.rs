//! A run of BP6 as every front end sets it up — the program `seas_bp6`'s flags and its
//! `--config` file's keys, the Python package's `rsf.seas_bp6` keywords: the settings,
//! their defaults, ranges and the rules between them (one place for every front end,
//! [`RunConfig`]), and the fingerprint a checkpoint of the run carries, so that a
//! checkpoint of either front end resumes in the other (docs/design.md, "One run
//! configuration").

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{FaultKernel, OdeIntegrator};
use rsf::whole_space::WholeSpaceKernel;

use crate::invalid;
use crate::run_config::{check_ranges, fault_kernel, KernelChoice, RunConfig};
#[cfg(feature = "clap")]
use crate::run_config::{KERNEL_EPSILON_HELP, KERNEL_HELP};
use crate::seas_bp6::{Bp6Pressure, Bp6Variant, SeasBp6, SeasBp6Grid};
#[cfg(feature = "clap")]
use crate::seas_square_run::INTEGRATOR_HELP;

/// The elastic kernel of a BP6 run: `bem` or `fe`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp6Elastic {
    /// The whole space's boundary-element kernel on the fault alone (the default).
    #[default]
    Bem,
    /// The finite-element half space condensed onto the fault (C: the implicit scheme on
    /// the volume).
    Fe,
}

/// How the boundary-element kernel's products are computed: `fft` or `stored`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp6BemProduct {
    /// FFTs of the Toeplitz kernel's circulant embedding: exact up to round-off,
    /// O(n log n) per product (the default).
    #[default]
    Fft,
    /// The kernel stored as [`SeasBp6Run::kernel`] says (dense, or an ℋ-matrix).
    Stored,
}

/// How a BP6 run computes the pore pressure: `closed-form` or `diffusion` (on
/// [`SeasBp6Run::diffusion_cells`] cells; [`Bp6Pressure`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp6PressureChoice {
    /// The description's closed form (the default).
    #[default]
    ClosedForm,
    /// The diffusion solved on `diffusion_cells` cells between no-flux ends at ±l_f.
    Diffusion,
}

/// Cells of the pore pressure's diffusion along `2 l_f` unless a run says otherwise
/// ([`Bp6Pressure::Diffusion`]).
pub const BP6_DIFFUSION_CELLS: usize = 800;

/// The first step (s) of BP6-C's implicit scheme, from which its steps adapt.
pub const BP6_C_FIRST_STEP: f64 = 60.0;

/// The ranges of a BP6 run's settings (closed intervals) and the flags' help texts: the
/// program's flags, its `--config` keys and the Python keywords of the same names check
/// them.
pub mod bp6_ranges {
    use crate::setting_range;

    setting_range!(
        pub END_YEARS,
        END_YEARS_HELP = "End time (years of 365 days)",
        [1e-9, 100]
    );
    setting_range!(
        pub DZ,
        DZ_HELP = "Cell (BEM) or element (FE) size along the fault (m), dividing 2 l_f = 40 km into whole cells; at most l_f/2",
        [0.4, 10e3]
    );
    setting_range!(
        pub DOMAIN_KM,
        DOMAIN_KM_HELP = "FE: the truncation of the half space, 0 ≤ x ≤ L, |z| ≤ L (km)",
        [30, 1e5]
    );
    setting_range!(
        pub RATIO,
        RATIO_HELP = "FE: growth of the elements away from the fault",
        [1, 2]
    );
    setting_range!(
        pub TOLERANCE,
        TOLERANCE_HELP = "Tolerance: of the fault ODE (a, s), of the implicit steps' slip error relative to D_RS (c) [default: 1e-7 for a and s, 1e-3 for c]",
        [1e-12, 0.1]
    );
    setting_range!(
        pub STATION_INTERVAL,
        STATION_INTERVAL_HELP = "Seconds between station and `global.dat` rows (0: a row at every accepted step, the default — a transient of the slip law lasts minutes, D_RS/V)",
        [0, 1e7]
    );
    setting_range!(
        pub PROFILE_INTERVAL,
        PROFILE_INTERVAL_HELP = "Seconds between profile rows",
        [60, 1e7]
    );
    setting_range!(
        pub DIFFUSION_CELLS,
        DIFFUSION_CELLS_HELP = "Cells of the diffusion along 2 l_f (`--pressure diffusion`) [default: 800]; at most rsf::pore_pressure::MAX_DIFFUSION_CELLS",
        [2, 20000]
    );
    /// Cells of BP6-C on the boundary-element kernel, whose stiffness is formed densely.
    pub const C_BEM_MAX_CELLS: f64 = 20_000.0;
}
use bp6_ranges as r;

const _: () = assert!(r::DIFFUSION_CELLS.1 == rsf::pore_pressure::MAX_DIFFUSION_CELLS as f64);

impl Bp6Pressure {
    /// Checks the diffusion's cells against [`bp6_ranges::DIFFUSION_CELLS`].
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `diffusion_cells`.
    pub fn validate(&self) -> rsf::Result<()> {
        if let Self::Diffusion { cells } = *self {
            check_ranges(&[("diffusion_cells", cells as f64, r::DIFFUSION_CELLS, "cells")])?;
        }
        Ok(())
    }
}

impl Bp6Variant {
    /// The default tolerance of the variant's run: of the fault ODE (A, S: 1e-7), of the
    /// implicit steps' slip error relative to `D_RS` (C: 1e-3).
    pub fn default_tolerance(self) -> f64 {
        match self {
            Self::C => 1e-3,
            _ => 1e-7,
        }
    }
}

/// The settings of a BP6 run (the program's flags and `--config` keys, Python's
/// keywords). [`Default`] is the program's defaults: BP6-A on 10 m cells of the FFT
/// boundary-element kernel, the closed-form pressure, 2 years. A setting left `None`
/// takes its default where the run uses it (the variant's tolerance, the FFT product,
/// 800 diffusion cells); one set where the run would ignore it is refused.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct SeasBp6Run {
    /// The variant: a (aging law), s (slip law), c (constant friction).
    #[cfg_attr(feature = "clap", arg(long, value_enum, ignore_case = true, default_value_t = SeasBp6Run::default().variant))]
    pub variant: Bp6Variant,
    /// The end time (years of 365 days).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp6Run::default().end_years, allow_negative_numbers = true, help = r::END_YEARS_HELP))]
    pub end_years: f64,
    /// Cell (BEM) or element (FE) size along the fault (m), dividing `2 l_f`.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp6Run::default().dz, allow_negative_numbers = true, help = r::DZ_HELP))]
    pub dz: f64,
    /// The elastic kernel: bem (the default, for c too, whose finite-element model at the
    /// default 10 m would need about 50 GB) or fe.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp6Run::default().elastic))]
    pub elastic: Bp6Elastic,
    /// BEM: how the kernel's products are computed [default: fft].
    #[cfg_attr(feature = "clap", arg(long, value_enum))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bem_product: Option<Bp6BemProduct>,
    /// FE: the truncation of the half space (km).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp6Run::default().domain_km, allow_negative_numbers = true, help = r::DOMAIN_KM_HELP))]
    pub domain_km: f64,
    /// FE: the elements' growth away from the fault.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp6Run::default().ratio, allow_negative_numbers = true, help = r::RATIO_HELP))]
    pub ratio: f64,
    /// The tolerance (default: [`Bp6Variant::default_tolerance`]).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::TOLERANCE_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// The pore pressure.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp6Run::default().pressure))]
    pub pressure: Bp6PressureChoice,
    /// Seconds between station and `global.dat` rows (0: every accepted step).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp6Run::default().station_interval, allow_negative_numbers = true, help = r::STATION_INTERVAL_HELP))]
    pub station_interval: f64,
    /// Seconds between profile rows.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = SeasBp6Run::default().profile_interval, allow_negative_numbers = true, help = r::PROFILE_INTERVAL_HELP))]
    pub profile_interval: f64,
    /// Cells of the diffusion along `2 l_f` (`pressure = diffusion`; default
    /// [`BP6_DIFFUSION_CELLS`]).
    #[cfg_attr(feature = "clap", arg(long, help = r::DIFFUSION_CELLS_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diffusion_cells: Option<usize>,
    /// The stored kernel (`bem_product = stored`, or the FE model's condensed operator).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp6Run::default().kernel, help = KERNEL_HELP))]
    pub kernel: KernelChoice,
    /// Relative accuracy of the hierarchical kernel (default: the tolerance, within its
    /// range).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = KERNEL_EPSILON_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kernel_epsilon: Option<f64>,
    /// The fault ODE's integrator (A, S).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = SeasBp6Run::default().integrator, help = INTEGRATOR_HELP))]
    pub integrator: OdeIntegrator,
}

impl Default for SeasBp6Run {
    fn default() -> Self {
        let grid = SeasBp6Grid::default();
        Self {
            variant: Bp6Variant::A,
            end_years: 2.0,
            dz: grid.dz,
            elastic: Bp6Elastic::Bem,
            bem_product: None,
            domain_km: grid.domain / 1e3,
            ratio: grid.ratio,
            tolerance: None,
            pressure: Bp6PressureChoice::ClosedForm,
            station_interval: 0.0,
            profile_interval: 10_800.0,
            diffusion_cells: None,
            kernel: KernelChoice::Hierarchical,
            kernel_epsilon: None,
            integrator: OdeIntegrator::Auto,
        }
    }
}

impl SeasBp6Run {
    /// The tolerance: the setting, or the variant's default.
    pub fn tolerance(&self) -> f64 {
        self.tolerance.unwrap_or(self.variant.default_tolerance())
    }

    /// The boundary-element product: the setting, or the FFT's.
    pub fn bem_product(&self) -> Bp6BemProduct {
        self.bem_product.unwrap_or_default()
    }

    /// The pore pressure: the closed form, or the diffusion on `diffusion_cells` cells
    /// (default [`BP6_DIFFUSION_CELLS`]).
    pub fn pressure(&self) -> Bp6Pressure {
        match self.pressure {
            Bp6PressureChoice::ClosedForm => Bp6Pressure::ClosedForm,
            Bp6PressureChoice::Diffusion => Bp6Pressure::Diffusion {
                cells: self.diffusion_cells.unwrap_or(BP6_DIFFUSION_CELLS),
            },
        }
    }

    /// The stored kernel (`bem_product = stored`, or the FE model's condensed operator):
    /// its accuracy the tolerance, at most 1e-2, unless `kernel_epsilon` says
    /// ([`fault_kernel`]).
    ///
    /// # Errors
    /// `kernel_epsilon` refused.
    pub fn fault_kernel(&self) -> rsf::Result<FaultKernel> {
        fault_kernel(self.kernel, self.kernel_epsilon, self.tolerance().min(1e-2))
    }

    /// The boundary-element kernel's product: FFTs, or the stored kernel.
    ///
    /// # Errors
    /// `kernel_epsilon` refused.
    pub fn bem_kernel(&self) -> rsf::Result<WholeSpaceKernel> {
        Ok(match self.bem_product() {
            Bp6BemProduct::Fft => WholeSpaceKernel::Fft,
            Bp6BemProduct::Stored => WholeSpaceKernel::Stored(self.fault_kernel()?),
        })
    }

    /// The finite-element grid.
    pub fn grid(&self) -> SeasBp6Grid {
        SeasBp6Grid {
            dz: self.dz,
            domain: self.domain_km * 1e3,
            ratio: self.ratio,
        }
    }

    /// Cells (BEM) or fault nodes (FE) along `2 l_f` of `bp6`.
    pub fn cells(&self, bp6: &SeasBp6) -> f64 {
        2.0 * bp6.l_f / self.dz
    }

    /// Checks every setting against its range ([`bp6_ranges`]) and the rules between
    /// them for the scene `bp6`: `dz` divides `2 l_f`, BP6-C on the boundary-element
    /// kernel at most [`bp6_ranges::C_BEM_MAX_CELLS`] cells, no setting the run would
    /// ignore (`bem_product` with the finite elements, `kernel` or `kernel_epsilon` with
    /// the FFT product, `diffusion_cells` with the closed form).
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named by the setting (the Python keyword; the flag
    /// with `--` and dashes).
    pub fn validate_with(&self, bp6: &SeasBp6) -> rsf::Result<()> {
        check_ranges(&[
            ("end_years", self.end_years, r::END_YEARS, "years"),
            ("dz", self.dz, r::DZ, "m"),
        ])?;
        let cells = self.cells(bp6);
        if (cells - cells.round()).abs() > 1e-9 * cells {
            return Err(invalid(
                "dz",
                format!(
                    "{}: must divide 2 l_f = {} m",
                    rsf_numeric::written(self.dz),
                    rsf_numeric::number(2.0 * bp6.l_f)
                ),
            ));
        }
        if self.variant == Bp6Variant::C
            && self.elastic == Bp6Elastic::Bem
            && cells > r::C_BEM_MAX_CELLS
        {
            return Err(invalid(
                "dz",
                format!(
                    "{}: BP6-C on the boundary-element kernel forms its stiffness densely: \
                     at most {} cells",
                    rsf_numeric::written(self.dz),
                    rsf_numeric::number(r::C_BEM_MAX_CELLS)
                ),
            ));
        }
        self.check_ignored()?;
        // The finite-element settings are checked whatever the kernel: a value refused
        // with `elastic = fe` is a careless input with the default kernel too.
        check_ranges(&[
            (
                "domain_km",
                self.domain_km,
                r::DOMAIN_KM,
                "km: beyond 1.5 l_f",
            ),
            ("ratio", self.ratio, r::RATIO, "the growth of the elements"),
            ("tolerance", self.tolerance(), r::TOLERANCE, ""),
            (
                "station_interval",
                self.station_interval,
                r::STATION_INTERVAL,
                "s",
            ),
            (
                "profile_interval",
                self.profile_interval,
                r::PROFILE_INTERVAL,
                "s",
            ),
        ])?;
        self.pressure().validate()?;
        self.fault_kernel().map(|_| ())
    }

    /// Refuses the settings the chosen kernel or pressure would ignore.
    fn check_ignored(&self) -> rsf::Result<()> {
        let name = |v: &dyn std::fmt::Debug| format!("{v:?}").to_lowercase();
        match (self.elastic, self.bem_product) {
            (Bp6Elastic::Fe, Some(product)) => {
                return Err(invalid(
                    "bem_product",
                    format!(
                        "{}: a setting of the boundary-element kernel (elastic bem): the \
                         finite-element model would ignore it",
                        name(&product)
                    ),
                ))
            }
            (Bp6Elastic::Bem, _) if self.bem_product() == Bp6BemProduct::Fft => {
                let (setting, value) = match self.kernel_epsilon {
                    Some(e) => ("kernel_epsilon", rsf_numeric::written(e)),
                    None => ("kernel", name(&self.kernel)),
                };
                if self.kernel_epsilon.is_some() || self.kernel != KernelChoice::Hierarchical {
                    return Err(invalid(
                        setting,
                        format!(
                            "{value}: kernel and kernel_epsilon (--kernel, --kernel-epsilon) \
                             set the stored kernel of bem_product stored: the FFT product \
                             (the default) would ignore them"
                        ),
                    ));
                }
            }
            _ => {}
        }
        match (self.pressure, self.diffusion_cells) {
            (Bp6PressureChoice::ClosedForm, Some(cells)) => Err(invalid(
                "diffusion_cells",
                format!(
                    "{cells}: a setting of pressure diffusion: with the closed form it \
                     would be ignored"
                ),
            )),
            _ => Ok(()),
        }
    }

    /// The fingerprint of a checkpoint of this run of `bp6`: every setting, the defaults
    /// of those left unset resolved (the tolerance, the product, the diffusion's cells),
    /// the integrator of A and S only (BP6-C's implicit scheme takes none), then the
    /// scene's parameters as `scene.NAME`.
    pub fn fingerprint_with(&self, bp6: &SeasBp6) -> Fingerprint {
        let resolved = Self {
            tolerance: Some(self.tolerance()),
            bem_product: (self.elastic == Bp6Elastic::Bem).then(|| self.bem_product()),
            diffusion_cells: match self.pressure() {
                Bp6Pressure::Diffusion { cells } => Some(cells),
                Bp6Pressure::ClosedForm => None,
            },
            integrator: match self.variant {
                Bp6Variant::C => OdeIntegrator::default(),
                _ => self.integrator,
            },
            ..*self
        };
        crate::run_config::with_scene(Fingerprint::of_serialized(&resolved), bp6)
    }
}

impl RunConfig for SeasBp6Run {
    /// [`validate_with`](Self::validate_with) the benchmark's scene.
    fn validate(&self) -> rsf::Result<()> {
        self.validate_with(&SeasBp6::default())
    }

    /// [`fingerprint_with`](Self::fingerprint_with) the benchmark's scene.
    fn fingerprint(&self) -> Fingerprint {
        self.fingerprint_with(&SeasBp6::default())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults are those of the scene's grid and of the variant.
    #[test]
    fn the_defaults_are_the_grids_and_the_variants() {
        let run = SeasBp6Run::default();
        let grid = SeasBp6Grid::default();
        assert_eq!(run.grid(), grid);
        assert_eq!(run.tolerance(), Bp6Variant::A.default_tolerance());
        let c = SeasBp6Run {
            variant: Bp6Variant::C,
            ..run
        };
        assert_eq!(c.tolerance(), 1e-3);
        assert_eq!(c.fault_kernel().unwrap(), FaultKernel::matching(1e-3));
        assert!(run.validate().is_ok());
        assert!(c.validate().is_ok());
        // `dz`'s upper bound is l_f/2 (the range is written as a literal, for `--help`).
        assert_eq!(r::DZ.1, SeasBp6::default().l_f / 2.0);
    }

    /// Every range and rule refuses by the setting's name; the integrator is in A's
    /// fingerprint, not in C's; a default left unset and set to its value are one run.
    #[test]
    fn refusals_name_the_setting_and_c_has_no_integrator() {
        let run = SeasBp6Run::default();
        let name = |r: SeasBp6Run| crate::refused_name(r.validate());
        assert_eq!(name(SeasBp6Run { dz: 3.0, ..run }), "dz");
        assert_eq!(name(SeasBp6Run { dz: 0.3, ..run }), "dz");
        assert_eq!(
            name(SeasBp6Run {
                end_years: -1.0,
                ..run
            }),
            "end_years"
        );
        assert_eq!(
            name(SeasBp6Run {
                ratio: f64::NAN,
                ..run
            }),
            "ratio"
        );
        let diffusion = SeasBp6Run {
            pressure: Bp6PressureChoice::Diffusion,
            ..run
        };
        assert_eq!(
            name(SeasBp6Run {
                diffusion_cells: Some(1),
                ..diffusion
            }),
            "diffusion_cells"
        );
        assert_eq!(
            name(SeasBp6Run {
                diffusion_cells: Some(100),
                ..run
            }),
            "diffusion_cells"
        );
        assert_eq!(
            name(SeasBp6Run {
                kernel: KernelChoice::Dense,
                ..run
            }),
            "kernel"
        );
        assert_eq!(
            name(SeasBp6Run {
                elastic: Bp6Elastic::Fe,
                bem_product: Some(Bp6BemProduct::Fft),
                ..run
            }),
            "bem_product"
        );
        let c = SeasBp6Run {
            variant: Bp6Variant::C,
            ..run
        };
        assert_eq!(name(SeasBp6Run { dz: 1.0, ..c }), "dz");
        let rkc = SeasBp6Run {
            integrator: OdeIntegrator::Rkc,
            ..run
        };
        assert_ne!(rkc.fingerprint(), run.fingerprint());
        let c_rkc = SeasBp6Run {
            integrator: OdeIntegrator::Rkc,
            ..c
        };
        assert_eq!(c_rkc.fingerprint(), c.fingerprint());
        let explicit = SeasBp6Run {
            tolerance: Some(1e-7),
            bem_product: Some(Bp6BemProduct::Fft),
            ..run
        };
        assert_eq!(explicit.fingerprint(), run.fingerprint());
        assert_eq!(
            SeasBp6Run {
                diffusion_cells: Some(BP6_DIFFUSION_CELLS),
                ..diffusion
            }
            .fingerprint(),
            diffusion.fingerprint()
        );
    }
}
