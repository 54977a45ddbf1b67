//! The SCEC SEAS benchmark BP7-QD-A / BP7-QD-S (docs/seas-bp7.md; the description
//! "SEAS_BP7_May2023rev", restated from five implementations in the shared notes
//! `benchmarks/seas-bp7.md`): a velocity-weakening disc of radius `R_VW = 200 m` in the
//! rate-and-state square `|x₂|, |x₃| ≤ l_f = 400 m` of a planar fault in a whole space,
//! the fault outside the square creeping at `V_p` (back slip), kicked at `t = 0` by the
//! prescribed shear-stress bump `Δτ₀ G₁(r) G₂(t)` centred at `(−50, −50)` m. Variants:
//! the aging law (A) and the slip law (S).
//!
//! The fault alone on `(2 l_f/Δx)²` square cells with the whole space's operator
//! ([`crate::square_fault`], [`rsf::halfspace_operator::WholeSpaceGrid`]); the bump a
//! [`LoadChange`] of the fault ODE. Coordinates are the description's, `x₃` positive
//! down.

use std::sync::Arc;

use rsf::fault_alone::FaultAlone;
use rsf::fault_ode::{FaultOdeOptions, LoadChange};
use rsf::halfspace::Medium;
use rsf::time::Quasistatic;
use rsf::{FaultOde, Integrator, Model, Result, SimulationBuilder};
use rsf_friction::{AsinhLaw, RateStateParams};
use rsf_seas::{bp7_body_station_points, SeasBp5Output, SeasSetup, StrikeDipFault};
use rsf_state::{BuiltinStateLaw, StateLawKind};

use crate::invalid;
use crate::scene_file::{finite, poisson_ratio, positive_fields};
use crate::square_fault::{square_cells, square_model, square_operator, SquareProblemBuilder};

/// The fault ODE of BP7 (the regularised law, the aging or the slip law, a 3-D fault
/// alone).
pub type SeasBp7FaultOde = FaultOde<3, AsinhLaw, BuiltinStateLaw, 3>;

/// The state law of a BP7 variant (`aging`, `slip` in files, flags and Python).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Bp7Law {
    /// BP7-QD-A: the aging law `θ̇ = 1 − Vθ/D_RS`.
    #[default]
    Aging,
    /// BP7-QD-S: the slip law `θ̇ = −(Vθ/D_RS) ln(Vθ/D_RS)`.
    Slip,
}

impl Bp7Law {
    /// `"A"` or `"S"`, as the benchmark names the variants.
    pub fn name(self) -> &'static str {
        match self {
            Self::Aging => "A",
            Self::Slip => "S",
        }
    }

    /// The state law's kind.
    pub fn kind(self) -> StateLawKind {
        match self {
            Self::Aging => StateLawKind::Aging,
            Self::Slip => StateLawKind::Slip,
        }
    }
}

impl std::str::FromStr for Bp7Law {
    type Err = rsf::Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "aging" | "a" => Ok(Self::Aging),
            "slip" | "s" => Ok(Self::Slip),
            _ => Err(invalid("law", format!("`{s}`: one of aging, slip"))),
        }
    }
}

/// BP7-QD parameters (Table 1 as the implementations use it; SI units).
/// [`SeasBp7::default`] is the benchmark with `D_RS = 0.50 mm` (the restatement's open
/// point: 0.53 mm in two of five sources; docs/seas-bp7.md).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SeasBp7 {
    /// Density ρ (kg/m³).
    pub rho: f64,
    /// Shear wave speed c_s (m/s).
    pub c_s: f64,
    /// Poisson's ratio ν.
    pub nu: f64,
    /// Effective normal stress σ̄ (Pa).
    pub sigma_n: f64,
    /// Direct effect in the velocity-weakening disc, a₀.
    pub a0: f64,
    /// Direct effect in the rest of the square, a_max.
    pub a_max: f64,
    /// Evolution effect b (uniform).
    pub b: f64,
    /// Characteristic slip distance D_RS (m).
    pub d_rs: f64,
    /// Reference slip rate V₀ (m/s).
    pub v0: f64,
    /// Reference friction coefficient f₀.
    pub f0: f64,
    /// Plate rate V_p (m/s): the fault outside the square creeps at it along `+x₂`.
    pub v_p: f64,
    /// Initial slip rate along x₂, V_init (m/s).
    pub v_init: f64,
    /// Initial slip rate along x₃, V_zero (m/s; keeps log10 V₃ finite).
    pub v_zero: f64,
    /// Radius of the velocity-weakening disc R_VW (m).
    pub r_vw: f64,
    /// Half-width l_f of the rate-and-state square (m).
    pub l_f: f64,
    /// Amplitude of the stress bump Δτ₀ (Pa).
    pub dtau0: f64,
    /// Radius of the bump R_nuc (m).
    pub r_nuc: f64,
    /// Rise time of the bump T (s).
    pub t_rise: f64,
    /// The bump's centre `(y₂, y₃)` (m, `x₃` down).
    pub hypocentre: [f64; 2],
}

impl Default for SeasBp7 {
    fn default() -> Self {
        Self {
            rho: 2670.0,
            c_s: 3464.0,
            nu: 0.25,
            sigma_n: 25e6,
            a0: 0.004,
            a_max: 0.016,
            b: 0.01,
            d_rs: 5e-4,
            v0: 1e-6,
            f0: 0.6,
            v_p: 1e-9,
            v_init: 1e-9,
            v_zero: 1e-20,
            r_vw: 200.0,
            l_f: 400.0,
            dtau0: 1.75e6,
            r_nuc: 150.0,
            t_rise: 1.0,
            hypocentre: [-50.0, -50.0],
        }
    }
}

/// `G₁(r) = exp(r²/(r² − R²))` for `r < R`, 0 beyond (a `C^∞` bump, `G₁(0) = 1`).
pub fn bp7_g1(r: f64, r_nuc: f64) -> f64 {
    if r < r_nuc {
        (r * r / (r * r - r_nuc * r_nuc)).exp()
    } else {
        0.0
    }
}

/// `G₂(t) = exp((t − T)²/(t (t − 2T)))` for `0 < t < T`, 0 before, 1 from `T` on.
pub fn bp7_g2(t: f64, t_rise: f64) -> f64 {
    if t <= 0.0 {
        0.0
    } else if t < t_rise {
        ((t - t_rise).powi(2) / (t * (t - 2.0 * t_rise))).exp()
    } else {
        1.0
    }
}

impl SeasBp7 {
    /// Checks every parameter finite, all but `f0`, `nu` and the hypocentre positive, `ν`
    /// in `(−1, ½)`, `R_VW ≤ l_f`.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        positive_fields!(self; rho, c_s, sigma_n, a0, a_max, b, d_rs, v0, v_p, v_init, v_zero,
            r_vw, l_f, dtau0, r_nuc, t_rise)?;
        finite("f0", self.f0)?;
        if !self.hypocentre.iter().all(|c| c.is_finite()) {
            return Err(invalid("hypocentre", "must be finite"));
        }
        poisson_ratio(self.nu)?;
        if self.r_vw > self.l_f {
            return Err(invalid("r_vw", "must be at most l_f"));
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

    /// The direct effect at `(x₂, x₃)` (m): `a₀` in the disc `r ≤ R_VW` (a sharp step),
    /// `a_max` outside.
    pub fn a_at(&self, x2: f64, x3: f64) -> f64 {
        if x2.hypot(x3) <= self.r_vw {
            self.a0
        } else {
            self.a_max
        }
    }

    /// The rate-and-state parameters of [`AsinhLaw`] at `(x₂, x₃)`: `mu0 = f₀`,
    /// `v0 = V₀`, `l = D_RS`, the local a.
    pub fn params(&self, x2: f64, x3: f64) -> RateStateParams {
        RateStateParams {
            mu0: self.f0,
            a: self.a_at(x2, x3),
            b: self.b,
            v0: self.v0,
            l: self.d_rs,
            sigma_n: self.sigma_n,
        }
    }

    /// The initial state `α = ln θ₀`, `θ₀ = D_RS/V_init` (s) everywhere.
    pub fn alpha0(&self) -> f64 {
        (self.d_rs / self.v_init).ln()
    }

    /// The prestress `τ⁰` at `(x₂, x₃)` (Pa; components along x₂, x₃): steady state at
    /// `|V(0)|`, `σ̄ a asinh(|V(0)|/(2V₀) exp((f₀ + b ln(V₀θ₀/D_RS))/a)) + η|V(0)|`
    /// with the local a, along `V(0)/|V(0)|`. 16.036 MPa in the disc, 13.964 MPa outside.
    pub fn tau0_at(&self, x2: f64, x3: f64) -> [f64; 2] {
        let v = self.initial_speed();
        let a = self.a_at(x2, x3);
        let psi = self.f0 + self.b * (self.v0 * self.alpha0().exp() / self.d_rs).ln();
        // asinh(x) for x up to e^{0.67/0.004}: ln(2x) beyond 1e150, as asinh overflows.
        let ln_x = (v / (2.0 * self.v0)).ln() + psi / a;
        let asinh = if ln_x > 300.0 {
            ln_x + std::f64::consts::LN_2
        } else {
            ln_x.exp().asinh()
        };
        let tau = self.sigma_n * a * asinh + self.radiation_damping() * v;
        [tau * (self.v_init / v), tau * (self.v_zero / v)]
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
    /// prestress [`tau0_at`](Self::tau0_at) of each cell's centre.
    ///
    /// # Errors
    /// As [`cells`](Self::cells).
    pub fn model(&self, dx: f64) -> Result<Model<3, 3>> {
        square_model(&self.cells(dx)?, dx, |x2, x3| self.tau0_at(x2, x3))
    }

    /// The stress bump `Δτ⁰ = Δτ₀ G₁(r) G₂(t)` along `x₂` on the cells of side `dx`
    /// (each cell its centre's `G₁`), as a change of the load: forces `dx² Δτ₀ G₁` on
    /// the x₂ unknowns, history [`bp7_g2`], a breakpoint at `T`. It stays on after `T`.
    ///
    /// # Errors
    /// As [`cells`](Self::cells).
    pub fn perturbation(&self, dx: f64) -> Result<LoadChange> {
        let area = dx * dx;
        let forces = self
            .cells(dx)?
            .iter()
            .flat_map(|c| self.bump_force(area, c[0], c[1]))
            .collect();
        Ok(self.bump(forces))
    }

    /// The bump's force `w Δτ₀ G₁(r)` along `x₂` and 0 along `x₃` (N) at `(x₂, x₃)` (m)
    /// of the weight `w` (m², a cell's area or a node's), `r` the distance from the
    /// hypocentre.
    pub(crate) fn bump_force(&self, w: f64, x2: f64, x3: f64) -> [f64; 2] {
        let [y2, y3] = self.hypocentre;
        let r = (x2 - y2).hypot(x3 - y3);
        [w * self.dtau0 * bp7_g1(r, self.r_nuc), 0.0]
    }

    /// The bump as a change of the load: `forces` (N, per slip unknown,
    /// [`bump_force`](Self::bump_force)), history [`bp7_g2`], a breakpoint at `T`.
    pub(crate) fn bump(&self, forces: Vec<f64>) -> LoadChange {
        let t_rise = self.t_rise;
        LoadChange {
            forces,
            history: Arc::new(move |t| bp7_g2(t, t_rise)),
            breakpoints: vec![t_rise],
        }
    }

    /// The problem of BP7 on `model` with the state law `law`: the regularised law with
    /// the local [`params`](Self::params), θ₀ of [`alpha0`](Self::alpha0), quasi-dynamic
    /// with η = μ/(2c_s), first trial step 1 ms.
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn problem_builder(&self, model: Model<3, 3>, law: Bp7Law) -> Result<SquareProblemBuilder> {
        self.validate()?;
        let this = *self;
        Ok(SimulationBuilder::new(model)
            .friction_at(move |x| AsinhLaw::new(this.params(x[1], x[2])))
            .state_law(BuiltinStateLaw::new(law.kind(), self.d_rs)?)
            .initial_state(self.alpha0())
            .integrator(Integrator::Quasistatic(Quasistatic::new()))
            .radiation_damping(self.radiation_damping())
            .time_step(1e-3))
    }

    /// The fault ODE of BP7 on the cells of side `dx` with the whole space's operator
    /// ([`square_operator`]), loaded by back slip at `V_p` along `+x₂` and the bump
    /// ([`perturbation`](Self::perturbation)), and the displacement per unit slip at
    /// the six off-fault stations ([`bp7_body_station_points`]; for
    /// [`output`](Self::output)).
    ///
    /// # Errors
    /// As [`model`](Self::model) and [`problem_builder`](Self::problem_builder); the
    /// operator's; the set-up errors of
    /// [`build_fault_ode_alone`](rsf::SimulationBuilder::build_fault_ode_alone) and
    /// [`FaultOde::with_load_change`].
    pub fn fault_ode(
        &self,
        dx: f64,
        law: Bp7Law,
        options: FaultOdeOptions,
    ) -> Result<(SeasBp7FaultOde, Vec<Vec<f64>>)> {
        let model = self.model(dx)?;
        let medium = self.medium()?;
        let operator = square_operator(&model, medium)?;
        let columns = operator.displacement_columns(&medium, &bp7_body_station_points())?;
        let alone = FaultAlone {
            operator: Box::new(operator),
            plate_velocity: (0..model.vertices.len())
                .flat_map(|_| [self.v_p, 0.0])
                .collect(),
        };
        let ode = self
            .problem_builder(model, law)?
            .build_fault_ode_alone(options, alone)?
            .with_load_change(self.perturbation(dx)?)?;
        Ok((ode, columns))
    }

    /// Options of the fault ODE for BP7: Dormand–Prince 5(4), local errors at most
    /// `tolerance · D_RS` in slip and `tolerance` in ln θ per step, steps in
    /// [1e-6 s, 1 yr].
    ///
    /// # Errors
    /// An invalid tolerance.
    pub fn fault_ode_options(&self, tolerance: f64) -> Result<FaultOdeOptions> {
        crate::seas_fault_ode_options(tolerance, self.d_rs)
    }

    /// The fault as the files see it: the square `2 l_f × 2 l_f`, μ, η, the plate rate.
    pub fn output_fault(&self) -> StrikeDipFault {
        StrikeDipFault {
            length: 2.0 * self.l_f,
            width: 2.0 * self.l_f,
            shear_modulus: self.shear_modulus(),
            radiation_damping: self.radiation_damping(),
            plate_rate: self.v_p,
        }
    }

    /// BP7's files ([`SeasBp5Output::bp7`]) of a run on the cells of side `dx` into `dir`
    /// (created if missing): `body_columns` from [`fault_ode`](Self::fault_ode), `setup`
    /// the headers and sampling.
    ///
    /// # Errors
    /// As [`cells`](Self::cells); those of [`SeasBp5Output::bp7`].
    pub fn output(
        &self,
        dir: &std::path::Path,
        dx: f64,
        body_columns: Vec<Vec<f64>>,
        setup: SeasSetup,
    ) -> Result<SeasBp5Output> {
        let cells = self.cells(dx)?;
        Ok(SeasBp5Output::bp7(
            dir,
            &self.output_fault(),
            (dx, self.r_vw),
            cells,
            body_columns,
            setup,
        )?)
    }
}
