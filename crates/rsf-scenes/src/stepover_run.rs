//! The run configuration of the stepover (the program `stepover`; docs/fault-networks.md):
//! its flags, the keys of its `--config` file, its checkpoints' fingerprint and
//! `summary.json`'s `settings` from one struct ([`RunConfig`], docs/design.md "One run
//! configuration").

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{FaultKernel, OdeIntegrator};

use crate::run_config::{check_ranges, fault_kernel, KernelChoice, RunConfig};
#[cfg(feature = "clap")]
use crate::seas_square_run::INTEGRATOR_HELP;
use crate::stepover::{Stepover, StepoverGrid};
use crate::{invalid, SeasBp1};

/// The ranges of the stepover's settings.
pub mod stepover_ranges {
    use crate::setting_range;

    setting_range!(pub END_YEARS, END_YEARS_HELP = "End time (years)", [1e-9, 1e5]);
    setting_range!(
        pub DX,
        DX_HELP = "Element size along the strands and next to them (m); must divide half the gap, half the overlap and the strands' frictional length into whole cells; at most H/8 = 1875 m",
        [1, 1875]
    );
    setting_range!(
        pub GAP_KM,
        GAP_KM_HELP = "Distance between the strands across strike (km); half of it at least the smallest --dx, 1 m",
        [2e-3, 1e3]
    );
    setting_range!(
        pub STRAND_KM,
        STRAND_KM_HELP = "Length of each strand's frictional part (km), from its tip: velocity weakening over 15 km, the transition to 18 km, velocity strengthening to this, creep beyond",
        [1, 1e4]
    );
    setting_range!(
        pub RATIO,
        RATIO_HELP = "Growth of the elements away from the strands",
        [1, 2]
    );
    /// `--help` of the hierarchical kernel's accuracy.
    pub use crate::run_config::KERNEL_EPSILON_HELP;
}
use stepover_ranges as r;

/// The settings of a run of the stepover (the program `stepover`'s flags, the keys of its
/// `--config` file, the fields of its checkpoints' fingerprint). [`Default`] is the
/// program's: 25 m cells, strands 25 km long 1 km apart with 2 km of overlap, 3 000 years.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "clap", derive(clap::Args))]
pub struct StepoverRun {
    /// End time (years).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = StepoverRun::default().end_years, allow_negative_numbers = true, help = r::END_YEARS_HELP))]
    pub end_years: f64,
    /// Element size (m).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = StepoverRun::default().dx, allow_negative_numbers = true, help = r::DX_HELP))]
    pub dx: f64,
    /// Distance between the strands across strike (km).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = StepoverRun::default().gap_km, allow_negative_numbers = true, help = r::GAP_KM_HELP))]
    pub gap_km: f64,
    /// Overlap of the strands along strike (km; negative: an underlap, the tips apart);
    /// shorter than 0.9 of a strand either way.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = StepoverRun::default().overlap_km, allow_negative_numbers = true))]
    pub overlap_km: f64,
    /// Length of each strand's frictional part (km).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = StepoverRun::default().strand_km, allow_negative_numbers = true, help = r::STRAND_KM_HELP))]
    pub strand_km: f64,
    /// How far the box reaches beyond the strands (km), along and across strike: at least
    /// `--strand-km`, at most 1e5.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = StepoverRun::default().domain_km, allow_negative_numbers = true))]
    pub domain_km: f64,
    /// Growth of the elements away from the strands.
    #[cfg_attr(feature = "clap", arg(long, default_value_t = StepoverRun::default().ratio, allow_negative_numbers = true, help = r::RATIO_HELP))]
    pub ratio: f64,
    /// The normal stress changes with slip (a releasing or restraining step); default the
    /// laws' fixed σ_n.
    #[cfg_attr(feature = "clap", arg(long))]
    pub normal_stress_from_slip: bool,
    /// Tolerance of the fault ODE, in (2.220446049250313e-16, 1) (open: from f64::EPSILON
    /// to 1).
    #[cfg_attr(feature = "clap", arg(long, default_value_t = StepoverRun::default().tolerance, allow_negative_numbers = true))]
    pub tolerance: f64,
    /// The operators condensed onto the strands: `hierarchical` (ℋ-matrices, the
    /// default) or `dense`.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = StepoverRun::default().kernel))]
    pub kernel: KernelChoice,
    /// Relative accuracy of the hierarchical kernel (default: the tolerance, within its
    /// range).
    #[cfg_attr(feature = "clap", arg(long, allow_negative_numbers = true, help = r::KERNEL_EPSILON_HELP))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kernel_epsilon: Option<f64>,
    /// The fault ODE's integrator.
    #[cfg_attr(feature = "clap", arg(long, value_enum, default_value_t = StepoverRun::default().integrator, help = INTEGRATOR_HELP))]
    pub integrator: OdeIntegrator,
}

impl Default for StepoverRun {
    fn default() -> Self {
        let scene = Stepover::default();
        Self {
            end_years: 3000.0,
            dx: 25.0,
            gap_km: scene.gap / 1e3,
            overlap_km: scene.overlap / 1e3,
            strand_km: scene.params.w_f / 1e3,
            domain_km: 50.0,
            ratio: 1.05,
            normal_stress_from_slip: scene.normal_stress_from_slip,
            // The pair at 1e-4, as BP1's (issue 84; the strands carry BP1's friction):
            // at 100 m over 3 000 years the catalogue's statistics are those of `auto` at
            // 1e-6 at 0.53× its CPU (docs/fault-networks.md).
            tolerance: 1e-4,
            kernel: KernelChoice::Hierarchical,
            kernel_epsilon: None,
            integrator: OdeIntegrator::DormandPrince,
        }
    }
}

impl StepoverRun {
    /// The scene: BP1's parameters with strands `strand_km` long, `gap_km` apart,
    /// overlapping by `overlap_km`.
    pub fn scene(&self) -> Stepover {
        Stepover {
            params: SeasBp1 {
                w_f: self.strand_km * 1e3,
                ..SeasBp1::default()
            },
            gap: self.gap_km * 1e3,
            overlap: self.overlap_km * 1e3,
            normal_stress_from_slip: self.normal_stress_from_slip,
        }
    }

    /// The graded grid.
    pub fn grid(&self) -> StepoverGrid {
        StepoverGrid {
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
}

impl RunConfig for StepoverRun {
    fn validate(&self) -> rsf::Result<()> {
        let strand = self.strand_km;
        check_ranges(&[
            ("end_years", self.end_years, r::END_YEARS, "years"),
            ("strand_km", strand, r::STRAND_KM, "km"),
            ("gap_km", self.gap_km, r::GAP_KM, "km"),
            (
                "overlap_km",
                self.overlap_km,
                (-0.9 * strand, 0.9 * strand),
                "km: shorter than a strand either way",
            ),
            ("dx", self.dx, r::DX, "m: at most H/8"),
            (
                "domain_km",
                self.domain_km,
                (strand, 1e5),
                "km: at least a strand's length",
            ),
            ("ratio", self.ratio, r::RATIO, "the growth of the elements"),
        ])?;
        let scene = self.scene();
        scene
            .check_grid(&self.grid())
            .map_err(|e| invalid("dx", format!("{}: {e}", rsf_numeric::written(self.dx))))?;
        crate::run_config::as_setting("tolerance", scene.params.fault_ode_options(self.tolerance))?;
        self.fault_kernel().map(|_| ())
    }

    /// Every setting, then the scene's parameters as `scene.NAME`.
    fn fingerprint(&self) -> Fingerprint {
        crate::run_config::with_scene(Fingerprint::of_serialized(self), &self.scene())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults validate and are the scene's; `dx`'s upper bound is H/8.
    #[test]
    fn the_defaults_are_the_scenes() {
        let run = StepoverRun::default();
        run.validate().unwrap();
        assert_eq!(run.scene(), Stepover::default());
        assert_eq!(r::DX.1, SeasBp1::default().h_top / 8.0);
    }
}
