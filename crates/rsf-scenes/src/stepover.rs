//! A stepover between two strike-slip strands in map view (docs/fault-networks.md): plane
//! strain, the strands parallel, each with SEAS BP1's friction along strike from its tip
//! in the stepover, loaded by creep beyond their far ends and by the far boundaries' plate
//! motion — the fault network of two disjoint faults whose ruptures may jump the step.
//!
//! Geometry (x along strike, y across, m): the **south** strand lies on `y = −gap/2`, from
//! its tip at `x = overlap/2` west to the box's west side; the **north** strand on
//! `y = gap/2`, from the box's east side west to its tip at `x = −overlap/2`. A negative
//! overlap is an underlap (the tips apart along strike). The distance `s` from a strand's
//! tip plays BP1's depth: velocity weakening for `s < H`, `a` growing to `a_max` over
//! `H … H + h`, creep at the plate rate beyond `W_f`. The north side of each strand moves
//! east relative to its south side (right-lateral): the box's north side at `+V_p/2`, its
//! south side at `−V_p/2` (x), its west and east sides split at the strand that reaches
//! them, each part with its side's motion.

use rsf::fem::{geometric_grading, rectangle_from_coordinates, Diagonal, TriangleMesh};
use rsf::friction::AsinhLaw;
use rsf::model::FaultPoint;
use rsf::normal_stress::NormalStress;
use rsf::observe::FaultStation;
use rsf::state::Aging;
use rsf::time::Quasistatic;
use rsf::{Material, Model, ModelBuilder, Part, Result, SimulationBuilder};

use crate::seas_bp1::Bp1PlaneStrainBuilder;
use crate::{check_ratio, invalid, invalid_length, SeasBp1};

/// The names of the two strands: the south one (ending at `x = overlap/2`) and the north
/// one (ending at `x = −overlap/2`).
pub const STEPOVER_FAULTS: [&str; 2] = ["south", "north"];

/// The distances (m) from each strand's tip of its stations.
pub const STEPOVER_STATION_DISTANCES: [f64; 6] = [0.5e3, 2.5e3, 5e3, 7.5e3, 10e3, 12.5e3];

/// The fault ODE of a stepover ([`Stepover::fault_ode`]).
pub type StepoverFaultOde = rsf::FaultOde<2, AsinhLaw, Aging>;

/// A stepover between two parallel strike-slip strands (module docs): BP1's parameters
/// along strike from each tip (`params.w_f` the length of each strand's frictional part),
/// the step across strike and the overlap along it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stepover {
    /// The material, friction and loading parameters (SI units); the depth of BP1 is the
    /// distance from a strand's tip.
    pub params: SeasBp1,
    /// The distance between the strands across strike (m), > 0.
    pub gap: f64,
    /// The overlap of the strands along strike (m; negative: an underlap).
    pub overlap: f64,
    /// The normal stress: the laws' fixed `σ_n` (default), or changing with slip
    /// ([`NormalStress::FromSlip`]: a releasing or restraining step).
    pub normal_stress_from_slip: bool,
}

impl Default for Stepover {
    /// BP1's parameters with strands 25 km long (VW 15 km from the tip, the transition to
    /// 18 km, velocity strengthening to 25 km, creep beyond), 1 km apart with 2 km of overlap.
    fn default() -> Self {
        Self {
            params: SeasBp1 {
                w_f: 25e3,
                ..SeasBp1::default()
            },
            gap: 1e3,
            overlap: 2e3,
            normal_stress_from_slip: false,
        }
    }
}

/// The mesh of a stepover run ([`Stepover::mesh`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepoverGrid {
    /// Element size along the strands and next to them (m).
    pub dx: f64,
    /// How far the box reaches beyond the strands' frictional parts along strike and
    /// beyond the strands across it (m).
    pub domain: f64,
    /// Growth of the elements away from the strands, in [1, 2].
    pub ratio: f64,
}

impl Default for StepoverGrid {
    fn default() -> Self {
        Self {
            dx: 25.0,
            domain: 50e3,
            ratio: 1.05,
        }
    }
}

impl Stepover {
    /// Checks the parameters ([`SeasBp1::validate`]), the gap and the overlap.
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] naming the first invalid one.
    pub fn validate(&self) -> Result<()> {
        self.params.validate()?;
        if !(self.gap > 0.0 && self.gap.is_finite()) {
            return Err(invalid_length("gap", self.gap, "must be positive"));
        }
        if !(self.overlap.is_finite() && self.overlap.abs() < self.params.w_f) {
            let w_f = rsf_numeric::number(self.params.w_f);
            let rule = format!("must be finite and shorter than a strand ({w_f} m)");
            return Err(invalid_length("overlap", self.overlap, rule));
        }
        Ok(())
    }

    /// The tip of `fault` (`south` or `north`): `(x, y)` (m).
    ///
    /// # Panics
    /// For another fault name (an internal invariant: the scene's faults are
    /// [`STEPOVER_FAULTS`]).
    pub fn tip(&self, fault: &str) -> [f64; 2] {
        match fault {
            "south" => [0.5 * self.overlap, -0.5 * self.gap],
            "north" => [-0.5 * self.overlap, 0.5 * self.gap],
            other => panic!("no strand `{other}` in a stepover"),
        }
    }

    /// The distance `s` (m) along strike of `x` from the tip of `fault`, positive into
    /// the strand.
    pub fn distance(&self, fault: &str, x: &[f64; 2]) -> f64 {
        let tip = self.tip(fault);
        match fault {
            "south" => tip[0] - x[0],
            _ => x[0] - tip[0],
        }
    }

    /// The point of `fault` at distance `s` (m) from its tip.
    pub fn point(&self, fault: &str, s: f64) -> [f64; 2] {
        let tip = self.tip(fault);
        match fault {
            "south" => [tip[0] - s, tip[1]],
            _ => [tip[0] + s, tip[1]],
        }
    }

    /// The half-extents `[X, Y]` (m) of the box of `grid`: `X` the frictional parts' reach
    /// along strike plus `grid.domain`, `Y` half the gap plus `grid.domain`.
    pub fn box_half(&self, grid: &StepoverGrid) -> [f64; 2] {
        let reach = (0.5 * self.overlap)
            .abs()
            .max(self.params.w_f - 0.5 * self.overlap);
        [reach + grid.domain, 0.5 * self.gap + grid.domain]
    }

    /// Checks `grid` against the scene: `dx` positive, dividing half the gap, half the
    /// overlap and `W_f` into whole cells, at most `H/8`; `domain` at least `W_f`; `ratio`
    /// in [1, 2].
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `dx`, `domain` or `ratio`.
    pub fn check_grid(&self, grid: &StepoverGrid) -> Result<()> {
        self.validate()?;
        let dx = grid.dx;
        let whole = |len: f64| {
            let n = len / dx;
            (n - n.round()).abs() <= 1e-9 * n.abs().max(1.0)
        };
        if !(dx > 0.0 && dx.is_finite() && 8.0 * dx <= self.params.h_top) {
            return Err(invalid(
                "dx",
                format!(
                    "{} m must be positive and at most H/8 = {} m",
                    rsf_numeric::written(dx),
                    rsf_numeric::number(self.params.h_top / 8.0)
                ),
            ));
        }
        if !(whole(0.5 * self.gap) && whole(0.5 * self.overlap) && whole(self.params.w_f)) {
            return Err(invalid(
                "dx",
                format!(
                    "{} m must divide half the gap ({} m), half the overlap ({} m) and W_f \
                     ({} m) into whole cells",
                    rsf_numeric::written(dx),
                    rsf_numeric::number(0.5 * self.gap),
                    rsf_numeric::number(0.5 * self.overlap),
                    rsf_numeric::number(self.params.w_f)
                ),
            ));
        }
        if !(grid.domain >= self.params.w_f && grid.domain.is_finite()) {
            let w_f = rsf_numeric::number(self.params.w_f);
            let rule = format!("must be at least W_f ({w_f} m)");
            return Err(invalid_length("domain", grid.domain, rule));
        }
        check_ratio(grid.ratio)?;
        Ok(())
    }

    /// The mesh: a graded structured mesh, elements `dx` along strike over the strands'
    /// frictional parts (growing by `ratio` beyond) and across strike within `2 dx` of each
    /// strand (growing by `ratio` away from it, towards the gap's middle and the box's
    /// sides).
    ///
    /// # Errors
    /// As [`check_grid`](Self::check_grid); grading errors.
    pub fn mesh(&self, grid: &StepoverGrid) -> Result<TriangleMesh> {
        self.check_grid(grid)?;
        let [x_half, _] = self.box_half(grid);
        let (dx, r) = (grid.dx, grid.ratio);
        // Along strike: dx over the frictional reach, then graded to the sides.
        let reach = x_half - grid.domain;
        let side = geometric_grading(dx, reach, r, x_half)?;
        let mut xs: Vec<f64> = side.iter().rev().map(|x| -x).collect();
        xs.extend(side.iter().skip(1));
        // Across strike: graded away from each strand, to the gap's middle and outwards.
        let g = 0.5 * self.gap;
        let inner = geometric_grading(dx, (2.0 * dx).min(g), r, g)?;
        let outer = geometric_grading(dx, 2.0 * dx, r, grid.domain)?;
        let mut ys: Vec<f64> = outer.iter().rev().map(|y| -g - y).collect();
        ys.extend(inner.iter().skip(1).map(|y| -g + y));
        ys.extend(inner.iter().rev().skip(1).map(|y| g - y));
        ys.extend(outer.iter().map(|y| g + y));
        ys.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * dx);
        Ok(rectangle_from_coordinates(&xs, &ys, Diagonal::Forward)?)
    }

    /// The model on `grid` (quasi-dynamic: no mass): isotropic plane strain (ν = 0.25,
    /// μ = ρc_s²); the strands `south` and `north` inside the body, each creeping at the
    /// plate rate beyond `W_f` from its tip; the box's sides with their side's plate
    /// motion; the prestress τ⁰ as equal and opposite tractions on the strands' faces, each
    /// side's in its direction of motion; the initial displacement 0.
    ///
    /// # Errors
    /// As [`mesh`](Self::mesh); model assembly errors.
    pub fn model(&self, grid: &StepoverGrid) -> Result<Model<2>> {
        let mesh = self.mesh(grid)?;
        let p = &self.params;
        let [x_half, y_half] = self.box_half(grid);
        let nu = 0.25;
        let material = Material::new(2.0 * p.shear_modulus() * (1.0 + nu), nu, p.rho);
        let h = 0.5 * p.v_p;
        let eps = 1e-6 * grid.dx;
        let tau0 = p.tau0();
        let g = 0.5 * self.gap;
        let (south, north) = (self.tip("south"), self.tip("north"));
        let this = *self;
        // Both strands run westwards (from the east side to the north tip; from the south
        // tip to the west side): the minus side is north of each, the plus side south, the
        // pair tangent points east, and the slip of right-lateral motion is −V_p.
        ModelBuilder::new(mesh)
            .material(material)
            .without_mass()
            .dirichlet(
                Part::predicate("north side", move |x| x[1] > y_half - eps),
                [h, 0.0],
            )
            .dirichlet(
                Part::predicate("south side", move |x| x[1] < -y_half + eps),
                [-h, 0.0],
            )
            .dirichlet(
                Part::predicate("west side, north", move |x| {
                    x[0] < -x_half + eps && x[1] > -g
                }),
                [h, 0.0],
            )
            .dirichlet(
                Part::predicate("west side, south", move |x| {
                    x[0] < -x_half + eps && x[1] < -g
                }),
                [-h, 0.0],
            )
            .dirichlet(
                Part::predicate("east side, north", move |x| x[0] > x_half - eps && x[1] > g),
                [h, 0.0],
            )
            .dirichlet(
                Part::predicate("east side, south", move |x| x[0] > x_half - eps && x[1] < g),
                [-h, 0.0],
            )
            .internal_fault("south", south, [-x_half, south[1]])
            .internal_fault("north", [x_half, north[1]], north)
            .internal_creep(
                move |x| {
                    let fault = if x[1] < 0.0 { "south" } else { "north" };
                    this.distance(fault, x) > this.params.w_f + eps
                },
                -p.v_p,
            )
            .neumann(Part::from("south_minus"), move |_| [tau0, 0.0])
            .neumann(Part::from("south_plus"), move |_| [-tau0, 0.0])
            .neumann(Part::from("north_minus"), move |_| [tau0, 0.0])
            .neumann(Part::from("north_plus"), move |_| [-tau0, 0.0])
            // u₀ = 0: the fault ODE carries the load in its condensed right-hand side.
            .without_initial_equilibrium()
            .build()
    }

    /// The problem on `model` (quasi-dynamic): on each strand the regularised law with BP1's
    /// `a(s)` at the distance `s` from its tip, the aging law, BP1's initial state (steady
    /// state at V_init under τ⁰), radiation damping `μ/(2c_s)`, the normal stress fixed or
    /// from slip ([`normal_stress_from_slip`](Self::normal_stress_from_slip)).
    ///
    /// # Errors
    /// Invalid parameters.
    pub fn problem_builder(&self, model: Model<2>) -> Result<Bp1PlaneStrainBuilder> {
        self.validate()?;
        let p = self.params;
        let this = *self;
        let s = move |q: FaultPoint<'_, 2>| this.distance(q.fault, q.x);
        Ok(SimulationBuilder::new(model)
            .friction_on_faults(move |q| AsinhLaw::new(p.params(s(q))))
            .state_law(Aging::new(p.d_c)?)
            .initial_state_on_faults(move |q| p.alpha0(s(q)))
            .integrator(Quasistatic::new())
            .radiation_damping(p.radiation_damping())
            .normal_stress(if self.normal_stress_from_slip {
                NormalStress::FromSlip
            } else {
                NormalStress::Fixed
            }))
    }

    /// The stepover on `model` as a run condensed onto the strands (first trial step
    /// 0.01 s).
    ///
    /// # Errors
    /// Invalid parameters; the fault ODE's set-up errors.
    pub fn fault_ode(
        &self,
        model: Model<2>,
        options: rsf::fault_ode::FaultOdeOptions,
    ) -> Result<StepoverFaultOde> {
        self.problem_builder(model)?
            .time_step(1e-2)
            .build_fault_ode(options)
    }

    /// The stations: on each strand at the distances [`STEPOVER_STATION_DISTANCES`] from
    /// its tip, labelled `sNN.Nkm` (e.g. `south_s02.5km.csv`).
    pub fn stations(&self) -> Vec<FaultStation<2>> {
        STEPOVER_FAULTS
            .iter()
            .flat_map(|&fault| {
                STEPOVER_STATION_DISTANCES
                    .iter()
                    .map(move |&s| FaultStation {
                        fault: fault.to_owned(),
                        near: self.point(fault, s),
                        label: format!("s{:04.1}km", s / 1e3),
                    })
            })
            .collect()
    }
}
