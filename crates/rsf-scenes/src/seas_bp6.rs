//! The SCEC SEAS benchmark BP6-QD-A/S/C (docs/seas-bp6.md; Lambert & Dunham's description,
//! Lambert et al. 2025, JGR 130, e2024JB030601): fluid injected at the centre of a planar
//! fault in an antiplane whole space; the pore pressure lowers the effective normal
//! stress and drives one aseismic slip transient — velocity strengthening rate-and-state
//! friction with the aging law (A) or the slip law (S), or constant friction locked until
//! the pressure frees it (C).
//!
//! Coordinates: the fault is the line `x = 0`, `z` along it (m); the frictional fault is
//! `|z| < l_f`, locked beyond. Two elastic kernels on the same problem: the fault alone with
//! the whole space's boundary-element kernel ([`SeasBp6::bem_model`],
//! [`rsf::whole_space::WholeSpaceAntiplane`]: cells of width Δz centred at
//! `z = −l_f + (i + ½) Δz`), and the finite-element half space `x ≥ 0` of the
//! antisymmetric problem truncated at `|z|, x ≤ L` ([`SeasBp6::fe_model`]: nodes every
//! Δz on the fault).

use std::sync::Arc;

use rsf::fault_alone::FaultAlone;
use rsf::fault_ode::FaultOdeOptions;
use rsf::fem::{geometric_grading, rectangle_from_coordinates, symmetric_grading, Diagonal};
use rsf::model::AntiplaneMaterial;
use rsf::pore_pressure::{FaultDiffusion, Injection, InjectionPressure, PorePressure};
use rsf::simulation::NoState;
use rsf::time::{Quasistatic, StepControl};
use rsf::whole_space::{WholeSpaceAntiplane, WholeSpaceKernel};
use rsf::{FaultOde, Integrator, Model, ModelBuilder, Part, Result, Simulation, SimulationBuilder};
use rsf_friction::{AsinhLaw, RateStateParams, Tresca};
use rsf_state::{BuiltinStateLaw, StateLawKind};

use crate::invalid;
use crate::scene_file::positive_fields;

/// The fault ODE of BP6-A and -S (the regularised law, the aging or slip law) on the fault
/// alone (`C = 2`: the normal component fixed) or the finite-element model (`C = 1`).
pub type SeasBp6FaultOde<const C: usize> = FaultOde<2, AsinhLaw, BuiltinStateLaw, C>;

/// The implicit simulation of BP6-C (constant friction, Tresca with the bound
/// `f (σ̄₀ − p(t))`) on the finite-element model (`C = 1`) or the fault alone with the
/// boundary-element kernel (`C = 2`: the normal component fixed).
pub type SeasBp6Implicit<const C: usize = 1> = Simulation<2, Tresca, NoState, Integrator, C>;

/// Seconds in the benchmark's year (365 days, as tandem and hbi use: t_f = 63 072 000 s).
pub const BP6_SECONDS_PER_YEAR: f64 = 365.0 * 86_400.0;

/// The three friction variants of BP6: `a`, `s`, `c` in flags, files and Python (`A`,
/// `S`, `C` read too).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp6Variant {
    /// Rate and state, aging law.
    #[serde(rename = "a", alias = "A")]
    A,
    /// Rate and state, slip law.
    #[serde(rename = "s", alias = "S")]
    S,
    /// Constant friction `f = 0.6`, locked/sliding complementarity with radiation damping.
    #[serde(rename = "c", alias = "C")]
    C,
}

impl Bp6Variant {
    /// `"A"`, `"S"`, `"C"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::A => "A",
            Self::S => "S",
            Self::C => "C",
        }
    }
}

impl std::str::FromStr for Bp6Variant {
    type Err = rsf::Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "a" => Ok(Self::A),
            "s" => Ok(Self::S),
            "c" => Ok(Self::C),
            _ => Err(invalid("variant", format!("`{s}`: one of a, s, c"))),
        }
    }
}

/// How the pore pressure is computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Bp6Pressure {
    /// The description's closed form (eqs. 26–27; [`InjectionPressure`]).
    ClosedForm,
    /// The diffusion solved on `cells` cells between the no-flux ends `±l_f`
    /// ([`FaultDiffusion`]).
    Diffusion {
        /// Cells along `2 l_f`.
        cells: usize,
    },
}

/// BP6-QD parameters (Table 1 of the description; SI units). [`SeasBp6::default`] is the
/// benchmark.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SeasBp6 {
    /// Density ρ (kg/m³).
    pub rho: f64,
    /// Shear wave speed c_s (m/s).
    pub c_s: f64,
    /// Effective normal stress before the injection σ̄₀ (Pa).
    pub sigma_n: f64,
    /// Initial shear stress τ_init (Pa).
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
    /// Initial slip rate V_init (m/s) of A and S.
    pub v_init: f64,
    /// Friction coefficient of BP6-C.
    pub f_c: f64,
    /// Half-length l_f of the frictional fault (m).
    pub l_f: f64,
    /// Injection rate q₀ (m/s).
    pub q0: f64,
    /// Shut-in time t_off (s).
    pub t_off: f64,
    /// Pore and fluid compressibility β (1/Pa).
    pub beta: f64,
    /// Porosity φ.
    pub phi: f64,
    /// Permeability k (m²).
    pub k: f64,
    /// Fluid viscosity η_f (Pa·s).
    pub eta_f: f64,
}

impl Default for SeasBp6 {
    fn default() -> Self {
        Self {
            rho: 2670.0,
            c_s: 3464.0,
            sigma_n: 50e6,
            tau_init: 29.2e6,
            a: 0.007,
            b: 0.005,
            d_rs: 4e-3,
            v_star: 1e-6,
            f_star: 0.6,
            v_init: 1e-12,
            f_c: 0.6,
            l_f: 20e3,
            q0: 1.25e-6,
            t_off: 100.0 * 86_400.0,
            beta: 1e-8,
            phi: 0.1,
            k: 1e-13,
            eta_f: 1e-3,
        }
    }
}

/// The finite-element grid of BP6 ([`SeasBp6::fe_model`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeasBp6Grid {
    /// Node spacing along the fault (m); must divide `l_f`.
    pub dz: f64,
    /// Truncation of the half space: `0 ≤ x ≤ L`, `|z| ≤ L` (m), beyond `1.5 l_f`.
    pub domain: f64,
    /// Growth of the elements away from the fault, in `[1, 2]`.
    pub ratio: f64,
}

impl Default for SeasBp6Grid {
    /// 10 m on the fault, L = 400 km, growth 1.05.
    fn default() -> Self {
        Self {
            dz: 10.0,
            domain: 400e3,
            ratio: 1.05,
        }
    }
}

impl SeasBp6 {
    /// Checks that every parameter is positive and finite (`f_star`, `f_c` finite, ≥ 0)
    /// and that the fault starts below its strength.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        positive_fields!(self; rho, c_s, sigma_n, tau_init, a, b, d_rs, v_star, v_init, l_f,
            q0, t_off, beta, phi, k, eta_f)?;
        for (name, v) in [("f_star", self.f_star), ("f_c", self.f_c)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid(name, format!("{v} must be finite and >= 0")));
            }
        }
        Ok(())
    }

    /// Shear modulus μ = ρ c_s² (Pa); 32.04 GPa.
    pub fn shear_modulus(&self) -> f64 {
        self.rho * self.c_s * self.c_s
    }

    /// Radiation damping η = μ/(2c_s) (Pa·s/m).
    pub fn radiation_damping(&self) -> f64 {
        self.shear_modulus() / (2.0 * self.c_s)
    }

    /// Storage βφ (1/Pa).
    pub fn storage(&self) -> f64 {
        self.beta * self.phi
    }

    /// Hydraulic diffusivity α = k/(φβη_f) (m²/s); 0.1.
    pub fn diffusivity(&self) -> f64 {
        self.k / (self.phi * self.beta * self.eta_f)
    }

    /// The injection: q₀ until t_off.
    pub fn injection(&self) -> Injection {
        Injection {
            rate: self.q0,
            shut_in: self.t_off,
        }
    }

    /// The pore pressure as `how` says, the injection at `z = 0` diffusing along `z`.
    ///
    /// # Errors
    /// Invalid parameters; a diffusion grid out of range.
    pub fn pressure(&self, how: Bp6Pressure) -> Result<Arc<dyn PorePressure<2>>> {
        self.validate()?;
        Ok(match how {
            Bp6Pressure::ClosedForm => Arc::new(InjectionPressure::new(
                self.injection(),
                self.storage(),
                self.diffusivity(),
                [0.0, 0.0],
                [0.0, 1.0],
            )?),
            Bp6Pressure::Diffusion { cells } => Arc::new(FaultDiffusion::new(
                self.injection(),
                (self.storage(), self.diffusivity(), self.k / self.eta_f),
                [0.0, 0.0],
                [0.0, 1.0],
                [-self.l_f, self.l_f],
                cells,
            )?),
        })
    }

    /// The initial state of A and S, `α₀ = ln θ₀` with θ₀ of the description's eq. 24:
    /// `θ₀ = (D_RS/V*) exp{(a/b) ln[(2V*/V_init) sinh(τ_init/(aσ̄₀))] − f*/b}` (log10 θ₀ =
    /// 10.6123 for the benchmark), so that the law at `V_init` gives `τ_init`.
    pub fn alpha0(&self) -> f64 {
        let x = self.tau_init / (self.a * self.sigma_n);
        // ln sinh x without overflow: x + ln((1 − e^{−2x})/2).
        let ln_sinh = x + (0.5 * (-(-2.0 * x).exp_m1())).ln();
        let ln_arg = (2.0 * self.v_star / self.v_init).ln() + ln_sinh;
        (self.d_rs / self.v_star).ln() + self.a / self.b * ln_arg - self.f_star / self.b
    }

    /// The prestress τ⁰ (Pa): `τ_init + η V_init` for A and S (eq. 23: the fault starts
    /// at `V_init`), `τ_init` for C (locked).
    pub fn tau0(&self, variant: Bp6Variant) -> f64 {
        match variant {
            Bp6Variant::C => self.tau_init,
            _ => self.tau_init + self.radiation_damping() * self.v_init,
        }
    }

    /// The rate-and-state parameters of the regularised law [`AsinhLaw`]: `mu0 = f*`,
    /// `v0 = V*`, `l = D_RS`, `σ̄_n = σ̄₀`.
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

    /// `2 l_f / dz` cells, checked.
    fn cell_count(&self, dz: f64) -> Result<usize> {
        self.validate()?;
        let n = 2.0 * self.l_f / dz;
        if !(dz.is_finite() && dz > 0.0) || n < 4.0 || (n - n.round()).abs() > 1e-9 * n {
            return Err(invalid(
                "dz",
                format!(
                    "{dz} m must divide 2 l_f = {} m into at least 4 cells",
                    2.0 * self.l_f
                ),
            ));
        }
        if n > 100_000.0 {
            return Err(invalid(
                "dz",
                format!("{dz} m gives {n} cells, more than 100 000 (0.4 m)"),
            ));
        }
        Ok(n.round() as usize)
    }

    /// The cells' centres `z` (m) on the grid of size `dz`.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dz` unless it divides `2 l_f`.
    pub fn cell_centres(&self, dz: f64) -> Result<Vec<f64>> {
        let n = self.cell_count(dz)?;
        Ok((0..n).map(|i| -self.l_f + (i as f64 + 0.5) * dz).collect())
    }

    /// The fault alone on cells of size `dz` ([`Model::fault_only`]): one vertex per cell
    /// at `(0, z)`, its `x` component fixed (the normal) and its second component the
    /// slip, the prestress [`tau0`](Self::tau0) times `dz` as the load.
    ///
    /// # Errors
    /// Those of [`cell_centres`](Self::cell_centres).
    pub fn bem_model(&self, dz: f64, variant: Bp6Variant) -> Result<Model<2, 2>> {
        let centres = self.cell_centres(dz)?;
        let n = centres.len();
        let mut model =
            Model::fault_only(centres.iter().map(|&z| [0.0, z]).collect(), &vec![dz; n], 0)?;
        let tau0 = self.tau0(variant);
        for k in 0..n {
            model.load[2 * k + 1] = dz * tau0;
        }
        Ok(model)
    }

    /// The finite-element model on `grid` (quasi-dynamic: no mass): the half space
    /// `0 ≤ x ≤ L`, `|z| ≤ L` of the antisymmetric problem (the unknown the slip-equivalent
    /// field `2u`, [`ModelBuilder::antisymmetric_fault`]), a structured mesh uniform `dz`
    /// along the fault on `|z| ≤ l_f` and growing by `ratio` away from it; the frictional
    /// nodes `x = 0`, `|z| ≤ l_f` with the prestress [`tau0`](Self::tau0); the fault plane
    /// beyond `l_f` locked (`u = 0`, the ends `z = ±l_f` too: frictional nodes held at
    /// rest); the far sides `x = L`, `|z| = L` held (`u = 0`: the whole space's field
    /// vanishes at infinity); the initial displacement 0.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dz` (not dividing `l_f`), `domain` (not
    /// beyond 1.5 l_f) or `ratio` (outside `[1, 2]`); grading and assembly errors.
    pub fn fe_model(&self, grid: &SeasBp6Grid, variant: Bp6Variant) -> Result<Model<2, 1>> {
        self.cell_count(grid.dz)?;
        let (l_f, far, dz) = (self.l_f, grid.domain, grid.dz);
        if !(far.is_finite() && far >= 1.5 * l_f) {
            return Err(invalid(
                "domain",
                format!("{far} m must reach 1.5 l_f = {} m", 1.5 * l_f),
            ));
        }
        if !(1.0..=2.0).contains(&grid.ratio) {
            return Err(invalid(
                "ratio",
                format!("{} must be in [1, 2]", grid.ratio),
            ));
        }
        let xs = geometric_grading(dz, 0.0, grid.ratio, far)?;
        let zs = symmetric_grading(dz, l_f, grid.ratio, far)?;
        let mesh = rectangle_from_coordinates(&xs, &zs, Diagonal::Forward)?;
        let eps = 1e-6 * dz;
        let tau0 = self.tau0(variant);
        let on_fault = move |x: &[f64; 2]| x[0] < eps && x[1].abs() < l_f + eps;
        let mut model = ModelBuilder::scalar(mesh)
            .material(AntiplaneMaterial::new(self.shear_modulus(), self.rho))
            .frictional_boundary(Part::predicate("fault", on_fault))
            .neumann(Part::predicate("fault", on_fault), move |_| [tau0])
            .dirichlet(
                Part::predicate("locked", move |x| x[0] < eps && x[1].abs() > l_f - eps),
                [0.0],
            )
            .dirichlet(
                Part::predicate("far", move |x| x[0] > far - eps || x[1].abs() > far - eps),
                [0.0],
            )
            .antisymmetric_fault(2.0)
            .without_mass()
            .build()?;
        model.initial_displacement.fill(0.0);
        Ok(model)
    }

    /// The problem of A or S on `model` (the fault alone or the finite-element model):
    /// the regularised law at σ̄₀, the aging or slip law with D_RS, θ₀ of
    /// [`alpha0`](Self::alpha0), quasi-dynamic with η = μ/(2c_s), the pore pressure
    /// `pressure`, first trial step 1 s.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `variant` for C; invalid parameters.
    pub fn rate_state_builder<const C: usize>(
        &self,
        model: Model<2, C>,
        variant: Bp6Variant,
        pressure: Arc<dyn PorePressure<2>>,
    ) -> Result<SimulationBuilder<2, AsinhLaw, BuiltinStateLaw, Integrator, C>> {
        self.validate()?;
        let kind = match variant {
            Bp6Variant::A => StateLawKind::Aging,
            Bp6Variant::S => StateLawKind::Slip,
            Bp6Variant::C => {
                return Err(invalid(
                    "variant",
                    "BP6-C has constant friction: use SeasBp6::constant_friction",
                ))
            }
        };
        let law = AsinhLaw::new(self.params())?;
        Ok(SimulationBuilder::new(model)
            .friction_at(move |_| Ok::<_, rsf_friction::Error>(law))
            .state_law(BuiltinStateLaw::new(kind, self.d_rs)?)
            .initial_state(self.alpha0())
            .integrator(Integrator::Quasistatic(Quasistatic::new()))
            .radiation_damping(self.radiation_damping())
            .pore_pressure(pressure)
            .time_step(1.0))
    }

    /// BP6-A or -S on the fault alone of cells `dz` with the whole space's kernel
    /// (`kernel`: the FFT product, or stored dense or as an ℋ-matrix), as a fault ODE with
    /// `options`.
    ///
    /// # Errors
    /// As [`rate_state_builder`](Self::rate_state_builder); the operator's and the
    /// fault ODE's set-up errors.
    pub fn bem_fault_ode(
        &self,
        dz: f64,
        variant: Bp6Variant,
        kernel: impl Into<WholeSpaceKernel>,
        options: FaultOdeOptions,
        pressure: Arc<dyn PorePressure<2>>,
    ) -> Result<SeasBp6FaultOde<2>> {
        let model = self.bem_model(dz, variant)?;
        let n = model.vertices.len();
        let operator = WholeSpaceAntiplane::new(n, dz, self.shear_modulus(), kernel)?;
        let alone = FaultAlone {
            operator: Box::new(operator),
            plate_velocity: vec![0.0; n],
        };
        self.rate_state_builder(model, variant, pressure)?
            .build_fault_ode_alone(options, alone)
    }

    /// The fault alone of BP6-C on cells `dz` ([`bem_model`](Self::bem_model)) with the
    /// whole space's kernel as its stiffness ([`Model::set_fault_stiffness`]: `S` formed
    /// densely from `kernel`'s products and symmetrised), for the implicit scheme
    /// ([`constant_friction`](Self::constant_friction)).
    ///
    /// # Errors
    /// Those of [`bem_model`](Self::bem_model), of the operator and of the stiffness
    /// (more than 20 000 cells).
    pub fn bem_constant_friction_model(
        &self,
        dz: f64,
        kernel: impl Into<WholeSpaceKernel>,
    ) -> Result<Model<2, 2>> {
        let mut model = self.bem_model(dz, Bp6Variant::C)?;
        let n = model.vertices.len();
        let mut operator = WholeSpaceAntiplane::new(n, dz, self.shear_modulus(), kernel)?;
        model.set_fault_stiffness(&mut operator, rsf::Parallelism::SEQ)?;
        Ok(model)
    }

    /// BP6-A or -S on the finite-element model `model` ([`fe_model`](Self::fe_model)) as
    /// a fault ODE (the model condensed onto the fault, `options.kernel`).
    ///
    /// # Errors
    /// As [`rate_state_builder`](Self::rate_state_builder); the set-up errors.
    pub fn fe_fault_ode(
        &self,
        model: Model<2, 1>,
        variant: Bp6Variant,
        options: FaultOdeOptions,
        pressure: Arc<dyn PorePressure<2>>,
    ) -> Result<SeasBp6FaultOde<1>> {
        self.rate_state_builder(model, variant, pressure)?
            .build_fault_ode(options)
    }

    /// BP6-C on `model` — the finite-element model ([`fe_model`](Self::fe_model) with
    /// [`Bp6Variant::C`], `C = 1`) or the fault alone with the boundary-element kernel
    /// ([`bem_constant_friction_model`](Self::bem_constant_friction_model), `C = 2`) — as
    /// the implicit scheme: Tresca friction `f_c (σ̄₀ − p(t))` (the bound moves with the
    /// pressure; [`rsf_friction::TrescaPotential`]'s exact minimiser), radiation damping η,
    /// quasi-static backward Euler (docs/math.md §11), the direct solver (the model
    /// condensed onto the fault and the nonsmooth problem solved there by Newton's method
    /// on the sliding nodes), adaptive steps of `control` from `tau0` (s), `V_init = 0`.
    ///
    /// # Errors
    /// Invalid parameters; the simulation's set-up errors.
    pub fn constant_friction<const C: usize>(
        &self,
        model: Model<2, C>,
        pressure: Arc<dyn PorePressure<2>>,
        tau0: f64,
        control: StepControl,
    ) -> Result<SeasBp6Implicit<C>> {
        self.validate()?;
        let law = Tresca::new(self.f_c, self.sigma_n)?;
        SimulationBuilder::new(model)
            .friction_at(move |_| Ok::<_, rsf_friction::Error>(law))
            .integrator(Integrator::Quasistatic(Quasistatic::new()))
            .radiation_damping(self.radiation_damping())
            .pore_pressure(pressure)
            .solver(rsf::SolverKind::Direct)
            .time_step(tau0)
            .step_control(control)
            .build()
    }

    /// The adaptive steps of BP6-C: local error of the slip at most `tolerance` relative
    /// and `tolerance · D_RS` (m) absolute per step, steps in [1e-3 s, 1 day]. No test on
    /// the slip rate's logarithm (`slip_rate_floor`): a node that starts to slide jumps
    /// from `V = 0` to `V > 0` however short the step.
    ///
    /// # Errors
    /// An invalid tolerance.
    pub fn step_control(&self, tolerance: f64) -> Result<StepControl> {
        Ok(StepControl::new(tolerance, self.d_rs, 1e-3, 86_400.0)?)
    }

    /// Options of the fault ODE for BP6-A and -S: Dormand–Prince 5(4), local errors at most
    /// `tolerance · D_RS` in slip and `tolerance` in ln θ per step, steps in [1e-6 s,
    /// 1 yr].
    ///
    /// # Errors
    /// An invalid tolerance.
    pub fn fault_ode_options(&self, tolerance: f64) -> Result<FaultOdeOptions> {
        crate::seas_fault_ode_options(tolerance, self.d_rs)
    }

    /// The headers of the BP6 files of `variant` on cells or elements of `dz` (m)
    /// ([`rsf_seas::SeasBp6Output`] reads the problem, modeler, date and element size).
    pub fn seas_setup(&self, variant: Bp6Variant, dz: f64) -> rsf_seas::SeasSetup {
        rsf_seas::SeasSetup {
            problem: format!("SEAS Benchmark BP6-QD-{}", variant.name()),
            modeler: "rsf".into(),
            date: rsf_seas::utc_date_today(),
            element_size: dz,
            stations: Vec::new(),
            depth_axis: 1,
            depth_down: false,
            sigma_n: self.sigma_n,
            profile_spacing: 100.0,
            sampling: rsf_seas::SeasSampling::default(),
            layout: rsf_seas::SeasLayout::default(),
            surface_stations: Vec::new(),
        }
    }

    /// The frictional nodes of `model` as the BP6 output reads them: positions `z`, slip
    /// dofs (the second component of a fault alone's cells, the field of the
    /// finite-element model's nodes), lengths (weights).
    pub fn output_fault<const C: usize>(
        &self,
        model: &Model<2, C>,
        variant: Bp6Variant,
    ) -> rsf_seas::Bp6Fault {
        let fb = &model.frictional_boundary;
        let slip_component = if C == 1 { 0 } else { 1 };
        rsf_seas::Bp6Fault {
            positions: fb.nodes.iter().map(|&p| model.vertices[p][1]).collect(),
            slip_dofs: fb.nodes.iter().map(|&p| C * p + slip_component).collect(),
            lengths: fb.weights.clone(),
            shear_modulus: self.shear_modulus(),
            sigma_n: self.sigma_n,
            has_state: variant != Bp6Variant::C,
        }
    }
}
