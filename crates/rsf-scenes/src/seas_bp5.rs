//! The SCEC SEAS benchmark BP5-QD (Jiang et al. 2022, JGR Solid Earth 127,
//! e2021JB023519; docs/seas-bp5.md): a vertical strike-slip fault in a homogeneous
//! half-space, slip with two components, a 100 km × 40 km rate-and-state region in a
//! plane that creeps at the plate rate, a nucleation patch, 1800 years.
//!
//! Coordinates: the benchmark's `(x₁, x₂, x₃)` (`x₁` normal to the fault, `x₂` along
//! strike, `x₃` depth, positive down) are the model's `(x, y, −z)`: the model's `z` points
//! up, the free surface is `z = 0`. A model's slip `(u_y, u_z)` is the benchmark's
//! `(slip₂, −slip₃)`.

use rsf::fault_alone::FaultAlone;
use rsf::fault_ode::{FaultOdeOptions, SchurOnlySetup};
use rsf::fem::{
    cuboid_from_coordinates, cuboid_mirrored, geometric_grading, symmetric_grading, OctreeMesh,
    TetrahedronMesh,
};
use rsf::halfspace::Medium;
use rsf::halfspace_operator::{HalfSpaceOperator, HalfSpaceOptions};
use rsf::model::{CreepRate, MaterialRegions};
use rsf::{FaultOde, Material, Model, ModelBuilder, Part, Result, SimulationBuilder};
use rsf_friction::{AsinhLaw, RateStateParams};
use rsf_state::Aging;

use crate::invalid;
use rsf_seas::bp5_body_station_points;

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
        let fields = [
            ("rho", self.rho),
            ("c_s", self.c_s),
            ("sigma_n", self.sigma_n),
            ("a0", self.a0),
            ("a_max", self.a_max),
            ("b0", self.b0),
            ("l", self.l),
            ("l_nucleation", self.l_nucleation),
            ("v0", self.v0),
            ("v_p", self.v_p),
            ("v_init", self.v_init),
            ("v_i", self.v_i),
            ("h_s", self.h_s),
            ("h_t", self.h_t),
            ("h", self.h),
            ("l_core", self.l_core),
            ("w_f", self.w_f),
            ("l_f", self.l_f),
            ("w", self.w),
        ];
        for (name, v) in fields {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(name, format!("{v} must be positive and finite")));
            }
        }
        if !self.f0.is_finite() {
            return Err(invalid("f0", "must be finite"));
        }
        if !(self.nu > -1.0 && self.nu < 0.5) {
            return Err(invalid(
                "nu",
                format!("{} must be in (-1, 0.5)", rsf_numeric::number(self.nu)),
            ));
        }
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
                    format!("{} m must be positive and finite", zone.half_width),
                ));
            }
            if !(zone.rigidity_ratio > 0.0 && zone.rigidity_ratio <= 1.0) {
                return Err(invalid(
                    "fault_zone.rigidity_ratio",
                    format!("{} must be in (0, 1]", zone.rigidity_ratio),
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

    /// The cells of a grid of size `dx` on the rate-and-state region: their centres
    /// `(x₂, x₃)` (m), strike fastest, from the shallowest row down.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx` unless it divides `l_f` and `W_f` into
    /// whole cells (to 1e-9 relative).
    pub fn cells(&self, dx: f64) -> Result<Vec<[f64; 2]>> {
        self.validate()?;
        let count = |length: f64| -> Result<usize> {
            let n = length / dx;
            if !(dx.is_finite() && dx > 0.0) || n < 1.0 || (n - n.round()).abs() > 1e-12 * n {
                return Err(invalid(
                    "dx",
                    format!(
                        "{} m must divide l_f = {} m and W_f = {} m into whole cells",
                        rsf_numeric::number(dx),
                        self.l_f,
                        self.w_f
                    ),
                ));
            }
            Ok(n.round() as usize)
        };
        let (n_strike, n_dip) = (count(self.l_f)?, count(self.w_f)?);
        if n_strike.saturating_mul(n_dip) > MAX_CELLS {
            return Err(invalid(
                "dx",
                format!(
                    "{} m gives {n_strike} × {n_dip} cells, more than {MAX_CELLS} (a 250 m \
                     grid)",
                    rsf_numeric::number(dx)
                ),
            ));
        }
        let mut cells = Vec::with_capacity(n_strike * n_dip);
        for j in 0..n_dip {
            for i in 0..n_strike {
                cells.push([
                    -0.5 * self.l_f + (i as f64 + 0.5) * dx,
                    (j as f64 + 0.5) * dx,
                ]);
            }
        }
        Ok(cells)
    }

    /// The fault alone on the grid of size `dx` ([`Model::fault_only`]): one vertex per
    /// cell at `(0, x₂, −x₃)`, `x` (the fault normal) fixed, the prestress
    /// [`tau0`](Self::tau0) along `+y` as the load (times the cell's area).
    ///
    /// # Errors
    /// Those of [`cells`](Self::cells).
    pub fn model(&self, dx: f64) -> Result<Model<3, 3>> {
        let cells = self.cells(dx)?;
        let centres = cells.iter().map(|c| [0.0, c[0], -c[1]]).collect();
        let areas = vec![dx * dx; cells.len()];
        let mut model = Model::fault_only(centres, &areas, 0)?;
        for (k, c) in cells.iter().enumerate() {
            model.load[3 * k + 1] = dx * dx * self.tau0(c[0], c[1]);
        }
        Ok(model)
    }

    /// The fault ODE of BP5 on `model` (from [`model`](Self::model)) with Okada's
    /// half-space operator ([`HalfSpaceOperator::fault_alone`]: dense up to
    /// `half_space.dense_max` unknowns, an ℋ-matrix of accuracy `half_space.epsilon`
    /// beyond), loaded by back slip at `V_p` along `+x₂`: the regularised law with
    /// [`params`](Self::params), the aging law with the local L, θ₀ of
    /// [`alpha0`](Self::alpha0), η = μ/(2c_s), first trial step 1 ms.
    ///
    /// # Errors
    /// Invalid parameters; the operator's errors (as
    /// [`rsf::Error::InvalidParameter`] named `half_space`); the set-up errors of
    /// [`build_fault_ode_alone`](SimulationBuilder::build_fault_ode_alone).
    pub fn fault_ode(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        half_space: &HalfSpaceOptions,
    ) -> Result<SeasBp5FaultOde> {
        Ok(self
            .fault_ode_with_stations(model, options, half_space, &[])?
            .0)
    }

    /// The off-fault stations of BP5 ([`SEAS_BP5_BODY_STATIONS`](crate::SEAS_BP5_BODY_STATIONS))
    /// as model points `(x₁, x₂, −x₃)` (m) ([`rsf_seas::bp5_body_station_points`]).
    pub fn body_station_points() -> Vec<[f64; 3]> {
        bp5_body_station_points()
    }

    /// The vertices of a volume model ([`fe_model`](Self::fe_model)) nearest the off-fault
    /// stations ([`body_station_points`](Self::body_station_points)), sorted, without
    /// repeats: those the output reads off the fault.
    ///
    /// # Errors
    /// [`Model::nearest_node`]'s (a model without vertices).
    pub fn station_vertices(&self, model: &Model<3, 3>) -> Result<Vec<usize>> {
        let mut vertices = Self::body_station_points()
            .iter()
            .map(|x| model.nearest_node(x))
            .collect::<Result<Vec<usize>>>()?;
        vertices.sort_unstable();
        vertices.dedup();
        Ok(vertices)
    }

    /// As [`fault_ode`](Self::fault_ode), with the half-space displacement at `points`
    /// (model coordinates, m) per unit slip of every slip unknown
    /// ([`HalfSpaceOperator::displacement_columns`]) for off-fault stations.
    ///
    /// # Errors
    /// As [`fault_ode`](Self::fault_ode); a point above the surface or on an element.
    pub fn fault_ode_with_stations(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        half_space: &HalfSpaceOptions,
        points: &[[f64; 3]],
    ) -> Result<(SeasBp5FaultOde, Vec<Vec<f64>>)> {
        self.fault_ode_on_ranks(model, options, half_space, points, None)
    }

    /// As [`fault_ode_with_stations`](Self::fault_ode_with_stations), the operator's rows
    /// shared out to `ranks` if given ([`HalfSpaceOperator::fault_alone_on_ranks`]: each
    /// rank builds and holds its part of an ℋ-matrix operator; collective — every rank
    /// calls this with the same arguments). Share the fault ODE's evaluations with the
    /// same ranks ([`rsf::FaultOde::share_evaluations`]).
    ///
    /// # Errors
    /// As [`fault_ode_with_stations`](Self::fault_ode_with_stations).
    pub fn fault_ode_on_ranks(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        half_space: &HalfSpaceOptions,
        points: &[[f64; 3]],
        ranks: Option<Box<dyn rsf::ranks::RankGroup + Send>>,
    ) -> Result<(SeasBp5FaultOde, Vec<Vec<f64>>)> {
        self.validate()?;
        if self.fault_zone.is_some() {
            return Err(invalid(
                "fault_zone",
                "a fault zone is a change of the volume: it needs the finite-element kernel \
                 (fe_model), not the half-space operator",
            ));
        }
        let operator = match ranks {
            Some(group) => HalfSpaceOperator::fault_alone_on_ranks(&model, half_space, group),
            None => HalfSpaceOperator::fault_alone(&model, half_space),
        }
        .map_err(|e| invalid("half_space", e.to_string()))?;
        let columns = operator.displacement_columns(points)?;
        let cells = model.vertices.len();
        let plate_velocity = (0..cells).flat_map(|_| [self.v_p, 0.0]).collect();
        let alone = FaultAlone {
            operator: Box::new(operator),
            plate_velocity,
        };
        self.problem_builder(model)
            .build_fault_ode_alone(options, alone)
            .map(|ode| (ode, columns))
    }

    /// The problem of BP5 on `model` (a fault alone or the volume model): the regularised
    /// law with [`params`](Self::params), the aging law with the local L, θ₀ of
    /// [`alpha0`](Self::alpha0), quasi-dynamic with η = μ/(2c_s), first trial step 1 ms.
    pub fn problem_builder(
        &self,
        model: Model<3, 3>,
    ) -> SimulationBuilder<3, AsinhLaw, Aging, rsf::Integrator, 3> {
        SimulationBuilder::new(model)
            .friction_at(|x| AsinhLaw::new(self.params(x[1], -x[2])))
            .state_law_at(|x| Aging::new(self.l_at(x[1], -x[2])))
            .initial_state_at(|x| self.alpha0(x[1], -x[2]))
            .integrator(rsf::Integrator::Quasistatic(rsf_time::Quasistatic::new()))
            .radiation_damping(self.radiation_damping())
            .time_step(1e-3)
    }

    /// Half-space options of BP5: the free surface `z = 0`, the medium, dense up to
    /// 4 096 unknowns, ε = `epsilon` beyond.
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn half_space(&self, epsilon: f64) -> Result<HalfSpaceOptions> {
        Ok(HalfSpaceOptions {
            epsilon,
            ..HalfSpaceOptions::new(0.0, self.medium()?)
        })
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

/// Largest root cube of [`SeasBp5Mesh::Graded`] (m): cells at the far faces, 400 km
/// from the fault, of at most 64 km (the tensor grid's there at ratio 1.3: about 90 km).
pub const GRADED_ROOT_MAX: f64 = 64e3;

/// Most cells of [`SeasBp5Mesh::Graded`]'s mesh (about 2.4 GB of mesh and a few times more
/// of matrices).
pub const GRADED_MAX_CELLS: usize = 20_000_000;

/// The distance (m) between the boxes `a` and `b`, each `(lower, upper)` corners (0 where
/// they meet).
fn box_distance(a: ([f64; 3], [f64; 3]), b: ([f64; 3], [f64; 3])) -> f64 {
    (0..3)
        .map(|k| (a.0[k] - b.1[k]).max(b.0[k] - a.1[k]).max(0.0).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// How [`SeasBp5::fe_model`] meshes the volume.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SeasBp5Mesh {
    /// A tensor grid of Kuhn boxes: uniform `dx` over the rate-and-state region along
    /// strike and dip (and one cell either side of the fault), growing by `ratio` beyond,
    /// axis by axis — the fault's fine spacing repeated in every layer of the box.
    Tensor,
    /// The tensor grid with the boxes mirrored by the parity of their position
    /// (`round(x/dx)` odd along an axis): the graded mesh's "union jack" pattern of
    /// diagonals on the tensor grid's boxes, to tell the effect of the pattern from that of
    /// the grading (docs/seas-bp5.md).
    TensorMirrored,
    /// An octree of Kuhn cubes refined towards the rate-and-state region and the off-fault
    /// stations ([`OctreeMesh`], docs/fem.md "Graded meshes: octree of Kuhn cubes"): cells
    /// `dx` there — the tensor grid's own Kuhn cells, with parallel diagonals — growing with
    /// the distance `d` in every direction as `dx + (ratio − 1) d` (the tensor grid's
    /// growth) beyond the slab `near_fault`.
    #[default]
    Graded,
}

/// The finite-element grid of BP5's volume model ([`SeasBp5::fe_model`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SeasBp5Grid {
    /// Spacing on the fault's rate-and-state region (m); must divide `l_f/2` and `W_f`.
    pub dx: f64,
    /// Distance from the fault to the box's far faces, and depth of the box (m).
    pub domain: f64,
    /// Growth of the spacing away from the rate-and-state region, in `[1, 2]`.
    pub ratio: f64,
    /// The tensor grid or the graded mesh (for the latter the box reaches the first
    /// multiple of its root cube not below `domain`).
    #[serde(default)]
    pub mesh: SeasBp5Mesh,
    /// The graded mesh's cells are `dx` in the slab `|x₁| ≤ near_fault` over the
    /// rate-and-state region (m; 0: on the fault's own cells only), so that a fault zone of
    /// that half-width is resolved cell for cell ([`FaultZone`]); a whole number of `dx`.
    #[serde(default)]
    pub near_fault: f64,
}

impl Default for SeasBp5Grid {
    /// 4 km on the fault, a box reaching 400 km from it, growth 1.3, the graded mesh.
    fn default() -> Self {
        Self {
            dx: 4e3,
            domain: 400e3,
            ratio: 1.3,
            mesh: SeasBp5Mesh::Graded,
            near_fault: 0.0,
        }
    }
}

impl SeasBp5 {
    /// The rate-and-state region `|x₂| ≤ l_f/2`, `x₃ ≤ W_f` (with a relative margin of
    /// 1e-9 of `W_f`).
    pub fn in_rate_state_region(&self, x2: f64, x3: f64) -> bool {
        let eps = 1e-9 * self.w_f;
        x2.abs() <= 0.5 * self.l_f + eps && x3 <= self.w_f + eps
    }

    /// BP5 as a finite-element volume model on `grid` (quasi-dynamic: no mass): the box
    /// `|x|, |y| ≤ domain`, `−domain ≤ z ≤ 0` of Kuhn tetrahedra (`grid.mesh`: on a tensor
    /// grid, uniform `dx` over the rate-and-state region and one cell across the fault and
    /// growing by `ratio` beyond; or graded by bisection in every direction, `dx` at the
    /// rate-and-state region and the off-fault stations, the box rounded up to whole root
    /// cubes), isotropic (μ = ρc_s², ν); the whole plane `x = 0` a fault inside
    /// the body ([`ModelBuilder::internal_fault_polygon`], `t₁` along strike): its pairs
    /// outside the rate-and-state region creeping at `(V_p, 0)`
    /// ([`ModelBuilder::internal_creep_at`]), those inside it frictional; the far faces
    /// carrying each side's rigid motion `±V_p/2` along `y` (the fault's own vertices on
    /// them only by the creep); the free surface `z = 0`; the prestress
    /// [`tau0`](Self::tau0) as equal and opposite tractions `±τ⁰ e_y` on the fault's two
    /// faces over the rate-and-state region; the initial displacement 0.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx` (not dividing `l_f/2` and `W_f`),
    /// `domain` (not beyond 1.5 l_f/2 and 1.5 W_f) or `ratio` (outside `[1, 2]`);
    /// grading and assembly errors.
    pub fn fe_model(&self, grid: &SeasBp5Grid) -> Result<Model<3, 3>> {
        self.fe_model_builder(grid)?.build()
    }

    /// The builder of [`fe_model`](Self::fe_model) (its mesh made, nothing assembled), e.g.
    /// to watch the build's stages ([`ModelBuilder::on_stage`]); `build` it for the model.
    ///
    /// # Errors
    /// As [`fe_model`](Self::fe_model) before its assembly.
    pub fn fe_model_builder(&self, grid: &SeasBp5Grid) -> Result<ModelBuilder<3>> {
        self.validate()?;
        let (h, far) = (grid.dx, grid.domain);
        let whole = |length: f64| {
            let n = length / h;
            h.is_finite() && h > 0.0 && n >= 1.0 && (n - n.round()).abs() <= 1e-12 * n
        };
        // The tensor grid is symmetric about x₂ = 0 (a line of nodes there); the graded
        // mesh's lattice is shifted along strike so that x₂ = ±l_f/2 are nodes.
        let along_strike = match grid.mesh {
            SeasBp5Mesh::Tensor | SeasBp5Mesh::TensorMirrored => 0.5 * self.l_f,
            SeasBp5Mesh::Graded => self.l_f,
        };
        if !(whole(along_strike) && whole(self.w_f)) {
            return Err(invalid(
                "dx",
                format!(
                    "{} m must divide {} = {along_strike} m and W_f = {} m into whole cells",
                    rsf_numeric::number(h),
                    match grid.mesh {
                        SeasBp5Mesh::Tensor | SeasBp5Mesh::TensorMirrored => {
                            "l_f/2 (the tensor grid)"
                        }
                        SeasBp5Mesh::Graded => "l_f",
                    },
                    self.w_f
                ),
            ));
        }
        if !(far.is_finite() && far >= 1.5 * (0.5 * self.l_f).max(self.w_f)) {
            return Err(invalid(
                "domain",
                format!(
                    "{} m must reach 1.5 times l_f/2 and W_f",
                    rsf_numeric::number(far)
                ),
            ));
        }
        if !(1.0..=2.0).contains(&grid.ratio) {
            return Err(invalid(
                "ratio",
                format!("{} must be in [1, 2]", rsf_numeric::number(grid.ratio)),
            ));
        }
        let multiple = |x: f64| x == 0.0 || (x > 0.0 && whole(x));
        if !(grid.near_fault.is_finite() && multiple(grid.near_fault)) {
            return Err(invalid(
                "near_fault",
                format!(
                    "{} m must be 0 or a whole number of dx = {} m",
                    rsf_numeric::number(grid.near_fault),
                    rsf_numeric::number(h)
                ),
            ));
        }
        if grid.near_fault > 0.0 && grid.mesh != SeasBp5Mesh::Graded {
            return Err(invalid(
                "near_fault",
                "a slab of cells dx is a setting of the graded mesh (the tensor grid grows \
                 from the fault at once)",
            ));
        }
        if let Some(zone) = self.fault_zone {
            if !(multiple(zone.half_width) && grid.near_fault >= zone.half_width) {
                return Err(invalid(
                    "fault_zone.half_width",
                    format!(
                        "{} m must be a whole number of dx = {} m and the graded mesh's \
                         near_fault ({} m) at least that, so that the zone is meshed cell \
                         for cell",
                        rsf_numeric::number(zone.half_width),
                        rsf_numeric::number(h),
                        rsf_numeric::number(grid.near_fault)
                    ),
                ));
            }
        }
        let (mesh, [lo, hi]) = match grid.mesh {
            SeasBp5Mesh::Tensor | SeasBp5Mesh::TensorMirrored => (
                self.tensor_mesh(grid)?,
                [[-far, -far, -far], [far, far, 0.0]],
            ),
            SeasBp5Mesh::Graded => self.graded_mesh(grid)?,
        };
        let mu = self.shear_modulus();
        let host = Material::new(2.0 * mu * (1.0 + self.nu), self.nu, self.rho);
        let builder = ModelBuilder::new(mesh);
        let builder = match self.fault_zone {
            None => builder.material(host),
            Some(zone) => {
                let mu_fz = self.fault_shear_modulus();
                let soft = Material::new(2.0 * mu_fz * (1.0 + self.nu), self.nu, self.rho);
                let scene = *self;
                builder.material(MaterialRegions::new(host).region(
                    "fault zone",
                    move |x| {
                        x[0].abs() <= zone.half_width && scene.in_rate_state_region(x[1], -x[2])
                    },
                    soft,
                ))
            }
        };
        let eps = 1e-6 * h;
        let side = 0.5 * self.v_p;
        // Every face of the box but the free surface z = 0.
        let far_face = move |x: &[f64; 3]| {
            (0..2).any(|k| x[k] < lo[k] + eps || x[k] > hi[k] - eps) || x[2] < lo[2] + eps
        };
        let (a, b, c) = (*self, *self, *self);
        // u₀ = 0: the fault ODE carries the load in its condensed right-hand side.
        let builder = builder
            .without_mass()
            .without_initial_equilibrium()
            .dirichlet(
                Part::predicate("far minus", move |x| x[0] < -eps && far_face(x)),
                [0.0, -side, 0.0],
            )
            .dirichlet(
                Part::predicate("far plus", move |x| x[0] > eps && far_face(x)),
                [0.0, side, 0.0],
            )
            .fault_tangent([0.0, 1.0, 0.0])
            .internal_fault_polygon(
                "fault",
                &[
                    [0.0, lo[1], lo[2]],
                    [0.0, hi[1], lo[2]],
                    [0.0, hi[1], 0.0],
                    [0.0, lo[1], 0.0],
                ],
            )
            .internal_creep_at(move |x| {
                (!a.in_rate_state_region(x[1], -x[2])).then_some(CreepRate::InFrame([a.v_p, 0.0]))
            })
            .neumann(Part::from("fault_minus"), move |x| {
                let t = if b.in_rate_state_region(x[1], -x[2]) {
                    b.tau0(x[1], -x[2])
                } else {
                    0.0
                };
                [0.0, -t, 0.0]
            })
            .neumann(Part::from("fault_plus"), move |x| {
                let t = if c.in_rate_state_region(x[1], -x[2]) {
                    c.tau0(x[1], -x[2])
                } else {
                    0.0
                };
                [0.0, t, 0.0]
            });
        Ok(builder)
    }

    /// The tensor grid of [`SeasBp5Mesh::Tensor`] (box `±domain`).
    fn tensor_mesh(&self, grid: &SeasBp5Grid) -> Result<TetrahedronMesh> {
        let (h, far) = (grid.dx, grid.domain);
        let xs = symmetric_grading(h, h, grid.ratio, far)?;
        let ys = symmetric_grading(h, 0.5 * self.l_f, grid.ratio, far)?;
        let mut zs: Vec<f64> = geometric_grading(h, self.w_f, grid.ratio, far)?
            .iter()
            .rev()
            .map(|z| -z)
            .collect();
        *zs.last_mut().expect("a graded list is not empty") = 0.0;
        if grid.mesh == SeasBp5Mesh::TensorMirrored {
            let odd = |c: &[f64]| -> Vec<bool> {
                c[..c.len() - 1]
                    .iter()
                    .map(|x| (x / h).round().rem_euclid(2.0) == 1.0)
                    .collect()
            };
            let (fx, fy, fz) = (odd(&xs), odd(&ys), odd(&zs));
            return Ok(cuboid_mirrored(&xs, &ys, &zs, [&fx, &fy, &fz])?);
        }
        Ok(cuboid_from_coordinates(&xs, &ys, &zs)?)
    }

    /// The mesh of [`SeasBp5Mesh::Graded`] and the corners of its box (m): an octree of
    /// Kuhn cubes of edge `root = dx·2^k` (the largest at most [`GRADED_ROOT_MAX`]) on the box
    /// `|x| ≤ far`, `|y − s| ≤ far`, `−far ≤ z ≤ 0`, `far` the smallest multiple of `root`
    /// not below `domain` and `s` the shift (`l_f/2` modulo `dx`: 0 or `dx/2`) that puts
    /// nodes at `x₂ = ±l_f/2`, split ([`OctreeMesh`]) until every cell is at most
    /// `dx + (ratio − 1) d`, `d` the distance of its bounding box from the rate-and-state
    /// region (on the plane `x = 0`, thickened to `|x| ≤ near_fault`) or from the nearest
    /// off-fault station
    /// ([`body_station_points`](Self::body_station_points)).
    fn graded_mesh(&self, grid: &SeasBp5Grid) -> Result<(TetrahedronMesh, [[f64; 3]; 2])> {
        let h = grid.dx;
        let doublings = (GRADED_ROOT_MAX / h).log2().floor().max(0.0);
        let root = h * doublings.exp2();
        let far = (grid.domain / root - 1e-9).ceil() * root;
        let shift = {
            let r = (0.5 * self.l_f / h).fract();
            if r > 0.25 && r < 0.75 {
                0.5 * h
            } else {
                0.0
            }
        };
        let (lo, hi) = ([-far, shift - far, -far], [far, shift + far, 0.0]);
        let growth = grid.ratio - 1.0;
        let near = grid.near_fault;
        let region = (
            [-near, -0.5 * self.l_f, -self.w_f],
            [near, 0.5 * self.l_f, 0.0],
        );
        let stations = Self::body_station_points();
        let size = move |lo: [f64; 3], hi: [f64; 3]| {
            let closest = stations
                .iter()
                .map(|&p| box_distance((lo, hi), (p, p)))
                .fold(box_distance((lo, hi), region), f64::min);
            h + growth * closest
        };
        let mut cubes = OctreeMesh::new(lo, hi, root)?;
        cubes
            .refine(size, GRADED_MAX_CELLS)
            .map_err(|e| invalid("dx", format!("the graded mesh: {e}")))?;
        Ok((cubes.into_mesh()?, [lo, hi]))
    }

    /// The fault ODE of BP5 on the volume model `model` ([`fe_model`](Self::fe_model))
    /// with the condensed finite-element operator (`options.kernel`): the laws, state and
    /// damping of [`fault_ode`](Self::fault_ode).
    ///
    /// # Errors
    /// Invalid parameters; the set-up errors of
    /// [`build_fault_ode`](SimulationBuilder::build_fault_ode).
    pub fn fe_fault_ode(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
    ) -> Result<SeasBp5FaultOde> {
        self.validate()?;
        self.problem_builder(model).build_fault_ode(options)
    }

    /// As [`fe_fault_ode`](Self::fe_fault_ode) without ever holding the volume's whole
    /// factor ([`SimulationBuilder::build_fault_ode_schur_only`]: the same operator to
    /// round-off; the stations' vertices, `setup.watch_vertices`, given before the set-up).
    ///
    /// # Errors
    /// As [`fe_fault_ode`](Self::fe_fault_ode); the elimination's.
    pub fn fe_fault_ode_schur_only(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        setup: SchurOnlySetup,
    ) -> Result<SeasBp5FaultOde> {
        self.validate()?;
        self.problem_builder(model)
            .build_fault_ode_schur_only(options, setup)
    }
}

/// Most cells [`SeasBp5::cells`] builds: the 250 m grid (400 × 160).
pub const MAX_CELLS: usize = 64_000;
