//! BP8 with the finite-element volume (`kernel = fe`, issue 85 item 5): the whole space
//! truncated to a clamped box graded towards the square ([`SquareVolumeGrid`]), the square
//! a fault inside the body whose rim is a shared tip, the prestress as equal and opposite
//! tractions on its two faces, the fault ODE with the condensed finite-element operator;
//! and a run's fault ODE and files with either kernel ([`SeasBp8Run`]: the programs' and
//! Python's one path).

use std::sync::Arc;

use rsf::fault_ode::{FaultOdeOptions, SchurOnlySetup};
use rsf::pore_pressure::PorePressure;
use rsf::{Material, Model, ModelBuilder, Part, Result};
use rsf_seas::{SeasBp5Output, SeasSetup};

use crate::seas_bp8::{SeasBp8, SeasBp8FaultOde};
use crate::seas_square_run::SeasBp8Run;
use crate::square_volume::{SquareVolumeGrid, VolumeElimination};

impl SeasBp8 {
    /// The isotropic medium of the volume: μ = ρc_s², ν, ρ.
    pub fn material(&self) -> Material {
        Material::from_shear_modulus(self.shear_modulus(), self.nu, self.rho)
    }

    /// The builder of BP8's volume model on `grid` ([`SquareVolumeGrid::builder`] for the
    /// square `|x₂|, |x₃| ≤ l_f`, the [`material`](Self::material)), the prestress
    /// [`tau0`](Self::tau0) as the tractions `±(0, τ⁰₂, τ⁰₃)` on the fault's plus and minus
    /// faces (Pa): the slip of a pair is the plus side's motion along `+x₂`, `+x₃` relative
    /// to the minus side's, as on the cells of [`model`](Self::model).
    ///
    /// # Errors
    /// Invalid parameters; [`SquareVolumeGrid::builder`]'s.
    pub fn fe_model_builder(&self, grid: &SquareVolumeGrid) -> Result<ModelBuilder<3>> {
        self.validate()?;
        let [t2, t3] = self.tau0();
        Ok(grid
            .builder(self.l_f, self.material())?
            .neumann(Part::from("fault_minus"), move |_| [0.0, -t2, -t3])
            .neumann(Part::from("fault_plus"), move |_| [0.0, t2, t3]))
    }

    /// BP8's volume model on `grid` ([`fe_model_builder`](Self::fe_model_builder), built):
    /// its frictional nodes are the `(2 l_f/dx − 1)²` split pairs inside the square.
    ///
    /// # Errors
    /// As [`fe_model_builder`](Self::fe_model_builder); the assembly's.
    pub fn fe_model(&self, grid: &SquareVolumeGrid) -> Result<Model<3, 3>> {
        self.fe_model_builder(grid)?.build()
    }

    /// The fault ODE of BP8 on the volume model `model` ([`fe_model`](Self::fe_model)):
    /// the condensed finite-element operator (`options.kernel`, `options.ordering`), the
    /// laws, state, damping and pressure of [`fault_ode`](Self::fault_ode); no loading but
    /// the pressure (the box's faces clamped).
    ///
    /// # Errors
    /// As [`problem_builder`](Self::problem_builder); the set-up errors of
    /// [`build_fault_ode`](rsf::SimulationBuilder::build_fault_ode).
    pub fn fe_fault_ode(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        pressure: Arc<dyn PorePressure<3>>,
    ) -> Result<SeasBp8FaultOde> {
        self.problem_builder(model, pressure)?
            .build_fault_ode(options)
    }

    /// As [`fe_fault_ode`](Self::fe_fault_ode) without ever holding the volume's whole
    /// factor ([`SimulationBuilder::build_fault_ode_schur_only`]: the same operator to
    /// round-off, a fraction of the memory).
    ///
    /// # Errors
    /// As [`fe_fault_ode`](Self::fe_fault_ode); the elimination's.
    ///
    /// [`SimulationBuilder::build_fault_ode_schur_only`]:
    ///     rsf::SimulationBuilder::build_fault_ode_schur_only
    pub fn fe_fault_ode_schur_only(
        &self,
        model: Model<3, 3>,
        options: FaultOdeOptions,
        (pressure, setup): (Arc<dyn PorePressure<3>>, SchurOnlySetup),
    ) -> Result<SeasBp8FaultOde> {
        self.problem_builder(model, pressure)?
            .build_fault_ode_schur_only(options, setup)
    }

    /// BP8's files ([`SeasBp5Output::bp8_volume`]) of a run on the volume model `model`
    /// of node spacing `dx` on the fault, as [`output`](Self::output).
    ///
    /// # Errors
    /// Those of [`SeasBp5Output::bp8_volume`].
    pub fn volume_output(
        &self,
        dir: &std::path::Path,
        model: &Model<3, 3>,
        dx: f64,
        field: Arc<dyn PorePressure<3>>,
        setup: SeasSetup,
    ) -> Result<SeasBp5Output> {
        Ok(SeasBp5Output::bp8_volume(
            dir,
            &self.output_fault(),
            model,
            dx,
            field,
            setup,
        )?)
    }
}

impl SeasBp8Run {
    /// The fault ODE of this run ([`SeasBp8::default`]) with its kernel: the cells and the
    /// whole space's boundary elements ([`SeasBp8::fault_ode`]), or the volume
    /// ([`volume_grid`](Self::volume_grid), [`SeasBp8::fe_model`]) by the Schur-only
    /// elimination `elimination` chooses for. `options` the scene's with the front end's
    /// threads and integrator; `pressure` the friction's
    /// ([`SeasBp8::friction_pressure`]).
    ///
    /// # Errors
    /// Those of the kernel's set-up.
    pub fn fault_ode(
        &self,
        mut options: FaultOdeOptions,
        pressure: Arc<dyn PorePressure<3>>,
        elimination: VolumeElimination,
    ) -> Result<SeasBp8FaultOde> {
        let bp8 = SeasBp8::default();
        match self.volume_grid()? {
            None => bp8.fault_ode(self.dx, options, pressure),
            Some(grid) => {
                let model = bp8.fe_model(&grid)?;
                let pairs = model.frictional_boundary.len();
                let setup = elimination.options(&mut options, pairs, Vec::new());
                bp8.fe_fault_ode_schur_only(model, options, (pressure, setup))
            }
        }
    }

    /// The files of this run on `model` (the fault ODE's: [`fault_ode`](Self::fault_ode))
    /// into `dir`, `field` the pressure they report, `setup` their headers and sampling
    /// ([`SeasBp8::output`] on the cells, [`SeasBp8::volume_output`] on the volume).
    ///
    /// # Errors
    /// The output's.
    pub fn output(
        &self,
        dir: &std::path::Path,
        model: &Model<3, 3>,
        field: Arc<dyn PorePressure<3>>,
        setup: SeasSetup,
    ) -> Result<SeasBp5Output> {
        let bp8 = SeasBp8::default();
        match self.volume_grid()? {
            None => bp8.output(dir, self.dx, field, setup),
            Some(_) => bp8.volume_output(dir, model, self.dx, field, setup),
        }
    }
}
