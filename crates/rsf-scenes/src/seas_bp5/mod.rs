//! The SCEC SEAS benchmark BP5-QD (Jiang et al. 2022, JGR Solid Earth 127,
//! e2021JB023519; docs/seas-bp5.md): a vertical strike-slip fault in a homogeneous
//! half-space, slip with two components, a 100 km × 40 km rate-and-state region in a
//! plane that creeps at the plate rate, a nucleation patch, 1800 years.
//!
//! Coordinates: the benchmark's `(x₁, x₂, x₃)` (`x₁` normal to the fault, `x₂` along
//! strike, `x₃` depth, positive down) are the model's `(x, y, −z)`: the model's `z` points
//! up, the free surface is `z = 0`. A model's slip `(u_y, u_z)` is the benchmark's
//! `(slip₂, −slip₃)`.

use rsf::fault_ode::FaultOdeOptions;
use rsf::halfspace::Medium;
use rsf::{FaultOde, Model, Result, SimulationBuilder};
use rsf_friction::{AsinhLaw, RateStateParams};
use rsf_state::Aging;

use crate::invalid;
use crate::scene_file::{finite, poisson_ratio, positive_fields};
use rsf_seas::bp5_body_station_points;

mod half_space;
mod pair;
mod volume;

pub use half_space::MAX_CELLS;
pub use pair::{Bp5Pair, Bp5PairPatch, BP5_PAIR_FAULTS, BP5_PAIR_STATIONS};
pub use volume::{SeasBp5Grid, SeasBp5Mesh, GRADED_MAX_CELLS};

/// The fault ODE of BP5 (the regularised law, the aging law, a 3-D fault alone).
pub type SeasBp5FaultOde = FaultOde<3, AsinhLaw, Aging, 3>;

/// BP5-QD parameters (Table 1 of the description; SI units). [`SeasBp5::default`] is
/// the benchmark.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SeasBp5 {
    /// Density ρ (kg/m³).
    pub rho: f64,
    /// Shear wave speed c_s (m/s).
    pub c_s: f64,
    /// Poisson's ratio ν.
    pub nu: f64,
    /// Effective normal stress σ̄_n (Pa).
    pub sigma_n: f64,
    /// Direct effect a in the velocity-weakening core.
    pub a0: f64,
    /// Direct effect a outside it (velocity strengthening).
    pub a_max: f64,
    /// Evolution effect b (uniform).
    pub b0: f64,
    /// Characteristic slip distance L (m) outside the nucleation patch.
    pub l: f64,
    /// L (m) in the nucleation patch.
    pub l_nucleation: f64,
    /// Reference friction coefficient f₀.
    pub f0: f64,
    /// Reference slip rate V₀ (m/s).
    pub v0: f64,
    /// Plate rate V_p (m/s), along +x₂.
    pub v_p: f64,
    /// Initial slip rate V_init (m/s) outside the nucleation patch.
    pub v_init: f64,
    /// Initial slip rate V_i (m/s) in the nucleation patch.
    pub v_i: f64,
    /// Depth h_s of the shallow strengthening layer (m).
    pub h_s: f64,
    /// Width h_t of the transitions of a (m).
    pub h_t: f64,
    /// Depth extent H of the weakening core (m).
    pub h: f64,
    /// Length l of the weakening core along strike (m).
    pub l_core: f64,
    /// Depth W_f of the rate-and-state region (m).
    pub w_f: f64,
    /// Length l_f of the rate-and-state region along strike (m).
    pub l_f: f64,
    /// Size w of the nucleation patch (m).
    pub w: f64,
    /// A compliant fault zone around the rate-and-state region (not part of the
    /// benchmark: `None` there; the finite-element kernel only; docs/seas-bp5.md, "A
    /// compliant fault zone").
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fault_zone: Option<FaultZone>,
}

/// A compliant fault zone (not part of BP5: a problem no half-space code can run): the slab
/// `|x₁| ≤ half_width` over the rate-and-state region (`|x₂| ≤ l_f/2`, `x₃ ≤ W_f`) has the
/// shear modulus `rigidity_ratio · μ` (the density and Poisson's ratio of the host, so its
/// shear-wave speed is `√rigidity_ratio · c_s`); the fault's radiation damping is the
/// zone's, `η = √(ρ μ_fz)/2`. Damaged rock around mature faults: low-velocity zones of a
/// few hundred metres to a few kilometres with wave speeds reduced by 20–60 %
/// (docs/seas-bp5.md lists the cycle models that study them).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaultZone {
    /// Half of the slab's width (m), positive; the mesh must resolve it
    /// ([`SeasBp5Grid::near_fault`] at least this, a whole number of `dx`).
    pub half_width: f64,
    /// The zone's shear modulus over the host's, in `(0, 1]` (1: no contrast).
    pub rigidity_ratio: f64,
}

impl Default for SeasBp5 {
    fn default() -> Self {
        Self {
            rho: 2670.0,
            c_s: 3464.0,
            nu: 0.25,
            sigma_n: 25e6,
            a0: 0.004,
            a_max: 0.04,
            b0: 0.03,
            l: 0.14,
            l_nucleation: 0.13,
            f0: 0.6,
            v0: 1e-6,
            v_p: 1e-9,
            v_init: 1e-9,
            v_i: 0.03,
            h_s: 2e3,
            h_t: 2e3,
            h: 12e3,
            l_core: 60e3,
            w_f: 40e3,
            l_f: 100e3,
            w: 12e3,
            fault_zone: None,
        }
    }
}

impl SeasBp5 {
    /// Checks that every parameter is finite, all but `f0` and `nu` positive, `ν` in
    /// `(−1, ½)`, and the core and the patch inside the rate-and-state region.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<()> {
        positive_fields!(self; rho, c_s, sigma_n, a0, a_max, b0, l, l_nucleation, v0, v_p,
            v_init, v_i, h_s, h_t, h, l_core, w_f, l_f, w)?;
        finite("f0", self.f0)?;
        poisson_ratio(self.nu)?;
        if self.h_s + 2.0 * self.h_t + self.h > self.w_f || self.l_core + 2.0 * self.h_t > self.l_f
        {
            return Err(invalid(
                "w_f",
                "the weakening core and its transitions must lie inside the rate-and-state \
                 region (h_s + 2 h_t + H <= W_f, l + 2 h_t <= l_f)",
            ));
        }
        if let Some(zone) = self.fault_zone {
            if !(zone.half_width.is_finite() && zone.half_width > 0.0) {
                return Err(invalid(
                    "fault_zone.half_width",
                    format!(
                        "{} m must be positive and finite",
                        rsf_numeric::written(zone.half_width)
                    ),
                ));
            }
            if !(zone.rigidity_ratio > 0.0 && zone.rigidity_ratio <= 1.0) {
                return Err(invalid(
                    "fault_zone.rigidity_ratio",
                    format!(
                        "{} must be in (0, 1]",
                        rsf_numeric::written(zone.rigidity_ratio)
                    ),
                ));
            }
        }
        if self.w > self.l_core {
            return Err(invalid(
                "w",
                "the nucleation patch must lie in the core (w <= l)",
            ));
        }
        Ok(())
    }

    /// Shear modulus μ = ρ c_s² (Pa); 32.04 GPa for the benchmark.
    pub fn shear_modulus(&self) -> f64 {
        self.rho * self.c_s * self.c_s
    }

    /// The shear modulus at the fault (Pa): the fault zone's, `rigidity_ratio · μ`, or μ.
    pub fn fault_shear_modulus(&self) -> f64 {
        self.shear_modulus() * self.fault_zone.map_or(1.0, |z| z.rigidity_ratio)
    }

    /// Radiation damping η = μ/(2c_s) (Pa·s/m) with the modulus and shear-wave speed at
    /// the fault: the fault zone's `rigidity_ratio · μ` and `√rigidity_ratio · c_s`, so
    /// that a ratio of 1 gives the description's `μ/(2c_s)` bit for bit.
    pub fn radiation_damping(&self) -> f64 {
        let ratio = self.fault_zone.map_or(1.0, |z| z.rigidity_ratio);
        self.fault_shear_modulus() / (2.0 * self.c_s * ratio.sqrt())
    }

    /// The half-space: λ = 2μν/(1 − 2ν), μ.
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn medium(&self) -> Result<Medium> {
        self.validate()?;
        let mu = self.shear_modulus();
        Medium::new(2.0 * mu * self.nu / (1.0 - 2.0 * self.nu), mu)
            .map_err(|e| invalid("nu", e.to_string()))
    }

    /// a at `(x₂, x₃)` (m; `x₃` the depth): `a0` in the core (`h_s + h_t ≤ x₃ ≤ h_s +
    /// h_t + H`, `|x₂| ≤ l/2`), `a_max` a transition `h_t` away from it, linear in between
    /// (the larger of the two distances along depth and strike).
    pub fn a(&self, x2: f64, x3: f64) -> f64 {
        let depth = (x3 - self.h_s - self.h_t - 0.5 * self.h).abs() - 0.5 * self.h;
        let strike = x2.abs() - 0.5 * self.l_core;
        let r = (depth.max(strike) / self.h_t).clamp(0.0, 1.0);
        self.a0 + r * (self.a_max - self.a0)
    }

    /// Whether `(x₂, x₃)` is in the nucleation patch (`−l/2 ≤ x₂ ≤ −l/2 + w`,
    /// `h_s + h_t ≤ x₃ ≤ h_s + h_t + H`).
    pub fn in_nucleation_patch(&self, x2: f64, x3: f64) -> bool {
        let x2_lo = -0.5 * self.l_core;
        let x3_lo = self.h_s + self.h_t;
        (x2_lo..=x2_lo + self.w).contains(&x2) && (x3_lo..=x3_lo + self.h).contains(&x3)
    }

    /// The share of the square of side `dx` centred at `(x₂, x₃)` — a node's dual cell
    /// on the fault's grid, or a boundary element's cell — that lies in the nucleation
    /// patch, in `[0, 1]` (exact: the overlap of two intervals along each axis, the dual
    /// cell clipped to the half-space `x₃ ≥ 0`). A node or cell on the patch's edge takes
    /// its share of the patch's L and prestress ([`l_in_cell`](Self::l_in_cell),
    /// [`tau0_in_cell`](Self::tau0_in_cell)), so that the patch's weights on the fault sum
    /// to its area `w × H` exactly (docs/seas-bp5.md, "The nucleation patch's weights").
    pub fn patch_share(&self, x2: f64, x3: f64, dx: f64) -> f64 {
        let overlap = |lo: f64, hi: f64, a: f64, b: f64| (hi.min(b) - lo.max(a)).max(0.0);
        let x2_lo = -0.5 * self.l_core;
        let x3_lo = self.h_s + self.h_t;
        let h = 0.5 * dx;
        let (d_lo, d_hi) = ((x3 - h).max(0.0), x3 + h);
        let along = overlap(x2 - h, x2 + h, x2_lo, x2_lo + self.w) / dx;
        let down = overlap(d_lo, d_hi, x3_lo, x3_lo + self.h) / (d_hi - d_lo);
        (along * down).clamp(0.0, 1.0)
    }

    /// L of the node or cell of side `dx` at `(x₂, x₃)` (m): the share-weighted mean of
    /// the patch's and the rest's ([`patch_share`](Self::patch_share)).
    pub fn l_in_cell(&self, x2: f64, x3: f64, dx: f64) -> f64 {
        let s = self.patch_share(x2, x3, dx);
        if s == 0.0 {
            self.l
        } else if s == 1.0 {
            self.l_nucleation
        } else {
            s * self.l_nucleation + (1.0 - s) * self.l
        }
    }

    /// The prestress of the node or cell of side `dx` at `(x₂, x₃)` (Pa): the
    /// share-weighted mean of [`tau0`](Self::tau0) with the patch's `V_i` and with
    /// `V_init` ([`patch_share`](Self::patch_share)).
    pub fn tau0_in_cell(&self, x2: f64, x3: f64, dx: f64) -> f64 {
        let s = self.patch_share(x2, x3, dx);
        let at = |v: f64| {
            let a = self.a(x2, x3);
            let psi = self.f0 + self.b0 * (self.v0 / self.v_init).ln();
            self.sigma_n * a * (v / (2.0 * self.v0) * (psi / a).exp()).asinh()
                + self.radiation_damping() * v
        };
        if s == 0.0 {
            at(self.v_init)
        } else if s == 1.0 {
            at(self.v_i)
        } else {
            s * at(self.v_i) + (1.0 - s) * at(self.v_init)
        }
    }

    /// The spacing of the fault's grid of frictional nodes (the smallest distance between
    /// two of their distinct `x₂`; m): `Δx` on BP5's grids, of cells or of nodes.
    pub fn grid_spacing(model: &Model<3, 3>) -> f64 {
        let mut x2: Vec<f64> = model.on_frictional_nodes(|x| x[1]);
        x2.sort_by(f64::total_cmp);
        x2.dedup();
        x2.windows(2)
            .map(|w| w[1] - w[0])
            .fold(f64::INFINITY, f64::min)
    }

    /// L at `(x₂, x₃)` (m).
    pub fn l_at(&self, x2: f64, x3: f64) -> f64 {
        if self.in_nucleation_patch(x2, x3) {
            self.l_nucleation
        } else {
            self.l
        }
    }

    /// The initial slip rate at `(x₂, x₃)` (m/s, along +x₂): `V_i` in the patch, `V_init`
    /// elsewhere.
    pub fn initial_slip_rate(&self, x2: f64, x3: f64) -> f64 {
        if self.in_nucleation_patch(x2, x3) {
            self.v_i
        } else {
            self.v_init
        }
    }

    /// The rate-and-state parameters at `(x₂, x₃)` for the regularised law
    /// [`AsinhLaw`]: `mu0 = f0`, `a(x₂, x₃)`, `b0`, `l = L(x₂, x₃)`.
    pub fn params(&self, x2: f64, x3: f64) -> RateStateParams {
        RateStateParams {
            mu0: self.f0,
            a: self.a(x2, x3),
            b: self.b0,
            v0: self.v0,
            l: self.l_at(x2, x3),
            sigma_n: self.sigma_n,
        }
    }

    /// The initial state `α = ln θ₀ = ln(L/V_init)` (θ in s): steady state at the plate
    /// rate everywhere, the patch included (its ψ is the same; docs/seas-bp5.md).
    pub fn alpha0(&self, x2: f64, x3: f64) -> f64 {
        (self.l_at(x2, x3) / self.v_init).ln()
    }

    /// The prestress along +x₂ (Pa): `τ⁰ = σ̄_n a asinh(V/(2V₀) exp((f₀ + b ln(V₀/V_init))/a)) + ηV`
    /// with the local `a` and `V` the initial slip rate ([`initial_slip_rate`](Self::initial_slip_rate)),
    /// so that the fault starts at `V` with the state [`alpha0`](Self::alpha0).
    pub fn tau0(&self, x2: f64, x3: f64) -> f64 {
        let a = self.a(x2, x3);
        let v = self.initial_slip_rate(x2, x3);
        let psi = self.f0 + self.b0 * (self.v0 / self.v_init).ln();
        self.sigma_n * a * (v / (2.0 * self.v0) * (psi / a).exp()).asinh()
            + self.radiation_damping() * v
    }

    /// The off-fault stations of BP5 ([`SEAS_BP5_BODY_STATIONS`](crate::SEAS_BP5_BODY_STATIONS))
    /// as model points `(x₁, x₂, −x₃)` (m) ([`rsf_seas::bp5_body_station_points`]).
    pub fn body_station_points() -> Vec<[f64; 3]> {
        bp5_body_station_points()
    }

    /// The problem of BP5 on `model` (a fault alone or the volume model): the regularised
    /// law with [`params`](Self::params), the aging law with the local L, θ₀ of
    /// [`alpha0`](Self::alpha0), quasi-dynamic with η = μ/(2c_s), first trial step 1 ms.
    /// L (and so θ₀) is each node's or cell's share of the nucleation patch's
    /// ([`l_in_cell`](Self::l_in_cell) on the grid of [`grid_spacing`](Self::grid_spacing)).
    pub fn problem_builder(
        &self,
        model: Model<3, 3>,
    ) -> SimulationBuilder<3, AsinhLaw, Aging, rsf::Integrator, 3> {
        self.problem_builder_by(model, |_| *self)
    }

    /// [`problem_builder`](Self::problem_builder) with the parameters of `scene(x)` at each
    /// node `x` (model coordinates) — faults whose parameters differ, as
    /// [`Bp5Pair`](super::Bp5Pair)'s strands with [`Bp5PairPatch::West`](super::Bp5PairPatch);
    /// the radiation damping is `self`'s.
    pub fn problem_builder_by(
        &self,
        model: Model<3, 3>,
        scene: impl Fn(&[f64; 3]) -> SeasBp5 + Copy,
    ) -> SimulationBuilder<3, AsinhLaw, Aging, rsf::Integrator, 3> {
        let dx = Self::grid_spacing(&model);
        let l = move |x: &[f64; 3]| scene(x).l_in_cell(x[1], -x[2], dx);
        SimulationBuilder::new(model)
            .friction_at(move |x| {
                AsinhLaw::new(RateStateParams {
                    l: l(x),
                    ..scene(x).params(x[1], -x[2])
                })
            })
            .state_law_at(move |x| Aging::new(l(x)))
            .initial_state_at(move |x| (l(x) / scene(x).v_init).ln())
            .integrator(rsf::Integrator::Quasistatic(rsf_time::Quasistatic::new()))
            .radiation_damping(self.radiation_damping())
            .time_step(1e-3)
    }

    /// Options of the fault ODE for BP5: Dormand–Prince 5(4), local errors at most
    /// `tolerance · L` in slip and `tolerance` in ln θ per step, steps in [1e-6 s, 1 yr].
    ///
    /// # Errors
    /// An invalid tolerance.
    pub fn fault_ode_options(&self, tolerance: f64) -> Result<FaultOdeOptions> {
        crate::seas_fault_ode_options(tolerance, self.l)
    }
}
