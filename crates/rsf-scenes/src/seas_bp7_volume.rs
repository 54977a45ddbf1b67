//! BP7 with the finite-element volume (`kernel = fe`, issue 85 item 5): the whole space
//! truncated to a box graded towards the square and the off-fault stations
//! ([`SquareVolumeGrid::creeping_plane_builder`]): the plane `x₁ = 0` across the box,
//! frictional on the square (rim included), creeping at `V_p` outside it, the box's faces
//! carried with each side's rigid motion — the back slip of the boundary elements — the
//! prestress node by node and the bump `Δτ₀ G₁ G₂` a load change of the fault ODE on the
//! frictional nodes; and a run's fault ODE and
//! files with either kernel ([`SeasBp7Run`]: the programs' and Python's one path).

use rsf::fault_ode::{FaultOdeOptions, LoadChange, SchurOnlySetup};
use rsf::{Material, Model, ModelBuilder, Result};
use rsf_seas::{bp7_body_station_points, SeasBp5Output, SeasSetup};

use crate::seas_bp7::{Bp7Law, SeasBp7, SeasBp7FaultOde};
use crate::seas_square_run::SeasBp7Run;
use crate::square_volume::{SquareVolumeGrid, VolumeElimination};

impl SeasBp7 {
    /// The isotropic medium of the volume: μ = ρc_s², ν, ρ.
    pub fn material(&self) -> Material {
        Material::from_shear_modulus(self.shear_modulus(), self.nu, self.rho)
    }

    /// The builder of BP7's volume model on `grid`
    /// ([`SquareVolumeGrid::creeping_plane_builder`] for the square `|x₂|, |x₃| ≤ l_f`,
    /// refined towards the off-fault stations, creeping at `V_p`). The prestress is not
    /// a traction of the builder's: it is given node by node to the fault ODE
    /// ([`fe_prestress`](Self::fe_prestress)).
    ///
    /// # Errors
    /// Invalid parameters; [`SquareVolumeGrid::creeping_plane_builder`]'s.
    pub fn fe_model_builder(&self, grid: &SquareVolumeGrid) -> Result<ModelBuilder<3>> {
        self.validate()?;
        grid.creeping_plane_builder(
            self.l_f,
            self.material(),
            &bp7_body_station_points(),
            self.v_p,
        )
    }

    /// The prestress [`tau0_at`](Self::tau0_at) of every frictional node of the volume
    /// model `model` as forces on its slip unknowns: `w τ⁰(x_k)` (N) in the pair's frame,
    /// so that every node starts at the steady state of its own `a` as the cells do (as
    /// tractions on the faces the assembly would integrate `τ⁰` against the hat
    /// functions, and a node within a cell of the disc's rim, where `τ⁰` jumps by
    /// 2.07 MPa, would start off its steady state).
    ///
    /// # Errors
    /// [`rsf::Error::InvalidParameter`] named `model` for a model without an internal
    /// fault or a frictional node that is not a pair.
    pub fn fe_prestress(&self, model: &Model<3, 3>) -> Result<Vec<f64>> {
        let fault = model
            .internal_fault
            .as_ref()
            .ok_or_else(|| crate::invalid("model", "has no fault inside the body"))?;
        let fb = &model.frictional_boundary;
        let mut forces = Vec::with_capacity(2 * fb.len());
        for (k, (&p, &w)) in fb.nodes.iter().zip(&fb.weights).enumerate() {
            let i = fault.pair_index(p).ok_or_else(|| {
                crate::invalid("model", format!("frictional node {k} is not a pair"))
            })?;
            let x = model.vertices[p];
            let [t2, t3] = self.tau0_at(x[1], x[2]);
            // The pair frame `Q` turns frame components into the Cartesian jump (its
            // row k the Cartesian component k): the force w (0, τ₂, τ₃) is `Qᵀ` of it in
            // the frame, whose components 0 and 1 (the tangents; 2 the normal) are the
            // slip unknowns.
            let q = fault.transform.frames[i];
            let frame = |j: usize| w * (t2 * q[1][j] + t3 * q[2][j]);
            forces.extend([frame(0), frame(1)]);
        }
        Ok(forces)
    }

    /// BP7's volume model on `grid` ([`fe_model_builder`](Self::fe_model_builder),
    /// built): its frictional nodes the `(2 l_f/dx + 1)²` pairs of the square.
    ///
    /// # Errors
    /// As [`fe_model_builder`](Self::fe_model_builder); the assembly's.
    pub fn fe_model(&self, grid: &SquareVolumeGrid) -> Result<Model<3, 3>> {
        self.fe_model_builder(grid)?.build()
    }

    /// The bump `Δτ⁰ = Δτ₀ G₁(r) G₂(t)` along `x₂` on the frictional nodes of the volume
    /// model `model` (each node its own `G₁` times its weight, in its frame's `t₁ = x₂`),
    /// as [`perturbation`](Self::perturbation) on the cells.
    pub fn fe_perturbation(&self, model: &Model<3, 3>) -> LoadChange {
        let fb = &model.frictional_boundary;
        let forces = fb
            .nodes
            .iter()
            .zip(&fb.weights)
            .flat_map(|(&p, &w)| {
                let x = model.vertices[p];
                self.bump_force(w, x[1], x[2])
            })
            .collect();
        self.bump(forces)
    }

    /// The fault ODE of BP7 with the state law `law` on the volume model `model`
    /// ([`fe_model`](Self::fe_model)) by the Schur-only elimination
    /// ([`SimulationBuilder::build_fault_ode_schur_only`]; `setup.watch_vertices` the
    /// stations' vertices the output reads), the bump
    /// ([`fe_perturbation`](Self::fe_perturbation)) a load change.
    ///
    /// # Errors
    /// As [`problem_builder`](Self::problem_builder); the elimination's; those of
    /// [`FaultOde::with_load_change`](rsf::FaultOde::with_load_change).
    ///
    /// [`SimulationBuilder::build_fault_ode_schur_only`]:
    ///     rsf::SimulationBuilder::build_fault_ode_schur_only
    pub fn fe_fault_ode_schur_only(
        &self,
        model: Model<3, 3>,
        law: Bp7Law,
        (options, setup): (FaultOdeOptions, SchurOnlySetup),
    ) -> Result<SeasBp7FaultOde> {
        let bump = self.fe_perturbation(&model);
        let prestress = self.fe_prestress(&model)?;
        self.problem_builder(model, law)?
            .build_fault_ode_schur_only(options, setup)?
            .with_load_added(&prestress)?
            .with_load_change(bump)
    }

    /// The vertices of the volume model `model` nearest the off-fault stations, sorted,
    /// without repeats (those the output reads off the fault).
    ///
    /// # Errors
    /// [`Model::nearest_node`]'s.
    pub fn station_vertices(&self, model: &Model<3, 3>) -> Result<Vec<usize>> {
        crate::nearest_vertices(model, &bp7_body_station_points())
    }

    /// BP7's files ([`SeasBp5Output::bp7_volume`]) of a run on the volume model `model`
    /// of node spacing `dx` on the fault, as [`output`](Self::output).
    ///
    /// # Errors
    /// Those of [`SeasBp5Output::bp7_volume`].
    pub fn volume_output(
        &self,
        dir: &std::path::Path,
        model: &Model<3, 3>,
        dx: f64,
        setup: SeasSetup,
    ) -> Result<SeasBp5Output> {
        Ok(SeasBp5Output::bp7_volume(
            dir,
            &self.output_fault(),
            model,
            (dx, self.r_vw),
            setup,
        )?)
    }
}

/// Where a BP7 run's off-fault stations read their displacement: the boundary elements'
/// columns per unit slip, or the volume's vertices (`None`).
pub type Bp7BodyColumns = Option<Vec<Vec<f64>>>;

impl SeasBp7Run {
    /// The fault ODE of this run ([`scene`](Self::scene)) with its kernel: the cells and
    /// the whole space's boundary elements ([`SeasBp7::fault_ode`], with the off-fault
    /// stations' columns), or the volume ([`volume_grid`](Self::volume_grid),
    /// [`SeasBp7::fe_model`]) by the Schur-only elimination `elimination` chooses for,
    /// keeping the stations' vertices. `options` the scene's with the front end's threads
    /// and integrator.
    ///
    /// # Errors
    /// Those of the kernel's set-up.
    pub fn fault_ode(
        &self,
        mut options: FaultOdeOptions,
        elimination: VolumeElimination,
    ) -> Result<(SeasBp7FaultOde, Bp7BodyColumns)> {
        let bp7 = self.scene();
        match self.volume_grid()? {
            None => {
                let (ode, columns) = bp7.fault_ode(self.dx, self.law, options)?;
                Ok((ode, Some(columns)))
            }
            Some(grid) => {
                let model = bp7.fe_model(&grid)?;
                let watch = bp7.station_vertices(&model)?;
                let pairs = model.frictional_boundary.len();
                let setup = elimination.options(&mut options, pairs, watch);
                let ode = bp7.fe_fault_ode_schur_only(model, self.law, (options, setup))?;
                Ok((ode, None))
            }
        }
    }

    /// The files of this run on `model` (the fault ODE's) into `dir` with `body` from
    /// [`fault_ode`](Self::fault_ode), `setup` their headers and sampling
    /// ([`SeasBp7::output`] on the cells, [`SeasBp7::volume_output`] on the volume).
    ///
    /// # Errors
    /// The output's; named `body` for columns with the volume or none with the cells.
    pub fn output(
        &self,
        dir: &std::path::Path,
        model: &Model<3, 3>,
        body: Bp7BodyColumns,
        setup: SeasSetup,
    ) -> Result<SeasBp5Output> {
        let bp7 = self.scene();
        match (self.volume_grid()?, body) {
            (None, Some(columns)) => bp7.output(dir, self.dx, columns, setup),
            (Some(_), None) => bp7.volume_output(dir, model, self.dx, setup),
            _ => Err(crate::invalid(
                "body",
                "the off-fault stations' columns go with the boundary elements alone",
            )),
        }
    }
}
