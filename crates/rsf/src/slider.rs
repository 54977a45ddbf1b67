//! The paper's model problem (§6.1, Table 6.1; docs/math.md §6) as a scene: a 5 m × 1 m
//! elastic block sheared over a rigid surface, as TOML-readable parameters.

use serde::{Deserialize, Serialize};

use rsf_fem::{
    body_force_load, lumped_weights, pipping_slider_coarse, Assembler, BoundarySegment,
    ConstrainedSystem, Diagonal, LinearElasticity, MeshHierarchy,
};
use rsf_friction::{DieterichRuina, RateStateParams};
use rsf_state::{Aging, Slip};
use rsf_time::{BackwardEuler, Newmark, Quasistatic};
use rsf_tnnmg::{DirectOptions, Stopping, TnnmgOptions};

use crate::dynamic::AnySimulation;
use crate::error::{invalid, Error, Result};
use crate::fixed_point::FixedPointOptions;
use crate::model::{DirichletVelocity, FrictionalBoundary, Model};
use crate::simulation::Simulation;
use crate::solver::SolverKind;

/// State law of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StateLawKind {
    /// Dieterich's aging law (2.15).
    Dieterich,
    /// Ruina's slip law (2.16).
    Ruina,
}

/// Velocity integrator of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorKind {
    /// Newmark, β = ¼, γ = ½.
    Newmark,
    /// Backward Euler for the velocity.
    BackwardEuler,
    /// Quasistatic (no inertia, no mass matrix).
    Quasistatic,
}

/// Velocity solver of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SolverChoice {
    /// Direct while the condensed problem is small, TNNMG beyond ([`SolverKind::resolve`]).
    Auto,
    /// TNNMG on the refinement hierarchy.
    Tnnmg,
    /// Direct condensation onto Γ_F.
    Direct,
}

/// Fixed point scheme of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FixedPointScheme {
    /// Anderson acceleration from an extrapolated predictor
    /// ([`FixedPointOptions::default`]).
    Anderson,
    /// The paper's relaxed iteration ([`FixedPointOptions::paper`]; Fig. 6.1's counts).
    Paper,
}

/// Triangulation diagonal of the coarse grid cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiagonalKind {
    /// Lower-left to upper-right.
    Forward,
    /// Upper-left to lower-right.
    Backward,
}

/// The paper's slider scene (Table 6.1). Every field has a default (the paper's value);
/// a TOML scene file may set any subset. Unknown fields are rejected with their name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SliderScene {
    /// Uniform refinement level j of the 2 × 6-vertex coarse grid (paper: 2…8; 4 for the
    /// time series).
    pub level: usize,
    /// Number of time steps N (τ = T/N).
    pub steps: usize,
    /// Final time T (s).
    pub end_time_s: f64,
    /// Density ρ (kg/m², per unit thickness).
    pub density_kg_per_m2: f64,
    /// Young's modulus E (Pa = N/m² ; the paper's N/m per unit thickness).
    pub youngs_modulus_pa: f64,
    /// Poisson ratio ν (plane strain).
    pub poisson_ratio: f64,
    /// Gravitational acceleration g (m/s² = N/kg); body force (0, −ρ g).
    pub gravity_m_per_s2: f64,
    /// Prescribed normal stress σ̄_n on Γ_F (Pa).
    pub sigma_n_pa: f64,
    /// Reference friction coefficient μ0.
    pub mu0: f64,
    /// Direct-effect parameter a.
    pub a: f64,
    /// Evolution-effect parameter b.
    pub b: f64,
    /// Reference slip rate V0 (m/s).
    pub v0_m_per_s: f64,
    /// Characteristic slip distance L (m).
    pub l_m: f64,
    /// Loading velocity of Γ_D after the ramp (m/s).
    pub loading_velocity_m_per_s: f64,
    /// Ramp duration as a fraction of T (paper: ¼).
    pub ramp_fraction: f64,
    /// Initial state α_0 = ln θ_0 (θ in s) on Γ_F.
    pub alpha0: f64,
    /// State law.
    pub state_law: StateLawKind,
    /// Velocity integrator.
    pub integrator: IntegratorKind,
    /// Velocity solver.
    pub solver: SolverChoice,
    /// Fixed point scheme.
    pub fixed_point: FixedPointScheme,
    /// Fixed point tolerance (energy norm, paper 1e-10).
    pub fixed_point_tolerance: f64,
    /// Fixed point iteration budget per step.
    pub fixed_point_max_iterations: usize,
    /// Velocity solver tolerance (energy norm, absolute; paper 1e-10).
    pub solver_tolerance: f64,
    /// Coarse grid diagonal.
    pub diagonal: DiagonalKind,
}

impl Default for SliderScene {
    fn default() -> Self {
        Self {
            level: 4,
            steps: 10_000,
            end_time_s: 15.0,
            density_kg_per_m2: 5e3,
            youngs_modulus_pa: 5e7,
            poisson_ratio: 0.3,
            gravity_m_per_s2: 9.81,
            sigma_n_pa: 49_050.0,
            mu0: 0.6,
            a: 0.010,
            b: 0.015,
            v0_m_per_s: 1e-6,
            l_m: 1e-5,
            loading_velocity_m_per_s: 2e-4,
            ramp_fraction: 0.25,
            alpha0: -10.0,
            state_law: StateLawKind::Dieterich,
            integrator: IntegratorKind::Newmark,
            solver: SolverChoice::Auto,
            fixed_point: FixedPointScheme::Anderson,
            fixed_point_tolerance: 1e-10,
            fixed_point_max_iterations: 100,
            solver_tolerance: 1e-10,
            diagonal: DiagonalKind::Forward,
        }
    }
}

/// The centre of Γ_F, `x0 = (2.5, 0)` m, where the paper records its time series.
pub const SLIDER_CENTRE: [f64; 2] = [2.5, 0.0];

impl SliderScene {
    /// Parses a TOML scene (fields as in this struct; unknown fields are an error).
    ///
    /// # Errors
    /// [`Error::SceneFile`] with the parser's message (it names unknown fields).
    pub fn from_toml(text: &str) -> Result<Self> {
        toml::from_str(text).map_err(|e| Error::SceneFile(e.to_string()))
    }

    /// The time step τ = T/N (s).
    pub fn tau(&self) -> f64 {
        self.end_time_s / self.steps as f64
    }

    /// Checks every parameter, naming the first invalid one.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] or the friction crate's parameter error.
    pub fn validate(&self) -> Result<()> {
        let pos = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(invalid(name, format!("{v} must be finite and > 0")))
            }
        };
        if self.level > 10 {
            return Err(invalid(
                "level",
                format!("{} is beyond what fits in memory (≤ 10)", self.level),
            ));
        }
        if self.steps == 0 {
            return Err(invalid("steps", "must be at least 1"));
        }
        pos("end_time_s", self.end_time_s)?;
        pos("density_kg_per_m2", self.density_kg_per_m2)?;
        pos("youngs_modulus_pa", self.youngs_modulus_pa)?;
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(invalid(
                "poisson_ratio",
                format!("{} must be in (-1, 0.5)", self.poisson_ratio),
            ));
        }
        if !(self.gravity_m_per_s2.is_finite() && self.gravity_m_per_s2 >= 0.0) {
            return Err(invalid("gravity_m_per_s2", "must be finite and >= 0"));
        }
        if !self.loading_velocity_m_per_s.is_finite() {
            return Err(invalid("loading_velocity_m_per_s", "must be finite"));
        }
        if !(self.ramp_fraction >= 0.0 && self.ramp_fraction <= 1.0) {
            return Err(invalid("ramp_fraction", "must be in [0, 1]"));
        }
        if !self.alpha0.is_finite() {
            return Err(invalid("alpha0", "must be finite"));
        }
        pos("fixed_point_tolerance", self.fixed_point_tolerance)?;
        pos("solver_tolerance", self.solver_tolerance)?;
        if self.fixed_point_max_iterations == 0 {
            return Err(invalid("fixed_point_max_iterations", "must be at least 1"));
        }
        self.rate_state_params().validate()?;
        Ok(())
    }

    /// The rate-and-state parameters of Γ_F.
    pub fn rate_state_params(&self) -> RateStateParams {
        RateStateParams {
            mu0: self.mu0,
            a: self.a,
            b: self.b,
            v0: self.v0_m_per_s,
            l: self.l_m,
            sigma_n: self.sigma_n_pa,
        }
    }

    /// Assembles the model at `self.level`: consistent mass (unless quasistatic),
    /// plane-strain stiffness, gravity load, Γ_D (top: both components, velocity
    /// `(V_D(t), 0)`), Γ_F (bottom: normal component fixed), the hierarchy's prolongations,
    /// lumped weights and `u_0` solving `K u_0 = F` with the same constraints.
    ///
    /// # Errors
    /// Invalid parameters; assembly errors.
    pub fn build_model(&self) -> Result<Model<2>> {
        self.validate()?;
        let diagonal = match self.diagonal {
            DiagonalKind::Forward => Diagonal::Forward,
            DiagonalKind::Backward => Diagonal::Backward,
        };
        let hierarchy =
            MeshHierarchy::refine_uniformly(pipping_slider_coarse(diagonal), self.level);
        let mesh = hierarchy.finest();
        let assembler = Assembler::new(mesh)?;
        let material = LinearElasticity::plane_strain(self.youngs_modulus_pa, self.poisson_ratio)?;
        let with_mass = self.integrator != IntegratorKind::Quasistatic;
        let stiffness = assembler.stiffness(mesh, &material)?;
        let (mass, energy_norm) = if with_mass {
            (
                Some(assembler.mass(mesh, self.density_kg_per_m2)?),
                assembler.energy(mesh, self.density_kg_per_m2, &material)?,
            )
        } else {
            (None, stiffness.clone())
        };
        let rho_g = self.density_kg_per_m2 * self.gravity_m_per_s2;
        let load = body_force_load(mesh, |_| [0.0, -rho_g])?;
        let gamma_d = BoundarySegment::from_tag(mesh, rsf_fem::TAG_DIRICHLET)?;
        let gamma_f = BoundarySegment::from_tag(mesh, rsf_fem::TAG_FRICTIONAL)?;
        let n = 2 * mesh.num_vertices();
        let mut fixed = vec![false; n];
        let mut dofs = Vec::new();
        for &p in gamma_d.nodes() {
            fixed[2 * p] = true;
            fixed[2 * p + 1] = true;
            dofs.push(2 * p);
        }
        for &p in gamma_f.nodes() {
            fixed[2 * p + 1] = true;
        }
        let weights = lumped_weights(mesh, &gamma_f);
        let frictional = FrictionalBoundary::new(gamma_f.nodes(), &weights)?;
        let mut u0 = vec![0.0; n];
        ConstrainedSystem::new(stiffness.as_ref(), &fixed)?.solve(&load, &mut u0)?;
        let prolongations = (1..=self.level)
            .map(|j| hierarchy.vector_prolongation(j).clone())
            .collect();
        let factors = vec![1.0; dofs.len()];
        Ok(Model {
            vertices: mesh.vertices().to_vec(),
            mass,
            stiffness,
            energy_norm,
            load,
            fixed,
            dirichlet: DirichletVelocity {
                dofs,
                factors,
                v_max: self.loading_velocity_m_per_s,
                t_ramp: self.ramp_fraction * self.end_time_s,
            },
            prolongations,
            frictional,
            initial_displacement: u0,
            cells: mesh.cells().to_vec(),
        })
    }

    /// The velocity solver choice with the scene's tolerance.
    pub fn solver_kind(&self) -> SolverKind {
        let stopping = Stopping {
            absolute: self.solver_tolerance,
            relative: 0.0,
            max_iterations: 500,
        };
        let tnnmg = TnnmgOptions {
            stopping,
            ..TnnmgOptions::default()
        };
        let direct = DirectOptions {
            stopping: Stopping {
                absolute: self.solver_tolerance * 1e-2,
                relative: 1e-14,
                max_iterations: 500,
            },
            ..DirectOptions::default()
        };
        match self.solver {
            SolverChoice::Auto => SolverKind::Auto { tnnmg, direct },
            SolverChoice::Tnnmg => SolverKind::Tnnmg(tnnmg),
            SolverChoice::Direct => SolverKind::Direct(direct),
        }
    }

    /// The fixed point options of the scene's scheme with its tolerance and budget.
    pub fn fixed_point_options(&self) -> FixedPointOptions {
        let base = match self.fixed_point {
            FixedPointScheme::Anderson => FixedPointOptions::default(),
            FixedPointScheme::Paper => FixedPointOptions::paper(),
        };
        FixedPointOptions {
            tolerance: self.fixed_point_tolerance,
            max_iterations: self.fixed_point_max_iterations,
            ..base
        }
    }

    /// Builds the simulation (monomorphised for the chosen law and integrator behind the
    /// object-safe [`AnySimulation`]).
    ///
    /// # Errors
    /// Invalid parameters; assembly and set-up errors.
    pub fn build(&self) -> Result<Box<dyn AnySimulation<2>>> {
        let model = self.build_model()?;
        self.build_with_model(model)
    }

    /// As [`build`](Self::build) with a model built (or modified) by the caller.
    ///
    /// # Errors
    /// As [`build`](Self::build).
    pub fn build_with_model(&self, model: Model<2>) -> Result<Box<dyn AnySimulation<2>>> {
        self.validate()?;
        let nf = model.frictional.len();
        let laws = vec![DieterichRuina::new(self.rate_state_params())?; nf];
        let alpha0 = vec![self.alpha0; nf];
        let tau = self.tau();
        let solver = self.solver_kind();
        let fp = self.fixed_point_options();
        macro_rules! make {
            ($state:expr, $integ:expr) => {
                Box::new(Simulation::new(
                    model,
                    laws,
                    vec![$state; nf],
                    alpha0,
                    $integ,
                    tau,
                    &solver,
                    fp,
                )?) as Box<dyn AnySimulation<2>>
            };
        }
        let aging = || Aging::new(self.l_m);
        let slip = || Slip::new(self.l_m);
        Ok(match (self.state_law, self.integrator) {
            (StateLawKind::Dieterich, IntegratorKind::Newmark) => make!(aging()?, Newmark),
            (StateLawKind::Dieterich, IntegratorKind::BackwardEuler) => {
                make!(aging()?, BackwardEuler)
            }
            (StateLawKind::Dieterich, IntegratorKind::Quasistatic) => {
                make!(aging()?, Quasistatic::new())
            }
            (StateLawKind::Ruina, IntegratorKind::Newmark) => make!(slip()?, Newmark),
            (StateLawKind::Ruina, IntegratorKind::BackwardEuler) => make!(slip()?, BackwardEuler),
            (StateLawKind::Ruina, IntegratorKind::Quasistatic) => {
                make!(slip()?, Quasistatic::new())
            }
        })
    }
}

/// Index of the vertex nearest to `x`.
pub fn nearest_vertex<const D: usize>(vertices: &[[f64; D]], x: &[f64; D]) -> usize {
    let d2 = |v: &[f64; D]| v.iter().zip(x).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
    (0..vertices.len())
        .min_by(|&i, &j| d2(&vertices[i]).total_cmp(&d2(&vertices[j])))
        .expect("a model has vertices")
}
