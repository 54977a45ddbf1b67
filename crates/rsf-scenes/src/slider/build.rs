//! The scene's model and simulation: [`SliderScene::build_model`] and the builders.

use super::{SceneSimulation, SceneSimulationBuilder, SliderScene, TimeStep};

use rsf_direct::DirectOptions;
use rsf_fem::{pipping_slider_coarse, TAG_DIRICHLET, TAG_FRICTIONAL, TAG_NEUMANN};
use rsf_nonsmooth::Stopping;
use rsf_state::BuiltinStateLaw;
use rsf_time::VelocityIntegrator;
use rsf_tnnmg::TnnmgOptions;

use rsf::method::FixedPointOptions;
use rsf::method::SolverOptions;
use rsf::model::{ProblemScales, ScaleFields};
use rsf::Model;
use rsf::Result;
use rsf::SimulationBuilder;
use rsf::{ModelBuilder, Part};

impl SliderScene {
    /// Assembles the model at `self.level` with [`ModelBuilder`]: the paper's coarse grid
    /// ([`pipping_slider_coarse`]) refined `level` times, with the scene's physics
    /// ([`physics`](Self::physics)) on its parts [`TAG_DIRICHLET`] (top) and
    /// [`TAG_FRICTIONAL`] (bottom): consistent mass (unless quasistatic), plane-strain
    /// stiffness, gravity, Γ_D (top: both components, velocity `(v_load g(t), 0)` with the
    /// ramp `g`), Γ_F (bottom, normal component fixed), the hierarchy's prolongations,
    /// lumped weights and `u_0` solving `K u_0 = F` with the same constraints; then
    /// [`check_conditioning`](Self::check_conditioning). The same path as
    /// [`build_model_on`](Self::build_model_on) on a mesh of one's own.
    ///
    /// # Errors
    /// Invalid parameters; assembly errors; [`Error::IllConditioned`](rsf::Error::IllConditioned).
    pub fn build_model(&self) -> Result<Model<2>> {
        self.validate()?;
        let builder = ModelBuilder::refined(pipping_slider_coarse(self.diagonal), self.level)?;
        let builder = self.physics(builder, TAG_DIRICHLET, TAG_FRICTIONAL);
        self.checked_model(if self.absorbing_sides {
            builder.absorbing_boundary(TAG_NEUMANN)
        } else {
            builder
        })
    }

    /// The scene's physics on the mesh (or refinement hierarchy) of a user's `builder`:
    /// the material of Table 6.1 ([`material`](Self::material)), gravity `(0, −g)`, the
    /// part `dirichlet` moving with velocity `(loading_velocity_m_per_s, 0) · g(t)` (both
    /// components fixed; `g` the loading ramp, [`loading`](Self::loading)), the part
    /// `frictional` as Γ_F with bilateral contact, and no mass matrix if the scene's
    /// integrator has no inertia. Parts are given by tag (e.g. a Gmsh physical group name,
    /// as a `&str`), by predicate ([`Part::predicate`]) or as a
    /// [`BoundaryPart`](rsf_fem::BoundaryPart) of the finest mesh; the rest of the
    /// boundary is traction-free unless the caller adds more (e.g.
    /// [`neumann`](ModelBuilder::neumann)) to the returned builder. The scene's `level` and
    /// `diagonal` describe the paper's mesh and are not used here.
    ///
    /// This is the seam [`build_model`](Self::build_model) itself uses; with
    /// [`build_model_on`](Self::build_model_on) or
    /// [`simulation_builder_on`](Self::simulation_builder_on) the scene's friction, state
    /// law, α₀, integrator, τ and solver follow.
    pub fn physics(
        &self,
        builder: ModelBuilder<2>,
        dirichlet: impl Into<Part<2>>,
        frictional: impl Into<Part<2>>,
    ) -> ModelBuilder<2> {
        let builder = builder
            .material(self.material())
            .gravity([0.0, -self.gravity_m_per_s2])
            .dirichlet(dirichlet, [self.loading_velocity_m_per_s, 0.0])
            .frictional_boundary(frictional)
            .loading(self.loading());
        if self.integrator.uses_mass() {
            builder
        } else {
            builder.without_mass()
        }
    }

    /// The model of the scene's physics ([`physics`](Self::physics)) on the mesh of a
    /// user's `builder`, with the parts `dirichlet` (the moving top) and `frictional`
    /// (Γ_F): validated scene, built, [`check_conditioning`](Self::check_conditioning).
    ///
    /// ```no_run
    /// use rsf::fem::read_gmsh;
    /// use rsf::ModelBuilder;
    /// use rsf_scenes::SliderScene;
    ///
    /// let scene = SliderScene::default();
    /// let coarse = read_gmsh::<2>("my_block.msh")?.mesh;
    /// // Three refinements (a hierarchy for TNNMG); physical groups `top` and `base`:
    /// let model = scene.build_model_on(ModelBuilder::refined(coarse, 3)?, "top", "base")?;
    /// let mut sim = scene.build_with_model(model)?;
    /// sim.run(100, &mut [])?;
    /// # Ok::<(), rsf::Error>(())
    /// ```
    ///
    /// # Errors
    /// Invalid parameters ([`validate`](Self::validate)); the builder's errors (e.g.
    /// [`Error::BoundaryPart`](rsf::Error::BoundaryPart) for a tag that selects nothing); [`Error::IllConditioned`](rsf::Error::IllConditioned).
    pub fn build_model_on(
        &self,
        builder: ModelBuilder<2>,
        dirichlet: impl Into<Part<2>>,
        frictional: impl Into<Part<2>>,
    ) -> Result<Model<2>> {
        self.validate()?;
        self.checked_model(self.physics(builder, dirichlet, frictional))
    }

    /// As [`simulation_builder`](Self::simulation_builder) on the model
    /// [`build_model_on`](Self::build_model_on) builds on a user's mesh: the paper's physics,
    /// friction, state law, α₀, integrator, τ and solver on one's own geometry.
    ///
    /// # Errors
    /// As [`build_model_on`](Self::build_model_on); invalid friction or state-law parameters.
    pub fn simulation_builder_on(
        &self,
        builder: ModelBuilder<2>,
        dirichlet: impl Into<Part<2>>,
        frictional: impl Into<Part<2>>,
    ) -> Result<SceneSimulationBuilder<2>> {
        let model = self.build_model_on(builder, dirichlet, frictional)?;
        scene_builder(self, model)
    }

    /// `builder` built and checked ([`check_conditioning`](Self::check_conditioning));
    /// the scene is validated by the caller.
    fn checked_model(&self, builder: ModelBuilder<2>) -> Result<Model<2>> {
        let model = builder.build()?;
        self.check_conditioning(&model)?;
        Ok(model)
    }

    /// Whether the scene's assembled `model` can be computed in double precision
    /// ([`ProblemScales::check`], docs/reliability.md "Conditioning"): the diagonals of `K`,
    /// `M` and of the time-step matrix `A = c_M M + c_K K` at the smallest and largest
    /// step of the run, `|F|∞`, `|u₀|∞`, `|F|∞ / min K_ii` and `|v_load| T` within
    /// [`representable_range`](rsf::model::representable_range), and `l_m` at least
    /// [`SLIP_RESOLUTION`](rsf::model::SLIP_RESOLUTION) times the largest displacement scale.
    /// `O(nnz)`; run by [`build_model`](Self::build_model) and on models given to
    /// [`simulation_builder_with_model`](Self::simulation_builder_with_model).
    ///
    /// # Errors
    /// [`Error::IllConditioned`](rsf::Error::IllConditioned) naming the scene fields behind the failed quantity.
    pub fn check_conditioning<const D: usize>(&self, model: &Model<D>) -> Result<()> {
        self.check_scales(&ProblemScales::of_model(model))
    }

    /// [`check_conditioning`](Self::check_conditioning) of a model given by its scales:
    /// e.g. the whole model's, [`ProblemScales::combined`] from the column models of the
    /// processes of a job (each process's own check sees only its columns' diagonals).
    ///
    /// # Errors
    /// As [`check_conditioning`](Self::check_conditioning).
    pub fn check_scales(&self, scales: &ProblemScales) -> Result<()> {
        let t = self.end_time_s;
        // The steps of the run: τ = T/N, or the controller's range clipped to T (a step
        // never passes the end time).
        let steps: Vec<(f64, &'static [&'static str])> = match self.time_step {
            TimeStep::Fixed {} => vec![(self.tau(), &["steps", "end_time_s"])],
            TimeStep::Adaptive(a) => vec![
                (a.tau_min_s.min(t), &["time_step.tau_min_s"]),
                (a.tau_max_s.min(t), &["time_step.tau_max_s", "end_time_s"]),
            ],
        };
        let coefficients: Vec<((f64, f64), &[&'static str])> = steps
            .into_iter()
            .map(|(tau, f)| (self.integrator.coefficients(tau), f))
            .collect();
        scales.check(
            &coefficients,
            (
                self.loading_velocity_m_per_s.abs() * t,
                &["loading_velocity_m_per_s", "end_time_s"],
            ),
            self.l_m,
            &ScaleFields {
                stiffness: &["youngs_modulus_pa", "poisson_ratio"],
                mass: &["density_kg_per_m2"],
                load: &["density_kg_per_m2", "gravity_m_per_s2"],
                displacement: &["gravity_m_per_s2", "density_kg_per_m2", "youngs_modulus_pa"],
                slip: &["l_m"],
            },
        )
    }

    /// The options of the velocity solvers with the scene's tolerance (TNNMG: absolute
    /// `solver_tolerance`, smoother order `tnnmg_smoother`; direct: absolute
    /// `solver_tolerance · 1e-2`, relative 1e-14; 500 iterations each).
    pub fn solver_options(&self) -> SolverOptions {
        let stopping = Stopping {
            absolute: self.solver_tolerance,
            relative: 0.0,
            max_iterations: 500,
        };
        SolverOptions {
            tnnmg: TnnmgOptions {
                stopping,
                smoother: self.tnnmg_smoother,
                ..TnnmgOptions::default()
            },
            direct: DirectOptions {
                stopping: Stopping {
                    absolute: self.solver_tolerance * 1e-2,
                    relative: 1e-14,
                    max_iterations: 500,
                },
                ..DirectOptions::default()
            },
            gauss_seidel: stopping,
            ..SolverOptions::default()
        }
    }

    /// The fixed point options of the scene's scheme with its tolerance and budget.
    pub fn fixed_point_options(&self) -> FixedPointOptions {
        FixedPointOptions {
            tolerance: self.fixed_point_tolerance,
            max_iterations: self.fixed_point_max_iterations,
            inner_solves: self.fixed_point_inner_solves,
            ..self.fixed_point.options()
        }
    }

    /// A [`SimulationBuilder`] with everything the scene decides: the model,
    /// Dieterich–Ruina friction, the state law, α₀, the integrator, τ (or the step
    /// control), the solver and the fixed point options. Any of the parts may be replaced
    /// before [`build`](SimulationBuilder::build), e.g. by a user state law or friction
    /// varying along Γ_F.
    ///
    /// ```no_run
    /// use rsf::state::StateLaw;
    /// use rsf_scenes::SliderScene;
    ///
    /// #[derive(Clone)]
    /// struct NoHealing { l: f64 }
    /// impl StateLaw for NoHealing {
    ///     fn dpsi_dalpha(&self, _alpha: f64, v: f64) -> f64 { v / self.l }
    /// }
    ///
    /// let scene = SliderScene { level: 2, ..SliderScene::default() };
    /// let mut sim = scene.simulation_builder()?.state_law(NoHealing { l: scene.l_m }).build()?;
    /// sim.run(10, &mut [])?;
    /// # Ok::<(), rsf::Error>(())
    /// ```
    ///
    /// # Errors
    /// Invalid parameters; assembly errors.
    pub fn simulation_builder(&self) -> Result<SceneSimulationBuilder<2>> {
        let model = self.build_model()?;
        scene_builder(self, model)
    }

    /// As [`simulation_builder`](Self::simulation_builder) on a model built (or modified)
    /// by the caller.
    ///
    /// # Errors
    /// Invalid parameters; [`Error::IllConditioned`](rsf::Error::IllConditioned)
    /// ([`check_conditioning`](Self::check_conditioning)).
    pub fn simulation_builder_with_model(
        &self,
        model: Model<2>,
    ) -> Result<SceneSimulationBuilder<2>> {
        self.validate()?;
        self.check_conditioning(&model)?;
        scene_builder(self, model)
    }

    /// Builds the simulation.
    ///
    /// # Errors
    /// Invalid parameters; assembly and set-up errors.
    pub fn build(&self) -> Result<SceneSimulation<2>> {
        self.simulation_builder()?.build()
    }

    /// As [`build`](Self::build) with a model built (or modified) by the caller.
    ///
    /// # Errors
    /// As [`build`](Self::build).
    pub fn build_with_model(&self, model: Model<2>) -> Result<SceneSimulation<2>> {
        self.simulation_builder_with_model(model)?.build()
    }

    /// A progress bar for a run of the scene from time `t0` (s): of its steps for fixed
    /// steps (the steps left after `t0`), of time for adaptive ones.
    pub fn progress(&self, t0: f64, label: &str) -> rsf::observe::Progress {
        use rsf::observe::Progress;
        match self.time_step {
            TimeStep::Adaptive(_) => Progress::time(t0, self.end_time_s, label),
            TimeStep::Fixed {} => {
                let done = (t0 / self.tau()).round() as usize;
                Progress::steps(self.steps.saturating_sub(done), label)
            }
        }
    }
}

/// The builder of a scene's simulation on `model` (validated scene): everything
/// [`SliderScene::simulation_builder`] lists. Shared by the 2-D and 3-D sliders.
///
/// # Errors
/// Invalid friction or state-law parameters.
pub(crate) fn scene_builder<const D: usize>(
    scene: &SliderScene,
    model: Model<D>,
) -> Result<SceneSimulationBuilder<D>> {
    let b = SimulationBuilder::new(model)
        .friction(scene.friction_law()?)
        .state_law(BuiltinStateLaw::new(scene.state_law, scene.l_m)?)
        .integrator(scene.integrator)
        .initial_state(scene.alpha0)
        .time_step(scene.initial_tau())
        .solver(scene.solver)
        .solver_options(scene.solver_options())
        .fixed_point(scene.fixed_point_options())
        .state_integrator(scene.state_integrator);
    Ok(match scene.step_control()? {
        Some(c) => b.step_control(c),
        None => b,
    })
}
