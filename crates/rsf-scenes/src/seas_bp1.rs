//! The SCEC SEAS benchmark BP1-QD (Erickson & Jiang 2018, the benchmark's problem
//! description; Erickson et al. 2020, Seismol. Res. Lett. 91(2), 874–890): parameters,
//! depth-dependent friction and the spec's closed-form initial conditions
//! (docs/seas-bp1.md). Antiplane, fault on x = 0, z ≥ 0 the depth (m).

use rsf_fem::{
    geometric_grading, geometric_grading_len, rectangle_from_coordinates, Diagonal, TriangleMesh,
};
use rsf_friction::{AsinhLaw, RateStateParams};
use rsf_state::Aging;
use rsf_time::{Integrator, Quasistatic, StepControl};

use crate::scene_file::{finite, positive_fields};
use crate::{check_ratio, invalid, invalid_length};
use rsf::checkpoint::Fingerprint;
use rsf::fault_ode::FaultOdeOptions;
use rsf::model::AntiplaneMaterial;
use rsf::FaultOde;
use rsf::Model;
use rsf::Result;
use rsf::Simulation;
use rsf::SimulationBuilder;
use rsf::{ModelBuilder, Part};
use rsf_seas::{SeasSampling, SeasSetup};

/// A simulation of BP1: 2-D mesh, one (antiplane) component, regularised rate-and-state
/// friction, aging law, quasi-dynamic ([`Quasistatic`] with radiation damping) or fully
/// dynamic ([`Integrator::Newmark`]).
pub type SeasBp1Simulation = Simulation<2, AsinhLaw, Aging, Integrator, 1>;

/// A quasi-dynamic run of BP1 condensed onto the fault and integrated by an explicit
/// Runge–Kutta pair ([`FaultOde`], docs/math.md §12).
pub type SeasBp1FaultOde = FaultOde<2, AsinhLaw, Aging, 1>;

/// The quasi-dynamic problem builder of BP1's friction (the regularised law, the aging law)
/// on a 2-D fault in plane strain, two slip components: BP3's and the stepover's.
pub(crate) type Bp1PlaneStrainBuilder = SimulationBuilder<2, AsinhLaw, Aging, Quasistatic, 2>;

/// The BP1 discretisation: a tensor-product mesh of `x ∈ [0, domain]` (distance from the
/// fault) × `z ∈ [0, domain]` (depth), spacing `dz` on `0 ≤ z ≤ W_f` along the fault and
/// from the fault in x, growing by `ratio` per cell beyond ([`geometric_grading`];
/// docs/seas-bp1.md "Why a structured graded mesh").
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeasBp1Grid {
    /// Element size Δz on the fault (m); the spec's is 25 m.
    pub dz: f64,
    /// Side of the square domain (m); 400 km by default.
    pub domain: f64,
    /// Growth ratio of the spacing away from the fault (≥ 1); 1.05 by default.
    pub ratio: f64,
}

impl Default for SeasBp1Grid {
    fn default() -> Self {
        Self {
            dz: 25.0,
            domain: 400e3,
            ratio: 1.05,
        }
    }
}

/// The size of a BP1 model estimated before it is built ([`SeasBp1::estimate`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridEstimate {
    /// Mesh nodes (at most 2 per direction above the exact count: an upper bound).
    pub nodes: f64,
    /// Nodes on the fault `0 ≤ z ≤ W_f`.
    pub fault_nodes: f64,
    /// Estimated peak memory of a run (bytes).
    pub bytes: f64,
}

/// The 12 on-fault stations of the benchmark output, depth in m (file `fltst_dpXXX` with
/// XXX the depth in hundreds of metres).
pub const SEAS_BP1_STATION_DEPTHS: [f64; 12] = [
    0.0, 2.5e3, 5e3, 7.5e3, 10e3, 12.5e3, 15e3, 17.5e3, 20e3, 25e3, 30e3, 35e3,
];

/// Name of the far side `x = domain` of the BP1 model (a boundary part).
pub const SEAS_BP1_FAR_SIDE: &str = "far side";

/// Name of the bottom `z = domain` of the BP1 model (a boundary part; traction-free
/// unless absorbing).
pub const SEAS_BP1_BOTTOM: &str = "bottom";

/// How the far boundaries of the truncated BP1 domain are treated
/// ([`SeasBp1::model_with_far`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SeasBp1Far {
    /// The spec's common choice: the far side moves with the plate, `u = V_p t/2`; the
    /// bottom is traction-free. Both reflect waves.
    #[default]
    Dirichlet,
    /// Both far boundaries absorbing (dashpots against the motion relative to the far
    /// field at `V_p/2`); fully dynamic models only.
    Absorbing,
}

/// BP1-QD parameters (Table 1 of the spec; SI units). [`SeasBp1::default`] is the spec.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SeasBp1 {
    /// Density ρ (kg/m³).
    pub rho: f64,
    /// Shear wave speed c_s (m/s).
    pub c_s: f64,
    /// Effective normal stress σ_n (Pa).
    pub sigma_n: f64,
    /// Direct effect a above `h_top` (dimensionless).
    pub a0: f64,
    /// Direct effect a below `h_top + h_transition`.
    pub a_max: f64,
    /// Evolution effect b (uniform).
    pub b0: f64,
    /// Characteristic slip distance D_c (m), the `l` of [`RateStateParams`].
    pub d_c: f64,
    /// Plate rate V_p (m/s): creep below `w_f` and far-side loading.
    pub v_p: f64,
    /// Initial slip rate V_init (m/s).
    pub v_init: f64,
    /// Reference slip rate V₀ (m/s).
    pub v0: f64,
    /// Reference friction coefficient f₀ (the `mu0` of [`RateStateParams`]).
    pub f0: f64,
    /// Depth H of the velocity-weakening zone (m).
    pub h_top: f64,
    /// Width h of the transition of a (m).
    pub h_transition: f64,
    /// Depth W_f of the frictional fault (m); creep at V_p below.
    pub w_f: f64,
}

impl Default for SeasBp1 {
    fn default() -> Self {
        Self {
            rho: 2670.0,
            c_s: 3464.0,
            sigma_n: 50e6,
            a0: 0.010,
            a_max: 0.025,
            b0: 0.015,
            d_c: 0.008,
            v_p: 1e-9,
            v_init: 1e-9,
            v0: 1e-6,
            f0: 0.6,
            h_top: 15e3,
            h_transition: 3e3,
            w_f: 40e3,
        }
    }
}

impl SeasBp1 {
    /// Checks that every parameter is finite and all but `f0` are positive (`a0 > a_max`
    /// is allowed: any a(z) profile of this shape).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](rsf::Error::InvalidParameter) naming the field.
    pub fn validate(&self) -> rsf::Result<()> {
        positive_fields!(self; rho, c_s, sigma_n, a0, a_max, b0, d_c, v_p, v_init, v0, h_top,
            h_transition, w_f)?;
        finite("f0", self.f0)?;
        Ok(())
    }

    /// Shear modulus μ = ρ c_s² (Pa); 32.038 GPa for the spec.
    pub fn shear_modulus(&self) -> f64 {
        self.rho * self.c_s * self.c_s
    }

    /// Radiation damping η = μ/(2c_s) (Pa·s/m).
    pub fn radiation_damping(&self) -> f64 {
        self.shear_modulus() / (2.0 * self.c_s)
    }

    /// a(z): `a0` above H, linear to `a_max` at H + h, `a_max` below (z in m).
    pub fn a(&self, z: f64) -> f64 {
        if z < self.h_top {
            self.a0
        } else if z < self.h_top + self.h_transition {
            self.a0 + (self.a_max - self.a0) * (z - self.h_top) / self.h_transition
        } else {
            self.a_max
        }
    }

    /// The rate-and-state parameters at depth `z` (m) for the regularised law
    /// [`AsinhLaw`](rsf_friction::AsinhLaw): `mu0 = f0`, `a = a(z)`, `b = b0`,
    /// `l = D_c`.
    pub fn params(&self, z: f64) -> RateStateParams {
        RateStateParams {
            mu0: self.f0,
            a: self.a(z),
            b: self.b0,
            v0: self.v0,
            l: self.d_c,
            sigma_n: self.sigma_n,
        }
    }

    /// Uniform prestress τ₀ = σ_n a_max asinh[V_init/(2V₀) exp((f₀ + b₀ ln(V₀/V_init))/a_max)]
    /// + η V_init (Pa): steady state at V_init where a = a_max.
    pub fn tau0(&self) -> f64 {
        let q = (self.f0 + self.b0 * (self.v0 / self.v_init).ln()) / self.a_max;
        self.sigma_n * self.a_max * (self.v_init / (2.0 * self.v0) * q.exp()).asinh()
            + self.radiation_damping() * self.v_init
    }

    /// Initial state θ(z, 0) = (D_c/V₀) exp[(a/b) ln((2V₀/V_init) sinh((τ₀ − ηV_init)/(aσ_n)))
    /// − f₀/b] (s), so that F(V_init, θ) = τ₀ − η V_init at every depth. Returned as
    /// `α = ln θ` (sinh is evaluated in log form: no overflow for small a).
    pub fn alpha0(&self, z: f64) -> f64 {
        let a = self.a(z);
        let x = (self.tau0() - self.radiation_damping() * self.v_init) / (a * self.sigma_n);
        // ln sinh x = x + ln((1 − e^{−2x})/2), x > 0.
        let ln_sinh = x + (-(-2.0 * x).exp_m1()).ln() - std::f64::consts::LN_2;
        (self.d_c / self.v0).ln() + (a / self.b0) * ((2.0 * self.v0 / self.v_init).ln() + ln_sinh)
            - self.f0 / self.b0
    }

    /// The graded mesh of `grid`: vertex `(x, z)`, x the distance from the fault, z the
    /// depth (m).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](rsf::Error::InvalidParameter) named `dz`, `domain` or
    /// `ratio` for a grid that does not fit BP1 (`dz` must divide `W_f` into whole cells,
    /// the domain must be larger than `W_f`); grading errors.
    pub fn mesh(&self, grid: &SeasBp1Grid) -> Result<TriangleMesh> {
        self.check_grid(grid)?;
        let xs = geometric_grading(grid.dz, 0.0, grid.ratio, grid.domain)?;
        let zs = geometric_grading(grid.dz, self.w_f, grid.ratio, grid.domain)?;
        Ok(rectangle_from_coordinates(&xs, &zs, Diagonal::Forward)?)
    }

    /// The size of the model on `grid`, estimated in closed form before anything is
    /// allocated ([`geometric_grading_len`]): its nodes, nodes on the fault and memory —
    /// to refuse a grid the machine cannot hold (a ratio of 1 over a 400 km domain is
    /// 2.6·10⁸ nodes) with a message instead of an aborted allocation.
    ///
    /// The memory model, from the runs of docs/seas-bp1.md (peak resident set: 407 MB at
    /// 237 558 nodes / 1601 on the fault, 104 MB at 16 896 / 201 with the implicit
    /// scheme): [`BYTES_PER_NODE`](Self::BYTES_PER_NODE) per node plus two dense
    /// fault-by-fault operators (the condensed `S` and its work copies).
    ///
    /// # Errors
    /// As [`mesh`](Self::mesh) for a grid that does not fit BP1.
    pub fn estimate(&self, grid: &SeasBp1Grid) -> Result<GridEstimate> {
        self.check_grid(grid)?;
        let nx = geometric_grading_len(grid.dz, 0.0, grid.ratio, grid.domain);
        let nz = geometric_grading_len(grid.dz, self.w_f, grid.ratio, grid.domain);
        let fault_nodes = (self.w_f / grid.dz).round() + 1.0;
        let nodes = nx * nz;
        Ok(GridEstimate {
            nodes,
            fault_nodes,
            bytes: nodes * Self::BYTES_PER_NODE + 2.0 * 8.0 * fault_nodes * fault_nodes,
        })
    }

    /// Bytes per mesh node of a BP1 run in [`estimate`](Self::estimate) (measured ≈ 1.6 kB
    /// with the fault ODE, ≈ 6 kB with the implicit scheme; the larger one).
    pub const BYTES_PER_NODE: f64 = 6.5e3;

    /// Checks that `grid` fits BP1: `dz` divides `W_f` into whole cells, the domain is
    /// larger than `W_f`, the ratio is in [1, 2].
    fn check_grid(&self, grid: &SeasBp1Grid) -> Result<()> {
        self.validate()?;
        let cells = self.w_f / grid.dz;
        if !(grid.dz > 0.0 && grid.dz.is_finite()) || (cells - cells.round()).abs() > 1e-9 {
            let rule = format!("must divide W_f = {} m into whole cells", self.w_f);
            return Err(invalid_length("dz", grid.dz, rule));
        }
        if !(grid.domain > self.w_f && grid.domain.is_finite()) {
            let rule = format!("must exceed W_f = {} m", self.w_f);
            return Err(invalid_length("domain", grid.domain, rule));
        }
        check_ratio(grid.ratio)?;
        Ok(())
    }

    /// The model of BP1 on `grid` (the half `x ≥ 0`; docs/seas-bp1.md): antiplane shear
    /// ([`AntiplaneMaterial`], μ = ρc_s²), the fault `x = 0, 0 ≤ z ≤ W_f` frictional and a
    /// plane of antisymmetry (slip `δ = 2u`, [`ModelBuilder::antisymmetric_fault`]), loaded
    /// by the prestress τ₀ (a traction on the fault), creeping at `V_p` below `W_f`
    /// (`u = V_p t/2` on `x = 0, z > W_f`) and on the far side `x = domain`; free surface
    /// `z = 0` and bottom traction-free. Without mass (quasi-dynamic) unless `inertia`.
    /// The initial displacement is 0 (the spec's δ(z, 0) = 0, the elastic stress change
    /// measured from it), not the builder's equilibrium.
    ///
    /// The node at `z = W_f` is both frictional and creeping: its velocity is prescribed.
    ///
    /// # Errors
    /// As [`mesh`](Self::mesh); model assembly errors.
    pub fn model(&self, grid: &SeasBp1Grid, inertia: bool) -> Result<Model<2, 1>> {
        self.model_with_far(grid, inertia, SeasBp1Far::Dirichlet)
    }

    /// The model of BP1 on `grid` as [`model`](Self::model), with the far boundaries
    /// (the parts [`SEAS_BP1_FAR_SIDE`] `x = domain` and [`SEAS_BP1_BOTTOM`] `z = domain`)
    /// treated as `far` says: [`SeasBp1Far::Dirichlet`] is [`model`](Self::model);
    /// [`SeasBp1Far::Absorbing`] makes both Lysmer–Kuhlemeyer dashpots (impedance ρc_s)
    /// against the motion relative to the far field moving at `V_p/2`
    /// ([`ModelBuilder::absorbing_boundary_moving`]; no Dirichlet data on the far side:
    /// the body is loaded by the creep below W_f only, as the whole half-space is), for
    /// the fully dynamic BP1-FD (docs/seas-bp1-fd.md). The fault ODE sees these parts
    /// traction-free.
    ///
    /// # Errors
    /// As [`model`](Self::model); [`Error::InvalidParameter`](rsf::Error::InvalidParameter)
    /// named `far` for absorbing parts without `inertia`.
    pub fn model_with_far(
        &self,
        grid: &SeasBp1Grid,
        inertia: bool,
        far: SeasBp1Far,
    ) -> Result<Model<2, 1>> {
        if far == SeasBp1Far::Absorbing && !inertia {
            return Err(invalid(
                "far",
                "absorbing far boundaries need inertia (BP1-FD)",
            ));
        }
        let mesh = self.mesh(grid)?;
        let (w_f, l, eps) = (self.w_f, grid.domain, 1e-6 * grid.dz);
        let tau0 = self.tau0();
        let on_fault = move |x: &[f64; 2]| x[0] < eps && x[1] < w_f;
        let mut builder = ModelBuilder::scalar(mesh)
            .material(AntiplaneMaterial::new(self.shear_modulus(), self.rho))
            .frictional_boundary(Part::predicate("fault", on_fault))
            .neumann(Part::predicate("fault", on_fault), move |_| [tau0])
            .dirichlet(
                Part::predicate("creep", move |x| x[0] < eps && x[1] > w_f),
                [0.5 * self.v_p],
            )
            .antisymmetric_fault(2.0);
        let far_side = Part::predicate(SEAS_BP1_FAR_SIDE, move |x| x[0] > l - eps);
        builder = match far {
            SeasBp1Far::Dirichlet => builder.dirichlet(far_side, [0.5 * self.v_p]),
            SeasBp1Far::Absorbing => builder
                .absorbing_boundary_moving(far_side, [0.5 * self.v_p])
                .absorbing_boundary_moving(
                    Part::predicate(SEAS_BP1_BOTTOM, move |x| x[1] > l - eps),
                    [0.5 * self.v_p],
                ),
        };
        if !inertia {
            builder = builder.without_mass();
        }
        // u₀ = 0: the fault ODE carries the load in its condensed right-hand side.
        builder.without_initial_equilibrium().build()
    }

    /// The problem of BP1 on `model` (from [`model`](Self::model)), without a method: the
    /// regularised law [`AsinhLaw`] with a(z), the aging law, θ₀(z) from the spec
    /// ([`alpha0`](Self::alpha0)), slip rate V_init everywhere (the half moves at
    /// V_init/2), and the physics — quasi-dynamic (no inertia, radiation damping
    /// η = μ/(2c_s)) or, with `inertia`, fully dynamic (BP1-FD: inertia, no damping; the
    /// model needs its mass matrix). The integrator is the one the physics implies
    /// (quasistatic, or Newmark with inertia). Choose the method on it:
    /// [`build_fault_ode`](SimulationBuilder::build_fault_ode) with a
    /// [`time_step`](SimulationBuilder::time_step) as the first trial step, or the implicit
    /// scheme's settings and [`build`](SimulationBuilder::build)
    /// ([`simulation_builder`](Self::simulation_builder)).
    ///
    /// # Errors
    /// Invalid parameters (laws, damping).
    pub fn problem_builder(
        &self,
        model: Model<2, 1>,
        inertia: bool,
    ) -> Result<SimulationBuilder<2, AsinhLaw, Aging, Integrator, 1>> {
        self.validate()?;
        let (integrator, eta) = if inertia {
            (Integrator::Newmark, 0.0)
        } else {
            (
                Integrator::Quasistatic(Quasistatic::new()),
                self.radiation_damping(),
            )
        };
        let v_half = 0.5 * self.v_init;
        Ok(SimulationBuilder::new(model)
            .friction_at(|x| AsinhLaw::new(self.params(x[1])))
            .state_law(Aging::new(self.d_c)?)
            .initial_state_at(|x| self.alpha0(x[1]))
            .initial_velocity_at(|_| [v_half])
            .integrator(integrator)
            .radiation_damping(eta))
    }

    /// A simulation builder of BP1 on `model` with the paper's implicit method: the
    /// problem of [`problem_builder`](Self::problem_builder), the direct solver, and
    /// adaptive steps from `tau0` (s) with `control`.
    ///
    /// # Errors
    /// Invalid parameters (laws, damping).
    pub fn simulation_builder(
        &self,
        model: Model<2, 1>,
        inertia: bool,
        tau0: f64,
        control: StepControl,
    ) -> Result<SimulationBuilder<2, AsinhLaw, Aging, Integrator, 1>> {
        Ok(self
            .problem_builder(model, inertia)?
            .solver(rsf::SolverKind::Direct)
            .time_step(tau0)
            .step_control(control))
    }

    /// The quasi-dynamic BP1 on `model` as a run condensed onto the fault
    /// ([`FaultOde`]): the problem of [`problem_builder`](Self::problem_builder) without
    /// inertia, first trial step 0.01 s, with `options` (e.g.
    /// [`fault_ode_options`](Self::fault_ode_options)).
    ///
    /// # Errors
    /// Invalid parameters; the set-up errors of
    /// [`build_fault_ode`](SimulationBuilder::build_fault_ode).
    pub fn fault_ode(
        &self,
        model: Model<2, 1>,
        options: FaultOdeOptions,
    ) -> Result<SeasBp1FaultOde> {
        self.problem_builder(model, false)?
            .time_step(1e-2)
            .build_fault_ode(options)
    }

    /// The adaptive step control used for BP1 by default: relative tolerance `tolerance`
    /// on the state and the slip (slip-rate floor V_p, docs/seas-bp1.md), state
    /// change per step at most ½ (τ ≤ D_c/(2V_max) in slip), τ in [1e-6 s, 1 yr]. (At the
    /// default tolerance 1e-3 the smallest step taken at Δz = 100 m was 1.6e-4 s; with
    /// 1e-4 the events need steps below 1e-4 s.)
    ///
    /// # Errors
    /// An invalid tolerance.
    pub fn step_control(&self, tolerance: f64) -> Result<StepControl> {
        let mut c = StepControl::new(tolerance, self.d_c, 1e-6, 3.15576e7)?;
        c.slip_rate_floor = Some(self.v_p);
        Ok(c)
    }

    /// Options of a run condensed onto the fault ([`FaultOde`]) for BP1: the
    /// Dormand–Prince 5(4) pair, local errors at most `tolerance · D_c` in slip and
    /// `tolerance` in ln θ per step, steps in [1e-6 s, 1 yr]. (docs/seas-bp1.md compares
    /// tolerances.)
    ///
    /// # Errors
    /// An invalid tolerance.
    pub fn fault_ode_options(&self, tolerance: f64) -> Result<FaultOdeOptions> {
        crate::seas_fault_ode_options(tolerance, self.d_c)
    }

    /// What a checkpoint of a BP1 run continues: every parameter (as serde names it),
    /// the grid (`grid.dz`, `grid.domain`, `grid.ratio`), `inertia` (BP1-FD) and the output
    /// sampling (`sampling.*`: it decides which rows the files hold), and the checkpoint
    /// `format`. A run appends the options of its method that change the trajectory
    /// (scheme, tolerances, end time, …) with [`Fingerprint::with`], e.g.
    /// `bp1.fingerprint(&grid, false, &sampling).with("scheme", "implicit")`.
    pub fn fingerprint(
        &self,
        grid: &SeasBp1Grid,
        inertia: bool,
        sampling: &SeasSampling,
    ) -> Fingerprint {
        let sampled = [
            ("sampling.station_quiet", sampling.station_quiet),
            ("sampling.station_event", sampling.station_event),
            ("sampling.profile_quiet", sampling.profile_quiet),
            ("sampling.profile_event", sampling.profile_event),
            ("sampling.event_threshold", sampling.event_threshold),
            ("sampling.event_quiet_time", sampling.event_quiet_time),
        ];
        let fingerprint = Fingerprint::of_serialized(self)
            .with("grid.dz", json_number(grid.dz))
            .with("grid.domain", json_number(grid.domain))
            .with("grid.ratio", json_number(grid.ratio))
            .with("inertia", inertia)
            .with("sampling.every_step", sampling.every_step);
        sampled
            .into_iter()
            .fold(fingerprint, |f, (name, x)| f.with(name, json_number(x)))
            .with("format", rsf::checkpoint::CHECKPOINT_FORMAT)
    }

    /// What the benchmark files of a BP1 run hold ([`SeasSetup`], for
    /// [`SeasOutput`](rsf_seas::SeasOutput)): the problem name
    /// `SEAS Benchmark BP1-QD` (`BP1-FD` with `inertia`), modeler `rsf`, today's UTC date,
    /// element size `dz` (m), every station of the description
    /// ([`SEAS_BP1_STATION_DEPTHS`],
    /// [`station_name`](Self::station_name)), depth = `z` growing downwards, this scene's
    /// σ_n, slip profiles every 500 m, and `sampling`. Change fields with struct update
    /// syntax (`SeasSetup { modeler, ..bp1.seas_setup(dz, inertia, sampling) }`).
    pub fn seas_setup(&self, dz: f64, inertia: bool, sampling: SeasSampling) -> SeasSetup {
        SeasSetup {
            problem: format!("SEAS Benchmark BP1-{}", if inertia { "FD" } else { "QD" }),
            modeler: "rsf".into(),
            date: rsf_seas::utc_date_today(),
            element_size: dz,
            stations: SEAS_BP1_STATION_DEPTHS
                .iter()
                .map(|&d| (Self::station_name(d), d))
                .collect(),
            depth_axis: 1,
            depth_down: true,
            sigma_n: self.sigma_n,
            profile_spacing: 500.0,
            sampling,
            layout: rsf_seas::SeasLayout::Bp1,
            surface_stations: Vec::new(),
        }
    }

    /// The files a BP1 run writes in its folder, those of the program `seas_bp1` and of
    /// the Python package's `rsf.seas_bp1(out=…)` alike: the station files
    /// ([`SEAS_BP1_STATION_DEPTHS`]), `devol.dat`, `events.csv` and their resume log
    /// ([`rsf_seas::SEAS_RESUME_LOG`]). Each front end adds its own (the checkpoint, the
    /// program's summary and figure).
    pub fn file_names() -> Vec<String> {
        let mut names: Vec<String> = SEAS_BP1_STATION_DEPTHS
            .iter()
            .map(|&d| Self::station_name(d))
            .collect();
        names.extend(["devol.dat", "events.csv", rsf_seas::SEAS_RESUME_LOG].map(String::from));
        names
    }

    /// Name of the station file at `depth` (m): `fltst_dp` and the depth in hundreds of
    /// metres, three digits (`fltst_dp025` for 2.5 km).
    pub fn station_name(depth: f64) -> String {
        format!("fltst_dp{:03}", (depth / 100.0).round() as i64)
    }
}

/// `x` as a fingerprint writes numbers: the shortest text that reads back to `x`.
fn json_number(x: f64) -> String {
    serde_json::Value::from(x).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rsf_friction::{AsinhLaw, FrictionLaw};

    /// The closed-form size bounds the built mesh (nodes at most 2 per direction above,
    /// fault nodes exact) and refuses nothing the mesh accepts; grids far beyond memory
    /// are estimated, not built.
    #[test]
    fn size_estimate_bounds_the_mesh() {
        let bp1 = SeasBp1::default();
        for (dz, domain, ratio) in [
            (500.0, 60e3, 1.05),
            (1000.0, 100e3, 1.2),
            (2000.0, 50e3, 1.0),
        ] {
            let grid = SeasBp1Grid { dz, domain, ratio };
            let e = bp1.estimate(&grid).unwrap();
            let model = bp1.model(&grid, false).unwrap();
            let n = model.num_nodes() as f64;
            let side = n.sqrt();
            assert!(
                e.nodes >= n && e.nodes <= (side + 2.0).powi(2) + 2.0 * side,
                "{e:?} vs {n}"
            );
            assert_eq!(e.fault_nodes, model.frictional_boundary.len() as f64);
        }
        let huge = bp1
            .estimate(&SeasBp1Grid {
                dz: 25.0,
                domain: 400e3,
                ratio: 1.0,
            })
            .unwrap();
        assert!(huge.nodes > 2.5e8 && huge.bytes > 1e12, "{huge:?}");
        let tiny = bp1
            .estimate(&SeasBp1Grid {
                dz: 1e-300,
                ..SeasBp1Grid::default()
            })
            .unwrap();
        assert!(tiny.bytes > 1e300, "{tiny:?}");
    }

    #[test]
    fn material_constants() {
        let s = SeasBp1::default();
        assert!((s.shear_modulus() / 32.038e9 - 1.0).abs() < 1e-4);
        assert!((s.radiation_damping() - 2670.0 * 3464.0 / 2.0).abs() < 1e-6);
    }

    #[test]
    fn a_of_depth_is_continuous_and_matches_the_table() {
        let s = SeasBp1::default();
        assert_eq!(s.a(0.0), 0.010);
        assert_eq!(s.a(14_999.0), 0.010);
        assert!((s.a(16.5e3) - 0.0175).abs() < 1e-15);
        assert_eq!(s.a(18e3), 0.025);
        assert_eq!(s.a(39e3), 0.025);
        for z in [15e3, 18e3] {
            assert!((s.a(z - 1e-6) - s.a(z)).abs() < 1e-11, "jump at {z}");
        }
    }

    /// The spec's θ₀ closed form against the library's regularised law (an independent
    /// evaluation): σ_n F(V_init, θ₀(z)) = τ₀ − η V_init at every depth.
    #[test]
    fn initial_state_balances_the_prestress_at_every_depth() {
        let s = SeasBp1::default();
        let target = s.tau0() - s.radiation_damping() * s.v_init;
        for i in 0..=80 {
            let z = i as f64 * 500.0;
            let law = AsinhLaw::new(s.params(z)).unwrap();
            let f = s.sigma_n * law.friction_coefficient(s.v_init, s.alpha0(z));
            assert!(
                (f - target).abs() <= 1e-12 * target,
                "z = {z}: {f} vs {target}"
            );
        }
    }

    /// Below H + h (a = a_max) the initial state is steady state at V_init: θ₀ = D_c/V_init
    /// (the aging law's θ̇ = 1 − Vθ/D_c vanishes); above it is not.
    #[test]
    fn initial_state_is_steady_where_a_is_a_max() {
        let s = SeasBp1::default();
        let ss = (s.d_c / s.v_init).ln();
        for z in [18e3, 25e3, 39.9e3] {
            assert!((s.alpha0(z) - ss).abs() < 1e-10, "z = {z}");
        }
        assert!((s.alpha0(5e3) - ss).abs() > 1.0);
        // τ₀ − ηV_init is the steady-state regularised friction at V_init with a_max,
        // which for V ≫ V_m is within 1e-12 of the Dieterich–Ruina steady state.
        let p = s.params(30e3);
        let mu_ss = p.steady_state_friction(s.v_init);
        let tau = s.tau0() - s.radiation_damping() * s.v_init;
        assert!(
            (tau / s.sigma_n - mu_ss).abs() < 1e-9,
            "{} {mu_ss}",
            tau / s.sigma_n
        );
    }

    #[test]
    fn invalid_parameters_name_the_field() {
        assert!(SeasBp1::default().validate().is_ok());
        let s = SeasBp1 {
            d_c: -1.0,
            ..SeasBp1::default()
        };
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("d_c"), "{e}");
        let s = SeasBp1 {
            f0: f64::NAN,
            ..SeasBp1::default()
        };
        assert!(s.validate().unwrap_err().to_string().contains("f0"));
    }

    #[test]
    fn station_names_are_the_spec_list() {
        let names: Vec<String> = SEAS_BP1_STATION_DEPTHS
            .iter()
            .map(|&d| SeasBp1::station_name(d))
            .collect();
        let spec = [
            "000", "025", "050", "075", "100", "125", "150", "175", "200", "250", "300", "350",
        ];
        for (n, s) in names.iter().zip(spec) {
            assert_eq!(n, &format!("fltst_dp{s}"));
        }
    }
}
