//! The run configuration of two parallel BP5 strands (the program `bp5_pair`;
//! docs/fault-networks.md, "Two parallel faults in 3-D"): its flags, the keys of its
//! `--config` file, its checkpoints' fingerprint and `summary.json`'s `settings` from one
//! struct ([`RunConfig`], docs/design.md "One run configuration").

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{FaultOdeOptions, InteriorOrdering, OdeIntegrator};

#[cfg(feature = "clap")]
use crate::run_config::TOLERANCE_HELP;
use crate::run_config::{as_setting, check_ranges, RunConfig};
#[cfg(feature = "clap")]
use crate::seas_square_run::INTEGRATOR_HELP;
use crate::{invalid, Bp5Kernel, Bp5Pair, Bp5PairPatch, SeasBp5, SeasBp5Grid};

/// The ranges of a two-strand run's settings and the flags' help texts.
pub mod bp5_pair_ranges {
    use crate::setting_range;

    setting_range!(
        pub DX,
        DX_HELP = "Cell size on the strands (m); must divide l_f = 100 km and W_f = 40 km (`fe`: and half the separation)",
        [250, 20e3]
    );
    setting_range!(
        pub SEPARATION_KM,
        SEPARATION_KM_HELP = "Distance between the strands across strike (km); `fe`: half of it a whole number of `--dx`",
        [1e-3, 1e3]
    );
    setting_range!(
        pub DOMAIN_KM,
        DOMAIN_KM_HELP = "`fe`: distance from the strands to the box's far faces, and its depth (km); the graded box's root cubes (edge dx·2^k ≤ 64 km) within the mesh's cell limit too (about 3000 km at --dx 2000: a larger box is refused naming --domain-km)",
        [75, 1e4]
    );
    setting_range!(
        pub RATIO,
        RATIO_HELP = "`fe`: growth of the spacing away from the strands' rate-and-state regions",
        [1, 2]
    );
    setting_range!(pub END_YEARS, END_YEARS_HELP = "End time (years)", [1e-9, 1e5]);
    setting_range!(
        pub EPSILON,
        EPSILON_HELP = "Relative accuracy ε of the ℋ-matrices (above 4 096 unknowns)",
        [1e-14, 1e-2]
    );
}
use bp5_pair_ranges as r;

/// The settings of a two-strand run (the program `bp5_pair`'s flags and `--config` keys).
/// [`Default`] is the program's: Okada's kernel on 2 km cells, the strands 8 km apart,
/// 1800 years, tolerance and ε 1e-6; with `fe` a box of ±400 km graded by 1.3, the
/// ordering the front end's (nested dissection where METIS is built, else AMD:
/// [`resolved`](Self::resolved)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct Bp5PairRun {
    /// The elastic operator: `okada` (both strands alone in Okada's half-space, boundary
    /// elements) or `fe` (both inside a finite-element box, condensed onto them).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = Bp5PairRun::default().kernel))]
    pub kernel: Bp5Kernel,
    /// Cell size on the strands (m).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = Bp5PairRun::default().dx, allow_negative_numbers = true, help = r::DX_HELP))]
    pub dx: f64,
    /// Distance between the strands across strike (km).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = Bp5PairRun::default().separation_km, allow_negative_numbers = true, help = r::SEPARATION_KM_HELP))]
    pub separation_km: f64,
    /// `fe`: distance from the strands to the box's far faces, and its depth (km).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = Bp5PairRun::default().domain_km, allow_negative_numbers = true, help = r::DOMAIN_KM_HELP))]
    pub domain_km: f64,
    /// `fe`: growth of the spacing away from the strands.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = Bp5PairRun::default().ratio, allow_negative_numbers = true, help = r::RATIO_HELP))]
    pub ratio: f64,
    /// `fe`: fill-reducing ordering of the volume's elimination, `nested-dissection`
    /// (METIS; the default where it is built, as in the examples: with two planes through
    /// the box AMD's fill is ten times larger — 37 GB against 2.7 GB at 4 km) or `amd`.
    #[cfg_attr(feature = "clap", arg(long))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ordering: Option<InteriorOrdering>,
    /// End time (years).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = Bp5PairRun::default().end_years, allow_negative_numbers = true, help = r::END_YEARS_HELP))]
    pub end_years: f64,
    /// Tolerance of the fault ODE (local error per step: tolerance · L in slip, tolerance
    /// in ln θ).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = Bp5PairRun::default().tolerance, allow_negative_numbers = true, help = TOLERANCE_HELP))]
    pub tolerance: f64,
    /// The fault ODE's integrator.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = Bp5PairRun::default().integrator, help = INTEGRATOR_HELP))]
    pub integrator: OdeIntegrator,
    /// Relative accuracy ε of the ℋ-matrices.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = Bp5PairRun::default().epsilon, allow_negative_numbers = true, help = r::EPSILON_HELP))]
    pub epsilon: f64,
    /// Where BP5's nucleation patch is: on `both` strands (mirror images) or on the `west`
    /// one only (the strands differ: the west one leads; docs/fault-networks.md).
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = Bp5PairPatch::Both))]
    #[serde(default, skip_serializing_if = "Bp5PairPatch::is_both")]
    pub patch: Bp5PairPatch,
}

impl Default for Bp5PairRun {
    fn default() -> Self {
        let grid = SeasBp5Grid::default();
        Self {
            kernel: Bp5Kernel::Okada,
            dx: 2000.0,
            separation_km: Bp5Pair::default().separation / 1e3,
            domain_km: grid.domain / 1e3,
            ratio: grid.ratio,
            ordering: None,
            end_years: 1800.0,
            tolerance: 1e-6,
            integrator: OdeIntegrator::Auto,
            epsilon: 1e-6,
            patch: Bp5PairPatch::Both,
        }
    }
}

impl Bp5PairRun {
    /// The scene: BP5's parameters, the strands `separation_km` apart, the patch where
    /// `patch` says.
    pub fn scene(&self) -> Bp5Pair {
        Bp5Pair {
            bp5: SeasBp5::default(),
            separation: self.separation_km * 1e3,
            patch: self.patch,
        }
    }

    /// The finite-element box's grid (`fe`).
    pub fn grid(&self) -> SeasBp5Grid {
        SeasBp5Grid {
            dx: self.dx,
            domain: self.domain_km * 1e3,
            ratio: self.ratio,
            ..SeasBp5Grid::default()
        }
    }

    /// The run as it runs: the ordering `ordering` (the front end's default) where unset.
    pub fn resolved(&self, ordering: InteriorOrdering) -> Self {
        Self {
            ordering: Some(self.ordering.unwrap_or(ordering)),
            ..*self
        }
    }

    /// The fault ODE's options on `threads` threads: BP5's at the tolerance, the run's
    /// integrator, the ℋ-matrices at `epsilon`, the volume's elimination ordered by the
    /// resolved ordering (AMD if unset).
    ///
    /// # Errors
    /// An invalid tolerance (named `tolerance`).
    pub fn fault_ode_options(&self, threads: usize) -> rsf::Result<FaultOdeOptions> {
        let mut options = as_setting(
            "tolerance",
            self.scene().bp5.fault_ode_options(self.tolerance),
        )?;
        options.integrator = self.integrator;
        options.parallelism = rsf::Parallelism::rayon(threads);
        options.kernel = rsf::fault_ode::FaultKernel::matching(self.epsilon);
        options.ordering = self.ordering.unwrap_or(InteriorOrdering::Amd);
        Ok(options)
    }

    /// The fingerprint of a checkpoint of the run with the front end's default ordering
    /// `ordering`: every setting, resolved, then BP5's parameters as `scene.NAME`.
    pub fn fingerprint_with(&self, ordering: InteriorOrdering) -> Fingerprint {
        crate::run_config::with_scene(
            Fingerprint::of_serialized(&self.resolved(ordering)),
            &self.scene().bp5,
        )
    }
}

impl RunConfig for Bp5PairRun {
    fn validate(&self) -> rsf::Result<()> {
        check_ranges(&[
            ("end_years", self.end_years, r::END_YEARS, "years"),
            ("dx", self.dx, r::DX, "m"),
            ("separation_km", self.separation_km, r::SEPARATION_KM, "km"),
            ("domain_km", self.domain_km, r::DOMAIN_KM, "km"),
            ("ratio", self.ratio, r::RATIO, "the growth of the spacing"),
            ("epsilon", self.epsilon, r::EPSILON, "a relative accuracy"),
        ])?;
        let written = rsf_numeric::written;
        let pair = self.scene();
        pair.bp5
            .cells(self.dx)
            .map_err(|e| invalid("dx", format!("{}: {e}", written(self.dx))))?;
        pair.validate().map_err(|e| {
            invalid(
                "separation_km",
                format!("{}: {e}", written(self.separation_km)),
            )
        })?;
        as_setting("tolerance", pair.bp5.fault_ode_options(self.tolerance))?;
        if self.kernel == Bp5Kernel::Fe {
            let half = 0.5 * self.separation_km * 1e3 / self.dx;
            if (half - half.round()).abs() > 1e-9 * half.max(1.0) || half < 1.0 {
                return Err(invalid(
                    "separation_km",
                    format!(
                        "{}: half of it must be a whole number (≥ 1) of --dx",
                        written(self.separation_km)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// [`fingerprint_with`](Self::fingerprint_with) AMD where the ordering is unset (a
    /// front end with METIS resolves it first).
    fn fingerprint(&self) -> Fingerprint {
        self.fingerprint_with(InteriorOrdering::Amd)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults validate and are the scene's; the separation's rule with `fe`.
    #[test]
    fn the_defaults_validate_and_fe_needs_whole_cells() {
        let run = Bp5PairRun::default();
        run.validate().unwrap();
        assert_eq!(run.scene(), Bp5Pair::default());
        let fe = Bp5PairRun {
            kernel: Bp5Kernel::Fe,
            separation_km: 3.0,
            ..run
        };
        match fe.validate() {
            Err(rsf::Error::InvalidParameter { name, .. }) => assert_eq!(name, "separation_km"),
            other => panic!("{other:?}"),
        }
        assert_eq!(r::EPSILON.0, rsf::fault_ode::MIN_KERNEL_EPSILON);
    }
}
