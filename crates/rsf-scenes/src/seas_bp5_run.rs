//! A run of BP5 as every front end sets it up — the program `seas_bp5`'s flags and the
//! Python package's `rsf.seas_bp5` keywords: the settings, their defaults and ranges (one
//! place for both front ends), the files' headers and the fingerprint a checkpoint of the
//! run carries, so that a checkpoint of either front end resumes in the other
//! (docs/reliability.md, "Round 5"). The scene's parameters (friction included: `a0`,
//! `a_max`, `b0`, `l`, `l_nucleation`, `sigma_n`, …) are [`SeasBp5`]'s fields.

use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::{
    integrator_fingerprint, FaultKernel, FaultOdeOptions, InteriorOrdering, OdeIntegrator,
};
use rsf_seas::{SeasLayout, SeasSampling, SeasSetup};

use crate::{check_ranges, SeasBp5, SeasBp5Grid, SeasBp5Mesh};

/// The file of the Schur-only elimination's checkpoints in a run's folder (its finished
/// state kept: a resume of the run reads it instead of eliminating again).
pub const BP5_SETUP_FILE: &str = "setup.bin";

/// The ranges of a BP5 run's settings (closed intervals): the program's flags and the
/// Python keywords of the same names check them.
pub mod bp5_ranges {
    /// `end_years` (years).
    pub const END_YEARS: (f64, f64) = (1e-9, 1e5);
    /// `domain_km` (km) of the finite-element kernel: beyond `1.5 l_f/2`.
    pub const DOMAIN_KM: (f64, f64) = (75.0, 1e4);
    /// `ratio` of the finite-element kernel: the growth of the spacing.
    pub const RATIO: (f64, f64) = (1.0, 2.0);
    /// `epsilon`: the ℋ-matrix's relative accuracy.
    pub const EPSILON: (f64, f64) = (
        rsf::fault_ode::MIN_KERNEL_EPSILON,
        rsf::fault_ode::MAX_KERNEL_EPSILON,
    );
}

/// The elastic operator of a BP5 run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bp5Kernel {
    /// Okada's half-space, a fault alone, back slip (the default).
    #[default]
    Okada,
    /// The finite-element volume model condensed onto the fault.
    Fe,
}

/// How the finite-element kernel condenses the volume onto the fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Bp5Condensation {
    /// The Schur complement alone, by an elimination that keeps no factor column
    /// (checkpointed in the run's folder as [`BP5_SETUP_FILE`]; the default).
    #[default]
    SchurOnly,
    /// The volume's whole sparse Cholesky factor, kept for the run.
    Factor,
}

/// The settings of a BP5 run (the program's flags, Python's keywords). [`Default`] is the
/// program's defaults: Okada's kernel on 2 km cells, 1800 years, tolerance 1e-6, ε 1e-6;
/// for the finite-element kernel a graded box of ±400 km grown by 1.3, condensed by the
/// Schur-only elimination, ordered by AMD (the program's default is nested dissection
/// where METIS is built: [`SeasBp5Run::ordering`] is set by the front end).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeasBp5Run {
    /// The elastic operator.
    pub kernel: Bp5Kernel,
    /// Cell size on the fault (m), dividing `l_f` and `W_f`.
    pub dx: f64,
    /// Finite elements: the distance from the fault to the box's far faces and its depth
    /// (km).
    pub domain_km: f64,
    /// Finite elements: the growth of the spacing away from the rate-and-state region.
    pub ratio: f64,
    /// Finite elements: the volume's mesh.
    pub mesh: SeasBp5Mesh,
    /// Finite elements: how the volume is condensed.
    pub condensation: Bp5Condensation,
    /// Finite elements: the fill-reducing ordering of the volume's factor.
    pub ordering: InteriorOrdering,
    /// The end time (years).
    pub end_years: f64,
    /// Tolerance of the fault ODE (local error per step: tolerance · L in slip, tolerance
    /// in ln θ).
    pub tolerance: f64,
    /// Relative accuracy ε of the ℋ-matrix (above 4 096 unknowns).
    pub epsilon: f64,
    /// The fault ODE's integrator.
    pub integrator: OdeIntegrator,
}

impl Default for SeasBp5Run {
    fn default() -> Self {
        Self {
            kernel: Bp5Kernel::Okada,
            dx: 2000.0,
            domain_km: 400.0,
            ratio: 1.3,
            mesh: SeasBp5Mesh::Graded,
            condensation: Bp5Condensation::SchurOnly,
            ordering: InteriorOrdering::Amd,
            end_years: 1800.0,
            tolerance: 1e-6,
            epsilon: 1e-6,
            integrator: OdeIntegrator::Auto,
        }
    }
}

impl SeasBp5Run {
    /// The finite-element grid of `bp5` (its fault zone's slab meshed at `dx`).
    pub fn grid(&self, bp5: &SeasBp5) -> SeasBp5Grid {
        SeasBp5Grid {
            dx: self.dx,
            domain: self.domain_km * 1e3,
            ratio: self.ratio,
            mesh: self.mesh,
            near_fault: bp5.fault_zone.map_or(0.0, |z| z.half_width),
        }
    }

    /// Checks every setting against its range ([`bp5_ranges`]; the box's only for the
    /// finite-element kernel), `dx` against the fault ([`SeasBp5::cells`]), the tolerance
    /// (the fault ODE's options of `bp5`) and `bp5`.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named by the setting (the Python keyword; the flag
    /// with `--` and dashes) or the scene's field.
    pub fn validate(&self, bp5: &SeasBp5) -> rsf::Result<()> {
        use bp5_ranges as r;
        check_ranges(&[
            ("end_years", self.end_years, r::END_YEARS, "years"),
            ("epsilon", self.epsilon, r::EPSILON, "a relative accuracy"),
        ])?;
        bp5.cells(self.dx)?;
        bp5.fault_ode_options(self.tolerance)?;
        bp5.half_space(self.epsilon)?;
        if self.kernel == Bp5Kernel::Fe {
            check_ranges(&[
                (
                    "domain_km",
                    self.domain_km,
                    r::DOMAIN_KM,
                    "km: 1.5 l_f/2 and more",
                ),
                ("ratio", self.ratio, r::RATIO, "the growth of the spacing"),
            ])?;
        }
        Ok(())
    }

    /// The fault ODE's options of this run of `bp5` on `threads` threads: the scene's for
    /// the tolerance, the run's integrator. The finite-element kernel adds
    /// [`volume_options`](Self::volume_options) once its model is built.
    ///
    /// # Errors
    /// An invalid tolerance (named `tolerance`).
    pub fn fault_ode_options(&self, bp5: &SeasBp5, threads: usize) -> rsf::Result<FaultOdeOptions> {
        let mut options = bp5.fault_ode_options(self.tolerance)?;
        options.parallelism = rsf::Parallelism::rayon(threads);
        options.integrator = self.integrator;
        Ok(options)
    }

    /// `options` for the finite-element kernel's model of `slip_unknowns` unknowns on the
    /// fault: its condensed operator an ℋ-matrix of accuracy `epsilon` above 4 096 of
    /// them (dense below), the volume's factor ordered by `ordering`.
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
            ordering: self.ordering,
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

    /// The fingerprint of a checkpoint of this run of `bp5`: the scene's parameters and
    /// every setting (the box's with either kernel, the ordering, the mesh and the
    /// condensation with the finite-element kernel alone), and the integrator.
    pub fn fingerprint(&self, bp5: &SeasBp5) -> Fingerprint {
        let mut f = Fingerprint::of_serialized(bp5)
            .with("kernel", format!("{:?}", self.kernel))
            .with("dx", self.dx)
            .with("domain_km", self.domain_km)
            .with("ratio", self.ratio)
            .with("end_years", self.end_years)
            .with("tolerance", self.tolerance)
            .with("epsilon", self.epsilon);
        if self.kernel == Bp5Kernel::Fe {
            // The volume's ordering (the operator changes by round-off; Okada's kernel has
            // no volume to order: its fingerprint holds none, so that a checkpoint of a
            // build with METIS resumes in one without), its mesh (a field since the graded
            // mesh; an older finite-element checkpoint, of the tensor grid, is then
            // refused by its missing field).
            f = f
                .with("ordering", self.ordering)
                .with("mesh", format!("{:?}", self.mesh))
                .with("condensation", format!("{:?}", self.condensation));
        }
        integrator_fingerprint(f, self.integrator)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The defaults validate; every range and the scene's `dx` refuse by the setting's
    /// name; the box is checked with the finite-element kernel alone.
    #[test]
    fn refusals_name_the_setting() {
        let bp5 = SeasBp5::default();
        let run = SeasBp5Run::default();
        assert!(run.validate(&bp5).is_ok());
        let name = |r: SeasBp5Run| match r.validate(&bp5) {
            Err(rsf::Error::InvalidParameter { name, .. }) => name,
            other => panic!("{other:?}"),
        };
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
        let small_box = SeasBp5Run {
            domain_km: 50.0,
            ..run
        };
        assert!(small_box.validate(&bp5).is_ok());
        assert_eq!(
            name(SeasBp5Run {
                kernel: Bp5Kernel::Fe,
                ..small_box
            }),
            "domain_km"
        );
        assert_eq!(
            name(SeasBp5Run {
                kernel: Bp5Kernel::Fe,
                ratio: 3.0,
                ..run
            }),
            "ratio"
        );
    }

    /// The mesh and the condensation are in the finite-element run's fingerprint, not in
    /// Okada's; the scene's friction is in both.
    #[test]
    fn the_fingerprint_holds_what_the_kernel_reads() {
        let bp5 = SeasBp5::default();
        let okada = SeasBp5Run::default();
        let fe = SeasBp5Run {
            kernel: Bp5Kernel::Fe,
            ..okada
        };
        let factor = |r: SeasBp5Run| SeasBp5Run {
            condensation: Bp5Condensation::Factor,
            ..r
        };
        assert_eq!(factor(okada).fingerprint(&bp5), okada.fingerprint(&bp5));
        let nd = |r: SeasBp5Run| SeasBp5Run {
            ordering: InteriorOrdering::NestedDissection,
            ..r
        };
        assert_eq!(nd(okada).fingerprint(&bp5), okada.fingerprint(&bp5));
        assert_ne!(nd(fe).fingerprint(&bp5), fe.fingerprint(&bp5));
        assert_ne!(factor(fe).fingerprint(&bp5), fe.fingerprint(&bp5));
        let weaker = SeasBp5 { b0: 0.02, ..bp5 };
        assert_ne!(okada.fingerprint(&weaker), okada.fingerprint(&bp5));
    }
}
