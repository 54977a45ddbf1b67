//! The SCEC SEAS benchmark BP3-QD (docs/seas-bp3.md): a planar fault dipping under a free
//! surface in a plane-strain half-space, inside the body, its normal stress changing with
//! slip, loaded by creep below W_f and by each side's rigid motion.

use rsf::fem::{geometric_grading, rectangle_from_coordinates, Diagonal, TriangleMesh};
use rsf::friction::AsinhLaw;
use rsf::model::FaultSide;
use rsf::normal_stress::NormalStress;
use rsf::state::Aging;
use rsf::time::Quasistatic;
use rsf::{Material, Model, ModelBuilder, Part, Result, SimulationBuilder};
use rsf_seas::{SeasLayout, SeasSampling, SeasSetup, SeasSurfaceStation};

use crate::seas_bp1::Bp1PlaneStrainBuilder;
use crate::{check_ratio, invalid, SeasBp1};

/// The down-dip distances (m) of the benchmark's on-fault stations.
pub const SEAS_BP3_STATION_DISTANCES: [f64; 12] = [
    0.0, 2.5e3, 5e3, 7.5e3, 10e3, 12.5e3, 15e3, 17.5e3, 20e3, 25e3, 30e3, 35e3,
];

/// The benchmark's stations on the free surface: `(file name, x in m, side)`, the side
/// saying which copy of the fault's trace the `±0` stations read.
pub const SEAS_BP3_SURFACE_STATIONS: [(&str, f64, FaultSide); 8] = [
    ("srfst_fn-32", -32e3, FaultSide::Minus),
    ("srfst_fn-16", -16e3, FaultSide::Minus),
    ("srfst_fn-08", -8e3, FaultSide::Minus),
    ("srfst_fn-00", 0.0, FaultSide::Minus),
    ("srfst_fn+00", 0.0, FaultSide::Plus),
    ("srfst_fn+08", 8e3, FaultSide::Plus),
    ("srfst_fn+16", 16e3, FaultSide::Plus),
    ("srfst_fn+32", 32e3, FaultSide::Plus),
];

/// The fault ODE of BP3 ([`SeasBp3::fault_ode`]).
pub type SeasBp3FaultOde = rsf::FaultOde<2, AsinhLaw, Aging>;

/// BP3-QD: the parameters of the description's Table 1 — which are BP1's
/// ([`SeasBp1::default`]), with the depth replaced by the down-dip distance `x_d` in the
/// depth-dependent `a` and the initial state — and the dip. `params.v_p` and
/// `params.v_init` are magnitudes; a normal fault (`normal_faulting`) slips the other way
/// (V_p = −1e-9 m/s, the prestress negative).
#[derive(Debug, Clone, PartialEq)]
pub struct SeasBp3 {
    /// The material, friction and loading parameters (SI units).
    pub params: SeasBp1,
    /// Dip ψ from the horizontal (degrees), in (0, 90).
    pub dip_degrees: f64,
    /// `true` for the normal fault (slip negative), `false` for the thrust.
    pub normal_faulting: bool,
}

/// The mesh of a BP3 run ([`SeasBp3::mesh`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeasBp3Grid {
    /// Element size along the fault (m), down to W_f.
    pub dx: f64,
    /// Half-width `L` of the box across the fault (m); its depth is `L sin ψ`. Default
    /// 1600 km: the shallow normal fault (30°) needs a deep box — its first event moves by
    /// 17.6 yr from L = 100 to 800 km and by 0.4 yr from 800 to 1600 km at Δx = 250 m
    /// (docs/seas-bp3.md).
    pub domain: f64,
    /// Growth of the elements away from the fault and below W_f, in [1, 2]. Default
    /// 1.025: the far field's elements (about `(ratio − 1)·d` at distance `d`) set an error
    /// that refining `dx` does not remove — at Δx = 250 m the normal fault's (30°) first
    /// event moves by 2.9 yr from ratio 1.1 to 1.0125, the thrust's by 0.35 yr; at 1.025
    /// both are within 0.2 yr of 1.0125 (docs/seas-bp3.md, "Mesh grading").
    pub ratio: f64,
}

impl Default for SeasBp3Grid {
    fn default() -> Self {
        Self {
            dx: 25.0,
            domain: 1600e3,
            ratio: 1.025,
        }
    }
}

impl SeasBp3 {
    /// The thrust case: dip 60°.
    pub fn thrust() -> Self {
        Self {
            params: SeasBp1::default(),
            dip_degrees: 60.0,
            normal_faulting: false,
        }
    }

    /// The normal-fault case: dip 30°, slip negative.
    pub fn normal() -> Self {
        Self {
            params: SeasBp1::default(),
            dip_degrees: 30.0,
            normal_faulting: true,
        }
    }

    /// Checks the parameters ([`SeasBp1::validate`]) and the dip.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] naming the first invalid one.
    pub fn validate(&self) -> Result<()> {
        self.params.validate()?;
        if !(self.dip_degrees > 0.0 && self.dip_degrees < 90.0) {
            return Err(invalid(
                "dip_degrees",
                format!(
                    "{} must be in (0, 90)",
                    rsf_numeric::written(self.dip_degrees)
                ),
            ));
        }
        Ok(())
    }

    /// `(sin ψ, cos ψ)`.
    fn dip(&self) -> (f64, f64) {
        self.dip_degrees.to_radians().sin_cos()
    }

    /// The slip's sign: +1 thrust, −1 normal.
    pub fn sign(&self) -> f64 {
        if self.normal_faulting {
            -1.0
        } else {
            1.0
        }
    }

    /// Down-dip distance `x_d = z / sin ψ` (m) of a point `x = (x, y)`, `y = −z` ≤ 0.
    pub fn x_d(&self, x: &[f64; 2]) -> f64 {
        -x[1] / self.dip().0
    }

    /// The coordinate across the fault, `ξ = x − z cot ψ` (m): 0 on the fault, negative on
    /// the minus side Ω⁻.
    pub fn xi(&self, x: &[f64; 2]) -> f64 {
        let (s, c) = self.dip();
        x[0] + x[1] * c / s
    }

    /// The mesh: a graded structured mesh in `(ξ, z)` (elements `dx` along the fault down
    /// to W_f and `dx` across it within `2 dx`, growing by `ratio` beyond) sheared by
    /// `x = ξ + z cot ψ`, so that the column `ξ = 0` is the fault and the box is the
    /// parallelogram `|ξ| ≤ L`, `0 ≤ z ≤ L sin ψ` with sides parallel to the fault.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx`, `domain` or `ratio`; grading errors.
    pub fn mesh(&self, grid: &SeasBp3Grid) -> Result<TriangleMesh> {
        self.validate()?;
        let (s, c) = self.dip();
        let depth = grid.domain * s;
        if !(grid.dx > 0.0 && grid.dx.is_finite() && 4.0 * grid.dx <= self.params.w_f) {
            return Err(invalid(
                "dx",
                format!(
                    "{} m must be positive and at most W_f/4",
                    rsf_numeric::written(grid.dx)
                ),
            ));
        }
        if !(depth > self.params.w_f * s * 1.5 && grid.domain.is_finite()) {
            return Err(invalid(
                "domain",
                format!(
                    "{} m: the box must reach 1.5 W_f down the fault",
                    grid.domain
                ),
            ));
        }
        check_ratio(grid.ratio)?;
        let side = geometric_grading(grid.dx, 2.0 * grid.dx, grid.ratio, grid.domain)?;
        let mut xi: Vec<f64> = side.iter().rev().map(|x| -x).collect();
        xi.extend(side.iter().skip(1));
        let zs = geometric_grading(grid.dx * s, self.params.w_f * s, grid.ratio, depth)?;
        let ys: Vec<f64> = zs.iter().rev().map(|z| -z).collect();
        let grid_mesh = rectangle_from_coordinates(&xi, &ys, Diagonal::Forward)?;
        let sheared = grid_mesh
            .vertices()
            .iter()
            .map(|v| [v[0] - v[1] * c / s, v[1]])
            .collect();
        Ok(grid_mesh.with_moved_vertices(sheared)?)
    }

    /// The model on `grid` (quasi-dynamic: no mass): isotropic plane strain (ν = 0.25,
    /// μ = ρc_s²); the fault `internal_fault("fault", …)` from the surface along the dip
    /// to the bottom; the pairs with `x_d > W_f` creeping at `±V_p`
    /// ([`ModelBuilder::internal_creep`]); the far boundaries moving with their side's
    /// rigid motion (`v⁻ = ±(V_p/2)(cos ψ, −sin ψ)`, `v⁺ = −v⁻`: slip `±V_p`); the
    /// prestress `±τ⁰` as equal and opposite tractions on the fault's faces; the initial
    /// displacement 0 (the description's δ(x_d, 0) = 0, stress changes measured from it).
    ///
    /// # Errors
    /// As [`mesh`](Self::mesh); model assembly errors.
    pub fn model(&self, grid: &SeasBp3Grid) -> Result<Model<2>> {
        self.model_on(self.mesh(grid)?, grid)
    }

    /// [`model`](Self::model) on `mesh`, a mesh of `grid`'s box ([`mesh`](Self::mesh)'s,
    /// e.g. with its vertices numbered otherwise).
    ///
    /// # Errors
    /// Model assembly errors (e.g. a mesh without the fault's line).
    pub fn model_on(&self, mesh: TriangleMesh, grid: &SeasBp3Grid) -> Result<Model<2>> {
        let p = &self.params;
        let (s, c) = self.dip();
        let bottom = -grid.domain * s;
        let nu = 0.25;
        let material = Material::new(2.0 * p.shear_modulus() * (1.0 + nu), nu, p.rho);
        let h = 0.5 * self.sign() * p.v_p;
        let minus = [h * c, -h * s];
        let plus = [-minus[0], -minus[1]];
        let eps = 1e-6 * grid.dx;
        let tau0 = self.sign() * p.tau0();
        let t = [-c, s];
        let (w_f, l) = (p.w_f, grid.domain);
        let (a, b, d) = (self.clone(), self.clone(), self.clone());
        let (e, f) = (self.clone(), self.clone());
        ModelBuilder::new(mesh)
            .material(material)
            .without_mass()
            .dirichlet(Part::predicate("left", move |x| a.xi(x) < -l + eps), minus)
            .dirichlet(Part::predicate("right", move |x| b.xi(x) > l - eps), plus)
            .dirichlet(
                Part::predicate("bottom minus", move |x| {
                    x[1] < bottom + eps && d.xi(x) < 0.0
                }),
                minus,
            )
            .dirichlet(
                Part::predicate("bottom plus", move |x| x[1] < bottom + eps && e.xi(x) > 0.0),
                plus,
            )
            .internal_fault("fault", [0.0, 0.0], [-bottom * c / s, bottom])
            .internal_creep(move |x| f.x_d(x) > w_f + eps, self.sign() * p.v_p)
            .neumann(Part::from("fault_minus"), move |_| {
                [-tau0 * t[0], -tau0 * t[1]]
            })
            .neumann(Part::from("fault_plus"), move |_| {
                [tau0 * t[0], tau0 * t[1]]
            })
            // u₀ = 0: the fault ODE carries the load in its condensed right-hand side.
            .without_initial_equilibrium()
            .build()
    }

    /// The problem on `model` (quasi-dynamic): the regularised law with `a(x_d)`, the
    /// aging law, the initial state of the description, the initial velocity each side's
    /// rigid motion at `V_init`, radiation damping `μ/(2c_s)`, the normal stress from slip
    /// ([`NormalStress::FromSlip`]).
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn problem_builder(&self, model: Model<2>) -> Result<Bp1PlaneStrainBuilder> {
        self.validate()?;
        let p = &self.params;
        let (s, c) = self.dip();
        let h = 0.5 * self.sign() * p.v_init;
        Ok(SimulationBuilder::new(model)
            .friction_at(|x| AsinhLaw::new(p.params(self.x_d(x))))
            .state_law(Aging::new(p.d_c)?)
            .initial_state_at(|x| p.alpha0(self.x_d(x)))
            // Each side's rigid motion at V_init (steady creep, for the implicit scheme's
            // first predictor).
            .initial_velocity_at(|x| {
                let side = if self.xi(x) < 0.0 { 1.0 } else { -1.0 };
                [side * h * c, -side * h * s]
            })
            .integrator(Quasistatic::new())
            .radiation_damping(p.radiation_damping())
            .normal_stress(NormalStress::FromSlip))
    }

    /// The benchmark output of a BP3-QD run with elements `dx` (m) along the fault
    /// ([`SeasOutput`](rsf_seas::SeasOutput) with [`SeasLayout::Bp3`]): the twelve
    /// on-fault stations `fltst_dpXXX` (XXX the down-dip distance in hundreds of metres)
    /// with six columns, the slip profiles `slip.dat` every 500 m down-dip, the event
    /// catalogue, the stress profiles `shear_stress.dat` and `normal_stress.dat`, and the
    /// eight stations on the free surface `srfst_fn…` ([`SEAS_BP3_SURFACE_STATIONS`]:
    /// displacement and velocity, the vertical positive down).
    pub fn seas_setup(&self, dx: f64, sampling: SeasSampling) -> SeasSetup {
        SeasSetup {
            problem: "SEAS Benchmark BP3-QD".into(),
            modeler: "rsf".into(),
            date: rsf_seas::utc_date_today(),
            element_size: dx,
            stations: SEAS_BP3_STATION_DISTANCES
                .iter()
                .map(|&d| (SeasBp1::station_name(d), d))
                .collect(),
            depth_axis: 1,
            depth_down: false,
            sigma_n: self.params.sigma_n,
            profile_spacing: 500.0,
            sampling,
            layout: SeasLayout::Bp3 {
                dip_degrees: self.dip_degrees,
            },
            surface_stations: SEAS_BP3_SURFACE_STATIONS
                .iter()
                .map(|&(name, x, side)| SeasSurfaceStation {
                    name: name.into(),
                    position: vec![x, 0.0],
                    side,
                })
                .collect(),
        }
    }

    /// The names of a BP3 run's benchmark files: the on-fault stations
    /// ([`SEAS_BP3_STATION_DISTANCES`]), the surface stations
    /// ([`SEAS_BP3_SURFACE_STATIONS`]), the three profiles, `events.csv` and their resume
    /// log ([`rsf_seas::SEAS_RESUME_LOG`]). Each front end adds its own (the checkpoint,
    /// the program's figure).
    pub fn file_names() -> Vec<String> {
        let mut names: Vec<String> = SEAS_BP3_STATION_DISTANCES
            .iter()
            .map(|&d| SeasBp1::station_name(d))
            .collect();
        names.extend(SEAS_BP3_SURFACE_STATIONS.iter().map(|s| s.0.to_owned()));
        names.extend(
            [
                "slip.dat",
                "shear_stress.dat",
                "normal_stress.dat",
                "events.csv",
                rsf_seas::SEAS_RESUME_LOG,
            ]
            .map(String::from),
        );
        names
    }

    /// BP3-QD on `model` as a run condensed onto the fault (first trial step 0.01 s).
    ///
    /// # Errors
    /// Invalid parameters; the fault ODE's set-up errors.
    pub fn fault_ode(
        &self,
        model: Model<2>,
        options: rsf::fault_ode::FaultOdeOptions,
    ) -> Result<SeasBp3FaultOde> {
        self.problem_builder(model)?
            .time_step(1e-2)
            .build_fault_ode(options)
    }
}
