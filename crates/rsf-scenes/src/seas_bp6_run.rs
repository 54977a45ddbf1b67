//! A run of BP6 as every front end sets it up — the program `seas_bp6`'s flags and the
//! Python package's `rsf.seas_bp6` keywords: the settings, their defaults and ranges
//! (one place for both front ends), and the fingerprint a checkpoint of the run carries,
//! so that a checkpoint of either front end resumes in the other (docs/reliability.md,
//! "Round 5").

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{integrator_fingerprint, FaultKernel, OdeIntegrator};

use crate::seas_bp6::{Bp6Pressure, Bp6Variant, SeasBp6, SeasBp6Grid};
use crate::{check_ranges, invalid};

/// The elastic kernel of a BP6 run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bp6Elastic {
    /// The whole space's boundary-element kernel on the fault alone (the default).
    #[default]
    Bem,
    /// The finite-element half space condensed onto the fault (C: the implicit scheme on
    /// the volume).
    Fe,
}

/// How the boundary-element kernel's products are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bp6BemProduct {
    /// FFTs of the Toeplitz kernel's circulant embedding (the default).
    #[default]
    Fft,
    /// The kernel stored as [`SeasBp6Run::kernel`] says (dense, or an ℋ-matrix).
    Stored,
}

/// Cells of the pore pressure's diffusion along `2 l_f` unless a run says otherwise
/// ([`Bp6Pressure::Diffusion`]).
pub const BP6_DIFFUSION_CELLS: usize = 800;

/// The first step (s) of BP6-C's implicit scheme, from which its steps adapt.
pub const BP6_C_FIRST_STEP: f64 = 60.0;

/// The ranges of a BP6 run's settings (closed intervals): the program's flags and the
/// Python keywords of the same names check them.
pub mod bp6_ranges {
    /// `end_years` (years of 365 days).
    pub const END_YEARS: (f64, f64) = (1e-9, 100.0);
    /// `dz` (m): cells of at least 0.4 m, at most `l_f/2`.
    pub const DZ: (f64, f64) = (0.4, 10e3);
    /// `domain_km` (km): beyond `1.5 l_f`.
    pub const DOMAIN_KM: (f64, f64) = (30.0, 1e5);
    /// `ratio`: the growth of the finite elements away from the fault.
    pub const RATIO: (f64, f64) = (1.0, 2.0);
    /// `tolerance`.
    pub const TOLERANCE: (f64, f64) = (1e-12, 0.1);
    /// `station_interval` (s).
    pub const STATION_INTERVAL: (f64, f64) = (0.0, 1e7);
    /// `profile_interval` (s).
    pub const PROFILE_INTERVAL: (f64, f64) = (60.0, 1e7);
    /// `diffusion_cells`.
    pub const DIFFUSION_CELLS: (f64, f64) = (2.0, 20_000.0);
    /// Cells of BP6-C on the boundary-element kernel, whose stiffness is formed densely.
    pub const C_BEM_MAX_CELLS: f64 = 20_000.0;
}

impl Bp6Pressure {
    /// Checks the diffusion's cells against [`bp6_ranges::DIFFUSION_CELLS`].
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `diffusion_cells`.
    pub fn validate(&self) -> rsf::Result<()> {
        if let Self::Diffusion { cells } = *self {
            check_ranges(&[(
                "diffusion_cells",
                cells as f64,
                bp6_ranges::DIFFUSION_CELLS,
                "",
            )])?;
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

/// The settings of a BP6 run (the program's flags, Python's keywords). [`Default`] is
/// the program's defaults for BP6-A: 10 m cells of the FFT boundary-element kernel, the
/// closed-form pressure, 2 years.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeasBp6Run {
    /// The friction variant.
    pub variant: Bp6Variant,
    /// Cell (BEM) or element (FE) size along the fault (m), dividing `2 l_f`.
    pub dz: f64,
    /// The elastic kernel.
    pub elastic: Bp6Elastic,
    /// The boundary-element kernel's products.
    pub bem_product: Bp6BemProduct,
    /// FE: the truncation of the half space (km).
    pub domain_km: f64,
    /// FE: the elements' growth away from the fault.
    pub ratio: f64,
    /// The tolerance ([`Bp6Variant::default_tolerance`]).
    pub tolerance: f64,
    /// The pore pressure.
    pub pressure: Bp6Pressure,
    /// The stored kernel (`Bp6BemProduct::Stored`, or the FE model's condensed operator).
    pub kernel: FaultKernel,
    /// The fault ODE's integrator (A, S).
    pub integrator: OdeIntegrator,
    /// The end time (years of 365 days).
    pub end_years: f64,
    /// Seconds between station and `global.dat` rows (0: every accepted step).
    pub station_interval: f64,
    /// Seconds between profile rows.
    pub profile_interval: f64,
}

impl Default for SeasBp6Run {
    fn default() -> Self {
        let grid = SeasBp6Grid::default();
        let variant = Bp6Variant::A;
        Self::of_variant(
            variant,
            Self {
                variant,
                dz: grid.dz,
                elastic: Bp6Elastic::Bem,
                bem_product: Bp6BemProduct::Fft,
                domain_km: grid.domain / 1e3,
                ratio: grid.ratio,
                tolerance: variant.default_tolerance(),
                pressure: Bp6Pressure::ClosedForm,
                kernel: FaultKernel::Dense,
                integrator: OdeIntegrator::Auto,
                end_years: 2.0,
                station_interval: 0.0,
                profile_interval: 10_800.0,
            },
        )
    }
}

impl SeasBp6Run {
    /// `run` for `variant` with the variant's default tolerance and the kernel matching it
    /// ([`Self::matching_kernel`]).
    pub fn of_variant(variant: Bp6Variant, run: Self) -> Self {
        let tolerance = variant.default_tolerance();
        Self {
            variant,
            tolerance,
            kernel: Self::matching_kernel(tolerance),
            ..run
        }
    }

    /// The hierarchical kernel of a run of `tolerance`: its accuracy the tolerance, at
    /// most 1e-2 ([`FaultKernel::matching`]).
    pub fn matching_kernel(tolerance: f64) -> FaultKernel {
        FaultKernel::matching(tolerance.min(1e-2))
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
    /// them: `dz` divides `2 l_f`, BP6-C on the boundary-element kernel at most
    /// [`bp6_ranges::C_BEM_MAX_CELLS`] cells, `diffusion_cells` in its range.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named by the setting (the Python keyword; the flag
    /// with `--` and dashes).
    pub fn validate(&self, bp6: &SeasBp6) -> rsf::Result<()> {
        use bp6_ranges as r;
        let ranged = [
            ("end_years", self.end_years, r::END_YEARS, ""),
            ("dz", self.dz, r::DZ, ""),
            ("domain_km", self.domain_km, r::DOMAIN_KM, ""),
            ("ratio", self.ratio, r::RATIO, ""),
            ("tolerance", self.tolerance, r::TOLERANCE, ""),
            (
                "station_interval",
                self.station_interval,
                r::STATION_INTERVAL,
                "",
            ),
            (
                "profile_interval",
                self.profile_interval,
                r::PROFILE_INTERVAL,
                "",
            ),
        ];
        check_ranges(&ranged)?;
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
        self.pressure.validate()?;
        self.kernel.validate()
    }

    /// The fingerprint of a checkpoint of this run of `bp6`: the scene's parameters and
    /// every setting (the integrator for A and S only: BP6-C's implicit scheme takes none).
    pub fn fingerprint(&self, bp6: &SeasBp6) -> Fingerprint {
        let f = Fingerprint::of_serialized(bp6)
            .with("variant", self.variant.name())
            .with("dz", self.dz)
            .with("elastic", format!("{:?}", self.elastic))
            .with("domain_km", self.domain_km)
            .with("ratio", self.ratio)
            .with("tolerance", self.tolerance)
            .with("pressure", format!("{:?}", self.pressure))
            .with("kernel", self.kernel)
            .with("bem_product", format!("{:?}", self.bem_product))
            .with("end_years", self.end_years)
            .with("station_interval", self.station_interval)
            .with("profile_interval", self.profile_interval);
        match self.variant {
            Bp6Variant::C => f,
            _ => integrator_fingerprint(f, self.integrator),
        }
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
        assert_eq!(run.tolerance, Bp6Variant::A.default_tolerance());
        let c = SeasBp6Run::of_variant(Bp6Variant::C, run);
        assert_eq!(c.tolerance, 1e-3);
        assert_eq!(c.kernel, FaultKernel::matching(1e-3));
        assert!(run.validate(&SeasBp6::default()).is_ok());
        assert!(c.validate(&SeasBp6::default()).is_ok());
    }

    /// Every range and rule refuses by the setting's name; the integrator is in A's
    /// fingerprint, not in C's.
    #[test]
    fn refusals_name_the_setting_and_c_has_no_integrator() {
        let bp6 = SeasBp6::default();
        let run = SeasBp6Run::default();
        let name = |r: SeasBp6Run| match r.validate(&bp6) {
            Err(rsf::Error::InvalidParameter { name, .. }) => name,
            other => panic!("{other:?}"),
        };
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
        assert_eq!(
            name(SeasBp6Run {
                pressure: Bp6Pressure::Diffusion { cells: 1 },
                ..run
            }),
            "diffusion_cells"
        );
        let c = SeasBp6Run::of_variant(Bp6Variant::C, run);
        assert_eq!(name(SeasBp6Run { dz: 1.0, ..c }), "dz");
        let rk4 = SeasBp6Run {
            integrator: OdeIntegrator::Rkc,
            ..run
        };
        assert_ne!(rk4.fingerprint(&bp6), run.fingerprint(&bp6));
        let c_rkc = SeasBp6Run {
            integrator: OdeIntegrator::Rkc,
            ..c
        };
        assert_eq!(c_rkc.fingerprint(&bp6), c.fingerprint(&bp6));
    }
}
