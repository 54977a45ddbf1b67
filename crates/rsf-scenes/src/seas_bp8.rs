//! The SCEC SEAS benchmark BP8-QD-GS / BP8-QD-PW (docs/seas-bp8.md; Kim, Dunham, Romanet
//! & Erickson's description of 2026-08-12): fluid injected for 100 hours into the
//! velocity-strengthening square `|x₂|, |x₃| < l_f = 400 m` of a planar fault in a whole
//! space; the pressure diffuses in the fault plane, lowers the effective normal stress
//! and drives one aseismic slip transient. No tectonic loading; outside the square the
//! fault is locked. Two sources: a Gaussian (GS) or a Peaceman well (PW).
//!
//! The fault alone on `(2 l_f/Δx)²` square cells with the whole space's operator
//! ([`crate::square_fault`], [`rsf::halfspace_operator::WholeSpaceGrid`]); the pressure
//! the diffusion on the square's nodes, exact in time
//! ([`rsf::pore_pressure::SurfaceDiffusion`], the cells' centres reading its bilinear
//! interpolant). Coordinates are the description's, `x₃` positive down.

use std::sync::Arc;

use rsf::fault_alone::FaultAlone;
use rsf::fault_ode::FaultOdeOptions;
use rsf::halfspace::Medium;
use rsf::pore_pressure::{
    EffectiveStressFloor, FaultPlane, FaultZone, Injection, PeacemanWell, PorePressure,
    SurfaceDiffusion, SurfaceGrid, SurfaceInjection, SurfaceSource,
};
use rsf::time::Quasistatic;
use rsf::{FaultOde, Integrator, Model, Result, SimulationBuilder};
use rsf_friction::{AsinhLaw, RateStateParams};
use rsf_seas::{SeasBp5Output, SeasSetup, StrikeDipFault};
use rsf_state::{BuiltinStateLaw, StateLawKind};

use crate::invalid;
use crate::scene_file::{finite, poisson_ratio, positive_fields};
use crate::square_fault::{
    ln_theta_at, square_cells, square_model, square_operator, SquareProblemBuilder,
};

/// The fault ODE of BP8 (the regularised law, the aging law, a 3-D fault alone).
pub type SeasBp8FaultOde = FaultOde<3, AsinhLaw, BuiltinStateLaw, 3>;

/// Seconds per day.
pub const BP8_SECONDS_PER_DAY: f64 = 86_400.0;

/// How the injection enters the fault (`gs`, `pw` in files, flags and Python).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp8Source {
    /// GS: a Gaussian of width `L_gauss` (description eq. 19).
    #[default]
    #[serde(rename = "gs")]
    #[cfg_attr(feature = "clap", value(name = "gs"))]
    Gaussian,
    /// PW: a Peaceman well with storage (eqs. 22–23).
    #[serde(rename = "pw")]
    #[cfg_attr(feature = "clap", value(name = "pw"))]
    Well,
}

impl Bp8Source {
    /// `"GS"` or `"PW"`, as the benchmark names the variants.
    pub fn name(self) -> &'static str {
        match self {
            Self::Gaussian => "GS",
            Self::Well => "PW",
        }
    }
}

impl std::str::FromStr for Bp8Source {
    type Err = rsf::Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "gs" => Ok(Self::Gaussian),
            "pw" => Ok(Self::Well),
            _ => Err(invalid("source", format!("`{s}`: one of gs, pw"))),
        }
    }
}

/// What a run does where the pressure would reach the normal stress (docs/seas-bp8.md,
/// "Where p reaches σ̄₀"; only BP8-PW gets there, at the cells nearest the well).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Bp8Overpressure {
    /// The effective normal stress is `σ̄₀ − p` as the description writes it, and a run
    /// where it reaches 0 stops with [`rsf::Error::NormalStressNotPositive`] naming the
    /// cell and the time.
    Refuse,
    /// The effective normal stress held above `sigma_min` (Pa) by the `C¹` floor of
    /// [`EffectiveStressFloor`] (the identity above `2 σ_min`): the fault zone held barely
    /// closed where the pressure would open it.
    Floor {
        /// `σ_min` (Pa).
        sigma_min: f64,
    },
}

/// BP8-QD parameters (Table 1 of the description; SI units). [`SeasBp8::default`] is the
/// benchmark.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SeasBp8 {
    /// Density ρ (kg/m³).
    pub rho: f64,
    /// Shear wave speed c_s (m/s).
    pub c_s: f64,
    /// Poisson's ratio ν.
    pub nu: f64,
    /// Effective normal stress before the injection σ̄₀ (Pa).
    pub sigma_n: f64,
    /// Initial shear stress τ_init (Pa), along the initial slip rate.
    pub tau_init: f64,
    /// Direct effect a.
    pub a: f64,
    /// Evolution effect b.
    pub b: f64,
    /// Characteristic slip distance D_RS (m).
    pub d_rs: f64,
    /// Reference slip rate V* (m/s).
    pub v_star: f64,
    /// Reference friction coefficient f*.
    pub f_star: f64,
    /// Initial slip rate along x₂, V_init (m/s).
    pub v_init: f64,
    /// Initial slip rate along x₃, V_zero (m/s; keeps log10 V₃ finite).
    pub v_zero: f64,
    /// Half-width l_f of the frictional square (m).
    pub l_f: f64,
    /// Injection rate Q₀ (m³/s).
    pub q0: f64,
    /// Shut-in time t_off (s).
    pub t_off: f64,
    /// Fault-zone thickness L_fwid (m).
    pub l_fwid: f64,
    /// Permeability k (m²).
    pub k: f64,
    /// Fluid viscosity η_f (Pa·s).
    pub eta_f: f64,
    /// Porosity φ.
    pub phi: f64,
    /// Pore and fluid compressibility β (1/Pa).
    pub beta: f64,
    /// Width of the Gaussian source L_gauss (m).
    pub l_gauss: f64,
    /// Wellbore storage S_well (m³/Pa).
    pub s_well: f64,
    /// Well radius r_well (m).
    pub r_well: f64,
}

impl Default for SeasBp8 {
    fn default() -> Self {
        Self {
            rho: 2670.0,
            c_s: 3464.0,
            nu: 0.25,
            sigma_n: 25e6,
            tau_init: 14.6e6,
            a: 0.016,
            b: 0.010,
            d_rs: 5e-4,
            v_star: 1e-6,
            f_star: 0.6,
            v_init: 1e-12,
            v_zero: 1e-20,
            l_f: 400.0,
            q0: 3e-3,
            t_off: 100.0 * 3600.0,
            l_fwid: 1.0,
            k: 5e-14,
            eta_f: 1e-3,
            phi: 0.1,
            beta: 1e-8,
            l_gauss: 50.0,
            s_well: 1e-7,
            r_well: 0.05,
        }
    }
}

impl SeasBp8 {
    /// Checks every parameter finite, all but `f_star` and `nu` positive, `ν` in
    /// `(−1, ½)`, `S_well ≥ 0`, and the initial shear stress inside the friction's range
    /// (`τ_init > η |V(0)|`).
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        positive_fields!(self; rho, c_s, sigma_n, tau_init, a, b, d_rs, v_star, v_init, v_zero,
            l_f, q0, t_off, l_fwid, k, eta_f, phi, beta, l_gauss, r_well)?;
        finite("f_star", self.f_star)?;
        if !(self.s_well.is_finite() && self.s_well >= 0.0) {
            return Err(invalid("s_well", format!("{} must be >= 0", self.s_well)));
        }
        poisson_ratio(self.nu)?;
        if self.tau_init <= self.radiation_damping() * self.initial_speed() {
            return Err(invalid(
                "tau_init",
                "must exceed the radiation damping's η |V(0)|",
            ));
        }
        Ok(())
    }

    /// Shear modulus μ = ρ c_s² (Pa); 32.04 GPa for the benchmark.
    pub fn shear_modulus(&self) -> f64 {
        self.rho * self.c_s * self.c_s
    }

    /// Radiation damping η = μ/(2c_s) (Pa·s/m).
    pub fn radiation_damping(&self) -> f64 {
        self.shear_modulus() / (2.0 * self.c_s)
    }

    /// The whole space's medium (μ, ν).
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn medium(&self) -> Result<Medium> {
        self.validate()?;
        Medium::from_shear_poisson(self.shear_modulus(), self.nu)
            .map_err(|e| invalid("nu", e.to_string()))
    }

    /// `|V(0)| = |(V_init, V_zero)|` (m/s).
    pub fn initial_speed(&self) -> f64 {
        self.v_init.hypot(self.v_zero)
    }

    /// The prestress `τ⁰ = τ_init V(0)/|V(0)|` (Pa; components along x₂, x₃; eq. 29).
    pub fn tau0(&self) -> [f64; 2] {
        let s = self.initial_speed();
        [
            self.tau_init * (self.v_init / s),
            self.tau_init * (self.v_zero / s),
        ]
    }

    /// The rate-and-state parameters of [`AsinhLaw`] at `σ̄₀`: `mu0 = f*`, `v0 = V*`,
    /// `l = D_RS`.
    pub fn params(&self) -> RateStateParams {
        RateStateParams {
            mu0: self.f_star,
            a: self.a,
            b: self.b,
            v0: self.v_star,
            l: self.d_rs,
            sigma_n: self.sigma_n,
        }
    }

    /// The initial state `α = ln θ₀` (θ in s): the state at which the fault carries its
    /// prestress at `V(0)` — the friction law (eq. 12) at `τ = τ_init − η|V(0)|`,
    /// `σ̄₀`, `|V(0)|` (§3 of the 2026-08-12 description: `τ_init` and `V_init` kept, θ₀
    /// derived). 4.0188e11 s for the benchmark.
    pub fn alpha0(&self) -> f64 {
        let v = self.initial_speed();
        let f = (self.tau_init - self.radiation_damping() * v) / self.sigma_n;
        ln_theta_at(&self.params(), f, v)
    }

    /// The fault zone's hydraulic properties.
    pub fn zone(&self) -> FaultZone {
        FaultZone {
            thickness: self.l_fwid,
            permeability: self.k,
            porosity: self.phi,
            compressibility: self.beta,
            viscosity: self.eta_f,
        }
    }

    /// The injection at the origin through `source`.
    pub fn injection(&self, source: Bp8Source) -> SurfaceInjection {
        SurfaceInjection {
            injection: Injection {
                rate: self.q0,
                shut_in: self.t_off,
            },
            source: match source {
                Bp8Source::Gaussian => SurfaceSource::Gaussian {
                    width: self.l_gauss,
                },
                Bp8Source::Well => SurfaceSource::Well(PeacemanWell {
                    radius: self.r_well,
                    storage: self.s_well,
                    equivalent_radius: None,
                }),
            },
            position: [0.0, 0.0],
        }
    }

    /// The fault plane `x₁ = 0` with `(u, v) = (x₂, x₃)`.
    pub fn plane() -> FaultPlane {
        FaultPlane {
            origin: [0.0; 3],
            axis_u: [0.0, 1.0, 0.0],
            axis_v: [0.0, 0.0, 1.0],
        }
    }

    /// The pressure diffusing over the square from `source`, on the nodes of the grid of
    /// spacing `dx` (`2 l_f/dx` cells per side, nodes at the cells' corners: the
    /// injection point is a node; docs/pore-pressure.md), no flux across its edges. The
    /// field itself: the files' pressure and Darcy velocity.
    ///
    /// # Errors
    /// Invalid parameters; `dx` as [`square_cells`]; the field's errors.
    pub fn pressure(&self, source: Bp8Source, dx: f64) -> Result<Arc<SurfaceDiffusion>> {
        self.validate()?;
        let n = (square_cells(self.l_f, dx)?.len() as f64).sqrt().round() as usize;
        let grid = SurfaceGrid {
            lower: [-self.l_f; 2],
            upper: [self.l_f; 2],
            cells: [n, n],
        };
        Ok(Arc::new(SurfaceDiffusion::new(
            self.zone(),
            self.injection(source),
            Self::plane(),
            grid,
        )?))
    }

    /// The pressure the friction laws see: `field`, or `field` held below `σ̄₀` by
    /// `policy`'s floor.
    ///
    /// # Errors
    /// An invalid floor ([`EffectiveStressFloor::new`]).
    pub fn friction_pressure(
        &self,
        field: Arc<SurfaceDiffusion>,
        policy: Bp8Overpressure,
    ) -> Result<Arc<dyn PorePressure<3>>> {
        Ok(match policy {
            Bp8Overpressure::Refuse => field,
            Bp8Overpressure::Floor { sigma_min } => {
                Arc::new(EffectiveStressFloor::new(field, self.sigma_n, sigma_min)?)
            }
        })
    }

    /// The cells' centres `(x₂, x₃)` (m) of the grid of side `dx`, `x₂` fastest
    /// ([`square_cells`]).
    ///
    /// # Errors
    /// As [`square_cells`].
    pub fn cells(&self, dx: f64) -> Result<Vec<[f64; 2]>> {
        self.validate()?;
        square_cells(self.l_f, dx)
    }

    /// The fault alone on the cells of side `dx` ([`square_model`]), loaded by the
    /// prestress [`tau0`](Self::tau0).
    ///
    /// # Errors
    /// As [`cells`](Self::cells).
    pub fn model(&self, dx: f64) -> Result<Model<3, 3>> {
        let tau0 = self.tau0();
        square_model(&self.cells(dx)?, dx, |_, _| tau0)
    }

    /// The problem of BP8 on `model` with the pressure `pressure` (Pa) lowering `σ̄₀`: the
    /// regularised law with [`params`](Self::params), the aging law, θ₀ of
    /// [`alpha0`](Self::alpha0), quasi-dynamic with η = μ/(2c_s), first trial step 1 s.
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn problem_builder(
        &self,
        model: Model<3, 3>,
        pressure: Arc<dyn PorePressure<3>>,
    ) -> Result<SquareProblemBuilder> {
        self.validate()?;
        let law = AsinhLaw::new(self.params())?;
        Ok(SimulationBuilder::new(model)
            .friction_at(move |_| Ok::<_, rsf_friction::Error>(law))
            .state_law(BuiltinStateLaw::new(StateLawKind::Aging, self.d_rs)?)
            .initial_state(self.alpha0())
            .integrator(Integrator::Quasistatic(Quasistatic::new()))
            .radiation_damping(self.radiation_damping())
            .pore_pressure(pressure)
            .time_step(1.0))
    }

    /// The fault ODE of BP8 on the cells of side `dx` with the whole space's operator
    /// ([`square_operator`]) and no loading but the pressure `pressure` (from
    /// [`friction_pressure`](Self::friction_pressure)).
    ///
    /// # Errors
    /// As [`model`](Self::model) and [`problem_builder`](Self::problem_builder); the
    /// operator's; the set-up errors of
    /// [`build_fault_ode_alone`](rsf::SimulationBuilder::build_fault_ode_alone).
    pub fn fault_ode(
        &self,
        dx: f64,
        options: FaultOdeOptions,
        pressure: Arc<dyn PorePressure<3>>,
    ) -> Result<SeasBp8FaultOde> {
        let model = self.model(dx)?;
        let operator = square_operator(&model, self.medium()?)?;
        let alone = FaultAlone {
            operator: Box::new(operator),
            plate_velocity: vec![0.0; 2 * model.vertices.len()],
        };
        self.problem_builder(model, pressure)?
            .build_fault_ode_alone(options, alone)
    }

    /// Options of the fault ODE for BP8: Dormand–Prince 5(4), local errors at most
    /// `tolerance · D_RS` in slip and `tolerance` in ln θ per step, steps in
    /// [1e-6 s, 1 yr].
    ///
    /// # Errors
    /// An invalid tolerance.
    pub fn fault_ode_options(&self, tolerance: f64) -> Result<FaultOdeOptions> {
        crate::seas_fault_ode_options(tolerance, self.d_rs)
    }

    /// The fault as the files see it: the square `2 l_f × 2 l_f`, μ, η, no plate rate.
    pub fn output_fault(&self) -> StrikeDipFault {
        StrikeDipFault {
            length: 2.0 * self.l_f,
            width: 2.0 * self.l_f,
            shear_modulus: self.shear_modulus(),
            radiation_damping: self.radiation_damping(),
            plate_rate: 0.0,
        }
    }

    /// BP8's files ([`SeasBp5Output::bp8`]) of a run on the cells of side `dx` into `dir`
    /// (created if missing): `field` the pressure they report (the diffusion's, from
    /// [`pressure`](Self::pressure), not a floor's), `setup` the headers and sampling.
    ///
    /// # Errors
    /// As [`cells`](Self::cells); those of [`SeasBp5Output::bp8`].
    pub fn output(
        &self,
        dir: &std::path::Path,
        dx: f64,
        field: Arc<dyn PorePressure<3>>,
        setup: SeasSetup,
    ) -> Result<SeasBp5Output> {
        let cells = self.cells(dx)?;
        Ok(SeasBp5Output::bp8(
            dir,
            &self.output_fault(),
            dx,
            cells,
            field,
            setup,
        )?)
    }
}
